//! Reading a block's items against a schema: parameter name → how many
//! values, and what they should be. Unknown names get a suggestion from the
//! names valid *in that block*; a parameter that runs into the next
//! parameter or the end of the block is "missing its value"; a parameter
//! given twice is an error (transforms may repeat: they compose).

use super::objects;
use crate::eval::expr::Env;
use crate::lang::ast::{Block, Item, Span, Spanned};
use crate::lang::diagnostics::{Error, did_you_mean};
use std::borrow::Cow;

/// One parameter a block accepts.
#[derive(Debug)]
pub struct Spec {
    pub name: &'static str,
    pub arity: usize,
    /// What its values should be, for messages ("a number").
    pub expects: &'static str,
    /// A value that may be a pattern: a name followed by an optional string
    /// and a block (`checker { … }`, `image "f.png" { … }`).
    pub pattern: bool,
}

pub const fn spec(name: &'static str, arity: usize, expects: &'static str) -> Spec {
    Spec {
        name,
        arity,
        expects,
        pattern: false,
    }
}

const fn pattern_spec(name: &'static str, expects: &'static str) -> Spec {
    Spec {
        name,
        arity: 1,
        expects,
        pattern: true,
    }
}

/// What a block accepts.
#[derive(Debug)]
pub struct Schema {
    pub own: &'static [Spec],
    /// Objects accept `material` and the transforms.
    pub object: bool,
    /// `group` and the CSG operations hold objects.
    pub children: bool,
}

/// The transforms, written once: the list [`TRANSFORMS`] and the `match`
/// of [`is_transform`] are made from it.
macro_rules! transforms {
    ($(spec($name:literal, $arity:literal, $expects:literal $(,)?)),+ $(,)?) => {
        pub const TRANSFORMS: &[Spec] = &[$(spec($name, $arity, $expects)),+];

        /// Whether `name` is one of [`TRANSFORMS`] (a `match`: asked of
        /// every parameter of every object).
        pub fn is_transform(name: &str) -> bool {
            matches!(name, $($name)|+)
        }
    };
}

transforms![
    spec("translate", 1, "a 3-vector"),
    spec(
        "rotate",
        2,
        "an axis (`x`, `y`, `z` or a vector) and an angle in degrees",
    ),
    spec("scale", 1, "a number or a 3-vector"),
    spec(
        "shear",
        2,
        "a pair of axes (`xy`, `xz`, `yx`, `yz`, `zx` or `zy`) and a number",
    ),
    spec("mirror", 1, "an axis (`x`, `y` or `z`)"),
    spec("matrix", 1, "a list of 12 numbers"),
];

const MATERIAL_PARAM: Spec = spec(
    "material",
    1,
    "a material name or a block `{ colour …  reflect … }`",
);

impl Schema {
    pub fn get(&self, name: &str) -> Option<&'static Spec> {
        let same = |s: &&Spec| crate::lang::ast::same_name(s.name, name);
        self.own.iter().find(same).or_else(|| {
            if !self.object {
                return None;
            }
            if name == "material" {
                return Some(&MATERIAL_PARAM);
            }
            TRANSFORMS.iter().find(same)
        })
    }

    pub fn names(&self) -> Vec<&'static str> {
        let mut v: Vec<&'static str> = self.own.iter().map(|s| s.name).collect();
        if self.object {
            v.push("material");
            v.extend(TRANSFORMS.iter().map(|s| s.name));
        }
        if self.children {
            v.extend(objects::OBJECTS.iter().copied());
        }
        v
    }
}

/// `color` and `center` are accepted for `colour` and `centre`, and the
/// sketch's `texture` for `colour`.
pub fn canonical(name: &str) -> &str {
    match name {
        "color" | "texture" => "colour",
        "specular_color" => "specular_colour",
        "mirror_color" => "mirror_colour",
        "center" => "centre",
        n => n,
    }
}

