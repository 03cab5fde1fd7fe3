//! Unit tests of the expander (`mod.rs`): its budgets, counted exactly,
//! and the cancel flag.

use super::*;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

fn program(src: &str) -> Program {
    crate::lang::load_text(Path::new("scene.rt"), src.into())
        .unwrap_or_else(|_| panic!("{src} does not parse"))
}

fn with_limits(steps: u64, objects: u64) -> Options {
    Options {
        limits: Limits {
            steps,
            objects,
            ..Limits::default()
        },
        ..Options::default()
    }
}

/// Three bare keywords are three items: three steps and three objects,
/// nothing else. A budget of exactly three runs; one of two stops at the
/// third, which is named, with the limit, once.
#[test]
fn budgets_count_each_item_and_object_exactly() {
    let _watchdog = crate::watchdog::start();
    let p = program("sphere\nsphere\nsphere");
    let third = Span::new(p.root, 14, 20);
    let full = evaluate(&p, Transfer::Srgb, &with_limits(3, 3));
    assert!(full.errors.is_empty(), "{:?}", full.errors);
    assert_eq!(full.items.len(), 3);

    let e = evaluate(&p, Transfer::Srgb, &with_limits(2, 3));
    assert_eq!(e.items.len(), 2);
    assert_eq!(e.errors.len(), 1, "{:?}", e.errors);
    assert_eq!(
        e.errors[0].message,
        "the scene program ran for more than 2 evaluation steps"
    );
    assert_eq!(e.errors[0].label, "still running here");
    assert_eq!(e.errors[0].span, third);

    let e = evaluate(&p, Transfer::Srgb, &with_limits(3, 2));
    assert_eq!(e.items.len(), 2);
    assert_eq!(e.errors.len(), 1, "{:?}", e.errors);
    assert_eq!(e.errors[0].message, "the scene makes more than 2 objects");
    assert_eq!(e.errors[0].label, "one too many");
    assert_eq!(e.errors[0].span, third);
}

/// Past 4096 steps the budget is still counted to the step: a program
/// of 5000 items runs under a budget of 5000 and stops under 4999 or
/// 4500 (not at the next multiple of 4096), its last item not made.
#[test]
fn budgets_past_the_first_check_are_exact_too() {
    let _watchdog = crate::watchdog::start();
    let src = "sphere\n".repeat(5000);
    let p = program(&src);
    let full = evaluate(&p, Transfer::Srgb, &with_limits(5000, 5000));
    assert!(full.errors.is_empty(), "{:?}", full.errors);
    assert_eq!(full.items.len(), 5000);
    for limit in [4999, 4500] {
        let e = evaluate(&p, Transfer::Srgb, &with_limits(limit, 5000));
        assert_eq!(e.items.len() as u64, limit);
        assert_eq!(
            e.errors[0].message,
            format!("the scene program ran for more than {limit} evaluation steps")
        );
        let e = evaluate(&p, Transfer::Srgb, &with_limits(5000, limit));
        assert_eq!(e.items.len() as u64, limit);
        assert_eq!(
            e.errors[0].message,
            format!("the scene makes more than {limit} objects")
        );
    }
}

/// A cancel flag set before the evaluation stops it at once, quietly; one
/// set while it runs (here between parts) stops it at its next look, at
/// most 4096 steps later; one left unset changes nothing.
#[test]
fn cancelling_stops_quietly() {
    let _watchdog = crate::watchdog::start();
    let src = "sphere { }\nlet a = 1\nfor i in 0..20000 { sphere }";
    let p = program(src);
    let cancel = |set: bool| Options {
        cancel: Some(Arc::new(AtomicBool::new(set))),
        ..Options::default()
    };
    let e = evaluate(&p, Transfer::Srgb, &cancel(false));
    assert!(e.errors.is_empty());
    assert_eq!(e.items.len(), 2 + 20000);
    let e = evaluate(&p, Transfer::Srgb, &cancel(true));
    assert!(
        e.errors.is_empty() && e.items.is_empty(),
        "{:?}",
        e.items.len()
    );
    // Set once the first part (the sphere) is handed over.
    let options = cancel(false);
    let flag = options.cancel.clone().unwrap();
    let mut made = 0;
    let errors = evaluate_in_parts(&p, Transfer::Srgb, &options, |part, _| {
        made += part.len();
        flag.store(true, Ordering::Relaxed);
    });
    assert!(errors.is_empty(), "{errors:?}");
    assert!((2..2 + 4096).contains(&made), "{made}");
}

