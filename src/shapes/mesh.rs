//! Triangle meshes from files (read by `formats`), indexed by their own
//! kd-tree or wide BVH (`render { accel … }`, [`Accel`]).
//!
//! ```text
//! mesh "bunny.ply" { smooth  scale 20  material { colour rgb(0.8, 0.8, 0.8) } }
//! mesh "ico.ply"   { flat  translate <0, 1, 0> }
//! ```
//! The path is relative to the scene file. [`MeshData`] (vertices,
//! triangles, per-triangle corners and the index) is built once per file and
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
//! by exactly two triangles, corners compared by position (a uv seam
//! repeats a corner; it is not a hole).

use super::{Hit, Shape, ShearedRay, barycentric_point};
use crate::accel::bvh::TriangleBvh;
use crate::accel::{Accel, BuildParams, KdTree};
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

/// The structure that finds a ray's triangles. Both give the same nearest
/// hit: the same `f64` watertight test decides every triangle.
#[derive(Debug)]
enum Index {
    Kd(KdTree),
    Bvh(TriangleBvh),
}

/// Triangles loaded once and shared by every placement (instancing).
#[derive(Debug)]
pub struct MeshData {
    positions: Vec<DVec3>,
    /// Vertex normals (from the file, or area-weighted), for `smooth`.
    normals: Vec<DVec3>,
    uvs: Option<Vec<DVec2>>,
    triangles: Vec<[u32; 3]>,
    /// The corners copied out per triangle, for the kd-tree's tests (whose
    /// leaves hold only indices); empty under the BVH, whose leaves hold
    /// the corners themselves: see [`MeshData::tri`].
    pre: Vec<TriPre>,
    index: Index,
    /// Worked out when first asked (CSG asks; a render alone never does):
    /// its edge sort is a noticeable part of loading a big mesh.
    closed: std::sync::OnceLock<bool>,
    /// A closed mesh's facing where a line enters it, worked out with
    /// `closed`: see [`MeshData::entering_facing`].
    entering: std::sync::OnceLock<f64>,
}

impl MeshData {
    /// The mesh in a file (see [`formats::read_mesh`]).
    pub fn load(path: &Path) -> Result<MeshData, MeshFileError> {
        Self::load_with(path, Accel::default())
    }

    /// The mesh in a file, indexed by `accel`.
    pub fn load_with(path: &Path, accel: Accel) -> Result<MeshData, MeshFileError> {
        Ok(Self::from_soup_with(formats::read_mesh(path)?, accel))
    }

    /// The mesh in a PLY file's bytes.
    pub fn from_bytes(bytes: &[u8]) -> Result<MeshData, MeshFileError> {
        Self::from_bytes_with(bytes, Accel::default())
    }

    /// The mesh in a PLY file's bytes, indexed by `accel`.
    pub fn from_bytes_with(bytes: &[u8], accel: Accel) -> Result<MeshData, MeshFileError> {
        Ok(Self::from_soup_with(formats::ply::parse(bytes)?, accel))
    }

    /// The mesh of what a reader produced.
    pub fn from_soup(soup: TriangleSoup) -> MeshData {
        Self::from_soup_with(soup, Accel::default())
    }

    /// The mesh of what a reader produced, indexed by `accel`.
    pub fn from_soup_with(soup: TriangleSoup, accel: Accel) -> MeshData {
        Self::from_parts_with(
            soup.positions,
            soup.normals,
            soup.uvs,
            soup.triangles,
            accel,
        )
    }

    /// Builds from arrays already checked (indices in range, finite
    /// positions); the PLY reader guarantees that.
    pub fn from_parts(
        positions: Vec<DVec3>,
        normals: Option<Vec<DVec3>>,
        uvs: Option<Vec<DVec2>>,
        triangles: Vec<[u32; 3]>,
    ) -> MeshData {
        Self::from_parts_with(positions, normals, uvs, triangles, Accel::default())
    }

