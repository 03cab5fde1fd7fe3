//! Triangle meshes from files (read by `formats`), indexed by their own
//! kd-tree.
//!
//! ```text
//! mesh "bunny.ply" { smooth  scale 20  material { colour rgb(0.8, 0.8, 0.8) } }
//! mesh "ico.ply"   { flat  translate <0, 1, 0> }
//! ```
//! The path is relative to the scene file. [`MeshData`] (vertices,
//! triangles, per-triangle edges and the kd-tree) is built once per file and
//! shared by every placement through an `Arc`; a placement is a [`Mesh`]
//! (shading mode and material) inside a `Transformed`.
//!
//! `smooth` interpolates vertex normals (from the file, or area-weighted from
//! the faces around each vertex); `flat` uses each triangle's own normal. The
//! normal follows the winding (counter-clockwise seen from outside is
//! outward); the renderer turns it towards the ray, so meshes wound the other
//! way (the Stanford bunny) still shade correctly. Texture space: the file's
//! per-vertex u, v interpolated, else the barycentric coordinates.
//!
//! A mesh is a solid (usable in CSG) when it is closed: every edge is shared
//! by exactly two triangles.

use super::{Hit, Shape, ShearedRay, barycentric_point};
use crate::accel::{BuildParams, KdTree};
use crate::formats::{self, MeshFileError, TriangleSoup};
use crate::geometry::rounding::gamma;
use crate::geometry::{Aabb, DVec2, DVec3, Ray};
use crate::scene::MaterialId;
use std::path::Path;
use std::sync::Arc;

/// A triangle's corners, copied out of the index so the test reads them
/// from one place.
#[derive(Clone, Copy, Debug)]
struct TriPre {
    v0: DVec3,
    v1: DVec3,
    v2: DVec3,
}

impl TriPre {
    fn e1(&self) -> DVec3 {
        self.v1 - self.v0
    }

    fn e2(&self) -> DVec3 {
        self.v2 - self.v0
    }

    /// The face's outward normal by the winding, (v1 − v0) × (v2 − v0).
    fn normal(&self) -> DVec3 {
        self.e1().cross(self.e2())
    }

    /// The watertight test ([`ShearedRay`]): `(t, b1, b2)` with the
    /// barycentrics of corners 1 and 2, edges and corners included, so a ray
    /// through a shared edge or vertex is never lost between triangles.
    #[inline(always)]
    fn hit_sheared(&self, ray: &ShearedRay, t_min: f64, t_max: f64) -> Option<(f64, f64, f64)> {
        let (t, b) = ray.triangle(self.v0, self.v1, self.v2)?;
        (t > t_min && t < t_max).then_some((t, b[1], b[2]))
    }

    /// [`TriPre::hit_sheared`] for one ray and one triangle.
    #[cfg(test)]
    fn hit(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, f64, f64)> {
        self.hit_sheared(&ShearedRay::new(ray), t_min, t_max)
    }
}

/// The SAH's constants for triangles, found by measuring the benchmark's
/// rays (`bunny_rays_take_few_steps_and_tests`): the textbook ratios
/// (a test worth 2 or more steps, half the cost off for empty space) split
/// far past what pays, because a ray stops at its first hit and never sees
/// the cells behind it, and they spend the depth cap on slivers of empty
/// space while dense parts are left in leaves of a hundred triangles.
const MESH_TREE: BuildParams = BuildParams {
    item_cost: 0.3,
    empty_bonus: 0.1,
    depth_base: 8.0,
};

/// Triangles loaded once and shared by every placement (instancing).
#[derive(Debug)]
pub struct MeshData {
    positions: Vec<DVec3>,
    /// Vertex normals (from the file, or area-weighted), for `smooth`.
    normals: Vec<DVec3>,
    uvs: Option<Vec<DVec2>>,
    triangles: Vec<[u32; 3]>,
    pre: Vec<TriPre>,
    tree: KdTree,
    /// Worked out when first asked (CSG asks; a render alone never does):
    /// its edge sort is a noticeable part of loading a big mesh.
    closed: std::sync::OnceLock<bool>,
}

impl MeshData {
    /// The mesh in a file (see [`formats::read_mesh`]).
    pub fn load(path: &Path) -> Result<MeshData, MeshFileError> {
        Ok(Self::from_soup(formats::read_mesh(path)?))
    }

