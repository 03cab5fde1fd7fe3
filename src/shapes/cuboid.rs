//! An axis-aligned box, each face with its own material.
//!
//! ```text
//! box { min <-1, 0, -1>  max <1, 2, 1>  material wood }
//! box { min <0, 0, 0>  max <1, 1, 1>  material grey  front red  top blue }
//! ```
//! Faces: front z = max.z, back z = min.z, top y = max.y, bottom y = min.y,
//! left x = min.x, right x = max.x. Texture space (W, H, D the extents):
//! front/back u = (x − min.x)/W, v = (y − min.y)/H; top/bottom
//! u = (x − min.x)/W, v = (z − min.z)/D; left/right u = (y − min.y)/H,
//! v = (z − min.z)/D.

use super::{Crossing, Hit, Shape, ray_point_error};
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;

#[derive(Clone, Debug)]
pub struct Cuboid {
    pub min: DVec3,
    pub max: DVec3,
    /// front (+z), back (−z), top (+y), bottom (−y), left (−x), right (+x).
    pub materials: [MaterialId; 6],
}

/// A face: the axis it is perpendicular to and whether it is the high side.
#[derive(Clone, Copy, Debug)]
struct Face {
    axis: usize,
    high: bool,
}

impl Face {
    #[inline(always)]
    fn new(axis: usize, high: bool) -> Face {
        Face { axis, high }
    }

    fn normal(self) -> DVec3 {
        let mut normal = DVec3::ZERO;
        normal[self.axis] = if self.high { 1.0 } else { -1.0 };
        normal
    }

    /// The crossing at `t`, its key the face (axis · 2 + high).
    fn crossing(self, ray: &Ray, t: f64) -> Crossing {
        let key = (self.axis as u64) << 1 | self.high as u64;
        Crossing::new(t, self.normal(), ray, key)
    }
}

impl Cuboid {
    /// `materials` per face: front (+z), back (−z), top (+y), bottom (−y), left (−x), right (+x).
    pub fn new(min: DVec3, max: DVec3, materials: [MaterialId; 6]) -> Self {
        Cuboid {
            min: min.min(max),
            max: min.max(max),
            materials,
        }
    }

    /// The entering and leaving parameters along the whole line, with the
    /// faces they cross. Axes the ray runs parallel to are skipped (after
    /// checking the origin lies between their planes), so no 0·∞ NaN can
    /// leak into the comparisons.
    fn slabs(&self, ray: &Ray) -> Option<((f64, Face), (f64, Face))> {
        // Arrays, and one axis after another written out: indexing a
        // DVec3 by a loop's axis is a `match` per access, and the loop
        // over them stayed a loop (about 170 instructions a box; 8% of
        // glass_full's instructions went through the box). The same
        // operations in the same order, so the same crossings.
        let (o, d) = (ray.origin.to_array(), ray.dir.to_array());
        let (lo, hi) = (self.min.to_array(), self.max.to_array());
        let mut near = (f64::NEG_INFINITY, Face::new(0, false));
        let mut far = (f64::INFINITY, Face::new(0, true));
        let mut axis = |a: usize| -> bool {
            let (o, d) = (o[a], d[a]);
            let (lo, hi) = (lo[a], hi[a]);
            if d == 0.0 {
                return !(o < lo || o > hi);
            }
            let inv = 1.0 / d;
            let (t_lo, t_hi) = ((lo - o) * inv, (hi - o) * inv);
            // Entering through the low face when moving up the axis.
            let up = d > 0.0;
            let (enter, leave) = if up { (t_lo, t_hi) } else { (t_hi, t_lo) };
            if enter > near.0 {
                near = (enter, Face::new(a, !up));
            }
            if leave < far.0 {
                far = (leave, Face::new(a, up));
            }
            true
        };
        if !(axis(0) && axis(1) && axis(2)) {
            return None;
        }
        (near.0 <= far.0 && near.0.is_finite() && far.0.is_finite()).then_some((near, far))
    }

