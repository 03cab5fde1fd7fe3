//! `sectors { count n }` and `quadrants { }` (n = 4): n equal wedges.
//! Solid: around the y axis, the angle φ = atan2(z, x) measured from +x
//! towards +z; with `uv`: around the (u, v) origin, φ = atan2(v, u) from
//! +u towards +v (a `translate <u0, v0, 0>` moves the centre). Sector
//! k = ⌊n·φ/2π⌋ (φ in [0, 2π)) has the value k/(n − 1): 0 for the first,
//! 1 for the last, so `a`/`b` or a `colour_map` tells them apart. With
//! `alternate` the value is k mod 2 instead: wedges of `a` and `b` in turn
//! (an even `count` closes the circle without two alike side by side).

use crate::geometry::{DVec2, DVec3};
use std::f64::consts::TAU;

#[derive(Clone, Debug, PartialEq)]
pub struct Sectors {
    /// At least 2.
    pub count: u32,
    /// Around the (u, v) origin instead of the y axis.
    pub uv: bool,
    /// 0 and 1 in turn instead of k/(n − 1).
    pub alternate: bool,
}

impl Sectors {
    fn of_angle(&self, a: f64, b: f64) -> f64 {
        let phi = b.atan2(a).rem_euclid(TAU);
        let n = self.count as f64;
        let k = ((n * phi / TAU).floor()).min(n - 1.0);
        if self.alternate {
            k % 2.0
        } else {
            k / (n - 1.0)
        }
    }

    pub fn value_solid(&self, p: DVec3) -> f64 {
        self.of_angle(p.x, p.z)
    }

    pub fn value_uv(&self, uv: DVec2) -> f64 {
        self.of_angle(uv.x, uv.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at_degrees(s: &Sectors, deg: f64) -> f64 {
        let r = deg.to_radians();
        s.value_solid(DVec3::new(r.cos(), 0.7, r.sin()))
    }

    #[test]
    fn quadrants_change_at_right_angles() {
        let q = Sectors {
            count: 4,
            uv: false,
            alternate: false,
        };
        for (deg, v) in [
            (1.0, 0.0),
            (89.0, 0.0),
            (91.0, 1.0 / 3.0),
            (179.0, 1.0 / 3.0),
            (181.0, 2.0 / 3.0),
            (269.0, 2.0 / 3.0),
            (271.0, 1.0),
            (359.0, 1.0),
        ] {
            assert_eq!(at_degrees(&q, deg), v, "at {deg}°");
        }
    }

    #[test]
    fn six_sectors_change_every_sixty_degrees_in_uv() {
        let s = Sectors {
            count: 6,
            uv: true,
            alternate: false,
        };
        for k in 0..6 {
            for d in [0.5, 59.5] {
                let a = (60.0 * k as f64 + d).to_radians();
                let v = s.value_uv(DVec2::new(a.cos(), a.sin()) * 3.0);
                assert_eq!(v, k as f64 / 5.0, "sector {k} at +{d}°");
            }
        }
    }

    #[test]
    fn alternate_wedges_take_turns() {
        let s = Sectors {
            count: 8,
            uv: false,
            alternate: true,
        };
        for k in 0..8 {
            assert_eq!(at_degrees(&s, 45.0 * k as f64 + 20.0), (k % 2) as f64);
        }
    }

    /// Just below the +x (or +u) axis, φ = 2π − ε rounds to 2π: still the
    /// last sector (value 1, or k mod 2 of the last), never one past it.
    #[test]
    fn just_below_the_axis_is_the_last_sector() {
        for count in [2, 4, 5, 6] {
            let s = Sectors {
                count,
                uv: true,
                alternate: false,
            };
            assert_eq!(s.value_uv(DVec2::new(1.0, -1e-300)), 1.0, "{count}");
            assert_eq!(s.value_solid(DVec3::new(1.0, 0.0, -1e-300)), 1.0);
            let alt = Sectors {
                alternate: true,
                ..s
            };
            let last = ((count - 1) % 2) as f64;
            assert_eq!(alt.value_uv(DVec2::new(1.0, -1e-300)), last, "{count}");
        }
    }
}
