//! Compiler tests: every equation of conventions.md, expansion against
//! direct evaluation, and each error kind.

use super::*;
use proptest::prelude::*;

fn consts(name: &str) -> Option<f64> {
    match name {
        "R" => Some(2.0),
        "r" => Some(0.5),
        "N" => Some(12.0),
        "half" => Some(0.5),
        _ => None,
    }
}

fn compile(s: &str) -> Result<Equation, Vec<EquationError>> {
    Equation::compile(s, &consts)
}

/// The equations conventions.md says must be taken as they are, with the
/// degree each must compile to.
pub const CONVENTIONS: &[(&str, u32)] = &[
    ("x^2 + y^2 + z^2 - 1", 2),
    ("(x^2 + y^2 + z^2)_2 - 1", 2),
    ("(((x^2 + y^2)_2 - 1.5)^2 + z^2)_2 - 0.5", 4),
    ("x^2 + y^2 + z^2 + -1", 2),
    ("x", 1),
    (
        "x^4 + 2x^2*y^2 + 2x^2*z^2 - 2*(1.5^2 + 0.5^2)*x^2 + y^4 + 2y^2*z^2 + 2*(1.5^2 - 0.5^2)*y^2 + z^4 - 2*(1.5^2 + 0.5^2)*z^2 + (1.5^2 - 0.5^2)^2",
        4,
    ),
    (
        "(x - 2)^2(x+2)^2 + (y - 2)^2(y+2)^2 + (z - 2)^2(z+2)^2 + 3(x^2*y^2 + x^2z^2 + y^2z^2) + 6x y z - 10(x^2 + y^2 + z^2) + 22",
        4,
    ),
    (
        "(x^2 + (4.0/9.0)*y^2 + z^2 - 1)^3 - x^2 * z^3 - (9.0/80.0)*y^2*z^3",
        6,
    ),
    (
        "6.25 * (x^2 + -1.0)^2 * x^1 + 8.33333333333333 * (x^2 + -1.0)^1 * x^3 + 1 * (x^2 + -1.0)^0 * x^5 + 6.25 * (y^2 + -1.0)^2 * y^1 + 8.33333333333333 * (y^2 + -1.0)^1 * y^3 + 1 * (y^2 + -1.0)^0 * y^5 + 6.25 * (z^2 + -1.0)^2 * z^1 + 8.33333333333333 * (z^2 + -1.0)^1 * z^3 + 1 * (z^2 + -1.0)^0 * z^5",
        5,
    ),
    ("(x^2+y^2+z^2+R^2-r^2)^2 - 4R^2(x^2+y^2)", 4),
];

#[test]
fn conventions_equations_compile_to_their_degree() {
    let _watchdog = crate::watchdog::start();
    for (s, d) in CONVENTIONS {
        let e = compile(s).unwrap_or_else(|e| panic!("{s}: {e:?}"));
        assert_eq!(e.degree(), *d, "{s}");
    }
}

#[test]
fn roots_are_removed() {
    let _watchdog = crate::watchdog::start();
    let a = compile("(x^2 + y^2 + z^2)_2 - 1").unwrap();
    let p = DVec3::new(0.3, -0.4, 0.5);
    let b = compile("x^2 + y^2 + z^2 - 1").unwrap();
    // Same zero set, opposite sign is allowed; same up to a factor.
    let ratio = a.value(p) / b.value(p);
    let q = DVec3::new(1.2, 0.1, -0.7);
    assert!((a.value(q) / b.value(q) - ratio).abs() < 1e-12);
    // Cube root and nested root: the torus from both routes.
    let nested = compile("(((x^2 + y^2)_2 - 1.5)^2 + z^2)_2 - 0.5").unwrap();
    let textbook = compile("(x^2+y^2+z^2+1.5^2-0.5^2)^2 - 4*1.5^2(x^2+y^2)").unwrap();
    for p in [
        DVec3::new(0.3, 1.2, 0.1),
        DVec3::new(-2.0, 0.5, 0.3),
        DVec3::ZERO,
    ] {
        let k = nested.value(p) / textbook.value(p);
        assert!((k - nested.value(q) / textbook.value(q)).abs() < 1e-9);
    }
    let cube = compile("(x^3 + y)_3 - 2").unwrap();
    assert_eq!(cube.degree(), 3);
    assert!(cube.value(DVec3::new(2.0, 0.0, 0.0)).abs() < 1e-12);
    assert!(cube.value(DVec3::new(1.0, 7.0, 0.0)).abs() < 1e-12);
}