    fn hit_at(&self, ray: &Ray, t: f64, face: Face) -> Hit {
        let p = ray.at(t);
        let normal = face.normal();
        let size = (self.max - self.min).max(DVec3::splat(f64::MIN_POSITIVE));
        let rel = (p - self.min) / size;
        let (uv, material) = match (face.axis, face.high) {
            (2, true) => (DVec2::new(rel.x, rel.y), self.materials[0]),
            (2, false) => (DVec2::new(rel.x, rel.y), self.materials[1]),
            (1, true) => (DVec2::new(rel.x, rel.z), self.materials[2]),
            (1, false) => (DVec2::new(rel.x, rel.z), self.materials[3]),
            (_, false) => (DVec2::new(rel.y, rel.z), self.materials[4]),
            (_, true) => (DVec2::new(rel.y, rel.z), self.materials[5]),
        };
        // Snapped onto the face's plane: exact across it, rounding along it.
        let mut point = p;
        let mut p_error = ray_point_error(ray, t);
        point[face.axis] = if face.high {
            self.max[face.axis]
        } else {
            self.min[face.axis]
        };
        p_error[face.axis] = 0.0;
        Hit {
            t,
            normal,
            uv,
            local: p,
            point,
            p_error,
            geo_normal: normal,
            material,
            path: 0,
        }
    }
}

