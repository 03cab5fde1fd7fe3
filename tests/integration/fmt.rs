//! `raytrace fmt`: the layout changes no picture, is a fixed point, keeps
//! every comment, and refuses a file that does not parse.

use crate::support;
use raytrace::render::{Film, RenderOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Every scene the project ships: the examples, the benchmark scenes and
/// the standard library.
fn shipped_scenes() -> Vec<PathBuf> {
    let root = support::project_root();
    let mut out = Vec::new();
    let mut dirs = vec![
        root.join("examples"),
        root.join("benches/scenes"),
        root.join("src/stdlib"),
    ];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "rt") {
                out.push(p);
            }
        }
    }
    out.sort();
    assert!(out.len() > 20, "found {out:?}");
    out
}

/// The scene `text`, read as if it were the file at `path` (so that its
/// includes and meshes are found), rendered at 24×18 with one sample; or
/// `None` when it cannot be built here (a scene that needs the shared
/// data set).
fn render_as(path: &Path, text: String) -> Option<Film> {
    let program = raytrace::lang::load_text(path, text).ok()?;
    let mut scene = raytrace::scene::build(&program).ok()?;
    scene.settings.width = 24;
    scene.settings.height = 18;
    scene.settings.samples = 1;
    scene.settings.sample_rows = None;
    scene.settings.adaptive = None;
    let world = raytrace::accel::World::build(std::mem::take(&mut scene.objects));
    let opts = RenderOptions {
        progress: None,
        cancel: None,
    };
    Some(raytrace::render::render(&scene, &world, &opts)?.0)
}

#[test]
fn formatting_a_shipped_scene_is_a_fixed_point_and_keeps_its_comments() {
    for path in shipped_scenes() {
        let text = std::fs::read_to_string(&path).unwrap();
        raytrace::fmt::check("x", &path, &text).unwrap_or_else(|e| panic!("{e:?}"));
        let once = raytrace::fmt::format(&text);
        assert_eq!(raytrace::fmt::format(&once), once, "{}", path.display());
        // Every comment, and every string, is still there, word for word.
        let words = |s: &str| -> Vec<String> { s.split_whitespace().map(String::from).collect() };
        let lines_of = |s: &str, mark: &str| -> Vec<String> {
            s.lines()
                .filter_map(|l| l.find(mark).map(|k| l[k..].trim_end().to_string()))
                .collect()
        };
        assert_eq!(
            lines_of(&once, "//"),
            lines_of(&text, "//"),
            "{}",
            path.display()
        );
        let ink = |s: &str| words(s).concat().replace(' ', "");
        assert_eq!(ink(&once), ink(&text), "{}", path.display());
    }
}

#[test]
fn formatting_the_examples_changes_no_picture() {
    let mut rendered = 0;
    for path in shipped_scenes() {
        if path.starts_with(support::project_root().join("src")) {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let formatted = raytrace::fmt::format(&text);
        let Some(before) = render_as(&path, text.clone()) else {
            continue;
        };
        let after = render_as(&path, formatted).expect("the formatted scene builds");
        assert!(before == after, "{} renders differently", path.display());
        rendered += 1;
    }
    assert!(rendered > 20, "only {rendered} scenes rendered");
}

fn fmt(args: &[&str], dir: &Path) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .arg("fmt")
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

const MESSY: &str = "// a scene\nsphere{radius 1\n      material { colour red } }   \n\n\n\nlight { position <1,2,3> }";
const TIDY: &str =
    "// a scene\nsphere { radius 1\n  material { colour red } }\n\nlight { position <1, 2, 3> }\n";

#[test]
fn fmt_rewrites_in_place_and_check_names_what_would_change() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("a.rt"), MESSY).unwrap();
    std::fs::write(d.join("b.rt"), TIDY).unwrap();

    let o = fmt(&["--check", "a.rt", "b.rt"], d);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(String::from_utf8_lossy(&o.stdout), "a.rt\n");
    assert_eq!(std::fs::read_to_string(d.join("a.rt")).unwrap(), MESSY);

    let o = fmt(&["a.rt", "b.rt"], d);
    assert_eq!(o.status.code(), Some(0), "{}", support::stderr(&o));
    assert_eq!(std::fs::read_to_string(d.join("a.rt")).unwrap(), TIDY);
    assert!(support::temporaries(d).is_empty());

    let o = fmt(&["--check", "a.rt", "b.rt"], d);
    assert_eq!(o.status.code(), Some(0));
    assert!(o.stdout.is_empty());
}

#[test]
fn fmt_refuses_a_file_with_errors_and_leaves_it_alone() {
    let dir = tempfile::tempdir().unwrap();
    let bad = "sphere { radius 1\nlight { position <1, 2 3> }\n";
    std::fs::write(dir.path().join("bad.rt"), bad).unwrap();
    let o = fmt(&["bad.rt"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let err = support::stderr(&o);
    assert!(err.contains("bad.rt:"), "{err}");
    // The same report as rendering the scene gives.
    let render = support::raytrace(&[dir.path().join("bad.rt").as_os_str(), "--check".as_ref()]);
    let first_line = |s: &str| s.lines().find(|l| l.contains('×')).map(str::to_string);
    assert_eq!(first_line(&err), first_line(&support::stderr(&render)));
    assert_eq!(
        std::fs::read_to_string(dir.path().join("bad.rt")).unwrap(),
        bad
    );

    let o = fmt(&["missing.rt"], dir.path());
    assert_eq!(o.status.code(), Some(3));
    assert!(support::stderr(&o).contains("missing.rt"));
}

#[test]
fn fmt_dash_reads_stdin_and_writes_stdout() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raytrace"))
        .args(["fmt", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(MESSY.as_bytes())
        .unwrap();
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(String::from_utf8_lossy(&o.stdout), TIDY);
}
