//! Hover: what a word at the cursor is. A name the scene defines shows its
//! definition (a `let`'s value and kind, a `fn`'s signature) and where it
//! is; a parameter shows what it expects (the builder's words) and the
//! reference's row for it; a keyword, statement, object, pattern or
//! built-in function shows the reference's text (see [`super::docs`]); a
//! colour name its value.

use super::analysis::{Analysis, DefKind};
use super::context::{self, Tok};
use super::docs;

/// The Markdown to show for the word at byte `at` of `text`, and the
/// word's range.
pub fn hover(text: &str, at: usize, a: Option<&Analysis>) -> Option<(String, usize, usize)> {
    let (start, end, w) = context::word_at(text, at)?;
    // What comes after the word never changes what it is.
    let toks = context::tokens(&text[..end]);
    // Inside a comment or a string there is nothing to say.
    if !toks
        .iter()
        .any(|&(t, s, e)| s == start && e == end && t == Tok::Word(w))
    {
        return None;
    }
    let blocks = context::blocks_at(&toks, start);
    let (block, parent) = context::innermost(&blocks);
    let prev = context::previous_word(&toks, start);
    let param = block.and_then(|b| {
        crate::scene::block_parameters(b, parent)?
            .into_iter()
            .find(|p| p.name == crate::lsp::complete::canonical(w))
            .map(|p| (b, p))
    });
    let is_call = text[end..].starts_with('(');
    // A parameter written where a value goes (`radius r`) is a value.
    let value_place = prev.is_some_and(|p| {
        block.is_some_and(|b| {
            crate::scene::block_parameters(b, parent)
                .is_some_and(|ps| ps.iter().any(|q| q.name == p))
        })
    });
    let user = a.and_then(|a| {
        let d = *a.visible(w, a.root, start).first()?;
        Some((a, d))
    });
    let user = user.filter(|_| param.is_none() || value_place);
    let text = match (user, param) {
        (Some((a, d)), _) => {
            let f = a.file(d.span.file);
            let (line, _) = crate::lang::source::line_col(&f.text, d.span.start);
            let kind = match d.kind {
                DefKind::Let => "constant",
                DefKind::Fn => "function",
                DefKind::Material => "material",
                DefKind::LoopVar => "loop variable",
                DefKind::Param => "function parameter",
            };
            let mut s = format!("```rt\n{}\n```\n", d.signature);
            if let Some(v) = &d.value {
                s.push_str(&format!("\n= {v}\n"));
            }
            s.push_str(&format!("\n*{kind}*, defined at {}:{line}", f.name));
            s
        }
        (_, Some((b, p))) => {
            let mut s = format!("**{}** (in `{b}`): {}", p.name, p.expects);
            if let Some(more) = docs::parameter(b, p.name) {
                s.push_str(&format!("\n\n---\n\n{more}"));
            }
            s
        }
        _ => {
            if let Some(d) = docs::word(w).filter(|_| {
                // A built-in function is only one when called.
                !crate::eval::expr::FUNCTIONS.iter().any(|(f, _)| *f == w) || is_call
            }) {
                d
            } else if let Some(rgb) = crate::eval::colours::named_colour(w) {
                format!(
                    "**{w}**: the colour #{:02x}{:02x}{:02x} (a CSS name, decoded with the scene's `gamma`)",
                    rgb[0], rgb[1], rgb[2]
                )
            } else {
                return None;
            }
        }
    };
    Some((text, start, end))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str, needle: &str) -> usize {
        text.find(needle).unwrap() + 1
    }

    fn analysed(text: &str) -> Analysis {
        let path = std::path::Path::new("/nonexistent/hover.rt");
        let r = crate::lsp::check::check(path, text, None);
        Arc::try_unwrap(r.analysis.unwrap()).unwrap()
    }
    use std::sync::Arc;

    #[test]
    fn a_let_shows_its_value_and_place() {
        let t = "let r = 0.5 * 2\nsphere { radius r }\n";
        let a = analysed(t);
        let (h, s, e) = hover(t, t.rfind('r').unwrap(), Some(&a)).unwrap();
        assert_eq!(&t[s..e], "r");
        assert!(h.contains("let r = 0.5 * 2"), "{h}");
        assert!(h.contains("= 1 (a number)"), "{h}");
        assert!(h.contains("hover.rt:1"), "{h}");
    }

    #[test]
    fn a_fn_shows_its_signature() {
        let t = "fn bell(t, k = 2) = exp(-t * t * k)\nsphere { radius bell(1) }\n";
        let a = analysed(t);
        let (h, ..) = hover(t, t.rfind("bell").unwrap(), Some(&a)).unwrap();
        assert!(h.contains("fn bell(t, k = 2) = exp(-t * t * k)"), "{h}");
    }

    #[test]
    fn parameters_say_what_they_expect() {
        let t = "sphere { radius 1 }";
        let (h, ..) = hover(t, at(t, "radius"), None).unwrap();
        assert!(h.starts_with("**radius** (in `sphere`): a number"), "{h}");
        let t = "render { max_depth 3 }";
        let (h, ..) = hover(t, at(t, "max_depth"), None).unwrap();
        assert!(h.contains("reflection bounces"), "{h}");
    }

    #[test]
    fn keywords_functions_and_colours() {
        let t = "for i in 0..3 { sphere { radius sqrt(2)  material { colour gold } } }";
        assert!(hover(t, 1, None).unwrap().0.contains("**Loops.**"));
        assert!(
            hover(t, at(t, "sphere"), None)
                .unwrap()
                .0
                .contains("`centre <c>`")
        );
        assert!(hover(t, at(t, "sqrt"), None).unwrap().0.contains("radians"));
        assert!(hover(t, at(t, "gold"), None).unwrap().0.contains("#ffd700"));
        let c = "// sphere\n";
        assert!(hover(c, 4, None).is_none(), "comments have no hover");
    }
}
