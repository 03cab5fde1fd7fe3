//! Expression tree → one polynomial in x, y, z.
//!
//! Constants are substituted, products and powers multiplied out, and every
//! root `(C)_n` removed: it first becomes a new variable w with w^n = C, and
//! once the whole equation E is a polynomial in x, y, z and the w's, each w
//! is eliminated (outermost first) by taking the norm of E over w^n = C,
//! the determinant of "multiply by E" on the basis 1, w, …, w^(n-1). For a
//! square root that is exactly "isolate the radical and square both sides":
//! E = A + B·w gives A² − B²·C. The norm vanishes on every branch of the
//! root (w = ±√C); the compiled surface keeps the original tree (`Tree`) to
//! test, at each hit, that the point lies on the branch the equation wrote.

use super::EquationError;
use super::parse::{Expr, Node, Parsed};
use super::poly::{Poly, determinant};
use crate::geometry::DVec3;

/// The highest degree of the final polynomial; higher is an error. 40 is
/// the power cube's highest order; the root finder is tested to it.
pub const MAX_DEGREE: u32 = 40;
/// The highest root index `_n`.
pub const MAX_ROOT: u32 = 8;

/// The equation with constants resolved, for evaluating the original
/// expression (roots on their real principal branch) at a point.
#[derive(Clone, Debug)]
pub enum Tree {
    Num(f64),
    Var(usize),
    Neg(Box<Tree>),
    Sum(Vec<(bool, Tree)>),
    Product(Vec<(bool, Tree)>),
    Pow(Box<Tree>, i32),
    Root(Box<Tree>, u32),
}

pub struct Expanded {
    pub poly: Poly,
    pub tree: Tree,
    pub has_roots: bool,
}

struct Ctx<'a> {
    constant: &'a dyn Fn(&str) -> Option<f64>,
    nvars: usize,
    /// (index n, radicand) of each root variable 3 + i.
    roots: Vec<(u32, Poly)>,
}

fn err(
    span: &std::ops::Range<usize>,
    message: impl Into<String>,
    help: Option<String>,
) -> EquationError {
    EquationError {
        span: span.clone(),
        message: message.into(),
        help,
    }
}

