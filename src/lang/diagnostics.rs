//! Mistakes in scene files. The parser and the builder collect [`Error`]s
//! (spans, no text); [`Problems`] turns them into miette diagnostics, one per
//! mistake, each with its own file, so that a mistake in an included file is
//! shown in that file with the chain of includes that led to it. All the
//! mistakes of a run are reported together under one headline.

use super::ast::Span;
use super::source::Sources;
use miette::{
    Diagnostic, LabeledSpan, MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents,
};
use std::fmt;
use std::sync::Arc;

/// A mistake found while reading or building, before rendering.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    pub span: Span,
    pub message: String,
    /// Text under the primary span.
    pub label: String,
    pub help: Option<String>,
    /// Secondary spans (e.g. where a block was opened, where a name was
    /// first defined).
    pub notes: Vec<(Span, String)>,
}

impl Error {
    pub fn new(span: Span, message: impl Into<String>) -> Error {
        Error {
            span,
            message: message.into(),
            label: "here".into(),
            help: None,
            notes: Vec::new(),
        }
    }

    pub fn label(mut self, label: impl Into<String>) -> Error {
        self.label = label.into();
        self
    }

    pub fn help(mut self, help: impl Into<String>) -> Error {
        self.help = Some(help.into());
        self
    }

    pub fn maybe_help(mut self, help: Option<String>) -> Error {
        if help.is_some() {
            self.help = help;
        }
        self
    }

    pub fn note(mut self, span: Span, text: impl Into<String>) -> Error {
        self.notes.push((span, text.into()));
        self
    }
}

/// The closest of `candidates` to `name`, if it is close enough to be a
/// likely misspelling. Case is ignored, and a swap of two neighbouring
/// letters counts as one edit (`materail` → `material`).
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let lower = name.to_lowercase();
    // One edit per three letters: `whte` → `white`, but a one-letter name
    // is never "close" to another one-letter name.
    let limit = name.chars().count() / 3;
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (strsim::osa_distance(&lower, &c.to_lowercase()), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, c)| (*d, c.len()))
        .map(|(_, c)| c)
}

/// `Some("did you mean `x`?")` when a candidate is close.
pub fn did_you_mean<'a>(
    name: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<String> {
    closest(name, candidates).map(|c| format!("did you mean `{c}`?"))
}

/// Lines up to this many bytes are shown whole in a snippet; longer ones
/// are cut to about this much around the mistake.
const LONG_LINE: usize = 200;

/// A file's text as miette reads it for snippets, with long lines cut down
/// to a window around the span: a mistake in a 10 MB one-line file shows
/// the few dozen characters that matter, not the whole line.
pub struct Excerpt {
    name: String,
    text: Arc<str>,
}

impl fmt::Debug for Excerpt {
    // The name and size only: a debug print of every problem must not
    // repeat a 10 MB file once per problem.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Excerpt({}, {} bytes)", self.name, self.text.len())
    }
}

impl Excerpt {
    pub fn new(name: &str, text: Arc<str>) -> Excerpt {
        Excerpt {
            name: printable(name),
            text: shown(text),
        }
    }
}

/// The text as it may be written to a terminal: each control character
/// (tabs and line breaks aside) replaced by `?` or `¿` of the same length
/// in bytes, so that every span still points at the same characters and a
/// terminal escape in a file is never sent to the user's terminal.
fn shown(text: Arc<str>) -> Arc<str> {
    let is_bad = |c: char| c.is_control() && !matches!(c, '\t' | '\n' | '\r');
    if !text.chars().any(is_bad) {
        return text;
    }
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match (is_bad(c), c.len_utf8()) {
            (false, _) => out.push(c),
            (true, 1) => out.push('?'),
            (true, _) => out.push('¿'), // C1 controls are two bytes, as is `¿`
        }
    }
    Arc::from(out)
}

/// A name (a path) with control characters escaped, for messages.
pub fn printable(name: &str) -> String {
    name.chars()
        .flat_map(|c| {
            let escaped = if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            };
            escaped.into_iter()
        })
        .collect()
}

