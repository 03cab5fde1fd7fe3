//! Checking a document as `raytrace --check` does (parse, evaluate, build;
//! never render), within a budget, and turning every mistake into an LSP
//! diagnostic in the file it is in: the same messages and spans as the
//! command line, errors in an included file published for that file (and
//! summed up at the `include` in the document).

use super::analysis::Analysis;
use super::uri;
use crate::eval::{Limits, Options};
use crate::lang::ast::{FileId, Span};
use crate::lang::diagnostics::Error;
use crate::lang::incremental::ParseCache;
use lsp_types::{Diagnostic, DiagnosticRelatedInformation, DiagnosticSeverity, Location};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// The evaluation budget of one check: far below the command line's, so
/// that a runaway loop costs an editor a fraction of a second. A scene
/// past it is checked up to there (an information note says so);
/// `raytrace --check` checks it all.
pub const LIMITS: Limits = Limits {
    iterations: 1_000_000,
    objects: 1_000_000,
    depth: 100,
    steps: 20_000_000,
};

/// What one check found.
pub struct Report {
    /// Diagnostics for each file the program read, clean ones included
    /// (with none), so that an editor clears what was fixed.
    pub diagnostics: BTreeMap<PathBuf, Vec<Diagnostic>>,
    /// `None` when not even the document parsed.
    pub analysis: Option<Arc<Analysis>>,
    /// Seconds spent parsing, evaluating and building, and analysing.
    pub times: [f64; 3],
}

/// Checks `text` as the scene file at `path` (includes are read from disk,
/// relative to it). `cancel` stops the evaluation early: a newer version of
/// the document has arrived and this report will not be used.
#[cfg(test)]
pub fn check(path: &Path, text: &str, cancel: Option<Arc<AtomicBool>>) -> Report {
    check_with(path, text, cancel, None)
}

/// As [`check`], the document parsed through `cache` (the parses of its
/// last text), so that a keystroke re-parses only what it changed.
pub fn check_with(
    path: &Path,
    text: &str,
    cancel: Option<Arc<AtomicBool>>,
    mut cache: Option<&mut ParseCache>,
) -> Report {
    let clock = std::time::Instant::now();
    let (mut program, load_errors) =
        crate::lang::load_text_cached(path, text.to_string(), cache.as_deref_mut());
    let parsed = clock.elapsed().as_secs_f64();
    // A newer text may have come while this one was parsed.
    let cancelled = cancel.as_ref().is_some_and(|c| c.load(Ordering::Relaxed));
    let (mut errors, warnings, values) = if cancelled {
        (Vec::new(), Vec::new(), Vec::new())
    } else if load_errors.is_empty() {
        let options = Options {
            limits: LIMITS,
            cancel,
            ..Options::default()
        };
        let checked = crate::scene::check(&program, &options);
        (checked.errors, checked.warnings, checked.bound)
    } else {
        (load_errors, Vec::new(), Vec::new())
    };
    // As the command line: in file order, each mistake once.
    errors.sort_by_key(|e| (e.span.file, e.span.start));
    errors.dedup_by(|a, b| a.span == b.span && a.message == b.message);
    let built = clock.elapsed().as_secs_f64();
    let root_parsed = !program.items.is_empty() || text.trim().is_empty() || errors.is_empty();
    let analysis = Arc::new(Analysis::new(&program, &values));
    let mut diagnostics: BTreeMap<PathBuf, Vec<Diagnostic>> = BTreeMap::new();
    for f in analysis.files.iter().filter(|f| !f.standard) {
        diagnostics.entry(f.path.clone()).or_default();
    }
    // Errors in included files, by the `include` in the document that led there.
    let mut via: BTreeMap<(usize, usize), Vec<&Error>> = BTreeMap::new();
    for e in &errors {
        let file = e.span.file;
        if !analysis.file(file).standard {
            let d = diagnostic(&analysis, e, DiagnosticSeverity::ERROR);
            diagnostics
                .entry(analysis.file(file).path.clone())
                .or_default()
                .push(d);
        }
        if file != analysis.root
            && let Some(at) = chain(&analysis, file).last()
        {
            via.entry((at.start, at.end)).or_default().push(e);
        }
    }
    for ((start, end), errs) in via {
        let span = Span::new(analysis.root, start, end);
        let name = &analysis.file(errs[0].span.file).name;
        let message = match errs.len() {
            1 => format!(
                "the included file `{name}` has a mistake: {}",
                errs[0].message
            ),
            n => format!(
                "the included files have {n} mistakes; the first, in `{name}`: {}",
                errs[0].message
            ),
        };
        let mut d = diagnostic(
            &analysis,
            &Error::new(span, message),
            DiagnosticSeverity::ERROR,
        );
        d.related_information = Some(
            errs.iter()
                .filter_map(|e| related(&analysis, e.span, &e.message))
                .collect(),
        );
        diagnostics
            .entry(analysis.file(analysis.root).path.clone())
            .or_default()
            .push(d);
    }
    for (span, text) in warnings {
        let e = Error::new(span, text);
        let d = diagnostic(&analysis, &e, DiagnosticSeverity::WARNING);
        diagnostics
            .entry(analysis.file(span.file).path.clone())
            .or_default()
            .push(d);
    }
    // The items the cache lent go back to it, for the next keystroke.
    if let Some(c) = cache {
        c.reclaim(std::mem::take(&mut program.items), program.root);
    }
    let done = clock.elapsed().as_secs_f64();
    Report {
        diagnostics,
        analysis: root_parsed.then_some(analysis),
        times: [parsed, built - parsed, done - built],
    }
}

