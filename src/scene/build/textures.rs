//! The value of a material's `colour`: a plain colour or a pattern.
//!
//! ```text
//! colour rgb(1, 0.8, 0.2)
//! colour checker   { a white  b black  scale 4 }
//! colour checker3d { a white  b black  size 0.5 }
//! colour image "earth.png" { scale <1, 1>  offset <0, 0>  swap  flip_u  flip_v }
//! colour marble    { a white  b rgb(0.1, 0.1, 0.3)  scale 2  turbulence 4 }
//! colour wood      { a #c8a060  b #704018  scale 6  turbulence 0.5 }
//! ```

use super::params::{Schema, spec};
use super::{Builder, Colour, Texture};
use crate::geometry::DVec2;
use crate::lang::ast::{Block, Item, Span};
use crate::lang::diagnostics::{Error, did_you_mean};
use crate::scene::texture::{ImageTexture, UvMapping};
use std::sync::Arc;

const PATTERNS: &[&str] = &["checker", "checker3d", "image", "marble", "wood"];

const CHECKER: Schema = Schema {
    own: &[
        spec("a", 1, "a colour"),
        spec("b", 1, "a colour"),
        spec("scale", 1, "a positive number"),
    ],
    object: false,
    children: false,
};

const CHECKER3D: Schema = Schema {
    own: &[
        spec("a", 1, "a colour"),
        spec("b", 1, "a colour"),
        spec("size", 1, "a positive number"),
    ],
    object: false,
    children: false,
};

const NOISE: Schema = Schema {
    own: &[
        spec("a", 1, "a colour"),
        spec("b", 1, "a colour"),
        spec("scale", 1, "a positive number"),
        spec("turbulence", 1, "a number"),
    ],
    object: false,
    children: false,
};

const IMAGE: Schema = Schema {
    own: &[
        spec("scale", 1, "a 2-vector `<su, sv>` or a number"),
        spec("offset", 1, "a 2-vector `<ou, ov>`"),
        spec("swap", 0, "nothing"),
        spec("flip_u", 0, "nothing"),
        spec("flip_v", 0, "nothing"),
    ],
    object: false,
    children: false,
};

