//! Building patterns (`scene::pattern`) from their blocks: as a colour
//! (`colour marble { … }`), as a choice of whole materials
//! (`material tiles { checker { a m1  b m2 } }`) and as a tilt of the
//! shading normal (`normal bumps { … }`).
//!
//! ```text
//! colour granite  { colour_map { 0 #303030  0.6 #808080  1 white }  scale 2 }
//! colour gradient { axis <0, 1, 0>  a red  b blue  translate <0, 0.5, 0> }
//! material tiles  { checker { a marble_white  b { colour black  mirror 0.8 }  scale <8, 8> } }
//! material camo   { noise { material_map { 0 olive  0.45 sand  0.6 moss }  scale 3 } }
//! material rough  { colour white  normal bumps { amount 0.3  scale 10 } }
//! ```

use super::params::{Param, Params, Schema, Spec, spec};
use super::{Builder, Colour, Material, Texture};
use crate::eval::expr::Value;
use crate::geometry::{DVec2, DVec3};
use crate::lang::ast::{Block, Item, Span, Spanned};
use crate::lang::diagnostics::{Error, did_you_mean};
use crate::scene::MaterialId;
use crate::scene::pattern::{
    self, Checker, Checker3d, ColourMap, ColourPattern, Gradient, Granite, ImagePattern, Kind,
    MapError, Marble, MaterialPick, Noise, NormalKind, NormalPattern, Pattern, Sectors, Wood,
};
use std::sync::Arc;

/// What a pattern's values are: colours (`colour …`) or materials.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Target {
    Colour,
    Material,
}

/// A pattern as written: its name, an optional string, an optional block.
pub(super) struct Written<'a> {
    pub name: Spanned<&'a str>,
    pub string: Option<(&'a str, Span)>,
    pub block: Option<&'a Block>,
}

const TRANSLATE: Spec = spec("translate", 1, "a 3-vector (`<u, v, 0>` on (u, v))");
const ROTATE: Spec = spec(
    "rotate",
    2,
    "an axis (`x`, `y`, `z` or a vector) and an angle in degrees",
);
const TURBULENCE: Spec = spec("turbulence", 1, "a number, 0 or more");
const SCALE: Spec = spec("scale", 1, "a number or a 3-vector (repeats per unit)");
const A: Spec = spec("a", 1, "a colour (a material in a material pattern)");
const B: Spec = spec("b", 1, "a colour (a material in a material pattern)");
const COLOUR_MAP: Spec = spec(
    "colour_map",
    1,
    "a block of keys and colours `{ 0 black  0.5 red  1 white }`",
);
const MATERIAL_MAP: Spec = spec(
    "material_map",
    1,
    "a block of keys and materials `{ 0 stone  0.5 { colour red } }`",
);

/// The schema of each pattern: its own parameters, then the map ones.
macro_rules! schema {
    ($($s:expr),* $(,)?) => {
        Schema {
            own: &[$($s,)* A, B, COLOUR_MAP, MATERIAL_MAP, TRANSLATE, ROTATE],
            object: false,
            children: false,
        }
    };
}

const CHECKER: Schema = schema!(spec(
    "scale",
    1,
    "a number or a 2-vector `<ku, kv>` (cells per unit of u and v)"
));
const CHECKER3D: Schema = schema!(spec("size", 1, "a positive number"), SCALE, TURBULENCE);
const GRADIENT: Schema = schema!(
    spec("axis", 1, "a 3-vector (the direction it rises along)"),
    spec("mirror", 0, "nothing"),
    SCALE,
    TURBULENCE
);
const NOISE: Schema = schema!(
    spec("octaves", 1, "a whole number from 1 to 10"),
    SCALE,
    TURBULENCE
);
const PLAIN: Schema = schema!(SCALE, TURBULENCE);
const SECTORS: Schema = schema!(
    spec("count", 1, "a whole number of sectors from 2 to 360"),
    spec("uv", 0, "nothing"),
    spec("alternate", 0, "nothing"),
    SCALE,
    TURBULENCE
);
const QUADRANTS: Schema = schema!(
    spec("uv", 0, "nothing"),
    spec("alternate", 0, "nothing"),
    SCALE,
    TURBULENCE
);
const IMAGE: Schema = schema!(
    spec("scale", 1, "a 2-vector `<su, sv>` or a number"),
    spec("offset", 1, "a 2-vector `<ou, ov>`"),
    spec("swap", 0, "nothing"),
    spec("flip_u", 0, "nothing"),
    spec("flip_v", 0, "nothing"),
);

