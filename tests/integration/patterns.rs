//! Patterns as pictures and diagnostics show them: gradient values and
//! sector borders where the formulas put them, a checker of two materials
//! cell by cell equal to each material alone, maps, patterns that move with
//! their objects, bumps that leave the flat picture alone at amount 0, and
//! mistakes reported with their place.

use crate::support::*;

/// A plane y = 0 seen from straight above, fov 90, lit only by an ambient
/// white of 1 and stored linear: each pixel is the material's colour. The
/// image spans x, z ∈ [−10, 10]; pixel (a, b) looks at x = (a + 0.5)/2 − 10,
/// z = (b + 0.5)/2 − 10, where the plane's (u, v) is (x, −z).
const TOP_DOWN: &str = "
camera { position <0, 10, 0>  look_at <0, 0, 0>  up <0, 0, -1>  fov 90 }
render { width 40  height 40  gamma linear  background rgb(0.2, 0.6, 0.3) }
ambient white intensity 1
";

fn ground(a: u32, b: u32) -> (f64, f64) {
    ((a as f64 + 0.5) / 2.0 - 10.0, (b as f64 + 0.5) / 2.0 - 10.0)
}

fn top_down(material: &str) -> raytrace::render::Film {
    render_src(&format!(
        "{TOP_DOWN}\nplane {{ normal <0, 1, 0>  material {material} }}\n"
    ))
}

fn build_errors(src: &str) -> Vec<String> {
    let (_dir, path) = scene_file(src);
    let program = raytrace::lang::load(&path).expect("reads");
    match raytrace::scene::build(&program) {
        Ok(_) => panic!("built, but should not have:\n{src}"),
        Err(p) => p
            .problems()
            .iter()
            .map(|e| {
                use miette::Diagnostic;
                let help = e.help().map(|h| h.to_string()).unwrap_or_default();
                format!("{} | {help}", e.message())
            })
            .collect(),
    }
}

#[test]
fn gradient_values_are_the_fractional_part_along_the_axis() {
    let _watchdog = crate::watchdog::start();
    // Along x, a quarter as fast: the value is frac(x / 4), black to white.
    let film = top_down("{ colour gradient { axis <0.25, 0, 0>  a black  b white } }");
    for a in 0..40 {
        let (x, _) = ground(a, 20);
        let want = (x / 4.0) - (x / 4.0).floor();
        let got = film.get(a, 20)[0] as f64;
        assert!((got - want).abs() < 1e-5, "x {x}: {got} vs {want}");
    }
}

