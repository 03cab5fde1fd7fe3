//! Completion: what may be written at the cursor. At the top level, the
//! statements; inside a block, that block's parameters (from the builder's
//! schemas, so exactly what `raytrace` accepts there); after `material`,
//! the materials declared (the standard library's too, once included);
//! where a colour goes, the colour names; everywhere, the names in scope.

use super::analysis::{Analysis, DefKind};
use super::context;
use lsp_types::{CompletionItem, CompletionItemKind};

/// `color` → `colour`, as the builder reads parameters (the builder's own
/// spelling table).
pub use crate::scene::canonical_parameter as canonical;

const LANGUAGE: &[&str] = &["let", "for", "if", "fn", "include"];

fn item(label: &str, kind: CompletionItemKind, detail: Option<String>) -> CompletionItem {
    CompletionItem {
        label: label.to_string(),
        kind: Some(kind),
        detail,
        ..CompletionItem::default()
    }
}

/// The completions at byte `at` of `text`.
pub fn complete(text: &str, at: usize, a: Option<&Analysis>) -> Vec<CompletionItem> {
    // What comes after the cursor's line never changes what may be written.
    let line_end = text[at..].find('\n').map_or(text.len(), |i| at + i);
    let toks = context::tokens(&text[..line_end]);
    // In an include's string: the standard library's files.
    let holds = |s: usize, e: usize| s < at && (at < e || (at == e && e == line_end));
    let in_include = toks.windows(2).find(|w| {
        w[0].0 == context::Tok::Word("include")
            && w[1].0 == context::Tok::Str
            && holds(w[1].1, w[1].2)
    });
    if let Some(w) = in_include {
        // The whole path so far is replaced (a path is no word to an editor).
        let lines = super::positions::LineIndex::new(text);
        let range = lines.range(text, w[1].1 + 1, at);
        return crate::stdlib::include_names()
            .map(|n| CompletionItem {
                text_edit: Some(lsp_types::CompletionTextEdit::Edit(lsp_types::TextEdit {
                    range,
                    new_text: n.clone(),
                })),
                ..item(
                    &n,
                    CompletionItemKind::FILE,
                    Some("the standard library".into()),
                )
            })
            .collect();
    }
    // Inside a comment or another string: nothing.
    if inside_comment_or_string(text, &toks, at) {
        return Vec::new();
    }
    let blocks = context::blocks_at(&toks, at);
    let (block, parent) = context::innermost(&blocks);
    let prev = context::previous_word(&toks, at);
    let mut out: Vec<CompletionItem> = Vec::new();
    let names = a.map(|a| a.names_at(a.root, at)).unwrap_or_default();
    let params = block.and_then(|b| crate::scene::block_parameters(b, parent));
    let prev_param = prev.and_then(|p| {
        params
            .as_ref()?
            .iter()
            .find(|q| q.name == canonical(p))
            .copied()
    });
    // After `material` (a parameter or a statement): the materials.
    if prev == Some("material") && block != Some("material") {
        for d in names
            .iter()
            .filter(|d| d.kind == DefKind::Material || is_material_value(d))
        {
            out.push(item(
                &d.name,
                CompletionItemKind::COLOR,
                Some(d.signature.clone()),
            ));
        }
        return out;
    }
    if let Some(p) = prev_param.filter(|p| p.expects.contains("colour") && p.name != "material") {
        // A colour goes here: the names of colours (and patterns, for `colour`).
        for (c, hex) in crate::eval::colours::COLOURS {
            out.push(item(
                c,
                CompletionItemKind::COLOR,
                Some(format!("#{hex:06x}")),
            ));
        }
        if p.expects.contains("pattern") {
            for n in crate::scene::pattern::NAMES {
                out.push(item(n, CompletionItemKind::CLASS, Some("pattern".into())));
            }
        }
        if p.name == "normal" {
            out.clear();
        }
    }
    if prev_param.is_some_and(|p| p.name == "normal") {
        for n in ["bumps", "ripples", "waves"] {
            out.push(item(
                n,
                CompletionItemKind::CLASS,
                Some("normal pattern".into()),
            ));
        }
    }
    if prev_param.is_none() {
        match (block, &params) {
            // Top level, or a function's body: the statements.
            (None | Some("fn"), _) => {
                for k in crate::lang::parser::STATEMENT_KEYWORDS {
                    let kind = if LANGUAGE.contains(k) {
                        CompletionItemKind::KEYWORD
                    } else {
                        CompletionItemKind::CLASS
                    };
                    out.push(item(k, kind, super::docs::word(k).map(first_line)));
                }
            }
            (Some(_), Some(ps)) => {
                for p in ps {
                    let kind = if crate::scene::is_object(p.name) {
                        CompletionItemKind::CLASS
                    } else {
                        CompletionItemKind::PROPERTY
                    };
                    out.push(item(p.name, kind, Some(p.expects.to_string())));
                }
                for k in LANGUAGE.iter().filter(|k| **k != "include") {
                    out.push(item(k, CompletionItemKind::KEYWORD, None));
                }
            }
            // A placement (`wheel { … }`, `pillar(1) { … }`): a material
            // and transforms, as any object.
            (Some(_), None) => {
                if let Some(ps) = crate::scene::block_parameters("group", None) {
                    for p in ps.iter().filter(|p| !crate::scene::is_object(p.name)) {
                        out.push(item(
                            p.name,
                            CompletionItemKind::PROPERTY,
                            Some(p.expects.to_string()),
                        ));
                    }
                }
            }
        }
    }
    // The names in scope: values anywhere, functions, object values.
    for d in names {
        if d.kind == DefKind::Material {
            continue;
        }
        let kind = match d.kind {
            DefKind::Fn => CompletionItemKind::FUNCTION,
            DefKind::LoopVar | DefKind::Param => CompletionItemKind::VARIABLE,
            _ => CompletionItemKind::CONSTANT,
        };
        if !out.iter().any(|o| o.label == d.name) {
            let detail = d.value.clone().unwrap_or_else(|| d.signature.clone());
            out.push(item(&d.name, kind, Some(detail)));
        }
    }
    if prev_param.is_some() {
        for (f, n) in crate::eval::expr::FUNCTIONS {
            out.push(item(
                f,
                CompletionItemKind::FUNCTION,
                Some(format!(
                    "built-in, {n} argument{}",
                    if *n == 1 { "" } else { "s" }
                )),
            ));
        }
        out.push(item(
            "pi",
            CompletionItemKind::CONSTANT,
            Some("3.14159…".into()),
        ));
    }
    out
}

