//! Unit tests of `expr.rs`, kept in their own file so the module reads
//! as the code alone.

use super::*;
use crate::lang::ast::FileId;
use crate::lang::ast::Item;
use crate::lang::parser::parse;

fn eval(src: &str) -> Result<Value, Vec<Error>> {
    let Item::Let { value, .. } = parse(&format!("let v = {src}"), FileId(0))
        .unwrap()
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
