//! Shaft culling (Haines & Wallace, "Shaft culling for efficient
//! ray-cast radiosity", 1994) for an area light's grid of shadow rays.
//!
//! All the shadow rays from one shading point to the n × n points of a
//! flat light lie inside one pyramid: its apex is the point the rays start
//! from, its base the light's parallelogram pulled a little towards the
//! apex (every ray stops short of the light, [`BASE_PULL`] is less than
//! that). An object whose bounding box lies wholly outside the pyramid
//! cannot block any of those rays, so the rays need only be tested against
//! the few boxes that may meet it; when there are none, every ray of the
//! grid is known to be clear without casting one. That is exact: it
//! decides nothing a ray would not (the boxes bound the objects, and the
//! box test keeps any box within a rounding margin of the pyramid).
//!
//! ```text
//! pyramid  = hull(apex, apex + (c_k − apex)(1 − BASE_PULL), k = 0..3)
//! reject a box when, for one face plane (n, d) with n outward,
//!            min over the box's corners of n·x − d  >  margin
//! ```

use crate::geometry::{Aabb, DVec3};

/// How far the base is pulled from the light towards the apex, as a
/// fraction of the way. Shadow rays stop 10⁻⁴ of their length short of
/// the light (`SHADOW_EPSILON`), so their ends lie inside the pyramid, and
/// the light's own surface lies outside it.
pub const BASE_PULL: f64 = 1e-5;

/// Relative slack on each plane test, far above the rounding of the
/// points, the planes and the boxes (~10⁻¹⁵ of the coordinates).
const MARGIN: f64 = 1e-9;

/// The pyramid from one point to a parallelogram: five face planes with
/// outward normals, and its bounding box.
#[derive(Clone, Copy, Debug)]
pub struct Shaft {
    /// (n, d): outside is n·x > d.
    planes: [(DVec3, f64); 5],
    /// Per plane, the slack the box test allows.
    margins: [f64; 5],
    bounds: Aabb,
    vertices: [DVec3; 5],
}

impl Shaft {
    /// The pyramid from `apex` to the parallelogram with corners `corners`
    /// (in order around it), pulled by [`BASE_PULL`]. `None` when the apex
    /// lies in (or within rounding of) the parallelogram's plane, or the
    /// parallelogram has no area: the caller casts every ray then.
    pub fn new(apex: DVec3, corners: [DVec3; 4]) -> Option<Shaft> {
        let base = corners.map(|c| apex + (c - apex) * (1.0 - BASE_PULL));
        let scale = base
            .iter()
            .fold(apex.abs().max_element(), |m, c| {
                m.max(c.abs().max_element())
            })
            .max(f64::MIN_POSITIVE);
        let centre = (base[0] + base[1] + base[2] + base[3]) * 0.25;
        let inside = (apex + centre * 4.0) * 0.2;
        let mut planes = [(DVec3::ZERO, 0.0); 5];
        let mut margins = [0.0; 5];
        // The normals are left at the length the cross product gives them
        // (as `towards_box` leaves its own): each plane's margin and the
        // apex's clearance grow with |n|₁ instead, and no square root or
        // division waits at the head of every face (a shaft is made per
        // shading point).
        let mut face = |k: usize, a: DVec3, b: DVec3, c: DVec3| -> Option<()> {
            let mut n = (b - a).cross(c - a);
            let size = n.x.abs() + n.y.abs() + n.z.abs();
            if size == 0.0 || !size.is_finite() {
                return None;
            }
            let mut d = n.dot(a);
            // The apex must lie clearly inside every side and off the base.
            let depth = d - n.dot(inside);
            if depth.abs() <= 1e-6 * scale * size {
                return None;
            }
            if depth < 0.0 {
                n = -n;
                d = -d;
            }
            planes[k] = (n, d);
            margins[k] = margin(n, MARGIN * scale);
            Some(())
        };
        for k in 0..4 {
            face(k, apex, base[k], base[(k + 1) % 4])?;
        }
        face(4, base[0], base[1], base[2])?;
        let mut bounds = Aabb::new(apex, base[0]);
        for c in &base[1..] {
            bounds = bounds.grow(*c);
        }
        bounds = bounds.padded(MARGIN * scale);
        Some(Shaft {
            planes,
            margins,
            bounds,
            vertices: [apex, base[0], base[1], base[2], base[3]],
        })
    }