pub(super) const NORMALS: &[&str] = &["bumps", "ripples", "waves"];
pub(super) const NORMAL: Schema = Schema {
    own: &[
        spec("amount", 1, "a number, 0 or more (how far it tilts)"),
        SCALE,
        spec("centre", 1, "a 3-vector (ripples and waves)"),
        TRANSLATE,
        ROTATE,
    ],
    object: false,
    children: false,
};

pub(super) fn schema_of(kind: &str) -> &'static Schema {
    match kind {
        "checker" => &CHECKER,
        "checker3d" => &CHECKER3D,
        "gradient" => &GRADIENT,
        "noise" => &NOISE,
        "sectors" => &SECTORS,
        "quadrants" => &QUADRANTS,
        "image" => &IMAGE,
        _ => &PLAIN,
    }
}

/// Whether `items` (a material's block) is a material pattern: a pattern
/// name, perhaps a string, and a block.
pub(super) fn material_pattern(items: &[Item]) -> Option<Written<'_>> {
    let name = items.first()?.as_name()?;
    if !pattern::NAMES.contains(&name.node) || items.first()?.is_bound_name() {
        return None;
    }
    let (string, rest) = match items.get(1) {
        Some(Item::Str { text, content, .. }) => (Some((text.as_str(), *content)), &items[2..]),
        _ => (None, &items[1..]),
    };
    let block = match rest.first() {
        Some(Item::Block(b)) => Some(b),
        _ if string.is_some() => None,
        _ => return None,
    };
    Some(Written {
        name,
        string,
        block,
    })
}

