//! `camera` (with its thin lens) and `render` (size, depth, background,
//! samples, sampler, adaptive sampling, gamma): the once-per-scene blocks.

use super::*;

impl Builder<'_> {
    /// `samples N` (an N × N grid) or `samples <columns, rows>`; the rows
    /// are `None` where they equal the columns.
    fn sample_grid(&mut self, item: &Item) -> Option<(u32, Option<u32>)> {
        const MAX: u32 = crate::scene::MAX_SAMPLES;
        let what = format!("a whole number from 1 to {MAX}, or `<columns, rows>` of them");
        match self.value(item, &what)? {
            (Value::Number(x), s) => self.whole(x, s, 1, MAX).map(|n| (n, None)),
            (Value::Vector(v), s) if v.len() == 2 => {
                let whole = |c: f64| c.fract() == 0.0 && (1.0..=MAX as f64).contains(&c);
                if whole(v[0]) && whole(v[1]) {
                    let (n, rows) = (v[0] as u32, v[1] as u32);
                    return Some((n, (rows != n).then_some(rows)));
                }
                self.err(
                    Error::new(s, format!("a sample grid of <{}, {}>", v[0], v[1])).label(format!(
                        "columns and rows are whole numbers from 1 to {MAX}"
                    )),
                );
                None
            }
            (other, s) => {
                self.wrong_kind(s, &what, &other, None);
                None
            }
        }
    }

    pub(super) fn camera(&mut self, kw: &Spanned<&str>, block: &Block) {
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
                let given: Vec<&str> = plane.iter().map(|q| q.name.node).collect();
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
    pub(super) fn lens(
        &mut self,
        p: &mut Params,
        kw: &Spanned<&str>,
    ) -> Option<crate::scene::ThinLens> {
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
            _ => Some(crate::scene::ThinLens {
                aperture: a?,
                focus: f.unwrap_or(1.0),
            }),
        }
    }

    pub(super) fn render(&mut self, kw: &Spanned<&str>, block: &Block) {
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
        if let Some(q) = p.take("bailout")
            && let Some(b) = self.checked(
                &q.values[0],
                |b| (0.0..1.0).contains(&b),
                "from 0 up to (not including) 1",
            )
        {
            self.scene.settings.bailout = b;
        }
        if let Some(q) = p.take("background")
            && let Some((c, _)) = self.colour(&q.values[0])
        {
            self.scene.settings.background = c;
            self.background_given = true;
        }
        if let Some(q) = p.take("samples")
            && let Some((n, rows)) = self.sample_grid(&q.values[0])
        {
            self.scene.settings.samples = n;
            self.scene.settings.sample_rows = rows;
        }
        if let Some(q) = p.take("gamma") {
            // Already applied by `find_transfer`; checked here for mistakes.
            self.transfer_value(&q.values[0]);
        }
        if let Some(q) = p.take("sampler") {
            const KINDS: [&str; 4] = ["regular", "random", "jittered", "multijittered"];
            let kind = match q.values[0].as_name().map(|n| n.node) {
                Some("regular") => Some(crate::scene::SamplerKind::Regular),
                Some("random") => Some(crate::scene::SamplerKind::Random),
                Some("jittered") => Some(crate::scene::SamplerKind::Jittered),
                Some("multijittered" | "multi_jittered") => {
                    Some(crate::scene::SamplerKind::MultiJittered)
                }
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
        if let Some(q) = p.take("accel") {
            // Already applied by `find_accel`; checked here for mistakes.
            let name = q.values[0].as_name().map(|n| n.node);
            if name.and_then(crate::accel::Accel::from_name).is_none() {
                let names = crate::accel::Accel::NAMES;
                let help = name
                    .and_then(|n| did_you_mean(n, names))
                    .unwrap_or_else(|| format!("the structures are {}", names.join(", ")));
                self.err(
                    Error::new(q.values[0].span(), "unknown acceleration structure")
                        .label("expected `bvh` or `kdtree`")
                        .help(help),
                );
            }
        }
        if let Some(q) = p.take("seed")
            && let Some(n) = self.integer(&q.values[0], 0, u32::MAX)
        {
            self.scene.settings.seed = n as u64;
        }
        if let Some(q) = p.take("adaptive") {
            self.scene.settings.adaptive = self.adaptive_block(&q.values[0], q.name.span);
        }
        self.motion_blur(&mut p);
        self.finish("render", p);
    }

    /// `motion_blur N` (1 to 64 sub-frames) and `shutter S` (0 < S ≤ 1
    /// frames, default 0.5: a film camera's 180° shutter). A shutter
    /// without sub-frames blurs nothing, which is said.
    fn motion_blur(&mut self, p: &mut Params) {
        let samples = p.take("motion_blur");
        let shutter = p.take("shutter");
        let n = samples
            .as_ref()
            .and_then(|q| self.integer(&q.values[0], 1, crate::scene::MAX_MOTION_SAMPLES));
        let s = match &shutter {
            Some(q) => self.checked(
                &q.values[0],
                |s| s > 0.0 && s <= 1.0,
                "a time in frames, greater than 0 and at most 1",
            ),
            None => Some(0.5),
        };
        match (&samples, &shutter) {
            (None, Some(q)) => self.warn(
                q.name.span,
                "`shutter` does nothing without `motion_blur N` (the number of sub-frames)",
            ),
            (Some(_), _) => {
                if let (Some(samples), Some(shutter)) = (n, s) {
                    self.scene.settings.motion_blur =
                        Some(crate::scene::MotionBlur { samples, shutter });
                }
            }
            (None, None) => {}
        }
    }

    /// `adaptive { threshold T  max_samples M }` inside `render` (whose
    /// `samples` is read already): T > 0 (default 0.1), M from `samples` + 1
    /// to 16 (default twice `samples`, at most 16). A pixel needs two
    /// samples or more for them to disagree.
    pub(super) fn adaptive_block(
        &mut self,
        item: &Item,
        at: Span,
    ) -> Option<crate::scene::Adaptive> {
        let block = self.block_of(item, "adaptive { threshold 0.1  max_samples 8 }")?;
        let mut p = self.params("adaptive", block, &params::ADAPTIVE);
        let n = self.scene.settings.samples;
        let threshold = match p.take("threshold") {
            Some(q) => self.checked(&q.values[0], |x| x > 0.0 && x.is_finite(), "greater than 0"),
            None => Some(0.1),
        };
        let max_samples = match p.take("max_samples") {
            Some(q) => self.integer(&q.values[0], 1, crate::scene::MAX_SAMPLES),
            None => Some((2 * n).min(crate::scene::MAX_SAMPLES)),
        };
        self.finish("adaptive", p);
        let (threshold, max_samples) = (threshold?, max_samples?);
        let rows = self.scene.settings.grid().1;
        if n * rows < 2 || max_samples * max_samples <= n * rows {
            let grid = if rows == n {
                format!("{n}")
            } else {
                format!("<{n}, {rows}>")
            };
            let why = if n * rows < 2 {
                "a pixel's samples are compared: give `samples 2` or more before `adaptive`"
                    .to_string()
            } else if rows == n {
                format!("`max_samples` must exceed `samples` ({n}) to add any")
            } else {
                format!(
                    "`max_samples` × `max_samples` must exceed the {} samples of `{grid}` to add any",
                    n * rows
                )
            };
            self.err(
                Error::new(at, "adaptive sampling has nothing to do here")
                    .label(format!("with `samples {grid}`"))
                    .help(why),
            );
            return None;
        }
        Some(crate::scene::Adaptive {
            threshold,
            max_samples,
        })
    }

    pub(super) fn transfer_value(&mut self, item: &Item) -> Option<Transfer> {
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
}
