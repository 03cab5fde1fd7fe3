//! Dielectrics (glass, water): Fresnel reflection and refraction, total
//! internal reflection, and Beer absorption along the path inside.
//!
//! ```text
//! material glass { refract { ior 1.5  filter rgb(0.9, 1, 0.95) }  specular 1  shininess 300 }
//! material water { refract { ior 1.33  outside_ior 1.5 } }   // water inside a glass
//! ```
//! For a ray d meeting a surface with ior η_in inside and η_out outside
//! (when the ray leaves, both iors, both filters and n swap): η = η_in/η_out,
//! cos_i = −d·n, cos²_t = 1 − (1 − cos²_i)/η²; below 0 is total internal
//! reflection. Fresnel (unpolarised, exact):
//! r∥ = (η cos_i − cos_t)/(η cos_i + cos_t), r⊥ = (cos_i − η cos_t)/(cos_i + η cos_t),
//! k_r = (r∥² + r⊥²)/2, k_t = 1 − k_r, t = d/η − (cos_t − cos_i/η) n.
//! Result: k_r · f_out^s_r ⊙ L(reflected) + (k_t/η²) · f_in^s_t ⊙ L(refracted),
//! s the distance each ray travels to its next hit (Beer's law, filter^s).

use crate::geometry::{DVec3, renormalize};
use crate::scene::{Colour, Dielectric, Filter};

/// The two sides of the surface as this ray meets them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface {
    /// η = η_(side entered) / η_(side the ray is on).
    pub eta: f64,
    /// Filter of the medium the ray is in (its reflection stays there).
    pub filter_here: Filter,
    /// Filter of the medium a refracted ray enters.
    pub filter_there: Filter,
}

impl Interface {
    /// `entering`: the ray meets the outward side.
    pub fn new(d: &Dielectric, entering: bool) -> Interface {
        if entering {
            Interface {
                eta: d.ior / d.outside_ior,
                filter_here: d.outside_filter,
                filter_there: d.filter,
            }
        } else {
            Interface {
                eta: d.outside_ior / d.ior,
                filter_here: d.filter,
                filter_there: d.outside_filter,
            }
        }
    }
}

/// What happens at the surface: reflectance and, unless there is total
/// internal reflection, the refracted direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    pub kr: f64,
    pub refracted: Option<DVec3>,
}

/// Fresnel and Snell for the unit direction `d` at the facing unit normal
/// `n` (n·d ≤ 0), relative index `eta`.
pub fn split(d: DVec3, n: DVec3, eta: f64) -> Split {
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let cos2_t = 1.0 - (1.0 - cos_i * cos_i) / (eta * eta);
    // `<=`: at exactly cos²_t = 0 (the critical angle, or an index-matched
    // interface met at grazing) all is reflected; the Fresnel terms
    // below would be 0/0 in the grazing case.
    if cos2_t <= 0.0 {
        return Split {
            kr: 1.0,
            refracted: None,
        };
    }
    let cos_t = cos2_t.sqrt();
    let r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let kr = 0.5 * (r_par * r_par + r_perp * r_perp);
    let t = d / eta - (cos_t - cos_i / eta) * n;
    Split {
        kr,
        // Unit but for rounding: normalised again without a square root.
        refracted: Some(renormalize(t)),
    }
}

