//! The polynomial in x, y, z prepared for rays: substituting
//! x = ox + t·dx (and y, z alike) must cost per ray only the evaluation of
//! the coefficients of t, so the polynomial is stored as nested Horner
//! schemes, x outermost, z innermost:
//!
//! ```text
//! P = Σ_a x^a Σ_b y^b Σ_c k_abc z^c
//! ```
//!
//! Evaluated on univariate polynomials in t, each Horner step multiplies an
//! accumulator by a linear polynomial (o + d·t), which is O(degree). The
//! same structure evaluates P and its symbolic partial derivatives at a
//! point.

use super::poly::Poly;
use crate::geometry::DVec3;

/// Coefficients of t, lowest first; index ≤ MAX_DEGREE.
pub const CAP: usize = super::expand::MAX_DEGREE as usize + 1;

#[derive(Clone, Debug)]
pub struct Compact {
    degree: usize,
    xs: Vec<Group>,
    ys: Vec<Group>,
    /// (exponent of z, coefficient), descending exponents within a group.
    zs: Vec<(u16, f64)>,
}

/// An exponent with the range of its inner groups.
#[derive(Clone, Copy, Debug)]
struct Group {
    exp: u16,
    start: u32,
    end: u32,
}

impl Compact {
    pub fn new(p: &Poly) -> Compact {
        let mut terms: Vec<([u16; 3], f64)> = p
            .terms
            .iter()
            .map(|(e, c)| ([e[0], e[1], e[2]], *c))
            .collect();
        terms.sort_by_key(|t| std::cmp::Reverse(t.0));
        let mut c = Compact {
            degree: p.degree() as usize,
            xs: Vec::new(),
            ys: Vec::new(),
            zs: Vec::new(),
        };
        for (e, k) in terms {
            let new_x = c.xs.last().is_none_or(|g| g.exp != e[0]);
            if new_x {
                c.xs.push(Group {
                    exp: e[0],
                    start: c.ys.len() as u32,
                    end: c.ys.len() as u32,
                });
            }
            let new_y = new_x || c.ys.last().is_none_or(|g| g.exp != e[1]);
            if new_y {
                c.ys.push(Group {
                    exp: e[1],
                    start: c.zs.len() as u32,
                    end: c.zs.len() as u32,
                });
                c.xs.last_mut().expect("pushed").end += 1;
            }
            c.zs.push((e[2], k));
            c.ys.last_mut().expect("pushed").end += 1;
        }
        c
    }

    /// The value at a point.
    pub fn eval(&self, p: DVec3) -> f64 {
        let mut acc_x = 0.0;
        let mut prev_x = None;
        for gx in &self.xs {
            let mut acc_y = 0.0;
            let mut prev_y = None;
            for gy in &self.ys[gx.start as usize..gx.end as usize] {
                let mut acc_z = 0.0;
                let mut prev_z = None;
                for &(cz, k) in &self.zs[gy.start as usize..gy.end as usize] {
                    if let Some(pz) = prev_z {
                        acc_z *= ipow(p.z, (pz - cz) as u32);
                    }
                    acc_z += k;
                    prev_z = Some(cz);
                }
                acc_z *= ipow(p.z, (prev_z.unwrap_or(0)) as u32);
                if let Some(py) = prev_y {
                    acc_y *= ipow(p.y, (py - gy.exp) as u32);
                }
                acc_y += acc_z;
                prev_y = Some(gy.exp);
            }
            acc_y *= ipow(p.y, (prev_y.unwrap_or(0)) as u32);
            if let Some(px) = prev_x {
                acc_x *= ipow(p.x, (px - gx.exp) as u32);
            }
            acc_x += acc_y;
            prev_x = Some(gx.exp);
        }
        acc_x * ipow(p.x, (prev_x.unwrap_or(0)) as u32)
    }