impl Shape for Cuboid {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let ((t0, f0), (t1, f1)) = self.slabs(ray)?;
        if t0 > t_min && t0 < t_max {
            Some(self.hit_at(ray, t0, f0))
        } else if t1 > t_min && t1 < t_max {
            Some(self.hit_at(ray, t1, f1))
        } else {
            None
        }
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.slabs(ray).is_some_and(|((t0, _), (t1, _))| {
            (t0 > t_min && t0 < t_max) || (t1 > t_min && t1 < t_max)
        })
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        if let Some(((t0, f0), (t1, f1))) = self.slabs(ray) {
            out.push(self.hit_at(ray, t0, f0));
            out.push(self.hit_at(ray, t1, f1));
        }
    }

    fn crossings_lite(&self, ray: &Ray, out: &mut Vec<Crossing>) {
        if let Some(((t0, f0), (t1, f1))) = self.slabs(ray) {
            out.push(f0.crossing(ray, t0));
            out.push(f1.crossing(ray, t1));
        }
    }

    fn hit_of(&self, ray: &Ray, c: &Crossing) -> Hit {
        let face = Face {
            axis: (c.key >> 1) as usize % 3,
            high: c.key & 1 == 1,
        };
        self.hit_at(ray, c.t, face)
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    fn is_solid(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::testing;

    fn unit() -> Cuboid {
        Cuboid::new(DVec3::ZERO, DVec3::new(2.0, 3.0, 4.0), [1, 2, 3, 4, 5, 6])
    }

    #[test]
    fn faces_normals_and_materials() {
        let b = unit();
        let centre = DVec3::new(1.0, 1.5, 2.0);
        // (direction towards the face from outside, normal, material)
        let cases = [
            (DVec3::Z, 1),
            (-DVec3::Z, 2),
            (DVec3::Y, 3),
            (-DVec3::Y, 4),
            (-DVec3::X, 5),
            (DVec3::X, 6),
        ];
        for (n, m) in cases {
            let r = Ray::new(centre + n * 10.0, -n * 0.5);
            let h = b.intersect(&r, 1e-9, f64::INFINITY).unwrap();
            assert_eq!(h.normal, n);
            assert_eq!(h.material, m);
            let p = r.at(h.t);
            assert!((p - centre).dot(n) > 0.0 && b.bounds().contains(p));
        }
        // A non-unit direction keeps t in the same parameterisation.
        let r = Ray::new(DVec3::new(1.0, 1.0, 10.0), DVec3::new(0.0, 0.0, -2.0));
        assert!((b.intersect(&r, 0.0, 99.0).unwrap().t - 3.0).abs() < 1e-12);
    }

    #[test]
    fn uv_per_face() {
        let b = unit();
        let hit = |o: DVec3, d: DVec3| b.intersect(&Ray::new(o, d), 0.0, 99.0).unwrap().uv;
        // Front at (0.5, 0.75, 4): u = x/W, v = y/H.
        let uv = hit(DVec3::new(0.5, 0.75, 9.0), -DVec3::Z);
        assert!((uv - DVec2::new(0.25, 0.25)).length() < 1e-12);
        // Top at (1.5, 3, 1): u = x/W, v = z/D.
        let uv = hit(DVec3::new(1.5, 9.0, 1.0), -DVec3::Y);
        assert!((uv - DVec2::new(0.75, 0.25)).length() < 1e-12);
        // Left at (0, 1.5, 3): u = y/H, v = z/D.
        let uv = hit(DVec3::new(-9.0, 1.5, 3.0), DVec3::X);
        assert!((uv - DVec2::new(0.5, 0.75)).length() < 1e-12);
    }

    #[test]
    fn inside_parallel_and_miss() {
        let b = unit();
        let inside = Ray::new(DVec3::new(1.0, 1.0, 1.0), DVec3::X);
        let h = b.intersect(&inside, 1e-9, f64::INFINITY).unwrap();
        assert!((h.t - 1.0).abs() < 1e-12 && h.normal == DVec3::X);
        // Running inside the plane of a face: no NaN, a hit on the far face.
        let on_face = Ray::new(DVec3::new(0.0, 1.0, -5.0), DVec3::Z);
        let h = b.intersect(&on_face, 1e-9, f64::INFINITY).unwrap();
        assert!(h.t.is_finite() && (h.t - 5.0).abs() < 1e-12);
        let miss = Ray::new(DVec3::new(3.0, 1.0, -5.0), DVec3::Z);
        assert!(b.intersect(&miss, 0.0, f64::INFINITY).is_none());
        let mut xs = Vec::new();
        b.crossings(&miss, &mut xs);
        assert!(xs.is_empty());
        // A flat box does not panic and gives no NaN.
        let flat = Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0), [0; 6]);
        let h = flat.intersect(&Ray::new(DVec3::new(0.5, 1.0, 0.5), -DVec3::Y), 0.0, 9.0);
        assert!(h.is_none_or(|h| h.uv.is_finite() && h.t.is_finite()));
    }

    #[test]
    fn properties() {
        let b = unit();
        let rays = testing::rays_towards(DVec3::new(1.0, 1.5, 2.0), 3.0, 500, 7);
        testing::check_consistency(&b, &rays);
        testing::check_alternation(&b, &rays);
        testing::check_no_rehit(&b, &rays);
        assert!(testing::check_normals(&b, &rays) > 100);
    }

    /// Each face's (u, v) is the hit's position across the face as a
    /// fraction of the box's extents (the module's table), for a box away
    /// from the origin (so min and max are not the extents): all six
    /// faces, at points that tell u from v and the axes apart.
    #[test]
    fn uv_is_the_fraction_across_each_face_off_the_origin() {
        let (min, max) = (DVec3::new(-1.0, 2.0, 0.5), DVec3::new(1.0, 5.0, 2.5));
        let b = Cuboid::new(min, max, [0; 6]);
        let size = max - min;
        let centre = (min + max) / 2.0;
        for n in [
            DVec3::X,
            -DVec3::X,
            DVec3::Y,
            -DVec3::Y,
            DVec3::Z,
            -DVec3::Z,
        ] {
            for (i, j) in [(0.2, 0.7), (0.9, 0.35)] {
                // Two in-face axes in the table's order (x before y before z).
                let axes: Vec<usize> = (0..3).filter(|&a| n[a] == 0.0).collect();
                let mut p = centre + n * 10.0;
                p[axes[0]] = min[axes[0]] + i * size[axes[0]];
                p[axes[1]] = min[axes[1]] + j * size[axes[1]];
                let h = b.intersect(&Ray::new(p, -n), 0.0, f64::INFINITY).unwrap();
                assert_eq!(h.normal, n);
                assert!(
                    (h.uv - DVec2::new(i, j)).length() < 1e-12,
                    "{:?} vs ({i}, {j}) on {n:?}",
                    h.uv
                );
            }
        }
    }

    /// The window is open at both ends (`t_min < t < t_max`, as for every
    /// shape): a crossing exactly at either end is outside it. Down the z
    /// axis the box is entered at exactly t = 5 and left at t = 9.
    #[test]
    fn a_crossing_exactly_at_a_window_end_is_outside() {
        let b = unit();
        let r = Ray::new(DVec3::new(1.0, 1.0, 9.0), -DVec3::Z);
        let mut xs = Vec::new();
        b.crossings(&r, &mut xs);
        assert_eq!(xs.iter().map(|h| h.t).collect::<Vec<_>>(), [5.0, 9.0]);
        let t = |lo: f64, hi: f64| b.intersect(&r, lo, hi).map(|h| h.t);
        assert_eq!(t(5.0, 99.0), Some(9.0));
        assert!(b.occludes(&r, 5.0, 99.0));
        for (lo, hi) in [(0.0, 5.0), (9.0, 99.0), (5.0, 9.0)] {
            assert_eq!(t(lo, hi), None, "({lo}, {hi})");
            assert!(!b.occludes(&r, lo, hi), "({lo}, {hi})");
        }
        assert_eq!(t(0.0, 5.0 + 1e-9), Some(5.0));
        assert_eq!(t(9.0 - 1e-9, 99.0), Some(9.0));
        assert!(b.occludes(&r, 9.0 - 1e-9, 99.0));
    }

    /// The light route (`crossings_lite`, then `hit_of` for the one CSG
    /// keeps) gives the same crossings as `crossings`: the same t, facing
    /// in where the ray enters and out where it leaves, and the same hit —
    /// face, normal, point, uv and material (each face has its own).
    #[test]
    fn crossings_lite_and_hit_of_agree_with_crossings() {
        let b = unit();
        let mut met = 0;
        let mut faces = std::collections::HashSet::new();
        for r in testing::rays_towards(DVec3::new(1.0, 1.5, 2.0), 3.0, 400, 19) {
            let mut xs = Vec::new();
            b.crossings(&r, &mut xs);
            let mut lite = Vec::new();
            b.crossings_lite(&r, &mut lite);
            assert_eq!(xs.len(), lite.len());
            if xs.is_empty() {
                continue;
            }
            for (x, c) in xs.iter().zip(&lite) {
                assert_eq!(c.t, x.t);
                let h = b.hit_of(&r, c);
                assert_eq!(
                    (h.t, h.point, h.normal, h.uv, h.material),
                    (x.t, x.point, x.normal, x.uv, x.material)
                );
                assert_eq!(c.facing.signum(), x.normal.dot(r.dir).signum());
                faces.insert(x.material);
            }
            assert!(lite[0].facing < 0.0 && lite[1].facing > 0.0, "{lite:?}");
            met += 1;
        }
        assert!(met > 100, "{met}");
        assert_eq!(faces.len(), 6, "{faces:?}");
    }

    /// The box is its corners' box and holds every hit; shadow rays agree
    /// with the crossings in every window; it is a solid.
    #[test]
    fn bounds_hold_every_hit_and_it_is_solid() {
        let b = Cuboid::new(
            DVec3::new(1.0, -2.0, 3.0),
            DVec3::new(-1.0, 0.5, 2.0),
            [0; 6],
        );
        assert_eq!(
            b.bounds(),
            Aabb::new(DVec3::new(-1.0, -2.0, 2.0), DVec3::new(1.0, 0.5, 3.0))
        );
        let rays = testing::rays_towards(DVec3::new(0.0, -0.75, 2.5), 2.0, 300, 23);
        assert!(testing::check_bounds_hold_hits(&b, &rays) > 100);
        assert!(testing::check_occludes_agrees(&b, &rays) > 100);
        assert!(b.is_solid());
    }

    /// A ray running in the plane of a face belongs to the (closed) box:
    /// along each of the six face planes, through the box, it meets the
    /// far side at the face's edge.
    #[test]
    fn a_ray_in_the_plane_of_any_face_meets_the_box() {
        let b = unit();
        for (o, d, t) in [
            (DVec3::new(0.0, 1.0, -5.0), DVec3::Z, 5.0),
            (DVec3::new(2.0, 1.0, -5.0), DVec3::Z, 5.0),
            (DVec3::new(1.0, 0.0, -5.0), DVec3::Z, 5.0),
            (DVec3::new(1.0, 3.0, -5.0), DVec3::Z, 5.0),
            (DVec3::new(-5.0, 1.0, 0.0), DVec3::X, 5.0),
            (DVec3::new(-5.0, 1.0, 4.0), DVec3::X, 5.0),
        ] {
            let h = b.intersect(&Ray::new(o, d), 0.0, f64::INFINITY);
            assert_eq!(h.map(|h| h.t), Some(t), "from {o:?} along {d:?}");
        }
    }

    /// A line that touches an edge (entering one slab as it leaves
    /// another, at the same t) meets the box at that edge.
    #[test]
    fn a_line_touching_an_edge_meets_the_box_there() {
        let b = unit();
        // Past the edge x = 0, y = 3 at z = 1, rising at 45°: the line
        // y = 3 + x has the whole box on or below it.
        let r = Ray::new(DVec3::new(-1.0, 2.0, 1.0), DVec3::new(1.0, 1.0, 0.0));
        let h = b.intersect(&r, 0.0, f64::INFINITY).unwrap();
        assert_eq!(h.t, 1.0);
        assert_eq!(h.point, DVec3::new(0.0, 3.0, 1.0));
        // A hair higher, it misses.
        let r = Ray::new(DVec3::new(-1.0, 2.0 + 1e-9, 1.0), DVec3::new(1.0, 1.0, 0.0));
        assert!(b.intersect(&r, 0.0, f64::INFINITY).is_none());
    }
}