    /// The mesh in a PLY file's bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<MeshData, MeshFileError> {
        Ok(Self::from_soup(formats::ply::parse(bytes)?))
    }

    /// The mesh of what a reader produced.
    pub fn from_soup(soup: TriangleSoup) -> MeshData {
        Self::from_parts(soup.positions, soup.normals, soup.uvs, soup.triangles)
    }

    /// Builds from arrays already checked (indices in range, finite
    /// positions); the PLY reader guarantees that.
    pub fn from_parts(
        positions: Vec<DVec3>,
        normals: Option<Vec<DVec3>>,
        uvs: Option<Vec<DVec2>>,
        triangles: Vec<[u32; 3]>,
    ) -> MeshData {
        let corner = |t: &[u32; 3], k: usize| positions[t[k] as usize];
        let pre: Vec<TriPre> = triangles
            .iter()
            .map(|t| TriPre {
                v0: corner(t, 0),
                v1: corner(t, 1),
                v2: corner(t, 2),
            })
            .collect();
        let boxes: Vec<Aabb> = triangles
            .iter()
            .map(|t| Aabb::new(corner(t, 0), corner(t, 1)).grow(corner(t, 2)))
            .collect();
        let clip = |i: u32, cell: &Aabb, axis: usize, split: f64| {
            let t = &triangles[i as usize];
            split_triangle([0, 1, 2].map(|k| corner(t, k)), cell, axis, split)
        };
        // The tree's first levels run on one thread: the rest of the set-up
        // fills the other.
        let (tree, normals) = rayon::join(
            || KdTree::build_clipped(&boxes, &clip, MESH_TREE),
            || match normals {
                Some(n) => n,
                None => area_weighted_normals(&positions, &pre, &triangles),
            },
        );
        drop(boxes);
        crate::accel::record_mesh_tree(&tree.stats);
        MeshData {
            positions,
            normals,
            uvs,
            triangles,
            pre,
            tree,
            closed: std::sync::OnceLock::new(),
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn bounds(&self) -> Aabb {
        self.tree.bounds()
    }

    pub fn is_closed(&self) -> bool {
        *self.closed.get_or_init(|| is_closed(&self.triangles))
    }

    pub fn tree_stats(&self) -> &crate::accel::TreeStats {
        &self.tree.stats
    }

    /// The corners of triangle `i`.
    pub fn triangle(&self, i: usize) -> [DVec3; 3] {
        let t = self.triangles[i];
        t.map(|k| self.positions[k as usize])
    }

    /// Approximate bytes held (for reports and tests of instancing).
    pub fn memory(&self) -> usize {
        use std::mem::size_of;
        self.positions.len() * size_of::<DVec3>() * 2
            + self
                .uvs
                .as_ref()
                .map_or(0, |u| u.len() * size_of::<DVec2>())
            + self.triangles.len() * (size_of::<[u32; 3]>() + size_of::<TriPre>())
            + self.tree.memory()
    }

    /// Nearest triangle: `(t, triangle, b1, b2)`.
    #[inline]
    fn nearest(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, u32, f64, f64)> {
        let mut rec = (0u32, 0.0, 0.0);
        let sheared = ShearedRay::new(ray);
        let t = self.tree.nearest(ray, t_min, t_max, |i, best| {
            let (t, b1, b2) = self.pre[i as usize].hit_sheared(&sheared, t_min, best)?;
            rec = (i, b1, b2);
            Some(t)
        })?;
        Some((t, rec.0, rec.1, rec.2))
    }

    fn hit_record(&self, ray: &Ray, t: f64, tri: u32, b1: f64, b2: f64, smooth: bool) -> MeshHit {
        let pre = &self.pre[tri as usize];
        let geometric = pre.normal();
        let idx = self.triangles[tri as usize];
        let b0 = 1.0 - b1 - b2;
        let normal = if smooth {
            let [n0, n1, n2] = idx.map(|k| self.normals[k as usize]);
            let n = b0 * n0 + b1 * n1 + b2 * n2;
            if n.length_squared() > 0.0 {
                n
            } else {
                geometric
            }
        } else {
            geometric
        };
        let uv = match &self.uvs {
            Some(uvs) => {
                let [u0, u1, u2] = idx.map(|k| uvs[k as usize]);
                b0 * u0 + b1 * u1 + b2 * u2
            }
            None => DVec2::new(b1, b2),
        };
        let corners = [pre.v0, pre.v1, pre.v2];
        let (mut point, mut p_error) = barycentric_point(corners, [b0, b1, b2]);
        if smooth {
            let lift = terminator_lift(
                point,
                corners,
                idx.map(|k| self.normals[k as usize]),
                [b0, b1, b2],
                if geometric.dot(ray.dir) > 0.0 {
                    -geometric
                } else {
                    geometric
                },
            );
            point += lift;
            p_error += gamma(4) * point.abs();
        }
        MeshHit {
            normal,
            geometric,
            uv,
            local: ray.at(t),
            point,
            p_error,
        }
    }
}

/// How far a smooth mesh's hit point is lifted towards the viewer to sit on
/// the curved surface its vertex normals describe rather than on the flat
/// facet (Hanika, "Hacking the Shadow Terminator", Ray Tracing Gems II
/// ch. 4): the point is projected onto each corner's tangent plane where it
/// lies below it, and the projections are blended by the barycentric
/// weights. Secondary rays then start from the smooth surface, so a light
/// that the shading normal faces is not hidden by the facet's own
/// neighbours, and the shadow terminator follows the surface, not the
/// facets. `facing` is the geometric normal turned towards the viewer; each
/// vertex normal is turned to its side.
fn terminator_lift(
    p: DVec3,
    corners: [DVec3; 3],
    normals: [DVec3; 3],
    b: [f64; 3],
    facing: DVec3,
) -> DVec3 {
    let mut lift = DVec3::ZERO;
    for k in 0..3 {
        let mut n = normals[k].normalize_or_zero();
        if n.dot(facing) < 0.0 {
            n = -n;
        }
        let below = (p - corners[k]).dot(n).min(0.0);
        lift -= b[k] * below * n;
    }
    if lift.is_finite() { lift } else { DVec3::ZERO }
}

/// What a mesh's hit record holds beside t and the material.
struct MeshHit {
    normal: DVec3,
    geometric: DVec3,
    uv: DVec2,
    local: DVec3,
    point: DVec3,
    p_error: DVec3,
}

/// The boxes around the parts of a triangle inside `cell` below and above
/// the plane `split` on `axis` (`None` for a side it misses): the triangle
/// is clipped to the cell (Sutherland–Hodgman against the planes it
/// crosses), and the polygon left is cut at the split plane. The clipping
/// is done against planes moved out by a hair, and a triangle that comes
/// that close is kept (its box pressed onto the cell's face), so that
/// rounding here or in the ray test can never lose a triangle from a cell
/// where the ray finds it.
fn split_triangle(tri: [DVec3; 3], cell: &Aabb, axis: usize, split: f64) -> [Option<Aabb>; 2] {
    let size = cell.min.abs().max(cell.max.abs()).max_element() + cell.extent().max_element();
    let pad = size * 1e-9;
    let (lo, hi) = (
        (cell.min - DVec3::splat(pad)).to_array(),
        (cell.max + DVec3::splat(pad)).to_array(),
    );
    let (tmin, tmax) = (
        tri[0].min(tri[1]).min(tri[2]).to_array(),
        tri[0].max(tri[1]).max(tri[2]).to_array(),
    );
    let corners = tri.map(|v| v.to_array());
    let mut crossed = false;
    for a in 0..3 {
        if tmax[a] < lo[a] || tmin[a] > hi[a] {
            return [None, None];
        }
        crossed |= tmin[a] < lo[a] || tmax[a] > hi[a];
    }
    let side = |poly: &[[f64; 3]], keep_above: bool, plane: f64, child: &Aabb| {
        let (mut bmin, mut bmax) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        // Plain comparisons, not `f64::min`: the corners are finite, and
        // the NaN handling of `min` and `max` was a third of this closure.
        half_space(poly, axis, plane, keep_above, |p| {
            for j in 0..3 {
                bmin[j] = if p[j] < bmin[j] { p[j] } else { bmin[j] };
                bmax[j] = if p[j] > bmax[j] { p[j] } else { bmax[j] };
            }
        });
        (bmin[0] <= bmax[0]).then(|| Aabb {
            min: DVec3::from_array(bmin).clamp(child.min, child.max),
            max: DVec3::from_array(bmax).clamp(child.min, child.max),
        })
    };
    let (mut below, mut above) = (*cell, *cell);
    below.max[axis] = split;
    above.min[axis] = split;
    let sides = |poly: &[[f64; 3]]| {
        [
            side(poly, false, split + pad, &below),
            side(poly, true, split - pad, &above),
        ]
    };
    // Most triangles lie inside the cell: they need no clipping (and no
    // buffers, whose zeroing was a tenth of the cost).
    if !crossed {
        return sides(&corners);
    }
    // A triangle cut by six planes keeps at most nine corners. Two buffers
    // used in turn: copying the polygon after each plane cost more than
    // the clipping itself.
    let mut bufs = [[[0f64; 3]; 9]; 2];
    let (mut n, mut cur) = (3, 0);
    bufs[0][..3].copy_from_slice(&corners);
    {
        for a in 0..3 {
            for (plane, keep_above) in [(lo[a], true), (hi[a], false)] {
                // Only the planes the triangle crosses can cut it.
                if (keep_above && tmin[a] >= plane) || (!keep_above && tmax[a] <= plane) {
                    continue;
                }
                let [a_buf, b_buf] = &mut bufs;
                let (src, dst) = if cur == 0 {
                    (&*a_buf, b_buf)
                } else {
                    (&*b_buf, a_buf)
                };
                let mut m = 0;
                half_space(&src[..n], a, plane, keep_above, |p| {
                    dst[m] = p;
                    m += 1;
                });
                if m == 0 {
                    return [None, None];
                }
                n = m;
                cur ^= 1;
            }
        }
    }
    sides(&bufs[cur][..n])
}

/// One step of Sutherland–Hodgman: the corners of the convex polygon
/// `poly` on one side of the plane at `plane` on `axis` (inclusive), in
/// order, passed to `out`.
#[inline]
fn half_space(
    poly: &[[f64; 3]],
    axis: usize,
    plane: f64,
    keep_above: bool,
    mut out: impl FnMut([f64; 3]),
) {
    let inside = |p: &[f64; 3]| {
        if keep_above {
            p[axis] >= plane
        } else {
            p[axis] <= plane
        }
    };
    // The edges in the same directions as always (so that the same
    // points come out), from the closing edge on: the previous corner is
    // carried rather than fetched again.
    let Some(&last) = poly.last() else { return };
    let (mut a, mut ia) = (last, inside(&last));
    for &b in poly {
        let ib = inside(&b);
        if ia {
            out(a);
        }
        if ia != ib {
            let s = (plane - a[axis]) / (b[axis] - a[axis]);
            let mut c = [0f64; 3];
            for j in 0..3 {
                c[j] = a[j] + s * (b[j] - a[j]);
            }
            c[axis] = plane;
            out(c);
        }
        (a, ia) = (b, ib);
    }
}

/// Each vertex gets the sum of its triangles' unnormalised normals
/// (|e1 × e2| is twice the area, so big faces weigh more), normalised.
fn area_weighted_normals(
    positions: &[DVec3],
    pre: &[TriPre],
    triangles: &[[u32; 3]],
) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; positions.len()];
    for (t, p) in triangles.iter().zip(pre) {
        let face = p.normal();
        for &k in t {
            n[k as usize] += face;
        }
    }
    for v in &mut n {
        *v = v.normalize_or_zero();
    }
    n
}

