//! The evaluation stage end to end: loops, conditions, functions, object
//! values, built-ins, `-D`, `clock`/`frame` and the limits. Most checks
//! hold by construction: two ways of writing one scene must give the same
//! picture or the same objects.

use super::lang::{Files, try_build};
use super::support::{render_src, scene_file};
use raytrace::eval::{Limits, Options};
use raytrace::geometry::DVec3;
use raytrace::scene::{self, Scene};

fn build(src: &str) -> Scene {
    let f = Files::new();
    let p = f.write("scene.rt", src);
    try_build(&p).unwrap_or_else(|e| panic!("scene did not build: {e:#?}"))
}

fn build_with(src: &str, options: &Options) -> Result<Scene, Vec<(String, Option<String>)>> {
    let (_dir, path) = scene_file(src);
    let program = raytrace::lang::load(&path).expect("parses");
    scene::build_with(&program, options)
        .map(|(s, _)| s)
        .map_err(|p| {
            p.problems()
                .iter()
                .map(|p| {
                    (
                        p.message().to_string(),
                        miette::Diagnostic::help(p).map(|h| h.to_string()),
                    )
                })
                .collect()
        })
}

/// Messages and helps of a scene that must fail.
fn problems(src: &str) -> Vec<(String, Option<String>)> {
    match build_with(src, &Options::default()) {
        Ok(_) => panic!("the scene built"),
        Err(e) => e,
    }
}

fn messages(src: &str) -> Vec<String> {
    problems(src).into_iter().map(|(m, _)| m).collect()
}

fn centres(s: &Scene) -> Vec<DVec3> {
    s.objects.iter().map(|o| o.bounds().centre()).collect()
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).abs().max_element() < 1e-9
}

const STAGE: &str = "camera { position <0, 4, 12>  look_at <0, 1, 0> }\n\
    render { width 48  height 36 }\n\
    light { position <5, 10, 5> }\n\
    plane { normal <0, 1, 0> }\n";

#[test]
fn a_loop_renders_byte_identical_to_the_scene_written_out() {
    let _watchdog = crate::watchdog::start();
    let looped = format!(
        "{STAGE}for i in 0..4 {{ sphere {{ radius 0.4  centre <i * 1.5 - 2, 0.5, 0> }} }}\n\
         for i in 0..=2 step 2 {{ box {{ min <-0.3, 0, -0.3>  max <0.3, 0.6, 0.3>  translate <i, 0, 2> }} }}"
    );
    let written = format!(
        "{STAGE}sphere {{ radius 0.4  centre <-2, 0.5, 0> }}\n\
         sphere {{ radius 0.4  centre <-0.5, 0.5, 0> }}\n\
         sphere {{ radius 0.4  centre <1, 0.5, 0> }}\n\
         sphere {{ radius 0.4  centre <2.5, 0.5, 0> }}\n\
         box {{ min <-0.3, 0, -0.3>  max <0.3, 0.6, 0.3>  translate <0, 0, 2> }}\n\
         box {{ min <-0.3, 0, -0.3>  max <0.3, 0.6, 0.3>  translate <2, 0, 2> }}"
    );
    let (a, b) = (render_src(&looped), render_src(&written));
    assert_eq!(a.pixels, b.pixels);
    // And the loop made something: not an empty stage twice.
    let empty = render_src(STAGE);
    assert_ne!(a.pixels, empty.pixels);
}

#[test]
fn a_function_with_defaults_equals_the_call_spelled_out() {
    let _watchdog = crate::watchdog::start();
    let f = "fn post(h, r = 0.25, top = 1.3) {\n\
             cylinder { radius r  height h  translate <0, h / 2, 0> }\n\
             sphere { radius r * top  centre <0, h, 0> }\n}\n";
    let short = format!("{STAGE}{f}post(2) {{ translate <-1, 0, 0> }}\npost(1, top: 2)");
    let long = format!(
        "{STAGE}{f}post(2, 0.25, 1.3) {{ translate <-1, 0, 0> }}\npost(h: 1, r: 0.25, top: 2)"
    );
    assert_eq!(render_src(&short).pixels, render_src(&long).pixels);
    let s = build(&format!("{f}post(2)"));
    assert_eq!(s.objects.len(), 2);
    assert!(close(centres(&s)[1], DVec3::new(0.0, 2.0, 0.0)));
}

