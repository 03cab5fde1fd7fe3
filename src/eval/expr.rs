//! Values and expressions: arithmetic on numbers, vectors and colours,
//! comparisons and conditions, lists, the built-in functions, and named
//! colours. Every mistake is an [`Error`] at the characters that caused it.
//!
//! Names are looked up through [`Names`]: the evaluator (`eval::Expander`)
//! gives its scopes and user functions, the builder its leftovers.
//! One file, the language's values and what works on them, but for the
//! numeric built-ins' formulas (`builtins.rs`, shared with `fast.rs`).

use super::builtins::{Builtin, Refusal};
use super::colours::{COLOURS, named_colour};
use crate::lang::ast::{BinOp, Expr, ExprKind, Item, Span, Spanned};
use crate::lang::diagnostics::{Error, did_you_mean};
use crate::scene::{Colour, Transfer};
use std::collections::HashMap;
use std::sync::Arc;

/// What an expression evaluates to.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Number(f64),
    /// `<a, b, …>`: any number of components (a 3-vector is the usual,
    /// and is held inline: a loop's `centre <…>` allocates nothing).
    Vector(Components),
    /// Linear RGB.
    Colour(Colour),
    /// What a comparison gives.
    Bool(bool),
    /// `[a, b, …]`
    List(Arc<Vec<Value>>),
    /// An object, material or pattern written as items
    /// (`let spoke = cylinder { … }`), already evaluated.
    Items(Arc<Fragment>),
}

/// A vector's components: up to three inline.
pub type Components = smallvec::SmallVec<[f64; 3]>;

/// Items bound to a name: `cylinder { … }`, `material { … }`,
/// `checker { … }`, with the names inside already worked out.
#[derive(Debug, PartialEq)]
pub struct Fragment {
    pub items: Vec<Item>,
    /// Where the `let` wrote it.
    pub span: Span,
}

impl Fragment {
    /// The statement word it starts with (`cylinder`, `material`, …).
    pub fn head(&self) -> &str {
        self.items
            .first()
            .and_then(Item::as_name)
            .map_or("", |n| n.node)
    }

    pub fn is_material(&self) -> bool {
        self.head() == "material"
    }
}

impl Value {
    /// No infinity or NaN in it (the evaluator gives no other value).
    pub fn is_finite(&self) -> bool {
        match self {
            Value::Number(x) => x.is_finite(),
            Value::Vector(xs) => xs.iter().all(|x| x.is_finite()),
            Value::Colour(c) => c.is_finite(),
            Value::Bool(_) | Value::List(_) | Value::Items(_) => true,
        }
    }

    pub fn kind(&self) -> String {
        match self {
            Value::Number(_) => "a number".into(),
            Value::Vector(v) => format!("a {}-vector", v.len()),
            Value::Colour(_) => "a colour".into(),
            Value::Bool(_) => "a condition (true or false)".into(),
            Value::List(l) => format!("a list of {}", l.len()),
            Value::Items(f) if f.is_material() => "a material".into(),
            Value::Items(f) if crate::scene::is_object(f.head()) => {
                format!("an object (`{}`)", f.head())
            }
            Value::Items(f) => format!("a pattern (`{}`)", f.head()),
        }
    }

