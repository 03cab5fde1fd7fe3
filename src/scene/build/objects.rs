//! Objects and transforms. Each object's transforms compose in the order
//! written, then the enclosing blocks' transforms follow; the whole chain
//! becomes one [`Transformed`] wrapper (none when it is the identity).
//! `group` is flattened into its parent (inside a CSG operation it acts as
//! a union); CSG children must be solids. Reading a transform list is
//! transforms.rs.

use super::Builder;
use super::params::{self, Schema, Spec, spec};
use crate::eval::expr::Fragment;
use crate::geometry::{Aabb, DVec3, Transform};
use crate::implicit::{Equation, ImplicitSurface};
use crate::lang::ast::{Block, Item, Span, Spanned};
use crate::lang::diagnostics::Error;
use crate::scene::{LightSurface, MaterialId};
use crate::shapes::{
    Cone, Csg, CsgOp, Cuboid, Disc, Mesh, MeshData, Plane, Rectangle, Shape, Shared, Sphere, Torus,
    Transformed, Triangle,
};
use std::sync::Arc;

/// The object kinds are words of the language: the parser's list.
pub use crate::lang::parser::{OBJECTS, is_object};

/// `implicit "…"` and `mesh "…"` take a string before their block.
pub fn takes_string(name: &str) -> bool {
    matches!(name, "implicit" | "mesh")
}

/// What an object inherits from the blocks around it.
#[derive(Clone, Copy, Debug)]
pub struct Ctx {
    /// The default material (a `group` or CSG's own, or the scene default).
    pub material: MaterialId,
    /// The CSG operation the object is inside, if any.
    pub csg: Option<&'static str>,
    /// Transforms of the enclosing blocks, applied after the object's own.
    pub outer: Transform,
}

impl Ctx {
    pub const TOP: Ctx = Ctx {
        material: 0,
        csg: None,
        outer: Transform::IDENTITY,
    };
}

const V3: &str = "a 3-vector";
const NUM: &str = "a number";
const MAT: &str = "a material";
const LIGHT_SAMPLES: &str = "a whole number: n × n shadow points per shading point (area lights)";

pub(super) fn schema(kind: &str) -> Schema {
    let own: &'static [Spec] = match kind {
        "sphere" => {
            const {
                &[
                    spec("centre", 1, V3),
                    spec("radius", 1, NUM),
                    spec("samples", 1, LIGHT_SAMPLES),
                ]
            }
        }
        "plane" => const { &[spec("normal", 1, V3), spec("offset", 1, NUM)] },
        "box" => {
            const {
                &[
                    spec("min", 1, V3),
                    spec("max", 1, V3),
                    spec("front", 1, MAT),
                    spec("back", 1, MAT),
                    spec("top", 1, MAT),
                    spec("bottom", 1, MAT),
                    spec("left", 1, MAT),
                    spec("right", 1, MAT),
                ]
            }
        }
        "cylinder" => {
            const {
                &[
                    spec("centre", 1, V3),
                    spec("radius", 1, NUM),
                    spec("height", 1, NUM),
                    spec("open", 0, "nothing"),
                    spec("top", 1, MAT),
                    spec("bottom", 1, MAT),
                ]
            }
        }
        "cone" => {
            const {
                &[
                    spec("centre", 1, V3),
                    spec("radius", 1, NUM),
                    spec("top_radius", 1, NUM),
                    spec("height", 1, NUM),
                    spec("open", 0, "nothing"),
                    spec("top", 1, MAT),
                    spec("bottom", 1, MAT),
                ]
            }
        }
        "disc" => {
            const {
                &[
                    spec("centre", 1, V3),
                    spec("radius", 1, NUM),
                    spec("samples", 1, LIGHT_SAMPLES),
                ]
            }
        }
        "triangle" => const { &[spec("a", 1, V3), spec("b", 1, V3), spec("c", 1, V3)] },
        "rectangle" => {
            const {
                &[
                    spec("bottom_left", 1, V3),
                    spec("top_left", 1, V3),
                    spec("bottom_right", 1, V3),
                    spec("samples", 1, LIGHT_SAMPLES),
                ]
            }
        }
        "torus" => const { &[spec("major", 1, NUM), spec("minor", 1, NUM)] },
        "implicit" => const { &[spec("bounded_by", 2, "two 3-vectors (the box's corners)")] },
        "mesh" => const { &[spec("smooth", 0, "nothing"), spec("flat", 0, "nothing")] },
        _ => &[],
    };
    Schema {
        own,
        object: true,
        children: matches!(kind, "group" | "union" | "intersection" | "difference"),
    }
}