    /// A pyramid from `apex` (a point light) that holds the box `points`
    /// (the shading points of a pixel's samples), so every shadow ray from
    /// one of them to the light lies inside it. Its sides pass through the
    /// least and greatest slopes of the box's corners seen from the apex
    /// (a ratio of linear functions is greatest over a box at a corner),
    /// its base a little beyond the farthest corner. `None` when the apex
    /// is not clearly outside the box on one side.
    pub fn towards_box(apex: DVec3, points: &Aabb) -> Option<Shaft> {
        if points.is_empty() || !points.is_finite() {
            return None;
        }
        let l = (points.centre() - apex).try_normalize()?;
        let (r, u) = l.any_orthonormal_pair();
        let (mut lo, mut hi, mut depth) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2], 0.0f64);
        for corner in points.corners() {
            let c = corner - apex;
            let z = c.dot(l);
            if z.is_nan() || z <= 1e-6 * c.length() {
                return None;
            }
            let slope = [c.dot(r) / z, c.dot(u) / z];
            for a in 0..2 {
                lo[a] = lo[a].min(slope[a]);
                hi[a] = hi[a].max(slope[a]);
            }
            depth = depth.max(z);
        }
        // The side through the apex where x·axis = k·z, outside beyond it,
        // and the base a little past the farthest corner. (Built here
        // rather than by `new`: this runs once a pixel, and the planes
        // come straight from the slopes.)
        let side = |axis: DVec3, k: f64| {
            let n = axis - k * l;
            (n, n.dot(apex))
        };
        let far = depth * 1.001;
        let planes = [
            side(r, hi[0]),
            side(-r, -lo[0]),
            side(u, hi[1]),
            side(-u, -lo[1]),
            (l, l.dot(apex) + far),
        ];
        let at = |a: f64, b: f64| apex + far * (l + a * r + b * u);
        let vertices = [
            apex,
            at(lo[0], lo[1]),
            at(hi[0], lo[1]),
            at(hi[0], hi[1]),
            at(lo[0], hi[1]),
        ];
        let scale = vertices
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs().max_element()))
            .max(f64::MIN_POSITIVE);
        // (All finite: every corner lies ahead of the apex by 10⁻⁶ of its
        // distance at least, so no slope is infinite.)
        let margins = planes.map(|(n, _)| margin(n, MARGIN * scale));
        let bounds = vertices[1..]
            .iter()
            .fold(Aabb::new(apex, apex), |b, v| b.grow(*v));
        Some(Shaft {
            planes,
            margins,
            bounds: bounds.padded(MARGIN * scale),
            vertices,
        })
    }

    /// The pyramid's apex and the four corners of its base.
    pub fn vertices(&self) -> [DVec3; 5] {
        self.vertices
    }

    /// The pyramid's bounding box (padded by the margin).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Whether `b` may meet the pyramid: false only when it lies outside
    /// the pyramid's box or wholly outside one face.
    pub fn may_meet(&self, b: &Aabb) -> bool {
        if b.is_empty() {
            return false;
        }
        let s = &self.bounds;
        if b.min.x > s.max.x
            || b.min.y > s.max.y
            || b.min.z > s.max.z
            || b.max.x < s.min.x
            || b.max.y < s.min.y
            || b.max.z < s.min.z
        {
            return false;
        }
        within_planes(&self.planes, &self.margins, b)
    }
}