/// The expression after `radius` in the block of `sphere { radius … }`
/// written last in `src`, as the evaluator hands it to the builder, and
/// the evaluator's errors.
fn radius(src: &str) -> (ExprKind, Vec<Error>) {
    let e = evaluate(&program(src), Transfer::Srgb, &Options::default());
    let Some(Item::Block(b)) = e.items.last() else {
        panic!("{:?}", e.items);
    };
    let [first, Item::Value(v)] = b.items.as_slice() else {
        panic!("{:?}", b.items);
    };
    assert_eq!(first.as_name().map(|n| n.node), Some("radius"));
    (v.kind.clone(), e.errors)
}

/// A call of a user function among items is worked out to its value
/// (the trial evaluation gives up on it and the full one runs it), also
/// inside an expression naming a constant.
#[test]
fn user_function_calls_among_items_are_worked_out() {
    let _watchdog = crate::watchdog::start();
    let (v, errors) = radius("fn f(h) = h * 2\nsphere { radius f(1.5) }");
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(v, ExprKind::Value(Value::Number(3.0)));
    let (v, errors) = radius("let a = 2\nfn f(h) = h + 1\nsphere { radius a * f(1) }");
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(v, ExprKind::Value(Value::Number(4.0)));
}

/// An expression naming something the evaluator does not know (left for
/// the builder, whose keywords it does not know) is not worked out nor
/// reported here; its known names are filled in. That holds where `and`
/// would skip the unknown part too: the trial gives up there rather than
/// call the expression closed.
#[test]
fn expressions_naming_unknowns_are_left_to_the_builder() {
    let _watchdog = crate::watchdog::start();
    let (v, errors) = radius("let a = 2\nsphere { radius a * q }");
    assert!(errors.is_empty(), "{errors:?}");
    let ExprKind::Binary { lhs, rhs, .. } = v else {
        panic!("{v:?}");
    };
    assert_eq!(
        lhs.kind,
        ExprKind::Bound("a".into(), Some(Value::Number(2.0)))
    );
    assert_eq!(rhs.kind, ExprKind::Name("q".into()));
    let (v, errors) = radius("sphere { radius (1 > 2 and q) }");
    assert!(errors.is_empty(), "{errors:?}");
    assert!(!matches!(v, ExprKind::Value(_)), "{v:?}");
}

/// A constant used before its `let`: reported with where it is defined.
#[test]
fn a_constant_used_before_its_let_says_where_it_is_defined() {
    let _watchdog = crate::watchdog::start();
    let p = program("let a = b + 1\nlet c = 3\nlet b = 2");
    let e = evaluate(&p, Transfer::Srgb, &Options::default()).errors;
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].message, "unknown name `b`");
    assert_eq!(e[0].label, "not defined");
    assert_eq!(
        e[0].help.as_deref(),
        Some("`b` is defined later; a constant can only be used after its `let`")
    );
    assert_eq!(e[0].span, Span::new(p.root, 8, 9));
    assert_eq!(
        e[0].notes,
        [(Span::new(p.root, 28, 29), "defined here".to_string())]
    );
}

/// An unknown function is matched against the built-ins and the user's
/// functions (not the other constants) for a suggestion.
#[test]
fn unknown_functions_suggest_the_users_own() {
    let _watchdog = crate::watchdog::start();
    let e = |src: &str| evaluate(&program(src), Transfer::Srgb, &Options::default()).errors;
    let errors = e("fn pillar(h) = h\nlet b = pilar(1)");
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].message, "unknown function `pilar`");
    assert_eq!(errors[0].help.as_deref(), Some("did you mean `pillar`?"));
    let errors = e("let pillar = 1\nlet b = pilar(1)");
    assert_eq!(errors[0].message, "unknown function `pilar`");
    assert!(
        errors[0]
            .help
            .as_deref()
            .unwrap()
            .starts_with("the functions are sqrt"),
        "{errors:?}"
    );
}

