//! The evaluator's short cut for the expressions a loop's body is made of:
//! arithmetic on numbers and bound names, vectors of them, and numeric
//! built-ins (`centre <-20 + 0.1 * i, 0.05, j>`, `rgb(i % 10 / 10, …)`),
//! worked out with plain `f64`s instead of a `Value` per node.
//!
//! It answers only where the general walk ([`expr::eval`]) would answer
//! the same with no message, and otherwise gives up having changed
//! nothing: a name bound to anything but a number, a division by zero, a
//! result that is not finite, a user function, a step budget due a check.
//! The walk then does the expression again, with its messages. So it
//! changes no result and no step count, only the time: the walk's nodes
//! each return a 40-byte `Value` through memory and look their name up
//! one scope at a time, about half of `many`'s evaluation.

use super::builtins::Builtin;
use super::*;
use crate::lang::ast::BinOp;

/// `e`'s value when the short cut can tell it (see the module's doc),
/// its steps counted as the walk would count them.
pub(super) fn value(at: &At, e: &Expr) -> Option<Value> {
    let mut steps = 0;
    let v = match &e.kind {
        ExprKind::Vector(parts) => {
            steps += 1;
            let mut out = expr::Components::with_capacity(parts.len());
            for p in parts {
                out.push(number(at, p, &mut steps)?);
            }
            Value::Vector(out)
        }
        ExprKind::Call { name, args, named } => {
            steps += 1;
            call(at, &name.node, args, named, &mut steps)?
        }
        _ => Value::Number(number(at, e, &mut steps)?),
    };
    at.ex.take_steps(steps).then_some(v)
}

/// A numeric expression's value; `steps` counts its nodes.
fn number(at: &At, e: &Expr, steps: &mut u64) -> Option<f64> {
    *steps += 1;
    match &e.kind {
        ExprKind::Number(v) if v.is_finite() => Some(*v),
        ExprKind::Name(n) => at.number(n),
        ExprKind::Value(Value::Number(x)) | ExprKind::Bound(_, Some(Value::Number(x))) => Some(*x),
        ExprKind::Neg(x) => number(at, x, steps).map(|v| -v),
        ExprKind::Call { name, args, named } => match call(at, &name.node, args, named, steps)? {
            Value::Number(x) => Some(x),
            _ => None,
        },
        ExprKind::Binary { op, lhs, rhs }
            if matches!(
                op,
                BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Pow | BinOp::Rem
            ) =>
        {
            let a = number(at, lhs, steps)?;
            let b = number(at, rhs, steps)?;
            let v = expr::arithmetic(*op, a, b)?;
            v.is_finite().then_some(v)
        }
        _ => None,
    }
}

