//! Stage 3, ACCELERATE: the index the renderer asks for the nearest hit.
//!
//! Bounded objects go into a kd-tree ([`KdTree`], the same structure that
//! indexes the triangles of each mesh); unbounded ones (planes, some
//! implicit surfaces) are tested one by one beside it.

mod kdtree;

#[cfg(test)]
pub(crate) use kdtree::counters;
pub use kdtree::{BuildParams, Clip, KdTree, TreeStats};

use crate::geometry::Ray;
use crate::shapes::{Hit, Shape};
use std::sync::atomic::{AtomicU64, Ordering};

/// Counts for `--stats`.
#[derive(Clone, Debug, Default)]
pub struct AccelStats {
    pub objects: usize,
    pub unbounded: usize,
    /// Nodes of the scene-level tree.
    pub nodes: usize,
    pub build_seconds: f64,
    /// The scene-level tree in full.
    pub tree: TreeStats,
    /// Every mesh tree built so far in this process (meshes are built while
    /// the scene is, before the world; instances share one tree).
    pub meshes: MeshTreeTotals,
}

/// Sums over the kd-trees of the meshes loaded.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeshTreeTotals {
    pub trees: u64,
    pub triangles: u64,
    pub nodes: u64,
    pub leaves: u64,
    pub references: u64,
    pub max_depth: u64,
    pub build_seconds: f64,
}

static MESH_TREES: [AtomicU64; 7] = [const { AtomicU64::new(0) }; 7];

/// Called by each mesh once its tree is built.
pub(crate) fn record_mesh_tree(s: &TreeStats) {
    let m = &MESH_TREES;
    m[0].fetch_add(1, Ordering::Relaxed);
    m[1].fetch_add(s.items as u64, Ordering::Relaxed);
    m[2].fetch_add(s.nodes as u64, Ordering::Relaxed);
    m[3].fetch_add(s.leaves as u64, Ordering::Relaxed);
    m[4].fetch_add(s.references as u64, Ordering::Relaxed);
    m[5].fetch_max(s.max_depth as u64, Ordering::Relaxed);
    m[6].fetch_add((s.build_seconds * 1e9) as u64, Ordering::Relaxed);
}

fn mesh_totals() -> MeshTreeTotals {
    let v: Vec<u64> = MESH_TREES
        .iter()
        .map(|a| a.load(Ordering::Relaxed))
        .collect();
    MeshTreeTotals {
        trees: v[0],
        triangles: v[1],
        nodes: v[2],
        leaves: v[3],
        references: v[4],
        max_depth: v[5],
        build_seconds: v[6] as f64 * 1e-9,
    }
}

/// The last few objects a ray was tested against. An object spanning
/// several leaves would otherwise be intersected once per leaf, and an
/// object (a placed mesh) can cost thousands of instructions. Skipping a
/// repeat is exact: the search limit only shrinks, so a second test could
/// not find anything the first did not.
struct Mailbox {
    ids: [u32; 8],
    next: usize,
}

impl Default for Mailbox {
    fn default() -> Self {
        Mailbox {
            ids: [u32::MAX; 8],
            next: 0,
        }
    }
}

impl Mailbox {
    #[inline]
    fn seen(&mut self, id: u32) -> bool {
        if self.ids.contains(&id) {
            return true;
        }
        self.ids[self.next % 8] = id;
        self.next += 1;
        false
    }
}

/// The scene's objects, indexed for ray queries.
#[derive(Debug)]
pub struct World {
    bounded: Vec<Box<dyn Shape>>,
    tree: KdTree,
    unbounded: Vec<Box<dyn Shape>>,
    pub stats: AccelStats,
}

