//! Unit tests of `entry.rs`: what the entry points hand over (the items
//! in parts, the errors, the names, the top-level values) and `-D`.

use super::*;
use std::path::Path;

fn program(src: &str) -> Program {
    crate::lang::load_text(Path::new("scene.rt"), src.into())
        .unwrap_or_else(|_| panic!("{src} does not parse"))
}

/// The parts `evaluate_in_parts` hands over, and its errors.
fn parts(src: &str, options: &Options) -> (Vec<Vec<Item>>, Vec<Error>) {
    let p = program(src);
    let mut parts = Vec::new();
    let errors = evaluate_in_parts(&p, Transfer::Srgb, options, |part, _| parts.push(part));
    (parts, errors)
}

fn messages(errors: &[Error]) -> Vec<&str> {
    errors.iter().map(|e| e.message.as_str()).collect()
}

/// `evaluate` gives the items of every part in order, the errors, and the
/// names bound anywhere (a loop's variable and a function's parameters
/// included).
#[test]
fn evaluate_gives_items_errors_and_names() {
    let _watchdog = crate::watchdog::start();
    let p = program("let a = 2\nsphere { radius a }\nfn f(h) = h\nfor i in 0..2 { sphere { } }");
    let e = evaluate(&p, Transfer::Srgb, &Options::default());
    assert!(e.errors.is_empty(), "{:?}", e.errors);
    // sphere, its block, and one traced item per iteration.
    assert_eq!(e.items.len(), 4, "{:?}", e.items);
    assert_eq!(e.items[0].as_name().map(|n| n.node), Some("sphere"));
    assert!(matches!(&e.items[1], Item::Block(_)));
    assert!(matches!(&e.items[2], Item::Traced { .. }));
    for name in ["a", "f", "h", "i"] {
        assert!(e.known.iter().any(|k| k == name), "{name} in {:?}", e.known);
    }
    // The same items, in the same order, as the parts one after another.
    let (parts, errors) = parts(
        "let a = 2\nsphere { radius a }\nfn f(h) = h\nfor i in 0..2 { sphere { } }",
        &Options::default(),
    );
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(parts.concat(), e.items);
}

/// The errors of a program come back from each entry point, each once.
#[test]
fn each_entry_point_returns_the_errors() {
    let _watchdog = crate::watchdog::start();
    let src = "let a = b\nsphere { radius 1 / 0 }";
    let want = ["unknown name `b`", "division by zero"];
    let p = program(src);
    let e = evaluate(&p, Transfer::Srgb, &Options::default());
    assert_eq!(messages(&e.errors), want);
    let (_, errors) = parts(src, &Options::default());
    assert_eq!(messages(&errors), want);
    let (errors, _) = evaluate_in_parts_bound(&p, Transfer::Srgb, &Options::default(), |_, _| {});
    assert_eq!(messages(&errors), want);
    // And none from a program without mistakes.
    let (errors, bound) = evaluate_in_parts_bound(
        &program("let a = 1"),
        Transfer::Srgb,
        &Options::default(),
        |_, _| {},
    );
    assert!(
        errors.is_empty() && bound.len() == 1,
        "{errors:?} {bound:?}"
    );
}

/// Parts are runs of whole statements between the `let`s, `fn`s, `for`s
/// and `if`s: a statement of two items (a placement `s { … }`) is never
/// cut in two, a loop's items are a part of their own, and what follows
/// a loop is not lost.
#[test]
fn parts_are_runs_of_whole_statements() {
    let _watchdog = crate::watchdog::start();
    let src = "sphere { }\nsphere { }\n\
               let a = 1\nlet s = sphere { radius a }\n\
               sphere { }\ns { translate <1, 0, 0> }\n\
               for i in 0..2 { sphere { } }\n\
               sphere { }\nsphere { }\n\
               if a > 0 { sphere { } }\n\
               sphere { }";
    let (parts, errors) = parts(src, &Options::default());
    assert!(errors.is_empty(), "{errors:?}");
    let sizes: Vec<usize> = parts.iter().map(Vec::len).collect();
    assert_eq!(sizes, [4, 4, 2, 4, 2, 2], "{parts:#?}");
    // The placement: the bound value, then its block with the translate.
    let Item::Value(Expr {
        kind: ExprKind::Bound(name, Some(Value::Items(_))),
        ..
    }) = &parts[1][2]
    else {
        panic!("{:?}", parts[1][2]);
    };
    assert_eq!(&**name, "s");
    let Item::Block(b) = &parts[1][3] else {
        panic!("{:?}", parts[1][3]);
    };
    assert_eq!(b.items[0].as_name().map(|n| n.node), Some("translate"));
    assert!(parts[2].iter().all(|i| matches!(i, Item::Traced { .. })));
}

/// A top-level loop hands over what it made every `PART_ITEMS` items
/// when its iterations are cheap (a few steps each: 256 items are far
/// below `PART_STEPS`), nothing lost or repeated.
#[test]
fn a_cheap_loop_hands_over_every_part_items() {
    let _watchdog = crate::watchdog::start();
    let (parts, errors) = parts("for i in 0..600 { sphere { } }", &Options::default());
    assert!(errors.is_empty(), "{errors:?}");
    let sizes: Vec<usize> = parts.iter().map(Vec::len).collect();
    assert_eq!(sizes, [PART_ITEMS, PART_ITEMS, 600 - 2 * PART_ITEMS]);
}

