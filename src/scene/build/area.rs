//! Emissive spheres, discs and rectangles become area lights: the shape's
//! surface is carried into world space by the object's transforms (any
//! affine map for discs and rectangles, which stay flat; a sphere must keep
//! its shape) and its `samples` read. An emissive sphere inside CSG lights
//! the scene too, as a *clipped* light: built in the operation's space and
//! placed with it, its samples count only where the solid kept its surface.
//! A lamp whose material is a pattern of materials, some emitting, lights
//! with what the pattern chooses at each sample point.
//!
//! ```text
//! rectangle { bottom_left <-1, 6, 0>  top_left <-1, 6, 2>  bottom_right <1, 6, 0>  material lamp  samples 8 }
//! ```

use super::Builder;
use super::params::Params;
use crate::geometry::{DVec3, Transform};
use crate::lang::ast::{Span, Spanned};
use crate::lang::diagnostics::Error;
use crate::scene::{AreaLight, Colour, LightSurface, MaterialId};

/// Most grid points per side of an area light (`samples 32` is 1024 shadow
/// rays per shading point).
pub const MAX_LIGHT_SAMPLES: u32 = 32;

/// `surface` moved by `xf`, or `None` when it cannot stay that shape.
fn moved(surface: &LightSurface, xf: &Transform) -> Option<LightSurface> {
    Some(match surface {
        LightSurface::Sphere { centre, radius } => {
            let (a, b, c) = (
                xf.vector(DVec3::X),
                xf.vector(DVec3::Y),
                xf.vector(DVec3::Z),
            );
            let s = a.length();
            let tol = 1e-9 * s;
            let similar = (b.length() - s).abs() <= tol
                && (c.length() - s).abs() <= tol
                && a.dot(b).abs() <= tol * s
                && a.dot(c).abs() <= tol * s
                && b.dot(c).abs() <= tol * s;
            if !similar {
                return None;
            }
            LightSurface::Sphere {
                centre: xf.point(*centre),
                radius: radius * s,
            }
        }
        LightSurface::Disc {
            centre,
            normal,
            u,
            v,
            radius,
        } => {
            let (u2, v2) = (xf.vector(*u), xf.vector(*v));
            LightSurface::Disc {
                centre: xf.point(*centre),
                normal: xf.normal(*normal).normalize(),
                u: u2,
                v: v2,
                radius: radius * u2.length() / u.length(),
            }
        }
        LightSurface::Rectangle {
            corner,
            edge_u,
            edge_v,
        } => {
            let (eu, ev) = (xf.vector(*edge_u), xf.vector(*edge_v));
            let n = xf.normal(edge_u.cross(*edge_v));
            // Keep edge_u × edge_v along the shape's own normal (a mirror
            // transform would turn it over).
            let (eu, ev) = if eu.cross(ev).dot(n) < 0.0 {
                (ev, eu)
            } else {
                (eu, ev)
            };
            LightSurface::Rectangle {
                corner: xf.point(*corner),
                edge_u: eu,
                edge_v: ev,
            }
        }
    })
}

impl Builder<'_> {
    /// After a primitive is built: makes it an area light when its material
    /// emits and it is a sphere, disc or rectangle outside CSG; reads its
    /// `samples`.
    pub(super) fn area_light(
        &mut self,
        kw: &Spanned<&str>,
        p: &mut Params,
        local: Option<LightSurface>,
        material: MaterialId,
        xf: &Transform,
        in_csg: bool,
    ) {
        let samples = p.take("samples");
        // A pattern of materials emits where it chooses an emitting one.
        let chosen = self.scene.materials[material as usize].pick.is_some()
            && self.material_reach(material).emits;
        let m = &self.scene.materials[material as usize];
        let emit = if chosen { Colour::ONE } else { m.emit };
        let n = match &samples {
            Some(q) => match self.integer(&q.values[0], 1, MAX_LIGHT_SAMPLES) {
                Some(n) => Some((n, q.name.span)),
                None => return,
            },
            None => None,
        };
        let glows = emit != Colour::ZERO;
        let Some(local) = local.filter(|_| glows) else {
            if let Some((_, at)) = n {
                self.samples_unused(at);
            } else if glows {
                // Seen, but sending no light: say so rather than leave the
                // user to wonder why the room stays dark.
                self.warn(
                    kw.span,
                    format!(
                        "this emissive `{}` glows where it is seen but lights nothing: only spheres, discs and rectangles are area lights (add one, or a `light`, beside it)",
                        kw.node
                    ),
                );
            }
            return;
        };
        let Some(surface) = moved(&local, xf) else {
            self.err(
                Error::new(
                    kw.span,
                    "an emissive sphere must stay a sphere to light the scene",
                )
                .label("scaled unevenly or sheared")
                .help("scale it by one number, or use a disc or rectangle as the light"),
            );
            return;
        };
        self.scene.area_lights.push(AreaLight {
            surface,
            emit,
            samples: n.map(|n| n.0),
            // In CSG a cutter's surface faces inward; which side emits is
            // left to the visibility test of a clipped light.
            two_sided: in_csg,
            clipped: in_csg,
            chosen,
        });
    }

    /// The area lights made since there were `before` of them (inside a CSG
    /// operation, in its own space), placed by the operation's `xf`.
    pub(super) fn place_lights_since(&mut self, before: usize, xf: &Transform, at: Span) {
        let lights = self.scene.area_lights.split_off(before);
        self.place_area_lights(&lights, xf, at);
    }

    /// The area lights of an object value, placed by `xf`.
    pub(super) fn place_area_lights(&mut self, lights: &[AreaLight], xf: &Transform, at: Span) {
        for l in lights {
            match moved(&l.surface, xf) {
                Some(surface) => self.scene.area_lights.push(AreaLight {
                    surface,
                    ..l.clone()
                }),
                None => self.err(
                    Error::new(
                        at,
                        "an emissive sphere must stay a sphere to light the scene",
                    )
                    .label("scaled unevenly or sheared")
                    .help("scale it by one number, or use a disc or rectangle as the light"),
                ),
            }
        }
    }

    fn samples_unused(&mut self, at: Span) {
        self.err(
            Error::new(at, "`samples` has no effect here")
                .label("not an area light")
                .help("`samples` is for emissive spheres, discs and rectangles (area lights)"),
        );
    }
}
