//! Unit tests of `expr.rs`, kept in their own file so the module reads
//! as the code alone.

use super::*;
use crate::lang::ast::FileId;
use crate::lang::ast::Item;
use crate::lang::parser::parse;

fn eval(src: &str) -> Result<Value, Vec<Error>> {
    let Item::Let { value, .. } = parse(&format!("let v = {src}"), FileId(0))
        .unwrap_or_else(|e| panic!("{src} does not parse: {e:?}"))
        .remove(0)
    else {
        panic!()
    };
    let env = Env::new(Transfer::Gamma(2.0));
    let mut errors = Vec::new();
    env.eval(&value, &mut errors).ok_or(errors)
}

#[test]
fn colour_table_is_sorted_and_has_148_names() {
    assert!(COLOURS.windows(2).all(|w| w[0].0 < w[1].0));
    assert_eq!(COLOURS.len(), 148);
    assert_eq!(named_colour("green"), Some([0, 128, 0]));
}

#[test]
fn arithmetic() {
    assert_eq!(eval("-2^2"), Ok(Value::Number(-4.0)));
    assert_eq!(eval("2 * pi / pi"), Ok(Value::Number(2.0)));
    assert_eq!(
        eval("<1, 2, 3> * 2 - <1, 1, 1>"),
        Ok(Value::Vector(smallvec::smallvec![1.0, 3.0, 5.0]))
    );
    assert_eq!(eval("max(1, sqrt(9))"), Ok(Value::Number(3.0)));
    assert_eq!(eval("deg(rad(90))"), Ok(Value::Number(90.0)));
}

#[test]
fn conditions_remainders_lists_and_indices() {
    assert_eq!(eval("7 % 3"), Ok(Value::Number(1.0)));
    assert_eq!(eval("-1 % 12"), Ok(Value::Number(11.0)));
    assert_eq!(eval("1 + 2 == 3 and not (2 < 1)"), Ok(Value::Bool(true)));
    assert_eq!(
        eval("1 >= 2 or <1, 2, 3> != <1, 2, 3>"),
        Ok(Value::Bool(false))
    );
    assert_eq!(eval("[1, 2] + [3]"), eval("[1, 2, 3]"));
    assert_eq!(eval("[<1, 2, 3>][0][2]"), Ok(Value::Number(3.0)));
    assert_eq!(eval("len([1, 2, 3])"), Ok(Value::Number(3.0)));
    assert_eq!(
        eval("lerp(<0, 0, 0>, <2, 4, 6>, 0.5)"),
        Ok(Value::Vector(smallvec::smallvec![1.0, 2.0, 3.0]))
    );
    // `and` stops early: the index out of range is never evaluated.
    assert_eq!(eval("1 > 2 and [1][5] == 0"), Ok(Value::Bool(false)));
    let e = eval("[1, 2][2]").unwrap_err();
    assert_eq!(e[0].message, "index 2 is out of range");
    assert_eq!(e[0].label, "the list has 2 elements");
    let e = eval("5 % 0").unwrap_err();
    assert_eq!(e[0].message, "division by zero");
    let e = eval("1 < <1, 2, 3>").unwrap_err();
    assert!(
        e[0].message.starts_with("cannot compare"),
        "{}",
        e[0].message
    );
    let e = eval("not 1").unwrap_err();
    assert!(e[0].message.contains("needs a condition"));
}

#[test]
fn vector_built_ins() {
    assert_eq!(eval("dot(<1, 2, 3>, <4, 5, 6>)"), Ok(Value::Number(32.0)));
    assert_eq!(
        eval("cross(<0, 1, 0>, <0, 0, 1>)"),
        Ok(Value::Vector(smallvec::smallvec![1.0, 0.0, 0.0]))
    );
    assert_eq!(eval("length(<2, 3, 6>)"), Ok(Value::Number(7.0)));
    assert!(eval("normalize(<0, 0, 0>)").is_err());
    assert!(
        eval("dot(1, <1, 2, 3>)").unwrap_err()[0]
            .message
            .contains("needs a 3-vector")
    );
    assert_eq!(eval("clamp(5, 0, 1)"), Ok(Value::Number(1.0)));
    assert_eq!(
        eval("atan2(1, 0) * 2"),
        Ok(Value::Number(std::f64::consts::PI))
    );
}

