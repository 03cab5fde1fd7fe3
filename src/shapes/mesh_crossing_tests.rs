//! Cases mutation testing found unbuilt: a closed mesh's crossings where
//! the triangles met at one point face both ways along the line, though
//! the line crosses the surface there (a saddle vertex crossed through);
//! an open mesh's crossings at a shared edge met near the line's origin;
//! and the kd-tree's clipping of triangles a rounding outside a small
//! cell far from the origin.

use super::tests::{box_mesh, each_index};
use super::*;

/// An L-shaped prism scaled by `s`: the L (0,0), (2,0), (2,1), (1,1),
/// (1,2), (0,2) anticlockwise in xy, from z = 0 to 2, wound outwards; the
/// caps are fans from the reflex corner (1, 1). `y_wall_first` lists the
/// wall y = 1's triangle at (1, 1, 0) first (a point's triangles are taken
/// in the order of the list).
fn l_prism(s: f64, y_wall_first: bool) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let l = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let mut pos: Vec<DVec3> = l.iter().map(|&(x, y)| s * DVec3::new(x, y, 0.0)).collect();
    pos.extend(l.iter().map(|&(x, y)| s * DVec3::new(x, y, 2.0)));
    let fan = [[3, 4, 5], [3, 5, 0], [3, 0, 1], [3, 1, 2]];
    let mut tris: Vec<[u32; 3]> = Vec::new();
    for [a, b, c] in fan {
        tris.push([a, c, b]);
        tris.push([a + 6, b + 6, c + 6]);
    }
    for i in 0..6 {
        let j = (i + 1) % 6;
        tris.push([i, j, j + 6]);
        tris.push([i, j + 6, i + 6]);
    }
    if y_wall_first {
        let k = tris.iter().position(|&t| t == [2, 3, 9]).unwrap();
        tris.swap(0, k);
    }
    (pos, tris)
}

/// The line through the reflex corner (1, 1, 0) of the L's floor along
/// (−1, ½, 1) enters the prism there: behind it z < 0, ahead x < 1. The
/// floor (−z) and the wall x = 1 (+x) face against the line, the wall
/// y = 1 (+y) faces along it: the corner's triangles face both ways, and
/// still the line crosses. It leaves through x = 0 at (0, 3/2, 1). Both
/// ways along it, the crossings are that entry and that exit, and the one
/// at the corner has the outward normal of one of the corner's faces that
/// faces the way it is crossed (not a face turned over): at two scales,
/// wound either way, and far from the origin.
#[test]
fn a_line_through_a_saddle_corner_crosses_there() {
    let _watchdog = crate::watchdog::start();
    let corner_faces = [-DVec3::Z, DVec3::X, DVec3::Y];
    // Small and large; wound inwards; and 10⁸ from the origin, where the
    // winding's volume summed about the origin (or any far point) would
    // cancel to rounding of 10⁸ times the volume.
    let mut cases = vec![
        (0.25, DVec3::ZERO, false),
        (4.0, DVec3::ZERO, false),
        (0.25, DVec3::ZERO, true),
    ];
    for k in 0..6 {
        let far = DVec3::new(1e8 + 3e7 * k as f64, -7e7 + 1e7 * k as f64, 4e7);
        cases.extend([(1.0, far, false), (1.0, far, true)]);
    }
    for (s, at, inward) in cases {
        for y_wall_first in [false, true] {
            let (pos, mut tris) = l_prism(s, y_wall_first);
            let pos: Vec<DVec3> = pos.iter().map(|&p| at + p).collect();
            if inward {
                tris = tris.iter().map(|&[a, b, c]| [a, c, b]).collect();
            }
            for (name, d) in each_index(&pos, &tris) {
                let name = format!(
                    "{name}, scale {s} at {at}, inward {inward}, y wall first {y_wall_first}"
                );
                let mesh = Mesh::new(Arc::new(d), false, 0);
                assert!(mesh.is_solid(), "{name}");
                let corner = at + s * DVec3::new(1.0, 1.0, 0.0);
                let exit = at + s * DVec3::new(0.0, 1.5, 1.0);
                let dir = DVec3::new(-1.0, 0.5, 1.0);
                for (from, dir, at) in [(corner, dir, [corner, exit]), (exit, -dir, [exit, corner])]
                {
                    let ray = Ray::new(from - 3.0 * s * dir, dir);
                    let mut xs = Vec::new();
                    mesh.crossings(&ray, &mut xs);
                    let points: Vec<DVec3> = xs.iter().map(|h| ray.at(h.t)).collect();
                    assert_eq!(points, at, "{name}: {xs:?}");
                    assert!(
                        xs[0].geo_normal.dot(dir) < 0.0 && xs[1].geo_normal.dot(dir) > 0.0,
                        "{name}: {xs:?}"
                    );
                    let h = if at[0] == corner { &xs[0] } else { &xs[1] };
                    let n = h.geo_normal.normalize();
                    assert!(
                        corner_faces.iter().any(|&f| (n - f).length() < 1e-12),
                        "{name}: the corner's crossing has normal {n}, no face's there"
                    );
                }
            }
        }
    }
}

