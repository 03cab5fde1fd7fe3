//! `normal bumps { amount a  scale k }`, `normal ripples { amount a
//! scale k  centre c }`, `normal waves { … }`: patterns that tilt the
//! shading normal, not the colour (the surface stays flat: silhouettes
//! and shadows are unchanged, and the geometric normal still decides
//! which side a ray is on).
//!
//! Each gives a slope vector g at the object-space point q (placed by
//! `translate`/`rotate`, then multiplied by `scale`), and the normal
//! becomes n′ = normalize(n − a·(g − (g·n)n)): tilted along the part of
//! g in the surface's tangent plane, as a height field's normal is.
//! - bumps: g = ∇N(q), the gradient of Perlin noise (central differences);
//! - ripples: g = cos(2π r)·d/r with d = q − c, r = |d|: the slope of
//!   concentric sine waves around the centre, one per unit of q;
//! - waves: as ripples, damped with distance: g = cos(2π r)·d / (r (1 + r)).
//!
//! n′ is kept at least [`MIN_COS`] into the geometric normal's hemisphere,
//! so a strong tilt can never turn a surface's shading normal to face away.
//! `amount 0` leaves n untouched, bit for bit.
//!
//! g is found in the pattern's own axes and turned into the object's, then
//! the world's, the way a normal is turned (by the inverse transpose of
//! each linear map on the way: the pattern's `rotate`, the object's
//! transforms), keeping its length. A rotated object's bumps tilt with it,
//! exactly as the same bumps on the unrotated object rotated as a whole;
//! slopes do not change under uniform scale, since a bump's height scales
//! with its width. Under non-uniform scale the direction is the gradient's
//! and the length is kept (a choice: the bump's height has no one scale).

use crate::geometry::{DVec3, Transform};
use std::f64::consts::TAU;

/// The least cosine between the tilted normal and the geometric one.
pub const MIN_COS: f64 = 0.05;

#[derive(Clone, Debug, PartialEq)]
pub enum NormalKind {
    Bumps,
    Ripples { centre: DVec3 },
    Waves { centre: DVec3 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct NormalPattern {
    pub kind: NormalKind,
    pub amount: f64,
    pub scale: f64,
    pub place: Option<Transform>,
}

/// Central-difference step of the noise gradient, in noise cells.
const STEP: f64 = 1e-4;

impl NormalPattern {
    /// The slope vector g at object-space point `p`, in the object's axes.
    pub fn slope(&self, p: DVec3) -> DVec3 {
        match &self.place {
            Some(m) => {
                let g = self.pattern_slope(m.inverse_point(p));
                turned(g, m.normal(g))
            }
            None => self.pattern_slope(p),
        }
    }

    /// The slope at point `p` of the pattern's own space.
    fn pattern_slope(&self, p: DVec3) -> DVec3 {
        let q = p * self.scale;
        match &self.kind {
            NormalKind::Bumps => {
                let n = super::perlin::noise;
                let d = |e: DVec3| (n(q + e * STEP) - n(q - e * STEP)) / (2.0 * STEP);
                DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z))
            }
            NormalKind::Ripples { centre } | NormalKind::Waves { centre } => {
                let d = q - *centre;
                let r = d.length();
                if r < 1e-12 {
                    return DVec3::ZERO;
                }
                let mut g = (TAU * r).cos() * d / r;
                if matches!(self.kind, NormalKind::Waves { .. }) {
                    g /= 1.0 + r;
                }
                g
            }
        }
    }

    /// The shading normal `n` (unit, facing the ray) tilted at point `p`
    /// of an object that is not moved, kept in the hemisphere of the unit
    /// geometric normal `ng`.
    pub fn perturb(&self, n: DVec3, ng: DVec3, p: DVec3) -> DVec3 {
        self.perturb_mapped(n, ng, p, |g| g)
    }