/// Beer's law: what is left of light after `distance` in a medium of
/// `filter` per unit length, f^s = e^(s·ln f) per channel. An unbounded
/// path (the ray escaped) keeps only the channels that are fully clear;
/// no distance (s = 0) or a clear channel (ln f = 0) keeps everything, as
/// `powf` does (the product would be NaN there).
pub fn absorb(filter: &Filter, distance: f64) -> Colour {
    let channel = |ln: f64| {
        if ln == 0.0 || distance == 0.0 {
            1.0
        } else {
            (ln * distance).exp()
        }
    };
    let ln = filter.ln();
    Colour::new(channel(ln.x), channel(ln.y), channel(ln.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_is_four_percent_at_normal_incidence_for_1_5() {
        let s = split(-DVec3::Y, DVec3::Y, 1.5);
        assert!((s.kr - 0.04).abs() < 1e-12, "{}", s.kr);
        assert_eq!(s.refracted, Some(-DVec3::Y));
        // The same leaving the glass.
        let s = split(-DVec3::Y, DVec3::Y, 1.0 / 1.5);
        assert!((s.kr - 0.04).abs() < 1e-12);
    }

    #[test]
    fn total_internal_reflection_past_the_critical_angle() {
        let critical = (1.0f64 / 1.5).asin();
        let at = |a: f64| split(DVec3::new(a.sin(), -a.cos(), 0.0), DVec3::Y, 1.0 / 1.5);
        let below = at(critical - 0.01);
        assert!(below.refracted.is_some() && below.kr < 1.0);
        let past = at(critical + 0.01);
        assert_eq!(past.refracted, None);
        assert_eq!(past.kr, 1.0);
        // Just below it, almost everything is reflected already.
        assert!(at(critical - 1e-6).kr > 0.9);
    }

    #[test]
    fn snell_holds_for_the_refracted_direction() {
        let a: f64 = 0.6;
        let s = split(DVec3::new(a.sin(), -a.cos(), 0.0), DVec3::Y, 1.33);
        let t = s.refracted.unwrap();
        assert!((a.sin() - 1.33 * t.x).abs() < 1e-12, "sin θi = η sin θt");
        assert!(t.y < 0.0);
        // Reflectance rises towards grazing.
        let g = split(
            DVec3::new(0.999f64.sin(), -0.999f64.cos(), 0.0),
            DVec3::Y,
            1.33,
        );
        assert!(g.kr > s.kr);
    }

    #[test]
    fn beer_multiplies_by_filter_to_the_distance() {
        let f = Filter::new(Colour::new(0.5, 0.25, 1.0));
        let a = absorb(&f, 2.0);
        assert!((a - Colour::new(0.25, 0.0625, 1.0)).abs().max_element() < 1e-15);
        // Two halves make the whole.
        assert!((absorb(&f, 1.0) * absorb(&f, 1.0) - a).abs().max_element() < 1e-15);
        let gone = absorb(&f, f64::INFINITY);
        assert_eq!(gone, Colour::new(0.0, 0.0, 1.0));
        // No distance keeps everything, even in an opaque channel (0^0 = 1).
        let opaque = Filter::new(Colour::new(0.0, 0.5, 1.0));
        assert_eq!(absorb(&opaque, 0.0), Colour::ONE);
        assert_eq!(absorb(&opaque, 0.5).x, 0.0);
        assert_eq!(absorb(&Filter::CLEAR, f64::INFINITY), Colour::ONE);
    }

    #[test]
    fn beer_agrees_with_powf_to_a_few_ulps() {
        // e^(s·ln f) against f^s over filters and distances a scene meets.
        let mut worst = 0.0f64;
        for i in 1..=50 {
            let f = i as f64 / 50.0;
            let filter = Filter::new(Colour::new(f, f.sqrt(), f * f));
            for k in 0..200 {
                let s = k as f64 * 0.07;
                let got = absorb(&filter, s);
                for (g, c) in [(got.x, f), (got.y, f.sqrt()), (got.z, f * f)] {
                    let want = c.powf(s);
                    worst =
                        worst.max((g - want).abs() / (want * f64::EPSILON).max(f64::MIN_POSITIVE));
                }
            }
        }
        assert!(worst < 64.0, "{worst} ulp");
    }

    #[test]
    fn sides_swap_on_the_way_out() {
        let d = Dielectric {
            ior: 1.5,
            filter: Filter::new(Colour::splat(0.5)),
            outside_ior: 1.33,
            outside_filter: Filter::new(Colour::splat(0.9)),
        };
        let i = Interface::new(&d, true);
        let o = Interface::new(&d, false);
        assert!((i.eta * o.eta - 1.0).abs() < 1e-15);
        assert_eq!(i.filter_there, o.filter_here);
        assert_eq!(i.filter_here, Filter::new(Colour::splat(0.9)));
    }
}

/// Fresnel against its textbook angle form, independent of `split`'s
/// cosine form (mutation testing found that normal incidence alone, where
/// η·cos_i = η/cos_i, cannot tell a wrong r∥ from the right one).
#[cfg(test)]
mod fresnel_oracles {
    use super::*;

    /// The ray at angle `a` from the normal +Y, coming down.
    fn at(a: f64, eta: f64) -> Split {
        split(DVec3::new(a.sin(), -a.cos(), 0.0), DVec3::Y, eta)
    }

    /// R_s = (sin(θi − θt) / sin(θi + θt))², R_p = (tan(θi − θt) / tan(θi + θt))²,
    /// with sin θi = η sin θt; unpolarised light reflects their mean.
    fn textbook(a: f64, eta: f64) -> f64 {
        let t = (a.sin() / eta).asin();
        let rs = ((a - t).sin() / (a + t).sin()).powi(2);
        let rp = ((a - t).tan() / (a + t).tan()).powi(2);
        0.5 * (rs + rp)
    }

    #[test]
    fn reflectance_follows_the_angle_form_at_every_angle() {
        for eta in [1.5, 1.33, 2.4, 1.0 / 1.5] {
            for i in 1..60 {
                let a = i as f64 * 0.025;
                if eta < 1.0 && a.sin() >= eta {
                    continue; // past the critical angle: tested elsewhere
                }
                let (got, want) = (at(a, eta).kr, textbook(a, eta));
                assert!((got - want).abs() < 1e-12, "η {eta} θ {a}: {got} vs {want}");
            }
        }
        // A value to check by hand: glass at 45°, R_s 0.0920, R_p 0.0085.
        assert!((at(std::f64::consts::FRAC_PI_4, 1.5).kr - 0.05023).abs() < 1e-4);
    }

    #[test]
    fn at_brewsters_angle_only_the_perpendicular_part_reflects() {
        let eta = 1.5f64;
        let b = eta.atan();
        let t = (b.sin() / eta).asin();
        let rs = ((b - t).sin() / (b + t).sin()).powi(2);
        assert!((at(b, eta).kr - 0.5 * rs).abs() < 1e-12);
    }

    #[test]
    fn reflectance_is_the_same_from_either_side() {
        // Stokes: entering at θi and leaving at the matching θt reflect alike.
        for a in [0.1f64, 0.4, 0.7, 1.0, 1.3] {
            let eta = 1.5f64;
            let t = (a.sin() / eta).asin();
            let (into, out) = (at(a, eta).kr, at(t, 1.0 / eta).kr);
            assert!((into - out).abs() < 1e-12, "θ {a}: {into} vs {out}");
        }
    }

    #[test]
    fn an_index_matched_interface_is_invisible_up_to_grazing() {
        // η = 1 (glass of ior 1, or two equal media): nothing reflects and
        // the ray goes straight on, at every angle.
        for i in 0..63 {
            let a = i as f64 * 0.025;
            let s = at(a, 1.0);
            assert!(s.kr.abs() < 1e-12, "θ {a}: {}", s.kr);
            let d = DVec3::new(a.sin(), -a.cos(), 0.0);
            assert!((s.refracted.unwrap() - d).length() < 1e-12);
        }
        // Exactly grazing (cos θi = 0, or a shading normal turned a hair
        // past it and clamped): a number, not 0/0. Only reflection is left
        // there, and the mirror direction of a grazing ray is the ray.
        for d in [DVec3::X, DVec3::new(1.0, 1e-9, 0.0).normalize()] {
            let s = split(d, DVec3::Y, 1.0);
            assert!(s.kr.is_finite() && (0.0..=1.0).contains(&s.kr), "{s:?}");
        }
    }
}
