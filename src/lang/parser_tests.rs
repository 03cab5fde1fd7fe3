//! Unit tests of `parser.rs`, kept in their own file so the module reads
//! as the code alone.

use super::*;

const F: FileId = FileId(0);

fn one(src: &str) -> Expr {
    match parse(src, F).unwrap().pop().unwrap() {
        Item::Value(e) => e,
        i => panic!("{i:?}"),
    }
}

fn show(e: &Expr) -> String {
    match &e.kind {
        ExprKind::Number(v) => format!("{v}"),
        ExprKind::Name(n) => n.to_string(),
        ExprKind::Hex(h) => format!("#{:02x}{:02x}{:02x}", h[0], h[1], h[2]),
        ExprKind::Vector(v) => {
            format!("<{}>", v.iter().map(show).collect::<Vec<_>>().join(","))
        }
        ExprKind::Call { name, args, .. } => format!(
            "{}({})",
            name.node,
            args.iter().map(show).collect::<Vec<_>>().join(",")
        ),
        ExprKind::Neg(e) => format!("(-{})", show(e)),
        ExprKind::Binary { op, lhs, rhs } => format!("({} {op} {})", show(lhs), show(rhs)),
        ExprKind::Not(e) => format!("(not {})", show(e)),
        ExprKind::List(v) => format!("[{}]", v.iter().map(show).collect::<Vec<_>>().join(",")),
        ExprKind::Index { base, index } => format!("{}[{}]", show(base), show(index)),
        ExprKind::Value(v) => format!("{v:?}"),
        ExprKind::Bound(n, _) => n.to_string(),
    }
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(show(&one("1 + 2 * 3")), "(1 + (2 * 3))");
    assert_eq!(show(&one("-2^2")), "(-(2 ^ 2))");
    assert_eq!(show(&one("2^3^2")), "(2 ^ (3 ^ 2))");
    assert_eq!(show(&one("8 / 2 / 2")), "((8 / 2) / 2)");
    assert_eq!(show(&one("2 ^ -1")), "(2 ^ (-1))");
    assert_eq!(show(&one("(1 + 2) * 3")), "((1 + 2) * 3)");
    assert_eq!(show(&one("-a * b")), "((-a) * b)");
}

#[test]
fn vectors_calls_and_colours() {
    assert_eq!(show(&one("<1, 2 * a, -c>")), "<1,(2 * a),(-c)>");
    assert_eq!(show(&one("<1, 2>")), "<1,2>");
    assert_eq!(
        show(&one("sqrt(2) * rgb(1, 0.5, 0)")),
        "(sqrt(2) * rgb(1,0.5,0))"
    );
    assert_eq!(show(&one("#FF8000")), "#ff8000");
    assert_eq!(show(&one(".5e1")), "5");
}

#[test]
fn a_name_apart_from_its_parenthesis_is_not_a_call() {
    let items = parse("colour (1)", F).unwrap();
    assert_eq!(items.len(), 2);
    assert_eq!(items[0].as_name().unwrap().node, "colour");
}

#[test]
fn items_split_on_juxtaposition() {
    let items = parse(
        "sphere { centre <0,1,0> radius R/2 material gold rotate x 90 }",
        F,
    )
    .unwrap();
    let Item::Block(b) = &items[1] else { panic!() };
    let words: Vec<String> = b
        .items
        .iter()
        .map(|i| match i {
            Item::Value(e) => show(e),
            _ => "?".into(),
        })
        .collect();
    assert_eq!(
        words,
        [
            "centre", "<0,1,0>", "radius", "(R / 2)", "material", "gold", "rotate", "x", "90"
        ]
    );
}

#[test]
fn spans_point_at_the_text() {
    let src = "let R = 2 * pi";
    let Item::Let { name, value, .. } = &parse(src, F).unwrap()[0] else {
        panic!()
    };
    assert_eq!(&src[name.span.start..name.span.end], "R");
    assert_eq!(&src[value.span.start..value.span.end], "2 * pi");
}

#[test]
fn second_dot_is_the_error() {
    let src = "x <0, 1.2.3, 0>";
    let e = parse(src, F).unwrap_err();
    assert_eq!(e[0].span.start, 9);
    assert_eq!(&src[e[0].span.start..e[0].span.end], ".");
}

#[test]
fn unclosed_block_names_its_owner_and_the_next_statement() {
    let src = "sphere { radius 1\n  material gold\n\nplane { }\n";
    let e = parse(src, F).unwrap_err();
    assert_eq!(e.len(), 1);
    assert_eq!(e[0].span.start, 7);
    assert!(e[0].message.contains("`sphere`"), "{}", e[0].message);
    assert!(
        e[0].help
            .as_deref()
            .unwrap()
            .contains("before `plane` on line 4")
    );
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let src = "(".repeat(100_000);
    assert!(
        parse(&src, F).unwrap_err()[0]
            .message
            .contains("too deeply")
    );
    let src = format!("let a = {}1", "-".repeat(100_000));
    assert!(
        parse(&src, F).unwrap_err()[0]
            .message
            .contains("more than 256 operators")
    );
    let src = format!("let a = 1{}", "^1".repeat(100_000));
    assert!(
        parse(&src, F).unwrap_err()[0]
            .message
            .contains("more than 256 operators")
    );
    let src = format!("let a = 1{}", "+1".repeat(100_000));
    assert!(
        parse(&src, F).unwrap_err()[0]
            .message
            .contains("more than 256 operators")
    );
}

#[test]
fn comparisons_are_not_open_vectors() {
    for src in [
        "let a = 1 < 2",
        "let a = 1 < <1, 2, 3>",
        "let a = (1 < 2) and 3 > 2",
        "if 1 < 2 { }",
        "let b = 1 <= 2",
    ] {
        assert!(parse(src, F).is_ok(), "{src}");
    }
    let e = parse("let B = <1, 2, 3", F).unwrap_err();
    assert_eq!(e[0].message, "`<` is never closed");
}

#[test]
fn syntax_errors_use_our_words() {
    let e = parse("let a = ", F).unwrap_err();
    assert!(
        e[0].message.starts_with("expected a value"),
        "{}",
        e[0].message
    );
    assert!(!e[0].message.contains("expr"));
}

/// The statement keywords are the other statements' and then every
/// object's, each once.
#[test]
fn statement_keywords_are_the_statements_and_the_objects() {
    let (head, objects) = STATEMENT_KEYWORDS.split_at(STATEMENT_KEYWORDS.len() - OBJECTS.len());
    assert_eq!(objects, OBJECTS);
    assert_eq!(head, STATEMENTS);
    assert!(head.contains(&"camera") && head.contains(&"fn"));
    for (i, k) in STATEMENT_KEYWORDS.iter().enumerate() {
        assert!(!k.is_empty());
        assert!(!STATEMENT_KEYWORDS[..i].contains(k), "{k} twice");
    }
}
