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
mod catalogue;
mod lights;
mod materials;
mod objects;
mod params;
mod patterns;
mod pipeline;
mod settings;
mod textures;
mod transforms;

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

pub use catalogue::{ParamInfo, block_parameters};
pub use objects::is_object;
pub use params::{canonical as canonical_parameter, is_transform};

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
    let checked = check(program, options);
    if checked.errors.is_empty() {
        let warnings = checked
            .warnings
            .iter()
            .map(|(span, text)| format!("{}: {text}", program.sources.location(*span)))
            .collect();
        Ok((checked.scene, warnings))
    } else {
        Err(program.problems(checked.errors))
    }
}

/// Everything building a program finds, for a caller that shows it itself
/// (the language server).
pub struct Checked {
    /// The scene as far as it could be built.
    pub scene: Scene,
    /// Every mistake, each reported once.
    pub errors: Vec<Error>,
    /// What renders but perhaps not as meant, at its place.
    pub warnings: Vec<(Span, String)>,
    /// The top-level `let`s and their values.
    pub bound: Vec<crate::eval::TopLevel>,
}

/// Evaluates and builds, keeping the mistakes and warnings as they are.
pub fn check(program: &Program, options: &crate::eval::Options) -> Checked {
    let transfer = find_transfer(&program.items);
    let mut b = Builder::new(program, transfer);
    // Meshes are indexed as they load, so the choice is read first too.
    b.scene.settings.accel = options
        .accel
        .or_else(|| find_accel(&program.items))
        .unwrap_or_default();
    let (eval_errors, bound) = pipeline::evaluate_and_build(&mut b, options);
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
    Checked {
        scene: b.scene,
        errors: b.errors,
        warnings: b.warnings,
        bound,
    }
}