#[test]
fn built_ins_give_the_textbook_values() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "let v = normalize(<3, 0, 4>)\n\
         let c = cross(<1, 0, 0>, <0, 1, 0>)\n\
         let xs = [1, 2, 3]\n\
         sphere { radius length(v) * len(xs) + dot(v, <0, 0, 5>) - 4  centre c * atan2(1, 1) / pi * 4 }\n\
         fn bell(t) = exp(-t * t)\n\
         sphere { radius bell(0) * 3 }\n\
         sphere { radius clamp(7, 0, 2) + lerp(0, 10, 0.1) + floor(0.7) + ceil(0.2) + round(0.4) + log(exp(1)) - 2 }",
    );
    let b = s.objects[0].bounds();
    // radius 1·3 + 4 − 4 = 3, centre <0, 0, 1>.
    assert!(close(b.centre(), DVec3::new(0.0, 0.0, 1.0)), "{b:?}");
    assert!((b.max.x - 3.0).abs() < 1e-9, "{b:?}");
    assert!((s.objects[1].bounds().max.x - 3.0).abs() < 1e-9);
    let b = s.objects[2].bounds();
    // 2 + 1 + 0 + 1 + 0 + 1 − 2 = 3
    assert!((b.max.x - 3.0).abs() < 1e-9, "{b:?}");
}

#[test]
fn random_is_pure_and_in_the_unit_interval() {
    let _watchdog = crate::watchdog::start();
    use raytrace::eval::expr::random;
    let a: Vec<f64> = (0..1000).map(|i| random(7.0, i as f64)).collect();
    let b: Vec<f64> = (0..1000).map(|i| random(7.0, i as f64)).collect();
    assert_eq!(a, b);
    assert!(a.iter().all(|x| (0.0..1.0).contains(x)));
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    assert!((mean - 0.5).abs() < 0.05, "{mean}");
    assert_ne!(random(7.0, 1.0), random(8.0, 1.0));
    // Same number from the language.
    let s = build("sphere { radius 1 + random(7, 3) }");
    assert!((s.objects[0].bounds().max.x - (1.0 + random(7.0, 3.0))).abs() < 1e-12);
}

#[test]
fn conditions_choose_and_ranges_count_right() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "for i in 0..10 { if i % 3 == 0 and not (i == 6) { sphere { centre <i, 0, 0> } } \
         else if i == 7 or i > 8 { sphere { centre <i, 5, 0> } } }",
    );
    let c = centres(&s);
    let want = [(0.0, 0.0), (3.0, 0.0), (7.0, 5.0), (9.0, 0.0), (9.0, 5.0)];
    let got: Vec<(f64, f64)> = c.iter().map(|c| (c.x, c.y)).collect();
    // 9 % 3 == 0 takes the first branch only.
    assert_eq!(got, [want[0], want[1], want[2], want[3]], "{got:?}");
    assert_eq!(build("for i in 5..5 { sphere { } }").objects.len(), 0);
    assert_eq!(
        build("for i in 0..=4 step 2 { sphere { } }").objects.len(),
        3
    );
    assert_eq!(
        build("for i in 3..0 step -1 { sphere { } }").objects.len(),
        3
    );
    assert_eq!(
        build("for i in 0..1 step 0.25 { sphere { } }")
            .objects
            .len(),
        4
    );
    let s = build("for p in [<1, 0, 0>, <0, 2, 0>] { sphere { centre p } }");
    assert!(close(centres(&s)[1], DVec3::new(0.0, 2.0, 0.0)));
}

#[test]
fn an_object_value_is_placed_with_its_own_transforms_and_material() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "material gold { colour gold }\n\
         let ball = sphere { radius 0.5 }\n\
         let pair = group { ball { translate <-1, 0, 0> }  ball { translate <1, 0, 0> } }\n\
         pair { translate <0, 3, 0>  material gold }\n\
         ball",
    );
    let c = centres(&s);
    assert_eq!(c.len(), 3);
    assert!(close(c[0], DVec3::new(-1.0, 3.0, 0.0)), "{c:?}");
    assert!(close(c[1], DVec3::new(1.0, 3.0, 0.0)), "{c:?}");
    assert!(close(c[2], DVec3::ZERO), "{c:?}");
    // The placement's material reaches the parts that name none.
    let ray = raytrace::geometry::Ray::new(DVec3::new(-1.0, 3.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
    let hit = s.objects[0]
        .intersect(&ray, 1e-9, f64::INFINITY)
        .expect("hits");
    assert_eq!(hit.material, 1);
    let hit = s.objects[2]
        .intersect(
            &raytrace::geometry::Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0)),
            1e-9,
            f64::INFINITY,
        )
        .expect("hits");
    assert_eq!(hit.material, 0);
}

