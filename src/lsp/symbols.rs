//! Go to definition (a `let`, `fn`, `material`, loop variable or parameter
//! name; an `include` path, which jumps to the file) and the document's
//! outline.

use super::analysis::{Analysis, Symbol};
use super::context;
use super::uri;
use lsp_types::{DocumentSymbol, Location, Position, Range};

/// Where the thing at byte `at` of the document is defined.
pub fn definition(text: &str, at: usize, a: &Analysis) -> Option<Location> {
    // An include string: the file it read.
    if let Some(inc) = a
        .includes
        .iter()
        .find(|i| i.span.file == a.root && i.span.start <= at && at < i.span.end)
    {
        let f = a.file(inc.target);
        if f.standard {
            return None;
        }
        return Some(Location {
            uri: uri::from_path(&f.path)?,
            range: Range::new(Position::new(0, 0), Position::new(0, 0)),
        });
    }
    let (start, _, w) = context::word_at(text, at)?;
    let d = *a.visible(w, a.root, start).first()?;
    let f = a.file(d.span.file);
    if f.standard {
        return None;
    }
    Some(Location {
        uri: uri::from_path(&f.path)?,
        range: f.lines.range(&f.text, d.span.start, d.span.end),
    })
}

/// The outline, as the protocol's nested symbols.
pub fn outline(a: &Analysis) -> Vec<DocumentSymbol> {
    a.outline.iter().map(|s| convert(a, s)).collect()
}

#[allow(deprecated)] // `deprecated` is a required field of the type
fn convert(a: &Analysis, s: &Symbol) -> DocumentSymbol {
    let f = a.file(a.root);
    let range = f.lines.range(&f.text, s.span.start, s.span.end);
    let mut selection = f.lines.range(&f.text, s.selection.start, s.selection.end);
    if selection.start < range.start || selection.end > range.end {
        selection = range;
    }
    DocumentSymbol {
        name: s.name.clone(),
        detail: s.detail.clone(),
        kind: s.kind,
        tags: None,
        deprecated: None,
        range,
        selection_range: selection,
        children: (!s.children.is_empty())
            .then(|| s.children.iter().map(|c| convert(a, c)).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn analysed(path: &Path, text: &str) -> std::sync::Arc<Analysis> {
        crate::lsp::check::check(path, text, None).analysis.unwrap()
    }

    #[test]
    fn names_jump_to_their_definitions_innermost_first() {
        let t = "let r = 1\nfn f(r) = r * 2\nsphere { radius r }\n";
        let a = analysed(Path::new("/nonexistent/d.rt"), t);
        let use_outer = t.rfind('r').unwrap();
        let l = definition(t, use_outer, &a).unwrap();
        assert_eq!(l.range.start, Position::new(0, 4));
        let use_param = t.find("r * 2").unwrap();
        let l = definition(t, use_param, &a).unwrap();
        assert_eq!(
            l.range.start,
            Position::new(1, 5),
            "the parameter, not the outer let"
        );
    }

    #[test]
    fn includes_jump_to_the_file_and_its_names() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("m.rt"),
            "material steel { colour #b0b0c0 }\n",
        )
        .unwrap();
        let t = "include \"m.rt\"\nsphere { material steel }\n";
        let root = dir.path().join("scene.rt");
        let a = analysed(&root, t);
        let l = definition(t, t.find("m.rt").unwrap(), &a).unwrap();
        assert!(l.uri.as_str().ends_with("/m.rt"), "{:?}", l.uri);
        let l = definition(t, t.find("steel").unwrap() + 1, &a).unwrap();
        assert!(l.uri.as_str().ends_with("/m.rt"));
        assert_eq!(l.range.start, Position::new(0, 9));
    }

    #[test]
    fn the_outline_lists_statements() {
        let t = "let R = 2\ncamera { fov 40 }\nmaterial gold { colour gold }\nfn p(h) { sphere { } }\nunion { box { } sphere { } }\nlight { position <0, 5, 0> }\n";
        let a = analysed(Path::new("/nonexistent/o.rt"), t);
        let names: Vec<String> = outline(&a).into_iter().map(|s| s.name).collect();
        assert_eq!(
            names,
            ["R", "camera", "material gold", "p", "union", "light"]
        );
        let u = &outline(&a)[4];
        let kids: Vec<&str> = u
            .children
            .as_ref()
            .unwrap()
            .iter()
            .map(|s| s.name.as_str())
            .collect();
        assert_eq!(kids, ["box", "sphere"]);
    }
}