#[test]
fn the_written_branch_is_kept() {
    let _watchdog = crate::watchdog::start();
    // sqrt(x²+y²+z²) + 1 = 0 has no real point although its square does.
    let e = compile("(x^2 + y^2 + z^2)_2 + 1").unwrap();
    assert!(!e.on_written_branch(DVec3::new(1.0, 0.0, 0.0)));
    let e = compile("(x^2 + y^2 + z^2)_2 - 1").unwrap();
    assert!(e.on_written_branch(DVec3::new(0.0, 1.0, 0.0)));
    // x = sqrt(y): only the half x ≥ 0 of the parabola x² = y.
    let e = compile("x - (y)_2").unwrap();
    assert!(e.on_written_branch(DVec3::new(2.0, 4.0, 0.0)));
    assert!(!e.on_written_branch(DVec3::new(-2.0, 4.0, 0.0)));
}

#[test]
fn rhs_and_constants() {
    let _watchdog = crate::watchdog::start();
    let a = compile("x^2 + y^2 = 1 - z^2").unwrap();
    let b = compile("x^2 + y^2 + z^2 - 1").unwrap();
    let p = DVec3::new(0.1, 0.7, -2.0);
    assert!((a.value(p) - b.value(p)).abs() < 1e-12);
    // 4R^2 with R = 2 is 16; R^2 is R squared, not 4R squared.
    let e = compile("4R^2 - x").unwrap();
    assert!(e.value(DVec3::new(16.0, 0.0, 0.0)).abs() < 1e-12);
    let e = compile("x^N - 1").unwrap();
    assert_eq!(e.degree(), 12);
    // Unary minus binds tightest: -x^2 = x^2.
    let e = compile("-x^2 - 4").unwrap();
    assert!(e.value(DVec3::new(2.0, 0.0, 0.0)).abs() < 1e-12);
}

fn first_error(s: &str) -> EquationError {
    match compile(s) {
        Ok(_) => panic!("{s} compiled"),
        Err(e) => e[0].clone(),
    }
}

#[test]
fn errors_point_inside_the_string() {
    let _watchdog = crate::watchdog::start();
    let e = first_error("x^2 + w^2 - 1");
    assert_eq!(e.message, "unknown variable `w`");
    assert_eq!(e.span, 6..7);
    let e = first_error("xy - 1");
    assert_eq!(e.span, 0..2);
    assert!(e.help.unwrap().contains("x y"), "one name, suggest a space");
    let e = first_error("Rx - 1");
    assert!(e.help.unwrap().contains("R x"));
    let e = first_error("X - 1");
    assert!(e.help.unwrap().contains("`x`"));

    let e = first_error("x^2.5 - 1");
    assert_eq!(e.message, "non-integer exponent 2.5");
    assert_eq!(e.span, 2..5);
    let e = first_error("(x^2)_0 - 1");
    assert_eq!(e.message, "root of degree 0");
    assert_eq!(e.span, 6..7);
    let e = first_error("x^41 - 1");
    assert!(
        e.message.contains("degree 41, above the limit of 40"),
        "{}",
        e.message
    );
    let e = first_error("1 / (x + 1) - y");
    assert_eq!(e.message, "division by an expression containing x, y or z");
    assert_eq!(e.span, 4..11);
    assert_eq!(first_error("").message, "empty equation");
    assert_eq!(first_error("   ").message, "empty equation");
    assert_eq!(first_error("x / 0").message, "division by zero");
    assert!(first_error("x^y").message.contains("constant integer"));
    assert!(first_error("x^-1").message.contains("negative exponent"));
    assert!(first_error("(-4)_2 + x").message.contains("even root"));
    assert!(first_error("(x + 1)^1000000").message.contains("too large"));
    assert!(first_error("x - x").message.contains("does not depend"));
    assert_eq!(first_error("x + ").span.start, 4);
    // Several unknown names are all reported.
    assert_eq!(compile("a + b + x").unwrap_err().len(), 2);
}

