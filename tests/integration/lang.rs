//! The scene language end to end: text in temp files → `lang::load` →
//! `scene::build`. Geometry is checked with spheres and planes (the other
//! shapes are written elsewhere).

use miette::Diagnostic;
use proptest::prelude::*;
use raytrace::geometry::{DVec3, Ray};
use raytrace::lang;
use raytrace::scene::{self, Colour, Projection, Scene, Texture, Transfer};
use std::path::{Path, PathBuf};

/// A folder of scene files that lives as long as the test.
pub struct Files {
    pub dir: tempfile::TempDir,
}

impl Files {
    pub fn new() -> Files {
        Files {
            dir: tempfile::Builder::new()
                .tempdir_in("/tmp")
                .expect("temp dir"),
        }
    }

    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let p = self.dir.path().join(name);
        if let Some(d) = p.parent() {
            std::fs::create_dir_all(d).unwrap();
        }
        std::fs::write(&p, text).unwrap();
        p
    }
}

/// Loads and builds; on failure, the messages of every problem.
pub fn try_build(path: &Path) -> Result<Scene, Vec<String>> {
    let messages = |p: &lang::diagnostics::Problems| {
        p.problems()
            .iter()
            .map(|p| p.message().to_string())
            .collect::<Vec<_>>()
    };
    let program = lang::load(path).map_err(|p| messages(&p))?;
    scene::build(&program).map_err(|p| messages(&p))
}

fn build(src: &str) -> Scene {
    let f = Files::new();
    let p = f.write("scene.rt", src);
    match try_build(&p) {
        Ok(s) => s,
        Err(e) => panic!("scene did not build: {e:#?}"),
    }
}

fn errors(src: &str) -> Vec<String> {
    let f = Files::new();
    let p = f.write("scene.rt", src);
    match try_build(&p) {
        Ok(_) => panic!("scene built but should not have"),
        Err(e) => e,
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

fn centre_of(s: &Scene, i: usize) -> DVec3 {
    s.objects[i].bounds().centre()
}

#[test]
fn constants_feed_later_expressions() {
    let _watchdog = crate::watchdog::start();
    let s =
        build("let R = 4\nlet half = R / 2\nsphere { radius half - 1  centre <R, 0, 0> * 0.5 }");
    let b = s.objects[0].bounds();
    assert!(close(b.min, DVec3::new(1.0, -1.0, -1.0)), "{b:?}");
    assert!(close(b.max, DVec3::new(3.0, 1.0, 1.0)), "{b:?}");
}

#[test]
fn constants_are_defined_once_and_before_use() {
    let _watchdog = crate::watchdog::start();
    let e = errors("let a = 1\nlet a = 2");
    assert_eq!(e, ["`a` is already defined"]);
    let e = errors("sphere { radius r }\nlet r = 1");
    assert_eq!(e, ["unknown name `r`"]);
    let e = errors("let pi = 3");
    assert_eq!(e, ["`pi` is a built-in name"]);
}

#[test]
fn includes_are_relative_to_the_including_file() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    f.write(
        "parts/materials.rt",
        "include \"more/consts.rt\"\nmaterial gold { colour rgb(1, 0.8, 0.2) }",
    );
    f.write("parts/more/consts.rt", "let R = 3");
    let p = f.write(
        "scene.rt",
        "include \"parts/materials.rt\"\nsphere { radius R  material gold }",
    );
    let s = try_build(&p).unwrap();
    assert_eq!(s.objects.len(), 1);
    assert!(close(s.objects[0].bounds().max, DVec3::splat(3.0)));
    assert_eq!(
        s.materials[1].texture,
        Texture::Solid(Colour::new(1.0, 0.8, 0.2))
    );
}

#[test]
fn include_cycles_and_missing_files_are_errors() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    f.write("a.rt", "include \"b.rt\"");
    f.write("b.rt", "include \"a.rt\"");
    assert_eq!(
        try_build(&f.dir.path().join("a.rt")).unwrap_err(),
        ["include cycle"]
    );
    let p = f.write("c.rt", "include \"nowhere.rt\"");
    assert_eq!(
        try_build(&p).unwrap_err(),
        ["cannot find the included file `nowhere.rt`"]
    );
}

#[test]
fn transforms_apply_in_the_order_written() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "sphere { radius 0.5 translate <1, 0, 0> rotate z 90 }\n\
         sphere { radius 0.5 rotate z 90 translate <1, 0, 0> }",
    );
    assert!(
        close(centre_of(&s, 0), DVec3::new(0.0, 1.0, 0.0)),
        "{:?}",
        centre_of(&s, 0)
    );
    assert!(close(centre_of(&s, 1), DVec3::new(1.0, 0.0, 0.0)));
}