impl Builder<'_> {
    /// `colour NAME "string"? { … }` for any pattern but a plain image.
    pub(super) fn colour_pattern(&mut self, w: &Written) -> Option<Texture> {
        let (pattern, mut p) = self.pattern(w, Target::Colour)?;
        let mut ok = true;
        let map = match p.take("colour_map") {
            Some(q) => {
                if let Some(first) = p.take("a").or_else(|| p.take("b")) {
                    self.both_given(&first, &q);
                    ok = false;
                }
                self.colour_map(&q)
            }
            None => {
                let mut end = |b: &mut Self, name: &str, default: Colour| match p.take(name) {
                    Some(q) => b.pattern_colour(&q.values[0]).unwrap_or_else(|| {
                        ok = false;
                        default
                    }),
                    None => default,
                };
                let a = end(self, "a", Colour::ONE);
                let b = end(self, "b", Colour::ZERO);
                Some(ColourMap::two(a, b))
            }
        };
        self.finish(w.name.node, p);
        let map = map?;
        ok.then(|| Texture::Pattern(Arc::new(ColourPattern { pattern, map })))
    }

    /// `material NAME { PATTERN { a m1  b m2 … } }`: a material that stands
    /// for the ones its pattern chooses.
    pub(super) fn picking_material(&mut self, w: &Written, rest: &[Item]) -> Option<Material> {
        if let Some(extra) = rest.first() {
            self.err(
                Error::new(
                    extra.span(),
                    "a material pattern takes nothing after its pattern",
                )
                .label("not used")
                .help("give these parameters to the materials the pattern chooses"),
            );
        }
        let (pattern, mut p) = self.pattern(w, Target::Material)?;
        let bands = match p.take("material_map") {
            Some(q) => {
                if let Some(first) = p.take("a").or_else(|| p.take("b")) {
                    self.both_given(&first, &q);
                }
                self.material_map(&q)
            }
            None => match (p.take("a"), p.take("b")) {
                (Some(a), Some(b)) => {
                    let a = self.chosen_material(&a.values[0]);
                    let b = self.chosen_material(&b.values[0]);
                    Some(vec![(0.0, a?), (0.5, b?)])
                }
                _ => {
                    self.err(
                        Error::new(
                            w.name.span,
                            format!("a material `{}` needs its materials", w.name.node),
                        )
                        .label("no `a` and `b`, no `material_map`")
                        .help(format!(
                            "e.g. `{} {{ a stone  b {{ colour black  mirror 0.8 }} }}`",
                            w.name.node
                        )),
                    );
                    None
                }
            },
        };
        self.finish(w.name.node, p);
        Some(Material {
            pick: Some(Arc::new(MaterialPick {
                pattern,
                bands: bands?,
            })),
            ..Material::default()
        })
    }

    /// A material chosen by a pattern; a colour there is a kind error.
    fn chosen_material(&mut self, item: &Item) -> Option<MaterialId> {
        let declared = item.as_name().is_some_and(|n| {
            self.materials.contains_key(n.node) || self.all_materials.contains_key(n.node)
        });
        if let Item::Value(e) = item
            && !declared
        {
            let mut quiet = Vec::new();
            if let Some(Value::Colour(_)) = self.env.eval(e, &mut quiet) {
                self.err(
                    Error::new(e.span, "expected a material, found a colour")
                        .label("a colour where a material is needed")
                        .help("write it as a material, `{ colour … }`, or for a colour pattern write `colour checker { a white  b black }`"),
                );
                return None;
            }
        }
        self.material_value(item)
    }

    /// `material m { chequer { … } }`: a misspelt pattern name, reported as
    /// one (the params reader would suggest a material parameter).
    pub(super) fn misspelt_pattern(&mut self, items: &[Item]) -> bool {
        let Some(n) = items.first().and_then(Item::as_name) else {
            return false;
        };
        if !matches!(items.get(1), Some(Item::Block(_)))
            || super::params::MATERIAL
                .get(super::params::canonical(n.node))
                .is_some()
        {
            return false;
        }
        let Some(help) = did_you_mean(n.node, pattern::NAMES.iter().copied()) else {
            return false;
        };
        self.err(
            Error::new(n.span, format!("unknown pattern `{}`", n.node))
                .label("not a pattern")
                .help(help),
        );
        true
    }

    fn both_given(&mut self, first: &Param, map: &Param) {
        self.err(
            Error::new(
                first.name.span,
                format!("`{}` and `{}` both given", first.name.node, map.name.node),
            )
            .label("given here")
            .note(map.name.span, "and a map here")
            .help("`a` and `b` are the two-entry map `{ 0 a  1 b }`: give one or the other"),
        );
    }

    /// The pattern itself and the parameters it leaves (its map).
    fn pattern<'w>(&mut self, w: &Written<'w>, target: Target) -> Option<(Pattern, Params<'w>)> {
        let kind = w.name.node;
        if let (Some((_, s)), true) = (w.string, kind != "image") {
            self.err(
                Error::new(s, format!("`{kind}` takes no file name")).label("unexpected string"),
            );
            return None;
        }
        // No block reads as an empty one: no parameters and nothing to report.
        let mut p = match w.block {
            Some(b) => self.params(kind, b, schema_of(kind)),
            None => Params::default(),
        };
        let map_name = match target {
            Target::Colour => "material_map",
            Target::Material => "colour_map",
        };
        if let Some(q) = p.take(map_name) {
            let (want, e) = match target {
                Target::Colour => ("colour_map", "a colour pattern"),
                Target::Material => ("material_map", "a material pattern"),
            };
            self.err(
                Error::new(q.name.span, format!("`{map_name}` is not used in {e}"))
                    .label("wrong map")
                    .help(format!("did you mean `{want}`?")),
            );
            return None;
        }
        let mut ok = true;
        let mut mirrored = false;
        let (place, scale) = self.placement(&mut p, &mut ok, &mut mirrored);
        let mut pattern = Pattern::new(Kind::Granite(Granite));
        if let Some(q) = p.take("turbulence") {
            match self.checked(&q.values[0], |t| t >= 0.0 && t.is_finite(), "0 or more") {
                Some(t) => pattern.turbulence = t,
                None => ok = false,
            }
        } else if kind == "marble" {
            pattern.turbulence = 4.0;
        } else if kind == "wood" {
            pattern.turbulence = 0.5;
        }
        let number = |b: &mut Self, p: &mut Params, name: &str, ok: &mut bool| {
            let q = p.take(name)?;
            let v = b.positive(&q.values[0]);
            *ok &= v.is_some();
            v
        };
        if let Some((ScaleGiven::Uv(_), s)) = &scale
            && !matches!(kind, "checker" | "image")
        {
            self.err(
                Error::new(
                    *s,
                    format!("`{kind}` is a solid pattern: its scale is `k` or `<kx, ky, kz>`"),
                )
                .label("two components"),
            );
            ok = false;
        }
        let solid_scale = match &scale {
            Some((ScaleGiven::Number(s), _)) => DVec3::splat(*s),
            Some((ScaleGiven::Vector(v), _)) => *v,
            _ => DVec3::ONE,
        };
        pattern.kind = match kind {
            "checker" => {
                let k = match &scale {
                    None => DVec2::ONE,
                    Some((ScaleGiven::Number(s), _)) => DVec2::splat(*s),
                    Some((ScaleGiven::Vector(_), s)) => {
                        self.err(
                            Error::new(*s, "a checker's scale is `k` or `<ku, kv>`")
                                .label("three components")
                                .help("a checker reads (u, v); `checker3d` has cubes in space"),
                        );
                        ok = false;
                        DVec2::ONE
                    }
                    Some((ScaleGiven::Uv(v), _)) => *v,
                };
                Kind::Checker(Checker { scale: k })
            }
            "checker3d" => {
                pattern.scale = solid_scale;
                Kind::Checker3d(Checker3d::new(
                    number(self, &mut p, "size", &mut ok).unwrap_or(1.0),
                ))
            }
            "gradient" => {
                pattern.scale = solid_scale;
                let axis = match p.take("axis") {
                    Some(q) => match self.vec3(&q.values[0]) {
                        Some((v, _)) if v != DVec3::ZERO && v.is_finite() => v,
                        Some((_, s)) => {
                            self.err(
                                Error::new(s, "a gradient's axis may not be zero").label("zero"),
                            );
                            ok = false;
                            DVec3::Y
                        }
                        None => {
                            ok = false;
                            DVec3::Y
                        }
                    },
                    None => DVec3::Y,
                };
                Kind::Gradient(Gradient {
                    axis,
                    mirror: mirrored,
                })
            }
            "noise" => {
                pattern.scale = solid_scale;
                let octaves = match p.take("octaves") {
                    Some(q) => self.integer(&q.values[0], 1, 10).unwrap_or_else(|| {
                        ok = false;
                        1
                    }),
                    None => 1,
                };
                Kind::Noise(Noise { octaves })
            }
            "sectors" | "quadrants" => {
                pattern.scale = solid_scale;
                let count = match p.take("count") {
                    Some(q) => self.integer(&q.values[0], 2, 360).unwrap_or_else(|| {
                        ok = false;
                        6
                    }),
                    None if kind == "quadrants" => 4,
                    None => 6,
                };
                let uv = p.take("uv").is_some();
                if uv && pattern.turbulence != 0.0 {
                    self.err(
                        Error::new(w.name.span, "turbulence works on solid patterns only")
                            .label("read on (u, v) here")
                            .help("remove `uv` or `turbulence`"),
                    );
                    ok = false;
                }
                let alternate = p.take("alternate").is_some();
                Kind::Sectors(Sectors {
                    count,
                    uv,
                    alternate,
                })
            }
            "image" => {
                let image = self.image_for_pattern(w, scale.map(|(g, _)| g), &mut p)?;
                Kind::Image(ImagePattern { image })
            }
            "marble" => {
                pattern.scale = solid_scale;
                Kind::Marble(Marble)
            }
            "wood" => {
                pattern.scale = solid_scale;
                Kind::Wood(Wood)
            }
            _ => {
                pattern.scale = solid_scale;
                Kind::Granite(Granite)
            }
        };
        pattern.place = place;
        ok.then_some((pattern, p))
    }

    /// `translate` and `rotate` in the order written, and `scale`.
    fn placement(
        &mut self,
        p: &mut Params,
        ok: &mut bool,
        mirrored: &mut bool,
    ) -> (
        Option<crate::geometry::Transform>,
        Option<(ScaleGiven, Span)>,
    ) {
        let mut moves = p.take_transforms();
        // `mirror` is a transform's name too; in a gradient it is a flag.
        if let Some(k) = moves.iter().position(|q| q.name.node == "mirror") {
            *mirrored = true;
            moves.remove(k);
        }
        let scale = moves
            .iter()
            .position(|q| q.name.node == "scale")
            .map(|k| moves.remove(k));
        let scale = scale.and_then(|q| {
            let given = self.scale_given(&q.values[0]);
            *ok &= given.is_some();
            given
        });
        let place = (!moves.is_empty()).then(|| self.transform(moves));
        (place, scale)
    }

    fn scale_given(&mut self, item: &Item) -> Option<(ScaleGiven, Span)> {
        use crate::eval::expr::Value;
        let (v, s) = self.value(item, "a number or a vector")?;
        let given = match v {
            Value::Number(n) => ScaleGiven::Number(n),
            Value::Vector(v) if v.len() == 2 => ScaleGiven::Uv(DVec2::new(v[0], v[1])),
            Value::Vector(v) if v.len() == 3 => ScaleGiven::Vector(DVec3::new(v[0], v[1], v[2])),
            other => {
                self.wrong_kind(s, "a number or a vector", &other, None);
                return None;
            }
        };
        let fine = match given {
            ScaleGiven::Number(n) => n > 0.0 && n.is_finite(),
            ScaleGiven::Uv(v) => v.cmpgt(DVec2::ZERO).all() && v.is_finite(),
            ScaleGiven::Vector(v) => v.cmpgt(DVec3::ZERO).all() && v.is_finite(),
        };
        if !fine {
            self.err(
                Error::new(s, "a pattern's scale must be greater than 0")
                    .label("0, negative or not finite")
                    .help("`scale` counts repeats per unit: larger is finer"),
            );
            return None;
        }
        Some((given, s))
    }

    /// A colour in a colour pattern; a material there is a kind error.
    fn pattern_colour(&mut self, item: &Item) -> Option<Colour> {
        if let Some(n) = item.as_name()
            && !item.is_bound_name()
            && (self.materials.contains_key(n.node) || self.all_materials.contains_key(n.node))
        {
            self.err(
                Error::new(
                    n.span,
                    format!("expected a colour, found the material `{}`", n.node),
                )
                .label("a material where a colour is needed")
                .help(
                    "a pattern of whole materials is written `material { checker { a m1  b m2 } }`",
                ),
            );
            return None;
        }
        self.colour(item).map(|c| c.0)
    }

    /// Pairs of a key and a value, checked to be sorted within [0, 1].
    fn map_entries<'i>(&mut self, q: &'i Param) -> Option<Vec<(f64, Span, &'i Item)>> {
        let Item::Block(block) = &*q.values[0] else {
            self.err(
                Error::new(
                    q.values[0].span(),
                    format!(
                        "`{}` takes a block, found {}",
                        q.name.node,
                        q.values[0].describe()
                    ),
                )
                .label("not a block")
                .help("e.g. `colour_map { 0 black  0.5 red  1 white }`"),
            );
            return None;
        };
        if block.items.len() % 2 == 1 {
            let last = &block.items[block.items.len() - 1];
            self.err(
                Error::new(
                    last.span(),
                    format!("`{}` ends with a key alone", q.name.node),
                )
                .label("no value after this")
                .help("entries are pairs: a key from 0 to 1, then its value"),
            );
            return None;
        }
        let mut out = Vec::new();
        let mut ok = true;
        for pair in block.items.chunks(2) {
            match self.number(&pair[0]) {
                Some((k, s)) => out.push((k, s, &pair[1])),
                None => ok = false,
            }
        }
        if !ok {
            return None;
        }
        let keys: Vec<(f64, Colour)> = out.iter().map(|(k, _, _)| (*k, Colour::ZERO)).collect();
        match ColourMap::new(keys) {
            Ok(_) => Some(out),
            Err(e) => {
                let err = match e {
                    MapError::Empty => {
                        Error::new(block.span, format!("`{}` is empty", q.name.node))
                            .label("no entries")
                            .help("e.g. `{ 0 black  1 white }`")
                    }
                    MapError::OutOfRange(i) => Error::new(out[i].1, "a map's keys are from 0 to 1")
                        .label(format!("this is {}", out[i].0)),
                    MapError::Unsorted(i) => Error::new(out[i].1, "a map's keys must go up")
                        .label(format!("{} comes after {}", out[i].0, out[i - 1].0))
                        .note(out[i - 1].1, "the key before")
                        .help("write the entries in order of their keys"),
                };
                self.err(err);
                None
            }
        }
    }

    fn colour_map(&mut self, q: &Param) -> Option<ColourMap> {
        let entries = self.map_entries(q)?;
        let mut keys = Vec::new();
        for (k, _, item) in entries {
            keys.push((k, self.pattern_colour(item)?));
        }
        ColourMap::new(keys).ok()
    }

    fn material_map(&mut self, q: &Param) -> Option<Vec<(f64, MaterialId)>> {
        let entries = self.map_entries(q)?;
        let mut bands = Vec::new();
        let mut ok = true;
        for (k, _, item) in entries {
            match self.chosen_material(item) {
                Some(m) => bands.push((k, m)),
                None => ok = false,
            }
        }
        ok.then_some(bands)
    }

    /// `normal bumps { … }` (the values the params reader collected).
    pub(super) fn normal_pattern(
        &mut self,
        values: &[super::params::ItemRef],
    ) -> Option<NormalPattern> {
        let Some(name) = values.first().and_then(|v| v.as_name()) else {
            let first = &values[0];
            self.err(
                Error::new(
                    first.span(),
                    format!("expected a normal pattern, found {}", first.describe()),
                )
                .label("not a normal pattern")
                .help("`normal bumps { amount 0.3  scale 10 }`, `ripples` or `waves`"),
            );
            return None;
        };
        if !NORMALS.contains(&name.node) {
            self.err(
                Error::new(name.span, format!("unknown normal pattern `{}`", name.node))
                    .label("not a normal pattern")
                    .help(
                        did_you_mean(name.node, NORMALS.iter().copied()).unwrap_or_else(|| {
                            "normal patterns are bumps, ripples and waves".into()
                        }),
                    ),
            );
            return None;
        }
        if let Some(s @ Item::Str { .. }) = values.get(1).map(|v| &**v) {
            self.err(
                Error::new(s.span(), format!("`{}` takes no file name", name.node))
                    .label("unexpected string"),
            );
            return None;
        }
        let empty = Block {
            items: Vec::new(),
            span: name.span,
        };
        let block = values.iter().find_map(|v| match &**v {
            Item::Block(b) => Some(b),
            _ => None,
        });
        let mut p = self.params(name.node, block.unwrap_or(&empty), &NORMAL);
        let mut ok = true;
        let amount = match p.take("amount") {
            Some(q) => self
                .checked(&q.values[0], |a| a >= 0.0 && a.is_finite(), "0 or more")
                .unwrap_or_else(|| {
                    ok = false;
                    0.0
                }),
            None => 0.5,
        };
        let (place, scale) = self.placement(&mut p, &mut ok, &mut false);
        let scale = match scale {
            None => 1.0,
            Some((ScaleGiven::Number(s), _)) => s,
            Some((_, s)) => {
                self.err(
                    Error::new(s, "a normal pattern's scale is one number")
                        .label("a vector")
                        .help("`scale 10`: ten bumps or ripples per unit"),
                );
                ok = false;
                1.0
            }
        };
        let centre = match p.take("centre") {
            Some(q) if name.node == "bumps" => {
                self.err(
                    Error::new(q.name.span, "`bumps` have no centre")
                        .label("only ripples and waves have one"),
                );
                ok = false;
                DVec3::ZERO
            }
            Some(q) => self.vec3(&q.values[0]).map(|v| v.0).unwrap_or_else(|| {
                ok = false;
                DVec3::ZERO
            }),
            None => DVec3::ZERO,
        };
        let kind = match name.node {
            "bumps" => NormalKind::Bumps,
            "ripples" => NormalKind::Ripples { centre },
            _ => NormalKind::Waves { centre },
        };
        self.finish(name.node, p);
        ok.then_some(NormalPattern {
            kind,
            amount,
            scale,
            place,
        })
    }
}

/// `scale` as written: one number, `<ku, kv>` or `<kx, ky, kz>`.
#[derive(Clone, Copy)]
pub(super) enum ScaleGiven {
    Number(f64),
    Uv(DVec2),
    Vector(DVec3),
}
