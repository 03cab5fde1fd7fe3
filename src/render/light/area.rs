//! Area lights: emissive spheres, discs and rectangles. For a point y on
//! the light drawn uniformly over its area A (discs through the concentric
//! map) the light arriving at x is
//!
//! ```text
//! L_e · (n_y·(−l))⁺ / |x − y|² · A       (l the unit direction x → y)
//! ```
//! which the integrator weighs by k_d c (n·l)⁺ and one shadow ray to y:
//! area lights fall off with distance squared, unlike point lights.
//!
//! A sphere seen from outside is sampled over the cone of directions it
//! fills instead (pbrt's `Sphere::Sample` with the cone): with
//! sin θ_max = r/|c − x|, a direction is drawn uniformly in solid angle
//! within θ_max of the centre's direction and y is where it meets the near
//! cap, so no sample lands on the half the point cannot see; each sample
//! brings L_e · 2π(1 − cos θ_max) (L_e over the density 1/(2π(1 − cos θ_max))).
//! A point facing the sphere then receives E = π L_e (r/d)².
//!
//! A light inside CSG (`clipped`) is sampled over its whole surface on
//! both sides, and the integrator keeps a sample only where a ray to it
//! finds the solid's surface there, emitting toward the point.
//!
//! With no `samples` each pixel sample draws one point (the course's way;
//! the noise averages out over the pixel's samples); `samples n` on the
//! object gives it its own n × n grid of cell centres per shading point
//! (POV-Ray's `area_light`, no randomness).
//!
//! ```text
//! material lamp { emit white  intensity 4 }
//! rectangle { bottom_left <-1, 6, 0>  top_left <-1, 6, 2>  bottom_right <1, 6, 0>  material lamp  samples 8 }
//! sphere { centre <0, 5, 0>  radius 0.3  material lamp }
//! ```

use super::LightSample;
use crate::geometry::DVec3;
use crate::render::sampler::concentric_disc;
use crate::scene::{AreaLight, LightSurface};

/// A point on the surface for the square sample `u`, with the surface's
/// unit outward normal there.
pub fn point_on(s: &LightSurface, u: (f64, f64)) -> (DVec3, DVec3) {
    point_at(s, u, flat_normal(s))
}

/// The unit normal of a rectangle (zero for the other surfaces, whose
/// normal depends on the point).
fn flat_normal(s: &LightSurface) -> DVec3 {
    match s {
        LightSurface::Rectangle { edge_u, edge_v, .. } => edge_u.cross(*edge_v).normalize(),
        _ => DVec3::ZERO,
    }
}

/// [`point_on`] with the rectangle's normal given.
#[inline]
fn point_at(s: &LightSurface, u: (f64, f64), flat_normal: DVec3) -> (DVec3, DVec3) {
    match s {
        LightSurface::Sphere { centre, radius } => {
            let z = 1.0 - 2.0 * u.0;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = std::f64::consts::TAU * u.1;
            let (sin_phi, cos_phi) = sin_cos(phi);
            let n = DVec3::new(r * cos_phi, r * sin_phi, z);
            (*centre + *radius * n, n)
        }
        LightSurface::Disc {
            centre,
            normal,
            u: eu,
            v: ev,
            ..
        } => {
            let (x, y) = concentric_disc(u);
            (*centre + x * *eu + y * *ev, *normal)
        }
        LightSurface::Rectangle {
            corner,
            edge_u,
            edge_v,
        } => (*corner + u.0 * *edge_u + u.1 * *edge_v, flat_normal),
    }
}

/// `(sin φ, cos φ)`, never inlined: the compiler may compute a sine
/// ahead of the branch that needs it, and did so for every row of every
/// rectangle light's sample grid (4% of the `soft` benchmark's
/// instructions on an angle no sample used); a call it cannot.
#[inline(never)]
fn sin_cos(phi: f64) -> (f64, f64) {
    (phi.sin(), phi.cos())
}

/// The surface's area.
pub fn area(s: &LightSurface) -> f64 {
    match s {
        LightSurface::Sphere { radius, .. } => 4.0 * std::f64::consts::PI * radius * radius,
        LightSurface::Disc { u, v, .. } => std::f64::consts::PI * u.cross(*v).length(),
        LightSurface::Rectangle { edge_u, edge_v, .. } => edge_u.cross(*edge_v).length(),
    }
}