pub fn expand(
    parsed: &Parsed,
    constant: &dyn Fn(&str) -> Option<f64>,
) -> Result<Expanded, Vec<EquationError>> {
    super::poly::reset_work_budget();
    let mut errors = Vec::new();
    let mut nroots = 0;
    for side in [Some(&parsed.lhs), parsed.rhs.as_ref()]
        .into_iter()
        .flatten()
    {
        check_names(side, constant, &mut errors, &mut nroots);
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut ctx = Ctx {
        constant,
        nvars: 3 + nroots,
        roots: Vec::new(),
    };
    let lhs = ctx.expand(&parsed.lhs).map_err(|e| vec![e])?;
    let mut poly = lhs;
    let mut tree = resolve(&parsed.lhs, constant);
    if let Some(rhs) = &parsed.rhs {
        let r = ctx.expand(rhs).map_err(|e| vec![e])?;
        poly = poly.sub(&r);
        tree = Tree::Sum(vec![(false, tree), (true, resolve(rhs, constant))]);
    }
    let whole = parsed.rhs.as_ref().map_or(parsed.lhs.span.clone(), |r| {
        parsed.lhs.span.start..r.span.end
    });
    let has_roots = !ctx.roots.is_empty();
    // Inner roots were numbered before the roots around them, so eliminating
    // from the last index down never leaves a w inside a radicand still
    // to be used.
    for k in (0..ctx.roots.len()).rev() {
        let var = 3 + k;
        if !poly.uses(var) {
            continue;
        }
        let (n, radicand) = ctx.roots[k].clone();
        poly = eliminate(&poly, var, n, &radicand).map_err(|m| vec![err(&whole, m, None)])?;
    }
    let mut xyz = Poly::zero(3);
    for (e, c) in &poly.terms {
        xyz.terms.insert(e[..3].to_vec(), *c);
    }
    if xyz.terms.values().any(|c| !c.is_finite()) {
        return Err(vec![err(
            &whole,
            "a coefficient of the expanded equation is too large to represent",
            Some("scale the equation's numbers down".into()),
        )]);
    }
    let degree = xyz.degree();
    if degree > MAX_DEGREE {
        return Err(vec![err(
            &whole,
            format!("the equation expands to degree {degree}, above the limit of {MAX_DEGREE}"),
            Some("the root finder is exact up to degree 40".into()),
        )]);
    }
    if degree == 0 {
        let msg = if xyz.terms.is_empty() {
            "the equation holds everywhere: it does not depend on x, y or z"
        } else {
            "the equation holds nowhere: it does not depend on x, y or z"
        };
        return Err(vec![err(&whole, msg, None)]);
    }
    Ok(Expanded {
        poly: xyz,
        tree,
        has_roots,
    })
}

#[allow(clippy::needless_range_loop)] // row and column are both computed
fn eliminate(e: &Poly, var: usize, n: u32, c: &Poly) -> Result<Poly, String> {
    let n = n as usize;
    // Reduce modulo w^n = C and split E into a_0 + a_1 w + … + a_(n-1) w^(n-1).
    let mut parts = vec![Poly::zero(e.nvars); n];
    let mut c_powers = vec![Poly::constant(1.0, e.nvars)];
    for (exp, coef) in &e.terms {
        let k = exp[var] as usize;
        let (q, r) = (k / n, k % n);
        while c_powers.len() <= q {
            let next = c_powers.last().expect("non-empty").mul(c)?;
            c_powers.push(next);
        }
        let mut rest = exp.clone();
        rest[var] = 0;
        let mut mono = Poly::zero(e.nvars);
        mono.terms.insert(rest, *coef);
        parts[r].add_in_place(mono.mul(&c_powers[q])?);
    }
    if parts[1..].iter().all(|p| p.terms.is_empty()) {
        return Ok(parts.swap_remove(0));
    }
    // Column j is E·w^j in the basis 1, w, …, w^(n-1).
    let mut m = vec![vec![Poly::zero(e.nvars); n]; n];
    for j in 0..n {
        for (k, a) in parts.iter().enumerate() {
            if a.terms.is_empty() {
                continue;
            }
            let row = k + j;
            if row < n {
                m[row][j] = m[row][j].add(a);
            } else {
                m[row - n][j] = m[row - n][j].add(&a.mul(c)?);
            }
        }
    }
    determinant(&m)
}

/// Reports every name that is neither x, y, z nor a known constant, and
/// counts the roots (each may become a variable).
fn check_names(
    e: &Expr,
    constant: &dyn Fn(&str) -> Option<f64>,
    errors: &mut Vec<EquationError>,
    nroots: &mut usize,
) {
    match &e.node {
        Node::Num(_) => {}
        Node::Name(n) => {
            if !matches!(n.as_str(), "x" | "y" | "z") && constant(n).is_none() {
                errors.push(err(
                    &e.span,
                    format!("unknown variable `{n}`"),
                    Some(suggest(n, constant)),
                ));
            }
        }
        Node::Neg(a) => check_names(a, constant, errors, nroots),
        Node::Sum(ts) | Node::Product(ts) => {
            for (_, t) in ts {
                check_names(t, constant, errors, nroots);
            }
        }
        Node::Pow(a, b) => {
            check_names(a, constant, errors, nroots);
            check_names(b, constant, errors, nroots);
        }
        Node::Root(a, b) => {
            *nroots += 1;
            check_names(a, constant, errors, nroots);
            check_names(b, constant, errors, nroots);
        }
    }
}

/// "Did you mean": a run of known names written together (`xy`, `Rx`), a
/// constant in the other case (`r` for `R`), or else the variables.
fn suggest(name: &str, constant: &dyn Fn(&str) -> Option<f64>) -> String {
    let known = |s: &str| matches!(s, "x" | "y" | "z") || constant(s).is_some();
    if let Some(parts) = split_known(name, &known) {
        return format!(
            "`{name}` is one name; for a product write `{}` or `{}`",
            parts.join(" "),
            parts.join("*")
        );
    }
    let swapped: String = name
        .chars()
        .map(|c| {
            if c.is_uppercase() {
                c.to_ascii_lowercase()
            } else {
                c.to_ascii_uppercase()
            }
        })
        .collect();
    if constant(&swapped).is_some() {
        return format!("did you mean `{swapped}`?");
    }
    let lower = name.to_ascii_lowercase();
    if matches!(lower.as_str(), "x" | "y" | "z") {
        return format!("did you mean `{lower}`? Variables are lower case");
    }
    "did you mean `x`, `y` or `z`? Other names must be numeric constants defined with `let`".into()
}

fn split_known<'a>(name: &'a str, known: &dyn Fn(&str) -> bool) -> Option<Vec<&'a str>> {
    // Shortest splits first would be ambiguous; any split into at least two
    // known names is a good hint. Names are ASCII (grammar).
    fn go<'a>(s: &'a str, known: &dyn Fn(&str) -> bool, out: &mut Vec<&'a str>) -> bool {
        if s.is_empty() {
            return out.len() >= 2;
        }
        for k in (1..=s.len()).rev() {
            if known(&s[..k]) {
                out.push(&s[..k]);
                if go(&s[k..], known, out) {
                    return true;
                }
                out.pop();
            }
        }
        false
    }
    let mut out = Vec::new();
    (name.len() <= 32 && go(name, known, &mut out)).then_some(out)
}

