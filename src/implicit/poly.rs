//! Multivariate polynomials with `f64` coefficients, used only while an
//! equation is compiled (never per ray). Variables 0, 1, 2 are x, y, z; any
//! further ones stand for roots `(…)_n` until they are eliminated.

use std::collections::BTreeMap;

/// The largest total degree an intermediate result may reach, and the most
/// terms multiplied per product: both stop a hostile equation such as
/// `(x+y+z)^100000` before it takes the machine's memory or time.
pub const INTERNAL_DEGREE: u32 = 400;
const MAX_WORK: usize = 8_000_000;

/// The most term products one whole compile may do: the per-product cap
/// alone let nested roots run a determinant of thousands of products, each
/// under the cap, for minutes (a fuzz find). The largest equations the
/// examples and tests use need well under it, and (x+y+z)^40, the
/// densest polynomial of the largest degree, fits.
pub const MAX_TOTAL_WORK: u64 = 3_000_000;

thread_local! {
    static WORK_LEFT: std::cell::Cell<u64> = const { std::cell::Cell::new(MAX_TOTAL_WORK) };
}

/// Restores the whole budget; called at the start of each compile.
pub fn reset_work_budget() {
    WORK_LEFT.with(|w| w.set(MAX_TOTAL_WORK));
}

/// Takes `n` term products from the budget, or says the expansion is too big.
fn charge(n: usize) -> Result<(), String> {
    WORK_LEFT.with(|w| {
        let left = w.get();
        if n as u64 > left {
            w.set(0);
            Err(too_big())
        } else {
            w.set(left - n as u64);
            Ok(())
        }
    })
}

#[derive(Clone, Debug, PartialEq)]
pub struct Poly {
    pub nvars: usize,
    /// Exponent vector (length `nvars`) → coefficient; no zero coefficients.
    pub terms: BTreeMap<Vec<u16>, f64>,
}

impl Poly {
    pub fn zero(nvars: usize) -> Self {
        Poly {
            nvars,
            terms: BTreeMap::new(),
        }
    }

    pub fn constant(c: f64, nvars: usize) -> Self {
        let mut p = Poly::zero(nvars);
        if c != 0.0 {
            p.terms.insert(vec![0; nvars], c);
        }
        p
    }

    pub fn var(i: usize, nvars: usize) -> Self {
        let mut p = Poly::zero(nvars);
        let mut e = vec![0; nvars];
        e[i] = 1;
        p.terms.insert(e, 1.0);
        p
    }

    /// The value when the polynomial does not depend on any variable.
    pub fn as_constant(&self) -> Option<f64> {
        match self.terms.len() {
            0 => Some(0.0),
            1 => {
                let (e, c) = self.terms.iter().next().expect("one term");
                e.iter().all(|&k| k == 0).then_some(*c)
            }
            _ => None,
        }
    }

    pub fn degree(&self) -> u32 {
        self.terms
            .keys()
            .map(|e| e.iter().map(|&k| k as u32).sum())
            .max()
            .unwrap_or(0)
    }

    pub fn uses(&self, var: usize) -> bool {
        self.terms.keys().any(|e| e[var] > 0)
    }

    fn add_term(&mut self, e: Vec<u16>, c: f64) {
        let entry = self.terms.entry(e);
        match entry {
            std::collections::btree_map::Entry::Occupied(mut o) => {
                let v = *o.get() + c;
                if v == 0.0 {
                    o.remove();
                } else {
                    *o.get_mut() = v;
                }
            }
            std::collections::btree_map::Entry::Vacant(v) => {
                if c != 0.0 {
                    v.insert(c);
                }
            }
        }
    }

    /// `self += o` without copying `self`: sums built term by term stay
    /// linear in their size (a fuzz find: copying made one quadratic).
    pub fn add_in_place(&mut self, o: Poly) {
        for (e, c) in o.terms {
            self.add_term(e, c);
        }
    }

    pub fn add(&self, o: &Poly) -> Poly {
        let mut r = self.clone();
        for (e, c) in &o.terms {
            r.add_term(e.clone(), *c);
        }
        r
    }

    pub fn scale(&self, s: f64) -> Poly {
        let mut r = Poly::zero(self.nvars);
        for (e, c) in &self.terms {
            r.add_term(e.clone(), c * s);
        }
        r
    }

    pub fn sub(&self, o: &Poly) -> Poly {
        self.add(&o.scale(-1.0))
    }

    pub fn mul(&self, o: &Poly) -> Result<Poly, String> {
        if self.degree() + o.degree() > INTERNAL_DEGREE {
            return Err(too_big());
        }
        let work = self.terms.len().saturating_mul(o.terms.len());
        if work > MAX_WORK {
            return Err(too_big());
        }
        charge(work)?;
        let mut r = Poly::zero(self.nvars);
        for (ea, ca) in &self.terms {
            for (eb, cb) in &o.terms {
                let e: Vec<u16> = ea.iter().zip(eb).map(|(a, b)| a + b).collect();
                r.add_term(e, ca * cb);
            }
        }
        Ok(r)
    }

