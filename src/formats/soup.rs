//! The neutral form every mesh reader produces and `shapes::MeshData`
//! consumes: positions, optional per-vertex normals and uv, and triangles
//! as index triples, already checked (indices in range, finite positions),
//! so the mesh may trust them. Also the error a reader reports and the
//! polygon cutting every reader shares.

use crate::geometry::{DVec2, DVec3};

/// The contents of a mesh file, validated.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleSoup {
    pub positions: Vec<DVec3>,
    pub normals: Option<Vec<DVec3>>,
    pub uvs: Option<Vec<DVec2>>,
    pub triangles: Vec<[u32; 3]>,
}

/// A mesh file that could not be read; `line` or `element` where known.
/// The message does not name the file: the caller knows it and the span of
/// the statement that asked for it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}{}", where_(line, element))]
pub struct MeshFileError {
    pub message: String,
    pub line: Option<usize>,
    pub element: Option<String>,
}

fn where_(line: &Option<usize>, element: &Option<String>) -> String {
    match (line, element) {
        (Some(l), _) => format!(" (line {l})"),
        (None, Some(e)) => format!(" (element {e})"),
        (None, None) => String::new(),
    }
}

/// A text format's bytes as text, or the 1-based line holding the first
/// byte that is not UTF-8 (for the reader's "not text" error).
pub fn text_or_bad_line(bytes: &[u8]) -> Result<&str, usize> {
    std::str::from_utf8(bytes).map_err(|e| {
        1 + bytes[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    })
}

/// Polygons up to this many corners are cut into a fan from corner 0.
pub const FAN_MAX: usize = 16;

/// Cuts a polygon (corners in order, at least three) into triangles with
/// its winding. A small one (the quads and pentagons of ordinary meshes)
/// becomes a fan from its first corner. A larger one is halved again and
/// again, (i, m, j) and then each side, with an explicit stack: a fan's
/// slivers all reach back to corner 0, so their boxes all overlap and no
/// kd-tree can separate them (a 100,000-corner face took over 15 s and
/// 1 GB to draw at 64×64); halving keeps triangles compact. Both cover a
/// convex polygon exactly.
pub fn triangulate(corners: &[u32], out: &mut Vec<[u32; 3]>) {
    let n = corners.len();
    if n <= FAN_MAX {
        for j in 1..n.saturating_sub(1) {
            out.push([corners[0], corners[j], corners[j + 1]]);
        }
        return;
    }
    out.reserve(n - 2);
    let mut stack = vec![(0, n - 1)];
    while let Some((i, j)) = stack.pop() {
        if j - i < 2 {
            continue;
        }
        let m = (i + j) / 2;
        out.push([corners[i], corners[m], corners[j]]);
        stack.push((i, m));
        stack.push((m, j));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A large convex polygon cut by halving covers exactly what a fan
    /// covers: the same area, the same winding, every corner used, n − 2
    /// triangles.
    #[test]
    fn large_polygons_are_halved_and_cover_the_polygon() {
        let n = 1000;
        let ring: Vec<DVec3> = (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                DVec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        let corners: Vec<u32> = (0..n as u32).collect();
        let mut tris = Vec::new();
        triangulate(&corners, &mut tris);
        assert_eq!(tris.len(), n - 2);
        let signed = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|k| ring[k as usize]);
            (b - a).cross(c - a).z / 2.0
        };
        assert!(tris.iter().all(|t| signed(t) > 0.0), "winding kept");
        let area: f64 = tris.iter().map(signed).sum();
        let exact = n as f64 / 2.0 * (std::f64::consts::TAU / n as f64).sin();
        assert!((area - exact).abs() < 1e-9 * exact, "{area} vs {exact}");
        let mut used = vec![false; n];
        tris.iter().flatten().for_each(|&k| used[k as usize] = true);
        assert!(used.iter().all(|&u| u));
        // Compact: no triangle of the halving reaches from every part of
        // the ring to corner 0 as a fan's do; most are small.
        let small = tris.iter().filter(|t| t[2] - t[0] <= 8).count();
        assert!(small > n / 2, "{small}");
        // Small polygons are still fans, as before.
        let mut quad = Vec::new();
        triangulate(&[0, 1, 2, 3], &mut quad);
        assert_eq!(quad, vec![[0, 1, 2], [0, 2, 3]]);
    }
}