#[test]
fn materials_and_patterns_are_values_too() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "let shiny = material { colour red  reflect 0.5 }\n\
         let tiles = checker { a white  b black }\n\
         sphere { material shiny }\n\
         sphere { material { colour tiles } }",
    );
    assert_eq!(s.materials.len(), 3);
    assert_eq!(s.materials[1].reflect, 0.5);
    assert!(matches!(
        s.materials[2].texture,
        raytrace::scene::Texture::Pattern(_)
    ));
}

#[test]
fn recursion_builds_and_stops_at_its_base_case() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "fn tower(n) {\n\
           sphere { radius 0.3  centre <0, n, 0> }\n\
           if n > 0 { tower(n - 1) }\n\
         }\n\
         tower(5)",
    );
    assert_eq!(s.objects.len(), 6);
    let e = messages("fn f(n) { f(n + 1) }\nf(0)");
    assert_eq!(e, ["function calls nest more than 100 deep"]);
}

#[test]
fn minus_d_changes_exactly_the_named_constant() {
    let _watchdog = crate::watchdog::start();
    let src = "let R = 1\nlet S = 2\nsphere { radius R }\nsphere { radius S  centre <5, 0, 0> }";
    let plain = build_with(src, &Options::default()).unwrap();
    let options = Options {
        defines: vec![("R".into(), raytrace::eval::define_value("3").unwrap())],
        ..Options::default()
    };
    let moved = build_with(src, &options).unwrap();
    let (a, b) = (plain.objects[0].bounds(), moved.objects[0].bounds());
    assert!((a.max.x - 1.0).abs() < 1e-12 && (b.max.x - 3.0).abs() < 1e-12);
    // The other constant and object are untouched, to the bit.
    assert_eq!(plain.objects[1].bounds(), moved.objects[1].bounds());
    let bad = Options {
        defines: vec![("Q".into(), raytrace::eval::define_value("3").unwrap())],
        ..Options::default()
    };
    let e = build_with(src, &bad).unwrap_err();
    assert_eq!(e[0].0, "`-D Q`: the scene has no top-level `let Q`");
    assert!(raytrace::eval::define_value("<1, 2").is_err());
}

#[test]
fn clock_and_frame_are_read_only_numbers() {
    let _watchdog = crate::watchdog::start();
    let s = build("sphere { radius 1 + clock + frame }");
    assert!((s.objects[0].bounds().max.x - 1.0).abs() < 1e-12);
    let options = Options {
        clock: 0.5,
        frame: 2.0,
        ..Options::default()
    };
    let s = build_with("sphere { radius 1 + clock + frame }", &options).unwrap();
    assert!((s.objects[0].bounds().max.x - 3.5).abs() < 1e-12);
    assert_eq!(messages("let clock = 1"), ["`clock` is a built-in name"]);
}

#[test]
fn errors_in_a_loop_or_call_say_which() {
    let _watchdog = crate::watchdog::start();
    let e = problems("for i in 0..10 {\n  sphere { radius 3 - i }\n}");
    assert_eq!(e.len(), 1, "one report, not one per iteration: {e:?}");
    assert_eq!(e[0].0, "this must be greater than 0");
    let help = e[0].1.as_deref().unwrap();
    assert!(
        help.contains("in iteration i = 3 of the loop at ") && help.ends_with("scene.rt:1:1"),
        "{help}"
    );
    let e = problems("fn pillar(h) {\n  sphere { radius h - 2 }\n}\npillar(1.5)");
    let help = e[0].1.as_deref().unwrap();
    assert!(
        help.contains("in `pillar` called from ") && help.ends_with("scene.rt:4:1 with h = 1.5"),
        "{help}"
    );
    let e = problems("fn f(a) = 1 / a\nfor k in 0..3 { sphere { radius f(k) } }");
    assert_eq!(e[0].0, "division by zero");
    let help = e[0].1.as_deref().unwrap();
    assert!(
        help.contains("in `f` called from") && help.contains("in iteration k = 0"),
        "{help}"
    );
    // Nested loops, innermost first: a mistake the builder finds, and one
    // the evaluator finds (an iteration's trace is made only when needed).
    let e = problems("for i in 0..3 {\n  for j in 0..3 {\n    sphere { radius 3 - i - j }\n  }\n}");
    assert_eq!(e.len(), 1, "{e:?}");
    nested_trail(&e[0], 2, 1);
    let e =
        problems("for i in 1..3 {\n  for j in 0..3 {\n    sphere { radius 1 / (i - j) }\n  }\n}");
    assert_eq!(e[0].0, "division by zero");
    nested_trail(&e[0], 1, 1);
}