pub const CAMERA: Schema = Schema {
    own: &[
        spec("position", 1, "a 3-vector"),
        spec("look_at", 1, "a 3-vector"),
        spec("up", 1, "a 3-vector"),
        spec("fov", 1, "an angle in degrees"),
        spec("distance", 1, "a number"),
        spec("width", 1, "a number"),
        spec("height", 1, "a number"),
        spec("aperture", 1, "the lens radius (0 for a pinhole)"),
        spec("focus", 1, "the distance that is sharp"),
    ],
    object: false,
    children: false,
};

pub const RENDER: Schema = Schema {
    own: &[
        spec("width", 1, "a number of pixels"),
        spec("height", 1, "a number of pixels"),
        spec("max_depth", 1, "a whole number"),
        spec(
            "bailout",
            1,
            "the smallest share of the pixel a ray is traced for, 0 to below 1",
        ),
        spec("background", 1, "a colour"),
        spec(
            "samples",
            1,
            "a whole number of samples per pixel side, or `<columns, rows>`",
        ),
        spec("gamma", 1, "`srgb`, `linear` or a number"),
        spec(
            "sampler",
            1,
            "`regular`, `random`, `jittered` or `multijittered`",
        ),
        spec("seed", 1, "a whole number"),
        spec("accel", 1, "`bvh` or `kdtree`"),
        spec("adaptive", 1, "a block `{ threshold …  max_samples … }`"),
        spec("motion_blur", 1, "a whole number of sub-frames, 1 to 64"),
        spec(
            "shutter",
            1,
            "the time the shutter is open, in frames (0 to 1)",
        ),
    ],
    object: false,
    children: false,
};

pub const ADAPTIVE: Schema = Schema {
    own: &[
        spec("threshold", 1, "a number greater than 0"),
        spec("max_samples", 1, "a whole number of samples per pixel side"),
    ],
    object: false,
    children: false,
};

pub const LIGHT: Schema = Schema {
    own: &[
        spec("position", 1, "a 3-vector"),
        spec("colour", 1, "a colour"),
        spec("intensity", 1, "a number"),
        spec(
            "direction",
            1,
            "a 3-vector (the way a parallel light shines)",
        ),
        spec("look_at", 1, "a 3-vector (where a spot light points)"),
        spec("angle", 1, "the spot's full-light half-angle in degrees"),
        spec("falloff", 1, "the spot's outer half-angle in degrees"),
    ],
    object: false,
    children: false,
};

pub const MATERIAL: Schema = Schema {
    own: &[
        pattern_spec(
            "colour",
            "a colour or a pattern (`checker`, `checker3d`, `gradient`, `noise`, `granite`, `marble`, `wood`, `sectors`, `quadrants`, `image`)",
        ),
        pattern_spec(
            "normal",
            "a normal pattern (`bumps`, `ripples`, `waves`) and its block",
        ),
        spec("reflect", 1, "a number from 0 to 1"),
        spec("diffuse", 1, "a number, 0 or more"),
        spec("ambient", 1, "a number, 0 or more"),
        spec("specular", 1, "a number, 0 or more"),
        spec("shininess", 1, "a Phong exponent, greater than 0"),
        spec("specular_colour", 1, "a colour"),
        spec("mirror", 1, "a number, 0 or more"),
        spec("mirror_colour", 1, "a colour"),
        spec("glossy", 1, "a lobe exponent, greater than 0"),
        spec(
            "refract",
            1,
            "a block `{ ior …  filter …  outside_ior …  outside_filter … }`",
        ),
        spec("emit", 1, "a colour"),
        spec("intensity", 1, "a number, 0 or more (scales `emit`)"),
    ],
    object: false,
    children: false,
};

pub const REFRACT: Schema = Schema {
    own: &[
        spec("ior", 1, "an index of refraction, greater than 0"),
        spec("filter", 1, "a colour (transmittance per unit length)"),
        spec("outside_ior", 1, "an index of refraction, greater than 0"),
        spec("outside_filter", 1, "a colour"),
    ],
    object: false,
    children: false,
};

pub const ENVIRONMENT: Schema = Schema {
    own: &[
        spec("colour", 1, "a colour"),
        spec("intensity", 1, "a number, 0 or more"),
        spec(
            "samples",
            1,
            "a whole number of directions per shading point",
        ),
        spec(
            "image",
            1,
            "a file name (an HDR or EXR sky, latitude-longitude)",
        ),
    ],
    object: false,
    children: false,
};

