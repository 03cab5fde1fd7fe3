//! Values and expressions: constants, arithmetic on numbers, vectors and
//! colours, the built-in functions, and named colours. Every mistake is an
//! [`Error`] at the characters that caused it.

use crate::lang::ast::{BinOp, Expr, ExprKind, Span};
use crate::lang::diagnostics::{Error, did_you_mean};
use crate::scene::{Colour, Transfer};
use std::collections::HashMap;

/// What an expression evaluates to.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Number(f64),
    /// `<a, b, …>`: any number of components (a 3-vector is the usual).
    Vector(Vec<f64>),
    /// Linear RGB.
    Colour(Colour),
}

impl Value {
    pub fn kind(&self) -> String {
        match self {
            Value::Number(_) => "a number".into(),
            Value::Vector(v) => format!("a {}-vector", v.len()),
            Value::Colour(_) => "a colour".into(),
        }
    }
}

/// Built-in functions and their argument counts.
pub const FUNCTIONS: &[(&str, usize)] = &[
    ("sqrt", 1),
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("rad", 1),
    ("deg", 1),
    ("abs", 1),
    ("min", 2),
    ("max", 2),
    ("rgb", 3),
];

/// Names a `let` may not take: built-in constants and functions, and the
/// variables of equations (a constant `x` would make `implicit "x^2 …"`
/// ambiguous).
pub fn is_reserved(name: &str) -> bool {
    name == "pi" || matches!(name, "x" | "y" | "z") || FUNCTIONS.iter().any(|(f, _)| *f == name)
}

/// A defined constant: its value (`None` when its definition was wrong and
/// has been reported, so uses of it stay quiet) and where it was defined.
#[derive(Clone, Debug)]
pub struct Constant {
    pub value: Option<Value>,
    pub span: Span,
}

/// The constants defined so far, and the curve that decodes `#rrggbb` and
/// named colours.
#[derive(Debug)]
pub struct Env {
    pub constants: HashMap<String, Constant>,
    pub transfer: Transfer,
    /// Every constant of the program with where it is defined, for "is
    /// defined later" hints.
    pub all_lets: HashMap<String, Span>,
    /// Every named material of the program: after `material`, such a name
    /// is the material even when it is also a keyword (`material mirror`).
    pub material_names: std::collections::HashSet<String>,
}

impl Env {
    pub fn new(transfer: Transfer) -> Env {
        Env {
            constants: HashMap::new(),
            transfer,
            all_lets: HashMap::new(),
            material_names: Default::default(),
        }
    }

    pub fn number_constant(&self, name: &str) -> Option<f64> {
        match self.constants.get(name)?.value {
            Some(Value::Number(v)) => Some(v),
            _ => None,
        }
    }

    /// Evaluates `e`, reporting mistakes into `errors`; `None` when it failed
    /// (already reported).
    pub fn eval(&self, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
        let v = match &e.kind {
            ExprKind::Number(v) => {
                if !v.is_finite() {
                    errors.push(
                        Error::new(e.span, "this number is too large")
                            .label("larger than a 64-bit float can hold"),
                    );
                    return None;
                }
                Value::Number(*v)
            }
            ExprKind::Hex([r, g, b]) => Value::Colour(self.transfer.decode_rgb8(*r, *g, *b)),
            ExprKind::Name(n) => return self.name(n, e.span, errors),
            ExprKind::Vector(parts) => {
                let mut out = Vec::with_capacity(parts.len());
                let mut ok = true;
                for p in parts {
                    match self.eval(p, errors) {
                        Some(Value::Number(v)) => out.push(v),
                        Some(other) => {
                            errors.push(
                                Error::new(p.span, "a vector's components must be numbers")
                                    .label(format!("this is {}", other.kind())),
                            );
                            ok = false;
                        }
                        None => ok = false,
                    }
                }
                if !ok {
                    return None;
                }
                Value::Vector(out)
            }
            ExprKind::Neg(inner) => match self.eval(inner, errors)? {
                Value::Number(v) => Value::Number(-v),
                Value::Vector(v) => Value::Vector(v.iter().map(|x| -x).collect()),
                Value::Colour(_) => {
                    errors.push(
                        Error::new(e.span, "a colour cannot be negated").label("negative colour"),
                    );
                    return None;
                }
            },
            ExprKind::Binary { op, lhs, rhs } => {
                let a = self.eval(lhs, errors);
                let b = self.eval(rhs, errors);
                return binary(*op, a?, b?, e, errors);
            }
            ExprKind::Call { name, args } => {
                let mut vals = Vec::with_capacity(args.len());
                for a in args {
                    vals.push(self.eval(a, errors));
                }
                let Some(&(_, arity)) = FUNCTIONS.iter().find(|(f, _)| *f == name.node) else {
                    let help = did_you_mean(&name.node, FUNCTIONS.iter().map(|(f, _)| *f));
                    errors.push(
                        Error::new(name.span, format!("unknown function `{}`", name.node))
                            .label("not a function")
                            .help(help.unwrap_or_else(|| {
                                "the functions are sqrt, sin, cos, tan, rad, deg, abs, min, max and rgb".into()
                            })),
                    );
                    return None;
                };
                if vals.len() != arity {
                    errors.push(
                        Error::new(
                            e.span,
                            format!(
                                "`{}` takes {arity} argument{}, not {}",
                                name.node,
                                if arity == 1 { "" } else { "s" },
                                vals.len()
                            ),
                        )
                        .label(format!("{} given", vals.len())),
                    );
                    return None;
                }
                let mut nums = Vec::with_capacity(arity);
                for (v, a) in vals.into_iter().zip(args) {
                    match v? {
                        Value::Number(x) => nums.push(x),
                        other => {
                            errors.push(
                                Error::new(a.span, format!("`{}` needs numbers", name.node))
                                    .label(format!("this is {}", other.kind())),
                            );
                            return None;
                        }
                    }
                }
                return call(&name.node, &nums, e, args, errors);
            }
        };
        Some(v)
    }