impl World {
    pub fn build(objects: Vec<Box<dyn Shape>>) -> World {
        let start = std::time::Instant::now();
        let (mut bounded, mut unbounded) = (Vec::new(), Vec::new());
        for o in objects {
            if o.bounds().is_finite() {
                bounded.push(o);
            } else {
                unbounded.push(o);
            }
        }
        let boxes: Vec<_> = bounded.iter().map(|o| o.bounds()).collect();
        let tree = KdTree::build(&boxes);
        let stats = AccelStats {
            objects: bounded.len() + unbounded.len(),
            unbounded: unbounded.len(),
            nodes: tree.stats.nodes,
            build_seconds: start.elapsed().as_secs_f64(),
            tree: tree.stats,
            meshes: mesh_totals(),
        };
        World {
            bounded,
            tree,
            unbounded,
            stats,
        }
    }

    pub fn intersect(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<Hit> {
        self.nearest(ray, t_min, t_max).map(|(h, _)| h)
    }

    /// The nearest hit and the object that made it (which gives the hit's
    /// texture coordinates, see [`Shape::uv`]).
    pub fn nearest(&self, ray: &Ray, t_min: f64, t_max: f64) -> Option<(Hit, &dyn Shape)> {
        let mut best: Option<(Hit, &dyn Shape)> = None;
        let mut t_best = t_max;
        for o in &self.unbounded {
            if let Some(h) = o.intersect(ray, t_min, t_best) {
                t_best = h.t;
                best = Some((h, &**o));
            }
        }
        let mut mailbox = Mailbox::default();
        self.tree.nearest(ray, t_min, t_best, |i, limit| {
            if mailbox.seen(i) {
                return None;
            }
            let o = &*self.bounded[i as usize];
            let h = o.intersect(ray, t_min, limit)?;
            best = Some((h, o));
            Some(h.t)
        });
        best
    }

    pub fn occludes(&self, ray: &Ray, t_min: f64, t_max: f64) -> bool {
        self.unbounded.iter().any(|o| o.occludes(ray, t_min, t_max)) || {
            let mut mailbox = Mailbox::default();
            self.tree.any(ray, t_min, t_max, |i| {
                !mailbox.seen(i) && self.bounded[i as usize].occludes(ray, t_min, t_max)
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::DVec3;
    use crate::shapes::{Plane, Sphere};

    #[test]
    fn world_agrees_with_a_linear_scan() {
        let _watchdog = crate::watchdog::start();
        let mut s = 0x9e3779b97f4a7c15u64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let spheres: Vec<Sphere> = (0..300)
            .map(|i| {
                let c = DVec3::new(rnd(), rnd(), rnd()) * 10.0;
                Sphere::new(c, 0.1 + rnd().abs(), i)
            })
            .collect();
        let mut objects: Vec<Box<dyn Shape>> = spheres
            .iter()
            .map(|s| Box::new(s.clone()) as Box<dyn Shape>)
            .collect();
        objects.push(Box::new(Plane::new(DVec3::Y, -9.0, 999)));
        let world = World::build(objects);
        assert_eq!(world.stats.unbounded, 1);
        assert!(world.stats.tree.leaves > 10, "{:?}", world.stats.tree);
        let floor = Plane::new(DVec3::Y, -9.0, 999);
        for _ in 0..3000 {
            let o = DVec3::new(rnd(), rnd(), rnd()) * 15.0;
            let d = DVec3::new(rnd(), rnd(), rnd()).normalize_or(DVec3::X);
            let ray = Ray::new(o, d);
            let want = spheres
                .iter()
                .map(|s| s as &dyn Shape)
                .chain([&floor as &dyn Shape])
                .filter_map(|s| s.intersect(&ray, 1e-9, f64::INFINITY))
                .min_by(|a, b| a.t.total_cmp(&b.t));
            let got = world.intersect(&ray, 1e-9, f64::INFINITY);
            assert_eq!(
                got.map(|h| (h.t, h.material)),
                want.map(|h| (h.t, h.material))
            );
            // Shadow rays: blocked just past the nearest hit, free just before.
            let t = want.map_or(f64::INFINITY, |h| h.t);
            assert_eq!(world.occludes(&ray, 1e-9, t * 1.001), want.is_some());
            if want.is_some() {
                assert!(!world.occludes(&ray, 1e-9, t * 0.999));
            }
        }
    }
}