pub const OCCLUSION: Schema = Schema {
    own: &[
        spec(
            "samples",
            1,
            "a whole number of directions per shading point",
        ),
        spec("min", 1, "a number from 0 to 1"),
        spec("distance", 1, "a distance, greater than 0"),
    ],
    object: false,
    children: false,
};

/// A parameter as written: its (canonical) name and its values, borrowed
/// from the block that was read (a value is owned only where reading made
/// it: the `-2` of `offset -2`).
#[derive(Clone, Debug)]
pub struct Param<'a> {
    /// The schema's own name (static: no String per parameter read).
    pub name: Spanned<&'static str>,
    /// Inline: a parameter takes one or two values (`radius 2`,
    /// `rotate x 90`), and a loop-built scene reads a few per object.
    pub values: smallvec::SmallVec<[ItemRef<'a>; 2]>,
}

/// A parameter's value: an item of the block, or one made while reading
/// (the `-2` split off `offset -2`). As a `Cow`, but 16 bytes rather than
/// an item's 128: parameters are moved about as they are taken.
#[derive(Clone, Debug)]
pub enum ItemRef<'a> {
    Borrowed(&'a Item),
    Owned(Box<Item>),
}

impl std::ops::Deref for ItemRef<'_> {
    type Target = Item;
    fn deref(&self) -> &Item {
        match self {
            ItemRef::Borrowed(i) => i,
            ItemRef::Owned(i) => i,
        }
    }
}

/// An object inside a `group` or CSG block.
#[derive(Clone, Debug)]
pub struct Child<'a> {
    pub kw: Spanned<String>,
    pub string: Option<&'a Item>,
    pub block: &'a Block,
    /// The loop iteration or call that made it.
    pub trace: Option<crate::eval::TraceRef>,
    /// A placement of an object value: `kw` is its name, `block` the
    /// placement's transforms and material.
    pub instance: Option<std::sync::Arc<crate::eval::expr::Fragment>>,
}

/// The object value an item places (`wheel` in `wheel { … }`), if it is one.
pub fn instance_of(item: &Item) -> Option<&std::sync::Arc<crate::eval::expr::Fragment>> {
    match item {
        Item::Value(crate::lang::ast::Expr {
            kind: crate::lang::ast::ExprKind::Bound(_, Some(crate::eval::expr::Value::Items(f))),
            ..
        }) if objects::is_object(f.head()) => Some(f),
        _ => None,
    }
}

type Trace = Option<crate::eval::TraceRef>;

/// A block's items with the evaluator's [`Item::Traced`] wrappers opened,
/// each item with the trace of the wrapper it was in.
fn flatten<'a>(items: &'a [Item], trace: &Trace, out: &mut Vec<(&'a Item, Trace)>) {
    for it in items {
        match it {
            Item::Traced { trace, items } => flatten(items, &Some(trace.clone()), out),
            other => out.push((other, trace.clone())),
        }
    }
}

/// A block's items as read: the block's own list, or (when the evaluator
/// wrapped some) the opened one.
enum Seq<'a> {
    Plain(&'a [Item]),
    Opened(Vec<(&'a Item, Trace)>),
}

impl<'a> Seq<'a> {
    fn len(&self) -> usize {
        match self {
            Seq::Plain(s) => s.len(),
            Seq::Opened(v) => v.len(),
        }
    }

    fn get(&self, k: usize) -> Option<&'a Item> {
        match self {
            Seq::Plain(s) => s.get(k),
            Seq::Opened(v) => v.get(k).map(|(i, _)| *i),
        }
    }

    fn trace(&self, k: usize) -> Trace {
        match self {
            Seq::Plain(_) => None,
            Seq::Opened(v) => v.get(k).and_then(|(_, t)| t.clone()),
        }
    }
}

/// The parameters of one block, in the order written.
#[derive(Debug, Default)]
pub struct Params<'a> {
    list: Vec<Param<'a>>,
    pub children: Vec<Child<'a>>,
    /// Whether an unknown parameter was reported: then "needs `x`" errors
    /// are held back, as the unknown one is likely `x` misspelt.
    pub had_unknown: bool,
}