#[test]
fn hex_and_named_colours_decode_with_the_transfer() {
    // gamma 2: display 128/255 decodes by squaring.
    let g = (128.0f64 / 255.0).powi(2);
    assert_eq!(eval("#008000"), Ok(Value::Colour(Colour::new(0.0, g, 0.0))));
    assert_eq!(eval("green"), Ok(Value::Colour(Colour::new(0.0, g, 0.0))));
    assert_eq!(
        eval("rgb(0, 0.5, 0)"),
        Ok(Value::Colour(Colour::new(0.0, 0.5, 0.0)))
    );
}

#[test]
fn mistakes_point_at_their_characters() {
    let e = eval("1 / 0").unwrap_err();
    assert_eq!(e[0].message, "division by zero");
    let e = eval("sqrt(-1)").unwrap_err();
    assert_eq!((e[0].span.start, e[0].span.end), (13, 15));
    let e = eval("sqr(2)").unwrap_err();
    assert_eq!(e[0].help.as_deref(), Some("did you mean `sqrt`?"));
    let e = eval("<1, 2> + <1, 2, 3>").unwrap_err();
    assert!(
        e[0].message.contains("cannot add a 2-vector to a 3-vector"),
        "{}",
        e[0].message
    );
    let e = eval("whte").unwrap_err();
    assert_eq!(e[0].help.as_deref(), Some("did you mean `white`?"));
    let e = eval("1e999").unwrap_err();
    assert!(e[0].message.contains("too large"));
    let e = eval("10 ^ 400").unwrap_err();
    assert!(e[0].message.contains("finite"));
}

#[test]
fn numeric_builtins_take_at_most_three_arguments_and_use_each() {
    // `call` reads numeric arguments into a [f64; 3]: a built-in with more
    // would not fit. Each place must still reach the maths.
    assert!(FUNCTIONS.iter().all(|(_, arity)| *arity <= 3));
    assert!(matches!(eval("clamp(5, 1, 3)"), Ok(Value::Number(x)) if x == 3.0));
    assert!(matches!(eval("min(4, 2)"), Ok(Value::Number(x)) if x == 2.0));
    assert!(
        matches!(eval("atan2(1, 0)"), Ok(Value::Number(x)) if (x - std::f64::consts::FRAC_PI_2).abs() < 1e-12)
    );
    let Ok(Value::Colour(c)) = eval("rgb(0.25, 0.5, 1)") else {
        panic!("rgb is a colour")
    };
    assert_eq!(c, Colour::new(0.25, 0.5, 1.0));
    let e = eval("rgb(0.5, -1, 0)").unwrap_err();
    assert!(e[0].message.contains("cannot be negative"));
}

/// The number `src` evaluates to (panics on anything else).
fn num(src: &str) -> f64 {
    match eval(src) {
        Ok(Value::Number(x)) => x,
        other => panic!("{src}: {other:?}"),
    }
}

fn vector(src: &str) -> Vec<f64> {
    match eval(src) {
        Ok(Value::Vector(v)) => v.to_vec(),
        other => panic!("{src}: {other:?}"),
    }
}

fn colour(src: &str) -> Colour {
    match eval(src) {
        Ok(Value::Colour(c)) => c,
        other => panic!("{src}: {other:?}"),
    }
}

/// The first mistake's message and label.
fn mistake(src: &str) -> (String, String) {
    match eval(src) {
        Err(e) => (e[0].message.clone(), e[0].label.clone()),
        Ok(v) => panic!("{src} gave {v:?}"),
    }
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + b.abs())
}