/// A loop whose iterations cost hundreds of steps each (an inner loop of
/// 100 `let`s) hands over every `PART_STEPS` steps: several parts, each
/// of several items (not one per item, not all at the end).
#[test]
fn a_costly_loop_hands_over_every_part_steps() {
    let _watchdog = crate::watchdog::start();
    let (parts, errors) = parts(
        "for i in 0..60 {\n  for j in 0..100 { let q = j * 2 }\n  sphere { }\n}",
        &Options::default(),
    );
    assert!(errors.is_empty(), "{errors:?}");
    let sizes: Vec<usize> = parts.iter().map(Vec::len).collect();
    assert_eq!(sizes.iter().sum::<usize>(), 60, "{sizes:?}");
    assert!(sizes.len() >= 3, "{sizes:?}");
    assert!(
        sizes[..sizes.len() - 1]
            .iter()
            .all(|&n| (2..30).contains(&n)),
        "{sizes:?}"
    );
}

/// The top-level `let`s with their values (`None` where the definition
/// failed), at their names' spans; functions and inner lets left out.
#[test]
fn the_top_level_lets_and_their_values() {
    let _watchdog = crate::watchdog::start();
    let src =
        "let a = 2\nlet b = <1, 2, 3>\nlet c = nope\nfn f(x) = x\nfor i in 0..2 { let d = i }";
    let p = program(src);
    let (errors, bound) =
        evaluate_in_parts_bound(&p, Transfer::Srgb, &Options::default(), |_, _| {});
    assert_eq!(messages(&errors), ["unknown name `nope`"]);
    let names: Vec<&str> = bound.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["a", "b", "c"]);
    assert_eq!(bound[0].value, Some(Value::Number(2.0)));
    assert_eq!(
        bound[1].value,
        Some(Value::Vector(smallvec::smallvec![1.0, 2.0, 3.0]))
    );
    assert_eq!(bound[2].value, None);
    assert_eq!(bound[0].span, Span::new(p.root, 4, 5));
    assert_eq!(bound[1].span, Span::new(p.root, 14, 15));
}

/// `-D NAME` replaces a top-level `let NAME`; one naming none is
/// reported at the file's start, with the nearest top-level `let` as a
/// suggestion, or what `-D` does when none is near.
#[test]
fn defines_that_replace_nothing_are_reported() {
    let _watchdog = crate::watchdog::start();
    let src = "let size = 1\nlet ball = sphere { }\nsphere { radius size }";
    let define = |name: &str| Options {
        defines: vec![(name.into(), Value::Number(3.0))],
        ..Options::default()
    };
    let p = program(src);
    let used = evaluate(&p, Transfer::Srgb, &define("size"));
    assert!(used.errors.is_empty(), "{:?}", used.errors);
    let e = evaluate(&p, Transfer::Srgb, &define("sise")).errors;
    assert_eq!(
        messages(&e),
        ["`-D sise`: the scene has no top-level `let sise`"]
    );
    assert_eq!(e[0].label, "nothing to replace");
    assert_eq!(e[0].help.as_deref(), Some("did you mean `size`?"));
    assert_eq!(e[0].span, Span::new(p.root, 0, 0));
    // Nothing near: what `-D` does.
    let e = evaluate(&p, Transfer::Srgb, &define("zzz")).errors;
    assert_eq!(
        e[0].help.as_deref(),
        Some("`-D` replaces the value of a top-level `let`")
    );
}

/// `-D`'s values: numbers, vectors, colours and lists of built-ins; what
/// is not a value says so, with the evaluator's message where it has one.
#[test]
fn define_values() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(define_value("2"), Ok(Value::Number(2.0)));
    assert_eq!(define_value("-0.5 * 4"), Ok(Value::Number(-2.0)));
    assert_eq!(
        define_value("<1, 2, 3>"),
        Ok(Value::Vector(smallvec::smallvec![1.0, 2.0, 3.0]))
    );
    assert_eq!(
        define_value("[1, max(2, 5)]"),
        Ok(Value::List(Arc::new(vec![
            Value::Number(1.0),
            Value::Number(5.0)
        ])))
    );
    let not = "is not a value (write e.g. `2`, `<1, 2, 3>` or `rgb(1, 0, 0)`)";
    assert_eq!(define_value("<1, 2"), Err(format!("`<1, 2` {not}")));
    assert_eq!(
        define_value("sphere { }"),
        Err(format!("`sphere {{ }}` {not}"))
    );
    assert_eq!(
        define_value("1 / 0"),
        Err("`1 / 0`: division by zero".into())
    );
    assert_eq!(define_value("q"), Err("`q`: unknown name `q`".into()));
}

/// A sink's recycler runs once after every loop iteration, inner loops'
/// included, so that it can free as many used iterations as were made.
#[test]
fn the_recycler_runs_after_every_iteration_at_any_depth() {
    struct Counting(std::rc::Rc<std::cell::Cell<u32>>);
    impl Sink for &mut Counting {
        fn part(&mut self, _: Vec<Item>, _: &[String]) {}
        fn recycler(&mut self) -> Option<Box<dyn FnMut()>> {
            let n = self.0.clone();
            Some(Box::new(move || n.set(n.get() + 1)))
        }
    }
    let _watchdog = crate::watchdog::start();
    let p =
        program("sphere { }\nfor i in 0..3 { for j in 0..4 { sphere { } } }\nfor k in [1, 2] { }");
    let calls = std::rc::Rc::new(std::cell::Cell::new(0));
    let (errors, _) = evaluate_into(
        &p,
        Transfer::Srgb,
        &Options::default(),
        &mut Counting(calls.clone()),
    );
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(calls.get(), 3 * 4 + 3 + 2);
}