fn wrap(shape: Box<dyn Shape>, xf: Transform) -> Box<dyn Shape> {
    if xf.is_identity() {
        shape
    } else {
        Box::new(Transformed::new(shape, xf))
    }
}

impl Builder<'_> {
    /// An object statement at `items[*i - 1]`: its string (for `implicit`
    /// and `mesh`) and block follow.
    pub(super) fn object_statement(
        &mut self,
        kw: &Spanned<&str>,
        items: &[Item],
        i: &mut usize,
        ctx: Ctx,
    ) -> Vec<Box<dyn Shape>> {
        let mut string = None;
        if takes_string(kw.node) {
            match items.get(*i) {
                Some(s @ Item::Str { .. }) => {
                    *i += 1;
                    string = Some(s.clone());
                }
                _ => {
                    let what = if kw.node == "mesh" {
                        "a file name: `mesh \"bunny.ply\" { … }`"
                    } else {
                        "an equation: `implicit \"x^2 + y^2 + z^2 - 1\" { … }`"
                    };
                    self.err(
                        Error::new(kw.span, format!("`{}` needs a string", kw.node))
                            .label(format!("expected {what}")),
                    );
                    return Vec::new();
                }
            }
        }
        let Some(block) = self.block_after(kw, items, i) else {
            return Vec::new();
        };
        self.object(kw, string.as_ref(), block, ctx)
    }

    pub(super) fn object(
        &mut self,
        kw: &Spanned<&str>,
        string: Option<&Item>,
        block: &Block,
        ctx: Ctx,
    ) -> Vec<Box<dyn Shape>> {
        let kind = kw.node;
        let schema = schema(kind);
        let mut p = self.params(kind, block, &schema);
        let mat = match p.take("material") {
            Some(q) => self.material_value(&q.values[0]).unwrap_or(ctx.material),
            None => ctx.material,
        };
        let own = self.transform(p.take_transforms());
        let total = own.then(&ctx.outer);
        let children = std::mem::take(&mut p.children);
        let out: Vec<Box<dyn Shape>> = match kind {
            "group" if ctx.csg.is_some() => {
                // Inside CSG a group is a union of its children.
                let inner = Ctx {
                    material: mat,
                    csg: ctx.csg,
                    outer: Transform::IDENTITY,
                };
                let lights = self.scene.area_lights.len();
                let shapes = self.children(&children, inner);
                self.place_lights_since(lights, &total, kw.span);
                if shapes.is_empty() {
                    Vec::new()
                } else {
                    let reads_uv = self.material_reach(mat).reads_uv;
                    let csg = Csg::new(CsgOp::Union, shapes).texture_space(mat, reads_uv);
                    vec![wrap(Box::new(csg), total)]
                }
            }
            "group" => {
                let inner = Ctx {
                    material: mat,
                    csg: None,
                    outer: total,
                };
                self.children(&children, inner)
            }
            "union" | "intersection" | "difference" => {
                let op = match kind {
                    "union" => CsgOp::Union,
                    "intersection" => CsgOp::Intersection,
                    _ => CsgOp::Difference,
                };
                let name: &'static str = match op {
                    CsgOp::Union => "union",
                    CsgOp::Intersection => "intersection",
                    CsgOp::Difference => "difference",
                };
                let inner = Ctx {
                    material: mat,
                    csg: Some(name),
                    outer: Transform::IDENTITY,
                };
                if children.is_empty() {
                    self.err(
                        Error::new(kw.span, format!("`{kind}` holds no objects"))
                            .label("empty")
                            .help("put the solids to combine inside its block"),
                    );
                    Vec::new()
                } else {
                    let lights = self.scene.area_lights.len();
                    let shapes = self.children(&children, inner);
                    // Emissive spheres inside were placed in its space.
                    self.place_lights_since(lights, &total, kw.span);
                    // Its material's solid patterns live in the block's space.
                    let reads_uv = self.material_reach(mat).reads_uv;
                    let csg = Csg::new(op, shapes).texture_space(mat, reads_uv);
                    vec![wrap(Box::new(csg), total)]
                }
            }
            _ => {
                let shape = self.primitive(kind, kw, string, &mut p, mat, ctx.csg.is_some());
                let surface = self.light_surface.take();
                if shape.is_some() {
                    self.area_light(kw, &mut p, surface, mat, &total, ctx.csg.is_some());
                } else {
                    p.take("samples");
                }
                shape.map(|s| wrap(s, total)).into_iter().collect()
            }
        };
        self.finish(kind, p);
        out
    }

    /// A placement of an object value (`wheel { translate … material … }`):
    /// the value is built once per material and CSG context and shared
    /// ([`Shared`]) by every placement, each under its own transform.
    pub(super) fn instance(
        &mut self,
        name: &Spanned<String>,
        value: &Arc<Fragment>,
        block: &Block,
        ctx: Ctx,
    ) -> Vec<Box<dyn Shape>> {
        const PLACEMENT: Schema = Schema {
            own: &[],
            object: true,
            children: false,
        };
        let mut p = self.params(&name.node, block, &PLACEMENT);
        let mat = match p.take("material") {
            Some(q) => self.material_value(&q.values[0]).unwrap_or(ctx.material),
            None => ctx.material,
        };
        let total = self.transform(p.take_transforms()).then(&ctx.outer);
        self.finish(&name.node, p);
        let key = (Arc::as_ptr(value) as usize, mat, ctx.csg);
        let lights_before = self.scene.area_lights.len();
        let shapes = match self.instances.get(&key) {
            Some(s) => s.clone(),
            None => {
                let inner = Ctx {
                    material: mat,
                    csg: ctx.csg,
                    outer: Transform::IDENTITY,
                };
                let Some(kw) = value.items.first().and_then(Item::as_name) else {
                    return Vec::new();
                };
                let mut i = 1;
                let built: Vec<Arc<dyn Shape>> = self
                    .object_statement(&kw, &value.items, &mut i, inner)
                    .into_iter()
                    .map(Arc::from)
                    .collect();
                self.instances.insert(key, built.clone());
                // Area lights it holds were made in its own space: kept
                // with it and placed with each placement below.
                let lights = self.scene.area_lights.split_off(lights_before);
                self.instance_lights.insert(key, lights);
                built
            }
        };
        let lights = self.instance_lights.get(&key).cloned().unwrap_or_default();
        self.place_area_lights(&lights, &total, name.span);
        shapes
            .into_iter()
            .map(|s| wrap(Box::new(Shared(s)), total))
            .collect()
    }

    fn children(&mut self, children: &[params::Child], ctx: Ctx) -> Vec<Box<dyn Shape>> {
        let mut out = Vec::new();
        for c in children {
            let shapes = self.traced(c.trace.as_ref(), |b| match &c.instance {
                Some(f) => b.instance(&c.kw, f, c.block, ctx),
                None => b.object(
                    &Spanned::new(c.kw.node.as_str(), c.kw.span),
                    c.string,
                    c.block,
                    ctx,
                ),
            });
            if let Some(op) = ctx.csg {
                for s in &shapes {
                    if !s.is_solid() {
                        self.err(
                            Error::new(
                                c.kw.span,
                                format!(
                                    "`{}` is an open surface and cannot be used in `{op}`: it has no inside",
                                    c.kw.node
                                ),
                            )
                            .label("not a solid")
                            .help("CSG combines solids: sphere, box, cylinder, cone, torus, plane, implicit, or CSG of those"),
                        );
                        break;
                    }
                }
            }
            out.extend(shapes);
        }
        out
    }

    fn vec3_or(&mut self, p: &mut params::Params, name: &str, default: DVec3) -> Option<DVec3> {
        match p.take(name) {
            Some(q) => self.vec3(&q.values[0]).map(|v| v.0),
            None => Some(default),
        }
    }

    fn required_vec3(
        &mut self,
        p: &mut params::Params,
        name: &str,
        kw: &Spanned<&str>,
    ) -> Option<DVec3> {
        match p.take(name) {
            Some(q) => self.vec3(&q.values[0]).map(|v| v.0),
            None => {
                if !p.had_unknown {
                    self.missing(kw, name, "a 3-vector");
                }
                None
            }
        }
    }

    fn missing(&mut self, kw: &Spanned<&str>, name: &str, what: &str) {
        self.err(
            Error::new(kw.span, format!("`{}` needs `{name}`", kw.node))
                .label(format!("no `{name}` given"))
                .help(format!("add `{name}` followed by {what}")),
        );
    }

    fn positive_or(
        &mut self,
        p: &mut params::Params,
        name: &str,
        default: Option<f64>,
        kw: &Spanned<&str>,
    ) -> Option<f64> {
        match p.take(name) {
            Some(q) => self.positive(&q.values[0]),
            None => {
                if default.is_none() && !p.had_unknown {
                    self.missing(kw, name, "a number greater than 0");
                }
                default
            }
        }
    }

    fn face(&mut self, p: &mut params::Params, name: &str, default: MaterialId) -> MaterialId {
        match p.take(name) {
            Some(q) => self.material_value(&q.values[0]).unwrap_or(default),
            None => default,
        }
    }

    fn primitive(
        &mut self,
        kind: &str,
        kw: &Spanned<&str>,
        string: Option<&Item>,
        p: &mut params::Params,
        mat: MaterialId,
        in_csg: bool,
    ) -> Option<Box<dyn Shape>> {
        Some(match kind {
            "sphere" => {
                let c = self.vec3_or(p, "centre", DVec3::ZERO);
                let r = self.positive_or(p, "radius", Some(1.0), kw);
                let (centre, radius) = (c?, r?);
                self.light_surface = Some(LightSurface::Sphere { centre, radius });
                Box::new(Sphere::new(centre, radius, mat))
            }
            "plane" => {
                let n = match p.take("normal") {
                    Some(q) => match self.vec3(&q.values[0]) {
                        Some((v, _)) if v.length() > 0.0 => Some(v),
                        Some((_, s)) => {
                            self.err(
                                Error::new(s, "a plane's normal cannot be zero")
                                    .label("zero vector"),
                            );
                            None
                        }
                        None => None,
                    },
                    None => Some(DVec3::Z),
                };
                let d = match p.take("offset") {
                    Some(q) => self.number(&q.values[0]).map(|v| v.0),
                    None => Some(0.0),
                };
                Box::new(Plane::new(n?, d?, mat))
            }
            "box" => {
                let lo = self.vec3_or(p, "min", DVec3::splat(-1.0));
                let hi_item = p.take("max");
                let hi = match &hi_item {
                    Some(q) => self.vec3(&q.values[0]).map(|v| v.0),
                    None => Some(DVec3::ONE),
                };
                let faces = ["front", "back", "top", "bottom", "left", "right"]
                    .map(|f| self.face(p, f, mat));
                let (lo, hi) = (lo?, hi?);
                if !(lo.cmplt(hi).all()) {
                    let at = hi_item.map_or(kw.span, |q| q.values[0].span());
                    self.err(
                        Error::new(
                            at,
                            "a box's `max` must be greater than its `min` on every axis",
                        )
                        .label(format!("min {lo}, max {hi}")),
                    );
                    return None;
                }
                Box::new(Cuboid::new(lo, hi, faces))
            }
            "cylinder" | "cone" => {
                let c = self.vec3_or(p, "centre", DVec3::ZERO);
                let r = self.positive_or(p, "radius", Some(1.0), kw);
                let top_r = if kind == "cone" {
                    match p.take("top_radius") {
                        Some(q) => self.checked(&q.values[0], |v| v >= 0.0, "0 or more"),
                        None => Some(0.0),
                    }
                } else {
                    Some(0.0)
                };
                let h = self.positive_or(p, "height", Some(1.0), kw);
                let open = p.take("open");
                let top = p.take("top");
                let bottom = p.take("bottom");
                let caps = if let Some(o) = &open {
                    if let Some(cap) = top.as_ref().or(bottom.as_ref()) {
                        self.err(
                            Error::new(cap.name.span, format!("an `open` {kind} has no caps"))
                                .label("no cap to colour")
                                .note(o.name.span, "made open here"),
                        );
                    }
                    None
                } else {
                    let t = top.map_or(Some(mat), |q| self.material_value(&q.values[0]));
                    let b = bottom.map_or(Some(mat), |q| self.material_value(&q.values[0]));
                    Some([t.unwrap_or(mat), b.unwrap_or(mat)])
                };
                let (c, r, h, top_r) = (c?, r?, h?, top_r?);
                if kind == "cone" {
                    Box::new(Cone::new(c, r, top_r, h, mat, caps))
                } else {
                    Box::new(Cone::cylinder(c, r, h, mat, caps))
                }
            }
            "disc" => {
                let c = self.vec3_or(p, "centre", DVec3::ZERO);
                let r = self.positive_or(p, "radius", Some(1.0), kw);
                let (centre, radius) = (c?, r?);
                self.light_surface = Some(LightSurface::Disc {
                    centre,
                    normal: DVec3::Z,
                    u: DVec3::X * radius,
                    v: DVec3::Y * radius,
                    radius,
                });
                Box::new(Disc::new(centre, radius, mat))
            }
            "triangle" => {
                let a = self.required_vec3(p, "a", kw);
                let b = self.required_vec3(p, "b", kw);
                let c = self.required_vec3(p, "c", kw);
                let (a, b, c) = (a?, b?, c?);
                if (b - a).cross(c - a).length()
                    <= 1e-12 * (b - a).length().max((c - a).length()).max(1e-300)
                {
                    self.err(
                        Error::new(kw.span, "this triangle has no area")
                            .label("its corners are on one line"),
                    );
                    return None;
                }
                Box::new(Triangle::new(a, b, c, mat))
            }
            "rectangle" => {
                let bl = self.required_vec3(p, "bottom_left", kw);
                let tl = self.required_vec3(p, "top_left", kw);
                let br = self.required_vec3(p, "bottom_right", kw);
                let (bl, tl, br) = (bl?, tl?, br?);
                if (tl - bl).cross(br - bl).length()
                    <= 1e-12 * (tl - bl).length().max((br - bl).length()).max(1e-300)
                {
                    self.err(
                        Error::new(kw.span, "this rectangle has no area")
                            .label("its corners are on one line"),
                    );
                    return None;
                }
                self.light_surface = Some(LightSurface::Rectangle {
                    corner: bl,
                    edge_u: br - bl,
                    edge_v: tl - bl,
                });
                Box::new(Rectangle::new(bl, tl, br, mat))
            }
            "torus" => {
                let major = self.positive_or(p, "major", None, kw);
                let minor = self.positive_or(p, "minor", None, kw);
                Box::new(Torus::new(major?, minor?, mat))
            }
            "implicit" => return self.implicit(string?, p, mat, in_csg),
            "mesh" => return self.mesh(string?, p, mat),
            _ => unreachable!("is_object lists every kind"),
        })
    }

    fn implicit(
        &mut self,
        string: &Item,
        p: &mut params::Params,
        mat: MaterialId,
        in_csg: bool,
    ) -> Option<Box<dyn Shape>> {
        let Item::Str {
            text,
            content,
            constants,
            ..
        } = string
        else {
            return None;
        };
        let bounds = match p.take("bounded_by") {
            Some(q) => {
                let a = self.vec3(&q.values[0]);
                let b = self.vec3(&q.values[1]);
                let ((a, _), (b, sb)) = (a?, b?);
                if (a - b).abs().min_element() <= 0.0 {
                    self.err(
                        Error::new(q.name.span.to(sb), "`bounded_by` encloses no volume")
                            .label("the corners share a coordinate"),
                    );
                    return None;
                }
                Some(Aabb::new(a, b))
            }
            None => None,
        };
        let env = &self.env;
        let compiled = Equation::compile(text, &|name| {
            constants
                .as_ref()
                .and_then(|c| c.iter().find(|(n, _)| n == name).map(|(_, v)| *v))
                .or_else(|| env.number_constant(name))
        });
        match compiled {
            Ok(eq) => {
                let mut surface = ImplicitSurface::new(eq, bounds, mat);
                if in_csg {
                    // A solid: where `bounded_by` cuts it, the box is its face.
                    surface = surface.solid_in_box();
                }
                if let Some(note) = surface.bound_note() {
                    self.warn(*content, note);
                }
                Some(Box::new(surface))
            }
            Err(errs) => {
                for e in errs {
                    let start = (content.start + e.span.start).min(content.end);
                    let end = (content.start + e.span.end).clamp(start, content.end);
                    let err = Error::new(Span::new(content.file, start, end), e.message.clone())
                        .label("here")
                        .maybe_help(e.help.clone());
                    self.err(err);
                }
                None
            }
        }
    }

    fn mesh(
        &mut self,
        string: &Item,
        p: &mut params::Params,
        mat: MaterialId,
    ) -> Option<Box<dyn Shape>> {
        let Item::Str { text, span, .. } = string else {
            return None;
        };
        let smooth = p.take("smooth");
        let flat = p.take("flat");
        if let (Some(s), Some(f)) = (&smooth, &flat) {
            self.err(
                Error::new(f.name.span, "a mesh is either `smooth` or `flat`")
                    .label("flat")
                    .note(s.name.span, "smooth"),
            );
        }
        let path = self.program.sources.dir_of(span.file).join(text);
        let Ok(canonical) = path.canonicalize() else {
            self.err(
                Error::new(*span, format!("cannot find the mesh file `{text}`"))
                    .label(format!("looked for {}", path.display()))
                    .help("a mesh path is relative to the scene file that names it"),
            );
            return None;
        };
        let data = match self.meshes.get(&canonical) {
            Some(d) => d.clone(),
            None => match MeshData::load_with(&canonical, self.scene.settings.accel) {
                Ok(d) => {
                    let d = Arc::new(d);
                    self.meshes.insert(canonical, d.clone());
                    d
                }
                Err(e) => {
                    let mut place = Vec::new();
                    if let Some(l) = e.line {
                        place.push(format!("line {l}"));
                    }
                    if let Some(el) = &e.element {
                        place.push(format!("element `{el}`"));
                    }
                    let place = if place.is_empty() {
                        String::new()
                    } else {
                        format!(" ({})", place.join(", "))
                    };
                    self.err(
                        Error::new(*span, format!("cannot read the mesh `{text}`{place}"))
                            .label(e.message.clone()),
                    );
                    return None;
                }
            },
        };
        Some(Box::new(Mesh::new(data, smooth.is_some(), mat)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn is_object_says_yes_to_exactly_the_listed_objects() {
        for name in OBJECTS {
            assert!(is_object(name), "{name} is an object");
        }
        // Near misses of every kind: other keywords, a prefix, a longer
        // word, another case, the empty name.
        for name in [
            "material", "centre", "radius", "colour", "light", "camera", "spher", "spheres",
            "Sphere", "boxes", "", "csg", "cube",
        ] {
            assert!(!is_object(name), "{name} is not an object");
        }
    }
}