#[test]
fn every_operator_gives_its_known_value() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(num("2 ^ 10"), 1024.0);
    assert_eq!(num("7 - 10"), -3.0);
    assert_eq!(num("3 * 4"), 12.0);
    assert_eq!(num("6 / 4"), 1.5);
    assert_eq!(num("3 + 4"), 7.0);
    // Remainders take the divisor's sign, in whole numbers and not.
    for (src, want) in [
        ("7 % 3", 1.0),
        ("-7 % 3", 2.0),
        ("7 % -3", 1.0),
        ("-7 % -3", 2.0),
        ("-1 % 12", 11.0),
        ("-6 % 3", 0.0),
        ("6 % 3", 0.0),
        ("7.5 % 2", 1.5),
        ("-0.5 % 2", 1.5),
        ("7 % 2.5", 2.0),
        ("9007199254740993 % 10", 2.0),
        // Whole numbers past i64 (10^20 = 2^20·5^20 is exact; 10 ≡ 3 and
        // 3^6 ≡ 1 mod 7, so 10^20 ≡ 3^2 ≡ 2).
        ("1e20 % 7", 2.0),
        ("-1e20 % 7", 5.0),
    ] {
        assert_eq!(num(src), want, "{src}");
    }
    // A whole remainder of 0 keeps the dividend's sign, as `rem_euclid`:
    // atan2 tells -0 from 0.
    assert_eq!(num("atan2(-6 % 3, -1)"), -std::f64::consts::PI);
    assert_eq!(num("atan2(6 % 3, -1)"), std::f64::consts::PI);
    // Comparisons on both sides of a tie.
    for (src, want) in [
        ("1 < 2", true),
        ("2 < 2", false),
        ("3 < 2", false),
        ("2 <= 2", true),
        ("3 <= 2", false),
        ("1 <= 2", true),
        ("2 > 2", false),
        ("3 > 2", true),
        ("1 > 2", false),
        ("2 >= 2", true),
        ("1 >= 2", false),
        ("3 >= 2", true),
        ("2 == 2", true),
        ("2 == 3", false),
        ("2 != 3", true),
        ("2 != 2", false),
        ("<1, 2, 3> == <1, 2, 3>", true),
        ("<1, 2, 3> == <1, 2, 4>", false),
        ("rgb(1, 2, 3) == rgb(1, 2, 3)", true),
        ("rgb(1, 2, 3) != rgb(1, 2, 4)", true),
        ("(1 < 2) == (2 < 3)", true),
        ("(1 < 2) == (3 < 2)", false),
        ("[1, 2] == [1, 2]", true),
        ("[1, 2] == [2, 1]", false),
    ] {
        assert_eq!(eval(src), Ok(Value::Bool(want)), "{src}");
    }
    // `and` and `or` in all four cases, and `or` stops early.
    for (src, want) in [
        ("1 < 2 and 2 < 3", true),
        ("1 < 2 and 3 < 2", false),
        ("2 < 1 and 2 < 3", false),
        ("1 < 2 or 3 < 2", true),
        ("2 < 1 or 2 < 3", true),
        ("2 < 1 or 3 < 2", false),
        ("1 < 2 or [1][5] == 0", true),
        ("not (1 < 2)", false),
        ("not (2 < 1)", true),
    ] {
        assert_eq!(eval(src), Ok(Value::Bool(want)), "{src}");
    }
    // Vectors.
    assert_eq!(vector("<1, 2, 3> + <4, 6, 8>"), [5.0, 8.0, 11.0]);
    assert_eq!(vector("<1, 2, 3> - <4, 6, 8>"), [-3.0, -4.0, -5.0]);
    assert_eq!(vector("<1, 2, 3> * 2"), [2.0, 4.0, 6.0]);
    assert_eq!(vector("2 * <1, 2, 3>"), [2.0, 4.0, 6.0]);
    assert_eq!(vector("<2, 4, 6> / 4"), [0.5, 1.0, 1.5]);
    assert_eq!(vector("-<1, -2, 3>"), [-1.0, 2.0, -3.0]);
    assert_eq!(vector("<1, 2>"), [1.0, 2.0]);
    assert_eq!(num("-(2)"), -2.0);
    // Colours.
    assert_eq!(
        colour("rgb(1, 2, 3) + rgb(4, 6, 8)"),
        Colour::new(5.0, 8.0, 11.0)
    );
    assert_eq!(
        colour("rgb(4, 6, 8) - rgb(1, 2, 3)"),
        Colour::new(3.0, 4.0, 5.0)
    );
    assert_eq!(
        colour("rgb(1, 2, 3) * rgb(4, 6, 8)"),
        Colour::new(4.0, 12.0, 24.0)
    );
    assert_eq!(colour("rgb(1, 2, 3) * 2"), Colour::new(2.0, 4.0, 6.0));
    assert_eq!(colour("2 * rgb(1, 2, 3)"), Colour::new(2.0, 4.0, 6.0));
    assert_eq!(colour("rgb(2, 4, 6) / 4"), Colour::new(0.5, 1.0, 1.5));
    // Lists and indices.
    assert_eq!(eval("([1] + [2, 3])[2]"), Ok(Value::Number(3.0)));
    assert_eq!(num("<4, 5, 6>[1]"), 5.0);
    assert_eq!(num("[4, 5, 6][0]"), 4.0);
    assert_eq!(num("pi"), std::f64::consts::PI);
}

