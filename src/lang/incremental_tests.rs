//! The incremental parse against the whole-file parse: after every edit of
//! many edit sequences, the same items and the same errors, spans
//! included.

use super::*;
use crate::lang::source::floor_char_boundary;
use proptest::prelude::*;

const F: FileId = FileId(0);

/// Parses `text` through `cache` and asserts it is the full parse's; the
/// items go back to the cache as the language server gives them back.
fn same(cache: &mut ParseCache, text: &str) {
    check_same(cache, text);
}

/// As [`same`], the items not given back (a check that was cut short).
fn same_unclaimed(cache: &mut ParseCache, text: &str) {
    let full = parser::parse(text, F);
    let incremental = cache.parse(text, F);
    assert!(
        incremental == full,
        "the incremental parse differs for\n{text}"
    );
}

fn check_same(cache: &mut ParseCache, text: &str) {
    let full = parser::parse(text, F);
    let incremental = cache.parse(text, F);
    if incremental != full {
        let first = |r: &Result<Vec<Item>, Vec<Error>>| match r {
            Ok(items) => format!("{} items", items.len()),
            Err(e) => format!("errors {e:#?}"),
        };
        let differ = match (&incremental, &full) {
            (Ok(a), Ok(b)) => a
                .iter()
                .zip(b)
                .find(|(x, y)| x != y)
                .map(|(x, y)| format!("{x:#?}\nagainst\n{y:#?}")),
            _ => None,
        };
        panic!(
            "the incremental parse differs for\n-----\n{text}\n-----\nincremental: {}\nfull: {}\n{differ:?}",
            first(&incremental),
            first(&full)
        );
    }
    if let Ok(items) = incremental {
        cache.reclaim(items, F);
    }
}

/// A scene as a program writes one (as scripts/lsp_latency.py), with the
/// forms an item may go on over lines mixed in.
pub(crate) fn generated(lines: usize) -> String {
    let mut out = vec![
        "camera { position <0, 20, 60>  look_at <0, 0, 0>  fov 50 }".to_string(),
        "light { position <50, 80, 40> }".to_string(),
        "fn post(h, r = 0.2) { cylinder { radius r  height h  translate <0, h / 2, 0> } }"
            .to_string(),
        "fn twice(x) = 2 * x".to_string(),
        "let flag = 1 < 2\n  and 3 > 2\nor not flag".to_string(),
        "if flag {\n  sphere { radius 1 }\n}\nelse {\n  box { }\n}".to_string(),
        "let wheel = union\n{\n  sphere { radius 1 }\n}".to_string(),
        "/* a comment\nsphere { over lines } */ let s = \"a // string { \"".to_string(),
        "for i in 0..10\n  step 2 { sphere { centre <i,\n  0, i> } }".to_string(),
        "let v = <1,\nq, 2>".to_string(),
        "let w = 3\n  - 1".to_string(),
        "let u = 3\n-1".to_string(),
        "include \"std/metals.rt\"".to_string(),
    ];
    for k in 0..10 {
        out.push(format!("let r{k} = 0.2 + {k} * 0.01"));
        out.push(format!(
            "material m{k} {{ colour rgb({:.2}, 0.5, 0.5)  specular 0.3 }}",
            k as f64 / 10.0
        ));
    }
    let mut i = 0;
    while out.len() < lines {
        let (x, z) = (i % 30, i / 30);
        out.push(match i % 5 {
            0 => format!(
                "sphere {{ centre <{x}, 0, {z}>  radius r{}  material m{} }}",
                i % 10,
                i % 10
            ),
            1 => format!("box {{ min <{x}, -1, {z}>  max <{x}.5, -0.5, {z}.5> }} // box {i}"),
            2 => format!("cylinder {{\n  radius 0.1  height 2\n  rotate x {i}\n}}"),
            3 => format!("post({}) {{ translate <{x}, 0, {z}> }}", 1 + i % 3),
            _ => format!("let t{i} = twice({i})"),
        });
        i += 1;
    }
    out.join("\n") + "\n"
}

fn examples() -> Vec<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut out = Vec::new();
    let mut dirs = vec![root];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "rt") {
                out.push(std::fs::read_to_string(&p).unwrap());
            }
        }
    }
    out.sort();
    assert!(out.len() > 10, "the example scenes are there");
    out
}

/// What an edit inserts: brackets, strings and comments opened and
/// closed, and the words and signs an item may go on with.
const SNIPPETS: &[&str] = &[
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    "<",
    ">",
    "\"",
    "//",
    "/*",
    "*/",
    "\n",
    " ",
    "let x = ",
    "else",
    "else { }",
    "-",
    " - ",
    "+ 1",
    "<1,\nz, 2>",
    "or",
    "and b",
    "not ",
    "\nsphere",
    "sphere { radius 1 }\n",
    "\nelse",
    "\nor x",
    "\nand",
    "\nin",
    "\nstep 2",
    "1.2.3",
    "#ff80",
    "fn f(a) = a\n",
    "for i in 0..3 { }",
    "if x { }",
    "é",
    "\t",
    "x",
    "r: 1",
    "=",
    "\n{",
    "\n\"s\"",
    "\n- 1",
    "\n-1",
    "/* c */",
    "// c\n",
    "\nlet",
    "\n_a",
    "let\n",
    "\n  box",
    "include \"nothing.rt\"\n",
    "radus",
    "0",
    "\r\n",
];