impl SourceCode for Excerpt {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        before: usize,
        after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let bytes = self.text.as_bytes();
        let named = |data: &'a [u8], span: SourceSpan, line: usize, column: usize, lines: usize| {
            Ok(Box::new(MietteSpanContents::new_named(
                self.name.clone(),
                data,
                span,
                line,
                column,
                lines,
            )) as Box<dyn SpanContents<'a> + 'a>)
        };
        let full = bytes.read_span(span, before, after)?;
        // miette counts the column in bytes; the `file:line:col` it prints
        // comes from a read with no context lines, whose column is the
        // span's own: count it in characters, as an editor does.
        let column = |bytes_column: usize, at: usize| {
            if before > 0 {
                return bytes_column;
            }
            let text = &*self.text;
            let at = super::source::floor_char_boundary(text, at);
            let line_start = text[..at].rfind(['\n', '\r']).map_or(0, |i| i + 1);
            text[line_start..at].chars().count()
        };
        let longest = full.data().split(|&b| b == b'\n').map(<[u8]>::len).max();
        if longest.unwrap_or(0) <= LONG_LINE {
            return named(
                full.data(),
                *full.span(),
                full.line(),
                column(full.column(), span.offset()),
                full.line_count(),
            );
        }
        // A window on the span's own line, without context lines.
        let text = &*self.text;
        let floor = |i: usize| super::source::floor_char_boundary(text, i);
        let at = floor(span.offset());
        let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
        let line_end = text[at..].find('\n').map_or(text.len(), |i| at + i);
        let start = floor(at.saturating_sub(LONG_LINE / 4).max(line_start));
        let end = floor(
            (at + span.len())
                .max(at + LONG_LINE / 2)
                .min(start + LONG_LINE)
                .min(line_end),
        );
        let here = bytes.read_span(&(start, 0).into(), 0, 0)?;
        named(
            &bytes[start..end],
            (start, end - start).into(),
            here.line(),
            column(here.column(), start),
            1,
        )
    }
}

/// One mistake, ready to render.
#[derive(Debug)]
pub struct Problem {
    message: String,
    src: Option<Excerpt>,
    labels: Vec<LabeledSpan>,
    help: Option<String>,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Problem {}

impl Diagnostic for Problem {
    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.src.as_ref().map(|s| s as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        Some(Box::new(self.labels.iter().cloned()))
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help
            .as_ref()
            .map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }
}

impl Problem {
    pub fn message(&self) -> &str {
        &self.message
    }

