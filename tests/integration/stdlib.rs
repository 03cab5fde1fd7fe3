//! The standard library (`include "std/…"`): every file parses, every
//! material in it renders, the library comes before a user's `std/` folder,
//! a misspelt name gets a suggestion, and its bytes count in the include
//! budgets like any include's.

use super::lang::Files;
use raytrace::stdlib::FILES;

/// The materials a std file declares (each `material NAME` opening a line).
fn materials(text: &str) -> Vec<&str> {
    text.lines()
        .filter_map(|l| l.strip_prefix("material "))
        .map(|rest| rest.split_whitespace().next().unwrap())
        .collect()
}

/// The build's report, or "" when the scene builds.
fn problems(root: &std::path::Path) -> String {
    let shown = |p: &dyn miette::Diagnostic| {
        let mut out = String::new();
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .with_width(200)
            .render_report(&mut out, p)
            .unwrap();
        out
    };
    match raytrace::lang::load(root) {
        Err(p) => shown(&p),
        Ok(program) => match raytrace::scene::build(&program) {
            Err(p) => shown(&p),
            Ok(_) => String::new(),
        },
    }
}

#[test]
fn every_std_file_parses_and_every_material_renders() {
    let _watchdog = crate::watchdog::start();
    let mut count = 0;
    for (name, text) in FILES {
        let f = Files::new();
        // Each file alone builds (colours.rt too: it only binds names).
        f.write("alone.rt", &format!("include \"std/{name}\"\n"));
        assert_eq!(problems(&f.dir.path().join("alone.rt")), "", "std/{name}");
        for m in materials(text) {
            count += 1;
            let scene = f.write(
                "scene.rt",
                &format!(
                    "include \"std/{name}\"\n\
                     camera {{ position <0, 1.5, 4>  look_at <0, 0.75, 0>  fov 34 }}\n\
                     render {{ width 24  height 24  max_depth 8 }}\n\
                     light {{ position <-3, 6, 5> }}\n\
                     plane {{ normal <0, 1, 0>  material {{ colour checker {{ a white  b rgb(0.1, 0.1, 0.1)  scale 0.5 }} }} }}\n\
                     sphere {{ radius 0.75  centre <0, 0.75, 0>  material {m} }}\n"
                ),
            );
            let film = super::support::render_path(&scene, None, 2);
            assert!(
                film.pixels
                    .iter()
                    .flatten()
                    .all(|c| c.is_finite() && *c >= 0.0),
                "{m}: a pixel is not a finite, non-negative colour"
            );
            // The sphere covers the middle of the picture: it must show
            // something there (light through glass, a metal's highlight or
            // mirror image), not black.
            let middle: f32 = (8..16)
                .flat_map(|y| (8..16).map(move |x| y * 24 + x))
                .map(|i| super::support::luminance(film.pixels[i]))
                .sum::<f32>()
                / 64.0;
            assert!(middle > 0.02, "{m} from std/{name} is black ({middle})");
        }
    }
    assert!(count >= 19, "only {count} materials found");
}

#[test]
fn the_library_comes_before_a_users_std_folder() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    // A user's own std/metals.rt with another gold, and a file of theirs
    // the library does not have.
    std::fs::create_dir_all(f.dir.path().join("std")).unwrap();
    f.write("std/metals.rt", "material gold { colour rgb(0, 0, 1) }\n");
    f.write("std/mine.rt", "material mine { colour rgb(0, 1, 0) }\n");
    let scene = |inc: &str, m: &str| {
        f.write(
            "scene.rt",
            &format!(
                "include \"{inc}\"\n\
                 camera {{ position <0, 0, 4>  look_at <0, 0, 0> }}\n\
                 render {{ width 8  height 8  max_depth 1 }}\n\
                 ambient rgb(1, 1, 1) intensity 1\n\
                 sphere {{ radius 2  material {{ colour rgb(0, 0, 0) }} }}\n\
                 sphere {{ radius 1  centre <0, 0, 2>  material {m} }}\n"
            ),
        )
    };
    let centre =
        |path: std::path::PathBuf| super::support::render_path(&path, None, 1).pixels[4 * 8 + 4];
    // The library's gold is yellow: red above blue.
    let p = centre(scene("std/metals.rt", "gold"));
    assert!(
        p[0] > p[2],
        "the library's gold, not the user's blue: {p:?}"
    );
    // `./std/...` names the user's file.
    let p = centre(scene("./std/metals.rt", "gold"));
    assert!(p[2] > p[0], "the user's gold: {p:?}");
    // A name the library lacks is read from disk.
    let p = centre(scene("std/mine.rt", "mine"));
    assert!(p[1] > p[0] && p[1] > p[2], "{p:?}");
}

