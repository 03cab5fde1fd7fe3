//! The numeric built-ins (`sqrt`, `min`, `rgb`, …): their names, argument
//! counts and formulas, written once for the general walk (`expr::call`,
//! which reports a refusal) and the short cut (`fast`, which gives up on
//! one). The built-ins of vectors and lists read their arguments' kinds
//! and stay in `expr::call`.

use super::expr::{Value, random};
use crate::scene::Colour;

/// A numeric built-in: numbers in, a number or a colour out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Builtin {
    Sqrt,
    Sin,
    Cos,
    Tan,
    Rad,
    Deg,
    Abs,
    Min,
    Max,
    Rgb,
    Exp,
    Log,
    Floor,
    Ceil,
    Round,
    Atan2,
    Clamp,
    Random,
}

/// Why a built-in gives no value for its numbers: argument `arg` is out
/// of its domain, `what` says how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Refusal {
    pub arg: usize,
    pub what: &'static str,
}

impl Builtin {
    /// The built-in `name` names, by its bytes: a `match` on `&str`
    /// compares each arm with `memcmp`, and `rgb` is the tenth.
    pub(super) fn named(name: &str) -> Option<Builtin> {
        use Builtin::*;
        Some(match name.as_bytes() {
            b"rgb" => Rgb,
            b"sqrt" => Sqrt,
            b"sin" => Sin,
            b"cos" => Cos,
            b"tan" => Tan,
            b"rad" => Rad,
            b"deg" => Deg,
            b"abs" => Abs,
            b"min" => Min,
            b"max" => Max,
            b"exp" => Exp,
            b"log" => Log,
            b"floor" => Floor,
            b"ceil" => Ceil,
            b"round" => Round,
            b"atan2" => Atan2,
            b"clamp" => Clamp,
            b"random" => Random,
            _ => return None,
        })
    }

    /// How many arguments it takes (as `expr::FUNCTIONS` says: a test
    /// checks the two agree).
    pub(super) fn arity(self) -> usize {
        use Builtin::*;
        match self {
            Rgb | Clamp => 3,
            Min | Max | Atan2 | Random => 2,
            _ => 1,
        }
    }

    /// The value for numbers `x` (unused places 0), finite or not (the
    /// caller tells), or the argument out of the built-in's domain: a
    /// negative colour component (the first), the square root of a
    /// negative number, the logarithm of one that is not positive.
    #[inline]
    pub(super) fn apply(self, x: [f64; 3]) -> Result<Value, Refusal> {
        use Builtin::*;
        let refuse = |arg: usize, what: &'static str| Err(Refusal { arg, what });
        Ok(Value::Number(match self {
            Rgb => {
                return match x.iter().position(|c| *c < 0.0) {
                    Some(k) => refuse(k, "a colour component cannot be negative"),
                    None => Ok(Value::Colour(Colour::new(x[0], x[1], x[2]))),
                };
            }
            Sqrt if x[0] >= 0.0 => x[0].sqrt(),
            Sqrt => return refuse(0, "square root of a negative number"),
            Log if x[0] > 0.0 => x[0].ln(),
            Log => return refuse(0, "logarithm of a number that is not positive"),
            Sin => x[0].sin(),
            Cos => x[0].cos(),
            Tan => x[0].tan(),
            Rad => x[0].to_radians(),
            Deg => x[0].to_degrees(),
            Abs => x[0].abs(),
            Min => x[0].min(x[1]),
            Max => x[0].max(x[1]),
            Exp => x[0].exp(),
            Floor => x[0].floor(),
            Ceil => x[0].ceil(),
            Round => x[0].round(),
            Atan2 => x[0].atan2(x[1]),
            Clamp => x[0].max(x[1]).min(x[2]),
            Random => random(x[0], x[1]),
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_ins_it_knows_are_those_of_numbers_with_their_counts() {
        for &(name, arity) in crate::eval::expr::FUNCTIONS {
            match Builtin::named(name) {
                Some(f) => assert_eq!(f.arity(), arity, "{name}"),
                None => assert!(
                    matches!(
                        name,
                        "normalize" | "length" | "dot" | "cross" | "len" | "lerp"
                    ),
                    "{name}"
                ),
            }
        }
        for name in ["rg", "rgbb", "Rgb", "sqr", "f", ""] {
            assert_eq!(Builtin::named(name), None, "{name}");
        }
    }
}