impl Ctx<'_> {
    fn expand(&mut self, e: &Expr) -> Result<Poly, EquationError> {
        let nv = self.nvars;
        match &e.node {
            Node::Num(v) => {
                if !v.is_finite() {
                    return Err(err(&e.span, "number too large", None));
                }
                Ok(Poly::constant(*v, nv))
            }
            Node::Name(n) => Ok(match n.as_str() {
                "x" => Poly::var(0, nv),
                "y" => Poly::var(1, nv),
                "z" => Poly::var(2, nv),
                _ => {
                    let v = (self.constant)(n)
                        .ok_or_else(|| err(&e.span, format!("unknown variable `{n}`"), None))?;
                    if !v.is_finite() {
                        return Err(err(&e.span, format!("`{n}` is not a finite number"), None));
                    }
                    Poly::constant(v, nv)
                }
            }),
            Node::Neg(a) => Ok(self.expand(a)?.scale(-1.0)),
            Node::Sum(ts) => {
                let mut acc = Poly::zero(nv);
                for (minus, t) in ts {
                    let p = self.expand(t)?;
                    acc = if *minus { acc.sub(&p) } else { acc.add(&p) };
                }
                Ok(acc)
            }
            Node::Product(fs) => {
                let mut acc = Poly::constant(1.0, nv);
                for (divide, f) in fs {
                    let p = self.expand(f)?;
                    if *divide {
                        let Some(c) = p.as_constant() else {
                            return Err(err(
                                &f.span,
                                "division by an expression containing x, y or z",
                                Some("only constants may divide; multiply both sides by the divisor instead".into()),
                            ));
                        };
                        if c == 0.0 {
                            return Err(err(&f.span, "division by zero", None));
                        }
                        acc = acc.scale(1.0 / c);
                    } else {
                        acc = acc.mul(&p).map_err(|m| err(&e.span, m, None))?;
                    }
                }
                Ok(acc)
            }
            Node::Pow(a, idx) => {
                let base = self.expand(a)?;
                let k = self.index(idx, "exponent")?;
                if let Some(c) = base.as_constant() {
                    return Ok(Poly::constant(
                        c.powi(k.clamp(i32::MIN as i64, i32::MAX as i64) as i32),
                        nv,
                    ));
                }
                if k < 0 {
                    return Err(err(
                        &idx.span,
                        format!("negative exponent {k} of an expression containing x, y or z"),
                        Some(
                            "an equation must be a polynomial: multiply both sides instead".into(),
                        ),
                    ));
                }
                if k > super::poly::INTERNAL_DEGREE as i64 {
                    return Err(err(&idx.span, format!("exponent {k} is too large"), None));
                }
                base.pow(k as u32).map_err(|m| err(&e.span, m, None))
            }
            Node::Root(a, idx) => {
                let radicand = self.expand(a)?;
                let n = self.index(idx, "root index")?;
                if n == 0 {
                    return Err(err(
                        &idx.span,
                        "root of degree 0",
                        Some("`(e)_2` is the square root, `(e)_3` the cube root".into()),
                    ));
                }
                if n < 0 {
                    return Err(err(&idx.span, format!("negative root index {n}"), None));
                }
                if n > MAX_ROOT as i64 {
                    return Err(err(
                        &idx.span,
                        format!("root index {n} is above the limit of {MAX_ROOT}"),
                        None,
                    ));
                }
                let n = n as u32;
                // Number the root even when it folds away, so that indices
                // keep matching the count taken before expansion.
                self.roots.push((n, Poly::zero(nv)));
                let var = 3 + self.roots.len() - 1;
                if n == 1 {
                    return Ok(radicand);
                }
                if let Some(c) = radicand.as_constant() {
                    if c < 0.0 && n.is_multiple_of(2) {
                        return Err(err(
                            &a.span,
                            format!("even root of the negative number {c}"),
                            None,
                        ));
                    }
                    return Ok(Poly::constant(real_root(c, n), nv));
                }
                self.roots.last_mut().expect("just pushed").1 = radicand;
                Ok(Poly::var(var, nv))
            }
        }
    }

    /// An exponent or root index: a constant integer.
    fn index(&mut self, idx: &Expr, what: &str) -> Result<i64, EquationError> {
        let p = self.expand(idx)?;
        let Some(v) = p.as_constant() else {
            return Err(err(
                &idx.span,
                format!("the {what} must be a constant integer, not an expression in x, y or z"),
                None,
            ));
        };
        if v.fract() != 0.0 || !v.is_finite() {
            return Err(err(
                &idx.span,
                format!("non-integer {what} {v}"),
                Some(if what == "exponent" {
                    "only whole powers make a polynomial; write roots as `(…)_n`".into()
                } else {
                    "roots are `(…)_n` with a whole n".into()
                }),
            ));
        }
        Ok(v as i64)
    }
}

