//! An automatic bounding box for implicit surfaces that are bounded.
//!
//! Step 1, a proven cube: if the top-degree part P_n of the polynomial is
//! positive on the whole surface of the unit cube (‖u‖∞ = 1; even degree),
//! then for ‖x‖∞ = r, P(x) ≥ m·r^n − Σ_{k<n} M_k·r^k where m is P_n's
//! minimum there and M_k the sum of |coefficients| of degree k (as every
//! |u_i| ≤ 1). So no point of the surface lies beyond the positive root R
//! of that Cauchy polynomial: the cube [−R, R]³ holds the surface. m is
//! estimated on a 33×33 grid per face and halved for safety.
//!
//! Step 2, tightening: a 48×48 grid of lines along each axis crosses the
//! cube; the roots on them give the surface's extent, padded by two grid
//! cells and clipped to the cube. A feature thinner than a grid cell could
//! poke out of that box and be clipped; `bounded_by` overrides.
//!
//! When step 1 fails (odd degree, or P_n not positive: planes, cubics,
//! cylinders, cones) there is no box: the surface is traced unbounded.

use super::Equation;
use super::ray_poly::CAP;
use super::solve::roots_in;
use crate::geometry::{Aabb, DVec3};

/// `out[k] = x^k`.
fn powers(x: f64, out: &mut [f64]) {
    let mut p = 1.0;
    for o in out {
        *o = p;
        p *= x;
    }
}

pub fn auto_box(eq: &Equation) -> Option<Aabb> {
    let r = proven_half_size(eq)?;
    let cube = Aabb::new(DVec3::splat(-r), DVec3::splat(r));
    // Twice: the second grid is finer, over the first box.
    let first = tighten(eq, cube);
    Some(tighten(eq, first))
}

/// A 33×33 grid on each face of the cube ‖u‖∞ = 1.
fn for_face_points(mut f: impl FnMut(DVec3)) {
    let g = 33;
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            for i in 0..g {
                for j in 0..g {
                    let mut u = DVec3::ZERO;
                    u[axis] = side;
                    u[(axis + 1) % 3] = -1.0 + 2.0 * i as f64 / (g - 1) as f64;
                    u[(axis + 2) % 3] = -1.0 + 2.0 * j as f64 / (g - 1) as f64;
                    f(u);
                }
            }
        }
    }
}

fn proven_half_size(eq: &Equation) -> Option<f64> {
    let n = eq.degree as usize;
    if n % 2 == 1 {
        return None;
    }
    let top: Vec<_> = eq
        .terms
        .iter()
        .filter(|(e, _)| (e[0] + e[1] + e[2]) as usize == n)
        .collect();
    let top_at = |u: DVec3| -> f64 {
        top.iter()
            .map(|(e, c)| c * u.x.powi(e[0] as i32) * u.y.powi(e[1] as i32) * u.z.powi(e[2] as i32))
            .sum()
    };
    let mut m = f64::INFINITY;
    for_face_points(|u| m = m.min(top_at(u)));
    if m.is_nan() || m <= 0.0 {
        // Negative definite is as good: the surface of −P is the same.
        let mut neg_max = f64::NEG_INFINITY;
        for_face_points(|u| neg_max = neg_max.max(top_at(u)));
        if neg_max.is_nan() || neg_max >= 0.0 {
            return None;
        }
        m = -neg_max;
    }
    let m = 0.5 * m;
    let mut sums = vec![0.0; n];
    for (e, c) in &eq.terms {
        let k = (e[0] + e[1] + e[2]) as usize;
        if k < n {
            sums[k] += c.abs();
        }
    }
    let f = |r: f64| m * r.powi(n as i32) - (0..n).map(|k| sums[k] * r.powi(k as i32)).sum::<f64>();
    // f has one sign change in its coefficients, hence one positive root;
    // beyond it f > 0.
    let mut hi = 1.0;
    while f(hi) <= 0.0 {
        hi *= 2.0;
        if hi > 1e12 {
            return None;
        }
    }
    let mut lo = 0.0;
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi * (1.0 + 1e-9) + 1e-12)
}

/// The extent of the roots found on a grid of lines through `bx`, padded
/// by two cells, within `bx`.
///
/// Each line runs along an axis, so the polynomial on it is read straight
/// off the terms with the coordinate itself as the unknown (a term
/// c·x^a·y^b·z^c adds c·y^b·z^c to the coefficient of x^a): no binomial
/// expansion, which for a high-degree equation with many terms is what
/// made this step cost a second.
fn tighten(eq: &Equation, bx: Aabb) -> Aabb {
    let g = 48;
    let cell = bx.extent() / g as f64;
    let mut found = Aabb::EMPTY;
    let n = eq.degree as usize;
    let mut c = [0.0; CAP];
    let (mut pu, mut pv) = ([0.0; CAP], [0.0; CAP]);
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (lo, hi) = (bx.min[axis], bx.max[axis]);
        let eps = 1e-12 * (hi - lo).max(f64::MIN_POSITIVE);
        for i in 0..=g {
            for j in 0..=g {
                let mut o = DVec3::ZERO;
                o[u] = bx.min[u] + i as f64 * cell[u];
                o[v] = bx.min[v] + j as f64 * cell[v];
                powers(o[u], &mut pu[..=n]);
                powers(o[v], &mut pv[..=n]);
                c[..=n].fill(0.0);
                for (e, k) in &eq.terms {
                    c[e[axis] as usize] += k * pu[e[u] as usize] * pv[e[v] as usize];
                }
                roots_in(&c[..=n], lo, hi, eps, |t| {
                    let mut p = o;
                    p[axis] = t;
                    if eq.on_written_branch(p) {
                        found = found.grow(p);
                    }
                    false
                });
            }
        }
    }
    if found.is_empty() {
        // Nothing met: the surface is empty or tiny; the box stays.
        return bx;
    }
    let pad = 2.0 * cell;
    Aabb::new(found.min - pad, found.max + pad).intersection(&bx)
}
