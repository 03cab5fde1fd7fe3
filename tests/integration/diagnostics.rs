//! What a person sees when a scene is wrong: reports rendered at a fixed
//! width without colour and compared with insta snapshots. The first nine
//! are POV-Ray's classic mistakes (/work/shared/peers/povray/errors) written
//! as `.rt`; each comment quotes what POV-Ray printed, and each of our
//! reports must say more (a column, the opening brace, a suggestion, a
//! count).

use super::lang::Files;
use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme};
use raytrace::{lang, scene};

fn render(d: &dyn Diagnostic) -> String {
    let mut out = String::new();
    GraphicalReportHandler::new_themed(GraphicalTheme::unicode_nocolor())
        .with_width(100)
        .render_report(&mut out, d)
        .expect("rendering into a String cannot fail");
    out
}

/// Writes the files (the first is the scene), loads and builds, and renders
/// the report with the temp folder's path removed.
fn report(files: &[(&str, &str)]) -> String {
    let f = Files::new();
    for (name, text) in files {
        f.write(name, text);
    }
    let root = f.dir.path().join(files[0].0);
    let text = match lang::load(&root) {
        Err(p) => render(&p),
        Ok(program) => match scene::build(&program) {
            Err(p) => render(&p),
            Ok(_) => panic!("the scene built without errors"),
        },
    };
    text.replace(&format!("{}/", f.dir.path().display()), "")
}

// POV-Ray: File 'error_brace.pov' line 8: Parse Error: No matching } in
// 'sphere', plane found instead
#[test]
fn pov_missing_brace_before_the_next_object() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_brace.rt",
        r#"// malformed on purpose: the sphere's closing brace is missing.
camera { position <0, 2, 8>  look_at <0, 1, 0> }
light { position <5, 10, 5> }
sphere { centre <0, 1, 0>  radius 1
  material { colour rgb(1, 0, 0) }

plane { normal <0, 1, 0>  material { colour rgb(0.8, 0.8, 0.8) } }
"#,
    )]));
}

// POV-Ray: File 'error_eof.pov' line 6: Parse Error: No matching } in
// 'sphere', End of File found instead
#[test]
fn pov_unclosed_at_end_of_file() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_eof.rt",
        r#"// malformed on purpose: the last object is never closed.
camera { position <0, 2, 8>  look_at <0, 1, 0> }
light { position <5, 10, 5> }
sphere { centre <0, 1, 0>  radius 1
  material { colour rgb(1, 0, 0) }
"#,
    )]));
}

// POV-Ray: File 'error_ident.pov' line 6: Parse Error: Expected 'numeric
// expression', undeclared identifier 'Radus' found instead
#[test]
fn pov_misspelt_identifier() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_ident.rt",
        r#"// malformed on purpose: `Radius` is declared, `Radus` is used.
let Radius = 1
camera { position <0, 2, 8>  look_at <0, 1, 0> }
sphere { centre <0, 1, 0>  radius Radus
  material { colour rgb(1, 0, 0) }
}
"#,
    )]));
}

// POV-Ray: File 'bad_include.inc' line 3: Parse Error: Expected '>', ;
// found instead  (and no word on which file included it)
#[test]
fn pov_error_inside_an_included_file() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[
        (
            "error_in_include.rt",
            r#"// malformed on purpose: the error is inside an included file.
render { gamma srgb }
include "bad_include.rt"
camera { position <0, 2, 8>  look_at <0, 1, 0> }
"#,
        ),
        (
            "bad_include.rt",
            r#"// included by error_in_include.rt; line 3 has an unclosed vector.
let A = 1
let B = <1, 2, 3
let C = 2
"#,
        ),
    ]));
}

// POV-Ray: File 'error_include.pov' line 3: Possible Parse Error: Cannot
// find file 'no_such_file.inc', even after trying to append file type
// extension. ... Parse Error: Cannot open include file no_such_file.inc.
#[test]
fn pov_missing_include_file() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_include.rt",
        r#"// malformed on purpose: the included file does not exist.
include "no_such_file.rt"
camera { position <0, 2, 8>  look_at <0, 1, 0> }
"#,
    )]));
}

// POV-Ray: File 'error_keyword.pov' line 6: Parse Error: No matching } in
// 'sphere', undeclared identifier 'pigmnet' found instead
#[test]
fn pov_misspelt_keyword() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_keyword.rt",
        r#"// malformed on purpose: misspelt keyword `materail`.
camera { position <0, 2, 8>  look_at <0, 1, 0> }
light { position <5, 10, 5> }
sphere { centre <0, 1, 0>  radius 1
  materail { colour rgb(1, 0, 0) }
}
"#,
    )]));
}

// POV-Ray: File 'error_number.pov' line 5: Parse Error: Unexpected
// additional '.' in floating-point number
#[test]
fn pov_bad_number() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_number.rt",
        r#"// malformed on purpose: a bad number `1.2.3` in a vector.
