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
//! it cannot diverge and converges quadratically near the root. A critical
//! point (a root of a derivative) is wanted only for the sign of the level
//! above there, so its Newton steps stop as soon as that sign is sure.
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
        13..=20 => cascade::<21>(c, lo, hi, eps, visit),
        _ => cascade::<CAP>(c, lo, hi, eps, visit),
    }
}

/// Pascal's triangle as floats, for the Bernstein test.
const BINOM: [[f64; 13]; 13] = {
    let mut t = [[0.0; 13]; 13];
    let mut n = 0;
    while n < 13 {
        t[n][0] = 1.0;
        let mut k = 1;
        while k <= n {
            t[n][k] = t[n - 1][k - 1] + if k < n { t[n - 1][k] } else { 0.0 };
            k += 1;
        }
        n += 1;
    }
    t
};

/// RATIO[deg][i][j] = C(i, j) / C(deg, j): power basis on [0, 1] to
/// Bernstein, computed at compile time (divisions per ray are slow).
static RATIO: [[[f64; 13]; 13]; 13] = {
    let mut t = [[[0.0; 13]; 13]; 13];
    let mut d = 0;
    while d < 13 {
        let mut i = 0;
        while i <= d {
            let mut j = 0;
            while j <= i {
                t[d][i][j] = BINOM[i][j] / BINOM[d][j];
                j += 1;
            }
            i += 1;
        }
        d += 1;
    }
    t
};

/// A quick, conservative test that the polynomial has no root in [−1, 1]:
/// its Bernstein coefficients there all have the same sign, with a margin
/// (the convex hull property: the curve lies within their hull). Most rays
/// that enter a surface's box but miss the surface stop here. Only up to
/// degree 12, where the change of basis is accurate; `false` means "maybe".
pub fn no_root_in_unit(c: &[f64]) -> bool {
    // The torus's quartic and the sextic's degree 6 get their own copies
    // with the sizes known, which the compiler unrolls: the same
    // operations in the same order, so the same answers, at about half the
    // instructions of the loops sized at run time.
    match c.len() {
        5 => no_root_in_unit_sized::<5>(c),
        7 => no_root_in_unit_sized::<7>(c),
        2..=13 => no_root_in_unit_sized::<13>(c),
        _ => false,
    }
}

/// [`no_root_in_unit`] for up to `N` coefficients (`c.len()` in 2..=N,
/// N ≤ 13).
#[inline(always)]
fn no_root_in_unit_sized<const N: usize>(c: &[f64]) -> bool {
    let n = c.len();
    let deg = n - 1;
    // q(u) = p(2u − 1): Taylor shift by −1, then scale by 2^j.
    let mut q = [0.0f64; N];
    q[..n].copy_from_slice(c);
    for i in 0..deg {
        for j in (i..deg).rev() {
            q[j] -= q[j + 1];
        }
    }
    let mut scale = 1.0;
    for qj in q[..n].iter_mut() {
        *qj *= scale;
        scale *= 2.0;
    }
    // b_i = Σ_{j ≤ i} C(i, j) / C(deg, j) · q_j
    let ratio = &RATIO[deg];
    let sign = q[0].signum();
    let mut mags = 0.0f64;
    let mut min_signed = f64::INFINITY;
    for (i, row) in ratio[..n].iter().enumerate() {
        let mut b = 0.0;
        let mut m = 0.0;
        for j in 0..=i {
            let term = row[j] * q[j];
            b += term;
            m += term.abs();
        }
        let signed = b * sign;
        if signed <= 0.0 {
            return false;
        }
        mags = mags.max(m);
        min_signed = min_signed.min(signed);
    }
    min_signed > 1e-12 * mags
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

/// DERIVATIVE_SCALE[d][j] = (j + 1)/d: the factor that takes coefficient
/// j + 1 of a polynomial of degree d to coefficient j of its derivative
/// divided by d ([`Cascade`]'s scaling). A multiplication per coefficient
/// where x·(j + 1)/d took a division, which waited on the divider for a
/// seventh of the torus's intersection: a different rounding and as good
/// (where d is a power of two, the same bits).
static DERIVATIVE_SCALE: [[f64; CAP]; CAP + 1] = {
    let mut t = [[0.0; CAP]; CAP + 1];
    let mut d = 1;
    while d <= CAP {
        let mut j = 0;
        while j < d {
            t[d][j] = (j + 1) as f64 / d as f64;
            j += 1;
        }
        d += 1;
    }
    t
};

/// The cascade, run lazily: level k (the k-th derivative) hands out its
/// roots one at a time, in increasing order, and asks level k + 1 for the
/// next critical point only when it needs the end of its next monotonic
/// piece. The first root of P (the nearest hit, a shadow ray's answer)
/// therefore costs only the critical points before it. `N` bounds the
/// degree + 1 (a compile-time size keeps the work arrays on the stack and
/// small for the common low degrees).
struct Cascade<const N: usize> {
    deg: usize,
    /// derivs[k] is the k-th derivative divided by a positive constant (only
    /// signs and roots matter), chosen so that magnitudes stay near c's.
    derivs: [[f64; N]; N],
    hi: f64,
    eps: f64,
    /// Per level: the left end of the current piece and the value there.
    a: [f64; N],
    fa: [f64; N],
    /// Per level: the right end of the current piece, once fetched.
    b: [f64; N],
    fb: [f64; N],
    fetched: [bool; N],
    done: [bool; N],
    /// The quadratic level's roots, in order, and how many were handed out.
    quad: [f64; 2],
    quad_count: usize,
    quad_next: usize,
}

impl<const N: usize> Cascade<N> {
    // Filled in place in the caller's state (a few hundred bytes): built
    // here and returned, it was copied out with a `memcpy` per solve
    // even when inlined.
    #[inline(always)]
    fn fill(&mut self, c: &[f64], lo: f64) {
        let deg = self.deg;
        debug_assert!((3..N).contains(&deg) && c.len() == deg + 1);
        let derivs = &mut self.derivs;
        derivs[0][..=deg].copy_from_slice(c);
        for k in 1..=deg - 2 {
            let m = deg - k;
            let scale = &DERIVATIVE_SCALE[m + 1];
            for j in 0..=m {
                // d/dt of derivs[k-1] (degree m+1), divided by (m+1).
                derivs[k][j] = derivs[k - 1][j + 1] * scale[j];
            }
        }
        let hi = self.hi;
        let q = &self.derivs[deg - 2];
        if let Some((r0, r1)) = solve_quadratic(q[2], q[1], q[0]) {
            for t in [r0, r1] {
                if t > lo && t < hi && (self.quad_count == 0 || t > self.quad[self.quad_count - 1])
                {
                    self.quad[self.quad_count] = t;
                    self.quad_count += 1;
                }
            }
        }
        for k in 0..deg - 2 {
            self.fa[k] = horner(self.poly(k), lo);
        }
    }

    #[inline]
    fn poly(&self, k: usize) -> &[f64] {
        &self.derivs[k][..=self.deg - k]
    }

    /// The next root of level k in (a_k, hi], or `None`.
    fn next(&mut self, k: usize) -> Option<f64> {
        if k == self.deg - 2 {
            let i = self.quad_next;
            self.quad_next += 1;
            return (i < self.quad_count).then(|| self.quad[i]);
        }
        // Critical points need not be exact: P is flat there, so an error
        // δ in one moves P's value by O(δ²). Only level 0's roots are hits.
        let eps = if k == 0 { self.eps } else { self.eps.max(1e-9) };
        while !self.done[k] {
            if !self.fetched[k] {
                self.b[k] = self.next(k + 1).unwrap_or(self.hi);
                self.fb[k] = horner(self.poly(k), self.b[k]);
                self.fetched[k] = true;
            }
            let (a, b, fa, fb) = (self.a[k], self.b[k], self.fa[k], self.fb[k]);
            self.a[k] = b;
            self.fa[k] = fb;
            self.fetched[k] = false;
            if b >= self.hi {
                self.done[k] = true;
            }
            if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
                if k == 0 {
                    return Some(bracketed(self.poly(0), (a, b), (fa, fb), eps, |_, _| false));
                }
                // A critical point of level k − 1 is wanted only for the
                // sign of that level's polynomial there and as the end of
                // its monotonic pieces. An iterate x serves once that
                // polynomial's value there is farther from zero than it can
                // move between x and the true critical point (its slope is
                // (deg − k + 1) × this level's polynomial: `reach` bounds
                // the integral): then it has the same sign at both and no
                // root between them, and each piece still holds at most one
                // root. Twice that, for the rounding of both sides.
                let (up, slope) = (self.poly(k - 1), (self.deg - k + 1) as f64);
                return Some(bracketed(
                    self.poly(k),
                    (a, b),
                    (fa, fb),
                    eps,
                    |x, reach| horner(up, x).abs() > 2.0 * slope * reach,
                ));
            }
            if fb == 0.0 && b > a {
                return Some(b);
            }
        }
        None
    }
}