    /// Short text for messages ("with h = 1.7").
    pub fn show(&self) -> String {
        match self {
            Value::Number(v) => format!("{v}"),
            Value::Vector(v) => format!(
                "<{}>",
                v.iter()
                    .map(|x| x.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
            Value::Colour(c) => format!("rgb({}, {}, {})", c.x, c.y, c.z),
            Value::Bool(b) => format!("{b}"),
            Value::List(l) if l.len() <= 4 => {
                format!(
                    "[{}]",
                    l.iter().map(Value::show).collect::<Vec<_>>().join(", ")
                )
            }
            other => other.kind(),
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
    ("exp", 1),
    ("log", 1),
    ("floor", 1),
    ("ceil", 1),
    ("round", 1),
    ("atan2", 2),
    ("clamp", 3),
    ("lerp", 3),
    ("normalize", 1),
    ("dot", 2),
    ("cross", 2),
    ("length", 1),
    ("len", 1),
    ("random", 2),
];

/// Names a `let` may not take: built-in constants and functions, the
/// animation numbers, and the variables of equations (a constant `x` would
/// make `implicit "x^2 …"` ambiguous).
pub fn is_reserved(name: &str) -> bool {
    matches!(name, "pi" | "x" | "y" | "z" | "clock" | "frame")
        || FUNCTIONS.iter().any(|(f, _)| *f == name)
}

/// A defined constant: its value (`None` when its definition was wrong and
/// has been reported, so uses of it stay quiet) and where it was defined.
#[derive(Clone, Debug)]
pub struct Constant {
    pub value: Option<Value>,
    pub span: Span,
}

/// How an evaluation finds names and user functions.
pub trait Names {
    /// The curve that decodes `#rrggbb` and named colours.
    fn transfer(&self) -> Transfer;
    /// A bound name's value: `Some(None)` when it is bound to a value
    /// whose definition failed (already reported), `None` when unbound.
    fn lookup(&self, name: &str) -> Option<Option<Value>>;
    /// Whether `name` is bound to a value ([`Names::lookup`] without
    /// copying the value out).
    fn binds(&self, name: &str) -> bool {
        self.lookup(name).is_some()
    }
    /// Calls a user function, `None` when there is none of that name
    /// (then the built-ins are tried).
    fn call(&self, call: &Expr, errors: &mut Vec<Error>) -> Option<Option<Value>>;
    /// Reports an unknown name (with suggestions from what is in scope).
    fn unknown(&self, name: &str, span: Span, errors: &mut Vec<Error>);
    /// The user functions in scope (for suggestions).
    fn functions(&self) -> Vec<String> {
        Vec::new()
    }
    /// Counts one step of work; false when the budget is spent (reported).
    fn step(&self, _span: Span, _errors: &mut Vec<Error>) -> bool {
        true
    }
    /// True when this evaluation is a trial that must not pass a point
    /// where it could skip part of the expression (`and`, `or`): the trial
    /// is then marked given up and its result is not used.
    fn give_up(&self) -> bool {
        false
    }
}

/// The constants defined so far, and the curve that decodes `#rrggbb` and
/// named colours: what the builder evaluates its leftover names with.
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
    /// Names bound anywhere in the program (for suggestions).
    pub known: Vec<String>,
}

impl Names for Env {
    fn transfer(&self) -> Transfer {
        self.transfer
    }

    fn lookup(&self, name: &str) -> Option<Option<Value>> {
        self.constants.get(name).map(|c| c.value.clone())
    }

    fn call(&self, _call: &Expr, _errors: &mut Vec<Error>) -> Option<Option<Value>> {
        None
    }

    fn unknown(&self, n: &str, span: Span, errors: &mut Vec<Error>) {
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
                .chain(self.known.iter())
                .map(String::as_str)
                .chain(["pi", "clock", "frame"])
                .chain(COLOURS.iter().map(|(c, _)| *c));
            err = err.maybe_help(did_you_mean(n, names));
        }
        errors.push(err);
    }
}

impl Env {
    pub fn new(transfer: Transfer) -> Env {
        Env {
            constants: HashMap::new(),
            transfer,
            all_lets: HashMap::new(),
            material_names: Default::default(),
            known: Vec::new(),
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
        eval(self, e, errors)
    }
}

/// Evaluates `e` with the names of `names`, reporting mistakes into
/// `errors`; `None` when it failed (already reported).
///
/// Generic over the names, so that the evaluator's step count and lookups
/// are inlined into the walk (it is most of a loop's evaluation).
pub fn eval<N: Names + ?Sized>(names: &N, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
    if !names.step(e.span, errors) {
        return None;
    }
    // The commonest nodes of a loop's expressions here, the rest in
    // `eval_rest`: a small function the compiler keeps lean (its entry and
    // exit were a third of the walk's own time when every arm was here).
    match &e.kind {
        ExprKind::Number(v) if v.is_finite() => Some(Value::Number(*v)),
        ExprKind::Name(n) => name(names, n, e.span, errors),
        ExprKind::Binary { op, lhs, rhs } if !matches!(op, BinOp::And | BinOp::Or) => {
            // Arithmetic on two numbers is most of a scene's expressions:
            // straight to the number (as `binary` would give it).
            let a = take_number(eval(names, lhs, errors));
            let b = take_number(eval(names, rhs, errors));
            match (a, b) {
                (Ok(x), Ok(y)) => match arithmetic(*op, x, y) {
                    Some(v) if v.is_finite() => Some(Value::Number(v)),
                    Some(v) => finite(Value::Number(v), e, errors),
                    None => binary(*op, Value::Number(x), Value::Number(y), e, errors),
                },
                (a, b) => {
                    let a = a.map_or_else(|v| v, |x| Some(Value::Number(x)));
                    let b = b.map_or_else(|v| v, |x| Some(Value::Number(x)));
                    binary(*op, a?, b?, e, errors)
                }
            }
        }
        _ => eval_rest(names, e, errors),
    }
}

/// The number `v` holds, or `v` itself when it is not a number. By value,
/// and a number is let go without its drop (it owns nothing): the walk
/// otherwise called the drop of every operand, numbers included.
#[inline(always)]
fn take_number(v: Option<Value>) -> Result<f64, Option<Value>> {
    if let Some(Value::Number(x)) = v {
        std::mem::forget(v);
        return Ok(x);
    }
    Err(v)
}

/// [`eval`] of the nodes it does not handle itself (its step counted).
#[inline(never)]
fn eval_rest<N: Names + ?Sized>(names: &N, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
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
        ExprKind::Value(v) => return Some(v.clone()),
        ExprKind::Hex([r, g, b]) => Value::Colour(names.transfer().decode_rgb8(*r, *g, *b)),
        ExprKind::Name(n) => return name(names, n, e.span, errors),
        ExprKind::Vector(parts) => {
            let mut out = Components::with_capacity(parts.len());
            let mut ok = true;
            for p in parts {
                match eval(names, p, errors) {
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
        ExprKind::List(parts) => {
            let mut out = Vec::with_capacity(parts.len());
            let mut ok = true;
            for p in parts {
                match eval(names, p, errors) {
                    Some(v) => out.push(v),
                    None => ok = false,
                }
            }
            if !ok {
                return None;
            }
            Value::List(Arc::new(out))
        }
        ExprKind::Index { base, index } => {
            let b = eval(names, base, errors);
            let i = eval(names, index, errors);
            return self::index(b?, i?, base, index, errors);
        }
        ExprKind::Neg(inner) => match eval(names, inner, errors)? {
            Value::Number(v) => Value::Number(-v),
            Value::Vector(v) => Value::Vector(v.iter().map(|x| -x).collect()),
            other => {
                errors.push(
                    Error::new(e.span, format!("cannot negate {}", other.kind()))
                        .label(format!("this is {}", other.kind())),
                );
                return None;
            }
        },
        ExprKind::Not(inner) => match eval(names, inner, errors)? {
            Value::Bool(b) => Value::Bool(!b),
            other => {
                errors.push(
                    Error::new(
                        inner.span,
                        format!("`not` needs a condition, found {}", other.kind()),
                    )
                    .label(format!("this is {}", other.kind()))
                    .help("compare it: `not (a == 0)`"),
                );
                return None;
            }
        },
        ExprKind::Binary {
            op: op @ (BinOp::And | BinOp::Or),
            lhs,
            rhs,
        } => {
            if names.give_up() {
                return None;
            }
            // Short-circuit: `i > 0 and xs[i - 1] == 2` is safe.
            let a = condition(names, lhs, errors)?;
            if (*op == BinOp::And && !a) || (*op == BinOp::Or && a) {
                return Some(Value::Bool(a));
            }
            return condition(names, rhs, errors).map(Value::Bool);
        }
        ExprKind::Binary { op, lhs, rhs } => {
            // (`eval` takes these; both sides are evaluated, and reported,
            // before either is found missing.)
            let (a, b) = (eval(names, lhs, errors), eval(names, rhs, errors));
            return binary(*op, a?, b?, e, errors);
        }
        ExprKind::Call { name, args, named } => {
            if let Some(v) = names.call(e, errors) {
                return v;
            }
            // Every argument is evaluated (and its mistakes reported)
            // before any is found missing.
            // On the stack: a built-in takes at most three (`rgb`, `clamp`).
            let mut got: smallvec::SmallVec<[Value; 3]> = smallvec::SmallVec::new();
            let mut all = true;
            for a in args {
                match eval(names, a, errors) {
                    Some(v) => got.push(v),
                    None => all = false,
                }
            }
            let Some(&(_, arity)) = FUNCTIONS.iter().find(|(f, _)| *f == name.node) else {
                let user = names.functions();
                let help = did_you_mean(
                    &name.node,
                    FUNCTIONS
                        .iter()
                        .map(|(f, _)| *f)
                        .chain(user.iter().map(String::as_str)),
                );
                errors.push(
                    Error::new(name.span, format!("unknown function `{}`", name.node))
                        .label("not a function")
                        .help(help.unwrap_or_else(|| {
                            "the functions are sqrt, sin, cos, tan, rad, deg, abs, min, max, rgb, exp, log, floor, ceil, round, atan2, clamp, lerp, normalize, dot, cross, length, len and random, and those declared with `fn`".into()
                        })),
                );
                return None;
            };
            if let Some((n, _)) = named.first() {
                errors.push(
                    Error::new(n.span, format!("`{}` takes no named arguments", name.node))
                        .label("named argument")
                        .help("built-in functions take their arguments in order"),
                );
                return None;
            }
            if args.len() != arity {
                errors.push(
                    Error::new(
                        e.span,
                        format!(
                            "`{}` takes {arity} argument{}, not {}",
                            name.node,
                            if arity == 1 { "" } else { "s" },
                            args.len()
                        ),
                    )
                    .label(format!("{} given", args.len())),
                );
                return None;
            }
            if !all {
                return None;
            }
            return call(&name.node, &got, e, args, errors);
        }
        ExprKind::Bound(_, v) => return v.clone(),
    };
    Some(v)
}

/// Evaluates a condition: it must give true or false.
pub fn condition<N: Names + ?Sized>(names: &N, e: &Expr, errors: &mut Vec<Error>) -> Option<bool> {
    match eval(names, e, errors)? {
        Value::Bool(b) => Some(b),
        other => {
            errors.push(
                Error::new(
                    e.span,
                    format!("expected a condition, found {}", other.kind()),
                )
                .label(format!("this is {}", other.kind()))
                .help("a condition compares values: `i % 2 == 0`, `x < 3 and y > 1`"),
            );
            None
        }
    }
}

fn name<N: Names + ?Sized>(
    names: &N,
    n: &str,
    span: Span,
    errors: &mut Vec<Error>,
) -> Option<Value> {
    if let Some(v) = names.lookup(n) {
        return v;
    }
    if n == "pi" {
        return Some(Value::Number(std::f64::consts::PI));
    }
    if let Some(rgb) = named_colour(n) {
        return Some(Value::Colour(
            names.transfer().decode_rgb8(rgb[0], rgb[1], rgb[2]),
        ));
    }
    names.unknown(n, span, errors);
    None
}

fn index(base: Value, i: Value, be: &Expr, ie: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
    let len = match &base {
        Value::List(l) => l.len(),
        Value::Vector(v) => v.len(),
        other => {
            errors.push(
                Error::new(be.span, format!("cannot index {}", other.kind()))
                    .label(format!("this is {}", other.kind()))
                    .help("only lists `[…]` and vectors `<…>` have elements"),
            );
            return None;
        }
    };
    let k = match i {
        Value::Number(k) if k.fract() == 0.0 && k >= 0.0 && (k as usize) < len => k as usize,
        Value::Number(k) => {
            errors.push(
                Error::new(ie.span, format!("index {k} is out of range"))
                    .label(format!(
                        "the {} has {len} element{}",
                        if matches!(base, Value::List(_)) {
                            "list"
                        } else {
                            "vector"
                        },
                        if len == 1 { "" } else { "s" }
                    ))
                    .help(if len == 0 {
                        "it is empty".to_string()
                    } else {
                        format!("indices are whole numbers from 0 to {}", len - 1)
                    }),
            );
            return None;
        }
        other => {
            errors.push(
                Error::new(
                    ie.span,
                    format!("an index must be a number, found {}", other.kind()),
                )
                .label(format!("this is {}", other.kind())),
            );
            return None;
        }
    };
    Some(match base {
        Value::List(l) => l[k].clone(),
        Value::Vector(v) => Value::Number(v[k]),
        _ => unreachable!("checked above"),
    })
}

#[inline]
fn finite(v: Value, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
    if v.is_finite() {
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

/// `x op y` for the operators that give a number and cannot fail here
/// (`/` and `%` only by a divisor that is not 0); `None` for the rest,
/// which [`binary`] handles and reports.
#[inline(always)]
pub(super) fn arithmetic(op: BinOp, x: f64, y: f64) -> Option<f64> {
    Some(match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div if y != 0.0 => x / y,
        BinOp::Pow => x.powf(y),
        BinOp::Rem if y != 0.0 => rem_euclid(x, y),
        _ => return None,
    })
}

/// `x.rem_euclid(y)`, bit for bit, for `y` not 0: whole numbers below
/// 2⁵³ (a loop's `i % 10`) in integers, as `%` on floats is a slow
/// software `fmod`; told whole by a round trip through `i64` rather than
/// by `fract`, a call into libm on the machines without SSE4.1 that the
/// binary is built for.
#[inline]
pub(super) fn rem_euclid(x: f64, y: f64) -> f64 {
    const EXACT: f64 = (1u64 << 53) as f64;
    if x.abs() < EXACT && y.abs() < EXACT {
        let (a, b) = (x as i64, y as i64);
        if a as f64 == x && b as f64 == y {
            // `fmod`'s remainder has the sign of `x`, a zero one included.
            let r = match a % b {
                0 => 0.0f64.copysign(x),
                r => r as f64,
            };
            return if r < 0.0 { r + y.abs() } else { r };
        }
    }
    x.rem_euclid(y)
}

fn binary(op: BinOp, a: Value, b: Value, e: &Expr, errors: &mut Vec<Error>) -> Option<Value> {
    use Value::*;
    let num = |x: f64, y: f64| match op {
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Mul => x * y,
        BinOp::Div => x / y,
        BinOp::Pow => x.powf(y),
        // The sign of the divisor, so `-1 % 12` is 11 (what loops want).
        _ => x.rem_euclid(y),
    };
    let v = match (&a, &b, op) {
        (_, _, BinOp::Eq | BinOp::Ne) if comparable(&a, &b) => Bool((a == b) == (op == BinOp::Eq)),
        (Number(x), Number(y), BinOp::Lt) => Bool(x < y),
        (Number(x), Number(y), BinOp::Le) => Bool(x <= y),
        (Number(x), Number(y), BinOp::Gt) => Bool(x > y),
        (Number(x), Number(y), BinOp::Ge) => Bool(x >= y),
        (Number(_), Number(y), BinOp::Div | BinOp::Rem) if *y == 0.0 => {
            errors.push(Error::new(e.span, "division by zero").label("divides by zero"));
            return None;
        }
        (
            Number(x),
            Number(y),
            BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Pow | BinOp::Rem,
        ) => Number(num(*x, *y)),
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
        (List(x), List(y), BinOp::Add) => {
            List(Arc::new(x.iter().chain(y.iter()).cloned().collect()))
        }
        _ => {
            let what = match op {
                BinOp::Add => "add",
                BinOp::Sub => "subtract",
                BinOp::Mul => "multiply",
                BinOp::Div => "divide",
                BinOp::Pow => "raise",
                BinOp::Rem => "take the remainder of",
                _ => "compare",
            };
            let (pa, pb) = match op {
                BinOp::Add => (a.kind(), format!("to {}", b.kind())),
                BinOp::Sub => (b.kind(), format!("from {}", a.kind())),
                BinOp::Pow => (a.kind(), format!("to the power {}", b.kind())),
                BinOp::Eq | BinOp::Ne | BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => {
                    (a.kind(), format!("with {}", b.kind()))
                }
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

/// `==` is defined between values of one kind (objects never compare).
fn comparable(a: &Value, b: &Value) -> bool {
    use Value::*;
    matches!(
        (a, b),
        (Number(_), Number(_))
            | (Vector(_), Vector(_))
            | (Colour(_), Colour(_))
            | (Bool(_), Bool(_))
            | (List(_), List(_))
    )
}

/// A pure hash of (seed, i) to [0, 1): the same numbers on every run and
/// machine (SplitMix64 of the two numbers' bits).
pub fn random(seed: f64, i: f64) -> f64 {
    let mix = |mut z: u64| {
        z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    // +0.0 so that -0 and 0 give the same number.
    let h = mix(mix((seed + 0.0).to_bits()) ^ (i + 0.0).to_bits());
    (h >> 11) as f64 / (1u64 << 53) as f64
}

fn call(
    name: &str,
    v: &[Value],
    e: &Expr,
    args: &[Expr],
    errors: &mut Vec<Error>,
) -> Option<Value> {
    // Each argument's expected kind, checked before the maths.
    let want = |k: usize, what: &str, errors: &mut Vec<Error>| {
        errors.push(
            Error::new(
                args[k].span,
                format!("`{name}` needs {what} here, found {}", v[k].kind()),
            )
            .label(format!("this is {}", v[k].kind())),
        );
    };
    // The numeric built-ins take at most three arguments (FUNCTIONS), so
    // an array, not a Vec: `rgb(…)` once per object in a 100,000-object
    // loop then allocates nothing here. Unused places stay 0.
    let nums = |errors: &mut Vec<Error>| -> Option<[f64; 3]> {
        let mut out = [0.0; 3];
        for (k, x) in v.iter().enumerate() {
            match x {
                Value::Number(n) => out[k] = *n,
                _ => {
                    want(k, "a number", errors);
                    return None;
                }
            }
        }
        Some(out)
    };
    let vec3 = |k: usize, errors: &mut Vec<Error>| -> Option<[f64; 3]> {
        match &v[k] {
            Value::Vector(x) if x.len() == 3 => Some([x[0], x[1], x[2]]),
            _ => {
                want(k, "a 3-vector", errors);
                None
            }
        }
    };
    let out = match name {
        "normalize" | "length" => {
            let a = vec3(0, errors)?;
            let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            if name == "length" {
                Value::Number(l)
            } else if l == 0.0 {
                errors.push(
                    Error::new(args[0].span, "cannot normalize a zero vector")
                        .label("its length is 0"),
                );
                return None;
            } else {
                Value::Vector(a.iter().map(|x| x / l).collect())
            }
        }
        "dot" | "cross" => {
            let a = vec3(0, errors);
            let b = vec3(1, errors);
            let (a, b) = (a?, b?);
            if name == "dot" {
                Value::Number(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
            } else {
                Value::Vector(smallvec::smallvec![
                    a[1] * b[2] - a[2] * b[1],
                    a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0],
                ])
            }
        }
        "len" => match &v[0] {
            Value::List(l) => Value::Number(l.len() as f64),
            Value::Vector(x) => Value::Number(x.len() as f64),
            _ => {
                want(0, "a list", errors);
                return None;
            }
        },
        "lerp" if !matches!(v[2], Value::Number(_)) => {
            want(2, "a number", errors);
            return None;
        }
        "lerp" => {
            // Numbers, vectors or colours: a + (b − a)·t.
            let Value::Number(t) = v[2] else {
                unreachable!()
            };
            match (&v[0], &v[1]) {
                (Value::Number(a), Value::Number(b)) => Value::Number(a + (b - a) * t),
                (Value::Vector(a), Value::Vector(b)) if a.len() == b.len() => {
                    Value::Vector(a.iter().zip(b).map(|(a, b)| a + (b - a) * t).collect())
                }
                (Value::Colour(a), Value::Colour(b)) => Value::Colour(*a + (*b - *a) * t),
                _ => {
                    errors.push(
                        Error::new(
                            e.span,
                            format!("`lerp` cannot mix {} and {}", v[0].kind(), v[1].kind()),
                        )
                        .label("different kinds")
                        .help("lerp(a, b, t) mixes two numbers, vectors or colours of one kind"),
                    );
                    return None;
                }
            }
        }
        _ => {
            let x = nums(errors)?;
            let f = Builtin::named(name).expect("checked against FUNCTIONS");
            match f.apply(x) {
                Ok(v) => v,
                Err(Refusal { arg, what }) => {
                    errors.push(
                        Error::new(args[arg].span, what).label(format!("this is {}", x[arg])),
                    );
                    return None;
                }
            }
        }
    };
    finite(out, e, errors)
}

/// Whether `e` names nothing the evaluator cannot see: then it can be
/// worked out to a value before the builder.
pub fn is_closed(names: &dyn Names, e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Name(n) => names.binds(n) || &**n == "pi" || named_colour(n).is_some(),
        ExprKind::Number(_) | ExprKind::Hex(_) | ExprKind::Value(_) | ExprKind::Bound(..) => true,
        ExprKind::Vector(v) | ExprKind::List(v) => v.iter().all(|p| is_closed(names, p)),
        ExprKind::Call { args, named, .. } => {
            args.iter().all(|p| is_closed(names, p))
                && named.iter().all(|(_, p)| is_closed(names, p))
        }
        ExprKind::Neg(x) | ExprKind::Not(x) => is_closed(names, x),
        ExprKind::Binary { lhs, rhs, .. } => is_closed(names, lhs) && is_closed(names, rhs),
        ExprKind::Index { base, index } => is_closed(names, base) && is_closed(names, index),
    }
}

/// `Spanned` re-exported for the evaluator's signatures.
pub type Name = Spanned<String>;

#[cfg(test)]
#[path = "expr_tests.rs"]
mod tests;
