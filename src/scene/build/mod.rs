//! Stage 2, BUILD: the parser's items → a validated [`Scene`].
//!
//! The grammar knows no statements; this module reads items against a
//! schema per block ([`params::Schema`]): which parameter names are valid
//! there and how many values each takes. That is where unknown names get a
//! "did you mean", missing values say what was expected, and every
//! parameter is either used or reported. All mistakes are collected and
//! reported together.
//!
//! Order of work: the `render` block's `gamma` is found first (it decides
//! how `#rrggbb` and named colours decode), then statements are built in
//! the order written. Constants and named materials can only be used after
//! they are defined; using one earlier says where it is defined.

mod area;
mod objects;
mod params;
mod textures;

use super::{
    Camera, Colour, Light, Material, Projection, RenderSettings, Scene, Texture, Transfer,
};
use crate::eval::expr as eval;
use crate::geometry::DVec3;
use crate::lang::Program;
use crate::lang::ast::{Block, Item, Span, Spanned};
use crate::lang::diagnostics::{Error, Problems, did_you_mean};
use crate::lang::parser::STATEMENT_KEYWORDS;
use crate::shapes::MeshData;
use eval::{Constant, Env, Value};
use params::{Param, Params, Schema};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// Largest image side accepted from a scene file: the command line's
/// (`--width`, `--height`), so that one set of limits holds whichever
/// sets the size; the 100-megapixel guard (`--allow-large`) applies to
/// both alike, before the first ray.
pub const MAX_IMAGE_SIDE: u32 = crate::cli::MAX_SIDE;
/// Largest `max_depth`: deeper reflections than this cannot change a pixel
/// that is stored in 8 or 16 bits unless every surface is a perfect mirror.
pub const MAX_DEPTH: u32 = 64;

pub use objects::is_object;

/// Evaluates and builds the scene, reporting every mistake of the program
/// at once.
pub fn build(program: &Program) -> Result<Scene, Problems> {
    build_with_warnings(program).map(|(scene, _)| scene)
}

/// As [`build`], also giving the warnings: things that render, but perhaps
/// not as meant or not as fast as they could (each "file:line:col: text").
pub fn build_with_warnings(program: &Program) -> Result<(Scene, Vec<String>), Problems> {
    build_with(program, &crate::eval::Options::default())
}

/// As [`build_with_warnings`], with values from outside the file (`-D`,
/// `clock`, `frame`) and the evaluation's limits.
pub fn build_with(
    program: &Program,
    options: &crate::eval::Options,
) -> Result<(Scene, Vec<String>), Problems> {
    let transfer = find_transfer(&program.items);
    let mut b = Builder::new(program, transfer);
    // Each part is built as soon as it is evaluated, so the evaluated
    // items of a long loop never all exist at once.
    let eval_errors = crate::eval::evaluate_in_parts(program, transfer, options, |items, known| {
        if b.env.known.len() != known.len() {
            b.env.known = known.to_vec();
        }
        b.top_level(&items);
    });
    b.errors.extend(eval_errors);
    // A mistake inside a loop body is one mistake: keep its first report.
    let mut seen = std::collections::HashSet::new();
    b.errors
        .retain(|e| seen.insert((e.span, e.message.clone())));
    if let Some(env) = &mut b.scene.environment {
        if b.background_given {
            env.visible = false;
        } else {
            b.scene.settings.background = env.colour;
        }
    }
    if b.errors.is_empty() {
        Ok((b.scene, b.warnings))
    } else {
        Err(program.problems(b.errors))
    }
}

struct Builder<'p> {
    program: &'p Program,
    env: Env,
    errors: Vec<Error>,
    warnings: Vec<String>,
    scene: Scene,
    /// Named materials declared so far.
    materials: HashMap<String, (super::MaterialId, Span)>,
    /// Every named material of the program, for "declared later" hints.
    all_materials: HashMap<String, Span>,
    /// `camera`, `render`, `ambient`: where each was given (at most once).
    singletons: HashMap<&'static str, Span>,
    /// Meshes by canonical path: one file placed many times is read once.
    meshes: HashMap<PathBuf, Arc<MeshData>>,
    /// The last primitive's surface in its own space, should its material
    /// make it an area light.
    light_surface: Option<super::LightSurface>,
    /// Whether `render` set a `background` (else an environment is the sky).
    background_given: bool,
    /// The area lights of each object value, in its own space.
    instance_lights: HashMap<InstanceKey, Vec<super::AreaLight>>,
    /// Which loop iteration or call made what is being built.
    trace: Option<Arc<crate::eval::Trace>>,
    /// Mistakes reported so far, by place and message: one written inside
    /// a loop is reported once (for the first iteration), not per iteration.
    reported: std::collections::HashSet<(Span, String)>,
    /// Object values built so far, by (value, default material, CSG
    /// context): each is built once and shared by its placements.
    instances: HashMap<InstanceKey, Vec<Arc<dyn crate::shapes::Shape>>>,
}