/// The spans of the `include` strings that led to a file, innermost first.
fn chain(a: &Analysis, file: FileId) -> Vec<Span> {
    let mut out = Vec::new();
    let mut cur = file;
    while let Some(inc) = a.includes.iter().find(|i| i.target == cur) {
        out.push(inc.span);
        cur = inc.span.file;
        if out.len() > a.files.len() {
            break;
        }
    }
    out
}

/// Whether an error is the editor's budget running out rather than a
/// mistake `raytrace` would report.
fn over_budget(e: &Error) -> bool {
    e.message
        == format!(
            "the scene program ran for more than {} evaluation steps",
            LIMITS.steps
        )
        || e.message == format!("the scene makes more than {} objects", LIMITS.objects)
}

fn diagnostic(a: &Analysis, e: &Error, mut severity: DiagnosticSeverity) -> Diagnostic {
    let f = a.file(e.span.file);
    let range = f.lines.range(&f.text, e.span.start, e.span.end);
    // The message as the command line prints it: the headline, the
    // label under the characters, and the help.
    let mut message = e.message.clone();
    if over_budget(e) {
        severity = DiagnosticSeverity::INFORMATION;
        message = format!(
            "the editor stopped checking here ({message}); `raytrace --check` checks the whole scene"
        );
    } else {
        if !e.label.is_empty() && e.label != "here" {
            message.push_str(&format!("\n{}", e.label));
        }
        if let Some(h) = &e.help {
            message.push_str(&format!("\nhelp: {h}"));
        }
    }
    let mut related: Vec<DiagnosticRelatedInformation> = e
        .notes
        .iter()
        .filter_map(|(span, note)| related(a, *span, note))
        .collect();
    for (k, inc) in chain(a, e.span.file).into_iter().enumerate() {
        let step = if k == 0 {
            "included from here"
        } else {
            "which is included from here"
        };
        related.extend(self::related(a, inc, step));
    }
    Diagnostic {
        range,
        severity: Some(severity),
        code: None,
        code_description: None,
        source: Some("raytrace".into()),
        message,
        related_information: (!related.is_empty()).then_some(related),
        tags: None,
        data: None,
    }
}