#[test]
fn a_groups_transform_follows_its_childrens_and_wraps_once() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "group { sphere { translate <1, 0, 0> } sphere { translate <2, 0, 0> } rotate z 90 scale 2 }",
    );
    assert_eq!(s.objects.len(), 2, "groups are flattened");
    assert!(close(centre_of(&s, 0), DVec3::new(0.0, 2.0, 0.0)));
    assert!(close(centre_of(&s, 1), DVec3::new(0.0, 4.0, 0.0)));
    let shown = format!("{:?}", s.objects[0]);
    assert_eq!(shown.matches("Transformed").count(), 1, "{shown}");
    // No transform: no wrapper.
    let s = build("sphere { }");
    assert!(!format!("{:?}", s.objects[0]).contains("Transformed"));
}

#[test]
fn every_transform_kind() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "sphere { translate <0, 1, 0> shear yx 2 }\n\
         sphere { translate <1, 0, 0> mirror x }\n\
         sphere { matrix [1, 0, 0, 5,  0, 1, 0, 6,  0, 0, 1, 7] }\n\
         sphere { translate <0, 0, 1> rotate <1, 0, 0> 90 }",
    );
    // shear yx: x' = x + 2y, so the centre <0,1,0> moves to <2,1,0>.
    assert!(close(centre_of(&s, 0), DVec3::new(2.0, 1.0, 0.0)));
    assert!(close(centre_of(&s, 1), DVec3::new(-1.0, 0.0, 0.0)));
    assert!(close(centre_of(&s, 2), DVec3::new(5.0, 6.0, 7.0)));
    assert!(close(centre_of(&s, 3), DVec3::new(0.0, -1.0, 0.0)));
}

#[test]
fn rays_hit_the_transformed_sphere() {
    let _watchdog = crate::watchdog::start();
    let s = build("sphere { scale <2, 1, 1> translate <0, 0, -1> }");
    let r = Ray::new(DVec3::new(5.0, 0.0, -1.0), DVec3::new(-1.0, 0.0, 0.0));
    let h = s.objects[0].intersect(&r, 1e-9, f64::INFINITY).unwrap();
    assert!((h.t - 3.0).abs() < 1e-9, "{}", h.t);
}

#[test]
fn a_negative_value_after_a_name_is_the_value() {
    let _watchdog = crate::watchdog::start();
    // `offset -1` is read as the subtraction `offset - 1` by the grammar;
    // the builder splits it back.
    let s = build("plane { normal <0, 1, 0>  offset -1 }");
    let r = Ray::new(DVec3::new(0.0, 5.0, 0.0), DVec3::new(0.0, -1.0, 0.0));
    let h = s.objects[0].intersect(&r, 1e-9, f64::INFINITY).unwrap();
    assert!((h.t - 6.0).abs() < 1e-9);
}

#[test]
fn hex_and_named_colours_decode_with_the_scenes_gamma() {
    let _watchdog = crate::watchdog::start();
    // The material comes before `render`: gamma is still known first.
    let s = build(
        "material m { colour #808080 }\nmaterial n { colour green }\nmaterial o { colour rgb(0.5, 0.5, 0.5) }\nrender { gamma 2 }",
    );
    let g = (128.0f64 / 255.0).powi(2);
    assert_eq!(s.settings.transfer, Transfer::Gamma(2.0));
    assert_eq!(s.materials[1].texture, Texture::Solid(Colour::splat(g)));
    assert_eq!(
        s.materials[2].texture,
        Texture::Solid(Colour::new(0.0, g, 0.0))
    );
    assert_eq!(s.materials[3].texture, Texture::Solid(Colour::splat(0.5)));
    let s = build("material m { colour #808080 }");
    let srgb = Transfer::Srgb.decode(128.0 / 255.0);
    assert_eq!(s.materials[1].texture, Texture::Solid(Colour::splat(srgb)));
}