/// The trail under a mistake: each loop iteration and call it is inside,
/// innermost first, each with where it starts.
#[test]
fn mistakes_in_nested_loops_and_calls_name_each() {
    let _watchdog = crate::watchdog::start();
    let help = |src: &str| {
        let e = evaluate(&program(src), Transfer::Srgb, &Options::default()).errors;
        assert_eq!(e.len(), 1, "{e:?}");
        assert_eq!(e[0].message, "division by zero");
        let help = e[0].help.clone().unwrap_or_default();
        let lines: Vec<String> = help.lines().map(str::to_string).collect();
        lines
    };
    let lines = help("for i in 0..3 {\n  for j in 1..3 {\n    let q = 1 / (i - 2 * j)\n  }\n}");
    assert!(
        lines.ends_with(&[
            "in iteration j = 1 of the loop at scene.rt:2:3".to_string(),
            "in iteration i = 2 of the loop at scene.rt:1:1".to_string(),
        ]),
        "{lines:?}"
    );
    let lines = help("fn f(h) = 1 / (h - 1)\nfor i in 0..3 {\n  let q = f(i)\n}");
    assert!(
        lines.ends_with(&[
            "in `f` called from scene.rt:3:11 with h = 1".to_string(),
            "in iteration i = 1 of the loop at scene.rt:2:1".to_string(),
        ]),
        "{lines:?}"
    );
}

/// After a loop or a call, a mistake is outside it: no trail names them.
#[test]
fn after_a_loop_or_call_the_trail_is_gone() {
    let _watchdog = crate::watchdog::start();
    for src in [
        "for i in 0..2 { sphere { } }\nlet q = 1 / 0",
        "fn f(h) = h\nlet a = f(1)\nlet q = 1 / 0",
        "for i in 0..2 {\n  for j in 0..2 { sphere { } }\n  let q = 1 / (1 - i)\n}",
    ] {
        let e = evaluate(&program(src), Transfer::Srgb, &Options::default()).errors;
        assert_eq!(e.len(), 1, "{e:?}");
        assert_eq!(e[0].message, "division by zero");
        let help = e[0].help.clone().unwrap_or_default();
        assert!(
            !help.contains("called from") && !help.contains("iteration j"),
            "{src}: {help}"
        );
        assert_eq!(
            help.contains("iteration i = 1"),
            src.contains("1 - i"),
            "{src}: {help}"
        );
    }
}

/// The string right after `implicit` carries the numeric constants in
/// scope (for its equation); other strings, a string first in its
/// sequence included, carry none.
#[test]
fn an_implicit_equation_carries_the_constants_in_scope() {
    let _watchdog = crate::watchdog::start();
    let strs = |src: &str| -> Vec<Option<Vec<(String, f64)>>> {
        let e = evaluate(&program(src), Transfer::Srgb, &Options::default());
        assert!(e.errors.is_empty(), "{:?}", e.errors);
        e.items
            .iter()
            .filter_map(|i| match i {
                Item::Str { constants, .. } => Some(constants.as_deref().cloned()),
                _ => None,
            })
            .collect()
    };
    let found = strs("let r = 2\nimplicit \"x^2 - r\" { }\nmesh \"a.ply\" { }\n\"b\"");
    assert_eq!(found.len(), 3, "{found:?}");
    let constants = found[0].as_ref().expect("constants");
    assert!(constants.contains(&("r".to_string(), 2.0)), "{constants:?}");
    assert_eq!(found[1..], [None, None]);
    assert_eq!(strs("\"a\""), [None]);
}

/// A call of a function of items among items is its items, once, traced
/// to the call, its parameter bound to the argument.
#[test]
fn a_call_of_an_items_function_is_its_items() {
    let _watchdog = crate::watchdog::start();
    let e = evaluate(
        &program("fn post(h) { sphere { radius h } }\npost(2)"),
        Transfer::Srgb,
        &Options::default(),
    );
    assert!(e.errors.is_empty(), "{:?}", e.errors);
    let [Item::Traced { items, .. }] = e.items.as_slice() else {
        panic!("{:?}", e.items);
    };
    assert_eq!(items.len(), 2, "{items:?}");
    assert_eq!(items[0].as_name().map(|n| n.node), Some("sphere"));
    let Item::Block(b) = &items[1] else {
        panic!("{items:?}");
    };
    let Item::Value(v) = &b.items[1] else {
        panic!("{b:?}");
    };
    assert_eq!(
        v.kind,
        ExprKind::Bound("h".into(), Some(Value::Number(2.0)))
    );
}

