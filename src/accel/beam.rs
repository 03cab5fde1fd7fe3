//! Beam culling for the camera rays of one pixel: with many samples a
//! pixel (antialiasing, depth of field) its rays form a thin beam, and
//! only the few objects whose boxes may meet that beam can be hit by any
//! of them. The rays are tested against those alone
//! ([`super::World::beam_candidates`]) instead of walking the tree once
//! per ray.
//!
//! The camera describes the rays as a [`RayFamily`]: from a lens square
//! through a rectangle at some depth. In the camera's frame a ray's
//! sideways coordinates are linear in its depth z, so their greatest value
//! over the family is convex in z (the lens term is a·|1 − z/depth|) and
//! lies under its chord from the lens (z = 0) to the depth D of the
//! farthest corner of the objects' bounding box. The four chords, one per
//! side, are four planes; with z ≥ 0 they bound every point at which a ray
//! can meet a bounded object:
//!
//! ```text
//! x_r(z) ≤ hi_r(0) + z·(hi_r(D) − hi_r(0))/D      (and lo, and u)
//! reject a box when, for one plane (n, d), min over its corners n·x − d > margin
//! ```
//!
//! Beyond D the rays leave the planes, but no bounded object lies there;
//! unbounded ones (planes) are always candidates. Like the area light's
//! shaft (accel/shaft.rs) this decides nothing a ray would not: the
//! margin covers the rounding of the rays the camera makes.

use crate::geometry::{Aabb, DVec3};

/// Relative slack on each plane test, far above the rounding of the rays'
/// coordinates (~10⁻¹⁵ of them).
const MARGIN: f64 = 1e-9;

/// The camera rays of one pixel, as the camera makes them: each starts
/// at a point of the lens square (half-width `lens`, 0 for a pinhole)
/// about `origin` in the plane of `right` and `up`, and passes at depth
/// `depth` along `forward` through the rectangle `lo`..`hi` (in `right`
/// and `up` coordinates about `origin`). The three directions are an
/// orthonormal frame.
#[derive(Clone, Copy, Debug)]
pub struct RayFamily {
    pub origin: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub forward: DVec3,
    pub lens: f64,
    pub depth: f64,
    pub lo: [f64; 2],
    pub hi: [f64; 2],
}

impl RayFamily {
    /// The (right, up) extent of the rays at depth z ≥ 0: a lens point s
    /// and a target point p are at s·(1 − z/depth) + p·z/depth there.
    fn extent(&self, z: f64) -> ([f64; 2], [f64; 2]) {
        let (w, blur) = (z / self.depth, self.lens * (1.0 - z / self.depth).abs());
        (
            [self.lo[0] * w - blur, self.lo[1] * w - blur],
            [self.hi[0] * w + blur, self.hi[1] * w + blur],
        )
    }
}

/// The region a pixel's camera rays pass through before their depth
/// reaches the far side of the bounded objects.
#[derive(Clone, Copy, Debug)]
pub struct Beam {
    /// (n, d): outside is n·x > d. Four sides, then the near plane z ≥ 0.
    planes: [(DVec3, f64); 5],
    margins: [f64; 5],
    bounds: Aabb,
}

impl Beam {
    /// The beam of the rays of `f` up to the far side of `objects`, a
    /// finite non-empty box. `None` when `f` is degenerate (the rays then
    /// go through the tree); an empty beam, meeting nothing, when every
    /// object lies behind the lens.
    pub fn new(f: &RayFamily, objects: &Aabb) -> Option<Beam> {
        let (e, l) = (f.origin, f.forward);
        let corners = objects.corners().into_iter();
        let far = corners
            .clone()
            .map(|c| (c - e).dot(l))
            .fold(f64::NEG_INFINITY, f64::max);
        let scale = corners
            .map(|c| c.abs().max_element())
            .fold(e.abs().max_element(), f64::max)
            .max(f.lens)
            .max(f64::MIN_POSITIVE);
        let slack = MARGIN * scale;
        let sane = f.depth > 0.0 && f.lens >= 0.0 && f.lo[0] <= f.hi[0] && f.lo[1] <= f.hi[1];
        if !sane || !far.is_finite() || !scale.is_finite() {
            return None;
        }
        if far <= slack {
            return Some(Beam {
                planes: [(DVec3::ZERO, 0.0); 5],
                margins: [0.0; 5],
                bounds: Aabb::EMPTY,
            });
        }
        let ends = [f.extent(0.0), f.extent(far)];
        // x·axis ≤ edge(z), the edge linear from its value at depth 0 to
        // its value at `far` (a chord of the convex |1 − z/depth|).
        let side = |axis: DVec3, at_near: f64, at_far: f64| {
            let k = (at_far - at_near) / far;
            let n = axis - k * l;
            (n, at_near + n.dot(e))
        };
        let (r, u) = (f.right, f.up);
        let planes = [
            side(r, ends[0].1[0], ends[1].1[0]),
            side(-r, -ends[0].0[0], -ends[1].0[0]),
            side(u, ends[0].1[1], ends[1].1[1]),
            side(-u, -ends[0].0[1], -ends[1].0[1]),
            (-l, -l.dot(e)),
        ];
        if planes.iter().any(|(n, d)| !n.is_finite() || !d.is_finite()) {
            return None;
        }
        let margins = planes.map(|(n, _)| super::shaft::margin(n, slack));
        let mut bounds = Aabb::EMPTY;
        for ((lo, hi), depth) in ends.into_iter().zip([0.0, far]) {
            for (a, b) in [
                (lo[0], lo[1]),
                (lo[0], hi[1]),
                (hi[0], lo[1]),
                (hi[0], hi[1]),
            ] {
                bounds = bounds.grow(e + a * r + b * u + depth * l);
            }
        }
        Some(Beam {
            planes,
            margins,
            bounds: bounds.padded(slack * 4.0),
        })
    }

