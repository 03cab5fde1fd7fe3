//! `gradient { axis <0, 1, 0> }`: a ramp along a direction, repeating:
//! the value is the fractional part of p·axis (so 0 at the origin's plane,
//! rising to just below 1 one unit of |axis|⁻¹ further, then starting
//! again). With `mirror` it goes back down instead of jumping (a triangle
//! wave: t = (p·axis) mod 2, the value t up to 1 and 2 − t after).

use crate::geometry::DVec3;

#[derive(Clone, Debug, PartialEq)]
pub struct Gradient {
    /// The direction it rises along; its length is the repeats per unit.
    pub axis: DVec3,
    /// Rise then fall (period 2/|axis|) instead of rise then jump.
    pub mirror: bool,
}

impl Gradient {
    pub fn value(&self, p: DVec3) -> f64 {
        let s = p.dot(self.axis);
        if self.mirror {
            // Triangle wave: 0 at even integers, 1 at odd ones.
            let t = s.rem_euclid(2.0);
            if t <= 1.0 { t } else { 2.0 - t }
        } else {
            s - s.floor()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_at_known_points() {
        let g = Gradient {
            axis: DVec3::Y,
            mirror: false,
        };
        assert_eq!(g.value(DVec3::new(5.0, 0.25, -3.0)), 0.25);
        assert_eq!(g.value(DVec3::new(0.0, 1.75, 0.0)), 0.75);
        assert_eq!(
            g.value(DVec3::new(0.0, -0.25, 0.0)),
            0.75,
            "repeats below 0"
        );
        // A longer axis repeats faster: <0, 0, 4> has period 1/4.
        let g = Gradient {
            axis: DVec3::new(0.0, 0.0, 4.0),
            mirror: false,
        };
        assert_eq!(g.value(DVec3::new(0.0, 0.0, 0.3125)), 0.25);
        // A diagonal axis: the value is constant on planes normal to it.
        let g = Gradient {
            axis: DVec3::new(1.0, 1.0, 0.0),
            mirror: false,
        };
        assert_eq!(
            g.value(DVec3::new(0.1, 0.3, 0.0)),
            g.value(DVec3::new(0.3, 0.1, 7.0))
        );
    }

    #[test]
    fn mirrored_goes_up_and_down() {
        let g = Gradient {
            axis: DVec3::X,
            mirror: true,
        };
        assert_eq!(g.value(DVec3::new(0.25, 0.0, 0.0)), 0.25);
        assert_eq!(g.value(DVec3::new(1.0, 0.0, 0.0)), 1.0);
        assert_eq!(g.value(DVec3::new(1.25, 0.0, 0.0)), 0.75);
        assert_eq!(g.value(DVec3::new(-0.25, 0.0, 0.0)), 0.25);
    }
}