    fn from_error(sources: &Sources, e: Error) -> Problem {
        let file = e.span.file;
        let text = &sources.get(file).text;
        // Spans from other parts (equation errors) are clamped to the file
        // and to character boundaries: miette slices the text with them.
        let clamp = |s: Span| {
            let a = super::source::floor_char_boundary(text, s.start);
            let mut b = super::source::floor_char_boundary(text, s.end.max(a));
            // A label that runs along one long line for more than a
            // snippet's width is cut there (the snippet is cut too).
            if b - a > LONG_LINE && !text.as_bytes()[a..a + LONG_LINE].contains(&b'\n') {
                b = super::source::floor_char_boundary(text, a + LONG_LINE);
            }
            (a, b - a)
        };
        let mut labels = vec![LabeledSpan::new_primary_with_span(
            Some(e.label),
            clamp(e.span),
        )];
        let mut help: Vec<String> = e.help.into_iter().collect();
        for (span, note) in e.notes {
            if span.file == file {
                labels.push(LabeledSpan::new_with_span(Some(note), clamp(span)));
            } else {
                help.push(format!("{note} (at {})", sources.location(span)));
            }
        }
        // The header names the file; the chain says how it was reached.
        for (k, inc) in sources.chain(file).into_iter().enumerate() {
            let step = if k == 0 {
                "included from"
            } else {
                "which is included from"
            };
            help.push(format!("{step} {}", sources.location(inc)));
        }
        Problem {
            message: e.message,
            src: Some(sources.excerpt(file)),
            labels,
            help: (!help.is_empty()).then(|| help.join("\n")),
        }
    }
}

/// A run reports at most this many mistakes: past that, more of them help
/// nobody, and a file of junk (a million stray `]`) would print for minutes.
pub const MAX_SHOWN: usize = 25;

/// Every mistake of a run: what `lang::load` and `scene::build` return.
/// With one mistake it renders as that mistake; with several, under a
/// headline ("3 errors in scene.rt") with each one as a related diagnostic.
#[derive(Debug)]
pub struct Problems {
    headline: String,
    problems: Vec<Problem>,
}

impl Problems {
    /// `errors` must not be empty. They are shown in file order.
    pub fn new(sources: &Sources, root: &str, mut errors: Vec<Error>) -> Problems {
        errors.sort_by_key(|e| (e.span.file, e.span.start));
        errors.dedup_by(|a, b| a.span == b.span && a.message == b.message);
        let n = errors.len();
        let problems: Vec<Problem> = errors
            .into_iter()
            .take(MAX_SHOWN)
            .map(|e| Problem::from_error(sources, e))
            .collect();
        let headline = if n > MAX_SHOWN {
            format!("{n} errors in {root}; the first {MAX_SHOWN} are shown")
        } else {
            format!("{n} errors in {root}")
        };
        Problems { headline, problems }
    }

    /// A problem with no place in a file (the scene file cannot be read).
    pub fn plain(message: String) -> Problems {
        Problems {
            headline: message.clone(),
            problems: vec![Problem {
                message,
                src: None,
                labels: Vec::new(),
                help: None,
            }],
        }
    }

    pub fn problems(&self) -> &[Problem] {
        &self.problems
    }

    pub fn len(&self) -> usize {
        self.problems.len()
    }

    pub fn is_empty(&self) -> bool {
        self.problems.is_empty()
    }

    fn single(&self) -> Option<&Problem> {
        match self.problems.as_slice() {
            [one] => Some(one),
            _ => None,
        }
    }
}

impl fmt::Display for Problems {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.single() {
            Some(p) => p.fmt(f),
            None => f.write_str(&self.headline),
        }
    }
}

impl std::error::Error for Problems {}

impl Diagnostic for Problems {
    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.single().and_then(|p| p.source_code())
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        self.single().and_then(|p| p.labels())
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.single().and_then(|p| p.help())
    }

    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn Diagnostic> + 'a>> {
        if self.single().is_some() {
            return None;
        }
        Some(Box::new(self.problems.iter().map(|p| p as &dyn Diagnostic)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excerpts_never_carry_control_characters() {
        let text: Arc<str> = Arc::from("a \u{1b}[31m b\u{9b}c\td\n");
        let e = Excerpt::new("x\u{1b}.rt", text.clone());
        assert_eq!(&*e.text, "a ?[31m b¿c\td\n");
        assert_eq!(e.text.len(), text.len(), "spans still fit");
        assert_eq!(e.name, "x\\u{1b}.rt");
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        // `é` and `€` are two and three bytes: `x` is the 5th character.
        let text: Arc<str> = Arc::from("é€  x\n");
        let e = Excerpt::new("a.rt", text);
        let at = "é€  ".len();
        let c = e.read_span(&(at, 1).into(), 0, 0).unwrap();
        assert_eq!((c.line(), c.column()), (0, 4));
    }

    #[test]
    fn suggestions_catch_typos_and_swaps() {
        let c = ["radius", "material", "centre", "center"];
        assert_eq!(closest("materail", c), Some("material"));
        assert_eq!(closest("radus", c), Some("radius"));
        assert_eq!(closest("Radius", c), Some("radius"));
        assert_eq!(closest("colour", c), None);
        assert_eq!(closest("q", ["x", "y", "z"]), None);
        assert_eq!(closest("whte", ["white", "black"]), Some("white"));
    }
}
