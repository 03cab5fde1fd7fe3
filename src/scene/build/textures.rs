//! The value of a material's `colour`: a plain colour, an image's
//! colours, or a pattern through a colour map (built in `patterns.rs`).
//!
//! ```text
//! colour rgb(1, 0.8, 0.2)
//! colour checker   { a white  b black  scale 4 }
//! colour checker3d { a white  b black  size 0.5 }
//! colour image "earth.png" { scale <1, 1>  offset <0, 0>  swap  flip_u  flip_v }
//! colour marble    { a white  b rgb(0.1, 0.1, 0.3)  scale 2  turbulence 4 }
//! colour wood      { a #c8a060  b #704018  scale 6  turbulence 0.5 }
//! ```

use super::params::{Params, Schema, spec};
use super::patterns::{ScaleGiven, Written};
use super::{Builder, Texture};
use crate::geometry::DVec2;
use crate::lang::ast::{Block, Item, Span};
use crate::lang::diagnostics::{Error, did_you_mean};
use crate::scene::pattern;
use crate::scene::texture::{ImageTexture, UvMapping};
use std::sync::Arc;

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
    pub(super) fn texture(&mut self, values: &[super::params::ItemRef]) -> Option<Texture> {
        let name = match values {
            [single] => match single.as_name() {
                Some(n) if pattern::NAMES.contains(&n.node) && !single.is_bound_name() => n,
                _ => return self.colour(single).map(|(c, _)| Texture::Solid(c)),
            },
            [first, ..] => match first.as_name() {
                Some(n) if pattern::NAMES.contains(&n.node) => n,
                Some(n) => {
                    let e = Error::new(n.span, format!("unknown texture `{}`", n.node))
                        .label("not a texture")
                        .maybe_help(did_you_mean(n.node, pattern::NAMES.iter().copied()));
                    self.err(e);
                    return None;
                }
                None => return None,
            },
            [] => return None,
        };
        let string = values.iter().find_map(|v| match &**v {
            Item::Str { text, content, .. } => Some((text.as_str(), *content)),
            _ => None,
        });
        let block = values.iter().find_map(|v| match &**v {
            Item::Block(b) => Some(b),
            _ => None,
        });
        // An image without a map is its own colours.
        let mapped = block.is_some_and(|b| {
            b.items.iter().any(|i| {
                i.as_name()
                    .is_some_and(|n| matches!(n.node, "a" | "b" | "colour_map" | "material_map"))
            })
        });
        if name.node == "image" && !mapped {
            let Some((file, file_span)) = string else {
                self.err(
                    Error::new(name.span, "`image` needs a file name")
                        .label("expected a string after `image`")
                        .help("e.g. `colour image \"earth.png\" { scale <2, 1> }`"),
                );
                return None;
            };
            return self.image_texture(file, file_span, block);
        }
        self.colour_pattern(&Written {
            name,
            string,
            block,
        })
    }

    /// The picture of `image "file" { … }` as a pattern (with a map): the
    /// file name checked, its (u, v) mapping read from `p`.
    pub(super) fn image_for_pattern(
        &mut self,
        w: &Written,
        scale: Option<ScaleGiven>,
        p: &mut Params,
    ) -> Option<Arc<ImageTexture>> {
        let Some((file, file_span)) = w.string else {
            self.err(
                Error::new(w.name.span, "`image` needs a file name")
                    .label("expected a string after `image`")
                    .help("e.g. `image \"mask.png\" { a black  b white }`"),
            );
            return None;
        };
        let mut mapping = UvMapping::default();
        let mut ok = true;
        match scale {
            Some(ScaleGiven::Number(n)) => mapping.scale = DVec2::splat(n),
            Some(ScaleGiven::Uv(v)) => mapping.scale = v,
            Some(ScaleGiven::Vector(_)) => ok = false,
            None => {}
        }
        self.uv_mapping_flags(p, &mut mapping, &mut ok);
        let img = self.load_image(file, file_span, mapping)?;
        ok.then_some(img)
    }

    /// `offset`, `swap`, `flip_u`, `flip_v`.
    fn uv_mapping_flags(&mut self, p: &mut Params, mapping: &mut UvMapping, ok: &mut bool) {
        if let Some(q) = p.take("offset") {
            match self.vec2(&q.values[0]) {
                Some(v) => mapping.offset = v,
                None => *ok = false,
            }
        }
        mapping.swap = p.take("swap").is_some();
        mapping.flip_u = p.take("flip_u").is_some();
        mapping.flip_v = p.take("flip_v").is_some();
    }

    fn load_image(
        &mut self,
        file: &str,
        file_span: Span,
        mapping: UvMapping,
    ) -> Option<Arc<ImageTexture>> {
        let path = self.program.sources.dir_of(file_span.file).join(file);
        match ImageTexture::load(&path, self.env.transfer, mapping) {
            Ok(img) => Some(Arc::new(img)),
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
            self.uv_mapping_flags(&mut p, &mut mapping, &mut ok);
            self.finish("image", p);
        }
        let img = self.load_image(file, file_span, mapping)?;
        ok.then_some(Texture::Image(img))
    }

    /// `<u, v>`, or one number for both.
    pub(super) fn vec2(&mut self, item: &Item) -> Option<DVec2> {
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