#[test]
fn materials_named_inline_and_inherited() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "material gold { colour gold reflect 0.3 }\n\
         sphere { material gold }\n\
         sphere { material { color red } }\n\
         sphere { }\n\
         group { material gold  sphere { }  sphere { material { reflect 1 } } }",
    );
    let ids: Vec<u32> = s
        .objects
        .iter()
        .map(|o| {
            let r = Ray::new(
                o.bounds().centre() + DVec3::new(0.0, 0.0, 5.0),
                DVec3::new(0.0, 0.0, -1.0),
            );
            o.intersect(&r, 1e-9, f64::INFINITY).unwrap().material
        })
        .collect();
    assert_eq!(ids, [1, 2, 0, 1, 3]);
    assert_eq!(s.materials[1].reflect, 0.3);
    let e = errors("sphere { material gold }\nmaterial gold { }");
    assert_eq!(e, ["unknown material `gold`"]);
}

#[test]
fn camera_render_ambient_and_lights() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "camera { position <0, 0, 4>  look_at <0, 0, 0>  up <0, 1, 0>  distance 1  width 2  height 1.5 }\n\
         render { width 320  height 240  max_depth 2  background rgb(0.1, 0.2, 0.3)  gamma linear }\n\
         ambient rgb(1, 1, 1) intensity 0.25\n\
         light { position <5, 10, 5> }\n\
         light { position <0, 1, 0>  colour rgb(1, 0, 0)  intensity 2 }",
    );
    assert_eq!(
        s.camera.projection,
        Projection::ViewPlane {
            distance: 1.0,
            width: 2.0,
            height: 1.5
        }
    );
    assert_eq!(
        (s.settings.width, s.settings.height, s.settings.max_depth),
        (320, 240, 2)
    );
    assert_eq!(s.settings.background, Colour::new(0.1, 0.2, 0.3));
    assert_eq!(s.settings.transfer, Transfer::Linear);
    assert_eq!(s.ambient, Colour::splat(0.25));
    assert_eq!(s.lights.len(), 2);
    assert_eq!(s.lights[0].colour, Colour::ONE);
    assert_eq!(s.lights[1].colour, Colour::new(2.0, 0.0, 0.0));
    let s = build("camera { fov 40 }");
    assert_eq!(s.camera.projection, Projection::Fov(40.0));
}

#[test]
fn camera_mistakes() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(
        errors("camera { position <1, 1, 1> look_at <1, 1, 1> }"),
        ["the camera looks at its own position"]
    );
    assert_eq!(
        errors("camera { position <0, 5, 0> look_at <0, 0, 0> }"),
        ["`up` is parallel to the view direction"]
    );
    assert_eq!(
        errors("camera { fov 180 }"),
        ["this must be an angle between 0 and 180 degrees"]
    );
    assert_eq!(
        errors("camera { fov 40  width 2 }"),
        ["`fov` and the view plane cannot be mixed"]
    );
    assert_eq!(
        errors("camera { }\ncamera { }"),
        ["`camera` is given twice"]
    );
}

#[test]
fn numbers_the_user_controls_are_validated() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(
        errors("sphere { radius 0 }"),
        ["this must be greater than 0"]
    );
    assert_eq!(
        errors("sphere { radius 1e999 }"),
        ["this number is too large"]
    );
    assert_eq!(
        errors("render { width 0.5 }"),
        ["this must be a whole number from 1 to 65535"]
    );
    assert_eq!(
        errors("render { max_depth 1000 }"),
        ["this must be a whole number from 0 to 64"]
    );
    assert_eq!(
        errors("material m { reflect 2 }"),
        ["this must be between 0 and 1"]
    );
    assert_eq!(
        errors("sphere { scale <1, 0, 1> }"),
        ["this scale is singular"]
    );
    assert_eq!(
        errors("sphere { matrix [1,0,0,0, 0,1,0,0, 0,0,0,0] }"),
        ["this matrix is singular"]
    );
}

#[test]
fn all_errors_are_reported_together() {
    let _watchdog = crate::watchdog::start();
    let e = errors("sphere { radius -1 }\nsphere { centre <1, 2> }\nplane { nromal <0, 1, 0> }");
    assert_eq!(e.len(), 3, "{e:?}");
}

#[test]
fn equation_errors_land_inside_the_string() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    // `q` is at byte 16 of the file: 10 for `implicit "`, 6 into the string.
    let src = "implicit \"x^2 + q^2\" { }";
    let p = f.write("scene.rt", src);
    let program = lang::load(&p).unwrap();
    let err = scene::build(&program).unwrap_err();
    let label = err.labels().unwrap().next().unwrap();
    assert_eq!((label.offset(), label.len()), (16, 1));
}