    /// [`MeshData::from_parts`] indexed by `accel`.
    pub fn from_parts_with(
        positions: Vec<DVec3>,
        normals: Option<Vec<DVec3>>,
        uvs: Option<Vec<DVec2>>,
        triangles: Vec<[u32; 3]>,
        accel: Accel,
    ) -> MeshData {
        let corner = |t: &[u32; 3], k: usize| positions[t[k] as usize];
        let pre: Vec<TriPre> = match accel {
            Accel::KdTree => triangles.iter().map(|t| tri_pre(&positions, t)).collect(),
            // Auto: the BVH for a mesh's triangles.
            Accel::Bvh | Accel::Auto => Vec::new(),
        };
        let build = || match accel {
            Accel::KdTree => {
                let boxes: Vec<Aabb> = triangles
                    .iter()
                    .map(|t| Aabb::new(corner(t, 0), corner(t, 1)).grow(corner(t, 2)))
                    .collect();
                let clip = |i: u32, cell: &Aabb, axis: usize, split: f64| {
                    let t = &triangles[i as usize];
                    split_triangle([0, 1, 2].map(|k| corner(t, k)), cell, axis, split)
                };
                let tree = KdTree::build_clipped(&boxes, &clip, MESH_TREE);
                crate::accel::record_mesh_tree(&tree.stats);
                Index::Kd(tree)
            }
            Accel::Bvh | Accel::Auto => {
                let corners: Vec<[DVec3; 3]> = triangles
                    .iter()
                    .map(|t| [0, 1, 2].map(|k| corner(t, k)))
                    .collect();
                let bvh = TriangleBvh::build(&corners);
                crate::accel::record_mesh_bvh(bvh.stats());
                Index::Bvh(bvh)
            }
        };
        // The tree's first levels run on one thread: the rest of the set-up
        // fills the other.
        let (index, normals) = rayon::join(build, || match normals {
            Some(n) => n,
            None => area_weighted_normals(&positions, &triangles),
        });
        MeshData {
            positions,
            normals,
            uvs,
            triangles,
            pre,
            index,
            closed: std::sync::OnceLock::new(),
            entering: std::sync::OnceLock::new(),
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Every triangle's corners, in order.
    #[cfg(test)]
    fn all_tris(&self) -> Vec<TriPre> {
        (0..self.triangles.len() as u32)
            .map(|i| self.tri(i))
            .collect()
    }

    /// Triangle `i`'s corners: copied out for the kd-tree, read through
    /// the index under the BVH (which only asks for the nearest hit's).
    #[inline]
    fn tri(&self, i: u32) -> TriPre {
        match self.pre.get(i as usize) {
            Some(p) => *p,
            None => tri_pre(&self.positions, &self.triangles[i as usize]),
        }
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn bounds(&self) -> Aabb {
        match &self.index {
            Index::Kd(t) => t.bounds(),
            Index::Bvh(b) => b.bounds(),
        }
    }

    /// Which structure indexes the triangles.
    pub fn accel(&self) -> Accel {
        match &self.index {
            Index::Kd(_) => Accel::KdTree,
            Index::Bvh(_) => Accel::Bvh,
        }
    }

    pub fn is_closed(&self) -> bool {
        *self
            .closed
            .get_or_init(|| is_closed(&self.positions, &self.triangles))
    }

    /// The sign of `normal · dir` of a closed mesh's triangles where a line
    /// enters it: −1 wound outwards, +1 wound inwards, by the sign of the
    /// volume the triangles enclose; 0 where that is 0 (nothing inside).
    fn entering_facing(&self) -> f64 {
        *self
            .entering
            .get_or_init(|| entering_facing(&self.positions, &self.triangles))
    }

    /// The kd-tree's figures, when a kd-tree indexes the triangles.
    pub fn tree_stats(&self) -> Option<&crate::accel::TreeStats> {
        match &self.index {
            Index::Kd(t) => Some(&t.stats),
            Index::Bvh(_) => None,
        }
    }

    /// The wide BVH's figures, when a BVH indexes the triangles.
    pub fn bvh_stats(&self) -> Option<&crate::accel::bvh::BvhStats> {
        match &self.index {
            Index::Bvh(b) => Some(b.stats()),
            Index::Kd(_) => None,
        }
    }

    /// Forces the BVH's scalar or AVX2 path (tests run both).
    #[cfg(test)]
    pub(crate) fn set_simd(&mut self, simd: crate::accel::bvh::Simd) {
        if let Index::Bvh(b) = &mut self.index {
            b.set_simd(simd);
        }
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
            + self.triangles.len() * size_of::<[u32; 3]>()
            + self.pre.len() * size_of::<TriPre>()
            + match &self.index {
                Index::Kd(t) => t.memory(),
                Index::Bvh(b) => b.memory(),
            }
    }

    /// Nearest triangle: `(t, triangle, b1, b2)`.
    #[inline]
    fn nearest(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(f64, u32, f64, f64)> {
        let mut rec = (0u32, 0.0, 0.0);
        let sheared = ShearedRay::new(ray);
        let tree = match &self.index {
            Index::Kd(tree) => tree,
            Index::Bvh(bvh) => {
                // The BVH finds the triangle and its t; the barycentrics
                // come from the one scalar test, for the nearest only.
                let (t, i) = bvh.nearest(ray, &sheared, t_min, t_max)?;
                let (t1, b1, b2) = self.tri(i).hit_sheared(&sheared, t_min, t_max)?;
                debug_assert_eq!(t.to_bits(), t1.to_bits());
                return Some((t1, i, b1, b2));
            }
        };
        let t = tree.nearest(ray, t_min, t_max, |i, best| {
            let (t, b1, b2) = self.pre[i as usize].hit_sheared(&sheared, t_min, best)?;
            rec = (i, b1, b2);
            Some(t)
        })?;
        Some((t, rec.0, rec.1, rec.2))
    }

    fn hit_record(&self, ray: &Ray, t: f64, tri: u32, b1: f64, b2: f64, smooth: bool) -> MeshHit {
        let pre = &self.tri(tri);
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

/// A triangle's corners out of the vertex array.
#[inline]
fn tri_pre(positions: &[DVec3], t: &[u32; 3]) -> TriPre {
    TriPre {
        v0: positions[t[0] as usize],
        v1: positions[t[1] as usize],
        v2: positions[t[2] as usize],
    }
}

/// Each vertex gets the sum of its triangles' unnormalised normals
/// (|e1 × e2| is twice the area, so big faces weigh more), normalised.
fn area_weighted_normals(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<DVec3> {
    let mut n = vec![DVec3::ZERO; positions.len()];
    for t in triangles {
        let face = tri_pre(positions, t).normal();
        for &k in t {
            n[k as usize] += face;
        }
    }
    for v in &mut n {
        *v = v.normalize_or_zero();
    }
    n
}

/// Every undirected edge used by exactly two triangles, with vertices
/// compared by position: files split a vertex where its uv or normal
/// changes (OBJ's `v/vt` pairs, a PLY with per-face uv), and such a seam
/// is still a closed surface for CSG.
fn is_closed(positions: &[DVec3], triangles: &[[u32; 3]]) -> bool {
    if triangles.is_empty() {
        return false;
    }
    let weld = welded_indices(positions);
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(triangles.len() * 3);
    for t in triangles {
        let t = t.map(|k| weld[k as usize]);
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

/// See [`MeshData::entering_facing`]. Six times the signed volume, summed
/// about a corner of the mesh rather than the origin (far from the origin
/// the terms would cancel down to rounding); any point gives the same sum
/// for a closed surface.
fn entering_facing(positions: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    let Some(&o) = positions.first() else {
        return 0.0;
    };
    let volume: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| positions[k as usize] - o);
            a.dot(b.cross(c))
        })
        .sum();
    if volume > 0.0 {
        -1.0
    } else if volume < 0.0 {
        1.0
    } else {
        0.0
    }
}

/// For each vertex, the lowest index of a vertex at exactly the same
/// position (−0 and +0 are one coordinate). Exact equality, never a
/// tolerance: two vertices a rounding apart are a crack, and the
/// watertight triangle test would let a ray through it.
fn welded_indices(positions: &[DVec3]) -> Vec<u32> {
    let key = |i: u32| {
        let p = positions[i as usize] + DVec3::ZERO;
        [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
    };
    let mut order: Vec<u32> = (0..positions.len() as u32).collect();
    order.sort_unstable_by_key(|&i| (key(i), i));
    let mut weld = vec![0; positions.len()];
    let mut first = 0;
    for (k, &i) in order.iter().enumerate() {
        if k == 0 || key(i) != key(order[k - 1]) {
            first = i;
        }
        weld[i as usize] = first;
    }
    weld
}

/// A closed mesh's crossings for CSG, which must alternate entering and
/// leaving. Each triangle's winding tells the way (its geometric normal;
/// a smooth normal can disagree near a silhouette), and a mesh wound
/// inwards is recognised by its first crossing when that is clear (a
/// closed surface is entered first; this also holds a mesh whose parts
/// are wound different ways), else by the sign of the volume it encloses:
/// a line can enter through a saddle vertex, whose triangles face both
/// ways, and then the first clear crossing is where it leaves (a mesh
/// enclosing no volume falls back on that crossing).
/// Triangles met at one point (the two sharing an edge,
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
    let facing = |k: usize| d.tri(found[k].1).normal().dot(ray.dir);
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
    // A clear group's facing that means entering: the first group's,
    // when it is clear (a closed surface is entered first); after a mixed
    // group (a touch, or a saddle vertex crossed through) the winding's.
    let Some(first) = groups.iter().position(|g| g.2 != 0.0) else {
        return;
    };
    let enter_sign = match (first, d.entering_facing()) {
        (0, _) | (_, 0.0) => groups[first].2,
        (_, s) => s,
    };
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
        match &d.index {
            Index::Kd(tree) => tree.any(ray, t_min, t_max, |i| {
                d.pre[i as usize]
                    .hit_sheared(&sheared, t_min, t_max)
                    .is_some()
            }),
            Index::Bvh(bvh) => bvh.any(ray, &sheared, t_min, t_max),
        }
    }

    fn crossings(&self, ray: &Ray, out: &mut Vec<Hit>) {
        let d = &self.data;
        let mut found: Vec<(f64, u32, f64, f64)> = Vec::new();
        let sheared = ShearedRay::new(ray);
        let mut visit = |i: u32| {
            if let Some((t, b1, b2)) =
                d.tri(i)
                    .hit_sheared(&sheared, f64::NEG_INFINITY, f64::INFINITY)
            {
                found.push((t, i, b1, b2));
            }
        };
        match &d.index {
            Index::Kd(tree) => tree.along_line(ray, visit),
            Index::Bvh(bvh) => bvh.along_line(ray, &sheared, |_, i| visit(i)),
        }
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
#[path = "mesh_tests.rs"]
pub(crate) mod tests;

#[cfg(test)]
#[path = "mesh_crossing_tests.rs"]
mod crossing_tests;