#[test]
fn sector_borders_are_at_the_analytic_angles() {
    let _watchdog = crate::watchdog::start();
    // Six sectors in (u, v) = (x, −z) around the origin, values k/5.
    let film = top_down("{ colour sectors { count 6  uv  a black  b white } }");
    let mut checked = 0;
    for b in 0..40 {
        for a in 0..40 {
            let (x, z) = ground(a, b);
            let (u, v) = (x, -z);
            let deg = v.atan2(u).to_degrees().rem_euclid(360.0);
            // Leave out pixels within half a degree of a border.
            let off = deg % 60.0;
            if !(0.5..59.5).contains(&off) || u.hypot(v) < 1.0 {
                continue;
            }
            let k = (deg / 60.0).floor();
            let got = film.get(a, b)[0] as f64;
            assert!((got - k / 5.0).abs() < 1e-6, "at {deg:.1}°: {got}");
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked}");
    // Quadrants, solid, around y: φ = atan2(z, x) from +x towards +z.
    let film = top_down("{ colour quadrants { a black  b white } }");
    for (a, b, k) in [(30, 30, 0.0), (9, 30, 1.0), (9, 9, 2.0), (30, 9, 3.0)] {
        let got = film.get(a, b)[0] as f64;
        assert!((got - k / 3.0).abs() < 1e-6, "pixel ({a}, {b}): {got}");
    }
}

#[test]
fn a_checker_of_two_materials_is_each_material_in_its_cells() {
    let _watchdog = crate::watchdog::start();
    let materials = "
material matte  { colour rgb(0.8, 0.3, 0.1) }
material shiny  { colour rgb(0.1, 0.1, 0.5)  diffuse 0.5  mirror 0.6 }
";
    let scene = |m: &str| {
        render_src(&format!(
            "{TOP_DOWN}{materials}\nplane {{ normal <0, 1, 0>  material {m} }}\n"
        ))
    };
    let both = scene("{ checker { a matte  b shiny  scale 0.5 } }");
    let matte = scene("matte");
    let shiny = scene("shiny");
    // The two alone differ (the mirror shows the background): a real test.
    assert!(max_difference(&matte, &shiny) > 0.1);
    let f = |s: f64| if s >= 0.0 { 0.5 * s } else { 1.0 - 0.5 * s };
    let (mut na, mut nb) = (0, 0);
    for b in 0..40 {
        for a in 0..40 {
            let (x, z) = ground(a, b);
            let (u, v) = (f(x), f(-z));
            // Away from cell borders.
            if [u, v].iter().any(|c| (c - c.round()).abs() < 0.2) {
                continue;
            }
            let even = ((u.floor() + v.floor()) as i64).rem_euclid(2) == 0;
            let alone = if even { &matte } else { &shiny };
            assert_eq!(both.get(a, b), alone.get(a, b), "pixel ({a}, {b})");
            if even {
                na += 1;
            } else {
                nb += 1;
            }
        }
    }
    assert!(na > 150 && nb > 150, "{na} {nb}");
}

#[test]
fn a_material_pattern_may_be_a_value_and_its_materials_inline() {
    let _watchdog = crate::watchdog::start();
    let film = render_src(&format!(
        "{TOP_DOWN}
let tiles = checker {{ a {{ colour white }}  b {{ colour black }}  scale 0.5 }}
plane {{ normal <0, 1, 0>  material {{ tiles }} }}
"
    ));
    // x = 1.25, −z = 1.25: cell (0, 0), `a`; x = 3.25: cell (1, 0), `b`.
    assert_eq!(film.get(22, 17), [1.0, 1.0, 1.0]);
    assert_eq!(film.get(26, 17), [0.0, 0.0, 0.0]);
}

#[test]
fn a_two_key_colour_map_is_a_and_b() {
    let _watchdog = crate::watchdog::start();
    let ab = top_down("{ colour marble { a #e0d8d0  b #202840  scale 0.5 } }");
    let map = top_down("{ colour marble { colour_map { 0 #e0d8d0  1 #202840 }  scale 0.5 } }");
    assert_eq!(max_difference(&ab, &map), 0.0);
    // A three-key map with its middle on the line between differs nowhere
    // by more than rounding.
    let mid = top_down(
        "{ colour marble { colour_map { 0 rgb(1, 1, 1)  0.5 rgb(0.5, 0.5, 0.5)  1 rgb(0, 0, 0) }  scale 0.5 } }",
    );
    let two = top_down("{ colour marble { a rgb(1, 1, 1)  b rgb(0, 0, 0)  scale 0.5 } }");
    assert!(max_difference(&mid, &two) < 1e-6);
    let varied = two.pixels.iter().filter(|p| p[0] < 0.5).count();
    assert!(varied > 20, "veins seen: {varied}");
}

#[test]
fn patterns_move_with_their_objects_and_their_own_translate() {
    let _watchdog = crate::watchdog::start();
    let scene = |camera: f64, object: &str| {
        render_src(&format!(
            "
camera {{ position <{camera}, 0, 4>  look_at <{camera}, 0, 0>  fov 40 }}
render {{ width 32  height 32  gamma linear }}
ambient white intensity 0.3
light {{ position <{l}, 3, 4> }}
{object}
",
            l = camera + 2.0
        ))
    };
    let granite = "granite { colour_map { 0 black  0.5 #808080  1 white }  scale 0.7";
    let here = scene(
        0.0,
        &format!("sphere {{ radius 1  material {{ colour {granite} }} }} }}"),
    );
    // The object moved by a transform: its pattern goes with it.
    let moved = scene(
        5.0,
        &format!("sphere {{ radius 1  material {{ colour {granite} }} }}  translate <5, 0, 0> }}"),
    );
    // The sphere built at <5, 0, 0> (its centre is geometry, not a
    // transform) with the pattern translated by the same vector.
    let placed = scene(
        5.0,
        &format!(
            "sphere {{ centre <5, 0, 0>  radius 1  material {{ colour {granite}  translate <5, 0, 0> }} }} }}"
        ),
    );
    let unplaced = scene(
        5.0,
        &format!("sphere {{ centre <5, 0, 0>  radius 1  material {{ colour {granite} }} }} }}"),
    );
    assert!(max_difference(&here, &moved) < 1e-3);
    assert!(max_difference(&here, &placed) < 1e-3);
    assert!(
        max_difference(&here, &unplaced) > 0.05,
        "the pattern's translate did something"
    );
}

#[test]
fn bumps_of_amount_zero_change_nothing_and_others_only_the_shading() {
    let _watchdog = crate::watchdog::start();
    let scene = |normal: &str| {
        render_src(&format!(
            "
camera {{ position <0, 0, 4>  look_at <0, 0, 0>  fov 40 }}
render {{ width 40  height 40  gamma linear }}
ambient white intensity 0.1
light {{ position <2, 3, 4> }}
sphere {{ radius 1  material {{ colour white  specular 0.5  {normal} }} }}
"
        ))
    };
    let plain = scene("");
    assert_eq!(
        max_difference(&plain, &scene("normal bumps { amount 0 }")),
        0.0
    );
    let bumpy = scene("normal bumps { amount 0.6  scale 4 }");
    assert!(max_difference(&plain, &bumpy) > 0.05, "bumps show");
    // The silhouette is the same: background where there was background.
    for (p, q) in plain.pixels.iter().zip(&bumpy.pixels) {
        assert_eq!(*p == [0.0; 3], *q == [0.0; 3]);
    }
    // Ripples around the centre of a sphere would run along its normals
    // (no tilt); around the point facing the camera they show.
    let rippled = scene("normal ripples { amount 0.5  scale 3  centre <0, 0, 3> }");
    assert!(max_difference(&plain, &rippled) > 0.05, "ripples show");
}

/// Bumps belong to their object: an object turned with its camera and
/// light looks exactly as it did unturned, bumps and all (before the slope
/// was turned with the object, its tilt kept the unturned axes). Through a
/// `let` placement (a shared shape), a CSG child with its own transform,
/// and the pattern's own `rotate`.
#[test]
fn bumps_turn_with_their_object() {
    let _watchdog = crate::watchdog::start();
    let scene = |camera: &str, light: &str, object: &str| {
        render_src(&format!(
            "
camera {{ {camera}  look_at <0, 0, 0>  fov 40 }}
render {{ width 48  height 48  gamma linear }}
ambient white intensity 0.1
light {{ position {light} }}
material m {{ colour white  specular 0.6  shininess 30
  normal ripples {{ amount 0.7  scale 3  centre <0.3, 0.4, 1>  rotate z 30 }} }}
let ball = sphere {{ radius 1  material m }}
{object}
"
        ))
    };
    let plain = scene("position <0, 0, 4>", "<2, 3, 4>", "ball {}");
    let flat = scene(
        "position <0, 0, 4>",
        "<2, 3, 4>",
        "sphere { radius 1  material { colour white  specular 0.6  shininess 30 } }",
    );
    assert!(max_difference(&plain, &flat) > 0.1, "the ripples show");
    // Half a turn about y: the camera and light go to the other side.
    let half = scene(
        "position <0, 0, -4>",
        "<-2, 3, -4>",
        "ball { rotate y 180 }",
    );
    // A quarter turn about x (y -> z, z -> -y), the camera's up turned too,
    // the ball a CSG child with its own transform.
    let quarter = scene(
        "position <0, -4, 0>  up <0, 0, 1>",
        "<2, -4, 3>",
        "difference { sphere { radius 1  material m  rotate x 90 }  sphere { radius 0.1  centre <9, 9, 9> } }",
    );
    for (name, turned) in [("half", &half), ("quarter", &quarter)] {
        let d = max_difference(&plain, turned);
        assert!(d < 2e-4, "{name} turn: differs by {d}");
    }
}

#[test]
fn pattern_mistakes_are_reported_with_help() {
    let _watchdog = crate::watchdog::start();
    let e = build_errors("sphere { material { colour marble { turbulance 3 } } }");
    assert!(
        e[0].contains("unknown parameter `turbulance` in `marble`")
            && e[0].contains("did you mean `turbulence`?"),
        "{e:?}"
    );
    let e = build_errors(
        "material stone { colour white }\nsphere { material { colour checker { a stone  b black } } }",
    );
    assert!(
        e[0].contains("expected a colour, found the material `stone`"),
        "{e:?}"
    );
    let e =
        build_errors("sphere { material { colour noise { colour_map { 0.6 red  0.2 blue } } } }");
    assert!(e[0].contains("a map's keys must go up"), "{e:?}");
    let e = build_errors("sphere { material { colour noise { colour_map { 0 red  1.5 blue } } } }");
    assert!(e[0].contains("keys are from 0 to 1"), "{e:?}");
    let e = build_errors("sphere { material { colour noise { colour_map { } } } }");
    assert!(e[0].contains("is empty"), "{e:?}");
    let e = build_errors("sphere { material { colour noise { colour_map { 0 red  1 } } } }");
    assert!(e[0].contains("ends with a key alone"), "{e:?}");
    let e = build_errors(
        "sphere { material { colour noise { a red  colour_map { 0 red  1 blue } } } }",
    );
    assert!(e[0].contains("both given"), "{e:?}");
    let e = build_errors("sphere { material { checker { scale 2 } } }");
    assert!(e[0].contains("needs its materials"), "{e:?}");
    let e = build_errors("sphere { material { colour white  normal bunps { amount 1 } } }");
    assert!(
        e[0].contains("unknown normal pattern `bunps`") && e[0].contains("did you mean `bumps`?"),
        "{e:?}"
    );
    let e = build_errors("sphere { material { colour checker { scale <1, 2, 3> } } }");
    assert!(e[0].contains("a checker's scale is"), "{e:?}");
    let e = build_errors("sphere { material { colour sectors { count 1 } } }");
    assert!(e[0].contains("from 2 to 360"), "{e:?}");
    let e =
        build_errors("material m { colour red }\nsphere { material { checker { a m  b black } } }");
    assert!(
        e[0].contains("expected a material, found a colour")
            && e[0].contains("colour checker { a white  b black }"),
        "{e:?}"
    );
    let e = build_errors("sphere { material { chequer { a white  b black } } }");
    assert!(
        e[0].contains("unknown pattern `chequer`") && e[0].contains("did you mean `checker`?"),
        "{e:?}"
    );
    let e = build_errors("sphere { material { checker { a nothing_here  b { colour red } } } }");
    assert!(e[0].contains("unknown material `nothing_here`"), "{e:?}");
}

/// The `material NAME` statements of a library file, each checked to have
/// a comment line right above it.
fn documented_materials(file: &str) -> Vec<String> {
    let text = std::fs::read_to_string(project_root().join(file)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut names = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        if let Some(rest) = line.strip_prefix("material ") {
            let name = rest.split_whitespace().next().unwrap().to_string();
            assert!(
                i > 0 && lines[i - 1].starts_with("//"),
                "{file}: `{name}` has no comment line above it"
            );
            names.push(name);
        }
    }
    names
}

#[test]
fn the_wood_and_stone_libraries_build_and_every_material_shows_a_pattern() {
    let _watchdog = crate::watchdog::start();
    for (file, at_least) in [("src/stdlib/woods.rt", 4), ("src/stdlib/stones.rt", 5)] {
        let names = documented_materials(file);
        assert!(names.len() >= at_least, "{file}: {names:?}");
        let path = project_root().join(file);
        for name in names {
            // Each material on a sphere that fills the view: more than one
            // colour (its pattern shows) and nothing missing.
            let film = render_src(&format!(
                "include \"{}\"
camera {{ position <0, 0, 3>  look_at <0, 0, 0>  fov 30 }}
render {{ width 24  height 24  gamma linear }}
ambient white intensity 1
sphere {{ radius 1  material {name} }}
",
                path.display()
            ));
            let centre = film.get(12, 12);
            let differ = film
                .pixels
                .iter()
                .filter(|p| (0..3).any(|i| (p[i] - centre[i]).abs() > 0.01))
                .count();
            assert!(differ > 20, "{file}: `{name}` looks uniform");
        }
    }
}

#[test]
fn a_rotated_pattern_is_the_pattern_along_the_rotated_axis() {
    let _watchdog = crate::watchdog::start();
    // Read at M⁻¹p, the value is frac(p·(M a)): rotating y by 90° takes
    // the axis x to −z.
    let turned =
        top_down("{ colour gradient { axis <0.25, 0, 0>  rotate y 90  a black  b white } }");
    let along = top_down("{ colour gradient { axis <0, 0, -0.25>  a black  b white } }");
    let plain = top_down("{ colour gradient { axis <0.25, 0, 0>  a black  b white } }");
    // Away from the jumps (where rounding may land on either side).
    let mut same = 0;
    for (p, q) in turned.pixels.iter().zip(&along.pixels) {
        if q[0] > 0.01 && q[0] < 0.99 {
            assert!((p[0] - q[0]).abs() < 1e-5, "{p:?} vs {q:?}");
            same += 1;
        }
    }
    assert!(same > 1000, "{same}");
    assert!(max_difference(&turned, &plain) > 0.5);
}

#[test]
fn an_image_with_a_map_is_its_luminance() {
    let _watchdog = crate::watchdog::start();
    let film = render_quad_image("image \"quad.png\" { a black  b rgb(1, 0, 1) }");
    // Near each quadrant's centre (bilinear blending adds at most a few
    // percent of its neighbours): red, green, blue, white → their luminance
    // as the map's value: rgb(y, 0, y).
    for (a, b, y) in [
        (10, 10, 0.2126),
        (29, 10, 0.7152),
        (10, 29, 0.0722),
        (29, 29, 1.0),
    ] {
        let c = film.get(a, b);
        assert!(
            (c[0] as f64 - y).abs() < 0.04 && c[1] == 0.0,
            "({a}, {b}): {c:?} vs {y}"
        );
        assert_eq!(c[0], c[2]);
    }
}