/// The light from the point of `light` at square sample `u`, as seen from
/// `from`; `None` when that point faces away.
pub fn sample(light: &AreaLight, from: DVec3, u: (f64, f64)) -> Option<LightSample> {
    Prepared::new(light).sample(from, u)
}

/// An area light with what all its samples share worked out once (a
/// grid's 64 samples per shading point would otherwise find the same
/// normal and area 64 times).
pub struct Prepared<'a> {
    light: &'a AreaLight,
    flat_normal: DVec3,
    area: f64,
}

impl<'a> Prepared<'a> {
    pub fn new(light: &'a AreaLight) -> Self {
        Prepared {
            light,
            flat_normal: flat_normal(&light.surface),
            area: area(&light.surface),
        }
    }

    pub fn light(&self) -> &'a AreaLight {
        self.light
    }

    /// [`sample`].
    #[inline(always)]
    pub fn sample(&self, from: DVec3, u: (f64, f64)) -> Option<LightSample> {
        let light = self.light;
        if let LightSurface::Sphere { centre, radius } = light.surface
            && !light.clipped
            && let Some(s) = sphere_cone(centre, radius, from, u)
        {
            return Some(LightSample {
                radiance: light.emit * s.radiance.x,
                ..s
            });
        }
        let (y, ny) = point_at(&light.surface, u, self.flat_normal);
        towards(light, y, ny, self.area, from)
    }
}

/// A sample's shadow ray stops this share of the way to the light, short
/// of the light's own surface, which the sample's point lies on.
pub const SHORT_OF_SURFACE: f64 = 1.0 - 1e-9;