pub fn real_root(c: f64, n: u32) -> f64 {
    if n == 2 {
        c.sqrt()
    } else if n == 3 {
        c.cbrt()
    } else {
        c.signum() * c.abs().powf(1.0 / n as f64)
    }
}

fn resolve(e: &Expr, constant: &dyn Fn(&str) -> Option<f64>) -> Tree {
    let int = |i: &Expr| eval_const(&resolve(i, constant)) as i64;
    match &e.node {
        Node::Num(v) => Tree::Num(*v),
        Node::Name(n) => match n.as_str() {
            "x" => Tree::Var(0),
            "y" => Tree::Var(1),
            "z" => Tree::Var(2),
            _ => Tree::Num(constant(n).unwrap_or(f64::NAN)),
        },
        Node::Neg(a) => Tree::Neg(Box::new(resolve(a, constant))),
        Node::Sum(ts) => Tree::Sum(ts.iter().map(|(m, t)| (*m, resolve(t, constant))).collect()),
        Node::Product(ts) => {
            Tree::Product(ts.iter().map(|(m, t)| (*m, resolve(t, constant))).collect())
        }
        Node::Pow(a, i) => Tree::Pow(
            Box::new(resolve(a, constant)),
            int(i).clamp(-1000, 1000) as i32,
        ),
        Node::Root(a, i) => {
            Tree::Root(Box::new(resolve(a, constant)), int(i).clamp(1, 1000) as u32)
        }
    }
}

fn eval_const(t: &Tree) -> f64 {
    eval(t, DVec3::ZERO).map_or(f64::NAN, |d| d.v)
}

/// A value with its gradient and a magnitude (the same expression evaluated
/// on absolute values), which scales the tolerance of the branch test.
#[derive(Clone, Copy, Debug)]
pub struct Dual {
    pub v: f64,
    pub g: DVec3,
    pub mag: f64,
}

/// The original expression at `p`, roots on their real principal branch;
/// `None` where an even root of a negative number is taken (the point is
/// not on the surface the equation describes).
pub fn eval(t: &Tree, p: DVec3) -> Option<Dual> {
    Some(match t {
        Tree::Num(v) => Dual {
            v: *v,
            g: DVec3::ZERO,
            mag: v.abs(),
        },
        Tree::Var(i) => Dual {
            v: p[*i],
            g: DVec3::AXES[*i],
            mag: p[*i].abs(),
        },
        Tree::Neg(a) => {
            let a = eval(a, p)?;
            Dual {
                v: -a.v,
                g: -a.g,
                mag: a.mag,
            }
        }
        Tree::Sum(ts) => {
            let mut acc = Dual {
                v: 0.0,
                g: DVec3::ZERO,
                mag: 0.0,
            };
            for (minus, t) in ts {
                let d = eval(t, p)?;
                let s = if *minus { -1.0 } else { 1.0 };
                acc.v += s * d.v;
                acc.g += s * d.g;
                acc.mag += d.mag;
            }
            acc
        }
        Tree::Product(ts) => {
            let mut acc = Dual {
                v: 1.0,
                g: DVec3::ZERO,
                mag: 1.0,
            };
            for (divide, t) in ts {
                let d = eval(t, p)?;
                if *divide {
                    acc = Dual {
                        v: acc.v / d.v,
                        g: acc.g / d.v,
                        mag: acc.mag / d.mag,
                    };
                } else {
                    acc = Dual {
                        v: acc.v * d.v,
                        g: acc.g * d.v + d.g * acc.v,
                        mag: acc.mag * d.mag,
                    };
                }
            }
            acc
        }
        Tree::Pow(a, k) => {
            let a = eval(a, p)?;
            let v = a.v.powi(*k);
            let g = if *k == 0 {
                DVec3::ZERO
            } else {
                a.g * (*k as f64) * a.v.powi(*k - 1)
            };
            Dual {
                v,
                g,
                mag: a.mag.powi(*k),
            }
        }
        Tree::Root(a, n) => {
            let a = eval(a, p)?;
            if a.v < 0.0 && n % 2 == 0 {
                // Tolerate rounding just below zero at the root's edge.
                if a.v < -1e-9 * a.mag.max(1e-300) {
                    return None;
                }
            }
            let v = real_root(if n % 2 == 0 { a.v.max(0.0) } else { a.v }, *n);
            let g = a.g / (*n as f64 * v.powi(*n as i32 - 1));
            Dual {
                v,
                g,
                mag: real_root(a.mag, *n),
            }
        }
    })
}