/// Every undirected edge used by exactly two triangles.
fn is_closed(triangles: &[[u32; 3]]) -> bool {
    if triangles.is_empty() {
        return false;
    }
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a == b {
                return false;
            }
            edges.push((a.min(b), a.max(b)));
        }
    }
    edges.sort_unstable();
    let mut i = 0;
    while i < edges.len() {
        let mut j = i;
        while j < edges.len() && edges[j] == edges[i] {
            j += 1;
        }
        if j - i != 2 {
            return false;
        }
        i = j;
    }
    true
}

/// A closed mesh's crossings for CSG, which must alternate entering and
/// leaving. Each triangle's winding tells the way (its geometric normal;
/// a smooth normal can disagree near a silhouette), and a mesh wound
/// inwards is recognised by its first clear crossing (a closed surface is
/// entered first). Triangles met at one point (the two sharing an edge,
/// the fan around a vertex: the watertight test reports each of them) are
/// taken as one group:
/// - all facing one way: one crossing, skipped if it would not change the
///   side;
/// - facing both ways (a line touching a vertex or an edge, or crossing a
///   saddle vertex): the side after the point is read from the next clear
///   group (outside when none follows), and the group is one crossing or
///   none.
///
/// Reported normals are turned to agree.
fn solid_crossings(
    d: &MeshData,
    ray: &Ray,
    found: &[(f64, u32, f64, f64)],
    hit: impl Fn(f64, u32, f64, f64) -> Hit,
    out: &mut Vec<Hit>,
) {
    let facing = |k: usize| d.pre[found[k].1 as usize].normal().dot(ray.dir);
    // Groups of crossings at one point: (first index, end, the sign of
    // their facing if all agree, else 0).
    let mut groups: Vec<(usize, usize, f64)> = Vec::new();
    let mut i = 0;
    while i < found.len() {
        let t0 = found[i].0;
        let tol = POINT_TOLERANCE * t0.abs();
        let (mut pos, mut neg) = (false, false);
        let mut j = i;
        while j < found.len() && found[j].0 - t0 <= tol {
            let f = facing(j);
            pos |= f > 0.0;
            neg |= f < 0.0;
            j += 1;
        }
        if pos || neg {
            let sign = match (pos, neg) {
                (true, false) => 1.0,
                (false, true) => -1.0,
                _ => 0.0,
            };
            groups.push((i, j, sign));
        }
        i = j;
    }
    // A clear group's facing that means entering: the first clear group
    // along the line is entered.
    let Some(first) = groups.iter().find(|g| g.2 != 0.0) else {
        return;
    };
    let enter_sign = first.2;
    let mut inside = false;
    for (g, &(a, b, sign)) in groups.iter().enumerate() {
        let now_inside = if sign != 0.0 {
            sign == enter_sign
        } else {
            // Inside after this point if the next clear group leaves.
            groups[g + 1..]
                .iter()
                .find(|n| n.2 != 0.0)
                .is_some_and(|n| n.2 != enter_sign)
        };
        if now_inside == inside {
            continue;
        }
        inside = now_inside;
        // The group's triangle that faces the way of the crossing.
        let k = (a..b)
            .find(|&k| (facing(k) * enter_sign > 0.0) == inside)
            .unwrap_or(a);
        let (t, tri, b1, b2) = found[k];
        let mut h = hit(t, tri, b1, b2);
        if (h.geo_normal.dot(ray.dir) < 0.0) != inside {
            h = h.flipped();
        }
        out.push(h);
    }
}

