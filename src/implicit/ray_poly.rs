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
                        acc_z *= p.z.powi((pz - cz) as i32);
                    }
                    acc_z += k;
                    prev_z = Some(cz);
                }
                acc_z *= p.z.powi(prev_z.unwrap_or(0) as i32);
                if let Some(py) = prev_y {
                    acc_y *= p.y.powi((py - gy.exp) as i32);
                }
                acc_y += acc_z;
                prev_y = Some(gy.exp);
            }
            acc_y *= p.y.powi(prev_y.unwrap_or(0) as i32);
            if let Some(px) = prev_x {
                acc_x *= p.x.powi((px - gx.exp) as i32);
            }
            acc_x += acc_y;
            prev_x = Some(gx.exp);
        }
        acc_x * p.x.powi(prev_x.unwrap_or(0) as i32)
    }

    /// The coefficients of t in P(o + t·d), lowest first, into `out`;
    /// returns the number written (degree + 1).
    pub fn along(&self, o: DVec3, d: DVec3, out: &mut [f64; CAP]) -> usize {
        let mut ax = Acc::new();
        let mut prev_x: Option<u16> = None;
        for gx in &self.xs {
            let mut ay = Acc::new();
            let mut prev_y: Option<u16> = None;
            for gy in &self.ys[gx.start as usize..gx.end as usize] {
                let mut az = Acc::new();
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
        out[..ax.len].copy_from_slice(&ax.c[..ax.len]);
        ax.len
    }
}

/// A univariate polynomial in t under construction.
struct Acc {
    c: [f64; CAP],
    len: usize,
}

impl Acc {
    #[inline]
    fn new() -> Acc {
        Acc {
            c: [0.0; CAP],
            len: 1,
        }
    }

    /// Multiplies by (o + d·t)^k.
    #[inline]
    fn mul_lin_pow(&mut self, o: f64, d: f64, k: u16) {
        for _ in 0..k {
            let n = self.len;
            if n < CAP {
                self.c[n] = d * self.c[n - 1];
            }
            for i in (1..n).rev() {
                self.c[i] = o * self.c[i] + d * self.c[i - 1];
            }
            self.c[0] *= o;
            self.len = (n + 1).min(CAP);
        }
    }

    #[inline]
    fn add(&mut self, o: &Acc) {
        for i in 0..o.len {
            self.c[i] += o.c[i];
        }
        self.len = self.len.max(o.len);
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