#[test]
fn every_built_in_gives_its_known_value() {
    let _watchdog = crate::watchdog::start();
    use std::f64::consts::{E, FRAC_PI_2, PI};
    for (src, want) in [
        ("sqrt(16)", 4.0),
        ("sqrt(0)", 0.0),
        ("log(1)", 0.0),
        ("exp(0)", 1.0),
        ("exp(1)", E),
        ("log(exp(3))", 3.0),
        ("sin(0)", 0.0),
        ("sin(pi / 2)", 1.0),
        ("cos(0)", 1.0),
        ("cos(pi)", -1.0),
        ("tan(0)", 0.0),
        ("tan(pi / 4)", 1.0),
        ("rad(180)", PI),
        ("deg(pi)", 180.0),
        ("abs(-3)", 3.0),
        ("abs(3)", 3.0),
        ("min(4, 2)", 2.0),
        ("min(2, 4)", 2.0),
        ("max(4, 2)", 4.0),
        ("max(2, 4)", 4.0),
        ("floor(-1.5)", -2.0),
        ("floor(1.5)", 1.0),
        ("ceil(-1.5)", -1.0),
        ("ceil(1.5)", 2.0),
        ("round(2.5)", 3.0),
        ("round(-2.5)", -3.0),
        ("round(2.4)", 2.0),
        ("atan2(1, 0)", FRAC_PI_2),
        ("atan2(0, -1)", PI),
        ("atan2(0, 1)", 0.0),
        ("clamp(-5, 0, 1)", 0.0),
        ("clamp(0.5, 0, 1)", 0.5),
        ("clamp(5, 0, 1)", 1.0),
        ("lerp(2, 6, 0.25)", 3.0),
        ("lerp(2, 6, 0)", 2.0),
        ("lerp(2, 6, 1)", 6.0),
        ("len(<1, 2>)", 2.0),
        ("len([])", 0.0),
        ("len([1, [2, 3], 4])", 3.0),
        ("length(<2, 3, 6>)", 7.0),
        ("length(<0, 0, 0>)", 0.0),
        ("dot(<1, 2, 3>, <4, 5, 6>)", 32.0),
    ] {
        let got = num(src);
        assert!(near(got, want), "{src} = {got}, not {want}");
    }
    assert_eq!(vector("normalize(<3, 0, 4>)"), [0.6, 0.0, 0.8]);
    assert_eq!(vector("normalize(<0, -2, 0>)"), [0.0, -1.0, 0.0]);
    // a × b = <a₂b₃ − a₃b₂, a₃b₁ − a₁b₃, a₁b₂ − a₂b₁>
    assert_eq!(
        vector("cross(<1, 2, 3>, <4, 5, 7>)"),
        [2.0 * 7.0 - 3.0 * 5.0, 3.0 * 4.0 - 7.0, 5.0 - 2.0 * 4.0]
    );
    assert_eq!(vector("cross(<1, 0, 0>, <0, 1, 0>)"), [0.0, 0.0, 1.0]);
    assert_eq!(vector("lerp(<0, 2, 4>, <4, 2, 0>, 0.25)"), [1.0, 2.0, 3.0]);
    assert_eq!(
        colour("lerp(rgb(0, 2, 4), rgb(4, 2, 0), 0.25)"),
        Colour::new(1.0, 2.0, 3.0)
    );
    assert_eq!(colour("rgb(0, 0, 0)"), Colour::new(0.0, 0.0, 0.0));
    assert_eq!(colour("rgb(1, 2, 3)"), Colour::new(1.0, 2.0, 3.0));
    // random: the same numbers for the same arguments, in [0, 1), -0 as 0,
    // the two arguments not interchangeable, the pure function itself.
    assert_eq!(num("random(7, 3)"), random(7.0, 3.0));
    assert_eq!(num("random(-0, 1)"), num("random(0, 1)"));
    assert_eq!(num("random(1, -0)"), num("random(1, 0)"));
    assert_ne!(num("random(1, 2)"), num("random(2, 1)"));
    let xs: Vec<f64> = (0..1000).map(|i| random(3.0, i as f64)).collect();
    assert!(xs.iter().all(|x| (0.0..1.0).contains(x)));
    let mean = xs.iter().sum::<f64>() / xs.len() as f64;
    assert!((mean - 0.5).abs() < 0.05, "{mean}");
    assert!(xs.iter().any(|x| *x < 0.01) && xs.iter().any(|x| *x > 0.99));
}

