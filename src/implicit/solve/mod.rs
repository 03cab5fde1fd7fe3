//! Real roots of a univariate polynomial inside an interval, in increasing
//! order.
//!
//! Degrees 1 and 2 use closed forms (the quadratic in its cancellation-free
//! q-form). From degree 3 up, roots are isolated by the derivative cascade
//! (C. Yuksel, "High-Performance Polynomial Root Finding for Graphics",
//! HPG 2022): the roots of P' split the interval into pieces where P is
//! monotonic, so each piece holds at most one root, exactly when P changes
//! sign across it; the roots of P' come the same way from P'', down to a
//! quadratic. Each bracketed root is found by Newton's method that keeps
//! its bracket and falls back to bisection when a step would leave it, so
//! it cannot diverge and converges quadratically near the root.
//!
//! Why not Sturm sequences (as POV-Ray does)? A Sturm chain is a sequence
//! of polynomial remainders, and in floating point the remainders of a
//! high-degree polynomial lose every significant digit: that is where
//! POV-Ray's power cube speckles from N = 14. The cascade only evaluates
//! derivatives (exact coefficient scalings) and signs, so it stays reliable
//! to degree 40 (tested), and it is faster at every degree. The only root it
//! can miss is a pair closer together than the working precision (a ray
//! grazing the surface), which a Sturm count in floating point misses too.

pub mod quadratic;

pub use quadratic::solve_quadratic;

use super::ray_poly::CAP;

/// Calls `visit` with each real root of `c[0] + c[1]·t + … + c[n]·t^n`
/// in the closed interval [lo, hi], in increasing order, until it returns
/// `true`. `eps` is the absolute precision wanted on the roots.
pub fn roots_in(c: &[f64], lo: f64, hi: f64, eps: f64, mut visit: impl FnMut(f64) -> bool) {
    let mut n = c.len();
    while n > 0 && c[n - 1] == 0.0 {
        n -= 1;
    }
    if n <= 1 || lo.is_nan() || hi.is_nan() || lo > hi {
        return;
    }
    let c = &c[..n];
    let deg = n - 1;
    match deg {
        1 => {
            let t = -c[0] / c[1];
            if t >= lo && t <= hi {
                visit(t);
            }
        }
        2 => {
            if let Some((a, b)) = solve_quadratic(c[2], c[1], c[0]) {
                for t in [a, b] {
                    if t >= lo && t <= hi && visit(t) {
                        return;
                    }
                }
            }
        }
        3..=4 => cascade::<5>(c, lo, hi, eps, visit),
        5..=6 => cascade::<7>(c, lo, hi, eps, visit),
        7..=12 => cascade::<13>(c, lo, hi, eps, visit),
        _ => cascade::<CAP>(c, lo, hi, eps, visit),
    }
}

/// All roots in [lo, hi] into a vector (tests and benches).
pub fn all_roots(c: &[f64], lo: f64, hi: f64, eps: f64) -> Vec<f64> {
    let mut v = Vec::new();
    roots_in(c, lo, hi, eps, |t| {
        v.push(t);
        false
    });
    v
}

#[inline]
fn horner(c: &[f64], x: f64) -> f64 {
    let mut acc = 0.0;
    for &k in c.iter().rev() {
        acc = acc * x + k;
    }
    acc
}

/// Value and derivative together.
#[inline]
fn horner2(c: &[f64], x: f64) -> (f64, f64) {
    let mut f = 0.0;
    let mut df = 0.0;
    for &k in c.iter().rev() {
        df = df * x + f;
        f = f * x + k;
    }
    (f, df)
}

/// `N` bounds the degree + 1 (a compile-time size keeps the work arrays on
/// the stack and small for the common low degrees).
fn cascade<const N: usize>(
    c: &[f64],
    lo: f64,
    hi: f64,
    eps: f64,
    mut visit: impl FnMut(f64) -> bool,
) {
    let deg = c.len() - 1;
    debug_assert!(deg < N);
    // derivs[k] is the k-th derivative divided by a positive constant (only
    // signs and roots matter), chosen so that magnitudes stay near c's.
    let mut derivs = [[0.0f64; N]; N];
    derivs[0][..=deg].copy_from_slice(c);
    for k in 1..deg {
        let m = deg - k; // degree of derivs[k]
        for j in 0..=m {
            // d/dt of derivs[k-1] (degree m+1), divided by (m+1).
            derivs[k][j] = derivs[k - 1][j + 1] * (j + 1) as f64 / (m + 1) as f64;
        }
    }
    // Roots of the linear derivs[deg-1].
    let mut roots = [0.0f64; N];
    let mut count = 0;
    {
        let l = &derivs[deg - 1];
        if l[1] != 0.0 {
            let t = -l[0] / l[1];
            if t > lo && t < hi {
                roots[0] = t;
                count = 1;
            }
        }
    }
    for k in (0..deg - 1).rev() {
        let p = &derivs[k][..=deg - k];
        let mut next = [0.0f64; N];
        let mut found = 0;
        let top = k == 0;
        let mut a = lo;
        let mut fa = horner(p, a);
        if fa == 0.0 && top {
            if visit(a) {
                return;
            }
        } else if fa == 0.0 {
            next[found] = a;
            found += 1;
        }
        for &b in roots[..count].iter().chain(std::iter::once(&hi)) {
            let fb = horner(p, b);
            if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
                let r = bracketed(p, a, b, fa, eps);
                if top {
                    if visit(r) {
                        return;
                    }
                } else {
                    next[found] = r;
                    found += 1;
                }
            }
            if fb == 0.0 && b > a {
                if top {
                    if visit(b) {
                        return;
                    }
                } else if b < hi {
                    next[found] = b;
                    found += 1;
                }
            }
            a = b;
            fa = fb;
        }
        roots = next;
        count = found;
    }
}

/// The root of `p` in [a, b], where p(a) = fa and p(b) have opposite signs
/// and p is monotonic. Newton from the secant guess; every iterate updates
/// the bracket, and a step that leaves it is replaced by bisection.
fn bracketed(p: &[f64], mut a: f64, mut b: f64, fa: f64, eps: f64) -> f64 {
    let neg_at_a = fa < 0.0;
    let mut x = 0.5 * (a + b);
    for _ in 0..100 {
        let (f, df) = horner2(p, x);
        if f == 0.0 {
            return x;
        }
        if (f < 0.0) == neg_at_a {
            a = x;
        } else {
            b = x;
        }
        let mut nx = x - f / df;
        if !(nx > a && nx < b) {
            nx = 0.5 * (a + b);
        }
        if (nx - x).abs() <= eps || b - a <= eps {
            return nx;
        }
        x = nx;
    }
    x
}

#[cfg(test)]
mod tests;
