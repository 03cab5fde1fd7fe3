//! `checker3d { a …  b …  size s }`: cubes of side s in the object's space
//! (POV-Ray's `checker`); the cube [0, s)³ is 0 (`a`), its six neighbours
//! 1 (`b`): the value is (⌊x/s⌋ + ⌊y/s⌋ + ⌊z/s⌋) mod 2.

use super::checker::{CELL_NUDGE, floor_i64};
use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Checker3d {
    size: f64,
    /// 1/size where multiplying by it is dividing by size to the bit: size
    /// a power of two whose reciprocal is a normal number (then x·(1/s)
    /// and x/s are the same real number, rounded once). Every shading
    /// point of a checkered floor (side 1 or 0.5 in most scenes) divided
    /// three times here.
    exact_inverse: Option<f64>,
}

impl Checker3d {
    pub fn new(size: f64) -> Checker3d {
        let inverse = 1.0 / size;
        let power_of_two = size.is_normal() && size.to_bits() & ((1u64 << 52) - 1) == 0;
        Checker3d {
            size,
            exact_inverse: (power_of_two && inverse.is_normal()).then_some(inverse),
        }
    }

    /// `p` in units of the cube's side.
    #[inline]
    fn in_cells(&self, p: DVec3) -> DVec3 {
        match self.exact_inverse {
            Some(k) => p * k,
            None => p / self.size,
        }
    }

    pub fn value(&self, p: DVec3) -> f64 {
        let c = self.in_cells(p) + DVec3::splat(CELL_NUDGE);
        // Wrapping keeps the parity where huge points saturate.
        let i = floor_i64(c.x)
            .wrapping_add(floor_i64(c.y))
            .wrapping_add(floor_i64(c.z));
        if i.rem_euclid(2) == 0 { 0.0 } else { 1.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_at_the_origin_cell_and_stable_on_borders() {
        let c = Checker3d::new(1.0);
        assert_eq!(c.value(DVec3::new(0.5, 0.5, 0.5)), 0.0);
        assert_eq!(c.value(DVec3::new(1.5, 0.5, 0.5)), 1.0);
        assert_eq!(c.value(DVec3::new(1.5, 1.5, 0.5)), 0.0);
        // A floor at y = 0 hit a hair below zero stays in the same cell.
        assert_eq!(
            c.value(DVec3::new(0.5, -1e-15, 0.5)),
            c.value(DVec3::new(0.5, 1e-15, 0.5))
        );
        let v = c.value(DVec3::splat(1e300));
        assert!(v == 0.0 || v == 1.0, "no overflow");
    }

    /// Cubes of side `size`: with size 0.5 the origin cube is [0, 0.5)³,
    /// its neighbours start at 0.5; and a point a hair below a cube's
    /// lower face (a floor at y = 0 hit at −1e−15) is in that cube, the
    /// origin's, not the one below.
    #[test]
    fn cubes_have_the_given_side_and_a_hair_below_zero_is_the_origin_cube() {
        let c = Checker3d::new(0.5);
        for i in -4..4 {
            for j in -4..4 {
                for k in -4..4 {
                    let p = (DVec3::new(i as f64, j as f64, k as f64) + 0.5) * 0.5;
                    let want = ((i + j + k) as i64).rem_euclid(2) as f64;
                    assert_eq!(c.value(p), want, "{p}");
                }
            }
        }
        let c = Checker3d::new(1.0);
        assert_eq!(c.value(DVec3::new(0.5, -1e-15, 0.5)), 0.0);
        assert_eq!(c.value(DVec3::new(0.5, 0.5, -1e-15)), 0.0);
        assert_eq!(c.value(DVec3::new(0.5, 0.999, 0.5)), 0.0);
        assert_eq!(c.value(DVec3::new(0.5, 1.0, 0.5)), 1.0);
    }

    /// The multiplication stands in for the division only where the two
    /// agree to the bit: powers of two (both signs, large and small), and
    /// never a side whose reciprocal is inexact or not a normal number.
    #[test]
    fn cells_are_the_division_to_the_bit() {
        let mut state = 0x1234_5678_9abc_def1u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let exact = [
            1.0,
            0.5,
            2.0,
            0.25,
            1024.0,
            -4.0,
            2f64.powi(-1000),
            2f64.powi(1000),
        ];
        let inexact = [0.7, 3.0, 0.1, 1.5, 2f64.powi(-1030), 2f64.powi(1023) * 1.5];
        for s in exact {
            assert!(Checker3d::new(s).exact_inverse.is_some(), "{s}");
        }
        for s in inexact
            .into_iter()
            .chain([0.0, f64::INFINITY, f64::NAN, 2f64.powi(1023)])
        {
            assert!(Checker3d::new(s).exact_inverse.is_none(), "{s}");
        }
        for s in exact.into_iter().chain(inexact) {
            let c = Checker3d::new(s);
            for _ in 0..2000 {
                // Any finite bits (subnormals included), and a point on a
                // typical floor.
                let mut v = || loop {
                    let x = f64::from_bits(next());
                    if x.is_finite() {
                        return x;
                    }
                };
                let (x, y) = (v(), v());
                let z = (v().abs() % 2e3) - 1e3;
                let p = DVec3::new(x, y, z);
                let (got, want) = (c.in_cells(p), p / s);
                assert_eq!(
                    [got.x.to_bits(), got.y.to_bits(), got.z.to_bits()],
                    [want.x.to_bits(), want.y.to_bits(), want.z.to_bits()],
                    "side {s}, point {p}"
                );
            }
        }
    }
}