/// A random polynomial-ish expression in the equation grammar, with its
/// direct value at a point computed alongside.
fn arb_expr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        Just("z".to_string()),
        Just("R".to_string()),
        (0u32..20).prop_map(|n| format!("{}", n as f64 / 4.0)),
    ];
    leaf.prop_recursive(4, 24, 3, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} + {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a} - {b})")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("({a})({b})")),
            (inner.clone(), 0u32..4).prop_map(|(a, k)| format!("({a})^{k}")),
            inner.clone().prop_map(|a| format!("-({a})")),
            inner.clone().prop_map(|a| format!("({a})/4")),
        ]
    })
}

/// Direct evaluation of the same strings with a tiny recursive evaluator
/// over the parse tree (independent of the expansion).
fn direct(s: &str, p: DVec3) -> f64 {
    let parsed = parse::parse(s).unwrap();
    fn go(e: &parse::Expr, p: DVec3) -> f64 {
        use parse::Node::*;
        match &e.node {
            Num(v) => *v,
            Name(n) => match n.as_str() {
                "x" => p.x,
                "y" => p.y,
                "z" => p.z,
                other => consts(other).unwrap(),
            },
            Neg(a) => -go(a, p),
            Sum(ts) => ts
                .iter()
                .map(|(m, t)| if *m { -go(t, p) } else { go(t, p) })
                .sum(),
            Product(fs) => fs.iter().fold(
                1.0,
                |acc, (d, f)| if *d { acc / go(f, p) } else { acc * go(f, p) },
            ),
            Pow(a, k) => go(a, p).powi(go(k, p) as i32),
            Root(a, k) => go(a, p).powf(1.0 / go(k, p)),
        }
    }
    go(&parsed.lhs, p)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn expansion_matches_direct_evaluation(s in arb_expr(), px in -1.5f64..1.5, py in -1.5f64..1.5, pz in -1.5f64..1.5) {
        let _watchdog = crate::watchdog::start();
        let p = DVec3::new(px, py, pz);
        let want = direct(&s, p);
        let Ok(eq) = Equation::compile(&s, &consts) else {
            // Constant expressions are refused; nothing else may be.
            let parsed = parse::parse(&s).unwrap();
            let q = DVec3::new(0.3, -0.9, 1.1);
            prop_assert!((direct(&s, q) - direct(&s, p)).abs() < 1e-9 * (1.0 + want.abs()) || parsed.rhs.is_some());
            return Ok(());
        };
        // The compiled polynomial is scaled: compare ratios at two points.
        let q = DVec3::new(0.7, 0.2, -0.4);
        let (a, b) = (eq.value(p), eq.value(q));
        let (wa, wb) = (want, direct(&s, q));
        let tol = 1e-7 * (1.0 + wa.abs()) * (1.0 + wb.abs()) * 1e3;
        prop_assert!((a * wb - b * wa).abs() <= tol, "{s}: {a} {b} vs {wa} {wb}");
    }

    #[test]
    fn never_panics_on_any_text(s in "\\PC{0,40}") {
        let _watchdog = crate::watchdog::start();
        let _ = Equation::compile(&s, &consts);
    }

    #[test]
    fn never_panics_on_equation_like_text(s in "[xyzRr0-9 .+*/^_()=-]{0,40}") {
        let _watchdog = crate::watchdog::start();
        let _ = Equation::compile(&s, &consts);
    }
}

/// How an equation error looks once the builder hands it to miette (here
/// with the string itself as the source; the builder shifts the span into
/// the .rt file instead).
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
#[error("{message}")]
struct Shown {
    message: String,
    #[source_code]
    src: miette::NamedSource<String>,
    #[label("here")]
    at: miette::SourceSpan,
    #[help]
    help: Option<String>,
}

fn render_error(text: &str) -> String {
    let _watchdog = crate::watchdog::start();
    let errors = compile(text).expect_err("an error");
    let mut out = String::new();
    for e in errors {
        let shown = Shown {
            message: e.message,
            src: miette::NamedSource::new("equation", text.to_string()),
            at: (e.span.start, e.span.len()).into(),
            help: e.help,
        };
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .with_width(80)
            .render_report(&mut out, &shown)
            .expect("rendering to a string");
    }
    out
}