/// An open sheet of two triangles whose shared edge runs from (−a, −b, za)
/// to (a, b, −za + 2·10⁻¹²), crossed along z by the line through the
/// origin, which meets the edge at its midpoint, t = 10⁻¹². The edge's
/// ends lie on either side of the origin along the line, so each
/// triangle's t is a weighted sum of depths ±0.3 that cancel: the two
/// triangles give t some 10⁻¹⁷ apart (their weights are rounded
/// differently), relatively far more than ulps. Still one point of the
/// sheet: one crossing, at t = 10⁻¹² to within that rounding.
#[test]
fn a_shared_edge_met_near_the_lines_origin_is_one_crossing() {
    let _watchdog = crate::watchdog::start();
    let ray = Ray::new(DVec3::ZERO, DVec3::Z);
    let mut apart = 0;
    for i in 0..8 {
        for j in 0..4 {
            let (a, b) = (0.1 + 0.0873 * i as f64, 0.3 - 0.031 * j as f64);
            let za = -0.3 - 0.01 * j as f64;
            let pos = vec![
                DVec3::new(-a, -b, za),
                DVec3::new(a, b, -za + 2e-12),
                DVec3::new(0.7 + 0.01 * i as f64, -0.2, 0.1),
                DVec3::new(-0.6, 0.4 + 0.013 * j as f64, -0.1),
            ];
            let tris = vec![[0, 1, 3], [0, 2, 1]];
            for (name, d) in each_index(&pos, &tris) {
                let sheared = ShearedRay::new(&ray);
                let ts: Vec<f64> = (0..2)
                    .filter_map(|k| d.tri(k).hit_sheared(&sheared, -1.0, 1.0))
                    .map(|h| h.0)
                    .collect();
                assert_eq!(ts.len(), 2, "{name}, {i} {j}: both triangles meet the edge");
                apart += (ts[0] != ts[1]) as usize;
                let mesh = Mesh::new(Arc::new(d), false, 0);
                assert!(!mesh.is_solid());
                let mut xs = Vec::new();
                mesh.crossings(&ray, &mut xs);
                assert_eq!(xs.len(), 1, "{name}, {i} {j}: {ts:?} {xs:?}");
                assert!((xs[0].t - 1e-12).abs() < 1e-15, "{name}: {xs:?}");
            }
        }
    }
    // The case this is about: the two t differ.
    assert!(apart > 20, "{apart}");
}

/// The kd-tree's clipping keeps a triangle that comes within rounding of
/// a cell (its doc: so that rounding in the ray test can never lose it
/// from a cell where the ray finds it), and rounding is relative to the
/// coordinates, not to the cell: a cell 2⁻³⁰ wide at 1 from the origin
/// keeps triangles lying 1 to 8 ulps of 1 outside any of its faces (the
/// ray test's points there are rounded to ulps of 1, so may fall inside),
/// and drops one 10⁻⁷ outside (far past any rounding).
#[test]
fn a_small_cell_far_out_keeps_triangles_a_rounding_outside_it() {
    let lo = 1.0;
    let hi = 1.0 + 2f64.powi(-30);
    let cell = Aabb::new(DVec3::splat(lo), DVec3::splat(hi));
    let ulp = f64::EPSILON;
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        // A triangle across the whole cell in the other two axes, in the
        // plane `axis` = at.
        let tri = |at: f64| {
            [(-1.0, -1.0), (3.0, -1.0), (-1.0, 3.0)].map(|(a, b)| {
                let mut p = DVec3::ZERO;
                p[axis] = at;
                p[u] = a;
                p[v] = b;
                p
            })
        };
        let split = 0.5 * (lo + hi);
        for k in [1.0, 2.0, 8.0] {
            for (at, side) in [(lo - k * ulp / 2.0, 0), (hi + k * ulp, 1)] {
                let boxes = split_triangle(tri(at), &cell, axis, split);
                let b = boxes[side].unwrap_or_else(|| panic!("axis {axis}, {at}: dropped"));
                assert!(cell.contains(b.min) && cell.contains(b.max), "{b:?}");
            }
        }
        for at in [lo - 1e-7, hi + 1e-7] {
            assert_eq!(split_triangle(tri(at), &cell, axis, split), [None, None]);
        }
    }
}

/// A mesh whose parts are wound different ways (a big box wound outwards,
/// a small one inwards, as merged files can be): a line meeting one part
/// only, first at a clear crossing, is entered there and left again,
/// whatever the volume's sign says of the whole.
#[test]
fn parts_wound_different_ways_are_each_entered_first() {
    let _watchdog = crate::watchdog::start();
    let big = box_mesh(DVec3::ZERO, DVec3::splat(4.0));
    let small = box_mesh(DVec3::new(10.0, 0.0, 0.0), DVec3::ONE);
    let mut pos = big.positions.clone();
    pos.extend(&small.positions);
    let mut tris = big.triangles.clone();
    tris.extend(
        small
            .triangles
            .iter()
            .map(|&[a, b, c]| [a + 8, c + 8, b + 8]),
    );
    for (name, d) in each_index(&pos, &tris) {
        let mesh = Mesh::new(Arc::new(d), false, 0);
        assert!(mesh.is_solid(), "{name}");
        let dir = DVec3::new(0.2, 0.3, 1.0);
        for centre in [DVec3::splat(2.0), DVec3::new(10.5, 0.5, 0.5)] {
            let ray = Ray::new(centre - 4.0 * dir, dir);
            let mut xs = Vec::new();
            mesh.crossings(&ray, &mut xs);
            assert_eq!(xs.len(), 2, "{name}: {xs:?}");
            assert!(
                xs[0].normal.dot(dir) < 0.0 && xs[1].normal.dot(dir) > 0.0,
                "{name}: {centre} {xs:?}"
            );
        }
    }
}
