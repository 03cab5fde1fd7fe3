//! Materials: named (`material gold { … }`) and inline blocks, the 2017
//! colour and `reflect`, the 2018 weights, Phong, mirror, glossy, glass
//! (`refract { … }`) and emission, and material values from `let`.

use super::*;
use crate::eval::expr::Value;
use crate::lang::ast::ExprKind;

/// What a material may show wherever it is used: whether it emits or
/// reads the hit's (u, v), itself or through a material it may choose.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Reach {
    pub emits: bool,
    pub reads_uv: bool,
}

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

    /// What material `id` may show, through every material it may choose
    /// as a pattern of materials, at any depth of nesting. Worked out once
    /// per material, in the order they were made: a pattern chooses only
    /// materials made before it, so each entry reads earlier ones. (Walked
    /// again for every object, 40 patterns each choosing the one before
    /// twice took 2⁴⁰ steps.)
    pub(super) fn material_reach(&mut self, id: crate::scene::MaterialId) -> Reach {
        let (all, reach) = (&self.scene.materials, &mut self.material_reach);
        while reach.len() < all.len() {
            let i = reach.len();
            let m = &all[i];
            let r = match &m.pick {
                None => Reach {
                    emits: m.emits(),
                    reads_uv: m.reads_uv(),
                },
                Some(pick) => pick.bands.iter().fold(
                    Reach {
                        emits: false,
                        reads_uv: m.reads_uv(),
                    },
                    // A pattern's choices are made before it (the walk
                    // ends); one that was not would be a loop, and counts
                    // for nothing, as it did when walked.
                    |r, &(_, b)| match reach.get(b as usize).filter(|_| (b as usize) < i) {
                        Some(o) => Reach {
                            emits: r.emits || o.emits,
                            reads_uv: r.reads_uv || o.reads_uv,
                        },
                        None => r,
                    },
                ),
            };
            reach.push(r);
        }
        reach[id as usize]
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
                    Some((c, _)) if c.max_element() <= 1.0 => *slot = crate::scene::Filter::new(c),
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
            let key = block_key(b);
            if let Some(id) = key.as_ref().and_then(|k| self.block_materials.get(&k[..])) {
                return Some(*id);
            }
            let said = (self.err_calls, self.errors.len(), self.warnings.len());
            let m = self.material_block(b)?;
            // Only a plain material (the one kind shared by id) from a
            // block that said nothing: another block of the same words
            // would make the same material and say nothing either.
            let clean = said == (self.err_calls, self.errors.len(), self.warnings.len());
            let plain = plain_key(&m).is_some();
            let id = self.add_material(m);
            if let Some(k) = key
                && clean
                && plain
            {
                self.block_materials
                    .insert(k.into_vec().into_boxed_slice(), id);
            }
            return Some(id);
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

/// A material block's items as words, when they are only the material's
/// own parameter names and literal or worked-out numbers, vectors and
/// colours (`colour rgb(0.1, 0.2, 0.3)  diffuse 0.9`): what such a block
/// makes depends on nothing else, so blocks of the same words make the
/// same material. `None` for anything else (a pattern, a nested block, a
/// name the builder would look up, an expression left to it).
pub(super) fn block_key(b: &Block) -> Option<smallvec::SmallVec<[u64; 16]>> {
    let mut out = smallvec::SmallVec::new();
    for item in &b.items {
        let Item::Value(e) = item else {
            return None;
        };
        match &e.kind {
            ExprKind::Name(n) if params::MATERIAL.get(params::canonical(n)).is_some() => {
                // The name as written (`color` and `colour` both read
                // as `colour`, but a message would quote it): its length,
                // then its bytes eight to a word.
                out.push(1 << 32 | n.len() as u64);
                for w in n.as_bytes().chunks(8) {
                    let mut word = [0u8; 8];
                    word[..w.len()].copy_from_slice(w);
                    out.push(u64::from_le_bytes(word));
                }
            }
            ExprKind::Number(x) => out.extend([2 << 32, x.to_bits()]),
            ExprKind::Value(Value::Number(x)) => out.extend([3 << 32, x.to_bits()]),
            ExprKind::Value(Value::Colour(c)) => {
                out.extend([4 << 32, c.x.to_bits(), c.y.to_bits(), c.z.to_bits()]);
            }
            ExprKind::Value(Value::Vector(v)) => {
                out.push(5 << 32 | v.len() as u64);
                out.extend(v.iter().map(|x| x.to_bits()));
            }
            _ => return None,
        }
    }
    Some(out)
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
        filter: crate::scene::Filter::new(Colour::ZERO),
        outside_ior: 0.0,
        outside_filter: crate::scene::Filter::new(Colour::ZERO),
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
        d.filter.per_unit().x,
        d.filter.per_unit().y,
        d.filter.per_unit().z,
        d.outside_ior,
        d.outside_filter.per_unit().x,
        d.outside_filter.per_unit().y,
        d.outside_filter.per_unit().z,
        emit.x,
        emit.y,
        emit.z,
    ];
    Some(all.map(f64::to_bits))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Ray;
    use glam::DVec3;

    fn checked(text: &str) -> Checked {
        let program = crate::lang::load_text(std::path::Path::new("t.rt"), text.into())
            .unwrap_or_else(|_| panic!("parses"));
        check(&program, &crate::eval::Options::default())
    }

    /// The material of the object straight below (x, 10, 0).
    fn material_at(scene: &Scene, x: f64) -> &Material {
        let ray = Ray::new(DVec3::new(x, 10.0, 0.0), DVec3::NEG_Y);
        let hit = scene
            .objects
            .iter()
            .filter_map(|o| o.intersect(&ray, 0.0, f64::INFINITY))
            .min_by(|a, b| a.t.total_cmp(&b.t))
            .unwrap_or_else(|| panic!("nothing below x = {x}"));
        &scene.materials[hit.material as usize]
    }

    /// Blocks a loop writes many times over, each sphere's found again by
    /// a ray: blocks of the same words share one material, and any
    /// difference (a parameter's name, a value, a literal against a worked
    /// out number, `color` for `colour`) gives the material its own words
    /// say, whichever came first.
    #[test]
    fn material_blocks_of_the_same_words_share_a_material_and_no_others_do() {
        let c = checked(
            "for i in 0..24 {
               if i % 4 == 0 {
                 sphere { centre <3 * i, 0, 0>  radius 1
                   material { colour rgb(i % 3 / 2, 0.25, 0.5)  diffuse 0.5 } }
               } else if i % 4 == 1 {
                 sphere { centre <3 * i, 0, 0>  radius 1
                   material { colour rgb(i % 3 / 2, 0.25, 0.5)  ambient 0.5 } }
               } else if i % 4 == 2 {
                 sphere { centre <3 * i, 0, 0>  radius 1
                   material { color rgb(i % 3 / 2, 0.25, 0.5)  specular_colour rgb(0.5, 0.5, 0.5)  specular 1  shininess 10 + i % 8 } }
               } else {
                 sphere { centre <3 * i, 0, 0>  radius 1
                   material { colour rgb(i % 3 / 2, 0.25, 0.5)  diffuse 1 / 2 } }
               }
             }",
        );
        assert!(c.errors.is_empty(), "{:?}", c.errors);
        for i in 0..24 {
            let m = material_at(&c.scene, 3.0 * i as f64);
            let want = Colour::new((i % 3) as f64 / 2.0, 0.25, 0.5);
            let Texture::Solid(got) = &m.texture else {
                panic!("{i}: not solid")
            };
            assert_eq!(*got, want, "{i}");
            let d = Material::default();
            let (diffuse, ambient) = match i % 4 {
                0 | 3 => (0.5, d.ambient),
                1 => (d.diffuse, 0.5),
                _ => (d.diffuse, d.ambient),
            };
            assert_eq!((m.diffuse, m.ambient), (diffuse, ambient), "{i}");
            match (i % 4, &m.phong) {
                (2, Some(p)) => assert_eq!(p.shininess, 10.0 + (i % 8) as f64, "{i}"),
                (2, None) => panic!("{i}: no highlight"),
                (_, p) => assert!(p.is_none(), "{i}"),
            }
        }
        // Three colours with diffuse 0.5 (written two ways), three with
        // ambient 0.5, six (colour, shininess) pairs of the highlight
        // (i = 2, 6, …, 22), and the default.
        assert_eq!(c.scene.materials.len(), 1 + 3 + 3 + 6);
    }

    /// Glass whose words differ only in a worked-out filter keeps each
    /// filter: the shared-material key reads the filter as written.
    #[test]
    fn glass_blocks_differing_only_in_their_filter_keep_their_own() {
        let c = checked(
            "for i in 0..6 {
               sphere { centre <3 * i, 0, 0>  radius 1
                 material { refract { ior 1.5  filter rgb(1, 1 - i / 10, 0.5)  outside_filter rgb(1, 1, 1 - i / 20) } } }
             }",
        );
        assert!(c.errors.is_empty(), "{:?}", c.errors);
        for i in 0..6 {
            let m = material_at(&c.scene, 3.0 * i as f64);
            let d = m.refract.as_ref().expect("glass");
            let f = i as f64;
            assert_eq!(
                d.filter.per_unit(),
                Colour::new(1.0, 1.0 - f / 10.0, 0.5),
                "{i}"
            );
            assert_eq!(
                d.outside_filter.per_unit(),
                Colour::new(1.0, 1.0, 1.0 - f / 20.0),
                "{i}"
            );
        }
        assert_eq!(c.scene.materials.len(), 1 + 6);
    }

    /// A block that reports a mistake (an unknown parameter, the material
    /// still made) is reported where each copy of it is written.
    #[test]
    fn every_copy_of_a_block_with_a_mistake_reports_it() {
        let c = checked(
            "sphere { centre <0, 0, 0>  radius 1  material { colour rgb(1, 0, 0)  shinyness 3 } }
             sphere { centre <3, 0, 0>  radius 1  material { colour rgb(1, 0, 0)  shinyness 3 } }",
        );
        let lines: std::collections::HashSet<_> = c.errors.iter().map(|e| e.span.start).collect();
        assert_eq!(lines.len(), 2, "{:?}", c.errors);
    }

    /// Likewise for a block of only parameters and values, whose words
    /// would share its material (a parameter given twice, the material
    /// still made from the first): each copy reports it and wears the
    /// material its words make.
    #[test]
    fn every_copy_of_a_shareable_block_with_a_mistake_reports_it() {
        let block = "material { colour rgb(1, 0, 0)  diffuse 0.5  diffuse 0.5 }";
        let c = checked(&format!(
            "sphere {{ centre <0, 0, 0>  radius 1  {block} }}
             sphere {{ centre <3, 0, 0>  radius 1  {block} }}"
        ));
        let twice: std::collections::HashSet<_> = c
            .errors
            .iter()
            .filter(|e| e.message.contains("given twice"))
            .map(|e| e.span.start)
            .collect();
        assert_eq!(twice.len(), 2, "{:?}", c.errors);
        for x in [0.0, 3.0] {
            let m = material_at(&c.scene, x);
            assert!(
                matches!(m.texture, Texture::Solid(c) if c == Colour::new(1.0, 0.0, 0.0)),
                "{x}"
            );
            assert_eq!(m.diffuse, 0.5, "{x}");
        }
    }

    #[test]
    fn a_blocks_words_tell_names_numbers_colours_and_vectors_apart() {
        let key = |text: &str| {
            let c = crate::lang::load_text(
                std::path::Path::new("t.rt"),
                format!("material m {{ {text} }}"),
            )
            .unwrap_or_else(|_| panic!("parses"));
            let Some(Item::Block(b)) = c.items.get(2) else {
                panic!("{text}: {:?}", c.items)
            };
            block_key(b)
        };
        // Literal numbers (the evaluator leaves them) and names.
        let words = [
            "diffuse 0.5",
            "ambient 0.5",
            "diffuse 0.25",
            "specular_colour 0.5",
            "specular_color 0.5",
            "specular 0.5",
            "mirror 1  diffuse 0.5",
        ];
        let keys: Vec<_> = words.iter().map(|w| key(w).expect(w)).collect();
        for (i, a) in keys.iter().enumerate() {
            for (j, b) in keys.iter().enumerate() {
                assert_eq!(a == b, i == j, "{} against {}", words[i], words[j]);
            }
        }
        assert_eq!(
            key("diffuse 0.5"),
            key("diffuse   0.5"),
            "spaces are not words"
        );
        // Anything else is not a plain block.
        for text in [
            "colour checker { }",
            "reflect r",
            "colour \"x.png\"",
            "normal bumps { }",
        ] {
            assert_eq!(key(text), None, "{text}");
        }
    }

    /// The words of the block of `material m { text }` after the
    /// evaluator has worked it out (as the builder gets it), with `k` =
    /// 0.25 bound.
    fn evaluated_key(text: &str) -> Option<smallvec::SmallVec<[u64; 16]>> {
        let program = crate::lang::load_text(
            std::path::Path::new("t.rt"),
            format!("let k = 0.25\nmaterial m {{ {text} }}"),
        )
        .unwrap_or_else(|_| panic!("parses"));
        let options = crate::eval::Options::default();
        let e = crate::eval::evaluate(&program, crate::scene::Transfer::Srgb, &options);
        assert!(e.errors.is_empty(), "{text}: {:?}", e.errors);
        let Some(Item::Block(b)) = e.items.iter().find(|i| matches!(i, Item::Block(_))) else {
            panic!("{text}: {:?}", e.items)
        };
        block_key(b)
    }

    /// Numbers, colours and vectors the evaluator has worked out are
    /// words too (a loop's `colour rgb(i % 3 / 2, …)`), each told apart
    /// from the others and from a literal of the same value.
    #[test]
    fn worked_out_numbers_colours_and_vectors_are_words() {
        let words = [
            "diffuse 0.5",
            "diffuse k * 2",
            "diffuse k * 3",
            "colour rgb(k, k, k)",
            "colour rgb(k, k, 2 * k)",
            "colour <k, k, k>",
            "colour <k, k>",
            "colour <k, k, 2 * k>",
        ];
        let keys: Vec<_> = words
            .iter()
            .map(|w| evaluated_key(w).unwrap_or_else(|| panic!("{w}: no words")))
            .collect();
        for (i, a) in keys.iter().enumerate() {
            for (j, b) in keys.iter().enumerate() {
                assert_eq!(a == b, i == j, "{} against {}", words[i], words[j]);
            }
        }
        assert_eq!(
            evaluated_key("diffuse k * 2  colour rgb(k, k, k)"),
            evaluated_key("diffuse 2 * k  colour rgb(0.25, k, k)"),
            "the same values worked out are the same words"
        );
    }

    /// A vector's length is among its words: a short vector and the
    /// words after it cannot read as one longer vector whose extra
    /// components have the bits of those words.
    #[test]
    fn a_vectors_length_is_among_its_words() {
        let short = "colour <1, 2>  reflect 0.5";
        let Some(words) = evaluated_key(short) else {
            panic!("{short}: no words")
        };
        // The words of `reflect 0.5`, after the vector's own.
        let tail: Vec<String> = words[words.len() - 4..]
            .iter()
            .map(|w| format!("{:?}", f64::from_bits(*w)))
            .collect();
        let long = format!("colour <1, 2, {}>", tail.join(", "));
        let Some(other) = evaluated_key(&long) else {
            panic!("{long}: no words")
        };
        assert_eq!(words.len(), other.len(), "{long}");
        assert_ne!(words, other, "{short} against {long}");
    }
}