#[test]
fn diagnostic_snapshots() {
    let _watchdog = crate::watchdog::start();
    for (name, text) in [
        ("unknown_variable", "x^2 + w^2 - 1"),
        ("one_name", "xy + z - 1"),
        ("non_integer_exponent", "x^2.5 + y - 1"),
        ("root_of_degree_0", "(x^2 + y^2)_0 - 1"),
        ("degree_cap", "x^50 + y^2 - 1"),
        ("division", "x^2 / (y + 1) - 1"),
        ("empty", ""),
        ("syntax", "x^2 + * y"),
    ] {
        insta::assert_snapshot!(name, render_error(text));
    }
}

/// Fuzz find: nested roots made the elimination run thousands of products,
/// each under the per-product cap, for minutes. Now the whole compile has
/// one budget and this is refused at once.
#[test]
fn nested_roots_cannot_run_for_minutes() {
    let _watchdog = crate::watchdog::start();
    let s = "(x^3 +(((x - .1 r^2)_2 - 1.5)^2  +y)_2 - 2 z^2)333333 * (y^2 + (((x - .1 r^2)_2 - 1.5)^2  +y)_2 - 2 z^2)333333 * (y^2 + -1.0)_1 * y^3 + 1 * (y^2 + -1.0)^0 * y^5 + 6.25 * (z^2 + -1.0)^2(z^2 + -1.0)^0 * z^5";
    let e = first_error(s);
    assert!(e.message.contains("too many terms"), "{}", e.message);
    // The budget is per compile: a normal equation still compiles after.
    assert!(compile("x^2 + y^2 + z^2 - 1").is_ok());
    assert_eq!(compile("(x + y + z)^40 - 1").unwrap().degree(), 40);
}

/// Fuzz find: an equation with many terms and a root made the elimination
/// copy a growing sum once per term (quadratic, uncounted by the budget).
#[test]
fn long_sums_around_roots_stay_quick() {
    let _watchdog = crate::watchdog::start();
    let s = "-x-x (y)_2^2*z  (x^3 (y)_2^2*z  (x^3 + y)_2 - 2 (y)_2^2*z + y)_2 - 2 (y)_2^2*z  (x^2 + 4/4 y^2 +4(x^3 + y)_2 - 2 (y)_2^2*z + y)_2 - 2 (y)_2^2*z  (x^2 + 4/4 y^2 +4 z^2 -  z^2 - 1)^3 8/- 9--0 y_2 z^3";
    let clock = std::time::Instant::now();
    let out = compile(s);
    // Quick: well inside the watchdog's minute (it took minutes before).
    assert!(
        clock.elapsed() < std::time::Duration::from_secs(5),
        "{:?}",
        clock.elapsed()
    );
    // And an answer either way: a surface of some degree within the cap,
    // or a diagnostic saying why not.
    match out {
        Ok(eq) => assert!((1..=40).contains(&eq.degree()), "degree {}", eq.degree()),
        Err(errs) => assert!(!errs.is_empty() && !errs[0].message.is_empty()),
    }
}

/// Issue 17: twenty objects with one degree-40 equation loaded 20× as slowly
/// as one, in the automatic box's thousands of solves; the memo's clones
/// now share the box, found once.
#[test]
fn equal_equations_share_their_automatic_box() {
    let text = "x^40 + y^40 + z^40 - 1.25";
    let a = Equation::compile(text, &|_| None).unwrap();
    let b = Equation::compile(text, &|_| None).unwrap();
    assert!(std::sync::Arc::ptr_eq(&a.auto_box, &b.auto_box));
    let found = a.auto_bounds().expect("a bounded surface");
    // The box holds the surface: (1.25)^(1/40) along each axis.
    let r = 1.25f64.powf(1.0 / 40.0);
    assert!(found.max.x >= r && found.max.x < r * 1.05, "{found:?}");
    assert_eq!(b.auto_box.get().copied(), Some(Some(found)));
}