struct Builder<'p> {
    program: &'p Program,
    env: Env,
    errors: Vec<Error>,
    warnings: Vec<(Span, String)>,
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
    /// How many loop iterations or calls (each with its trace) enclose
    /// what is being built.
    traced_depth: u32,
    /// Mistakes reported inside the innermost of those, by index in
    /// `errors`, waiting for its trace: each is added to its message when
    /// the iteration has been read ([`Builder::traced`]) rather than the
    /// trace being copied in for every iteration, mistake or not (a copy
    /// is two atomic counts on a line the evaluator's thread is counting
    /// on too).
    untrailed: Vec<usize>,
    /// Mistakes reported so far, by place and message: one written inside
    /// a loop is reported once (for the first iteration), not per iteration.
    reported: std::collections::HashSet<(Span, String)>,
    /// Object values built so far, by (value, default material, CSG
    /// context): each is built once and shared by its placements.
    instances: HashMap<InstanceKey, Vec<Arc<dyn crate::shapes::Shape>>>,
    /// Plain materials added so far, by their numbers: equal ones share an id.
    plain_materials: HashMap<materials::PlainKey, super::MaterialId, materials::WordHash>,
    /// Plain materials by the words of the block that made them
    /// ([`materials::block_key`]): a loop's `material { colour rgb(…) }`
    /// built once for each distinct block, not once per object.
    block_materials: HashMap<Box<[u64]>, super::MaterialId, materials::WordHash>,
    /// Mistakes reported so far, those already seen included (so that a
    /// build can tell it met none: [`Builder::errors`] holds each once).
    err_calls: usize,
    /// Per material made so far, what it may show through the materials
    /// it may choose ([`Builder::material_reach`]).
    material_reach: Vec<materials::Reach>,
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
            traced_depth: 0,
            untrailed: Vec::new(),
            reported: Default::default(),
            instances: HashMap::new(),
            plain_materials: HashMap::default(),
            block_materials: HashMap::default(),
            err_calls: 0,
            material_reach: Vec::new(),
        }
    }

    /// Reports a mistake, saying which loop iteration or call made the
    /// thing it is in (added once that iteration has been read: see
    /// [`Builder::traced`]).
    fn err(&mut self, e: Error) {
        self.err_calls += 1;
        if !self.reported.insert((e.span, e.message.clone())) {
            return;
        }
        if self.traced_depth > 0 {
            self.untrailed.push(self.errors.len());
        }
        self.errors.push(e);
    }

    /// Runs `f` with `trace` as the current trace (when there is one).
    fn traced<T>(
        &mut self,
        trace: Option<&crate::eval::TraceRef>,
        f: impl FnOnce(&mut Self) -> T,
    ) -> T {
        let Some(t) = trace else {
            return f(self);
        };
        let mark = self.untrailed.len();
        self.traced_depth += 1;
        let out = f(self);
        self.traced_depth -= 1;
        if self.untrailed.len() > mark {
            let trail = crate::eval::trail(&t.lines(&self.program.sources));
            for i in self.untrailed.drain(mark..) {
                let e = &mut self.errors[i];
                e.help = Some(match e.help.take() {
                    Some(h) => format!("{h}\n{trail}"),
                    None => trail.clone(),
                });
            }
        }
        out
    }

    fn warn(&mut self, span: Span, text: impl std::fmt::Display) {
        self.warnings.push((span, text.to_string()));
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
            match kw.node {
                "camera" | "render" | "light" | "environment" => {
                    let Some(block) = self.block_after(&kw, items, &mut i) else {
                        continue;
                    };
                    match kw.node {
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
        kw: &Spanned<&str>,
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

    fn once(&mut self, kw: &Spanned<&str>, which: &'static str) -> bool {
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
        // A 3-vector the evaluator worked out (a loop's `centre <…>`) is
        // read where it lies rather than copied out by `value`.
        if let Item::Value(crate::lang::ast::Expr {
            kind: crate::lang::ast::ExprKind::Value(Value::Vector(v)),
            span,
        }) = item
            && let [x, y, z] = v[..]
        {
            return Some((DVec3::new(x, y, z), *span));
        }
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
        self.check(v, s, ok, what)
    }

    /// [`Builder::checked`] for a number already worked out, at span `s`.
    fn check(&mut self, v: f64, s: Span, ok: impl Fn(f64) -> bool, what: &str) -> Option<f64> {
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
        let (v, s) = self.number(item)?;
        self.whole(v, s, lo, hi)
    }

    /// [`Builder::integer`] for a number already worked out, at span `s`.
    fn whole(&mut self, v: f64, s: Span, lo: u32, hi: u32) -> Option<u32> {
        let v = self.check(
            v,
            s,
            |v| v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64,
            &format!("a whole number from {lo} to {hi}"),
        )?;
        Some(v as u32)
    }

    /// Reads a block against a schema, reporting unknown, duplicate and
    /// incomplete parameters.
    fn params<'b>(&mut self, owner: &str, block: &'b Block, schema: &Schema) -> Params<'b> {
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

    /// The block a parameter such as `refract { … }` must be given;
    /// reported (with `example` as the help) when it is something else.
    fn block_of<'i>(&mut self, item: &'i Item, example: &str) -> Option<&'i Block> {
        if let Item::Block(block) = item {
            return Some(block);
        }
        self.err(
            Error::new(
                item.span(),
                format!("expected a block, found {}", item.describe()),
            )
            .label("not a block")
            .help(format!("e.g. `{example}`")),
        );
        None
    }

    /// Reads the optional parameter `name` with `read` and hands the value
    /// to `set`. False when it was given but wrong (`read` has reported
    /// it), so a caller can drop the whole block after reading the rest.
    fn take_into<T>(
        &mut self,
        p: &mut Params,
        name: &str,
        read: impl FnOnce(&mut Self, &params::Param) -> Option<T>,
        set: impl FnOnce(T),
    ) -> bool {
        let Some(q) = p.take(name) else {
            return true;
        };
        match read(self, &q) {
            Some(v) => {
                set(v);
                true
            }
            None => false,
        }
    }
}

/// The output curve from `render { gamma … }`, found before anything else
/// is built because it decides what `#rrggbb` and named colours mean.
/// Mistakes are ignored here: the build reports them in place.
/// `render { accel NAME }` read before the scene is built (a mistake in
/// it is reported when the `render` block is).
fn find_accel(items: &[Item]) -> Option<crate::accel::Accel> {
    items.iter().enumerate().find_map(|(i, item)| {
        item.as_name().filter(|n| n.node == "render")?;
        let Some(Item::Block(b)) = items.get(i + 1) else {
            return None;
        };
        let at = b
            .items
            .iter()
            .position(|it| it.as_name().is_some_and(|n| n.node == "accel"))?;
        crate::accel::Accel::from_name(b.items.get(at + 1)?.as_name()?.node)
    })
}

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