    fn name(&self, n: &str, span: Span, errors: &mut Vec<Error>) -> Option<Value> {
        if let Some(c) = self.constants.get(n) {
            return c.value.clone();
        }
        if n == "pi" {
            return Some(Value::Number(std::f64::consts::PI));
        }
        if let Some(rgb) = named_colour(n) {
            return Some(Value::Colour(
                self.transfer.decode_rgb8(rgb[0], rgb[1], rgb[2]),
            ));
        }
        let mut err = Error::new(span, format!("unknown name `{n}`")).label("not defined");
        if let Some(def) = self.all_lets.get(n) {
            err = err
                .help(format!(
                    "`{n}` is defined later; a constant can only be used after its `let`"
                ))
                .note(*def, "defined here");
        } else {
            let names = self
                .constants
                .keys()
                .map(String::as_str)
                .chain(std::iter::once("pi"))
                .chain(COLOURS.iter().map(|(c, _)| *c));
            err = err.maybe_help(did_you_mean(n, names));
        }
        errors.push(err);
        None
    }
}

fn finite(v: Value, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
    let ok = match &v {
        Value::Number(x) => x.is_finite(),
        Value::Vector(xs) => xs.iter().all(|x| x.is_finite()),
        Value::Colour(c) => c.is_finite(),
    };
    if ok {
        Some(v)
    } else {
        errors.push(
            Error::new(e.span, "this does not give a finite value")
                .label("infinite or not a number")
                .help("check for a division by zero or a huge power"),
        );
        None
    }
}

fn binary(op: BinOp, a: Value, b: Value, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
    use Value::*;
    let num = |x: f64, y: f64| match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
        BinOp::Pow => x.powf(y),
    };
    let v = match (&a, &b, op) {
        (Number(x), Number(y), BinOp::Div) if *y == 0.0 => {
            let _ = x;
            errors.push(Error::new(e.span, "division by zero").label("divides by zero"));
            return None;
        }
        (Number(x), Number(y), _) => Number(num(*x, *y)),
        (Vector(x), Vector(y), BinOp::Add | BinOp::Sub) if x.len() == y.len() => {
            Vector(x.iter().zip(y).map(|(p, q)| num(*p, *q)).collect())
        }
        (Vector(x), Number(s), BinOp::Mul | BinOp::Div) => {
            Vector(x.iter().map(|p| num(*p, *s)).collect())
        }
        (Number(s), Vector(x), BinOp::Mul) => Vector(x.iter().map(|p| p * s).collect()),
        (Colour(x), Colour(y), BinOp::Add | BinOp::Sub | BinOp::Mul) => Colour(match op {
            BinOp::Add => *x + *y,
            BinOp::Sub => *x - *y,
            _ => *x * *y,
        }),
        (Colour(x), Number(s), BinOp::Mul) | (Number(s), Colour(x), BinOp::Mul) => Colour(*x * *s),
        (Colour(x), Number(s), BinOp::Div) => Colour(*x / *s),
        _ => {
            let what = match op {
                BinOp::Add => "add",
                BinOp::Sub => "subtract",
                BinOp::Mul => "multiply",
                BinOp::Div => "divide",
                BinOp::Pow => "raise",
            };
            let (pa, pb) = match op {
                BinOp::Add => (a.kind(), format!("to {}", b.kind())),
                BinOp::Sub => (b.kind(), format!("from {}", a.kind())),
                BinOp::Pow => (a.kind(), format!("to the power {}", b.kind())),
                _ => (a.kind(), format!("by {}", b.kind())),
            };
            errors.push(
                Error::new(e.span, format!("cannot {what} {pa} {pb}")).label(format!(
                    "{} {op} {}",
                    a.kind(),
                    b.kind()
                )),
            );
            return None;
        }
    };
    finite(v, e, errors)
}