#[derive(Clone, Debug)]
enum Edit {
    Insert(usize, usize),
    Delete(usize, usize),
    /// Back to the text before the last edit (a fix after a break).
    Undo,
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        4 => (any::<usize>(), 0..SNIPPETS.len()).prop_map(|(at, s)| Edit::Insert(at, s)),
        3 => (any::<usize>(), 0usize..40).prop_map(|(at, n)| Edit::Delete(at, n)),
        1 => Just(Edit::Undo),
    ]
}

fn apply(text: &str, e: &Edit, before: &str) -> String {
    let at = |n: usize| floor_char_boundary(text, n % (text.len() + 1));
    match *e {
        Edit::Insert(n, s) => {
            let p = at(n);
            format!("{}{}{}", &text[..p], SNIPPETS[s], &text[p..])
        }
        Edit::Delete(n, len) => {
            let p = at(n);
            let q = floor_char_boundary(text, (p + len).min(text.len()));
            format!("{}{}", &text[..p], &text[q..])
        }
        Edit::Undo => before.to_string(),
    }
}

fn run(scene: &str, edits: &[Edit]) {
    let mut cache = ParseCache::new();
    let mut text = scene.to_string();
    same(&mut cache, &text);
    let mut before = text.clone();
    for (k, e) in edits.iter().enumerate() {
        let next = apply(&text, e, &before);
        before = std::mem::replace(&mut text, next);
        if k % 5 == 3 {
            same_unclaimed(&mut cache, &text);
        } else {
            same(&mut cache, &text);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn edits_of_the_examples_parse_as_a_full_parse(
        k in any::<usize>(),
        edits in prop::collection::vec(edit(), 1..12),
    ) {
        let scenes = examples();
        run(&scenes[k % scenes.len()], &edits);
    }

    #[test]
    fn edits_of_a_generated_scene_parse_as_a_full_parse(
        edits in prop::collection::vec(edit(), 1..12),
    ) {
        run(&generated(120), &edits);
    }
}

/// Edits that change how the items around a line join: each text is
/// parsed after the one before it through one cache.
#[test]
fn edits_that_join_and_split_items() {
    let base = generated(60);
    let mid = base.len() / 2;
    let mid = base[mid..].find('\n').map_or(mid, |n| mid + n + 1);
    let with = |s: &str| format!("{}{s}{}", &base[..mid], &base[mid..]);
    let texts = [
        base.clone(),
        with("let a =\n"),
        with("let a = \n"),
        with("let a = 2\n"),
        with("if flag { }\n"),
        with("if flag { }\nelse "),
        with("let v = <1,\n"),
        with("{\n"),
        with("}\n"),
        with("/*\n"),
        with("/* */\n"),
        with("\"\n"),
        with("let a = 1 +\n"),
        with("let a = 1 -\n"),
        with("let a = 1\n- \n"),
        with("sphere\n"),
        with("let q = sphere\n\"x\"\n"),
        with("1.2.3\n"),
        with("#ff80 #ff8000\n"),
        base.replace("sphere", "sphere {"),
        base.replace("union", "union {"),
        base.replace("\nelse", "\nels"),
        base.replace("\nor", "\nor_"),
        base.clone(),
        String::new(),
        "// only a comment".into(),
        "sphere".into(),
        base,
    ];
    let mut cache = ParseCache::new();
    for t in &texts {
        same(&mut cache, t);
    }
    // And each alone, with nothing kept.
    for t in &texts {
        same(&mut ParseCache::new(), t);
    }
}

#[test]
fn a_one_line_edit_parses_one_chunk_again() {
    let text = generated(2000);
    let mut cache = ParseCache::new();
    same(&mut cache, &text);
    assert!(cache.last_chunks > 1500, "{} chunks", cache.last_chunks);
    let n = text.len() / 2;
    let line = text[n..].find('\n').unwrap() + n + 1;
    let edited = format!("{}sphere {{ radus 1 }}\n{}", &text[..line], &text[line..]);
    same(&mut cache, &edited);
    assert!(
        cache.last_parsed <= 2,
        "{} chunks parsed",
        cache.last_parsed
    );
    // A syntax error at the end: the chunks before it are kept.
    let broken = format!("{text}sphere {{ radius 1 ]\n");
    same(&mut cache, &broken);
    let broken = format!("{text}let a = 1 +\n");
    same(&mut cache, &broken);
    assert!(
        cache.last_parsed <= 2,
        "{} chunks parsed",
        cache.last_parsed
    );
    same(&mut cache, &text);
    assert!(
        cache.last_parsed <= 2,
        "{} chunks parsed",
        cache.last_parsed
    );
    // One in the middle: the chunks after it are kept for the fix.
    let broken = format!("{}let = 1\n{}", &text[..line], &text[line..]);
    same(&mut cache, &broken);
    same(&mut cache, &text);
    assert!(
        cache.last_parsed <= 2,
        "{} chunks parsed",
        cache.last_parsed
    );
}

#[test]
fn chunks_start_only_where_an_item_surely_does() {
    let t = "a\nb {\n  c\n}\n  else\nd // e\n\"f\" /* h\ni */ j\nor\n_k\n";
    let starts = chunk_starts(t);
    let words: Vec<&str> = starts
        .iter()
        .map(|&s| t[s..].split_whitespace().next().unwrap_or(""))
        .collect();
    assert_eq!(words, ["a", "b", "d", "_k"]);
}