impl Builder<'_> {
    /// `values` as the params reader collected them: one value, or a pattern
    /// name with an optional string and block.
    pub(super) fn texture(&mut self, values: &[Item]) -> Option<Texture> {
        let name = match values {
            [single] => match single.as_name() {
                Some(n) if PATTERNS.contains(&n.node) => n,
                _ => return self.colour(single).map(|(c, _)| Texture::Solid(c)),
            },
            [first, ..] => match first.as_name() {
                Some(n) if PATTERNS.contains(&n.node) => n,
                Some(n) => {
                    let e = Error::new(n.span, format!("unknown texture `{}`", n.node))
                        .label("not a texture")
                        .maybe_help(did_you_mean(n.node, PATTERNS.iter().copied()));
                    self.err(e);
                    return None;
                }
                None => return None,
            },
            [] => return None,
        };
        let kind = name.node;
        let span = name.span;
        let string = values.iter().find_map(|v| match v {
            Item::Str { text, content, .. } => Some((text.as_str(), *content)),
            _ => None,
        });
        let block = values.iter().find_map(|v| match v {
            Item::Block(b) => Some(b),
            _ => None,
        });
        if kind == "image" {
            let Some((file, file_span)) = string else {
                self.err(
                    Error::new(span, "`image` needs a file name")
                        .label("expected a string after `image`")
                        .help("e.g. `colour image \"earth.png\" { scale <2, 1> }`"),
                );
                return None;
            };
            return self.image_texture(file, file_span, block);
        }
        if let Some((_, s)) = string {
            self.err(
                Error::new(s, format!("`{kind}` takes no file name")).label("unexpected string"),
            );
            return None;
        }
        let empty = Block {
            items: Vec::new(),
            span,
        };
        let block = block.unwrap_or(&empty);
        let schema = match kind {
            "checker" => &CHECKER,
            "checker3d" => &CHECKER3D,
            _ => &NOISE,
        };
        let mut p = self.params(kind, block, schema);
        let mut ok = true;
        let mut colour_of = |b: &mut Self, name: &str, default: Colour| -> Colour {
            match p.take(name) {
                Some(q) => b.colour(&q.values[0]).map(|c| c.0).unwrap_or_else(|| {
                    ok = false;
                    default
                }),
                None => default,
            }
        };
        let a = colour_of(self, "a", Colour::ONE);
        let b = colour_of(self, "b", Colour::ZERO);
        let mut number = |b: &mut Self, name: &str, default: f64, positive: bool| -> f64 {
            match p.take(name) {
                Some(q) => {
                    let v = if positive {
                        b.positive(&q.values[0])
                    } else {
                        b.checked(&q.values[0], f64::is_finite, "a finite number")
                    };
                    v.unwrap_or_else(|| {
                        ok = false;
                        default
                    })
                }
                None => default,
            }
        };
        let t = match kind {
            "checker" => Texture::Checker {
                a,
                b,
                scale: number(self, "scale", 1.0, true),
            },
            "checker3d" => Texture::Checker3d {
                a,
                b,
                size: number(self, "size", 1.0, true),
            },
            "marble" => Texture::Marble {
                a,
                b,
                scale: number(self, "scale", 1.0, true),
                turbulence: number(self, "turbulence", 4.0, false),
            },
            _ => Texture::Wood {
                a,
                b,
                scale: number(self, "scale", 1.0, true),
                turbulence: number(self, "turbulence", 0.5, false),
            },
        };
        self.finish(kind, p);
        ok.then_some(t)
    }

    fn image_texture(
        &mut self,
        file: &str,
        file_span: Span,
        block: Option<&Block>,
    ) -> Option<Texture> {
        let mut mapping = UvMapping::default();
        let mut ok = true;
        if let Some(block) = block {
            let mut p = self.params("image", block, &IMAGE);
            if let Some(q) = p.take("scale") {
                match self.vec2(&q.values[0]) {
                    Some(v) if v.x != 0.0 && v.y != 0.0 => mapping.scale = v,
                    Some(_) => {
                        self.err(
                            Error::new(q.values[0].span(), "an image's scale may not be zero")
                                .label("zero"),
                        );
                        ok = false;
                    }
                    None => ok = false,
                }
            }
            if let Some(q) = p.take("offset") {
                match self.vec2(&q.values[0]) {
                    Some(v) => mapping.offset = v,
                    None => ok = false,
                }
            }
            mapping.swap = p.take("swap").is_some();
            mapping.flip_u = p.take("flip_u").is_some();
            mapping.flip_v = p.take("flip_v").is_some();
            self.finish("image", p);
        }
        let path = self.program.sources.dir_of(file_span.file).join(file);
        match ImageTexture::load(&path, self.env.transfer, mapping) {
            Ok(img) => ok.then(|| Texture::Image(Arc::new(img))),
            Err(e) => {
                self.err(
                    Error::new(file_span, format!("cannot use the image `{file}`: {e}"))
                        .label(format!("looked for {}", path.display()))
                        .help("an image path is relative to the scene file that names it"),
                );
                None
            }
        }
    }

    /// `<u, v>`, or one number for both.
    fn vec2(&mut self, item: &Item) -> Option<DVec2> {
        use crate::eval::expr::Value;
        match self.value(item, "a 2-vector `<u, v>`")? {
            (Value::Number(n), _) if n.is_finite() => Some(DVec2::splat(n)),
            (Value::Vector(v), _) if v.len() == 2 && v.iter().all(|c| c.is_finite()) => {
                Some(DVec2::new(v[0], v[1]))
            }
            (other, s) => {
                self.wrong_kind(s, "a 2-vector `<u, v>`", &other, None);
                None
            }
        }
    }
}