/// Crossings of one mesh closer than this (relative to `t`) are one point:
/// the triangles around a vertex give its `t` a few ulps apart.
const POINT_TOLERANCE: f64 = 1e-12;

#[derive(Debug)]
pub struct Mesh {
    data: Arc<MeshData>,
    smooth: bool,
    material: MaterialId,
}

impl Mesh {
    pub fn new(data: Arc<MeshData>, smooth: bool, material: MaterialId) -> Self {
        Mesh {
            data,
            smooth,
            material,
        }
    }

    pub fn data(&self) -> &Arc<MeshData> {
        &self.data
    }

    fn hit(&self, ray: &Ray, t: f64, tri: u32, b1: f64, b2: f64) -> Hit {
        let h = self.data.hit_record(ray, t, tri, b1, b2, self.smooth);
        Hit {
            t,
            normal: h.normal,
            uv: h.uv,
            local: h.local,
            point: h.point,
            p_error: h.p_error,
            geo_normal: h.geometric,
            material: self.material,
            path: 0,
        }
    }
}

impl Shape for Mesh {
    fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        let (t, tri, b1, b2) = self.data.nearest(ray, t_min, t_max)?;
        Some(self.hit(ray, t, tri, b1, b2))
    }

    fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        let d = &self.data;
        let sheared = ShearedRay::new(ray);
        d.tree.any(ray, t_min, t_max, |i| {
            d.pre[i as usize]
                .hit_sheared(&sheared, t_min, t_max)
                .is_some()
        })
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let d = &self.data;
        let mut found: Vec<(f64, u32, f64, f64)> = Vec::new();
        let sheared = ShearedRay::new(ray);
        d.tree.along_line(ray, |i| {
            if let Some((t, b1, b2)) =
                d.pre[i as usize].hit_sheared(&sheared, f64::NEG_INFINITY, f64::INFINITY)
            {
                found.push((t, i, b1, b2));
            }
        });
        // A triangle in several leaves is met once per leaf.
        found.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        found.dedup_by_key(|h| h.1);
        if d.is_closed() {
            solid_crossings(
                d,
                ray,
                &found,
                |t, tri, b1, b2| self.hit(ray, t, tri, b1, b2),
                out,
            );
            return;
        }
        let start = out.len();
        for (t, tri, b1, b2) in found {
            let h = self.hit(ray, t, tri, b1, b2);
            // A ray through an edge or vertex meets two or more triangles at
            // the same t going the same way: one crossing, not several, so
            // that entering and leaving keep alternating.
            if let Some(prev) = out[start..].last() {
                let same_t = (prev.t - h.t).abs() <= 1e-9 * (1.0 + h.t.abs());
                let same_way = (prev.normal.dot(ray.dir) > 0.0) == (h.normal.dot(ray.dir) > 0.0);
                if same_t && same_way {
                    continue;
                }
            }
            out.push(h);
        }
    }

    fn bounds(&self) -> Aabb {
        self.data.bounds()
    }

    fn is_solid(&self) -> bool {
        self.data.is_closed()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::ply::icosphere;
    use crate::shapes::testing;
    use proptest::prelude::*;

    fn sphere_mesh(levels: u32) -> Arc<MeshData> {
        let (p, t) = icosphere(levels);
        Arc::new(MeshData::from_parts(p, None, None, t))
    }

    /// The nearest hit by testing every triangle.
    fn brute(d: &MeshData, ray: &Ray) -> Option<f64> {
        d.pre
            .iter()
            .filter_map(|p| p.hit(ray, 1e-9, f64::INFINITY))
            .map(|h| h.0)
            .min_by(f64::total_cmp)
    }

    fn agree(d: &MeshData, rays: &[Ray]) -> usize {
        let mesh = Mesh::new(
            Arc::new(MeshData::from_parts(
                d.positions.clone(),
                None,
                None,
                d.triangles.clone(),
            )),
            false,
            0,
        );
        let mut hits = 0;
        for r in rays {
            let tree = mesh.intersect(r, 1e-9, f64::INFINITY).map(|h| h.t);
            let want = brute(d, r);
            assert_eq!(tree, want, "{r:?}");
            assert_eq!(mesh.occludes(r, 1e-9, f64::INFINITY), want.is_some());
            hits += want.is_some() as usize;
        }
        hits
    }

    #[test]
    fn icosphere_is_closed_outward_and_round() {
        let _watchdog = crate::watchdog::start();
        let d = sphere_mesh(3);
        assert_eq!(d.triangle_count(), 20 * 64);
        assert!(d.is_closed());
        for p in &d.pre {
            let centre = p.v0 + (p.e1() + p.e2()) / 3.0;
            assert!(p.normal().dot(centre) > 0.0, "inward triangle");
        }
        let mesh = Mesh::new(d.clone(), true, 0);
        assert!(mesh.is_solid());
        testing::check_consistency(&mesh, &testing::rays_towards(DVec3::ZERO, 1.2, 2000, 7));
        // An open mesh (one triangle removed) is not a solid.
        let (p, mut t) = icosphere(1);
        t.pop();
        assert!(!MeshData::from_parts(p, None, None, t).is_closed());
    }

    #[test]
    fn silhouette_matches_the_analytic_sphere() {
        let _watchdog = crate::watchdog::start();
        let d = sphere_mesh(3);
        // Every triangle's plane is at least `inner` from the centre: inside
        // that radius every ray must hit, beyond radius 1 none may.
        let inner = d
            .pre
            .iter()
            .map(|p| p.normal().normalize().dot(p.v0))
            .fold(f64::INFINITY, f64::min);
        assert!(inner > 0.99 && inner < 1.0);
        let mesh = Mesh::new(d, false, 0);
        let rays = testing::rays_towards(DVec3::ZERO, 0.0, 300, 3);
        for (k, r) in rays.iter().enumerate() {
            let dir = r.dir;
            let side = dir.any_orthonormal_vector();
            let side = glam::DQuat::from_axis_angle(dir, k as f64) * side;
            for (offset, must_hit) in [
                (0.0, true),
                (0.5, true),
                (inner - 1e-9, true),
                (1.0 + 1e-9, false),
                (1.3, false),
            ] {
                let ray = Ray::new(r.origin + side * offset, dir);
                let h = mesh.intersect(&ray, 0.0, f64::INFINITY);
                assert_eq!(h.is_some(), must_hit, "offset {offset}");
                if let Some(h) = h {
                    // Depth of the analytic sphere at this offset, within the
                    // tessellation's sag.
                    let centre_t = -r.origin.dot(dir);
                    let exact = centre_t - (1.0 - offset * offset).sqrt();
                    assert!((h.t - exact).abs() < 0.08, "{} vs {exact}", h.t);
                    assert!(h.normal.dot(dir) < 0.0, "outward normal faces the camera");
                }
            }
        }
    }

    #[test]
    fn smooth_normals_follow_the_sphere() {
        let _watchdog = crate::watchdog::start();
        let mesh = Mesh::new(sphere_mesh(2), true, 0);
        for r in testing::rays_towards(DVec3::ZERO, 0.7, 200, 5) {
            if let Some(h) = mesh.intersect(&r, 0.0, f64::INFINITY) {
                let p = r.at(h.t).normalize();
                assert!(h.normal.normalize().dot(p) > 0.999);
                assert!(h.uv.x >= 0.0 && h.uv.y >= 0.0 && h.uv.x + h.uv.y <= 1.0 + 1e-12);
            }
        }
    }

    #[test]
    fn tree_agrees_with_brute_force_on_a_sphere() {
        let _watchdog = crate::watchdog::start();
        let d = sphere_mesh(3);
        let hits = agree(&d, &testing::rays_towards(DVec3::ZERO, 1.5, 3000, 11));
        assert!(hits > 1000, "{hits}");
    }

    /// The Stanford bunny from the shared data folder: a missing one fails
    /// the test unless `RAYTRACE_SKIP_SHARED=1` (see `shared_data`).
    fn bunny() -> Option<MeshData> {
        let path = crate::shared_data::file("bunny.ply")?;
        Some(MeshData::load(&path).unwrap_or_else(|e| panic!("{}: {e:?}", path.display())))
    }

    #[test]
    fn tree_agrees_with_brute_force_on_the_bunny() {
        let _watchdog = crate::watchdog::start();
        let Some(d) = bunny() else { return };
        assert_eq!(d.triangle_count(), 69451);
        assert!(!d.is_closed(), "the bunny has holes in its base");
        let b = d.bounds();
        let hits = agree(&d, &testing::rays_towards(b.centre(), 0.1, 2000, 13));
        assert!(hits > 500, "{hits}");
    }

    /// The cost of the bunny benchmark's rays in the bunny's tree: camera
    /// rays of `benches/scenes/bunny.rt` (200x200, taken into the mesh's
    /// space as the renderer does, so their directions are not unit) and a
    /// shadow ray from each hit towards the light. Prints the figures
    /// (`--nocapture`) and holds the tree to them.
    #[test]
    fn bunny_rays_take_few_steps_and_tests() {
        let _watchdog = crate::watchdog::start();
        let Some(d) = bunny() else { return };
        let mesh = Mesh::new(Arc::new(d), true, 0);
        let (shift, scale) = (DVec3::new(0.3368, -0.6597, 0.0308), 20.0);
        let local = |p: DVec3| (p - shift) / scale;
        let (eye, light) = (DVec3::new(0.0, 2.5, 9.0), DVec3::new(5.0, 10.0, 7.0));
        let forward = (DVec3::new(0.0, 1.3, 0.0) - eye).normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        let half = 18f64.to_radians().tan();
        let n = 200;
        let tests = std::cell::Cell::new(0u64);
        let (mut rays, mut shadow_rays, mut hits) = (0u64, 0u64, 0u64);
        let (mut steps, mut shadow_steps, mut shadow_tests) = (0u64, 0u64, 0u64);
        crate::accel::counters::take();
        for j in 0..n {
            for i in 0..n {
                let x = (2.0 * (i as f64 + 0.5) / n as f64 - 1.0) * half;
                let y = (1.0 - 2.0 * (j as f64 + 0.5) / n as f64) * half;
                let dir = (forward + x * right + y * up).normalize() / scale;
                let ray = Ray::new(local(eye), dir);
                let mut best = f64::INFINITY;
                mesh.data
                    .tree
                    .nearest(&ray, 1e-9, f64::INFINITY, |k, limit| {
                        tests.set(tests.get() + 1);
                        let (t, _, _) = mesh.data.pre[k as usize].hit(&ray, 1e-9, limit)?;
                        best = t;
                        Some(t)
                    });
                rays += 1;
                steps += crate::accel::counters::take();
                if best.is_finite() {
                    hits += 1;
                    let p = ray.at(best);
                    let to_light = Ray::new(p, local(light) - p);
                    let before = tests.get();
                    mesh.data.tree.any(&to_light, 1e-6, 1.0, |k| {
                        tests.set(tests.get() + 1);
                        mesh.data.pre[k as usize]
                            .hit(&to_light, 1e-6, 1.0)
                            .is_some()
                    });
                    shadow_rays += 1;
                    shadow_tests += tests.get() - before;
                    shadow_steps += crate::accel::counters::take();
                }
            }
        }
        let primary_tests = tests.get() - shadow_tests;
        let per = |a: u64, b: u64| a as f64 / b.max(1) as f64;
        let s = mesh.data.tree.stats;
        eprintln!(
            "bunny tree: {} nodes, {} leaves ({} empty, max {}), {:.2} refs/triangle, depth {}; \
             camera rays: {hits}/{rays} hit, per hit {:.1} steps {:.1} tests; \
             shadow rays: {:.1} steps {:.1} tests",
            s.nodes,
            s.leaves,
            s.empty_leaves,
            s.max_leaf,
            per(s.references as u64, s.items as u64),
            s.max_depth,
            per(steps, hits),
            per(primary_tests, hits),
            per(shadow_steps, shadow_rays),
            per(shadow_tests, shadow_rays),
        );
        assert!(hits > 5000, "{hits}");
        // Before perfect splits and the tuned costs: 67 steps and 28 tests
        // per camera ray, 58 and 35 per shadow ray; now about 51 and 10.4,
        // 46 and 15.
        assert!(per(steps, hits) < 56.0 && per(primary_tests, hits) < 13.0);
        assert!(per(shadow_steps, shadow_rays) < 52.0 && per(shadow_tests, shadow_rays) < 18.0);
        assert!(s.references < 5 * s.items, "{s:?}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// The kd-tree may drop a triangle from a cell only if none of it
        /// is there: every point of the triangle inside the cell must lie
        /// in the box given for its side of the plane.
        #[test]
        fn split_triangle_keeps_every_point_in_the_cell(
            corners in proptest::array::uniform9(-2.0f64..2.0),
            axis in 0usize..3,
            at in 0.0f64..1.0,
        ) {
            let _watchdog = crate::watchdog::start();
            let c = corners;
            let tri = [
                DVec3::new(c[0], c[1], c[2]),
                DVec3::new(c[3], c[4], c[5]),
                DVec3::new(c[6], c[7], c[8]),
            ];
            let cell = Aabb::new(DVec3::new(-1.0, -0.5, -1.0), DVec3::new(1.0, 0.5, 0.25));
            let split = cell.min[axis] + at * cell.extent()[axis];
            let sides = split_triangle(tri, &cell, axis, split);
            let mut inside = [0, 0];
            for i in 0..=40 {
                for j in 0..=(40 - i) {
                    let (u, v) = (i as f64 / 40.0, j as f64 / 40.0);
                    let p = tri[0] + u * (tri[1] - tri[0]) + v * (tri[2] - tri[0]);
                    if !cell.contains(p) {
                        continue;
                    }
                    for (k, below) in [(0, true), (1, false)] {
                        if (below && p[axis] <= split) || (!below && p[axis] >= split) {
                            inside[k] += 1;
                            let b = sides[k];
                            prop_assert!(b.is_some(), "side {k} dropped, {p}");
                            let b = b.unwrap();
                            let grown = Aabb::new(b.min - DVec3::splat(1e-12), b.max + DVec3::splat(1e-12));
                            prop_assert!(grown.contains(p), "{p} outside {b:?}");
                        }
                    }
                }
            }
            // A box given must lie in its half of the cell.
            for (k, b) in sides.iter().enumerate() {
                if let Some(b) = b {
                    prop_assert!(cell.contains(b.min) && cell.contains(b.max));
                    let in_half = if k == 0 { b.max[axis] <= split } else { b.min[axis] >= split };
                    prop_assert!(in_half, "side {} box {:?}", k, b);
                }
            }
        }
    }

    #[test]
    fn split_triangle_tightens_and_drops() {
        let _watchdog = crate::watchdog::start();
        let cell = Aabb::new(DVec3::ZERO, DVec3::ONE);
        // A big triangle over the cell's corner at the origin, cut at x = 0.5:
        // the cell holds only a small part of it, all in the lower half.
        let tri = [
            DVec3::new(-1.0, -1.0, 0.5),
            DVec3::new(1.2, -1.0, 0.5),
            DVec3::new(-1.0, 1.2, 0.5),
        ];
        let [below, above] = split_triangle(tri, &cell, 0, 0.5);
        let b = below.expect("the corner is in the lower half");
        assert!(above.is_none(), "{above:?}");
        assert!(b.max.x < 0.21 && b.max.y < 0.21, "{b:?}");
        assert!((b.min.z - 0.5).abs() < 1e-9 && (b.max.z - 0.5).abs() < 1e-9);
        // Its box overlaps the cell but the triangle does not reach it.
        let far = tri.map(|p| p - DVec3::new(0.3, 0.3, 0.0));
        assert!(Aabb::new(far[1], far[2]).intersection(&cell).area() > 0.0);
        assert_eq!(split_triangle(far, &cell, 1, 0.5), [None, None]);
    }

    fn soup(seed: u64, n: usize) -> MeshData {
        let _watchdog = crate::watchdog::start();
        let mut s = seed | 1;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut pos = Vec::new();
        let mut tris = Vec::new();
        for i in 0..n as u32 {
            let c = DVec3::new(rnd(), rnd(), rnd()) * 3.0;
            let size = 0.05 + 0.5 * rnd().abs();
            for _ in 0..3 {
                pos.push(c + DVec3::new(rnd(), rnd(), rnd()) * size);
            }
            tris.push([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        // Some axis-aligned triangles, which lie in split planes.
        for k in 0..n as u32 / 10 {
            let z = (k % 5) as f64 * 0.5;
            let base = pos.len() as u32;
            pos.extend([
                DVec3::new(0.0, 0.0, z),
                DVec3::new(1.0, 0.0, z),
                DVec3::new(0.0, 1.0, z),
            ]);
            tris.push([base, base + 1, base + 2]);
        }
        MeshData::from_parts(pos, None, None, tris)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(24))]
        #[test]
        fn tree_agrees_with_brute_force_on_triangle_soups(seed in any::<u64>(), n in 1usize..400) {
            let _watchdog = crate::watchdog::start();
            let d = soup(seed, n);
            let mut rays = testing::rays_towards(DVec3::ZERO, 3.0, 300, seed);
            // Rays along the axes, with zero direction components.
            for k in 0..60 {
                let o = DVec3::new((k % 7) as f64 * 0.3 - 1.0, (k % 5) as f64 * 0.25, 10.0);
                rays.push(Ray::new(o, -DVec3::Z));
                rays.push(Ray::new(DVec3::new(-10.0, o.x, o.y), DVec3::X));
            }
            agree(&d, &rays);
        }
    }

    #[test]
    fn instances_share_one_mesh() {
        let _watchdog = crate::watchdog::start();
        let d = sphere_mesh(2);
        let a = Mesh::new(d.clone(), true, 1);
        let b = Mesh::new(d.clone(), false, 2);
        assert!(Arc::ptr_eq(a.data(), b.data()));
        assert_eq!(Arc::strong_count(&d), 3);
    }

    /// Rays from random points around a closed mesh aimed exactly at its
    /// vertices and at points of its edges (as rounded): each must hit, the
    /// mesh and `triangle` shapes made of the same corners must agree, and
    /// the crossings of the line must alternate (a lost or doubled crossing
    /// would flip a CSG ray's inside and outside).
    /// A closed box of twelve triangles, wound outwards: corner `min`,
    /// sides `size`.
    fn box_mesh(min: DVec3, size: DVec3) -> Arc<MeshData> {
        let pos: Vec<DVec3> = (0..8)
            .map(|i| {
                min + DVec3::new(
                    (i & 1) as f64 * size.x,
                    ((i >> 1) & 1) as f64 * size.y,
                    ((i >> 2) & 1) as f64 * size.z,
                )
            })
            .collect();
        let faces = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let tris = faces
            .iter()
            .flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]])
            .collect();
        Arc::new(MeshData::from_parts(pos, None, None, tris))
    }

    /// Squares per side of [`flat_grid`].
    const GRID: u32 = 40;

    /// A flat 40 × 40 grid of squares of side 0.1 in z = 0, centred on the
    /// origin, each cut along a diagonal: its vertices and the mesh.
    fn flat_grid() -> (Vec<DVec3>, Mesh) {
        let n = GRID;
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pos.push(DVec3::new(i as f64 * 0.1 - 2.0, j as f64 * 0.1 - 2.0, 0.0));
            }
        }
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                tris.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
        let mesh = Mesh::new(
            Arc::new(MeshData::from_parts(pos.clone(), None, None, tris)),
            false,
            0,
        );
        (pos, mesh)
    }

    fn check_watertight(d: Arc<MeshData>, seed: u64) {
        let mesh = Mesh::new(d.clone(), false, 0);
        let tris: Vec<crate::shapes::Triangle> = (0..d.triangle_count())
            .map(|i| {
                let [a, b, c] = d.triangle(i);
                crate::shapes::Triangle::new(a, b, c, 0)
            })
            .collect();
        let mut s = seed;
        let mut rnd = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64) / ((1u64 << 53) as f64)
        };
        let mut targets: Vec<DVec3> = d.positions.clone();
        for i in 0..d.triangle_count() {
            let [a, b, _] = d.triangle(i);
            targets.push(a + (b - a) * rnd());
            targets.push((a + b) * 0.5);
        }
        let centre = d.bounds().centre();
        for (k, &p) in targets.iter().enumerate() {
            // From outside, through the point into the (convex) solid: a ray
            // that only grazed a vertex could rightly miss by an ulp.
            let out = (p - centre).normalize();
            let wobble = DVec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            let dir = (out + 0.6 * wobble.reject_from(out)).normalize();
            let from = p + dir * (3.0 + k as f64 % 5.0);
            let ray = Ray::new(from, p - from);
            let hit = mesh.intersect(&ray, 0.0, f64::INFINITY);
            assert!(hit.is_some(), "ray at {p:?} from {from:?} slipped through");
            let by_tris = tris
                .iter()
                .filter_map(|t| t.intersect(&ray, 0.0, f64::INFINITY))
                .map(|h| h.t)
                .min_by(f64::total_cmp);
            // The same point: a vertex's triangles may give t an ulp apart,
            // and the tree stops at the first leaf holding one of them.
            let (a, b) = (hit.map(|h| h.t), by_tris);
            assert!(
                a.zip(b)
                    .is_some_and(|(a, b)| (a - b).abs() <= 1e-12 * b.abs()),
                "mesh {a:?} and triangles {b:?} disagree at {p:?}"
            );
            // Through an edge or a vertex the crossings alternate: the
            // fan around a vertex counts once, or not at all for a touch.
            testing::check_alternation(&mesh, &[ray]);
        }
    }

    /// Lines that touch a convex mesh at one vertex only (in the plane
    /// through it square to its radius, which supports an icosphere) meet
    /// triangles facing both ways there: the fan is a touch, and the
    /// crossings stay even and alternating, so CSG keeps its inside.
    #[test]
    fn lines_touching_a_vertex_keep_the_crossings_alternating() {
        let _watchdog = crate::watchdog::start();
        let d = sphere_mesh(2);
        let mesh = Mesh::new(d.clone(), false, 0);
        let centre = d.bounds().centre();
        let mut rays = Vec::new();
        for &v in &d.positions {
            let out = (v - centre).normalize();
            let a = out.any_orthonormal_vector();
            let b = out.cross(a);
            for k in 0..8 {
                let phi = k as f64 * std::f64::consts::TAU / 8.0 + 0.1;
                let dir = a * phi.cos() + b * phi.sin();
                rays.push(Ray::new(v - 3.0 * dir, dir));
            }
        }
        testing::check_alternation(&mesh, &rays);
        // And a cube's corner, met by a line that only grazes it.
        let cube = Mesh::new(box_mesh(DVec3::splat(-1.0), DVec3::splat(2.0)), false, 0);
        let corner = DVec3::splat(1.0);
        for dir in [
            DVec3::new(-1.0, -1.0, 1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(1.0, -1.0, -1.0),
        ] {
            let dir = dir.normalize();
            let ray = Ray::new(corner - 3.0 * dir, dir);
            testing::check_alternation(&cube, &[ray]);
        }
    }

    #[test]
    fn rays_at_vertices_and_edges_of_closed_meshes_always_hit() {
        check_watertight(sphere_mesh(2), 5);
        // A box made of twelve triangles, off-centre and far from unit size.
        let boxed = box_mesh(DVec3::new(1e3, -2e3, 5e2), DVec3::new(3.7, 1.3, 2.1));
        assert!(boxed.is_closed());
        check_watertight(boxed, 9);
    }

    /// The same flat grid through the kd-tree (`Mesh::intersect` and
    /// `occludes`): the walk must not lose a ray aimed at a vertex or an
    /// edge lying on one of its split planes, though the grid's box has no
    /// thickness and the planes are stored in f32.
    #[test]
    fn a_grid_has_no_cracks_through_its_kd_tree() {
        let _watchdog = crate::watchdog::start();
        let (pos, mesh) = flat_grid();
        let (mut missed, mut unblocked, mut rays) = (0, 0, 0);
        for eye in [
            DVec3::new(0.3, -0.2, 5.0),
            DVec3::new(-1.7, 2.9, 3.0),
            DVec3::new(4.0, 0.05, -2.5),
        ] {
            for &p in &pos {
                if p.x.abs() > 1.95 || p.y.abs() > 1.95 {
                    continue;
                }
                for q in [
                    p,
                    p + DVec3::new(0.05, 0.0, 0.0),
                    p + DVec3::new(0.0, 0.05, 0.0),
                    p + DVec3::new(0.05, 0.05, 0.0),
                ] {
                    let ray = Ray::new(eye, (q - eye).normalize());
                    rays += 1;
                    missed += mesh.intersect(&ray, 0.0, f64::INFINITY).is_none() as usize;
                    unblocked += !mesh.occludes(&ray, 0.0, f64::INFINITY) as usize;
                }
            }
        }
        assert_eq!((missed, unblocked), (0, 0), "of {rays} rays");
    }

    /// A flat grid of triangles seen by rays through its vertices and the
    /// middles of its edges: the triangle test lets none through
    /// (Möller-Trumbore with inclusive bounds let 123 of 37,636 such pixels
    /// through). The kd-tree's walk: `a_grid_has_no_cracks_through_its_kd_tree`.
    #[test]
    fn a_grid_has_no_cracks_at_its_vertices_and_edges() {
        let (pos, mesh) = flat_grid();
        let n = GRID;
        let eye = DVec3::new(0.3, -0.2, 5.0);
        let mut missed = 0;
        for &p in &pos {
            // Interior vertices and the middles of their edges.
            if p.x.abs() > 1.95 || p.y.abs() > 1.95 {
                continue;
            }
            for q in [
                p,
                p + DVec3::new(0.05, 0.0, 0.0),
                p + DVec3::new(0.05, 0.05, 0.0),
            ] {
                let ray = Ray::new(eye, (q - eye).normalize());
                let sheared = ShearedRay::new(&ray);
                let hit = mesh
                    .data
                    .pre
                    .iter()
                    .any(|t| t.hit_sheared(&sheared, 0.0, f64::INFINITY).is_some());
                missed += !hit as usize;
            }
        }
        assert_eq!(missed, 0);
        // Rays running along the edges, in the grid's plane from above it.
        for k in 0..n {
            let y = k as f64 * 0.1 - 2.0;
            let ray = Ray::new(DVec3::new(-1.0, y, 1.0), DVec3::new(0.0, 0.0, -1.0));
            let sheared = ShearedRay::new(&ray);
            assert!(
                mesh.data
                    .pre
                    .iter()
                    .any(|t| { t.hit_sheared(&sheared, 0.0, f64::INFINITY).is_some() })
            );
        }
    }
}