/// Whether the box `b` may reach inside every plane (n, d) of a convex
/// region (outside is n·x > d): false only when, for some plane, even
/// the box's corner farthest inside it lies beyond it by more than that
/// plane's margin. The shafts and the camera's beams (accel/beam.rs) both
/// ask it.
#[inline(always)]
pub(super) fn within_planes(planes: &[(DVec3, f64); 5], margins: &[f64; 5], b: &Aabb) -> bool {
    for ((n, d), m) in planes.iter().zip(margins) {
        // The box's corner farthest inside this face.
        let p = DVec3::new(
            if n.x > 0.0 { b.min.x } else { b.max.x },
            if n.y > 0.0 { b.min.y } else { b.max.y },
            if n.z > 0.0 { b.min.z } else { b.max.z },
        );
        if n.dot(p) - d > *m {
            return false;
        }
    }
    true
}

/// The margin a plane test with normal `n` (not of unit length) allows
/// for coordinates whose rounding `slack` bounds: the plane's value moves
/// by at most |n|₁ times the move of the point.
pub(super) fn margin(n: DVec3, slack: f64) -> f64 {
    slack * (n.x.abs() + n.y.abs() + n.z.abs())
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::geometry::Ray;

    fn unit_box(c: DVec3, r: f64) -> Aabb {
        Aabb::new(c - DVec3::splat(r), c + DVec3::splat(r))
    }

    /// The corners of a 2 × 2 light at height 6 over the origin (the
    /// accel tests' light too).
    pub(in crate::accel) fn light_square() -> [DVec3; 4] {
        [
            DVec3::new(-1.0, 6.0, -1.0),
            DVec3::new(1.0, 6.0, -1.0),
            DVec3::new(1.0, 6.0, 1.0),
            DVec3::new(-1.0, 6.0, 1.0),
        ]
    }

    /// That light seen from `apex` (on the floor, in most tests).
    fn shaft(apex: DVec3) -> Shaft {
        Shaft::new(apex, light_square()).unwrap()
    }

    #[test]
    fn boxes_on_the_way_meet_it_and_boxes_beside_it_do_not() {
        let _watchdog = crate::watchdog::start();
        let s = shaft(DVec3::ZERO);
        assert!(s.may_meet(&unit_box(DVec3::new(0.0, 3.0, 0.0), 0.1)));
        // Touching the pyramid's side from outside by a little: the side
        // at height 3 is at x = 0.5.
        assert!(s.may_meet(&unit_box(DVec3::new(0.55, 3.0, 0.0), 0.1)));
        assert!(!s.may_meet(&unit_box(DVec3::new(0.65, 3.0, 0.0), 0.1)));
        // Inside the pyramid's box but outside its slanted side.
        assert!(!s.may_meet(&unit_box(DVec3::new(0.9, 1.0, 0.9), 0.05)));
        // Below the apex, above the light.
        assert!(!s.may_meet(&unit_box(DVec3::new(0.0, -0.5, 0.0), 0.4)));
        assert!(!s.may_meet(&unit_box(DVec3::new(0.0, 7.0, 0.0), 0.5)));
    }

    /// The apex must lie clearly off the light's plane: where the
    /// pyramid's inner point (a fifth of the way from the base's centre
    /// to the apex) lies within a millionth of the scene's size (6 here)
    /// of a face, the shaft is refused and the rays go through the tree,
    /// whatever length the faces' normals have (the base's is 4 long).
    #[test]
    fn an_apex_all_but_in_the_lights_plane_is_refused() {
        let _watchdog = crate::watchdog::start();
        let below = |inner: f64| DVec3::new(0.0, 6.0 - 5.0 * inner * 6.0, 0.0);
        assert!(Shaft::new(below(0.6e-6), light_square()).is_none());
        assert!(Shaft::new(below(2e-6), light_square()).is_some());
    }

    #[test]
    fn the_light_itself_lies_outside_and_a_box_just_below_it_inside() {
        let _watchdog = crate::watchdog::start();
        let s = shaft(DVec3::ZERO);
        let light = Aabb::new(DVec3::new(-1.0, 6.0, -1.0), DVec3::new(1.0, 6.0, 1.0));
        assert!(!s.may_meet(&light));
        let under = Aabb::new(DVec3::new(-1.0, 5.999, -1.0), DVec3::new(1.0, 5.999, 1.0));
        assert!(s.may_meet(&under));
    }

    #[test]
    fn every_ray_to_the_light_stays_inside() {
        let _watchdog = crate::watchdog::start();
        // Points of each ray (to the light less SHADOW_EPSILON) as tiny
        // boxes: the test must keep every one.
        let apex = DVec3::new(0.3, 0.01, 2.0);
        let s = shaft(apex);
        for i in 0..=10 {
            for j in 0..=10 {
                let y = DVec3::new(-1.0 + 0.2 * i as f64, 6.0, -1.0 + 0.2 * j as f64);
                for k in 1..=20 {
                    let p = apex + (y - apex) * (k as f64 / 20.0) * (1.0 - 1e-4);
                    assert!(s.may_meet(&Aabb::new(p, p)), "{p}");
                }
            }
        }
    }

    /// Random lights (parallelograms in any orientation) seen from random
    /// points: every box holding a point of a shadow ray (to the light
    /// less `SHADOW_EPSILON`) is kept, straddling a face or not, whatever
    /// the signs of the faces' normals; a box clearly beyond one face is
    /// not, and neither is one beside the pyramid's box.
    #[test]
    fn boxes_on_any_ray_are_kept_and_boxes_outside_a_face_are_not() {
        let _watchdog = crate::watchdog::start();
        let mut seed = 0x5ba1_7e57_u64;
        let mut rnd = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let v = |s: f64, rnd: &mut dyn FnMut() -> f64| {
            DVec3::new(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0) * s
        };
        let (mut kept, mut culled) = (0, 0);
        for _ in 0..300 {
            let apex = v(5.0, &mut rnd);
            let corner = v(5.0, &mut rnd) + DVec3::new(0.0, 0.0, 8.0) * (rnd() - 0.5);
            let (eu, ev) = (v(2.0, &mut rnd), v(2.0, &mut rnd));
            let corners = [corner, corner + eu, corner + eu + ev, corner + ev];
            let Some(s) = Shaft::new(apex, corners) else {
                continue;
            };
            for _ in 0..20 {
                let (a, b, k) = (rnd(), rnd(), rnd());
                let y = corner + a * eu + b * ev;
                let p = apex + (y - apex) * k * (1.0 - 1e-4);
                // A box around a point of the ray, off-centre by a random
                // amount in each axis (so it straddles the faces near it).
                let (lo, hi) = (v(0.3, &mut rnd).abs(), v(0.3, &mut rnd).abs());
                let b = Aabb::new(p - lo, p + hi);
                assert!(s.may_meet(&b), "{b:?} holds {p} of a ray from {apex}");
                assert!(s.may_meet(&Aabb::new(p, p)));
                kept += 1;
            }
            // Boxes beyond each face: around a point of the face's plane
            // inside the face, pushed out along its normal by more than
            // the box's half-diagonal.
            let vs = s.vertices();
            let faces = [
                [vs[0], vs[1], vs[2]],
                [vs[0], vs[2], vs[3]],
                [vs[0], vs[3], vs[4]],
                [vs[0], vs[4], vs[1]],
                [vs[1], vs[2], vs[3]],
            ];
            for (k, f) in faces.iter().enumerate() {
                let c = (f[0] + f[1] + f[2]) / 3.0;
                // Normals are not of unit length: the shift goes along the
                // unit one.
                let (n, d) = s.planes[k];
                let scale = n.length() * (1.0 + c.abs().max_element());
                assert!((n.dot(c) - d).abs() < 1e-9 * scale);
                let n = n.normalize();
                let r = 0.01 * (f[1] - f[0]).length().min((f[2] - f[0]).length());
                let out = Aabb::new(c - DVec3::splat(r), c + DVec3::splat(r));
                let shifted = |t: f64| Aabb {
                    min: out.min + n * t,
                    max: out.max + n * t,
                };
                assert!(
                    !s.may_meet(&shifted(2.0 * r)),
                    "face {k}: a box beyond it kept"
                );
                // Straddling the face inside it: kept.
                assert!(s.may_meet(&out), "face {k}: a box across it culled");
                culled += 1;
            }
            // Beside the pyramid's box, on each side.
            let bb = s.bounds();
            let size = bb.max - bb.min;
            for a in 0..3 {
                for sign in [-1.0, 1.0] {
                    let mut shift = DVec3::ZERO;
                    shift[a] = sign * (size[a] + 1.0);
                    let b = Aabb {
                        min: bb.min + shift,
                        max: bb.max + shift,
                    };
                    assert!(!s.may_meet(&b));
                }
            }
        }
        assert!(kept > 3000 && culled > 700, "{kept} {culled}");
        assert!(!shaft(DVec3::ZERO).may_meet(&Aabb::EMPTY));
    }

    #[test]
    fn an_apex_in_the_lights_plane_gives_no_shaft() {
        let _watchdog = crate::watchdog::start();
        let corners = light_square();
        assert!(Shaft::new(DVec3::new(5.0, 6.0, 0.0), corners).is_none());
        assert!(Shaft::new(DVec3::new(5.0, 6.0, 0.0), [corners[0]; 4]).is_none());
    }

    #[test]
    fn a_lights_pyramid_over_a_box_holds_every_shadow_ray_from_it() {
        let _watchdog = crate::watchdog::start();
        let mut r = crate::accel::beam::tests::rng(0x11_9a7e);
        let (mut met, mut missed, mut rejected) = (0, 0, 0);
        for _ in 0..60 {
            let c = DVec3::new(r(), r(), r()) * 6.0 - 3.0;
            let size = DVec3::new(r(), r(), r()) * 0.8;
            let points = Aabb::new(c, c + size);
            let light = DVec3::new(r() * 10.0 - 5.0, 6.0 + 3.0 * r(), r() * 10.0 - 5.0);
            let s = Shaft::towards_box(light, &points).unwrap();
            // Shadow rays from the box's corners and inside it to the
            // light, stopping short of it as the renderer's do.
            let rays: Vec<(Ray, f64)> = (0..200)
                .map(|k| {
                    let mut pick = |bit: u32| if k < 8 { ((k >> bit) & 1) as f64 } else { r() };
                    let at = DVec3::new(pick(0), pick(1), pick(2));
                    let p = points.min + (points.max - points.min) * at;
                    let d = light - p;
                    (Ray::new(p, d.normalize()), d.length() * (1.0 - 1e-4))
                })
                .collect();
            for _ in 0..100 {
                // Near a point of one of the rays.
                let (ray, reach) = rays[(r() * rays.len() as f64) as usize];
                let q = ray.at(r() * reach) + (DVec3::new(r(), r(), r()) - 0.5) * 1.6;
                let b = Aabb::new(q, q + DVec3::splat(0.05 + 0.2 * r()));
                if rays
                    .iter()
                    .any(|(ray, reach)| b.clip(ray, 0.0, *reach).is_some())
                {
                    met += 1;
                    assert!(s.may_meet(&b), "{b:?} {points:?} {light}");
                } else {
                    missed += 1;
                    rejected += !s.may_meet(&b) as u32;
                }
            }
            // Its box holds the points and the light, and not much more.
            let (lo, hi) = (s.bounds().min, s.bounds().max);
            for p in points.corners().into_iter().chain([light]) {
                assert!(
                    p.cmpge(lo).all() && p.cmple(hi).all(),
                    "{p} {:?}",
                    s.bounds()
                );
            }
            let hull = points.grow(light);
            let slack = DVec3::splat(hull.extent().max_element() * 0.5);
            assert!(
                lo.cmpge(hull.min - slack).all() && hi.cmple(hull.max + slack).all(),
                "{:?} {hull:?}",
                s.bounds()
            );
            // Beside the box at its own height, on each side: no shadow
            // ray from it comes near.
            let mid = points.centre();
            for side in [DVec3::X, -DVec3::X, DVec3::Z, -DVec3::Z] {
                let q = mid + side * 1.5;
                let b = Aabb::new(q - DVec3::splat(0.1), q + DVec3::splat(0.1));
                assert!(!s.may_meet(&b), "{side} {points:?} {light}");
            }
            // Beyond the light, and behind the box as the light sees it.
            let beyond = light + (light - c) * 0.5;
            assert!(!s.may_meet(&Aabb::new(beyond, beyond + DVec3::splat(0.1))));
            let behind = c - (light - c).normalize() * 3.0;
            assert!(!s.may_meet(&Aabb::new(behind, behind + DVec3::splat(0.1))));
        }
        assert!(
            met > 300 && rejected as f64 > 0.8 * missed as f64,
            "{met} {rejected} {missed}"
        );
        // A light inside the box, or no box: no pyramid.
        let b = Aabb::new(DVec3::ZERO, DVec3::ONE);
        assert!(Shaft::towards_box(DVec3::splat(0.5), &b).is_none());
        assert!(Shaft::towards_box(DVec3::splat(5.0), &Aabb::EMPTY).is_none());
        let inverted = Aabb {
            min: DVec3::ONE,
            max: DVec3::ZERO,
        };
        assert!(Shaft::towards_box(DVec3::splat(5.0), &inverted).is_none());
        // A light beside a long box, some of whose corners lie behind it
        // as it looks at the box's centre: no pyramid holds the box.
        let long = Aabb::new(DVec3::new(-10.0, 0.0, 0.0), DVec3::new(10.0, 1.0, 1.0));
        assert!(Shaft::towards_box(DVec3::new(0.5, 0.5, 2.0), &long).is_none());
        // Hits on a floor, the light straight above: a lid just over the
        // floor, where every ray from it passes, meets the pyramid (its
        // base lies beyond the farthest corner, not short of it).
        let floor = Aabb::new(DVec3::new(-0.5, 0.0, -0.5), DVec3::new(0.5, 0.0, 0.5));
        let s = Shaft::towards_box(DVec3::new(0.0, 10.0, 0.0), &floor).unwrap();
        let lid = Aabb::new(
            DVec3::new(-0.05, 0.001, -0.05),
            DVec3::new(0.05, 0.004, 0.05),
        );
        assert!(s.may_meet(&lid));
        // A light close beside a box, seeing it askew (the slopes of its
        // corners far from symmetric): each corner of the base lies on two
        // sides and inside the other two.
        let b = Aabb::new(DVec3::ZERO, DVec3::ONE);
        let s = Shaft::towards_box(DVec3::new(2.2, 2.0, -0.3), &b).unwrap();
        for v in &s.vertices()[1..] {
            let on = s
                .planes
                .iter()
                .zip(s.margins)
                .take(4)
                .filter(|((n, d), m)| {
                    let e = n.dot(*v) - d;
                    assert!(e <= *m, "{v} outside by {e}");
                    e.abs() <= *m
                })
                .count();
            assert_eq!(on, 2, "{v}");
        }
        // One point: a pyramid with no width, holding it all the same.
        let p = Aabb::new(DVec3::ONE, DVec3::ONE);
        let s = Shaft::towards_box(DVec3::new(3.0, 9.0, 1.0), &p).unwrap();
        assert!(s.may_meet(&Aabb::new(DVec3::splat(0.99), DVec3::splat(1.01))));
        assert!(!s.may_meet(&Aabb::new(DVec3::splat(1.2), DVec3::splat(1.3))));
    }
}