fn is_material_value(d: &super::analysis::Def) -> bool {
    d.kind == DefKind::Let && d.signature.contains("= material {")
}

fn first_line(s: String) -> String {
    s.lines()
        .find(|l| !l.trim().is_empty() && !l.starts_with("```"))
        .unwrap_or("")
        .chars()
        .take(80)
        .collect()
}

fn inside_comment_or_string(
    text: &str,
    toks: &[(context::Tok<'_>, usize, usize)],
    at: usize,
) -> bool {
    if toks
        .iter()
        .any(|&(t, s, e)| t == context::Tok::Str && s < at && at < e)
    {
        return true;
    }
    // A `//` earlier on the line, outside a string.
    let line_start = text[..at.min(text.len())].rfind('\n').map_or(0, |i| i + 1);
    text[line_start..at.min(text.len())]
        .match_indices("//")
        .any(|(i, _)| {
            !toks.iter().any(|&(t, s, e)| {
                t == context::Tok::Str && s <= line_start + i && line_start + i < e
            })
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn labels(text: &str, a: Option<&Analysis>) -> Vec<String> {
        let at = text.find('|').unwrap();
        let text = text.replace('|', "");
        complete(&text, at, a)
            .into_iter()
            .map(|c| c.label)
            .collect()
    }

    fn analysed(text: &str) -> Analysis {
        let r = crate::lsp::check::check(std::path::Path::new("/nonexistent/c.rt"), text, None);
        Arc::try_unwrap(r.analysis.unwrap()).unwrap()
    }

    #[test]
    fn a_block_offers_its_own_parameters() {
        let l = labels("sphere { ra| }", None);
        assert!(l.contains(&"radius".into()) && l.contains(&"centre".into()));
        assert!(l.contains(&"translate".into()) && l.contains(&"material".into()));
        assert!(!l.contains(&"ior".into()) && !l.contains(&"box".into()));
        let l = labels("material glass { refract { | } }", None);
        assert!(l.contains(&"ior".into()) && !l.contains(&"radius".into()));
        let l = labels("union { for i in 0..3 { | } }", None);
        assert!(
            l.contains(&"sphere".into()),
            "a union holds objects, loops are see-through"
        );
    }

    #[test]
    fn the_top_level_offers_statements() {
        let l = labels("camera { fov 40 }\n|", None);
        assert!(l.contains(&"camera".into()) && l.contains(&"let".into()));
        assert!(!l.contains(&"radius".into()));
    }

    #[test]
    fn names_in_scope_materials_and_colours() {
        let t = "include \"std/metals.rt\"\nlet r = 2\nmaterial red_plastic { colour red }\nsphere { material | }";
        let a = analysed(&t.replace('|', ""));
        let l = labels(t, Some(&a));
        assert!(
            l.contains(&"red_plastic".into()) && l.contains(&"gold".into()),
            "{l:?}"
        );
        assert!(!l.contains(&"r".into()), "a number is no material");
        let t = "let r = 2\nsphere { radius | }";
        let a = analysed(&t.replace('|', "1"));
        assert!(labels(t, Some(&a)).contains(&"r".into()));
        let l = labels("light { colour | }", None);
        assert!(l.contains(&"skyblue".into()));
        assert!(labels("// sphere { |", None).is_empty());
        assert!(labels("include \"std/m|", None).contains(&"std/metals.rt".into()));
        assert!(labels("include \"std/m|\nsphere { }", None).contains(&"std/metals.rt".into()));
        assert!(labels("include \"std/metals.rt\" |", None).contains(&"camera".into()));
    }
}
