//! Materials: named (`material gold { … }`) and inline blocks, the 2017
//! colour and `reflect`, the 2018 weights, Phong, mirror, glossy, glass
//! (`refract { … }`) and emission, and material values from `let`.

use super::*;

impl Builder<'_> {
    pub(super) fn named_material(&mut self, kw: &Spanned<&str>, items: &[Item], i: &mut usize) {
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
        let Some(block) = self.block_after(&Spanned::new(name.node.as_str(), name.span), items, i)
        else {
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

    pub(super) fn add_material(&mut self, m: Material) -> crate::scene::MaterialId {
        // A loop that gives each of 100,000 spheres `material { colour … }`
        // writes a few distinct materials many times: equal plain ones
        // share one entry (a material is some 250 bytes).
        let key = plain_key(&m);
        if let Some(id) = key.and_then(|k| self.plain_materials.get(&k)) {
            return *id;
        }
        self.scene.materials.push(m);
        let id = (self.scene.materials.len() - 1) as crate::scene::MaterialId;
        if let Some(k) = key {
            self.plain_materials.insert(k, id);
        }
        id
    }

    pub(super) fn material_block(&mut self, block: &Block) -> Option<Material> {
        if let Some(w) = patterns::material_pattern(&block.items) {
            let used = 1 + usize::from(w.string.is_some()) + usize::from(w.block.is_some());
            return self.picking_material(&w, &block.items[used..]);
        }
        if self.misspelt_pattern(&block.items) {
            return None;
        }
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
        if let Some(q) = p.take("normal") {
            match self.normal_pattern(&q.values) {
                Some(n) => m.normal = Some(Arc::new(n)),
                None => ok = false,
            }
        }
        ok &= self.round2_material(&mut p, &mut m);
        self.finish("material", p);
        ok.then_some(m)
    }

    /// The 2018 parts of a material (see `render/material/`). Glass and
    /// lamps have no diffuse or ambient part unless they say so.
    pub(super) fn round2_material(&mut self, p: &mut Params, m: &mut Material) -> bool {
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
            m.phong = Some(crate::scene::Phong {
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

    pub(super) fn refract_block(&mut self, item: &Item) -> Option<crate::scene::Dielectric> {
        let block = self.block_of(item, "refract { ior 1.5  filter rgb(0.9, 1, 0.95) }")?;
        let mut p = self.params("refract", block, &params::REFRACT);
        let mut d = crate::scene::Dielectric::default();
        let mut ok = true;
        for (name, slot) in [("ior", &mut d.ior), ("outside_ior", &mut d.outside_ior)] {
            ok &= self.take_into(
                &mut p,
                name,
                |b, q| b.checked(&q.values[0], |x| x > 0.0 && x.is_finite(), "greater than 0"),
                |v| *slot = v,
            );
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
    pub(super) fn material_value(&mut self, item: &Item) -> Option<crate::scene::MaterialId> {
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

/// FxHash's rotate-multiply over whole words, for [`PlainKey`]s: they are
/// numbers already, and SipHash's guard against chosen keys (a fifth of
/// the cost of a sphere's material) buys nothing for them.
#[derive(Default)]
pub(super) struct WordHasher(u64);

impl std::hash::Hasher for WordHasher {
    fn write(&mut self, bytes: &[u8]) {
        // Whole words as words: a copy of a slice of unknown length is a
        // call to memcpy.
        let mut words = bytes.chunks_exact(8);
        for w in &mut words {
            self.write_u64(<[u8; 8]>::try_from(w).map_or(0, u64::from_le_bytes));
        }
        for &b in words.remainder() {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

pub(super) type WordHash = std::hash::BuildHasherDefault<WordHasher>;

/// Every number of a plain material, bit for bit: materials with equal
/// keys are the same material in every respect.
pub(super) type PlainKey = [u64; 28];

/// The key of a material that can be shared, or none. Only plain ones
/// (a solid colour, no pattern, no bumps) are shared: a CSG block moves
/// hits that wear its own material id into its texture space, which
/// changes nothing for a material that reads no position, but would for
/// a pattern.
fn plain_key(m: &Material) -> Option<PlainKey> {
    // Destructured so that a new field cannot be left out of the key.
    let Material {
        texture,
        reflect,
        diffuse,
        ambient,
        phong,
        mirror,
        glossy,
        refract,
        emit,
        pick,
        normal,
    } = m;
    let Texture::Solid(c) = texture else {
        return None;
    };
    if pick.is_some() || normal.is_some() {
        return None;
    }
    let flag = |on: bool| if on { 1.0 } else { 0.0 };
    let p = phong.unwrap_or(crate::scene::Phong {
        colour: Colour::ZERO,
        shininess: 0.0,
    });
    let d = refract.unwrap_or(crate::scene::Dielectric {
        ior: 0.0,
        filter: Colour::ZERO,
        outside_ior: 0.0,
        outside_filter: Colour::ZERO,
    });
    let all: [f64; 28] = [
        c.x,
        c.y,
        c.z,
        *reflect,
        *diffuse,
        *ambient,
        flag(phong.is_some()),
        p.colour.x,
        p.colour.y,
        p.colour.z,
        p.shininess,
        mirror.x,
        mirror.y,
        mirror.z,
        flag(glossy.is_some()),
        glossy.unwrap_or(0.0),
        flag(refract.is_some()),
        d.ior,
        d.filter.x,
        d.filter.y,
        d.filter.z,
        d.outside_ior,
        d.outside_filter.x,
        d.outside_filter.y,
        d.outside_filter.z,
        emit.x,
        emit.y,
        emit.z,
    ];
    Some(all.map(f64::to_bits))
}