#[test]
fn mistakes_in_operators_and_built_ins_say_what_and_where() {
    let _watchdog = crate::watchdog::start();
    for (src, message, label) in [
        ("sqrt(-1)", "square root of a negative number", "this is -1"),
        (
            "log(0)",
            "logarithm of a number that is not positive",
            "this is 0",
        ),
        (
            "log(-2)",
            "logarithm of a number that is not positive",
            "this is -2",
        ),
        (
            "rgb(0, -1, 0)",
            "a colour component cannot be negative",
            "this is -1",
        ),
        (
            "normalize(<0, 0, 0>)",
            "cannot normalize a zero vector",
            "its length is 0",
        ),
        (
            "len(3)",
            "`len` needs a list here, found a number",
            "this is a number",
        ),
        (
            "length(<1, 2>)",
            "`length` needs a 3-vector here, found a 2-vector",
            "this is a 2-vector",
        ),
        (
            "cross(<1, 2, 3>, 1)",
            "`cross` needs a 3-vector here, found a number",
            "this is a number",
        ),
        (
            "min(1, <1, 2, 3>)",
            "`min` needs a number here, found a 3-vector",
            "this is a 3-vector",
        ),
        (
            "lerp(1, 2, <1, 2, 3>)",
            "`lerp` needs a number here, found a 3-vector",
            "this is a 3-vector",
        ),
        (
            "lerp(1, <1, 2, 3>, 0.5)",
            "`lerp` cannot mix a number and a 3-vector",
            "different kinds",
        ),
        (
            "lerp(<1, 2>, <1, 2, 3>, 0.5)",
            "`lerp` cannot mix a 2-vector and a 3-vector",
            "different kinds",
        ),
        ("min(1)", "`min` takes 2 arguments, not 1", "1 given"),
        ("sqrt(1, 2)", "`sqrt` takes 1 argument, not 2", "2 given"),
        (
            "min(1, b: 2)",
            "`min` takes no named arguments",
            "named argument",
        ),
        ("qqqqqq(1)", "unknown function `qqqqqq`", "not a function"),
        (
            "1 - <1, 2, 3>",
            "cannot subtract a 3-vector from a number",
            "a number - a 3-vector",
        ),
        (
            "<1, 2, 3> + 1",
            "cannot add a 3-vector to a number",
            "a 3-vector + a number",
        ),
        (
            "<1, 2, 3> ^ 2",
            "cannot raise a 3-vector to the power a number",
            "a 3-vector ^ a number",
        ),
        (
            "[1] * 2",
            "cannot multiply a list of 1 by a number",
            "a list of 1 * a number",
        ),
        (
            "2 / <1, 2, 3>",
            "cannot divide a number by a 3-vector",
            "a number / a 3-vector",
        ),
        (
            "<1, 2, 3> % 2",
            "cannot take the remainder of a 3-vector by a number",
            "a 3-vector % a number",
        ),
        (
            "[1] < [2]",
            "cannot compare a list of 1 with a list of 1",
            "a list of 1 < a list of 1",
        ),
        (
            "1 == <1, 2, 3>",
            "cannot compare a number with a 3-vector",
            "a number == a 3-vector",
        ),
        ("1 / 0", "division by zero", "divides by zero"),
        ("1 % 0", "division by zero", "divides by zero"),
        (
            "<1, 2, 3> / 0",
            "this does not give a finite value",
            "infinite or not a number",
        ),
        (
            "<1e300, 0, 0> * 1e300",
            "this does not give a finite value",
            "infinite or not a number",
        ),
        (
            "rgb(1e300, 0, 0) * 1e300",
            "this does not give a finite value",
            "infinite or not a number",
        ),
        (
            "rgb(1e300, 0, 0) / 0",
            "this does not give a finite value",
            "infinite or not a number",
        ),
        (
            "rgb(1, 1, 1) - 2",
            "cannot subtract a number from a colour",
            "a colour - a number",
        ),
        (
            "exp(1000)",
            "this does not give a finite value",
            "infinite or not a number",
        ),
        (
            "-rgb(1, 1, 1)",
            "cannot negate a colour",
            "this is a colour",
        ),
        (
            "-(1 < 2)",
            "cannot negate a condition (true or false)",
            "this is a condition (true or false)",
        ),
        (
            "not [1, 2]",
            "`not` needs a condition, found a list of 2",
            "this is a list of 2",
        ),
        (
            "1 and 1 < 2",
            "expected a condition, found a number",
            "this is a number",
        ),
        (
            "1 < 2 and 3",
            "expected a condition, found a number",
            "this is a number",
        ),
        (
            "<1, (1 < 2)>",
            "a vector's components must be numbers",
            "this is a condition (true or false)",
        ),
        (
            "<1, 2, 3>[3]",
            "index 3 is out of range",
            "the vector has 3 elements",
        ),
        (
            "[1][1]",
            "index 1 is out of range",
            "the list has 1 element",
        ),
        (
            "[1, 2][-1]",
            "index -1 is out of range",
            "the list has 2 elements",
        ),
        (
            "[1, 2][0.5]",
            "index 0.5 is out of range",
            "the list has 2 elements",
        ),
        (
            "[][0]",
            "index 0 is out of range",
            "the list has 0 elements",
        ),
        (
            "[1, 2][<1, 2>]",
            "an index must be a number, found a 2-vector",
            "this is a 2-vector",
        ),
        ("3[0]", "cannot index a number", "this is a number"),
        (
            "nowhere_at_all",
            "unknown name `nowhere_at_all`",
            "not defined",
        ),
    ] {
        assert_eq!(mistake(src), (message.into(), label.into()), "{src}");
    }
    // The help names the last valid index, or that there is none.
    let help = |src: &str| eval(src).unwrap_err()[0].help.clone();
    assert_eq!(
        help("<1, 2, 3>[3]").as_deref(),
        Some("indices are whole numbers from 0 to 2")
    );
    assert_eq!(help("[][0]").as_deref(), Some("it is empty"));
    assert!(
        help("qqqqqq(1)")
            .unwrap()
            .starts_with("the functions are sqrt")
    );
    // Both sides of an operator, and every argument, are reported.
    assert_eq!(eval("nowhere + nothing").unwrap_err().len(), 2);
    assert_eq!(eval("min(nowhere, nothing)").unwrap_err().len(), 2);
    assert_eq!(eval("<nowhere, nothing>").unwrap_err().len(), 2);
    assert_eq!(eval("[nowhere, nothing]").unwrap_err().len(), 2);
    // A wrong argument count is reported even when an argument failed.
    assert_eq!(
        eval("min(nowhere)").unwrap_err()[1].message,
        "`min` takes 2 arguments, not 1"
    );
}