#[test]
fn csg_refuses_open_surfaces() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(
        errors("difference { sphere { } disc { } }"),
        ["`disc` is an open surface and cannot be used in `difference`: it has no inside"]
    );
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let _watchdog = crate::watchdog::start();
    for src in [
        "(".repeat(100_000),
        format!("let a = {}1{}", "(".repeat(100_000), ")".repeat(100_000)),
        "group { ".repeat(10_000),
        format!("let a = {}1", "-".repeat(100_000)),
    ] {
        let e = errors(&src);
        assert!(
            e.iter().any(|m| m.contains("too deeply")
                || m.contains("never closed")
                || m.contains("more than 256 operators")),
            "{e:?}"
        );
    }
}

const TOKENS: &[&str] = &[
    "sphere",
    "plane",
    "group",
    "union",
    "difference",
    "camera",
    "render",
    "light",
    "material",
    "ambient",
    "let",
    "include",
    "mesh",
    "implicit",
    "radius",
    "centre",
    "translate",
    "rotate",
    "scale",
    "shear",
    "mirror",
    "matrix",
    "x",
    "xy",
    "gold",
    "white",
    "R",
    "{",
    "}",
    "(",
    ")",
    "<",
    ">",
    "[",
    "]",
    ",",
    "=",
    "+",
    "-",
    "*",
    "/",
    "^",
    "1",
    "0",
    "-2.5",
    "1e999",
    "1.2.3",
    "#ff8000",
    "#ff",
    "\"x^2 + y^2 - 1\"",
    "\"nowhere.rt\"",
    "\"",
    "rgb(",
    "sqrt(",
    "//",
    "/*",
    "\n",
    " ",
    "pi",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _watchdog = crate::watchdog::start();
        let f = Files::new();
        let p = f.dir.path().join("scene.rt");
        std::fs::write(&p, &bytes).unwrap();
        let _ = try_build(&p);
    }

    #[test]
    fn random_tokens_never_panic(tokens in proptest::collection::vec(proptest::sample::select(TOKENS), 0..80)) {
        let _watchdog = crate::watchdog::start();
        let f = Files::new();
        let p = f.write("scene.rt", &tokens.join(" "));
        let _ = try_build(&p);
    }
}

/// The fenced examples of docs/language.md, so the reference cannot drift
/// from the parser: every one parses, and the statement examples build.
#[test]
fn the_language_reference_examples_work() {
    let _watchdog = crate::watchdog::start();
    let doc = include_str!("../../docs/language.md");
    let blocks: Vec<&str> = doc
        .split("```")
        .skip(1)
        .step_by(2)
        // Untagged or `rt` blocks are scenes; `sh` and others are not.
        .filter(|b| matches!(b.split('\n').next().map(str::trim), Some("" | "rt")))
        .map(|b| b.trim_start_matches(|c: char| c != '\n'))
        .filter(|b| !b.contains('×'))
        .collect();
    assert!(blocks.len() >= 7, "{}", blocks.len());
    let f = Files::new();
    f.write("materials.rt", "material gold { colour gold }");
    for (k, b) in blocks.iter().enumerate() {
        let p = f.write(&format!("doc{k}.rt"), b);
        if let Err(e) = lang::load(&p) {
            panic!("example {k} does not parse: {e}\n{b}");
        }
        // Transforms alone are not a statement; images and meshes need
        // files the examples only name.
        let statement = !b.trim_start().starts_with("translate")
            && !b.contains("image \"")
            && !b.contains("mesh \"");
        if !statement {
            continue;
        }
        // Build each top-level statement alone (one example shows two cameras).
        let mut chunks: Vec<String> = Vec::new();
        for line in b.lines() {
            match chunks.last_mut() {
                Some(c) if line.starts_with([' ', '}']) || line.is_empty() => {
                    c.push('\n');
                    c.push_str(line);
                }
                _ => chunks.push(line.to_string()),
            }
        }
        // Constants and materials are declarations the other chunks use.
        let declares = |c: &&String| {
            c.starts_with("let ") || c.starts_with("material ") || c.starts_with("fn ")
        };
        let prefix: Vec<&str> = chunks.iter().filter(declares).map(String::as_str).collect();
        let mut prefix = prefix.join("\n");
        // Materials an example uses but declares elsewhere (in its example
        // file): declare them plainly.
        let mentions: Vec<(String, bool)> = b
            .split("material ")
            .skip(1)
            .map(|after| {
                let name: String = after
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                let is_declaration = after[name.len()..].trim_start().starts_with('{');
                (name, is_declaration)
            })
            .collect();
        for (name, _) in mentions.iter().filter(|(n, d)| !n.is_empty() && !d) {
            let declared = mentions.iter().any(|(m, d)| m == name && *d);
            let added = prefix.contains(&format!("material {name} {{ }}"));
            if !declared && !added {
                prefix.push_str(&format!("\nmaterial {name} {{ }}"));
            }
        }
        for c in chunks.iter().filter(|c| !declares(c)) {
            let p = f.write(&format!("doc{k}.rt"), &format!("{prefix}\n{c}"));
            if let Err(e) = try_build(&p) {
                panic!("example {k} does not build: {e:?}\n{c}");
            }
        }
    }
}