/// A call of a numeric built-in with numbers (its node's step counted by
/// the caller).
fn call(
    at: &At,
    name: &str,
    args: &[Expr],
    named: &[(Spanned<String>, Expr)],
    steps: &mut u64,
) -> Option<Value> {
    let f = Builtin::named(name)?;
    if !named.is_empty() || args.len() != f.arity() || at.scope.with(name, |_| ()).is_some() {
        return None;
    }
    let mut x = [0.0; 3];
    for (x, a) in x.iter_mut().zip(args) {
        *x = number(at, a, steps)?;
    }
    f.apply(x).ok().filter(Value::is_finite)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::ast::Item;

    /// An expander over an empty program, and the expression `text`.
    fn parsed(text: &str) -> (crate::lang::Program, Expr) {
        let program =
            crate::lang::load_text(std::path::Path::new("t.rt"), format!("let e = {text}"))
                .unwrap_or_else(|_| panic!("{text} parses"));
        let Some(Item::Let { value, .. }) = program.items.first() else {
            panic!("{text}: not a let");
        };
        let e = (**value).clone();
        (program, e)
    }

    fn expander<'p>(program: &'p crate::lang::Program, options: &'p Options) -> Expander<'p> {
        let ex = Expander::new(program, Transfer::Srgb, options);
        // From 1: at 0 a step is due the cancel look (0 is a multiple of
        // 4096), which the short cut leaves to the walk.
        ex.steps.set(1);
        ex
    }

    /// i = 7, j = 3, h = 0.5, v = <1, 2, 3>, c a colour, f a function;
    /// `u` and `w` are unbound.
    fn scope() -> Rc<Scope> {
        let s = Scope::root();
        let bind = |n: &str, v: Value| s.bind(n, Binding::Value(Some(v)), None);
        bind("i", Value::Number(7.0));
        bind("j", Value::Number(3.0));
        bind("h", Value::Number(0.5));
        bind("v", Value::Vector(smallvec::smallvec![1.0, 2.0, 3.0]));
        bind("c", Value::Colour(crate::scene::Colour::new(0.1, 0.2, 0.3)));
        let (program, _) = parsed("1");
        let f = crate::lang::load_text(std::path::Path::new("f.rt"), "fn rgb2(x) = x".into())
            .expect("parses");
        let Some(Item::Fn(def)) = f.items.first() else {
            panic!("not a fn")
        };
        drop(program);
        s.bind("sin2", Binding::Function(def.clone(), s.clone()), None);
        s
    }

    /// What the walk and the short cut give for `text`, each from a fresh
    /// step count: (walk's value, its messages, its steps) and (short
    /// cut's value, its steps).
    #[allow(clippy::type_complexity)]
    fn both(text: &str, scope: &Rc<Scope>) -> ((Option<Value>, usize, u64), (Option<Value>, u64)) {
        let (program, e) = parsed(text);
        both_of(&program, &e, scope)
    }

    /// [`both`] for an expression already made.
    #[allow(clippy::type_complexity)]
    fn both_of(
        program: &crate::lang::Program,
        e: &Expr,
        scope: &Rc<Scope>,
    ) -> ((Option<Value>, usize, u64), (Option<Value>, u64)) {
        let options = Options::default();
        let ex = expander(program, &options);
        let at = ex.at(scope);
        let mut errors = Vec::new();
        let walk = expr::eval(&at, e, &mut errors);
        let walk_steps = ex.steps.get() - 1;
        let ex = expander(program, &options);
        let at = ex.at(scope);
        let fast = value(&at, e);
        ((walk, errors.len(), walk_steps), (fast, ex.steps.get() - 1))
    }

    /// Bit for bit, -0 and NaN included (`Debug` writes `-0.0`).
    fn same(a: &Value, b: &Value) -> bool {
        format!("{a:?}") == format!("{b:?}")
    }

    #[test]
    fn a_loops_expressions_take_the_short_cut_and_agree_with_the_walk() {
        let s = scope();
        for text in [
            "-20 + 0.1 * i",
            "<-20 + 0.1 * i, 0.05, -5 + 0.1 * j>",
            "rgb(i % 10 / 10, j % 10 / 10, 0.5)",
            "2 ^ 10 - -i",
            "sqrt(i * j) + sin(pi / 6) + min(i, j) + clamp(h, 0, 0.25)",
            "random(i, j) + atan2(-1, -h) + floor(-h) + round(h) + abs(-j)",
            "log(i) + exp(h) + cos(j) + tan(h) + rad(90) + deg(pi) + max(i, 1) + ceil(h)",
            "-7 % 3 + 7 % -3",
            // Black and a zero component are colours, not mistakes.
            "rgb(0, 0, 0)",
            "rgb(h - h, i % 1, j)",
        ] {
            let ((walk, errors, walk_steps), (fast, fast_steps)) = both(text, &s);
            let fast = fast.unwrap_or_else(|| panic!("{text}: no short cut"));
            let walk = walk.unwrap_or_else(|| panic!("{text}: no value"));
            assert!(same(&fast, &walk), "{text}: {fast:?} against {walk:?}");
            assert_eq!(errors, 0, "{text}");
            assert_eq!(fast_steps, walk_steps, "{text}");
        }
    }

    #[test]
    fn whatever_the_walk_would_report_or_cannot_give_a_number_is_left_to_it() {
        let s = scope();
        for text in [
            "1 / (i - 7)",   // division by zero
            "i % 0",         // remainder by zero
            "10 ^ 400",      // not finite
            "sqrt(-i)",      // a message of the built-in
            "log(0)",        // likewise
            "rgb(-h, 0, 0)", // a negative component
            "rgb(1e308 * 10, 0, 0)",
            "rgb(-h, 1, 1)", // a negative component among others
            "1e400",         // a literal too large for a float
            "min(1e400, i)", // likewise, in a call that would hide it
            "-1e400 + i",
            "u + 1",      // unbound
            "v * 2",      // a vector
            "c",          // a colour
            "i < j",      // a condition
            "dot(v, v)",  // a built-in of vectors
            "rgb(1, 2)",  // the wrong count
            "sin2(1)",    // a user function
            "sqrt(x: 1)", // a named argument
            "<i, v>",     // a vector in a vector
            "[i, j]",     // a list
        ] {
            let ((_, _, walk_steps), (fast, fast_steps)) = both(text, &s);
            assert!(fast.is_none(), "{text}: {fast:?}");
            assert_eq!(fast_steps, 0, "{text}: steps {fast_steps} of {walk_steps}");
        }
    }

    /// `e` as the evaluator leaves a part of an expression it has worked
    /// out already: `u` a worked-out number (`ExprKind::Value`), `w` a
    /// bound name carrying its number (`ExprKind::Bound`), `s` a bound
    /// name carrying a vector, `f` one whose definition failed. (None
    /// of them is bound in [`scope`]: only the node says what it is.)
    fn worked_out(e: &mut Expr) {
        let number = |x: f64| Some(Value::Number(x));
        let kind = match &mut e.kind {
            ExprKind::Name(n) => match &**n {
                "u" => ExprKind::Value(Value::Number(2.5)),
                "w" => ExprKind::Bound(n.clone(), number(-4.0)),
                "s" => ExprKind::Bound(
                    n.clone(),
                    Some(Value::Vector(smallvec::smallvec![1.0, 2.0])),
                ),
                "f" => ExprKind::Bound(n.clone(), None),
                _ => return,
            },
            ExprKind::Binary { lhs, rhs, .. } => {
                worked_out(lhs);
                worked_out(rhs);
                return;
            }
            ExprKind::Neg(x) => return worked_out(x),
            ExprKind::Call { args, .. } => return args.iter_mut().for_each(worked_out),
            ExprKind::Vector(parts) => return parts.iter_mut().for_each(worked_out),
            _ => return,
        };
        e.kind = kind;
    }

    /// Numbers the evaluator has already worked out or filled in for a
    /// bound name take the short cut, as the walk gives them; a bound
    /// vector or a failed definition is left to the walk.
    #[test]
    fn worked_out_numbers_and_bound_names_take_the_short_cut() {
        let s = scope();
        for text in [
            "u",
            "w * u",
            "-w + i",
            "<u, w, -u>",
            "rgb(u / 10, -w / 10, 0.5)",
            "sqrt(u) + w % 3 + min(u, w)",
        ] {
            let (program, mut e) = parsed(text);
            worked_out(&mut e);
            let ((walk, errors, walk_steps), (fast, fast_steps)) = both_of(&program, &e, &s);
            let fast = fast.unwrap_or_else(|| panic!("{text}: no short cut"));
            let walk = walk.unwrap_or_else(|| panic!("{text}: no value"));
            assert!(same(&fast, &walk), "{text}: {fast:?} against {walk:?}");
            assert_eq!(errors, 0, "{text}");
            assert_eq!(fast_steps, walk_steps, "{text}");
        }
        for text in ["s", "s + 1", "<u, s>", "f", "f * 2", "sqrt(f)"] {
            let (program, mut e) = parsed(text);
            worked_out(&mut e);
            let (_, (fast, fast_steps)) = both_of(&program, &e, &s);
            assert!(fast.is_none(), "{text}: {fast:?}");
            assert_eq!(fast_steps, 0, "{text}");
        }
    }

    #[test]
    fn a_call_of_a_shadowed_built_in_is_left_to_the_walk() {
        let s = scope();
        s.bind("min", Binding::Value(Some(Value::Number(1.0))), None);
        let (_, (fast, _)) = both("min(i, j)", &s);
        assert!(fast.is_none());
    }

    /// Expressions from a small grammar of numbers, names (bound to
    /// numbers or not), operators, calls and vectors, 4000 of them: where
    /// the short cut answers, the walk answers the same, bit for bit,
    /// without a message, in as many steps; where it does not, it took
    /// no step.
    #[test]
    fn random_expressions_agree_with_the_walk_wherever_the_short_cut_answers() {
        let s = scope();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        };
        fn grow(next: &mut dyn FnMut(u64) -> u64, depth: u32) -> String {
            const ATOMS: [&str; 13] = [
                "0", "1", "2", "0.5", "1e300", "-3", "i", "j", "h", "pi", "u", "v", "c",
            ];
            const OPS: [&str; 8] = ["+", "-", "*", "/", "%", "^", "<", "=="];
            const CALLS: [(&str, usize); 8] = [
                ("rgb", 3),
                ("sqrt", 1),
                ("log", 1),
                ("min", 2),
                ("clamp", 3),
                ("random", 2),
                ("dot", 2),
                ("sin2", 1),
            ];
            if depth == 0 {
                return ATOMS[next(ATOMS.len() as u64) as usize].to_string();
            }
            match next(6) {
                0 => ATOMS[next(ATOMS.len() as u64) as usize].to_string(),
                1 => format!("-({})", grow(next, depth - 1)),
                2 => {
                    let (f, n) = CALLS[next(CALLS.len() as u64) as usize];
                    let args: Vec<_> = (0..n).map(|_| grow(next, depth - 1)).collect();
                    format!("{f}({})", args.join(", "))
                }
                3 => {
                    let parts: Vec<_> = (0..3).map(|_| grow(next, depth - 1)).collect();
                    format!("<{}>", parts.join(", "))
                }
                _ => format!(
                    "({} {} {})",
                    grow(next, depth - 1),
                    OPS[next(OPS.len() as u64) as usize],
                    grow(next, depth - 1)
                ),
            }
        }
        let (mut answered, mut numbers, mut colours) = (0, 0, 0);
        for _ in 0..4000 {
            let depth = 1 + next(4) as u32;
            // One in eight a colour, as a material's `colour rgb(…)`.
            let text = match next(8) {
                0 => format!(
                    "rgb({}, {}, {})",
                    grow(&mut next, depth - 1),
                    grow(&mut next, depth - 1),
                    grow(&mut next, depth - 1)
                ),
                _ => grow(&mut next, depth),
            };
            let ((walk, errors, walk_steps), (fast, fast_steps)) = both(&text, &s);
            match fast {
                Some(f) => {
                    answered += 1;
                    match f {
                        Value::Number(_) => numbers += 1,
                        Value::Colour(_) => colours += 1,
                        _ => {}
                    }
                    let w = walk.unwrap_or_else(|| panic!("{text}: the walk gave nothing"));
                    assert!(same(&f, &w), "{text}: {f:?} against {w:?}");
                    assert_eq!(errors, 0, "{text}");
                    assert_eq!(fast_steps, walk_steps, "{text}");
                }
                None => assert_eq!(fast_steps, 0, "{text}"),
            }
        }
        // Not a test of nothing: a good share of them took the short cut.
        assert!(
            answered > 800 && numbers > 400 && colours > 50,
            "{answered} {numbers} {colours}"
        );
    }

    #[test]
    fn steps_are_taken_at_once_only_where_each_would_be_taken_without_a_check() {
        let (program, _) = parsed("1");
        let mut options = Options::default();
        options.limits.steps = 10_000;
        let ex = expander(&program, &options);
        // From 1: the steps counted 1 to 4095, not the cancel look at 4096.
        assert!(!ex.take_steps(4096));
        assert_eq!(ex.steps.get(), 1, "nothing taken");
        assert!(ex.take_steps(4095));
        assert_eq!(ex.steps.get(), 4096);
        assert!(!ex.take_steps(1), "a look due now");
        ex.steps.set(4097);
        assert!(!ex.take_steps(4096));
        assert!(ex.take_steps(4095));
        assert_eq!(ex.steps.get(), 8192);
        // The budget: up to it, not past it.
        ex.steps.set(9990);
        assert!(!ex.take_steps(11));
        assert!(ex.take_steps(10));
        assert_eq!(ex.steps.get(), 10_000);
        ex.steps.set(8193);
        ex.stopped.set(true);
        assert!(!ex.take_steps(1));
        ex.stopped.set(false);
        ex.steps.set(8192);
        assert!(!ex.take_steps(1), "a look due now");
        ex.steps.set(u64::MAX - 2);
        assert!(!ex.take_steps(1));
    }
}