fn call(name: &str, x: &[f64], e: &Expr, args: &[Expr], errors: &mut Vec<Error>) -> Option<Value> {
    let v = match name {
        "sqrt" => {
            if x[0] < 0.0 {
                errors.push(
                    Error::new(args[0].span, "square root of a negative number")
                        .label(format!("this is {}", x[0])),
                );
                return None;
            }
            Value::Number(x[0].sqrt())
        }
        "sin" => Value::Number(x[0].sin()),
        "cos" => Value::Number(x[0].cos()),
        "tan" => Value::Number(x[0].tan()),
        "rad" => Value::Number(x[0].to_radians()),
        "deg" => Value::Number(x[0].to_degrees()),
        "abs" => Value::Number(x[0].abs()),
        "min" => Value::Number(x[0].min(x[1])),
        "max" => Value::Number(x[0].max(x[1])),
        "rgb" => {
            for (v, a) in x.iter().zip(args) {
                if *v < 0.0 {
                    errors.push(
                        Error::new(a.span, "a colour component cannot be negative")
                            .label(format!("this is {v}")),
                    );
                    return None;
                }
            }
            Value::Colour(Colour::new(x[0], x[1], x[2]))
        }
        _ => unreachable!("checked against FUNCTIONS"),
    };
    finite(v, e, errors)
}

/// A CSS named colour as display-encoded bytes.
pub fn named_colour(name: &str) -> Option<[u8; 3]> {
    COLOURS
        .binary_search_by(|(n, _)| (*n).cmp(name))
        .ok()
        .map(|i| {
            let c = COLOURS[i].1;
            [(c >> 16) as u8, (c >> 8) as u8, c as u8]
        })
}