fn cascade<const N: usize>(
    c: &[f64],
    lo: f64,
    hi: f64,
    eps: f64,
    mut visit: impl FnMut(f64) -> bool,
) {
    if horner(c, lo) == 0.0 && visit(lo) {
        return;
    }
    let mut s = Cascade::<N> {
        deg: c.len() - 1,
        derivs: [[0.0f64; N]; N],
        hi,
        eps,
        a: [lo; N],
        fa: [0.0; N],
        b: [hi; N],
        fb: [0.0; N],
        fetched: [false; N],
        done: [false; N],
        quad: [0.0; 2],
        quad_count: 0,
        quad_next: 0,
    };
    s.fill(c, lo);
    while let Some(r) = s.next(0) {
        if visit(r) {
            return;
        }
    }
}

/// The root of `p` in [a, b], where p(a) = fa and p(b) = fb have opposite
/// signs and p is monotonic. Newton from the secant guess (on a monotonic
/// piece it is usually close); every iterate updates the bracket, and a
/// step that leaves it is replaced by bisection, so it can neither diverge
/// nor cycle. `settled(x, reach)` may stop it early at an iterate x, where
/// reach = |p(x)| · (b − a) for the bracket then: how far p's integral can
/// move between x and the root (p is monotonic and zero at the root, so no
/// larger than |p(x)| between them, and they are less than b − a apart).
#[inline(always)]
fn bracketed(
    p: &[f64],
    (mut a, mut b): (f64, f64),
    (fa, fb): (f64, f64),
    eps: f64,
    settled: impl Fn(f64, f64) -> bool,
) -> f64 {
    let neg_at_a = fa < 0.0;
    let mut x = a - fa * (b - a) / (fb - fa);
    if !(x > a && x < b) {
        x = 0.5 * (a + b);
    }
    // Newton converges quadratically: once a Newton step is below √eps,
    // the point it lands on is within about eps of the root, so it is
    // returned without another evaluation. Bisection steps only stop on
    // the bracket's width.
    let step_tol = eps.sqrt() * 0.1;
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
        if settled(x, f.abs() * (b - a)) {
            return x;
        }
        let nx = x - f / df;
        if nx > a && nx < b {
            if (nx - x).abs() <= step_tol {
                return nx;
            }
            x = nx;
        } else {
            x = 0.5 * (a + b);
        }
        if b - a <= eps {
            return x;
        }
    }
    x
}

#[cfg(test)]
mod tests;
