//! `checker { a …  b …  scale k }` or `scale <ku, kv>`: squares on the
//! shape's (u, v), the course's checker. With f(s, k) = k·s for s ≥ 0 and
//! 1 − k·s below, the value is 0 (`a`) where ⌊f(u, ku)⌋ + ⌊f(v, kv)⌋ is
//! even and 1 (`b`) where it is odd.

use crate::geometry::DVec2;

/// Cell borders are nudged by this fraction of a cell so that a floor at
/// y = 0 (whose hits land at ±1e-17) does not speckle between two cells.
pub(super) const CELL_NUDGE: f64 = 1e-6;

#[derive(Clone, Debug, PartialEq)]
pub struct Checker {
    /// Cells per unit of u and of v.
    pub scale: DVec2,
}

fn course_coordinate(s: f64, k: f64) -> i64 {
    let f = if s >= 0.0 { k * s } else { 1.0 - k * s };
    floor_i64(f + CELL_NUDGE)
}

/// `x.floor() as i64` for every x (saturating, NaN to 0), without the
/// library call `floor` is on baseline x86-64 (no SSE4.1): the truncation
/// is one instruction, and steps down once where it rounded a negative
/// fraction up. Checker floors are read at every shading point.
#[inline]
pub(super) fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

impl Checker {
    pub fn value(&self, uv: DVec2) -> f64 {
        // Wrapping keeps the parity (2⁶⁴ is even) where a huge scale
        // saturates both coordinates at i64::MAX.
        let i = course_coordinate(uv.x, self.scale.x)
            .wrapping_add(course_coordinate(uv.y, self.scale.y));
        if i.rem_euclid(2) == 0 { 0.0 } else { 1.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast floor is `floor() as i64` at and around every integer up
    /// to a few thousand, at the edges of i64, at 2^52 and 2^53 where f64
    /// stops having fractions, and at NaN, infinities and both zeros.
    #[test]
    fn the_fast_floor_is_the_library_floor() {
        let mut xs = vec![
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -0.0,
            1e300,
            -1e300,
        ];
        for k in -3000..=3000 {
            for start in [k as f64, k as f64 * 0.37] {
                let (mut up, mut down) = (start, start);
                for _ in 0..20 {
                    xs.extend([up, down]);
                    up = up.next_up();
                    down = down.next_down();
                }
            }
        }
        for e in [52, 53, 62, 63, 64] {
            let p = 2f64.powi(e);
            for x in [p, -p] {
                xs.extend([x, x.next_up(), x.next_down(), x + 0.5, x - 0.5]);
            }
        }
        for x in xs {
            assert_eq!(floor_i64(x), x.floor() as i64, "{x:e}");
        }
    }

    #[test]
    fn course_cells() {
        let c = Checker {
            scale: DVec2::splat(2.0),
        };
        assert_eq!(c.value(DVec2::new(0.1, 0.1)), 0.0);
        assert_eq!(c.value(DVec2::new(0.6, 0.1)), 1.0);
        assert_eq!(c.value(DVec2::new(0.6, 0.6)), 0.0);
        // Negative side: f(s) = 1 − k·s, so −0.1 gives 1.2 → cell 1.
        assert_eq!(c.value(DVec2::new(-0.1, 0.1)), 1.0);
    }

    #[test]
    fn a_huge_scale_is_no_overflow() {
        let c = Checker {
            scale: DVec2::splat(1e300),
        };
        let v = c.value(DVec2::new(0.5, 0.7));
        assert!(v == 0.0 || v == 1.0);
    }

    #[test]
    fn two_scales_make_rectangles() {
        // 8 cells across u, 2 along v: u = 0.2 is cell 1, v = 0.2 cell 0.
        let c = Checker {
            scale: DVec2::new(8.0, 2.0),
        };
        assert_eq!(c.value(DVec2::new(0.2, 0.2)), 1.0);
        assert_eq!(c.value(DVec2::new(0.2, 0.6)), 0.0);
        assert_eq!(c.value(DVec2::new(0.1, 0.45)), 0.0);
    }

    /// Away from the borders the cell is the documented one: the parity of
    /// ⌊f(u, ku)⌋ + ⌊f(v, kv)⌋ with f(s, k) = k·s for s ≥ 0, 1 − k·s below.
    #[test]
    fn cells_follow_the_course_formula_on_both_sides_of_zero() {
        let f = |s: f64, k: f64| if s >= 0.0 { k * s } else { 1.0 - k * s };
        let c = Checker {
            scale: DVec2::new(3.0, 1.5),
        };
        let mut checked = 0;
        for i in 0..400 {
            for j in 0..40 {
                let (u, v) = (-3.0 + i as f64 * 0.0151, -2.0 + j as f64 * 0.1013);
                let (fu, fv) = (f(u, 3.0), f(v, 1.5));
                if [fu, fv].iter().any(|x| (x - x.round()).abs() < 1e-3) {
                    continue;
                }
                let want = (fu.floor() + fv.floor()).rem_euclid(2.0);
                assert_eq!(c.value(DVec2::new(u, v)), want, "({u}, {v})");
                checked += 1;
            }
        }
        assert!(checked > 10000, "{checked}");
    }

    /// The two colours change exactly at the integer lines of f: at
    /// u = 0.5 with k = 2 (f = 1) the next cell begins, a hair before it
    /// the first still holds; likewise f = 2 at u = −0.5.
    #[test]
    fn cells_change_exactly_on_the_integer_lines() {
        let c = Checker {
            scale: DVec2::splat(2.0),
        };
        let v = 0.1;
        assert_eq!(c.value(DVec2::new(0.5, v)), 1.0);
        assert_eq!(c.value(DVec2::new(0.5 - 1e-3, v)), 0.0);
        assert_eq!(c.value(DVec2::new(-0.5, v)), 0.0);
        assert_eq!(c.value(DVec2::new(-0.5 + 1e-3, v)), 1.0);
        assert_eq!(c.value(DVec2::new(1.0, v)), 0.0);
        assert_eq!(c.value(DVec2::new(1.0 - 1e-3, v)), 1.0);
    }
}