/// The help of a mistake in iteration (i, j) of two nested loops at lines
/// 1 and 2: the inner iteration's line, then the outer one's.
fn nested_trail(e: &(String, Option<String>), j: u32, i: u32) {
    let help = e.1.as_deref().unwrap_or_default();
    let lines: Vec<&str> = help.lines().collect();
    assert_eq!(lines.len(), 2, "{help}");
    assert!(
        lines[0].starts_with(&format!("in iteration j = {j} of the loop at "))
            && lines[0].ends_with("scene.rt:2:3"),
        "{help}"
    );
    assert!(
        lines[1].starts_with(&format!("in iteration i = {i} of the loop at "))
            && lines[1].ends_with("scene.rt:1:1"),
        "{help}"
    );
}

#[test]
fn kind_errors_and_suggestions() {
    let _watchdog = crate::watchdog::start();
    assert_eq!(
        messages("let xs = [1, 2]\nsphere { radius xs[2] }"),
        ["index 2 is out of range"]
    );
    assert_eq!(
        messages("let r = 2\nsphere { radius r(1) }"),
        ["`r` is a number, not a function"]
    );
    assert_eq!(messages("for i in 3 { }"), ["cannot loop over a number"]);
    assert_eq!(
        messages("if 1 { }"),
        ["expected a condition, found a number"]
    );
    assert_eq!(
        messages("let b = sphere { }\nsphere { radius b }"),
        ["expected a number, found an object (`sphere`)"]
    );
    let e = problems("fn bell(t) = exp(-t * t)\nsphere { radius bel(1) }");
    assert_eq!(e[0].1.as_deref(), Some("did you mean `bell`?"));
    let e = problems("fn post(height) { sphere { } }\npost(heigth: 2)");
    assert_eq!(e[0].0, "`post` has no parameter `heigth`");
    assert_eq!(e[0].1.as_deref(), Some("did you mean `height`?"));
    let e = problems("for count in 0..2 { sphere { radius cuont } }");
    assert_eq!(
        e[0].1.as_deref().map(|h| h.lines().next().unwrap()),
        Some("did you mean `count`?")
    );
    assert_eq!(messages("fn f(a) { }\nf()"), ["`f` needs `a`"]);
    assert_eq!(
        messages("fn f(a) { }\nf(1, 2)"),
        ["`f` takes 1 argument, not 2"]
    );
}

#[test]
fn runaway_programs_are_refused_with_the_limit_named() {
    let _watchdog = crate::watchdog::start();
    let e = problems("for i in 0..100000000 { }");
    assert!(e[0].0.contains("the limit is 1000000"), "{e:?}");
    assert!(e[0].1.as_deref().unwrap().contains("--max-iterations"));
    let small = Options {
        limits: Limits {
            objects: 50,
            ..Limits::default()
        },
        ..Options::default()
    };
    let e = build_with("for i in 0..1000 { sphere { } }", &small).unwrap_err();
    assert_eq!(e.len(), 1);
    assert!(e[0].0.contains("more than 50 objects"), "{e:?}");
    assert!(e[0].1.as_deref().unwrap().contains("--max-objects"));
    let steps = Options {
        limits: Limits {
            steps: 10_000,
            ..Limits::default()
        },
        ..Options::default()
    };
    let e = build_with(
        "for i in 0..1000 { for j in 0..1000 { let k = i * j } }",
        &steps,
    )
    .unwrap_err();
    assert!(e[0].0.contains("more than 10000 evaluation steps"), "{e:?}");
    assert!(e[0].1.as_deref().unwrap().contains("--max-steps"));
}

#[test]
fn block_scoping_keeps_loop_lets_local() {
    let _watchdog = crate::watchdog::start();
    let s =
        build("let r = 1\nfor i in 0..2 { let r = 2  sphere { radius r } }\nsphere { radius r }");
    let radii: Vec<f64> = s
        .objects
        .iter()
        .map(|o| o.bounds().max.x - o.bounds().centre().x)
        .collect();
    assert_eq!(radii, [2.0, 2.0, 1.0]);
    assert_eq!(
        messages("for i in 0..2 { }\nsphere { radius i }"),
        ["unknown name `i`"]
    );
}