#[test]
fn a_texture_value_keeps_its_block() {
    let _watchdog = crate::watchdog::start();
    // One clear error for a misspelt texture, not a stray-block error too.
    assert_eq!(
        errors("material m { colour chequer { a white  b black }  reflect 0.5 }"),
        ["unknown texture `chequer`"]
    );
    let s = build("material m { colour checker { a white  b black }  reflect 0.5 }");
    assert!(matches!(
        s.materials[1].texture,
        raytrace::scene::Texture::Pattern(_)
    ));
}

#[test]
fn includes_inside_blocks_add_to_the_block() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    f.write(
        "balls.rt",
        "sphere { translate <1, 0, 0> }\nsphere { translate <2, 0, 0> }",
    );
    let p = f.write(
        "scene.rt",
        "group { include \"balls.rt\"  translate <0, 5, 0> }",
    );
    let s = try_build(&p).unwrap();
    assert_eq!(s.objects.len(), 2);
    assert!(close(centre_of(&s, 1), DVec3::new(2.0, 5.0, 0.0)));
    // A `let` inside a block is local to it.
    let s = build("sphere { let r = 2  radius r }");
    assert_eq!(s.objects.len(), 1);
    assert_eq!(
        errors("sphere { let r = 2 }\nsphere { radius r }"),
        ["unknown name `r`"]
    );
}

#[test]
fn mesh_files_are_found_relative_to_the_scene_and_errors_name_them() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    f.write(
        "models/bad.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n",
    );
    let p = f.write(
        "scenes/scene.rt",
        "mesh \"../models/bad.ply\" { flat }\nmesh \"gone.ply\" { }",
    );
    let e = try_build(&p).unwrap_err();
    assert_eq!(e.len(), 2, "{e:?}");
    assert!(
        e[0].starts_with("cannot read the mesh `../models/bad.ply`"),
        "{e:?}"
    );
    assert_eq!(e[1], "cannot find the mesh file `gone.ply`");
}

#[test]
fn a_group_inside_csg_is_a_union() {
    let _watchdog = crate::watchdog::start();
    // (A ∪ B) ∩ C is A ∪ B here; were the group's children flattened into
    // the intersection, A ∩ B ∩ C would be empty.
    let s = build(
        "intersection {\n\
           group { sphere { translate <-2, 0, 0> }  sphere { translate <2, 0, 0> } }\n\
           sphere { radius 3.5 }\n\
         }",
    );
    assert_eq!(s.objects.len(), 1);
    let r = Ray::new(DVec3::new(10.0, 0.0, 0.0), DVec3::new(-1.0, 0.0, 0.0));
    let h = s.objects[0]
        .intersect(&r, 1e-9, f64::INFINITY)
        .expect("hits B");
    assert!((h.t - 7.0).abs() < 1e-9, "{}", h.t);
}

#[test]
fn a_material_may_share_a_keywords_name() {
    let _watchdog = crate::watchdog::start();
    // `mirror` is also a transform; after `material` it is the material.
    let s = build(
        "material mirror { colour white  reflect 0.9 }\nsphere { radius 1  material mirror }\nsphere { material mirror  mirror x }",
    );
    assert_eq!(s.objects.len(), 2);
    assert_eq!(s.materials[1].reflect, 0.9);
}

#[test]
fn a_minus_after_a_space_starts_a_new_value() {
    let _watchdog = crate::watchdog::start();
    // `rotate y -90` is the axis `y` and the angle −90, not `y - 90`.
    let s = build("box { min <0, 0, 0>  max <1, 1, 1>  rotate y -90 }");
    let b = s.objects[0].bounds();
    assert!(close(b.min, DVec3::new(-1.0, 0.0, 0.0)), "{b:?}");
    // Subtraction is still subtraction, spaced or not.
    let s = build("let a = 3\nsphere { radius a - 1  centre <a-1, 0, 0> }");
    let b = s.objects[0].bounds();
    assert!(close(b.min, DVec3::new(0.0, -2.0, -2.0)), "{b:?}");
}