#[test]
fn a_misspelt_std_name_gets_a_suggestion() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    let root = f.write("scene.rt", "include \"std/metal.rt\"\n");
    let r = problems(&root);
    assert!(
        r.contains("cannot find the included file `std/metal.rt`"),
        "{r}"
    );
    assert!(r.contains("did you mean `std/metals.rt`?"), "{r}");
    let root = f.write("scene.rt", "include \"std/nothing_like_it.rt\"\n");
    let r = problems(&root);
    assert!(
        r.contains("std/colours.rt") && r.contains("std/glass.rt"),
        "{r}"
    );
}

/// An error in the user's scene that names a std material wrongly is
/// reported with a suggestion from the library's names, and a std file's
/// names clash with the user's like any include's.
#[test]
fn std_names_are_ordinary_names() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    let root = f.write(
        "scene.rt",
        "include \"std/metals.rt\"\nsphere { radius 1  material gld }\n",
    );
    let r = problems(&root);
    assert!(r.contains("gold"), "{r}");
    let root = f.write(
        "scene.rt",
        "include \"std/colours.rt\"\nlet Red = rgb(0.5, 0, 0)\n",
    );
    let r = problems(&root);
    assert!(
        r.contains("std/colours.rt"),
        "the first definition is shown: {r}"
    );
}

/// Included std text counts toward the include count (each time) and the
/// scene's byte budget, as a file on disk would.
#[test]
fn std_includes_count_in_the_budgets() {
    let _watchdog = crate::watchdog::start();
    let f = Files::new();
    let many = "include \"std/glass.rt\"\n".repeat(raytrace::lang::MAX_INCLUDES + 1);
    let root = f.write("scene.rt", &many);
    let r = problems(&root);
    assert!(r.contains("too many includes"), "{r}");
    // A root file just under the byte budget has no room for a std file.
    let glass = raytrace::stdlib::get("glass.rt").unwrap().len() as u64;
    let head = "include \"std/glass.rt\"\n";
    let pad = raytrace::lang::MAX_TOTAL_BYTES - glass / 2 - head.len() as u64;
    let text = format!("{head}//{}\n", "x".repeat(pad as usize - 3));
    let root = f.write("scene.rt", &text);
    let r = problems(&root);
    assert!(r.contains("included text is too large"), "{r}");
}

/// docs/std.md shows every material of every std file, and its swatch is
/// committed (scripts/std_swatches.sh writes them).
#[test]
fn the_docs_show_every_material_with_its_swatch() {
    let root = super::support::project_root();
    let doc = std::fs::read_to_string(root.join("docs/std.md")).unwrap();
    for (name, text) in FILES {
        assert!(
            doc.contains(&format!("## std/{name}")),
            "docs/std.md has no section for {name}"
        );
        for m in materials(text) {
            assert!(
                doc.contains(&format!("![{m}](std/{m}.png)")),
                "docs/std.md does not show `{m}`"
            );
            assert!(
                root.join(format!("docs/std/{m}.png")).is_file(),
                "docs/std/{m}.png is missing: run scripts/std_swatches.sh"
            );
        }
    }
}