/// The CSS colour names (sorted, for binary search).
pub const COLOURS: &[(&str, u32)] = &[
    ("aliceblue", 0xf0f8ff),
    ("antiquewhite", 0xfaebd7),
    ("aqua", 0x00ffff),
    ("aquamarine", 0x7fffd4),
    ("azure", 0xf0ffff),
    ("beige", 0xf5f5dc),
    ("bisque", 0xffe4c4),
    ("black", 0x000000),
    ("blanchedalmond", 0xffebcd),
    ("blue", 0x0000ff),
    ("blueviolet", 0x8a2be2),
    ("brown", 0xa52a2a),
    ("burlywood", 0xdeb887),
    ("cadetblue", 0x5f9ea0),
    ("chartreuse", 0x7fff00),
    ("chocolate", 0xd2691e),
    ("coral", 0xff7f50),
    ("cornflowerblue", 0x6495ed),
    ("cornsilk", 0xfff8dc),
    ("crimson", 0xdc143c),
    ("cyan", 0x00ffff),
    ("darkblue", 0x00008b),
    ("darkcyan", 0x008b8b),
    ("darkgoldenrod", 0xb8860b),
    ("darkgray", 0xa9a9a9),
    ("darkgreen", 0x006400),
    ("darkgrey", 0xa9a9a9),
    ("darkkhaki", 0xbdb76b),
    ("darkmagenta", 0x8b008b),
    ("darkolivegreen", 0x556b2f),
    ("darkorange", 0xff8c00),
    ("darkorchid", 0x9932cc),
    ("darkred", 0x8b0000),
    ("darksalmon", 0xe9967a),
    ("darkseagreen", 0x8fbc8f),
    ("darkslateblue", 0x483d8b),
    ("darkslategray", 0x2f4f4f),
    ("darkslategrey", 0x2f4f4f),
    ("darkturquoise", 0x00ced1),
    ("darkviolet", 0x9400d3),
    ("deeppink", 0xff1493),
    ("deepskyblue", 0x00bfff),
    ("dimgray", 0x696969),
    ("dimgrey", 0x696969),
    ("dodgerblue", 0x1e90ff),
    ("firebrick", 0xb22222),
    ("floralwhite", 0xfffaf0),
    ("forestgreen", 0x228b22),
    ("fuchsia", 0xff00ff),
    ("gainsboro", 0xdcdcdc),
    ("ghostwhite", 0xf8f8ff),
    ("gold", 0xffd700),
    ("goldenrod", 0xdaa520),
    ("gray", 0x808080),
    ("green", 0x008000),
    ("greenyellow", 0xadff2f),
    ("grey", 0x808080),
    ("honeydew", 0xf0fff0),
    ("hotpink", 0xff69b4),
    ("indianred", 0xcd5c5c),
    ("indigo", 0x4b0082),
    ("ivory", 0xfffff0),
    ("khaki", 0xf0e68c),
    ("lavender", 0xe6e6fa),
    ("lavenderblush", 0xfff0f5),
    ("lawngreen", 0x7cfc00),
    ("lemonchiffon", 0xfffacd),
    ("lightblue", 0xadd8e6),
    ("lightcoral", 0xf08080),
    ("lightcyan", 0xe0ffff),
    ("lightgoldenrodyellow", 0xfafad2),
    ("lightgray", 0xd3d3d3),
    ("lightgreen", 0x90ee90),
    ("lightgrey", 0xd3d3d3),
    ("lightpink", 0xffb6c1),
    ("lightsalmon", 0xffa07a),
    ("lightseagreen", 0x20b2aa),
    ("lightskyblue", 0x87cefa),
    ("lightslategray", 0x778899),
    ("lightslategrey", 0x778899),
    ("lightsteelblue", 0xb0c4de),
    ("lightyellow", 0xffffe0),
    ("lime", 0x00ff00),
    ("limegreen", 0x32cd32),
    ("linen", 0xfaf0e6),
    ("magenta", 0xff00ff),
    ("maroon", 0x800000),
    ("mediumaquamarine", 0x66cdaa),
    ("mediumblue", 0x0000cd),
    ("mediumorchid", 0xba55d3),
    ("mediumpurple", 0x9370db),
    ("mediumseagreen", 0x3cb371),
    ("mediumslateblue", 0x7b68ee),
    ("mediumspringgreen", 0x00fa9a),
    ("mediumturquoise", 0x48d1cc),
    ("mediumvioletred", 0xc71585),
    ("midnightblue", 0x191970),
    ("mintcream", 0xf5fffa),
    ("mistyrose", 0xffe4e1),
    ("moccasin", 0xffe4b5),
    ("navajowhite", 0xffdead),
    ("navy", 0x000080),
    ("oldlace", 0xfdf5e6),
    ("olive", 0x808000),
    ("olivedrab", 0x6b8e23),
    ("orange", 0xffa500),
    ("orangered", 0xff4500),
    ("orchid", 0xda70d6),
    ("palegoldenrod", 0xeee8aa),
    ("palegreen", 0x98fb98),
    ("paleturquoise", 0xafeeee),
    ("palevioletred", 0xdb7093),
    ("papayawhip", 0xffefd5),
    ("peachpuff", 0xffdab9),
    ("peru", 0xcd853f),
    ("pink", 0xffc0cb),
    ("plum", 0xdda0dd),
    ("powderblue", 0xb0e0e6),
    ("purple", 0x800080),
    ("rebeccapurple", 0x663399),
    ("red", 0xff0000),
    ("rosybrown", 0xbc8f8f),
    ("royalblue", 0x4169e1),
    ("saddlebrown", 0x8b4513),
    ("salmon", 0xfa8072),
    ("sandybrown", 0xf4a460),
    ("seagreen", 0x2e8b57),
    ("seashell", 0xfff5ee),
    ("sienna", 0xa0522d),
    ("silver", 0xc0c0c0),
    ("skyblue", 0x87ceeb),
    ("slateblue", 0x6a5acd),
    ("slategray", 0x708090),
    ("slategrey", 0x708090),
    ("snow", 0xfffafa),
    ("springgreen", 0x00ff7f),
    ("steelblue", 0x4682b4),
    ("tan", 0xd2b48c),
    ("teal", 0x008080),
    ("thistle", 0xd8bfd8),
    ("tomato", 0xff6347),
    ("turquoise", 0x40e0d0),
    ("violet", 0xee82ee),
    ("wheat", 0xf5deb3),
    ("white", 0xffffff),
    ("whitesmoke", 0xf5f5f5),
    ("yellow", 0xffff00),
    ("yellowgreen", 0x9acd32),
];

#[cfg(test)]
mod tests {
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
            Ok(Value::Vector(vec![1.0, 3.0, 5.0]))
        );
        assert_eq!(eval("max(1, sqrt(9))"), Ok(Value::Number(3.0)));
        assert_eq!(eval("deg(rad(90))"), Ok(Value::Number(90.0)));
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
}
