//! `checker3d { a …  b …  size s }`: cubes of side s in the object's space
//! (POV-Ray's `checker`); the cube [0, s)³ is 0 (`a`), its six neighbours
//! 1 (`b`): the value is (⌊x/s⌋ + ⌊y/s⌋ + ⌊z/s⌋) mod 2.

use super::checker::{CELL_NUDGE, floor_i64};
use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Checker3d {
    pub size: f64,
}

impl Checker3d {
    pub fn value(&self, p: DVec3) -> f64 {
        let c = p / self.size + DVec3::splat(CELL_NUDGE);
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
        let c = Checker3d { size: 1.0 };
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
        let c = Checker3d { size: 0.5 };
        for i in -4..4 {
            for j in -4..4 {
                for k in -4..4 {
                    let p = (DVec3::new(i as f64, j as f64, k as f64) + 0.5) * 0.5;
                    let want = ((i + j + k) as i64).rem_euclid(2) as f64;
                    assert_eq!(c.value(p), want, "{p}");
                }
            }
        }
        let c = Checker3d { size: 1.0 };
        assert_eq!(c.value(DVec3::new(0.5, -1e-15, 0.5)), 0.0);
        assert_eq!(c.value(DVec3::new(0.5, 0.5, -1e-15)), 0.0);
        assert_eq!(c.value(DVec3::new(0.5, 0.999, 0.5)), 0.0);
        assert_eq!(c.value(DVec3::new(0.5, 1.0, 0.5)), 1.0);
    }
}