#[test]
fn implicit_equations_see_loop_variables_and_parameters() {
    let _watchdog = crate::watchdog::start();
    let s = build(
        "fn ball(R) { implicit \"x^2 + y^2 + z^2 - R^2\" { bounded_by <-3, -3, -3> <3, 3, 3> } }\n\
         ball(2)",
    );
    let ray = raytrace::geometry::Ray::new(DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 0.0, -1.0));
    let hit = s.objects[0]
        .intersect(&ray, 1e-9, f64::INFINITY)
        .expect("hits");
    assert!((hit.t - 3.0).abs() < 1e-6, "{}", hit.t);
}

#[test]
fn placements_share_one_built_object_and_render_as_copies_would() {
    let _watchdog = crate::watchdog::start();
    let shared = format!(
        "{STAGE}let ball = sphere {{ radius 0.5 }}\n\
         for i in 0..3 {{ ball {{ translate <i - 1, 0.5, 0> }} }}"
    );
    let copies =
        format!("{STAGE}for i in 0..3 {{ sphere {{ radius 0.5  translate <i - 1, 0.5, 0> }} }}");
    assert_eq!(render_src(&shared).pixels, render_src(&copies).pixels);
    let s = build("let ball = sphere { radius 0.5 }\nball { translate <1, 0, 0> }\nball");
    assert!(
        s.objects
            .iter()
            .all(|o| format!("{o:?}").contains("Shared"))
    );
    // Inside CSG the placement is a solid like any other.
    let s = build("let ball = sphere { }\ndifference { box { }  ball { translate <1, 1, 1> } }");
    assert_eq!(s.objects.len(), 1);
}

#[test]
fn loops_run_their_counted_values_and_stop_at_the_limit() {
    let _watchdog = crate::watchdog::start();
    let xs = |src: &str| -> Vec<f64> { centres(&build(src)).iter().map(|c| c.x).collect() };
    let ball = "{ sphere { radius 0.1  centre <i, 0, 0> } }";
    // Each value a + k·s, up to b (included with `..=`), whole steps only.
    for (range, want) in [
        ("0..4", vec![0.0, 1.0, 2.0, 3.0]),
        ("0..=4", vec![0.0, 1.0, 2.0, 3.0, 4.0]),
        ("0..4 step 2", vec![0.0, 2.0]),
        ("0..5 step 2", vec![0.0, 2.0, 4.0]),
        ("0..=4 step 2", vec![0.0, 2.0, 4.0]),
        ("1..2 step 0.25", vec![1.0, 1.25, 1.5, 1.75]),
        ("0..0.5", vec![0.0]),
        ("0..=0", vec![0.0]),
        ("0..0", vec![]),
        ("4..0", vec![]),
        ("0..-2 step -1", vec![0.0, -1.0]),
        ("0..=-2 step -1", vec![0.0, -1.0, -2.0]),
    ] {
        assert_eq!(xs(&format!("for i in {range} {ball}")), want, "{range}");
    }
    assert_eq!(
        xs(&format!("for i in [3, -1, 0.5] {ball}")),
        [3.0, -1.0, 0.5]
    );
    // `x`, `y` and `z` are not constants: they may name a loop's variable.
    assert_eq!(build("for x in 0..2 { sphere { } }").objects.len(), 2);
    // The iteration limit: a loop of exactly the limit runs.
    let five = Options {
        limits: Limits {
            iterations: 5,
            ..Limits::default()
        },
        ..Options::default()
    };
    let count = |src: &str| build_with(src, &five).map(|s| s.objects.len());
    assert_eq!(count("for i in 0..5 { sphere { } }"), Ok(5));
    assert_eq!(count("for i in [1, 2, 3, 4, 5] { sphere { } }"), Ok(5));
    let refused = |src: &str| {
        let e = count(src).unwrap_err();
        assert_eq!(e.len(), 1, "{e:?}");
        e[0].0.clone()
    };
    assert_eq!(
        refused("for i in 0..6 { sphere { } }"),
        "this loop would run 6 times; the limit is 5"
    );
    assert_eq!(
        refused("for i in [1, 2, 3, 4, 5, 6] { sphere { } }"),
        "this loop would run 6 times; the limit is 5"
    );
    // Mistakes in the loop itself.
    assert_eq!(
        messages("for i in 0..3 step 0 { }"),
        ["a loop's step cannot be 0"]
    );
    assert_eq!(
        messages("for i in 0..(1 < 2) { }"),
        ["a range needs numbers, found a condition (true or false)"]
    );
    assert_eq!(
        messages("for i in (1 < 2)..3 step (1 < 2) { }"),
        [
            "a range needs numbers, found a condition (true or false)",
            "a range needs numbers, found a condition (true or false)"
        ]
    );
    assert_eq!(messages("for i in 3 { }"), ["cannot loop over a number"]);
    assert_eq!(messages("for pi in 0..3 { }"), ["`pi` is a built-in name"]);
    // A mistake the evaluator finds in the body: one report, in the
    // iteration that made it.
    let e = problems("for i in 0..6 {\n  let k = 1 / (i - 3)\n}");
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].0, "division by zero");
    assert!(
        e[0].1
            .as_deref()
            .unwrap()
            .contains("in iteration i = 3 of the loop at "),
        "{e:?}"
    );
}

