//! Glossy reflection: the mirror ray replaced by one drawn with density
//! ∝ cos^e of its angle to the mirror direction (φ = 2πa,
//! cos θ = (1 − b)^(1/(e+1)) from a square sample (a, b)). A direction that
//! falls below the surface is reflected back above it. The estimate is
//! k_r c_r ⊙ L(sample), one ray per pixel sample; large e approaches the
//! mirror.
//!
//! ```text
//! material brushed { colour #b0b0b0  mirror 0.8  mirror_colour #ffd080  glossy 500 }
//! ```

use super::mirror::reflect;
use crate::geometry::DVec3;
use crate::render::sampler::{about, cos_power_lobe};

/// A glossy direction for incoming `d` at facing normal `n`, exponent `e`,
/// from the square sample `u`.
pub fn direction(d: DVec3, n: DVec3, e: f64, u: (f64, f64)) -> DVec3 {
    let w = reflect(d, n);
    let out = about(w, cos_power_lobe(u, e));
    if out.dot(n) < 0.0 {
        reflect(out, n)
    } else {
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_stay_above_the_surface_and_cluster_with_e() {
        let n = DVec3::Y;
        let d = DVec3::new(1.0, -0.2, 0.0).normalize();
        let w = reflect(d, n);
        let spread = |e: f64| {
            let mut sum = 0.0;
            for i in 0..40 {
                for j in 0..40 {
                    let o = direction(d, n, e, ((i as f64 + 0.5) / 40.0, (j as f64 + 0.5) / 40.0));
                    assert!(o.dot(n) >= 0.0);
                    assert!((o.length() - 1.0).abs() < 1e-9);
                    sum += o.dot(w);
                }
            }
            sum / 1600.0
        };
        let (rough, sharp) = (spread(5.0), spread(5000.0));
        assert!(sharp > 0.999 && rough < sharp, "{rough} {sharp}");
    }
}