/// An object value built for placements: (the value's address, its
/// default material, the CSG operation it is inside).
type InstanceKey = (usize, super::MaterialId, Option<&'static str>);

/// Every `material NAME` statement of the items, inside generated ones too.
fn material_names(items: &[Item], out: &mut HashMap<String, Span>) {
    for (i, item) in items.iter().enumerate() {
        match item {
            Item::Traced { items, .. } => material_names(items, out),
            _ if item.as_name().is_some_and(|n| n.node == "material") => {
                if let Some(n) = items.get(i + 1).and_then(Item::as_name) {
                    out.entry(n.node.to_string()).or_insert(n.span);
                }
            }
            _ => {}
        }
    }
}

impl<'p> Builder<'p> {
    fn new(program: &'p Program, transfer: Transfer) -> Self {
        let mut env = Env::new(transfer);
        let mut all_materials = HashMap::new();
        for item in &program.items {
            if let Item::Let { name, .. } | Item::LetItems { name, .. } = item {
                env.all_lets.entry(name.node.clone()).or_insert(name.span);
            }
        }
        material_names(&program.items, &mut all_materials);
        env.material_names = all_materials.keys().cloned().collect();
        let settings = RenderSettings {
            transfer,
            ..RenderSettings::default()
        };
        Builder {
            program,
            env,
            errors: Vec::new(),
            warnings: Vec::new(),
            scene: Scene {
                camera: Camera::default(),
                settings,
                ambient: Colour::ZERO,
                materials: vec![Material::default()],
                ..Scene::default()
            },
            materials: HashMap::new(),
            all_materials,
            singletons: HashMap::new(),
            meshes: HashMap::new(),
            light_surface: None,
            background_given: false,
            instance_lights: HashMap::new(),
            trace: None,
            reported: Default::default(),
            instances: HashMap::new(),
        }
    }

    /// Reports a mistake, saying which loop iteration or call made the
    /// thing it is in.
    fn err(&mut self, mut e: Error) {
        if !self.reported.insert((e.span, e.message.clone())) {
            return;
        }
        if let Some(t) = &self.trace {
            let trail = crate::eval::trail(&t.lines(&self.program.sources));
            e.help = Some(match e.help {
                Some(h) => format!("{h}\n{trail}"),
                None => trail,
            });
        }
        self.errors.push(e);
    }

    /// Runs `f` with `trace` as the current trace (when there is one).
    fn traced<T>(
        &mut self,
        trace: Option<&Arc<crate::eval::Trace>>,
        f: impl FnOnce(&mut Self) -> T,
    ) -> T {
        let Some(t) = trace else {
            return f(self);
        };
        let outer = self.trace.replace(t.clone());
        let out = f(self);
        self.trace = outer;
        out
    }

    fn warn(&mut self, span: Span, text: impl std::fmt::Display) {
        let place = self.program.sources.location(span);
        self.warnings.push(format!("{place}: {text}"));
    }

    // ---- top level ----

    fn top_level(&mut self, items: &[Item]) {
        let mut i = 0;
        while i < items.len() {
            let item = &items[i];
            i += 1;
            if let Item::Traced { trace, items } = item {
                self.traced(Some(trace), |b| b.top_level(items));
                continue;
            }
            if let Some(value) = params::instance_of(item)
                && let Some(Item::Block(b)) = items.get(i)
            {
                i += 1;
                let name = item.as_name().map_or_else(
                    || Spanned::new(String::new(), item.span()),
                    |n| Spanned::new(n.node.to_string(), n.span),
                );
                let shapes = self.instance(&name, value, b, objects::Ctx::TOP);
                self.scene.objects.extend(shapes);
                continue;
            }
            let Some(kw) = item.as_name() else {
                self.err(
                    Error::new(
                        item.span(),
                        format!("expected a statement, found {}", item.describe()),
                    )
                    .label("not a statement")
                    .help("a statement starts with a keyword such as `sphere`, `camera` or `let`"),
                );
                continue;
            };
            let kw = Spanned::new(kw.node.to_string(), kw.span);
            match kw.node.as_str() {
                "camera" | "render" | "light" | "environment" => {
                    let Some(block) = self.block_after(&kw, items, &mut i) else {
                        continue;
                    };
                    match kw.node.as_str() {
                        "camera" => self.camera(&kw, block),
                        "render" => self.render(&kw, block),
                        "environment" => self.environment(&kw, block),
                        _ => self.light(&kw, block),
                    }
                }
                "ambient" => self.ambient(&kw, items, &mut i),
                "material" => self.named_material(&kw, items, &mut i),
                k if objects::is_object(k) => {
                    let shapes = self.object_statement(&kw, items, &mut i, objects::Ctx::TOP);
                    self.scene.objects.extend(shapes);
                }
                other => {
                    let help = did_you_mean(other, STATEMENT_KEYWORDS.iter().copied()).unwrap_or_else(|| {
                        "statements are camera, render, ambient, light, material, let, include and the objects".into()
                    });
                    self.err(
                        Error::new(kw.span, format!("unknown statement `{other}`"))
                            .label("not a statement")
                            .help(help),
                    );
                    // Skip what belongs to it: values and a block.
                    while i < items.len() && items[i].as_name().is_none() {
                        i += 1;
                    }
                }
            }
        }
    }

    /// The `{ … }` after a statement keyword.
    fn block_after<'a>(
        &mut self,
        kw: &Spanned<String>,
        items: &'a [Item],
        i: &mut usize,
    ) -> Option<&'a Block> {
        match items.get(*i) {
            Some(Item::Block(b)) => {
                *i += 1;
                Some(b)
            }
            other => {
                let mut e = Error::new(kw.span, format!("`{}` needs a block `{{ … }}`", kw.node))
                    .label(format!("expected `{{` after `{}`", kw.node));
                if let Some(o) = other {
                    e = e.note(o.span(), format!("found {} instead", o.describe()));
                }
                self.err(e);
                // Skip to the next statement rather than report each stray value.
                while let Some(it) = items.get(*i) {
                    let block_at = |k: usize| matches!(items.get(k), Some(Item::Block(_)));
                    let next_statement = matches!(it, Item::Let { .. })
                        || it.as_name().is_some_and(|n| {
                            STATEMENT_KEYWORDS.contains(&n.node)
                                && (n.node == "ambient" || block_at(*i + 1) || block_at(*i + 2))
                        });
                    if next_statement {
                        break;
                    }
                    *i += 1;
                }
                None
            }
        }
    }

    fn once(&mut self, kw: &Spanned<String>, which: &'static str) -> bool {
        if let Some(first) = self.singletons.get(which) {
            let first = *first;
            self.err(
                Error::new(kw.span, format!("`{which}` is given twice"))
                    .label("second one")
                    .note(first, "first one here")
                    .help(format!("a scene has at most one `{which}`")),
            );
            return false;
        }
        self.singletons.insert(which, kw.span);
        true
    }

    // ---- value helpers: each reports its own mistakes and gives None ----

    fn value(&mut self, item: &Item, expected: &str) -> Option<(Value, Span)> {
        match item {
            Item::Value(e) => {
                let v = self.env.eval(e, &mut self.errors)?;
                Some((v, e.span))
            }
            other => {
                self.err(
                    Error::new(
                        other.span(),
                        format!("expected {expected}, found {}", other.describe()),
                    )
                    .label(format!("expected {expected}")),
                );
                None
            }
        }
    }

    fn wrong_kind(&mut self, span: Span, expected: &str, found: &Value, help: Option<&str>) {
        let mut e = Error::new(span, format!("expected {expected}, found {}", found.kind()))
            .label(format!("this is {}", found.kind()));
        if let Some(h) = help {
            e = e.help(h);
        }
        self.err(e);
    }

    fn number(&mut self, item: &Item) -> Option<(f64, Span)> {
        match self.value(item, "a number")? {
            (Value::Number(v), s) => Some((v, s)),
            (other, s) => {
                self.wrong_kind(s, "a number", &other, None);
                None
            }
        }
    }

    fn vec3(&mut self, item: &Item) -> Option<(DVec3, Span)> {
        match self.value(item, "a 3-vector `<x, y, z>`")? {
            (Value::Vector(v), s) if v.len() == 3 => Some((DVec3::new(v[0], v[1], v[2]), s)),
            (other, s) => {
                let help = match &other {
                    Value::Vector(v) => Some(if v.len() < 3 {
                        "a point or direction has three components: `<x, y, z>`"
                    } else {
                        "a point or direction has exactly three components"
                    }),
                    Value::Number(_) => Some("write a vector as `<x, y, z>`"),
                    _ => None,
                };
                self.wrong_kind(s, "a 3-vector", &other, help);
                None
            }
        }
    }

    fn colour(&mut self, item: &Item) -> Option<(Colour, Span)> {
        match self.value(item, "a colour")? {
            (Value::Colour(c), s) => Some((c, s)),
            (other, s) => {
                let help = match other {
                    Value::Vector(_) => Some("write a linear colour as `rgb(r, g, b)`"),
                    _ => Some("a colour is `rgb(r, g, b)`, `#rrggbb` or a name such as `white`"),
                };
                self.wrong_kind(s, "a colour", &other, help);
                None
            }
        }
    }

    /// A number checked by `ok`; `what` completes "must be …".
    fn checked(&mut self, item: &Item, ok: impl Fn(f64) -> bool, what: &str) -> Option<f64> {
        let (v, s) = self.number(item)?;
        if ok(v) {
            Some(v)
        } else {
            self.err(Error::new(s, format!("this must be {what}")).label(format!("this is {v}")));
            None
        }
    }

    fn positive(&mut self, item: &Item) -> Option<f64> {
        self.checked(item, |v| v > 0.0, "greater than 0")
    }

    /// A whole number in `lo..=hi`.
    fn integer(&mut self, item: &Item, lo: u32, hi: u32) -> Option<u32> {
        let v = self.checked(
            item,
            |v| v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64,
            &format!("a whole number from {lo} to {hi}"),
        )?;
        Some(v as u32)
    }

    /// Reads a block against a schema, reporting unknown, duplicate and
    /// incomplete parameters.
    fn params(&mut self, owner: &str, block: &Block, schema: &Schema) -> Params {
        params::read(owner, block, schema, &self.env, &mut self.errors)
    }

    /// Reports parameters a handler did not take (none should remain).
    fn finish(&mut self, owner: &str, p: Params) {
        for param in p.rest() {
            self.err(
                Error::new(
                    param.name.span,
                    format!("`{}` has no effect in `{owner}`", param.name.node),
                )
                .label("not used"),
            );
        }
    }

    // ---- camera, render, ambient, light ----

    fn camera(&mut self, kw: &Spanned<String>, block: &Block) {
        if !self.once(kw, "camera") {
            return;
        }
        let p = &mut self.params("camera", block, &params::CAMERA);
        let mut cam = Camera::default();
        let position = p.take("position");
        let look_at = p.take("look_at");
        let up = p.take("up");
        let pos = position.as_ref().and_then(|q| self.vec3(&q.values[0]));
        let at = look_at.as_ref().and_then(|q| self.vec3(&q.values[0]));
        let upv = up.as_ref().and_then(|q| self.vec3(&q.values[0]));
        if let Some((v, _)) = pos {
            cam.position = v;
        }
        if let Some((v, _)) = at {
            cam.look_at = v;
        }
        if let Some((v, _)) = upv {
            cam.up = v;
        }
        let fov = p.take("fov");
        let plane: Vec<Param> = ["distance", "width", "height"]
            .iter()
            .filter_map(|n| p.take(n))
            .collect();
        if let Some(f) = &fov {
            if let Some(first) = plane.first() {
                self.err(
                    Error::new(first.name.span, "`fov` and the view plane cannot be mixed")
                        .label("view plane here")
                        .note(f.name.span, "`fov` here")
                        .help("give either `fov`, or all of `distance`, `width` and `height`"),
                );
            } else if let Some(a) = self.checked(
                &f.values[0],
                |a| a > 0.0 && a < 180.0,
                "an angle between 0 and 180 degrees",
            ) {
                cam.projection = Projection::Fov(a);
            }
        } else if !plane.is_empty() {
            if plane.len() < 3 {
                let given: Vec<&str> = plane.iter().map(|q| q.name.node.as_str()).collect();
                let missing: Vec<&str> = ["distance", "width", "height"]
                    .into_iter()
                    .filter(|n| !given.contains(n))
                    .collect();
                self.err(
                    Error::new(
                        plane[0].name.span,
                        format!("the view plane also needs `{}`", missing.join("` and `")),
                    )
                    .label("incomplete view plane")
                    .help("`distance`, `width` and `height` go together"),
                );
            } else {
                let d = self.positive(&plane[0].values[0]);
                let w = self.positive(&plane[1].values[0]);
                let h = self.positive(&plane[2].values[0]);
                if let (Some(distance), Some(width), Some(height)) = (d, w, h) {
                    cam.projection = Projection::ViewPlane {
                        distance,
                        width,
                        height,
                    };
                }
            }
        }
        // The frame: only judge it when every part of it was valid.
        let parts_ok = [&position, &look_at, &up]
            .iter()
            .zip([pos.is_some(), at.is_some(), upv.is_some()])
            .all(|(given, ok)| given.is_none() || ok);
        if parts_ok && cam.frame().is_none() {
            let span_of = |q: &Option<Param>| q.as_ref().map(|q| q.values[0].span());
            if !(cam.look_at - cam.position).length().is_finite() {
                // The view direction's length overflows (a coordinate near
                // 1e155 squares past f64's range): no angle is to blame.
                let at = span_of(&position).or(span_of(&look_at)).unwrap_or(kw.span);
                self.err(
                    Error::new(at, "the camera is too far from `look_at` to aim it")
                        .label("the distance to `look_at` is beyond the range of numbers")
                        .help("keep the camera's coordinates below about 1e150"),
                );
            } else if (cam.look_at - cam.position).length() < 1e-300 {
                let at = span_of(&look_at).or(span_of(&position)).unwrap_or(kw.span);
                self.err(
                    Error::new(at, "the camera looks at its own position")
                        .label("same point as `position`")
                        .help("`look_at` must differ from `position`"),
                );
            } else {
                let at = span_of(&up).unwrap_or(kw.span);
                self.err(
                    Error::new(at, "`up` is parallel to the view direction")
                        .label("parallel to `look_at` − `position`")
                        .help("choose an `up` that is not along the line of sight, e.g. `<0, 1, 0>` or `<0, 0, 1>`"),
                );
            }
        }
        cam.lens = self.lens(p, kw);
        self.scene.camera = cam;
        let p = std::mem::take(p);
        self.finish("camera", p);
    }

    /// `aperture` (lens radius) and `focus`: a thin lens, or `None`.
    fn lens(&mut self, p: &mut Params, kw: &Spanned<String>) -> Option<super::ThinLens> {
        let aperture = p.take("aperture");
        let focus = p.take("focus");
        let a = aperture
            .as_ref()
            .and_then(|q| self.checked(&q.values[0], |x| x >= 0.0 && x.is_finite(), "0 or more"));
        let f = focus.as_ref().and_then(|q| {
            self.checked(&q.values[0], |x| x > 0.0 && x.is_finite(), "greater than 0")
        });
        match (&aperture, &focus) {
            (Some(q), None) if a.is_some_and(|a| a > 0.0) => {
                self.err(
                    Error::new(q.name.span, "a lens `aperture` needs a `focus` distance")
                        .label("no `focus` in this camera")
                        .note(kw.span, "camera here")
                        .help("add `focus D`: the distance along the view direction that is sharp"),
                );
                None
            }
            _ => Some(super::ThinLens {
                aperture: a?,
                focus: f.unwrap_or(1.0),
            }),
        }
    }

    fn render(&mut self, kw: &Spanned<String>, block: &Block) {
        if !self.once(kw, "render") {
            return;
        }
        let mut p = self.params("render", block, &params::RENDER);
        if let Some(q) = p.take("width")
            && let Some(w) = self.integer(&q.values[0], 1, MAX_IMAGE_SIDE)
        {
            self.scene.settings.width = w;
        }
        if let Some(q) = p.take("height")
            && let Some(h) = self.integer(&q.values[0], 1, MAX_IMAGE_SIDE)
        {
            self.scene.settings.height = h;
        }
        if let Some(q) = p.take("max_depth")
            && let Some(d) = self.integer(&q.values[0], 0, MAX_DEPTH)
        {
            self.scene.settings.max_depth = d;
        }
        if let Some(q) = p.take("background")
            && let Some((c, _)) = self.colour(&q.values[0])
        {
            self.scene.settings.background = c;
            self.background_given = true;
        }
        if let Some(q) = p.take("samples")
            && let Some(n) = self.integer(&q.values[0], 1, super::MAX_SAMPLES)
        {
            self.scene.settings.samples = n;
        }
        if let Some(q) = p.take("gamma") {
            // Already applied by `find_transfer`; checked here for mistakes.
            self.transfer_value(&q.values[0]);
        }
        if let Some(q) = p.take("sampler") {
            const KINDS: [&str; 4] = ["regular", "random", "jittered", "multijittered"];
            let kind = match q.values[0].as_name().map(|n| n.node) {
                Some("regular") => Some(super::SamplerKind::Regular),
                Some("random") => Some(super::SamplerKind::Random),
                Some("jittered") => Some(super::SamplerKind::Jittered),
                Some("multijittered" | "multi_jittered") => Some(super::SamplerKind::MultiJittered),
                _ => None,
            };
            match kind {
                Some(k) => self.scene.settings.sampler = k,
                None => {
                    let at = q.values[0].span();
                    let help = q.values[0]
                        .as_name()
                        .and_then(|n| did_you_mean(n.node, KINDS))
                        .unwrap_or_else(|| format!("the samplers are {}", KINDS.join(", ")));
                    self.err(
                        Error::new(at, "unknown sampler")
                            .label("expected `regular`, `random`, `jittered` or `multijittered`")
                            .help(help),
                    );
                }
            }
        }
        if let Some(q) = p.take("seed")
            && let Some(n) = self.integer(&q.values[0], 0, u32::MAX)
        {
            self.scene.settings.seed = n as u64;
        }
        self.finish("render", p);
    }

    fn transfer_value(&mut self, item: &Item) -> Option<Transfer> {
        if let Some(n) = item.as_name() {
            match n.node {
                "srgb" => return Some(Transfer::Srgb),
                "linear" => return Some(Transfer::Linear),
                _ if !item.is_bound_name() => {
                    self.err(
                        Error::new(n.span, format!("unknown transfer curve `{}`", n.node))
                            .label("expected `srgb`, `linear` or a number")
                            .maybe_help(did_you_mean(n.node, ["srgb", "linear"])),
                    );
                    return None;
                }
                _ => {}
            }
        }
        let g = self.checked(
            item,
            |g| g > 0.0 && g <= 10.0,
            "a number from 0 (exclusive) to 10",
        )?;
        Some(Transfer::Gamma(g))
    }

    fn ambient(&mut self, kw: &Spanned<String>, items: &[Item], i: &mut usize) {
        let first = self.once(kw, "ambient");
        let Some(c) = items
            .get(*i)
            .filter(|it| it.as_name().is_none_or(|n| n.node != "intensity"))
        else {
            self.err(
                Error::new(kw.span, "`ambient` needs a colour")
                    .label("expected a colour after `ambient`")
                    .help("e.g. `ambient rgb(1, 1, 1) intensity 0.1`"),
            );
            return;
        };
        *i += 1;
        let colour = self.colour(c);
        let mut intensity = Some(1.0);
        if items
            .get(*i)
            .and_then(Item::as_name)
            .is_some_and(|n| n.node == "intensity")
        {
            let at = items[*i].span();
            *i += 1;
            match items.get(*i) {
                Some(v)
                    if v.as_name()
                        .is_none_or(|n| !STATEMENT_KEYWORDS.contains(&n.node)) =>
                {
                    *i += 1;
                    intensity = self.checked(v, |x| x >= 0.0, "0 or more");
                }
                _ => {
                    self.err(
                        Error::new(at, "`intensity` is missing its value")
                            .label("expected a number after `intensity`"),
                    );
                    intensity = None;
                }
            }
        }
        if let (true, Some((c, _)), Some(k)) = (first, colour, intensity) {
            self.scene.ambient = c * k;
        }
        if items
            .get(*i)
            .and_then(Item::as_name)
            .is_some_and(|n| n.node == "occlusion")
        {
            let at = Spanned::new("occlusion".to_string(), items[*i].span());
            *i += 1;
            if let Some(block) = self.block_after(&at, items, i) {
                self.occlusion(block);
            }
        }
    }

    /// `occlusion { samples n  min m  distance d }` after `ambient`.
    fn occlusion(&mut self, block: &Block) {
        let mut p = self.params("occlusion", block, &params::OCCLUSION);
        let mut o = super::Occlusion {
            samples: 16,
            min: 0.0,
            distance: f64::INFINITY,
        };
        let mut ok = true;
        if let Some(q) = p.take("samples") {
            match self.integer(&q.values[0], 1, 1024) {
                Some(n) => o.samples = n,
                None => ok = false,
            }
        }
        if let Some(q) = p.take("min") {
            match self.checked(
                &q.values[0],
                |x| (0.0..=1.0).contains(&x),
                "between 0 and 1",
            ) {
                Some(m) => o.min = m,
                None => ok = false,
            }
        }
        if let Some(q) = p.take("distance") {
            match self.positive(&q.values[0]) {
                Some(d) => o.distance = d,
                None => ok = false,
            }
        }
        self.finish("occlusion", p);
        if ok {
            self.scene.occlusion = Some(o);
        }
    }

    /// `environment { colour c  intensity k  samples n }`: light from every
    /// direction, and what camera rays that miss see unless a `background`
    /// is set.
    fn environment(&mut self, kw: &Spanned<String>, block: &Block) {
        if !self.once(kw, "environment") {
            return;
        }
        let mut p = self.params("environment", block, &params::ENVIRONMENT);
        let colour = match p.take("colour") {
            Some(q) => self.colour(&q.values[0]).map(|c| c.0),
            None => Some(Colour::ONE),
        };
        let intensity = match p.take("intensity") {
            Some(q) => self.checked(&q.values[0], |x| x >= 0.0, "0 or more"),
            None => Some(1.0),
        };
        let samples = match p.take("samples") {
            Some(q) => self.integer(&q.values[0], 1, 1024),
            None => Some(1),
        };
        let image = match p.take("image") {
            None => Some(None),
            Some(q) => match &q.values[0] {
                Item::Str { text, content, .. } => self.sky_image(text, *content).map(Some),
                other => {
                    self.err(
                        Error::new(
                            other.span(),
                            format!("expected a file name, found {}", other.describe()),
                        )
                        .label("not a string")
                        .help("e.g. `environment { image \"sky.hdr\" }`"),
                    );
                    None
                }
            },
        };
        self.finish("environment", p);
        if let (Some(c), Some(k), Some(samples), Some(image)) = (colour, intensity, samples, image)
        {
            self.scene.environment = Some(super::Environment {
                colour: c * k,
                samples,
                image,
                visible: true,
            });
        }
    }

    /// An environment's sky image: HDR and EXR are linear radiance; 8-bit
    /// images are decoded with the scene's curve.
    fn sky_image(&mut self, file: &str, span: Span) -> Option<Arc<super::texture::ImageTexture>> {
        let path = self.program.sources.dir_of(span.file).join(file);
        match super::texture::ImageTexture::load(&path, self.env.transfer, Default::default()) {
            Ok(img) => Some(Arc::new(img)),
            Err(e) => {
                self.err(
                    Error::new(span, format!("cannot use the image `{file}`: {e}"))
                        .label(format!("looked for {}", path.display()))
                        .help("an image path is relative to the scene file that names it"),
                );
                None
            }
        }
    }

    fn light(&mut self, kw: &Spanned<String>, block: &Block) {
        let mut p = self.params("light", block, &params::LIGHT);
        let direction = p.take("direction");
        let position = match p.take("position") {
            Some(q) => self.vec3(&q.values[0]).map(|v| v.0),
            None if p.had_unknown || direction.is_some() => None,
            None => {
                self.err(
                    Error::new(kw.span, "a `light` needs a `position`")
                        .label("no position")
                        .help("e.g. `light { position <5, 10, 5> }`"),
                );
                None
            }
        };
        let colour = match p.take("colour") {
            Some(q) => self.colour(&q.values[0]).map(|c| c.0),
            None => Some(Colour::ONE),
        };
        let intensity = match p.take("intensity") {
            Some(q) => self.checked(&q.values[0], |x| x >= 0.0, "0 or more"),
            None => Some(1.0),
        };
        let kind = self.light_kind(kw, &mut p, direction, position);
        if let (Some(kind), Some(colour), Some(k)) = (kind, colour, intensity) {
            self.scene.lights.push(Light {
                position: position.unwrap_or(DVec3::ZERO),
                colour: colour * k,
                kind,
            });
        }
        self.finish("light", p);
    }

    /// Point (a position), parallel (a direction) or spot (a position, a
    /// `look_at` and angles).
    fn light_kind(
        &mut self,
        kw: &Spanned<String>,
        p: &mut Params,
        direction: Option<Param>,
        position: Option<DVec3>,
    ) -> Option<super::LightKind> {
        let look_at = p.take("look_at");
        let angle = p.take("angle");
        let falloff = p.take("falloff");
        if let Some(d) = direction {
            if let Some(other) = look_at.as_ref().or(angle.as_ref()).or(falloff.as_ref()) {
                self.err(
                    Error::new(
                        other.name.span,
                        format!("`{}` has no effect on a parallel light", other.name.node),
                    )
                    .label("not used")
                    .note(d.name.span, "`direction` makes this a parallel light"),
                );
            }
            let (v, s) = self.vec3(&d.values[0])?;
            let Some(dir) = v.try_normalize() else {
                self.err(Error::new(s, "a light's direction cannot be zero").label("zero vector"));
                return None;
            };
            return Some(super::LightKind::Parallel { direction: dir });
        }
        let Some(target) = look_at else {
            if let Some(q) = angle.as_ref().or(falloff.as_ref()) {
                self.err(
                    Error::new(
                        q.name.span,
                        format!("`{}` needs a `look_at` (a spot light)", q.name.node),
                    )
                    .label("no `look_at` in this light")
                    .note(kw.span, "light here"),
                );
                return None;
            }
            position?;
            return Some(super::LightKind::Point);
        };
        let (at, s) = self.vec3(&target.values[0])?;
        let angle_deg = match &angle {
            Some(q) => self.checked(
                &q.values[0],
                |a| a > 0.0 && a < 90.0,
                "an angle between 0 and 90 degrees",
            )?,
            None => 30.0,
        };
        let falloff_deg = match &falloff {
            Some(q) => self.checked(
                &q.values[0],
                |a| a >= angle_deg && a < 90.0,
                &format!("an angle from `angle` ({angle_deg}) to 90 degrees"),
            )?,
            None => angle_deg,
        };
        let axis = (at - position?).try_normalize();
        let Some(axis) = axis else {
            self.err(
                Error::new(s, "a spot light looks at its own position")
                    .label("same point as `position`"),
            );
            return None;
        };
        Some(super::LightKind::Spot {
            axis,
            cos_angle: angle_deg.to_radians().cos(),
            cos_falloff: falloff_deg.to_radians().cos(),
        })
    }

    // ---- materials ----

    fn named_material(&mut self, kw: &Spanned<String>, items: &[Item], i: &mut usize) {
        let Some(name) = items.get(*i).and_then(Item::as_name) else {
            self.err(
                Error::new(kw.span, "a `material` statement needs a name and a block")
                    .label("expected a name after `material`")
                    .help("e.g. `material gold { colour rgb(1, 0.8, 0.2)  reflect 0.3 }`"),
            );
            return;
        };
        let name = Spanned::new(name.node.to_string(), name.span);
        *i += 1;
        let Some(block) = self.block_after(&name, items, i) else {
            return;
        };
        let m = self.material_block(block);
        if let Some((_, first)) = self.materials.get(&name.node) {
            let first = *first;
            self.err(
                Error::new(
                    name.span,
                    format!("material `{}` is already declared", name.node),
                )
                .label("declared again")
                .note(first, "first declared here"),
            );
            return;
        }
        let id = self.add_material(m.unwrap_or_default());
        self.materials.insert(name.node, (id, name.span));
    }

    fn add_material(&mut self, m: Material) -> super::MaterialId {
        self.scene.materials.push(m);
        (self.scene.materials.len() - 1) as super::MaterialId
    }

    fn material_block(&mut self, block: &Block) -> Option<Material> {
        let mut p = self.params("material", block, &params::MATERIAL);
        let mut m = Material::default();
        let mut ok = true;
        if let Some(q) = p.take("colour") {
            match self.texture(&q.values) {
                Some(t) => m.texture = t,
                None => ok = false,
            }
        }
        if let Some(q) = p.take("reflect") {
            match self.checked(
                &q.values[0],
                |r| (0.0..=1.0).contains(&r),
                "between 0 and 1",
            ) {
                Some(r) => m.reflect = r,
                None => ok = false,
            }
        }
        ok &= self.round2_material(&mut p, &mut m);
        self.finish("material", p);
        ok.then_some(m)
    }

    /// The 2018 parts of a material (see `render/material/`). Glass and
    /// lamps have no diffuse or ambient part unless they say so.
    fn round2_material(&mut self, p: &mut Params, m: &mut Material) -> bool {
        let mut ok = true;
        let mut weight = |b: &mut Self, name: &str| -> Option<f64> {
            let q = p.take(name)?;
            let v = b.checked(&q.values[0], |x| x >= 0.0 && x.is_finite(), "0 or more");
            ok &= v.is_some();
            v
        };
        let diffuse = weight(self, "diffuse");
        let ambient = weight(self, "ambient");
        let specular = weight(self, "specular");
        let mirror = weight(self, "mirror");
        let intensity = weight(self, "intensity");
        let mut positive = |b: &mut Self, name: &str| -> Option<(f64, Span)> {
            let q = p.take(name)?;
            let v = b.checked(&q.values[0], |x| x > 0.0 && x.is_finite(), "greater than 0");
            ok &= v.is_some();
            v.map(|v| (v, q.name.span))
        };
        let shininess = positive(self, "shininess");
        let glossy = positive(self, "glossy");
        let mut colour = |b: &mut Self, name: &str| -> Option<(Colour, Span)> {
            let q = p.take(name)?;
            let v = b.colour(&q.values[0]);
            ok &= v.is_some();
            v.map(|(c, _)| (c, q.name.span))
        };
        let specular_colour = colour(self, "specular_colour");
        let mirror_colour = colour(self, "mirror_colour");
        let emit = colour(self, "emit");
        let refract = p.take("refract");
        if let Some(q) = &refract {
            match self.refract_block(&q.values[0]) {
                Some(d) => m.refract = Some(d),
                None => ok = false,
            }
        }
        if let Some((c, _)) = emit {
            m.emit = c * intensity.unwrap_or(1.0);
        }
        if refract.is_some() || emit.is_some() {
            m.diffuse = 0.0;
            m.ambient = 0.0;
        }
        if let Some(kd) = diffuse {
            m.diffuse = kd;
        }
        if let Some(ka) = ambient {
            m.ambient = ka;
        }
        if specular.is_some() || shininess.is_some() || specular_colour.is_some() {
            let ks = specular.unwrap_or(1.0);
            let cs = specular_colour.map_or(Colour::ONE, |c| c.0);
            m.phong = Some(super::Phong {
                colour: cs * ks,
                shininess: shininess.map_or(20.0, |s| s.0),
            });
        }
        if mirror.is_some() || mirror_colour.is_some() || glossy.is_some() {
            let kr = mirror.unwrap_or(1.0);
            let cr = mirror_colour.map_or(Colour::ONE, |c| c.0);
            m.mirror = cr * kr;
            m.glossy = glossy.map(|g| g.0);
        }
        ok
    }

    fn refract_block(&mut self, item: &Item) -> Option<super::Dielectric> {
        let Item::Block(block) = item else {
            self.err(
                Error::new(
                    item.span(),
                    format!("expected a block, found {}", item.describe()),
                )
                .label("not a block")
                .help("e.g. `refract { ior 1.5  filter rgb(0.9, 1, 0.95) }`"),
            );
            return None;
        };
        let mut p = self.params("refract", block, &params::REFRACT);
        let mut d = super::Dielectric::default();
        let mut ok = true;
        for (name, slot) in [("ior", &mut d.ior), ("outside_ior", &mut d.outside_ior)] {
            if let Some(q) = p.take(name) {
                match self.checked(&q.values[0], |x| x > 0.0 && x.is_finite(), "greater than 0") {
                    Some(v) => *slot = v,
                    None => ok = false,
                }
            }
        }
        for (name, slot) in [
            ("filter", &mut d.filter),
            ("outside_filter", &mut d.outside_filter),
        ] {
            if let Some(q) = p.take(name) {
                match self.colour(&q.values[0]) {
                    Some((c, _)) if c.max_element() <= 1.0 => *slot = c,
                    Some((c, s)) => {
                        self.err(
                            Error::new(s, "a filter cannot exceed 1 in any channel")
                                .label(format!("this is rgb({}, {}, {})", c.x, c.y, c.z))
                                .help("a filter is the share of light left after one unit of distance"),
                        );
                        ok = false;
                    }
                    None => ok = false,
                }
            }
        }
        self.finish("refract", p);
        ok.then_some(d)
    }

    /// `material NAME` or `material { … }` inside an object.
    fn material_value(&mut self, item: &Item) -> Option<super::MaterialId> {
        if let Item::Block(b) = item {
            let m = self.material_block(b)?;
            return Some(self.add_material(m));
        }
        let Some(n) = item.as_name() else {
            self.err(
                Error::new(
                    item.span(),
                    format!("expected a material, found {}", item.describe()),
                )
                .label("not a material")
                .help("give a material's name, or `{ colour …  reflect … }`"),
            );
            return None;
        };
        if let Some((id, _)) = self.materials.get(n.node) {
            return Some(*id);
        }
        let mut e =
            Error::new(n.span, format!("unknown material `{}`", n.node)).label("not declared");
        if let Some(later) = self.all_materials.get(n.node) {
            e = e
                .note(*later, "declared here")
                .help("a material must be declared before it is used; move its declaration up");
        } else {
            e = e.maybe_help(did_you_mean(
                n.node,
                self.materials.keys().map(String::as_str),
            ));
        }
        self.err(e);
        None
    }
}