#[test]
fn calls_bind_arguments_by_place_name_and_default() {
    let _watchdog = crate::watchdog::start();
    // Each parameter a digit of the result: a wrong binding shows.
    let f = "fn f(a, b = 2, c = a + b) = a * 100 + b * 10 + c\n";
    let x = |call: &str| {
        let s = build(&format!(
            "{f}sphere {{ radius 0.1  centre <{call}, 0, 0> }}"
        ));
        centres(&s)[0].x
    };
    assert_eq!(x("f(1)"), 123.0);
    assert_eq!(x("f(1, 5)"), 156.0);
    assert_eq!(x("f(1, 5, 7)"), 157.0);
    assert_eq!(x("f(1, c: 9)"), 129.0);
    assert_eq!(x("f(b: 3, a: 2)"), 235.0);
    assert_eq!(x("f(2, b: 3)"), 235.0);
    // Mistakes in a call.
    assert_eq!(
        messages(&format!("{f}let v = f(1, 2, 3, 4)")),
        ["`f` takes 3 arguments, not 4"]
    );
    assert_eq!(
        messages(&format!("{f}let v = f(1, zzzz: 2)")),
        ["`f` has no parameter `zzzz`"]
    );
    let e = problems(&format!("{f}let v = f(1, zzzz: 2)"));
    assert_eq!(e[0].1.as_deref(), Some("its parameters are `a`, `b`, `c`"));
    assert_eq!(
        messages(&format!("{f}let v = f(1, a: 2)")),
        ["`a` is given twice"]
    );
    assert_eq!(
        messages(&format!("{f}let v = f(b: 1, b: 2, a: 1)")),
        ["`b` is given twice"]
    );
    assert_eq!(messages(&format!("{f}let v = f(b: 1)")), ["`f` needs `a`"]);
    // A mistake in an argument is the only report.
    assert_eq!(
        messages(&format!("{f}let v = f(1 / 0)")),
        ["division by zero"]
    );
    assert_eq!(
        messages(&format!("{f}let v = f(1, c: 1 / 0)")),
        ["division by zero"]
    );
    // An argument naming a constant whose definition failed (reported
    // there) stops the call quietly: no "needs" for the parameter.
    assert_eq!(
        messages(&format!("{f}let bad = 1 / 0\nlet v = f(bad)")),
        ["division by zero"]
    );
    assert_eq!(
        messages("fn g() { sphere { } }\nlet v = g()"),
        ["`g` makes objects, not a value"]
    );
    // The depth limit: calls exactly as deep as it run, one more is
    // refused, and the depth goes back down after each call.
    let three = Options {
        limits: Limits {
            depth: 3,
            ..Limits::default()
        },
        ..Options::default()
    };
    let down = "fn down(n) {\n  sphere { }\n  if n > 1 { down(n - 1) }\n}\n\
                fn v(n) = n\n";
    let count =
        |calls: &str| build_with(&format!("{down}{calls}"), &three).map(|s| s.objects.len());
    assert_eq!(count("down(3)"), Ok(3));
    assert_eq!(count("down(3)\ndown(3)\ndown(2)"), Ok(8));
    assert_eq!(
        count("sphere { radius v(v(v(v(1)))) }\ndown(3)"),
        Ok(4),
        "arguments are worked out before the call is entered"
    );
    let e = count("down(4)").unwrap_err();
    assert_eq!(e[0].0, "function calls nest more than 3 deep");
}