/// A value that failed (reported) is dropped where it stands as a
/// statement, with the block of a failed call, so that the builder does
/// not report it again; after a keyword it stays, as a failed value,
/// for the keyword.
#[test]
fn failed_values_are_dropped_as_statements_and_kept_after_keywords() {
    let _watchdog = crate::watchdog::start();
    for src in [
        "1 / 0\nsphere { }",
        "fn f(h) = 1 / h\nf(0)\nsphere { }",
        "fn f(h) = 1 / h\nf(0) { translate <1, 0, 0> }\nsphere { }",
    ] {
        let e = evaluate(&program(src), Transfer::Srgb, &Options::default());
        assert_eq!(e.errors.len(), 1, "{src}: {:?}", e.errors);
        assert_eq!(e.errors[0].message, "division by zero");
        assert_eq!(e.items.len(), 2, "{src}: {:?}", e.items);
        assert_eq!(e.items[0].as_name().map(|n| n.node), Some("sphere"));
        let Item::Block(b) = &e.items[1] else {
            panic!("{src}: {:?}", e.items);
        };
        assert!(b.items.is_empty(), "{src}: {b:?}");
    }
    let (v, errors) = radius("sphere { radius 1 / 0 }");
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(v, ExprKind::Bound("".into(), None));
}

/// A pattern value takes no block: one written after it (`colour tiles
/// { scale 2 }`) is reported where it stands, as a block the material
/// does not take, not wrapped with the pattern into a `group` as an
/// object value's block is.
#[test]
fn a_block_after_a_pattern_value_is_reported_where_it_stands() {
    let _watchdog = crate::watchdog::start();
    let src = "let tiles = checker { a white  b black }\n\
               sphere { material { colour tiles { scale 2 } } }";
    let p = program(src);
    let e = evaluate(&p, Transfer::Srgb, &Options::default());
    assert!(e.errors.is_empty(), "{:?}", e.errors);
    assert!(
        !format!("{:?}", e.items).contains("\"group\""),
        "{:?}",
        e.items
    );
    let errors = crate::scene::check(&p, &Options::default()).errors;
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].message.contains("found a block"),
        "{:?}",
        errors[0]
    );
    let at = src.find("{ scale").unwrap();
    assert_eq!(
        errors[0].span,
        Span::new(p.root, at, at + "{ scale 2 }".len())
    );
}

/// The step budget counts the work the evaluation keeps. An expression
/// naming something unknown here (left to the builder) is tried, and the
/// trial undone: it costs one step as an item, as a bare name does,
/// however long it is. A limit the trial runs into is met again at the
/// next item, not inside the expression, which the builder still gets
/// whole.
#[test]
fn an_expression_left_to_the_builder_costs_no_steps_of_its_own() {
    let _watchdog = crate::watchdog::start();
    let long = "sphere { radius 1 + 2 * q }\nsphere { }";
    let bare = "sphere { radius q }\nsphere { }";
    let run =
        |src: &str, steps: u64| evaluate(&program(src), Transfer::Srgb, &with_limits(steps, 10));
    let need = |src: &str| (0..100).find(|&n| run(src, n).errors.is_empty()).unwrap();
    assert_eq!(need(long), need(bare));
    let full = run(long, need(long));
    for src in [long, bare] {
        let p = program(src);
        // One step short, the last item (the second sphere's block) is not
        // made; two short, the second sphere itself.
        for (short, at, len) in [
            (1, src.rfind("{ }").unwrap(), 3),
            (2, src.rfind("sphere").unwrap(), 6),
        ] {
            let e = evaluate(&p, Transfer::Srgb, &with_limits(need(src) - short, 10));
            assert_eq!(e.errors.len(), 1, "{src}: {:?}", e.errors);
            assert!(
                e.errors[0].message.contains("evaluation steps"),
                "{:?}",
                e.errors
            );
            assert_eq!(
                e.errors[0].span,
                Span::new(p.root, at, at + len),
                "{src}: {:?}",
                e.errors
            );
            if src == long {
                assert_eq!(e.items[..], full.items[..full.items.len() - short as usize]);
            }
        }
    }
}
