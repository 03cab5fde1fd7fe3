//! `ambient` (with occlusion), `environment` (a colour or an HDR/EXR sky)
//! and `light` (point, parallel, spot); area lights come from emissive
//! objects (see `area.rs`).

use super::*;

impl Builder<'_> {
    pub(super) fn ambient(&mut self, kw: &Spanned<&str>, items: &[Item], i: &mut usize) {
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
            let at = Spanned::new("occlusion", items[*i].span());
            *i += 1;
            if let Some(block) = self.block_after(&at, items, i) {
                self.occlusion(block);
            }
        }
    }

    /// `occlusion { samples n  min m  distance d }` after `ambient`.
    pub(super) fn occlusion(&mut self, block: &Block) {
        let mut p = self.params("occlusion", block, &params::OCCLUSION);
        let mut o = crate::scene::Occlusion {
            samples: 16,
            min: 0.0,
            distance: f64::INFINITY,
        };
        let mut ok = self.take_into(
            &mut p,
            "samples",
            |b, q| b.integer(&q.values[0], 1, 1024),
            |n| o.samples = n,
        );
        ok &= self.take_into(
            &mut p,
            "min",
            |b, q| {
                b.checked(
                    &q.values[0],
                    |x| (0.0..=1.0).contains(&x),
                    "between 0 and 1",
                )
            },
            |m| o.min = m,
        );
        ok &= self.take_into(
            &mut p,
            "distance",
            |b, q| b.positive(&q.values[0]),
            |d| o.distance = d,
        );
        self.finish("occlusion", p);
        if ok {
            self.scene.occlusion = Some(o);
        }
    }

    /// `environment { colour c  intensity k  samples n }`: light from every
    /// direction, and what camera rays that miss see unless a `background`
    /// is set.
    pub(super) fn environment(&mut self, kw: &Spanned<&str>, block: &Block) {
        if !self.once(kw, "environment") {
            return;
        }
        let mut p = self.params("environment", block, &params::ENVIRONMENT);
        let emitted = self.colour_times_intensity(&mut p);
        let samples = match p.take("samples") {
            Some(q) => self.integer(&q.values[0], 1, 1024),
            None => Some(1),
        };
        let image = match p.take("image") {
            None => Some(None),
            Some(q) => match &*q.values[0] {
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
        if let (Some(colour), Some(samples), Some(image)) = (emitted, samples, image) {
            self.scene.environment = Some(crate::scene::Environment {
                colour,
                samples,
                image,
                visible: true,
            });
        }
    }

    /// An environment's sky image: HDR and EXR are linear radiance; 8-bit
    /// images are decoded with the scene's curve.
    pub(super) fn sky_image(
        &mut self,
        file: &str,
        span: Span,
    ) -> Option<Arc<crate::scene::texture::ImageTexture>> {
        let path = self.program.sources.dir_of(span.file).join(file);
        match crate::scene::texture::ImageTexture::load(
            &path,
            self.env.transfer,
            Default::default(),
        ) {
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

    /// `colour` (white) times `intensity` (1, 0 or more), as lights and
    /// the environment give them; `None` when either is wrong (reported).
    fn colour_times_intensity(&mut self, p: &mut Params) -> Option<Colour> {
        let colour = match p.take("colour") {
            Some(q) => self.colour(&q.values[0]).map(|c| c.0),
            None => Some(Colour::ONE),
        };
        let intensity = match p.take("intensity") {
            Some(q) => self.checked(&q.values[0], |x| x >= 0.0, "0 or more"),
            None => Some(1.0),
        };
        Some(colour? * intensity?)
    }

    pub(super) fn light(&mut self, kw: &Spanned<&str>, block: &Block) {
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
        let emitted = self.colour_times_intensity(&mut p);
        let kind = self.light_kind(kw, &mut p, direction, position);
        if let (Some(kind), Some(colour)) = (kind, emitted) {
            self.scene.lights.push(Light {
                position: position.unwrap_or(DVec3::ZERO),
                colour,
                kind,
            });
        }
        self.finish("light", p);
    }

    /// Point (a position), parallel (a direction) or spot (a position, a
    /// `look_at` and angles).
    pub(super) fn light_kind(
        &mut self,
        kw: &Spanned<&str>,
        p: &mut Params,
        direction: Option<Param>,
        position: Option<DVec3>,
    ) -> Option<crate::scene::LightKind> {
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
            return Some(crate::scene::LightKind::Parallel { direction: dir });
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
            return Some(crate::scene::LightKind::Point);
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
        Some(crate::scene::LightKind::Spot {
            axis,
            cos_angle: angle_deg.to_radians().cos(),
            cos_falloff: falloff_deg.to_radians().cos(),
        })
    }
}