camera { position <0, 2, 8>  look_at <0, 1, 0> }
sphere { centre <0, 1.2.3, 0>  radius 1
  material { colour rgb(1, 0, 0) }
}
"#,
    )]));
}

// POV-Ray (a quartic `poly` with 34 of its 35 coefficients): File
// 'error_poly.pov' line 10: Parse Error: Expected 'numeric expression', >
// found instead. Our analogue is `matrix` with 11 of its 12 numbers.
#[test]
fn pov_list_with_the_wrong_count() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_poly.rt",
        r#"// malformed on purpose: a matrix needs 12 numbers; this one has 11.
camera { position <0, 2, 8>  look_at <0, 1, 0> }
sphere {
  matrix [1, 0, 0, 0,
          0, 1, 0, 0,
          0, 0, 1]
}
"#,
    )]));
}

// POV-Ray accepted `sphere { <0, 1> 1 ... }` silently ("POV-Ray finished",
// exit status 0): the 2-vector was promoted and the missing comma ignored.
// Ours: two errors, together.
#[test]
fn pov_two_vector_and_missing_value() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "error_vector.rt",
        r#"// malformed on purpose: a 2-component centre, and a radius without its value.
camera { position <0, 2, 8>  look_at <0, 1, 0> }
sphere { centre <0, 1>  radius
  material { colour rgb(1, 0, 0) }
}
"#,
    )]));
}

#[test]
fn several_errors_in_one_file_are_reported_together() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        r#"camera { position <0, 2, 8>  look_at <0, 2, 8> }
render { width 640  height 0 }
sphere { radius 1  material shiny }
material shiny { reflect 0.5 }
box { scale 0 }
"#,
    )]));
}

#[test]
fn unknown_parameter_with_a_suggestion() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "light { positon <5, 10, 5>  intensity 0.8 }\n",
    )]));
}

#[test]
fn unknown_statement_with_a_suggestion() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[("scene.rt", "sphre { radius 1 }\n")]));
}

#[test]
fn duplicate_parameter() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "sphere {\n  radius 1\n  centre <0, 1, 0>\n  radius 2\n}\n",
    )]));
}

#[test]
fn wrong_value_kind() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "sphere { radius red }\nlight { position <0, 5, 0>  colour <1, 1, 1> }\n",
    )]));
}

#[test]
fn syntax_error_in_our_words() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "sphere { centre <0, 1, 0>  radius 1 + }\n",
    )]));
}

#[test]
fn mistake_two_includes_deep_shows_the_whole_chain() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[
        ("scene.rt", "let R = 1\ninclude \"parts/objects.rt\"\n"),
        (
            "parts/objects.rt",
            "// the objects\ninclude \"shapes/balls.rt\"\n"
        ),
        (
            "parts/shapes/balls.rt",
            "sphere { radius R }\nsphere { radius R * 2  material { colour rgb(1, 0.5) } }\n",
        ),
    ]));
}

// POV-Ray separates a sphere's centre and radius with a comma; a habit
// worth a specific hint.
#[test]
fn stray_comma_between_parameters() {
    let _watchdog = crate::watchdog::start();
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "sphere { centre <0, 1, 0>, radius 1 }\n",
    )]));
}

// ---- the evaluator: loops, calls, values ----

#[test]
fn mistake_inside_a_loop_names_the_iteration() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "let n = 6\nfor i in 0..n {\n  sphere { radius 3 - i  centre <i, 0, 0> }\n}\n",
    )]));
}

#[test]
fn mistake_inside_a_function_names_the_call_and_its_arguments() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "fn pillar(h, r = 0.3) {\n  cylinder { radius r  height h - 1.5 }\n}\n\nfor x in 0..3 {\n  pillar(1 + x * 0.5, r: 0.2) { translate <x, 0, 0> }\n}\n",
    )]));
}

#[test]
fn misspelt_function_and_parameter() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "fn bell(t) = exp(-t * t)\nfn post(height) { sphere { radius 0.2  centre <0, height, 0> } }\nsphere { radius bel(0.5) }\npost(heigth: 2)\n",
    )]));
}

#[test]
fn index_out_of_range_gives_the_length() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "let xs = [0.5, 1, 1.5]\nfor i in 0..=3 { sphere { radius xs[i] } }\n",
    )]));
}

#[test]
fn kinds_of_values_in_the_wrong_place() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "let ball = sphere { radius 1 }\nlet r = 2\nsphere { radius ball }\nsphere { radius r(2) }\nif r { sphere { } }\n",
    )]));
}

#[test]
fn runaway_recursion_is_refused() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "fn grow(n) {\n  sphere { centre <0, n, 0> }\n  grow(n + 1)\n}\ngrow(0)\n",
    )]));
}

#[test]
fn a_loop_too_long_is_refused() {
    insta::assert_snapshot!(report(&[(
        "scene.rt",
        "for i in 0..1e9 { sphere { centre <i, 0, 0> } }\n",
    )]));
}