    /// [`NormalPattern::perturb`] at object-space point `p` of an object
    /// whose normals `to_world` maps into the world (the shape's
    /// [`crate::shapes::Shape::normal_to_world`]).
    pub fn perturb_mapped(
        &self,
        n: DVec3,
        ng: DVec3,
        p: DVec3,
        to_world: impl Fn(DVec3) -> DVec3,
    ) -> DVec3 {
        if self.amount == 0.0 {
            return n;
        }
        let g = self.slope(p);
        let g = self.amount * turned(g, to_world(g));
        let tangent = g - g.dot(n) * n;
        let m = (n - tangent).normalize_or(n);
        let c = m.dot(ng);
        if c >= MIN_COS {
            return m;
        }
        // Too low: keep its tangent direction w, at exactly MIN_COS above
        // the surface (straight up when it has none: m = −ng).
        let w = (m - c * ng).normalize_or_zero();
        if w == DVec3::ZERO {
            return ng;
        }
        MIN_COS * ng + (1.0 - MIN_COS * MIN_COS).sqrt() * w
    }
}

/// Slope `g` turned to the direction `mapped` (g mapped as a normal is),
/// keeping g's length. An identity map returns g bit for bit.
fn turned(g: DVec3, mapped: DVec3) -> DVec3 {
    if mapped == g {
        return g;
    }
    let len = mapped.length();
    if len > 0.0 && len.is_finite() {
        mapped * (g.length() / len)
    } else {
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bumps(amount: f64) -> NormalPattern {
        NormalPattern {
            kind: NormalKind::Bumps,
            amount,
            scale: 3.0,
            place: None,
        }
    }

    #[test]
    fn bumps_vary_stay_above_and_average_to_the_plane_normal() {
        let b = bumps(0.6);
        let up = DVec3::Y;
        let mut sum = DVec3::ZERO;
        let mut min_dot: f64 = 1.0;
        let k = 120;
        for i in 0..k {
            for j in 0..k {
                let p = DVec3::new(i as f64 * 0.071, 0.0, j as f64 * 0.067);
                let n = b.perturb(up, up, p);
                assert!((n.length() - 1.0).abs() < 1e-12);
                min_dot = min_dot.min(n.dot(up));
                sum += n;
            }
        }
        let mean = sum / (k * k) as f64;
        assert!(min_dot >= MIN_COS - 1e-9, "below the surface: {min_dot}");
        assert!(min_dot < 0.99, "hardly tilted: {min_dot}");
        let m = mean.normalize();
        assert!(m.dot(up) > 0.999, "mean normal {mean}");
    }

    /// The pattern's own `rotate` turns its slopes with it: the placed
    /// pattern's slope at p is the unplaced one's at R⁻¹p, turned by R;
    /// and a non-uniform `to_world` turns the direction as a normal but
    /// keeps the length.
    #[test]
    fn placed_slopes_turn_with_the_pattern() {
        let unplaced = NormalPattern {
            kind: NormalKind::Waves {
                centre: DVec3::new(0.2, -0.1, 0.4),
            },
            amount: 1.0,
            scale: 2.0,
            place: None,
        };
        let r = Transform::rotate(DVec3::new(1.0, 2.0, -0.5), 70.0).unwrap();
        let placed = NormalPattern {
            place: Some(r),
            ..unplaced.clone()
        };
        for i in 0..50 {
            let p = DVec3::new(0.3 * i as f64, 1.0 - 0.07 * i as f64, (i as f64).sin());
            let want = r.vector(unplaced.slope(r.inverse_point(p)));
            let got = placed.slope(p);
            assert!(
                (got - want).length() < 1e-12 * (1.0 + want.length()),
                "{got} vs {want}"
            );
        }
        let stretch = Transform::scale(DVec3::new(4.0, 1.0, 1.0)).unwrap();
        let n = unplaced.perturb_mapped(DVec3::Y, DVec3::Y, DVec3::new(0.7, 0.0, 0.1), |g| {
            stretch.normal(g)
        });
        let g = unplaced.slope(DVec3::new(0.7, 0.0, 0.1));
        let mapped = stretch.normal(g).normalize() * g.length();
        let want = (DVec3::Y - (mapped - mapped.y * DVec3::Y)).normalize();
        assert!((n - want).length() < 1e-12, "{n} vs {want}");
    }

    #[test]
    fn zero_amount_is_the_same_normal_bit_for_bit() {
        let n = DVec3::new(0.3, 0.8, 0.1).normalize();
        assert_eq!(bumps(0.0).perturb(n, n, DVec3::new(0.2, 0.4, 0.9)), n);
    }

    #[test]
    fn a_huge_tilt_stays_in_the_geometric_hemisphere() {
        let b = bumps(500.0);
        for i in 0..200 {
            let p = DVec3::new(i as f64 * 0.13, 0.0, 0.3);
            let n = b.perturb(DVec3::Y, DVec3::Y, p);
            assert!(n.dot(DVec3::Y) >= MIN_COS - 1e-9, "{n}");
        }
    }

    #[test]
    fn ripples_tilt_radially_and_vanish_on_crests() {
        let r = NormalPattern {
            kind: NormalKind::Ripples {
                centre: DVec3::ZERO,
            },
            amount: 0.5,
            scale: 1.0,
            place: None,
        };
        // At r = 1 (cos 2π = 1) the slope points away from the centre: the
        // normal leans back towards it.
        let n = r.perturb(DVec3::Y, DVec3::Y, DVec3::new(1.0, 0.0, 0.0));
        assert!(n.x < -0.4 && n.z.abs() < 1e-12, "{n}");
        // At r = 1/4 (cos π/2 = 0) it is flat.
        let n = r.perturb(DVec3::Y, DVec3::Y, DVec3::new(0.0, 0.0, 0.25));
        assert!((n - DVec3::Y).length() < 1e-12, "{n}");
        // Waves are the same, damped by 1 + r.
        let w = NormalPattern {
            kind: NormalKind::Waves {
                centre: DVec3::ZERO,
            },
            ..r.clone()
        };
        let p = DVec3::new(3.0, 0.0, 0.0);
        assert!((w.slope(p) * 4.0 - r.slope(p)).length() < 1e-12);
    }

    /// Bumps: the slope is the gradient of the noise at q = scale·p (a
    /// central difference with another step agrees), and a scaled
    /// pattern's slope at p is the unscaled one's at scale·p (the slope
    /// itself is not multiplied: bumps keep their steepness).
    #[test]
    fn bumps_are_the_noise_gradient_at_the_scaled_point() {
        let n = super::super::perlin::noise;
        let h = 1e-6;
        let one = NormalPattern {
            scale: 1.0,
            ..bumps(1.0)
        };
        let three = bumps(1.0);
        for i in 0..40 {
            let p = DVec3::new(0.173 * i as f64, 0.5 - 0.061 * i as f64, (i as f64).cos());
            let q = p * 3.0;
            let d = |e: DVec3| (n(q + e * h) - n(q - e * h)) / (2.0 * h);
            let want = DVec3::new(d(DVec3::X), d(DVec3::Y), d(DVec3::Z));
            let got = three.slope(p);
            assert!(
                (got - want).length() < 1e-6 * (1.0 + want.length()),
                "{got} vs {want}"
            );
            assert_eq!(got, one.slope(q));
        }
    }

    /// Ripples: g = cos(2π r)·d/r with d = q − c; waves: that over 1 + r.
    #[test]
    fn ripples_and_waves_follow_their_formulas_around_an_off_origin_centre() {
        let centre = DVec3::new(0.4, -0.3, 0.2);
        let ripples = NormalPattern {
            kind: NormalKind::Ripples { centre },
            amount: 1.0,
            scale: 2.0,
            place: None,
        };
        let waves = NormalPattern {
            kind: NormalKind::Waves { centre },
            ..ripples.clone()
        };
        for i in 0..60 {
            let p = DVec3::new(
                0.11 * i as f64 - 2.0,
                (0.3 * i as f64).sin(),
                0.07 * i as f64,
            );
            let d = p * 2.0 - centre;
            let r = d.length();
            let want = (TAU * r).cos() * d / r;
            let got = ripples.slope(p);
            assert!((got - want).length() < 1e-12, "{got} vs {want}");
            let got = waves.slope(p);
            assert!((got - want / (1.0 + r)).length() < 1e-12, "{got} vs {want}");
        }
        // At the centre the slope is 0, not NaN.
        assert_eq!(ripples.slope(centre / 2.0), DVec3::ZERO);
    }

    /// n′ = normalize(n − a·(g − (g·n)n)) while it stays MIN_COS or more
    /// above the surface; below that it keeps its tangent direction at
    /// exactly MIN_COS, unit length.
    #[test]
    fn the_tilted_normal_is_the_documented_one_or_clamped_to_min_cos() {
        let (mut free, mut clamped) = (0, 0);
        for amount in [0.3, 1.5, 60.0] {
            let r = NormalPattern {
                kind: NormalKind::Ripples {
                    centre: DVec3::new(0.1, 0.2, -0.3),
                },
                amount,
                scale: 1.3,
                place: None,
            };
            for i in 0..80 {
                let p = DVec3::new(0.05 * i as f64, 0.3, (0.2 * i as f64).sin());
                // A tilted surface, so that g has a part along n.
                let n = DVec3::new(0.2, 1.0, -0.3).normalize();
                let ng = DVec3::new(0.1, 1.0, -0.2).normalize();
                let g = amount * r.slope(p);
                let m = (n - (g - g.dot(n) * n)).normalize();
                let got = r.perturb(n, ng, p);
                assert!((got.length() - 1.0).abs() < 1e-12, "{got}");
                if m.dot(ng) >= MIN_COS {
                    assert!((got - m).length() < 1e-12, "{got} vs {m}");
                    free += 1;
                } else {
                    assert!((got.dot(ng) - MIN_COS).abs() < 1e-12, "{got}");
                    let (wg, wm) = (got - got.dot(ng) * ng, m - m.dot(ng) * ng);
                    assert!(
                        (wg.normalize() - wm.normalize()).length() < 1e-9,
                        "{got} vs {m}"
                    );
                    clamped += 1;
                }
            }
        }
        assert!(free > 20 && clamped > 20, "{free} {clamped}");
    }

    /// A shading normal exactly against the geometric one with no slope to
    /// tilt it (a ripple's centre) has no tangent direction: straight up.
    #[test]
    fn a_normal_facing_straight_down_without_tilt_becomes_the_geometric_one() {
        let r = NormalPattern {
            kind: NormalKind::Ripples {
                centre: DVec3::ZERO,
            },
            amount: 1.0,
            scale: 1.0,
            place: None,
        };
        assert_eq!(r.perturb(-DVec3::Y, DVec3::Y, DVec3::ZERO), DVec3::Y);
    }

    /// A map that sends slopes to 0 or to infinity (degenerate) keeps the
    /// slope as it was instead of making NaN.
    #[test]
    fn a_degenerate_map_keeps_the_slope() {
        let b = bumps(0.8);
        for i in 0..20 {
            let p = DVec3::new(0.13 * i as f64, 0.0, 0.41);
            let want = b.perturb(DVec3::Y, DVec3::Y, p);
            let zero = b.perturb_mapped(DVec3::Y, DVec3::Y, p, |_| DVec3::ZERO);
            let inf = b.perturb_mapped(DVec3::Y, DVec3::Y, p, |g| g * f64::INFINITY);
            assert_eq!(zero, want);
            assert_eq!(inf, want);
        }
    }
}