    pub fn pow(&self, k: u32) -> Result<Poly, String> {
        if let Some(c) = self.as_constant() {
            return Ok(Poly::constant(
                c.powi(k.min(i32::MAX as u32) as i32),
                self.nvars,
            ));
        }
        if (self.degree() as u64) * (k as u64) > INTERNAL_DEGREE as u64 {
            return Err(too_big());
        }
        // Square-and-multiply: log2(k) products instead of k.
        let mut result = Poly::constant(1.0, self.nvars);
        let mut base = self.clone();
        let mut k = k;
        while k > 0 {
            if k & 1 == 1 {
                result = result.mul(&base)?;
            }
            k >>= 1;
            if k > 0 {
                base = base.mul(&base)?;
            }
        }
        Ok(result)
    }

    pub fn derivative(&self, var: usize) -> Poly {
        let mut r = Poly::zero(self.nvars);
        for (e, c) in &self.terms {
            if e[var] > 0 {
                let mut d = e.clone();
                d[var] -= 1;
                r.add_term(d, c * e[var] as f64);
            }
        }
        r
    }

    pub fn max_abs(&self) -> f64 {
        self.terms.values().fold(0.0, |m, c| m.max(c.abs()))
    }

    #[cfg(test)]
    pub fn eval(&self, p: &[f64]) -> f64 {
        self.terms
            .iter()
            .map(|(e, c)| {
                c * e
                    .iter()
                    .zip(p)
                    .map(|(&k, &v)| v.powi(k as i32))
                    .product::<f64>()
            })
            .sum()
    }
}

fn too_big() -> String {
    format!("the expansion grows beyond degree {INTERNAL_DEGREE} or too many terms")
}

/// The determinant of a square matrix of polynomials, by expansion over
/// subsets of columns (row r picks a column not yet used; the sign is the
/// number of used columns to its right). That costs n·2^(n-1) products
/// instead of n! and needs no division, which polynomials do not have.
#[allow(clippy::needless_range_loop)] // columns index a bit mask too
pub fn determinant(m: &[Vec<Poly>]) -> Result<Poly, String> {
    let n = m.len();
    let nvars = m[0][0].nvars;
    let mut dp: Vec<Option<Poly>> = vec![None; 1 << n];
    dp[0] = Some(Poly::constant(1.0, nvars));
    for mask in 0..(1usize << n) {
        let Some(acc) = dp[mask].take() else {
            continue;
        };
        let row = mask.count_ones() as usize;
        if row == n {
            dp[mask] = Some(acc);
            continue;
        }
        for col in 0..n {
            if mask & (1 << col) != 0 || m[row][col].terms.is_empty() {
                continue;
            }
            let above = (mask >> (col + 1)).count_ones();
            let mut term = acc.mul(&m[row][col])?;
            if above % 2 == 1 {
                term = term.scale(-1.0);
            }
            let next = mask | (1 << col);
            dp[next] = Some(match dp[next].take() {
                Some(mut p) => {
                    p.add_in_place(term);
                    p
                }
                None => term,
            });
        }
    }
    Ok(dp[(1 << n) - 1].take().unwrap_or_else(|| Poly::zero(nvars)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic() {
        let x = Poly::var(0, 3);
        let y = Poly::var(1, 3);
        let s = x.add(&y).pow(3).unwrap();
        assert_eq!(s.terms.len(), 4);
        assert_eq!(s.eval(&[1.0, 2.0, 0.0]), 27.0);
        assert_eq!(s.derivative(0).eval(&[1.0, 2.0, 0.0]), 27.0);
        assert!(x.pow(100_000).is_err());
        assert_eq!(x.sub(&x).as_constant(), Some(0.0));
    }

    #[test]
    fn determinant_of_2x2_and_3x3() {
        let c = |v| Poly::constant(v, 1);
        let m = vec![vec![c(1.0), c(2.0)], vec![c(3.0), c(4.0)]];
        assert_eq!(determinant(&m).unwrap().as_constant(), Some(-2.0));
        let m = vec![
            vec![c(2.0), c(0.0), c(1.0)],
            vec![c(1.0), c(3.0), c(2.0)],
            vec![c(1.0), c(1.0), c(1.0)],
        ];
        // 2(3-2) - 0 + 1(1-3) = 0
        assert_eq!(determinant(&m).unwrap().as_constant(), Some(0.0));
        let m = vec![
            vec![c(4.0), c(3.0), c(0.0)],
            vec![c(1.0), c(2.0), c(5.0)],
            vec![c(0.0), c(1.0), c(1.0)],
        ];
        // 4(2-5) - 3(1-0) + 0 = -15
        assert_eq!(determinant(&m).unwrap().as_constant(), Some(-15.0));
    }
}