fn fragment(src: &str) -> Value {
    let items = parse(src, FileId(0)).unwrap();
    let span = items[0].as_name().unwrap().span;
    Value::Items(Arc::new(Fragment { items, span }))
}

#[test]
fn values_name_their_kind_and_show_themselves() {
    let _watchdog = crate::watchdog::start();
    let kind = |src: &str| eval(src).unwrap().kind();
    assert_eq!(kind("1"), "a number");
    assert_eq!(kind("<1, 2>"), "a 2-vector");
    assert_eq!(kind("rgb(1, 1, 1)"), "a colour");
    assert_eq!(kind("1 < 2"), "a condition (true or false)");
    assert_eq!(kind("[1, 2, 3]"), "a list of 3");
    assert_eq!(fragment("material { }").kind(), "a material");
    assert_eq!(fragment("sphere { }").kind(), "an object (`sphere`)");
    assert_eq!(fragment("checker { }").kind(), "a pattern (`checker`)");
    let Value::Items(f) = fragment("material { }") else {
        unreachable!()
    };
    assert_eq!((f.head(), f.is_material()), ("material", true));
    let Value::Items(f) = fragment("sphere { }") else {
        unreachable!()
    };
    assert_eq!((f.head(), f.is_material()), ("sphere", false));
    let show = |src: &str| eval(src).unwrap().show();
    assert_eq!(show("1.5"), "1.5");
    assert_eq!(show("<1, 2.5, 3>"), "<1, 2.5, 3>");
    assert_eq!(show("rgb(1, 0.5, 0)"), "rgb(1, 0.5, 0)");
    assert_eq!(show("1 < 2"), "true");
    assert_eq!(show("[1, <1, 2>, 3, 4]"), "[1, <1, 2>, 3, 4]");
    assert_eq!(show("[1, 2, 3, 4, 5]"), "a list of 5");
    assert_eq!(fragment("sphere { }").show(), "an object (`sphere`)");
}