    /// The beam's bounding box (padded by the margin); empty when no
    /// bounded object can be met.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Whether `b` may meet the beam: false only when it lies wholly
    /// outside one of its planes (or the beam is empty). The planes alone
    /// decide: the beam's box only narrows the tree's query.
    pub fn may_meet(&self, b: &Aabb) -> bool {
        if b.is_empty() || self.bounds.is_empty() {
            return false;
        }
        super::shaft::within_planes(&self.planes, &self.margins, b)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::Ray;

    /// A camera at `origin` looking along `forward`, its lens square of
    /// half-width `lens`, its pixel's rays through [0.1, 0.13] × [−0.2,
    /// −0.17] (right, up) at depth `depth`.
    pub(in crate::accel) fn family(
        origin: DVec3,
        forward: DVec3,
        lens: f64,
        depth: f64,
    ) -> RayFamily {
        let forward = forward.normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        RayFamily {
            origin,
            right,
            up,
            forward,
            lens,
            depth,
            lo: [0.1 * depth, -0.2 * depth],
            hi: [0.13 * depth, -0.17 * depth],
        }
    }

    /// A ray of `f`: lens point (a, b) ∈ [−1, 1]² of the square, target
    /// (x, y) ∈ [0, 1]² of the rectangle, made as the camera makes them.
    pub(in crate::accel) fn ray_of(f: &RayFamily, (a, b): (f64, f64), (x, y): (f64, f64)) -> Ray {
        let start = f.origin + f.lens * (a * f.right + b * f.up);
        let (tx, ty) = (
            f.lo[0] + x * (f.hi[0] - f.lo[0]),
            f.lo[1] + y * (f.hi[1] - f.lo[1]),
        );
        let target = f.origin + f.depth * f.forward + tx * f.right + ty * f.up;
        Ray::new(start, (target - start).normalize())
    }

    pub(crate) fn rng(mut s: u64) -> impl FnMut() -> f64 {
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn every_box_a_ray_meets_meets_the_beam_and_most_others_do_not() {
        let _watchdog = crate::watchdog::start();
        let mut r = rng(0x51ed_2701);
        let objects = Aabb::new(DVec3::splat(-6.0), DVec3::splat(6.0));
        let origin = DVec3::new(1.0, 2.0, 9.0);
        let forward = DVec3::new(-0.1, -0.25, -1.0);
        // A pinhole; a lens focused short of the objects, inside them,
        // and beyond them.
        for (lens, depth) in [(0.0, 1.0), (0.2, 3.0), (0.3, 9.0), (0.1, 40.0)] {
            let f = family(origin, forward, lens, depth);
            let beam = Beam::new(&f, &objects).unwrap();
            let rays: Vec<Ray> = (0..400)
                .map(|k| {
                    // The square's corners and edges, then inside.
                    let c = |v: f64| if k < 16 { (k % 2) as f64 } else { v };
                    let lens = (2.0 * c(r()) - 1.0, 2.0 * c(r()) - 1.0);
                    ray_of(&f, lens, (c(r()), c(r())))
                })
                .collect();
            let (mut met, mut missed, mut rejected) = (0, 0, 0);
            for _ in 0..3000 {
                let c = DVec3::new(r(), r(), r()) * 12.0 - 6.0;
                let b = Aabb::new(c, c + DVec3::new(r(), r(), r()) * 0.4);
                if rays
                    .iter()
                    .any(|ray| b.clip(ray, 0.0, f64::INFINITY).is_some())
                {
                    met += 1;
                    assert!(beam.may_meet(&b), "lens {lens} depth {depth}: {b:?}");
                } else {
                    missed += 1;
                    rejected += !beam.may_meet(&b) as u32;
                }
            }
            assert!(
                met > 5,
                "lens {lens} depth {depth}: only {met} boxes on the way"
            );
            // The chord bound is loose near the lens for a wide aperture,
            // but most boxes off the way must still go.
            assert!(
                rejected as f64 > 0.8 * missed as f64,
                "lens {lens} depth {depth}: {rejected} of {missed} rejected"
            );
        }
    }

    #[test]
    fn a_box_beside_the_beam_goes_and_one_touching_it_stays() {
        // A pinhole at the origin looking down −z; its rays pass x ∈
        // [0.1, 0.13]·z and y ∈ [−0.2, −0.17]·z at depth z: at depth 5,
        // x ∈ [0.5, 0.65].
        let f = family(DVec3::ZERO, -DVec3::Z, 0.0, 1.0);
        let objects = Aabb::new(DVec3::splat(-10.0), DVec3::splat(10.0));
        let beam = Beam::new(&f, &objects).unwrap();
        let at =
            |x0: f64, x1: f64| Aabb::new(DVec3::new(x0, -1.0, -5.01), DVec3::new(x1, -0.9, -4.99));
        assert!(beam.may_meet(&at(0.55, 0.6)));
        assert!(beam.may_meet(&at(0.65, 0.7)), "touching its right side");
        assert!(!beam.may_meet(&at(0.68, 0.8)), "beside its right side");
        assert!(!beam.may_meet(&at(0.3, 0.48)), "beside its left side");
        // Below (y < −1) and above (y > −0.85) at that depth.
        let y =
            |y0: f64, y1: f64| Aabb::new(DVec3::new(0.55, y0, -5.01), DVec3::new(0.6, y1, -4.99));
        assert!(!beam.may_meet(&y(-1.3, -1.05)));
        assert!(!beam.may_meet(&y(-0.8, -0.7)));
        assert!(beam.may_meet(&y(-0.9, -0.8)));
        // Behind the eye, on the rays' line extended backwards.
        assert!(!beam.may_meet(&Aabb::new(
            DVec3::new(-0.7, 0.8, 4.0),
            DVec3::new(-0.5, 1.1, 6.0)
        )));
        // An empty box meets nothing.
        assert!(!beam.may_meet(&Aabb::EMPTY));
    }

    #[test]
    fn a_lens_widens_the_beam_by_its_blur_and_no_more() {
        // A lens of half-width 0.2 focused at depth 5, looking down −z from
        // the origin; the objects reach depth 10, where a ray is
        // s·(1 − 2) + p·2: its blur is 0.2 (not 0.2·3), the rectangle's
        // x ∈ [0.5, 0.65] doubled to [1.0, 1.3]: x ∈ [0.8, 1.5] in all.
        let f = family(DVec3::ZERO, -DVec3::Z, 0.2, 5.0);
        let objects = Aabb::new(DVec3::new(-5.0, -5.0, -10.0), DVec3::new(5.0, 5.0, 0.0));
        let beam = Beam::new(&f, &objects).unwrap();
        let at =
            |x0: f64, x1: f64| Aabb::new(DVec3::new(x0, -2.0, -10.0), DVec3::new(x1, -1.8, -9.9));
        assert!(beam.may_meet(&at(1.45, 1.55)));
        assert!(!beam.may_meet(&at(1.55, 1.7)), "beyond the blur");
        assert!(beam.may_meet(&at(0.7, 0.85)));
        assert!(!beam.may_meet(&at(0.5, 0.75)), "short of the blur");
    }

    #[test]
    fn objects_wholly_behind_the_lens_make_an_empty_beam() {
        let f = family(DVec3::ZERO, -DVec3::Z, 0.1, 4.0);
        let behind = Aabb::new(DVec3::new(-1.0, -1.0, 1.0), DVec3::new(1.0, 1.0, 3.0));
        let beam = Beam::new(&f, &behind).unwrap();
        assert!(beam.bounds().is_empty());
        assert!(!beam.may_meet(&behind));
        // A degenerate family gives no beam at all.
        let mut bad = f;
        bad.depth = 0.0;
        assert!(Beam::new(&bad, &behind).is_none());
        bad = f;
        bad.lo[0] = bad.hi[0] + 1.0;
        assert!(Beam::new(&bad, &behind).is_none());
    }
}