impl<'a> Params<'a> {
    /// Takes the parameter (at most one remains of each non-repeating name).
    pub fn take(&mut self, name: &str) -> Option<Param<'a>> {
        let k = self
            .list
            .iter()
            .position(|p| crate::lang::ast::same_name(p.name.node, name))?;
        Some(self.list.remove(k))
    }

    /// Takes every transform, in the order written.
    pub fn take_transforms(&mut self) -> Vec<Param<'a>> {
        // Most objects have none: then nothing is split into new lists.
        if !self.list.iter().any(|p| is_transform(p.name.node)) {
            return Vec::new();
        }
        let (t, rest) = std::mem::take(&mut self.list)
            .into_iter()
            .partition(|p| is_transform(p.name.node));
        self.list = rest;
        t
    }

    /// What no handler took.
    pub fn rest(self) -> Vec<Param<'a>> {
        self.list
    }
}

/// Reads `block` for `owner` (the statement's name, for messages).
pub fn read<'a>(
    owner: &str,
    block: &'a Block,
    schema: &Schema,
    env: &Env,
    errors: &mut Vec<Error>,
) -> Params<'a> {
    let items = if block.items.iter().any(|i| matches!(i, Item::Traced { .. })) {
        let mut flat = Vec::new();
        flatten(&block.items, &None, &mut flat);
        Seq::Opened(flat)
    } else {
        Seq::Plain(&block.items)
    };
    let trace_at = |k: usize| items.trace(k);
    let end = Span::new(
        block.span.file,
        block.span.end.saturating_sub(1),
        block.span.end,
    );
    // At most one parameter for every two items (a name and its value):
    // room for all of them at once rather than growing from empty.
    let mut out = Params {
        list: Vec::with_capacity(items.len().div_ceil(2)),
        ..Params::default()
    };
    // Whether an item starts the next parameter (so it is not a value).
    let starts_param = |it: &Item| -> bool {
        if matches!(it, Item::Let { .. }) {
            return true;
        }
        it.as_name().is_some_and(|n| {
            let c = canonical(n.node);
            (schema.get(c).is_some() || (schema.children && objects::is_object(c)))
                && !it.is_bound_name()
        })
    };
    let mut i = 0;
    while i < items.len() {
        let Some(item) = items.get(i) else { break };
        i += 1;
        if let Item::Let { span, .. } = item {
            errors.push(
                Error::new(*span, "`let` is only allowed at the top level")
                    .label("inside a block")
                    .help("move the `let` above the statement"),
            );
            continue;
        }
        // The name as written, borrowed from the item when it is a bare
        // name (the common case): one String per parameter, not two.
        let (name, pending): (Spanned<Cow<str>>, _) = if let Some(n) = item.as_name() {
            (Spanned::new(Cow::Borrowed(n.node), n.span), None)
        } else if let Item::Value(e) = item
            && let Some((n, rest)) = e.split_leading_name()
            && schema.get(canonical(&n.node)).is_some()
        {
            (
                Spanned::new(Cow::Owned(n.node), n.span),
                Some(Item::Value(rest)),
            )
        } else {
            let mut e = Error::new(
                item.span(),
                format!(
                    "expected a parameter of `{owner}`, found {}",
                    item.describe()
                ),
            )
            .label(format!("unexpected {}", item.describe()));
            e = match out.list.last() {
                Some(prev)
                    if prev
                        .values
                        .last()
                        .is_some_and(|v| v.span().end <= item.span().start) =>
                {
                    let spec = schema.get(prev.name.node);
                    e.help(format!(
                        "`{}` takes {}; this is one value too many",
                        prev.name.node,
                        spec.map_or("its values", |s| s.expects)
                    ))
                }
                _ => e.help(format!("`{owner}` takes: {}", schema.names().join(", "))),
            };
            errors.push(e);
            continue;
        };
        if schema.children
            && let Some(f) = instance_of(item)
            && let Some(Item::Block(b)) = items.get(i)
        {
            i += 1;
            out.children.push(Child {
                kw: Spanned::new(name.node.to_string(), name.span),
                string: None,
                block: b,
                trace: trace_at(i - 2),
                instance: Some(f.clone()),
            });
            continue;
        }
        let canon = canonical(&name.node);
        if schema.children && objects::is_object(canon) {
            let string = if objects::takes_string(canon) {
                match items.get(i) {
                    Some(s @ Item::Str { .. }) => {
                        i += 1;
                        Some(s)
                    }
                    _ => None,
                }
            } else {
                None
            };
            match items.get(i) {
                Some(Item::Block(b)) => {
                    i += 1;
                    out.children.push(Child {
                        kw: Spanned::new(canon.to_string(), name.span),
                        string,
                        block: b,
                        trace: trace_at(i - 1),
                        instance: None,
                    });
                }
                _ => errors.push(
                    Error::new(name.span, format!("`{canon}` needs a block `{{ … }}`"))
                        .label(format!("expected `{{` after `{canon}`")),
                ),
            }
            continue;
        }
        let Some(spec) = schema.get(canon) else {
            let mut e = Error::new(
                name.span,
                format!("unknown parameter `{}` in `{owner}`", name.node),
            )
            .label("not a parameter here");
            e = match did_you_mean(&name.node, schema.names()) {
                Some(h) => e.help(h),
                None if schema.object && matches!(canon, "colour" | "reflect") => e.help(format!(
                    "`{}` belongs in a material: `material {{ {} … }}`",
                    name.node, name.node
                )),
                None => e.help(format!("`{owner}` takes: {}", schema.names().join(", "))),
            };
            errors.push(e);
            out.had_unknown = true;
            // Skip its values, up to the next known parameter.
            while i < items.len() && !items.get(i).is_some_and(starts_param) {
                i += 1;
            }
            continue;
        };
        let mut values: smallvec::SmallVec<[ItemRef; 2]> = smallvec::SmallVec::new();
        if let Some(p) = pending {
            values.push(ItemRef::Owned(Box::new(p)));
        }
        // A declared material's name is `material`'s value even when it
        // is also a keyword (`material mirror`).
        let material_name = |it: &Item| {
            spec.name == "material"
                && it
                    .as_name()
                    .is_some_and(|n| env.material_names.contains(n.node))
        };
        // `front material { … }`: a face or cap takes its material directly.
        // Read as written, `front` would be empty and the block the object's
        // own material, then a cascade; it is one mistake, so one error,
        // and the material after the word is still read.
        if values.is_empty()
            && spec.expects == "a material"
            && spec.name != "material"
            && let Some(word) = items.get(i).and_then(Item::as_name)
            && word.node == "material"
            && items
                .get(i + 1)
                .is_some_and(|n| matches!(n, Item::Block(_)) || n.as_name().is_some())
        {
            errors.push(
                Error::new(
                    word.span,
                    format!(
                        "`{}` takes a material without the word `material`",
                        name.node
                    ),
                )
                .label("remove this word")
                .help(format!(
                    "write `{0} {{ colour … }}` or `{0} NAME`",
                    name.node
                )),
            );
            i += 1;
            if let Some(v) = items.get(i) {
                values.push(ItemRef::Borrowed(v));
            }
            i += 1;
        }
        while values.len() < spec.arity
            && i < items.len()
            && (!items.get(i).is_some_and(starts_param)
                || (values.is_empty() && items.get(i).is_some_and(material_name)))
        {
            if let Some(v) = items.get(i) {
                values.push(ItemRef::Borrowed(v));
            }
            i += 1;
        }
        if spec.pattern && values.len() == 1 && values[0].as_name().is_some() {
            if let Some(s @ Item::Str { .. }) = items.get(i) {
                values.push(ItemRef::Borrowed(s));
                i += 1;
            }
            if let Some(b @ Item::Block(_)) = items.get(i) {
                values.push(ItemRef::Borrowed(b));
                i += 1;
            }
        }
        if values.len() < spec.arity {
            let found = match items.get(i) {
                Some(next) => (next.span(), format!("{} starts here", next.describe())),
                None => (end, "the block ends here".to_string()),
            };
            let msg = if spec.arity == 1 || values.is_empty() {
                format!("`{}` is missing its value", name.node)
            } else {
                format!(
                    "`{}` needs {} values, found {}",
                    name.node,
                    spec.arity,
                    values.len()
                )
            };
            errors.push(
                Error::new(name.span, msg)
                    .label(format!("expected {} after this", spec.expects))
                    .note(found.0, found.1),
            );
            continue;
        }
        if values.len() > spec.arity && !spec.pattern {
            errors.push(
                Error::new(
                    values[spec.arity].span(),
                    format!("`{}` takes no value", name.node),
                )
                .label("unexpected value"),
            );
            continue;
        }
        if !is_transform(canon)
            && let Some(first) = out.list.iter().find(|p| p.name.node == canon)
        {
            errors.push(
                Error::new(
                    name.span,
                    format!("`{}` is given twice in `{owner}`", name.node),
                )
                .label("given again here")
                .note(first.name.span, "first given here")
                .help("remove one of them"),
            );
            continue;
        }
        out.list.push(Param {
            name: Spanned::new(spec.name, name.span),
            values,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::ast::FileId;
    use crate::lang::parser::parse;

    #[test]
    fn is_transform_says_yes_to_exactly_the_transforms() {
        for t in TRANSFORMS {
            assert!(is_transform(t.name), "{} is a transform", t.name);
        }
        for name in [
            "material",
            "radius",
            "centre",
            "translation",
            "rotat",
            "Scale",
            "",
        ] {
            assert!(!is_transform(name), "{name} is not a transform");
        }
    }
    use crate::scene::Transfer;

    /// The block of `sphere { body }`.
    fn sphere_block(body: &str) -> Block {
        let mut items = parse(&format!("sphere {{ {body} }}"), FileId(0)).unwrap();
        let Item::Block(b) = items.remove(1) else {
            panic!()
        };
        b
    }

    /// Reads a sphere's block with the sphere's schema.
    fn read_sphere(b: &Block) -> (Params<'_>, Vec<Error>) {
        let schema = Schema {
            own: const {
                &[
                    spec("centre", 1, "a 3-vector"),
                    spec("radius", 1, "a number"),
                ]
            },
            object: true,
            children: false,
        };
        let mut errors = Vec::new();
        let p = read("sphere", b, &schema, &Env::new(Transfer::Srgb), &mut errors);
        (p, errors)
    }

    #[test]
    fn parameters_in_any_order_and_transforms_in_order() {
        let b = sphere_block("translate <1,0,0> radius 2 rotate x 90 center <0,1,0>");
        let (mut p, e) = read_sphere(&b);
        assert!(e.is_empty(), "{e:?}");
        assert!(p.take("centre").is_some(), "`center` is read as `centre`");
        assert_eq!(p.take("radius").unwrap().values.len(), 1);
        let t: Vec<&str> = p
            .take_transforms()
            .into_iter()
            .map(|q| q.name.node)
            .collect();
        assert_eq!(t, ["translate", "rotate"]);
        assert!(p.rest().is_empty());
    }

    #[test]
    fn a_minus_after_a_name_is_its_value() {
        let b = sphere_block("radius -2");
        let (mut p, e) = read_sphere(&b);
        assert!(e.is_empty(), "{e:?}");
        let v = p.take("radius").unwrap();
        assert!(
            matches!(&*v.values[0], Item::Value(x) if matches!(x.kind, crate::lang::ast::ExprKind::Neg(_)))
        );
    }

    #[test]
    fn mistakes_are_reported_and_reading_goes_on() {
        let b = sphere_block("radius centre <0,0,0> raduis 1 radius 2 radius 3");
        let (mut p, e) = read_sphere(&b);
        let msgs: Vec<&str> = e.iter().map(|e| e.message.as_str()).collect();
        assert_eq!(
            msgs,
            [
                "`radius` is missing its value",
                "unknown parameter `raduis` in `sphere`",
                "`radius` is given twice in `sphere`",
            ]
        );
        assert_eq!(e[1].help.as_deref(), Some("did you mean `radius`?"));
        assert!(p.take("centre").is_some());
        assert!(p.had_unknown);
    }
}