#[test]
fn reserved_names_constants_and_closed_expressions() {
    let _watchdog = crate::watchdog::start();
    for n in [
        "pi", "x", "y", "z", "clock", "frame", "sqrt", "random", "len",
    ] {
        assert!(is_reserved(n), "{n}");
    }
    for n in ["radius", "k", "sqr", "red"] {
        assert!(!is_reserved(n), "{n}");
    }
    let span = |start| Span {
        file: FileId(0),
        start,
        end: start + 1,
    };
    let mut env = Env::new(Transfer::Gamma(2.0));
    env.constants.insert(
        "k".into(),
        Constant {
            value: Some(Value::Number(2.5)),
            span: span(0),
        },
    );
    env.constants.insert(
        "v".into(),
        Constant {
            value: Some(Value::Vector(smallvec::smallvec![1.0, 2.0, 3.0])),
            span: span(1),
        },
    );
    env.constants.insert(
        "failed".into(),
        Constant {
            value: None,
            span: span(2),
        },
    );
    env.constants.insert(
        "width".into(),
        Constant {
            value: Some(Value::Number(1.0)),
            span: span(4),
        },
    );
    env.all_lets.insert("later".into(), span(3));
    assert_eq!(env.number_constant("k"), Some(2.5));
    assert_eq!(env.number_constant("v"), None);
    assert_eq!(env.number_constant("nothing"), None);
    let parsed = |src: &str| {
        let Item::Let { value, .. } = parse(&format!("let w = {src}"), FileId(0))
            .unwrap()
            .remove(0)
        else {
            panic!()
        };
        value
    };
    let mut errors = Vec::new();
    assert_eq!(
        env.eval(&parsed("k * v"), &mut errors),
        Some(Value::Vector(smallvec::smallvec![2.5, 5.0, 7.5]))
    );
    // A constant whose definition failed is quiet.
    assert_eq!(env.eval(&parsed("failed + 1"), &mut errors), None);
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(env.eval(&parsed("later"), &mut errors), None);
    assert_eq!(errors[0].message, "unknown name `later`");
    assert_eq!(
        errors[0].help.as_deref(),
        Some("`later` is defined later; a constant can only be used after its `let`")
    );
    assert_eq!(env.eval(&parsed("widht + 1"), &mut errors), None);
    assert_eq!(errors[1].help.as_deref(), Some("did you mean `width`?"));
    // The builder's names hold no user functions: an unknown function
    // gets the list of the built-ins, no made-up suggestion.
    assert_eq!(env.eval(&parsed("xyzzx(1)"), &mut errors), None);
    assert!(
        errors[2]
            .help
            .as_deref()
            .unwrap()
            .starts_with("the functions are sqrt"),
        "{:?}",
        errors[2].help
    );
    // Closed: every name it uses is bound or built in.
    for (src, want) in [
        ("k + 1", true),
        ("q + 1", false),
        ("1 + q", false),
        ("pi * red", true),
        ("[k, v]", true),
        ("[k, q]", false),
        ("<k, q, 1>", false),
        ("min(k, 1)", true),
        ("min(k, q)", false),
        ("f(k, a: 1)", true),
        ("f(k, a: q)", false),
        ("-k", true),
        ("-q", false),
        ("not q", false),
        ("v[0]", true),
        ("v[q]", false),
        ("q[0]", false),
        ("#ff0000", true),
    ] {
        assert_eq!(is_closed(&env, &parsed(src)), want, "{src}");
    }
}