/// The output curve from `render { gamma … }`, found before anything else
/// is built because it decides what `#rrggbb` and named colours mean.
/// Mistakes are ignored here: the build reports them in place.
fn find_transfer(items: &[Item]) -> Transfer {
    let mut env = Env::new(Transfer::Srgb);
    let mut quiet = Vec::new();
    for (i, item) in items.iter().enumerate() {
        if let Item::Let { name, value, .. } = item {
            if !env.constants.contains_key(&name.node) {
                let v = env.eval(value, &mut quiet);
                env.constants.insert(
                    name.node.clone(),
                    Constant {
                        value: v,
                        span: name.span,
                    },
                );
            }
            continue;
        }
        if item.as_name().is_none_or(|n| n.node != "render") {
            continue;
        }
        let Some(Item::Block(b)) = items.get(i + 1) else {
            continue;
        };
        let at = b
            .items
            .iter()
            .position(|it| it.as_name().is_some_and(|n| n.node == "gamma"));
        let Some(v) = at.and_then(|k| b.items.get(k + 1)) else {
            return Transfer::Srgb;
        };
        return match v.as_name().map(|n| n.node) {
            Some("srgb") => Transfer::Srgb,
            Some("linear") => Transfer::Linear,
            _ => match v {
                Item::Value(e) => match env.eval(e, &mut quiet) {
                    Some(Value::Number(g)) if g > 0.0 && g <= 10.0 => Transfer::Gamma(g),
                    _ => Transfer::Srgb,
                },
                _ => Transfer::Srgb,
            },
        };
    }
    Transfer::Srgb
}