/// The centre of cell (i, j) of a k × k grid over the unit square: the
/// points of a light's own grid (`samples k`).
pub fn cell_centre(i: u32, j: u32, k: u32) -> (f64, f64) {
    ((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64)
}

/// The light from the point y (normal `ny`) of `light`, whose area is
/// `area`, as seen from `from`; `None` when y faces away.
#[inline(always)]
fn towards(light: &AreaLight, y: DVec3, ny: DVec3, area: f64, from: DVec3) -> Option<LightSample> {
    let to = y - from;
    let d2 = to.length_squared();
    let dist = d2.sqrt();
    // One division, not four: a grid's samples are bound by the divider
    // (see `Grid::each`, which rounds the same way).
    let r = 1.0 / dist;
    let dir = to * r;
    let mut cos_y = -ny.dot(dir);
    if light.two_sided {
        cos_y = cos_y.abs();
    }
    if cos_y <= 0.0 || d2 == 0.0 {
        return None;
    }
    Some(LightSample {
        dir,
        dist: dist * SHORT_OF_SURFACE,
        radiance: light.emit * (cos_y * (r * r) * area),
    })
}

/// A flat light's own k × k grid (`samples k`): the cell centres, row by
/// row, found once for the render, for only the direction to each changes
/// from one shading point to the next. The same points, to the bit, as
/// [`sample`] finds for u = ((i + ½)/k, (j + ½)/k).
///
/// The points are kept coordinate by coordinate, and their directions and
/// distances from a shading point are worked out [`CHUNK`] at a time
/// before any is used, in loops the compiler turns into vector
/// instructions: the square roots and divisions, most of a sample's cost
/// where no shadow ray needs casting, then go two or more at a time, each
/// rounded as the one-at-a-time [`towards`] rounds it (the same pictures).
pub struct Grid {
    /// The points' coordinates, padded with copies of the last point to
    /// whole chunks (the copies' results are never read).
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    /// How many points there are (k²).
    len: usize,
    normal: DVec3,
    area: f64,
    /// 1/k²: each point's share.
    weight: f64,
}

/// How many grid points are worked out together.
const CHUNK: usize = 16;

impl Grid {
    /// `None` for a light without a grid, a sphere (its points depend on
    /// where it is seen from), and a light whose samples must each find its
    /// surface first (clipped or with a chosen emission).
    pub fn new(light: &AreaLight) -> Option<Grid> {
        let k = light.samples?;
        if light.clipped || light.chosen || matches!(light.surface, LightSurface::Sphere { .. }) {
            return None;
        }
        let flat = flat_normal(&light.surface);
        let mut points: Vec<DVec3> = (0..k)
            .flat_map(|j| (0..k).map(move |i| cell_centre(i, j, k)))
            .map(|u| point_at(&light.surface, u, flat).0)
            .collect();
        // The same at every point of a flat light.
        let normal = point_at(&light.surface, (0.5, 0.5), flat).1;
        let len = points.len();
        let last = *points.last()?;
        points.resize(len.div_ceil(CHUNK) * CHUNK, last);
        Some(Grid {
            xs: points.iter().map(|p| p.x).collect(),
            ys: points.iter().map(|p| p.y).collect(),
            zs: points.iter().map(|p| p.z).collect(),
            len,
            normal,
            area: area(&light.surface),
            weight: 1.0 / (k * k) as f64,
        })
    }

    /// Each grid point's light seen from `from`, weighted by its share, in
    /// grid order; points facing away are left out. What [`towards`] gives
    /// for each, to the bit.
    #[inline(always)]
    pub fn each(&self, light: &AreaLight, from: DVec3, mut f: impl FnMut(LightSample)) {
        let n = self.normal;
        let two_sided = light.two_sided;
        for c in 0..self.xs.len() / CHUNK {
            let at = c * CHUNK;
            let (xs, ys, zs) = (
                &self.xs[at..at + CHUNK],
                &self.ys[at..at + CHUNK],
                &self.zs[at..at + CHUNK],
            );
            let mut dir = [[0.0; CHUNK]; 3];
            let mut dist = [0.0; CHUNK];
            let mut d2 = [0.0; CHUNK];
            let mut cos_y = [0.0; CHUNK];
            let mut share = [0.0; CHUNK];
            for i in 0..CHUNK {
                let (tx, ty, tz) = (xs[i] - from.x, ys[i] - from.y, zs[i] - from.z);
                let q = tx * tx + ty * ty + tz * tz;
                let d = q.sqrt();
                // One division for the direction and the 1/d² falloff,
                // where four took turns at the divider (a tenth of the
                // `soft` benchmark's time went waiting for them).
                let r = 1.0 / d;
                let (dx, dy, dz) = (tx * r, ty * r, tz * r);
                let cy = -(n.x * dx + n.y * dy + n.z * dz);
                let cy = if two_sided { cy.abs() } else { cy };
                dir[0][i] = dx;
                dir[1][i] = dy;
                dir[2][i] = dz;
                dist[i] = d;
                d2[i] = q;
                cos_y[i] = cy;
                share[i] = cy * (r * r) * self.area;
            }
            let valid = (self.len - at).min(CHUNK);
            for i in 0..valid {
                if cos_y[i] <= 0.0 || d2[i] == 0.0 {
                    continue;
                }
                let mut s = LightSample {
                    dir: DVec3::new(dir[0][i], dir[1][i], dir[2][i]),
                    dist: dist[i] * SHORT_OF_SURFACE,
                    radiance: light.emit * share[i],
                };
                s.radiance *= self.weight;
                f(s);
            }
        }
    }
}

/// A point of the cap of the sphere (`centre`, `radius`) that `from` sees,
/// drawn uniformly in the solid angle the sphere fills, with the weight
/// 2π(1 − cos θ_max) (in every channel of `radiance`, to be multiplied by
/// L_e). `None` when `from` is not outside the sphere.
pub fn sphere_cone(centre: DVec3, radius: f64, from: DVec3, u: (f64, f64)) -> Option<LightSample> {
    let to_centre = centre - from;
    let dc = to_centre.length();
    if dc <= radius * (1.0 + 1e-9) {
        return None;
    }
    let w = to_centre / dc;
    let sin2_max = (radius / dc).powi(2);
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    // 1 − cos θ_max, and cos θ, without cancellation for a tiny cone.
    let one_minus_cos_max = sin2_max / (1.0 + cos_max);
    let one_minus_cos = u.0 * one_minus_cos_max;
    let cos_t = 1.0 - one_minus_cos;
    let sin_t = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let phi = std::f64::consts::TAU * u.1;
    let (a, b) = w.any_orthonormal_pair();
    let (sin_phi, cos_phi) = sin_cos(phi);
    let dir = (sin_t * cos_phi) * a + (sin_t * sin_phi) * b + cos_t * w;
    // Where dir first meets the sphere: t² − 2t(dir·c') + |c'|² − r² = 0.
    let proj = dir.dot(to_centre);
    let disc = (radius * radius - (dc * dc - proj * proj)).max(0.0);
    let dist = proj - disc.sqrt();
    Some(LightSample {
        dir,
        dist: dist * SHORT_OF_SURFACE,
        radiance: crate::scene::Colour::splat(std::f64::consts::TAU * one_minus_cos_max),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Colour;

    #[test]
    fn points_lie_on_the_surface() {
        let s = LightSurface::Sphere {
            centre: DVec3::new(1.0, 2.0, 3.0),
            radius: 0.5,
        };
        for i in 0..10 {
            let (p, n) = point_on(&s, (i as f64 / 10.0, 0.37));
            assert!(((p - DVec3::new(1.0, 2.0, 3.0)).length() - 0.5).abs() < 1e-12);
            assert!((n.length() - 1.0).abs() < 1e-12);
        }
        let d = LightSurface::Disc {
            centre: DVec3::ZERO,
            normal: DVec3::Z,
            u: DVec3::X * 2.0,
            v: DVec3::Y * 2.0,
            radius: 2.0,
        };
        assert!((area(&d) - 4.0 * std::f64::consts::PI).abs() < 1e-12);
        let (p, _) = point_on(&d, (0.99, 0.5));
        assert!(p.length() <= 2.0 + 1e-12);
    }

    /// Every sample a grid gives, in order and to the bit, is the one
    /// `sample` gives at its cell centre, weighted 1/k²; the points facing
    /// away are the ones left out, and the padding of the last chunk never
    /// shows. Rectangles and discs, one- and two-sided, k = 3 (9 points:
    /// one partial chunk) and 5 (25: one whole, one partial).
    #[test]
    fn a_grid_gives_what_each_cell_centre_gives() {
        let rect = LightSurface::Rectangle {
            corner: DVec3::new(-1.3, 4.0, -0.2),
            edge_u: DVec3::new(2.1, 0.3, 0.0),
            edge_v: DVec3::new(0.0, -0.4, 1.7),
        };
        let disc = LightSurface::Disc {
            centre: DVec3::new(0.5, 3.0, 1.0),
            normal: DVec3::new(0.0, -1.0, 0.0),
            u: DVec3::X * 0.8,
            v: DVec3::Z * 0.8,
            radius: 0.8,
        };
        let froms = [
            DVec3::ZERO,
            DVec3::new(3.0, -1.0, 2.5),
            // Beside the rectangle's plane: some points face away.
            DVec3::new(-4.0, 4.6, 0.3),
            DVec3::new(0.2, 9.0, 0.4),
        ];
        let mut compared = 0;
        for surface in [rect.clone(), disc] {
            for two_sided in [false, true] {
                for k in [3, 5] {
                    let light = AreaLight {
                        surface: surface.clone(),
                        emit: Colour::new(0.9, 1.7, 2.3),
                        samples: Some(k),
                        two_sided,
                        clipped: false,
                        chosen: false,
                    };
                    let grid = Grid::new(&light).unwrap();
                    for from in froms {
                        let mut want = Vec::new();
                        for j in 0..k {
                            for i in 0..k {
                                let u = ((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64);
                                if let Some(mut s) = sample(&light, from, u) {
                                    s.radiance *= 1.0 / (k * k) as f64;
                                    want.push(s);
                                }
                            }
                        }
                        let mut got = Vec::new();
                        grid.each(&light, from, |s| got.push(s));
                        assert_eq!(got.len(), want.len());
                        for (g, w) in got.iter().zip(&want) {
                            assert_eq!(g.dir, w.dir);
                            assert_eq!(g.dist.to_bits(), w.dist.to_bits());
                            assert_eq!(g.radiance, w.radiance);
                        }
                        compared += want.len();
                    }
                }
            }
        }
        assert!(compared > 200, "{compared}");
        // A one-sided light seen from behind sends nothing.
        let one_sided = AreaLight {
            surface: rect,
            emit: Colour::ONE,
            samples: Some(4),
            two_sided: false,
            clipped: false,
            chosen: false,
        };
        let mut n = 0;
        Grid::new(&one_sided)
            .unwrap()
            .each(&one_sided, DVec3::new(0.0, 20.0, 0.0), |_| n += 1);
        assert_eq!(n, 0);
        // No grid for a light without one, a sphere, or a clipped light.
        assert!(
            Grid::new(&AreaLight {
                samples: None,
                ..one_sided.clone()
            })
            .is_none()
        );
        assert!(
            Grid::new(&AreaLight {
                clipped: true,
                ..one_sided.clone()
            })
            .is_none()
        );
        let ball = LightSurface::Sphere {
            centre: DVec3::ZERO,
            radius: 1.0,
        };
        assert!(
            Grid::new(&AreaLight {
                surface: ball,
                ..one_sided
            })
            .is_none()
        );
    }

    #[test]
    fn a_small_far_light_gives_the_inverse_square_irradiance() {
        // A 0.01 × 0.01 square of radiance 1 facing down, 5 above: L·A/r².
        let light = AreaLight {
            surface: LightSurface::Rectangle {
                corner: DVec3::new(-0.005, 5.0, -0.005),
                edge_u: DVec3::new(0.01, 0.0, 0.0),
                edge_v: DVec3::new(0.0, 0.0, 0.01),
            },
            emit: Colour::ONE,
            samples: None,
            two_sided: false,
            clipped: false,
            chosen: false,
        };
        let s = sample(&light, DVec3::ZERO, (0.5, 0.5)).unwrap();
        assert!(
            (s.radiance.x - 1e-4 / 25.0).abs() < 1e-12,
            "{}",
            s.radiance.x
        );
        assert!((s.dir - DVec3::Y).length() < 1e-12);
        // Seen from the back it sends nothing.
        assert!(sample(&light, DVec3::new(0.0, 10.0, 0.0), (0.5, 0.5)).is_none());
        // Twice as far, a quarter.
        let far = sample(&light, DVec3::new(0.0, -5.0, 0.0), (0.5, 0.5)).unwrap();
        assert!((far.dist - 10.0).abs() < 1e-6);
        assert!((far.radiance.x * 4.0 - s.radiance.x).abs() < 1e-15);
    }

    #[test]
    fn a_sphere_light_gives_pi_l_r2_over_d2_to_a_point_facing_it() {
        // Radius 1 at distance 3 and 1.2 (a wide cone), and a tiny far one.
        for (r, d) in [(1.0, 3.0), (1.0, 1.2), (0.01, 50.0)] {
            let light = AreaLight {
                surface: LightSurface::Sphere {
                    centre: DVec3::new(0.0, d, 0.0),
                    radius: r,
                },
                emit: Colour::new(2.0, 1.0, 0.5),
                samples: None,
                two_sided: false,
                clipped: false,
                chosen: false,
            };
            let n = 200;
            let mut e = 0.0;
            for i in 0..n {
                for j in 0..n {
                    let u = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                    let s = sample(&light, DVec3::ZERO, u).unwrap();
                    // Every point lies on the sphere, on the cap facing us.
                    let y = s.dir * s.dist / (1.0 - 1e-9);
                    let c = DVec3::new(0.0, d, 0.0);
                    assert!(((y - c).length() - r).abs() < 1e-9 * d, "on the sphere");
                    assert!((y - c).dot(-y) >= -1e-9 * d, "on the near cap");
                    e += s.radiance.x * s.dir.y.max(0.0);
                }
            }
            e /= (n * n) as f64;
            let want = std::f64::consts::PI * 2.0 * (r / d).powi(2);
            assert!((e - want).abs() < 1e-3 * want, "r {r} d {d}: {e} vs {want}");
        }
    }

    #[test]
    fn inside_a_sphere_light_or_clipped_the_whole_surface_is_sampled() {
        let c = DVec3::new(0.0, 3.0, 0.0);
        assert!(sphere_cone(c, 1.0, c + DVec3::X * 0.5, (0.3, 0.3)).is_none());
        let light = AreaLight {
            surface: LightSurface::Sphere {
                centre: c,
                radius: 1.0,
            },
            emit: Colour::ONE,
            samples: None,
            two_sided: true,
            clipped: true,
            chosen: false,
        };
        // u.0 near 0 is the sphere's far pole (+z), which a cone sample
        // from the origin could never reach.
        let s = sample(&light, DVec3::ZERO, (0.0, 0.0)).unwrap();
        let y = s.dir * s.dist / (1.0 - 1e-9);
        assert!((y - (c + DVec3::Z)).length() < 1e-6, "{y}");
    }
}

/// Where the square samples land (mutation testing: "on the surface" alone
/// let a sphere's samples crowd into a band, and a disc's turn over).
#[cfg(test)]
mod spread {
    use super::*;

    #[test]
    fn a_spheres_samples_cover_it_uniformly_with_outward_normals() {
        let centre = DVec3::new(1.0, 2.0, 3.0);
        let s = LightSurface::Sphere {
            centre,
            radius: 0.5,
        };
        let k = 40;
        let (mut mean, mut z2, mut upper) = (DVec3::ZERO, 0.0, 0);
        for i in 0..k {
            for j in 0..k {
                let u = ((i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64);
                let (p, n) = point_on(&s, u);
                // The normal is the outward one at that very point.
                assert!((p - (centre + 0.5 * n)).length() < 1e-12, "{u:?}");
                mean += n;
                z2 += n.z * n.z;
                upper += (n.z > 0.0) as usize;
            }
        }
        let m = (k * k) as f64;
        // Uniform over the area: centred, half above the equator, and
        // E[z²] = 1/3 (z = cos θ is uniform on [−1, 1], Archimedes).
        assert!((mean / m).length() < 1e-3, "{}", mean / m);
        assert_eq!(upper, k * k / 2);
        assert!((z2 / m - 1.0 / 3.0).abs() < 1e-3, "{}", z2 / m);
    }

    #[test]
    fn a_discs_samples_follow_the_concentric_map_onto_its_axes() {
        let centre = DVec3::new(0.0, 5.0, 0.0);
        let d = LightSurface::Disc {
            centre,
            normal: DVec3::NEG_Y,
            u: DVec3::X * 2.0,
            v: DVec3::Z * 2.0,
            radius: 2.0,
        };
        // The square's centre is the disc's; the middles of its right and
        // top edges land on the ends of the `u` and `v` axes.
        let at = |u| point_on(&d, u).0;
        assert!((at((0.5, 0.5)) - centre).length() < 1e-12);
        assert!((at((1.0, 0.5)) - (centre + DVec3::X * 2.0)).length() < 1e-12);
        assert!((at((0.5, 1.0)) - (centre + DVec3::Z * 2.0)).length() < 1e-12);
        assert_eq!(point_on(&d, (0.3, 0.8)).1, DVec3::NEG_Y);
    }
}

/// A sphere light's area, and a sample's reach: the shadow ray must stop
/// short of the point it aims at, which lies on the light's own surface.
#[cfg(test)]
mod reach {
    use super::*;
    use crate::scene::Colour;

    #[test]
    fn a_sphere_has_area_four_pi_r_squared() {
        let s = LightSurface::Sphere {
            centre: DVec3::ONE,
            radius: 0.5,
        };
        assert!((area(&s) - std::f64::consts::PI).abs() < 1e-12);
    }

    #[test]
    fn a_sample_stops_short_of_the_light() {
        let centre = DVec3::new(0.0, 0.0, 5.0);
        let light = |clipped| AreaLight {
            surface: LightSurface::Sphere {
                centre,
                radius: 1.0,
            },
            emit: Colour::ONE,
            samples: None,
            two_sided: false,
            clipped,
            chosen: false,
        };
        // Whole-surface route (a light inside CSG): u = (1, ·) gives
        // n = −z, the sphere's point nearest the origin, 4 away.
        let s = sample(&light(true), DVec3::ZERO, (1.0, 0.0)).unwrap();
        assert!(s.dist < 4.0 && s.dist > 4.0 * (1.0 - 1e-6), "{}", s.dist);
        // Visible-cap route: the ray ends just outside the sphere, on the
        // near side, wherever in the cone it points.
        for u in [(0.0, 0.0), (0.5, 0.25), (0.999, 0.7), (1.0, 0.5)] {
            let s = sample(&light(false), DVec3::ZERO, u).unwrap();
            let r = (s.dir * s.dist - centre).length();
            assert!(r > 1.0 && r < 1.0 + 1e-6, "{u:?}: {r}");
            assert!(
                s.dist <= 4.0 / 0.8 && s.dist >= 4.0 * (1.0 - 1e-6),
                "{u:?}: {}",
                s.dist
            );
        }
    }
}