#[test]
fn random_is_splitmix64_of_its_two_arguments() {
    let _watchdog = crate::watchdog::start();
    // SplitMix64's published first output for the seed 0 is
    // 0xe220a8397b1dcdaf: mix(0). With seed 0 the inner mix gives it, and
    // an i whose bits are that number cancels it, so the outer mix is of
    // 0 again: the number's top 53 bits over 2^53.
    const FIRST: u64 = 0xe220_a839_7b1d_cdaf;
    let want = (FIRST >> 11) as f64 / (1u64 << 53) as f64;
    assert_eq!(random(0.0, f64::from_bits(FIRST)), want);
    assert_eq!(random(-0.0, f64::from_bits(FIRST)), want);
}

/// The integer path (which the walk and the short cut share, through
/// `arithmetic`) changes no bit of any remainder, a zero's sign included.
#[test]
fn whole_remainders_are_rem_euclids_bit_for_bit() {
    let e = (1u64 << 53) as f64;
    let xs = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        7.0,
        -7.0,
        10.0,
        0.5,
        -2.5,
        3.75,
        e - 1.0,
        -(e - 1.0),
        e,
        -e,
        e + 2.0,
        1e300,
        -1e300,
        123456789.0,
        // 2^63, which saturates an i64 to 2^63 − 1 and converts back
        // to itself: only |x| below 2^53 may take the integers.
        2.0 * (1u64 << 62) as f64,
        -2.0 * (1u64 << 62) as f64,
    ];
    for &x in &xs {
        for &y in &xs {
            if y == 0.0 {
                continue;
            }
            let want = x.rem_euclid(y);
            assert_eq!(rem_euclid(x, y).to_bits(), want.to_bits(), "{x} % {y}");
        }
    }
}