    /// The coefficients of t in P(o + t·d), lowest first, into `out`;
    /// returns the number written (degree + 1).
    /// `N` must exceed the degree (a compile-time size keeps the
    /// accumulators small and on the stack for low degrees).
    pub fn along<const N: usize>(&self, o: DVec3, d: DVec3, out: &mut [f64; N]) -> usize {
        let mut ax = Acc::<N>::new();
        let mut prev_x: Option<u16> = None;
        for gx in &self.xs {
            let mut ay = Acc::<N>::new();
            let mut prev_y: Option<u16> = None;
            for gy in &self.ys[gx.start as usize..gx.end as usize] {
                let mut az = Acc::<N>::new();
                let mut prev_z: Option<u16> = None;
                for &(cz, k) in &self.zs[gy.start as usize..gy.end as usize] {
                    if let Some(pz) = prev_z {
                        az.mul_lin_pow(o.z, d.z, pz - cz);
                    }
                    az.c[0] += k;
                    prev_z = Some(cz);
                }
                az.mul_lin_pow(o.z, d.z, prev_z.unwrap_or(0));
                if let Some(py) = prev_y {
                    ay.mul_lin_pow(o.y, d.y, py - gy.exp);
                }
                ay.add(&az);
                prev_y = Some(gy.exp);
            }
            ay.mul_lin_pow(o.y, d.y, prev_y.unwrap_or(0));
            if let Some(px) = prev_x {
                ax.mul_lin_pow(o.x, d.x, px - gx.exp);
            }
            ax.add(&ay);
            prev_x = Some(gx.exp);
        }
        ax.mul_lin_pow(o.x, d.x, prev_x.unwrap_or(0));
        *out = ax.c;
        (self.degree + 1).min(N)
    }
}

/// x^k for the small k of polynomial terms (faster than `powi`'s call).
#[inline]
fn ipow(x: f64, k: u32) -> f64 {
    let mut r = 1.0;
    for _ in 0..k {
        r *= x;
    }
    r
}

/// A univariate polynomial in t under construction. Every operation runs
/// over all N coefficients (the unused ones stay zero): fixed-length loops
/// that the compiler unrolls and vectorises beat tracking the length.
struct Acc<const N: usize> {
    c: [f64; N],
}

impl<const N: usize> Acc<N> {
    #[inline]
    fn new() -> Self {
        Acc { c: [0.0; N] }
    }

    /// Multiplies by (o + d·t)^k.
    #[inline]
    fn mul_lin_pow(&mut self, o: f64, d: f64, k: u16) {
        for _ in 0..k {
            for i in (1..N).rev() {
                self.c[i] = o * self.c[i] + d * self.c[i - 1];
            }
            self.c[0] *= o;
        }
    }

    #[inline]
    fn add(&mut self, o: &Acc<N>) {
        for i in 0..N {
            self.c[i] += o.c[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn along_matches_point_evaluation() {
        let nv = 3;
        let x = Poly::var(0, nv);
        let y = Poly::var(1, nv);
        let z = Poly::var(2, nv);
        let p = x
            .mul(&y)
            .unwrap()
            .pow(2)
            .unwrap()
            .add(&z.pow(3).unwrap().scale(-2.0))
            .add(&x.scale(0.5))
            .add(&Poly::constant(-1.25, nv));
        let c = Compact::new(&p);
        let o = DVec3::new(0.3, -1.2, 0.7);
        let d = DVec3::new(-0.4, 0.9, 1.1);
        let mut out = [0.0; CAP];
        let n = c.along(o, d, &mut out);
        assert_eq!(n, 5);
        for t in [-1.0, 0.0, 0.37, 2.0] {
            let direct = p.eval(&[o.x + t * d.x, o.y + t * d.y, o.z + t * d.z]);
            let horner: f64 = out[..n].iter().rev().fold(0.0, |a, k| a * t + k);
            assert!((direct - horner).abs() < 1e-12 * (1.0 + direct.abs()));
            let pt = o + t * d;
            assert!((c.eval(pt) - direct).abs() < 1e-12 * (1.0 + direct.abs()));
        }
    }
}