fn related(a: &Analysis, span: Span, note: &str) -> Option<DiagnosticRelatedInformation> {
    let f = a.file(span.file);
    if f.standard {
        return None;
    }
    Some(DiagnosticRelatedInformation {
        location: Location {
            uri: uri::from_path(&f.path)?,
            range: f.lines.range(&f.text, span.start, span.end),
        },
        message: note.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn only(r: &Report) -> &Vec<Diagnostic> {
        assert_eq!(r.diagnostics.len(), 1, "{:?}", r.diagnostics.keys());
        r.diagnostics.values().next().unwrap()
    }

    #[test]
    fn every_mistake_of_the_build_is_reported_in_file_order() {
        let t = "box { materail red }\nsphere { radus 1  centre <1, 2> }\n";
        let r = check(Path::new("/nonexistent/a.rt"), t, None);
        let d = only(&r);
        let firsts: Vec<&str> = d
            .iter()
            .map(|d| d.message.lines().next().unwrap())
            .collect();
        assert_eq!(firsts.len(), 3, "{firsts:?}");
        assert!(
            firsts[0].contains("`materail`") && firsts[1].contains("`radus`"),
            "{firsts:?}"
        );
        assert!(d.windows(2).all(|w| w[0].range.start <= w[1].range.start));
        assert!(
            d[0].message.contains("help: did you mean `material`?"),
            "{}",
            d[0].message
        );
    }

    /// Checks through one cache, edit after edit, report what checks
    /// without one do: the cache's items lent to each program come back
    /// right, includes spliced in or not.
    #[test]
    fn a_cached_check_reports_what_a_fresh_one_does() {
        let mut lines: Vec<String> = vec![
            "include \"std/metals.rt\"".into(),
            "union {\n  include \"std/metals.rt\"\n  sphere { material gold }\n}".into(),
        ];
        for k in 0..300 {
            lines.push(match k % 3 {
                0 => format!("sphere {{ centre <{k}, 0, 0>  radius 0.4  material gold }}"),
                1 => format!("let r{k} = {k} * 0.01"),
                _ => format!("box {{\n  min <{k}, 0, 0>\n  max <{k}.5, 1, 1>\n}}"),
            });
        }
        let path = Path::new("/nonexistent/cached.rt");
        let mut cache = ParseCache::new();
        let mut texts = vec![lines.join("\n")];
        let mut edit = |k: usize, line: &str| {
            lines[k] = line.to_string();
            texts.push(lines.join("\n"));
        };
        edit(150, "sphere { radus 1 }");
        edit(10, "include \"std/metals.rt\" sphere { material silver }");
        edit(200, "box { materail red }");
        edit(250, "let = 1");
        edit(250, "let x = 1.2.3");
        edit(250, "let x = 1");
        edit(0, "include \"missing.rt\"");
        edit(150, "sphere { radius 1 }");
        let first = texts[0].clone();
        texts.push(first);
        for (k, t) in texts.iter().enumerate() {
            let cached = check_with(path, t, None, Some(&mut cache));
            assert_eq!(cached.diagnostics, check(path, t, None).diagnostics, "{t}");
            // Each edit but the last changed one line: its chunk is parsed
            // again, and nothing lent was lost.
            if k > 0 && k < texts.len() - 1 {
                assert!(cache.last_parsed <= 1, "{k}: {} parsed", cache.last_parsed);
            }
        }
    }

    /// As above, for pseudo-random edits (inserted and deleted text,
    /// includes among it) of a scene with includes.
    #[test]
    fn a_cached_check_reports_what_a_fresh_one_does_after_random_edits() {
        const SNIPPETS: &[&str] = &[
            "{",
            "}",
            "\"",
            "/*",
            "*/",
            "\n",
            "include \"std/metals.rt\"\n",
            "union { include \"std/metals.rt\" }\n",
            "sphere { radus 1 }\n",
            "let = 1\n",
            "1.2.3 ",
            "else ",
            "\nor x",
            "material gold",
            "box {\n",
        ];
        let mut text = String::from("include \"std/metals.rt\"\n");
        for k in 0..60 {
            text.push_str(&format!(
                "sphere {{ centre <{k}, 0, 0>  material gold }}\nlet r{k} = {k}\n"
            ));
        }
        let path = Path::new("/nonexistent/random.rt");
        let mut cache = ParseCache::new();
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed as usize
        };
        let mut parsed = 0;
        // The last text whose brackets, strings and comments were closed.
        let mut good = text.clone();
        for _ in 0..300 {
            let at = crate::lang::source::floor_char_boundary(&text, next() % (text.len() + 1));
            let edited = match next() % 5 {
                // Back to the last closed text: a break and its fix.
                0 | 1 => good.clone(),
                2 => {
                    let end = (at + next() % 30).min(text.len());
                    let end = crate::lang::source::floor_char_boundary(&text, end);
                    format!("{}{}", &text[..at], &text[end..])
                }
                _ => format!(
                    "{}{}{}",
                    &text[..at],
                    SNIPPETS[next() % SNIPPETS.len()],
                    &text[at..]
                ),
            };
            text = edited;
            let cached = check_with(path, &text, None, Some(&mut cache));
            assert_eq!(
                cached.diagnostics,
                check(path, &text, None).diagnostics,
                "{text}"
            );
            if crate::lang::parser::check_brackets(&text, FileId(0)).is_empty() {
                parsed += 1;
                good = text.clone();
            }
        }
        // Most edits are past the bracket pass, where the cache works.
        assert!(parsed > 100, "{parsed} of 300");
    }

    #[test]
    fn warnings_are_warnings() {
        // An unbounded implicit surface renders, with a warning.
        let t = "implicit \"x + y\" { }\n";
        let r = check(Path::new("/nonexistent/w.rt"), t, None);
        let d = only(&r);
        assert!(!d.is_empty());
        assert!(
            d.iter()
                .all(|d| d.severity == Some(DiagnosticSeverity::WARNING)),
            "{d:?}"
        );
    }

    #[test]
    fn the_budget_turns_a_runaway_loop_into_a_note() {
        let t = "for i in 0..100000 { for j in 0..100000 { let a = i } }\n";
        let r = check(Path::new("/nonexistent/l.rt"), t, None);
        let d = only(&r);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].severity, Some(DiagnosticSeverity::INFORMATION));
        assert!(
            d[0].message
                .contains("`raytrace --check` checks the whole scene")
        );
    }

    #[test]
    fn a_cancelled_check_stops_early_and_quietly() {
        let t = "for i in 0..100000 { for j in 0..100000 { let a = i } }\n";
        let cancel = Arc::new(AtomicBool::new(false));
        cancel.store(true, Ordering::Relaxed);
        let start = std::time::Instant::now();
        let r = check(Path::new("/nonexistent/l.rt"), t, Some(cancel));
        assert!(only(&r).is_empty(), "a cancelled check reports nothing");
        // The uncancelled check runs 20 million steps; this one, a few thousand.
        assert!(start.elapsed() < std::time::Duration::from_millis(500));
    }

    #[test]
    fn an_unreadable_include_is_reported_at_its_string() {
        let t = "sphere { }\ninclude \"missing.rt\"\n";
        let r = check(Path::new("/nonexistent/i.rt"), t, None);
        let d = only(&r);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].range.start, lsp_types::Position::new(1, 8));
        assert!(
            d[0].message
                .starts_with("cannot find the included file `missing.rt`")
        );
    }
}
