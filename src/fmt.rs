//! `raytrace fmt FILE...`: the canonical layout of `.rt` files, in the
//! manner of gofmt: the author's line breaks stay, and what is made
//! uniform is everything a reader should not have to think about.
//!
//! - Indentation: two spaces for each line opened by a `{`, `[` or `(`
//!   still open; a line that starts by closing one sits where its opener's
//!   line sits.
//! - Spacing at the places where the grammar ignores it: `a, b` (none
//!   before a comma, one after), none inside `( )` and `[ ]`, one inside
//!   `{ }` and before `{`, one on each side of `let`'s and `fn`'s `=`,
//!   `r: 0.2`.
//! - Everywhere else the grammar can tell "no space" from "space" (`a -b`
//!   is two values, `a - b` one; `xs[i]` indexes, `xs [i]` does not), so
//!   none stays none and some stays some: one space, or the run as it was
//!   where two or more line up columns.
//! - At most one blank line in a row, none at the start of the file, after
//!   a line that ends in `{` or before one that starts with `}`; no space at
//!   the end of a line; one line break at the end of the file.
//! - Comments and strings are kept byte for byte.
//!
//! The layout depends only on the tokens, the line breaks and which gaps
//! are empty, none of which it changes, so formatting twice gives what
//! formatting once gave. A file that does not parse is refused with the
//! parser's diagnostics: its tokens cannot be trusted.
//!
//! ```text
//! raytrace fmt scene.rt lib/*.rt    # rewrite in place (temporary + rename)
//! raytrace fmt --check scene.rt     # exit 1 and name the files that would change
//! raytrace fmt - < in.rt > out.rt   # stdin to stdout
//! ```

use crate::lang;
use clap::Parser;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

/// Lays out the scene text `text` canonically. The text must parse (see
/// [`check`]); text that does not still comes out, laid out as far as its
/// tokens allow.
pub fn format(text: &str) -> String {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let tokens = lex(text);
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    // The indentation of the line each open bracket is on.
    let mut open: Vec<usize> = Vec::new();
    let mut line_indent = 0;
    let mut prev: Option<&Token> = None;
    for t in &tokens {
        match prev {
            None => {
                line_indent = indent_for(t, &mut open);
                push_indent(&mut out, line_indent);
            }
            Some(p) if t.breaks > 0 => {
                let blank = t.breaks > 1
                    && !(p.kind == Kind::Open && p.text == "{")
                    && !(t.kind == Kind::Close && t.text == "}");
                out.push('\n');
                if blank {
                    out.push('\n');
                }
                line_indent = indent_for(t, &mut open);
                push_indent(&mut out, line_indent);
            }
            Some(p) => {
                if t.kind == Kind::Close {
                    open.pop();
                }
                for _ in 0..space_between(p, t) {
                    out.push(' ');
                }
            }
        }
        out.push_str(t.text);
        if t.kind == Kind::Open {
            open.push(line_indent);
        }
        prev = Some(t);
    }
    // An unclosed comment (only in text that does not parse) may end in
    // blanks of its own.
    out.truncate(out.trim_end().len());
    if !out.is_empty() {
        out.push('\n');
    }
    out
}

/// The indentation of a line that starts with `t`; a closer at the start
/// of a line closes its bracket here.
fn indent_for(t: &Token, open: &mut Vec<usize>) -> usize {
    if t.kind == Kind::Close {
        open.pop().unwrap_or(0)
    } else {
        open.last().map_or(0, |i| i + 1)
    }
}

fn push_indent(out: &mut String, level: usize) {
    for _ in 0..level {
        out.push_str("  ");
    }
}

/// Spaces between two tokens on one line: none or one where the grammar
/// ignores spacing; elsewhere none stays none. One space or more stays a
/// space, or the run as it was where two or more line up columns.
fn space_between(a: &Token, b: &Token) -> usize {
    let some = b.spaces.max(1);
    match (a.kind, b.kind) {
        (Kind::Open, Kind::Close) if a.text == "{" => 0,
        (_, Kind::Close) if b.text == "}" => some,
        (_, Kind::Close | Kind::Comma | Kind::Colon) => 0,
        (Kind::Open, _) if a.text == "{" => some,
        (Kind::Open, _) => 0,
        (Kind::Comma | Kind::Colon | Kind::Bind, _) | (_, Kind::Bind) => some,
        (_, Kind::Open) if b.text == "{" => some,
        (Kind::Close, _) if a.text == "}" => some,
        _ => b.spaces,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// `{`, `[` or `(`.
    Open,
    /// `}`, `]` or `)`.
    Close,
    Comma,
    /// The `:` of a named argument.
    Colon,
    /// A lone `=`: `let`'s, a default's, `fn f(x) = …`'s.
    Bind,
    /// `// …` to the end of its line.
    LineComment,
    /// Anything else, kept as written: names, numbers, operators,
    /// strings, `/* … */`.
    Other,
}

/// A token, with the gap before it: `breaks` line breaks, or `spaces`
/// columns of blank on the same line.
#[derive(Debug)]
struct Token<'a> {
    kind: Kind,
    text: &'a str,
    breaks: usize,
    spaces: usize,
}

/// Splits scene text into tokens. Only what the layout needs is told
/// apart; a run of other characters (`a-b`, `0..=12`, `#ff8000`) is one
/// token, kept whole.
fn lex(text: &str) -> Vec<Token<'_>> {
    let b = text.as_bytes();
    let mut tokens = Vec::new();
    let (mut breaks, mut spaces) = (0, 0);
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if matches!(c, b' ' | b'\t' | b'\r' | b'\n') {
            if c == b'\n' {
                breaks += 1;
                spaces = 0;
            } else if c != b'\r' {
                spaces += 1;
            }
            i += 1;
            continue;
        }
        let end = |k: Option<usize>| k.unwrap_or(b.len());
        let (kind, len) = match c {
            b'{' | b'[' | b'(' => (Kind::Open, 1),
            b'}' | b']' | b')' => (Kind::Close, 1),
            b',' => (Kind::Comma, 1),
            b':' => (Kind::Colon, 1),
            b'"' => {
                // To the closing quote (strings have no escapes and stay on
                // one line), or to the end of the line if there is none.
                let rest = &text[i + 1..];
                let k = rest.find(['"', '\n']);
                match k {
                    Some(k) if rest.as_bytes()[k] == b'"' => (Kind::Other, k + 2),
                    Some(k) => (Kind::Other, k + 1),
                    None => (Kind::Other, rest.len() + 1),
                }
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                let k = text[i..].find('\n').map(|k| i + k);
                let line = text[i..end(k)].trim_end();
                (Kind::LineComment, line.len())
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let k = text[i + 2..].find("*/").map(|k| k + 4);
                (Kind::Other, k.unwrap_or(b.len() - i))
            }
            b'=' => {
                // `==`, `<=`, `>=`, `!=` and `..=` are operators, spaced as
                // written; a lone `=` binds.
                let joined = b.get(i + 1) == Some(&b'=')
                    || (i > 0 && matches!(b[i - 1], b'=' | b'<' | b'>' | b'!' | b'.'));
                if joined {
                    (Kind::Other, 1)
                } else {
                    (Kind::Bind, 1)
                }
            }
            _ => {
                let k = text[i..]
                    .char_indices()
                    .find(|&(k, ch)| {
                        k > 0
                            && (ends_run(ch)
                                || text[i + k..].starts_with(['/']) && {
                                    let next = text[i + k + 1..].bytes().next();
                                    matches!(next, Some(b'/' | b'*'))
                                })
                    })
                    .map(|(k, _)| k);
                (Kind::Other, k.unwrap_or(b.len() - i))
            }
        };
        tokens.push(Token {
            kind,
            text: &text[i..i + len],
            breaks,
            spaces,
        });
        (breaks, spaces) = (0, 0);
        i += len;
        if kind == Kind::LineComment {
            // Trailing blanks of the comment's line are dropped.
            i = end(text[i..].find('\n').map(|k| i + k));
        }
    }
    tokens
}

/// Whether `c` ends a run of ordinary characters.
fn ends_run(c: char) -> bool {
    matches!(
        c,
        ' ' | '\t' | '\r' | '\n' | '{' | '}' | '[' | ']' | '(' | ')' | ',' | ':' | '"' | '='
    )
}

/// The parser's diagnostics for the file `name` holding `text`, if it has
/// any: the ones a render of it would print first.
pub fn check(name: &str, path: &Path, text: &str) -> Result<(), lang::diagnostics::Problems> {
    let mut sources = lang::source::Sources::default();
    let id = sources.add(lang::source::SourceFile {
        name: name.to_string(),
        path: path.to_path_buf(),
        text: Arc::from(text.strip_prefix('\u{feff}').unwrap_or(text)),
        included_from: None,
    });
    let text = sources.get(id).text.clone();
    let errors = match lang::control_character(&text, id) {
        Some(e) => vec![e],
        None => match lang::parser::parse(&text, id) {
            Ok(_) => return Ok(()),
            Err(errors) => errors,
        },
    };
    Err(lang::diagnostics::Problems::new(&sources, name, errors))
}

/// `raytrace fmt`'s command line.
#[derive(Parser, Debug)]
#[command(
    name = "raytrace fmt",
    about = "Lay out .rt files canonically (in place), keeping every comment",
    after_help = "Exit status:\n  0    done (with --check: every file is formatted)\n  1    a file has syntax errors (left untouched), or with --check a file would change\n  2    the command line is wrong\n  3    a file cannot be read or written"
)]
pub struct FmtArgs {
    /// The files to format in place; `-` reads stdin and writes stdout.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    /// Change nothing: name each file that is not formatted, and exit 1
    /// if there is one.
    #[arg(long)]
    pub check: bool,
}

/// `raytrace fmt ARGS...` (the arguments after `fmt`).
pub fn main() -> ExitCode {
    let args = FmtArgs::parse_from(
        std::iter::once("raytrace fmt".into()).chain(std::env::args_os().skip(2)),
    );
    ExitCode::from(run(&args))
}

/// Formats each file; the exit status (the worst file's).
pub fn run(args: &FmtArgs) -> u8 {
    let mut status = 0;
    for path in &args.files {
        let s = match one(path, args.check) {
            Ok(()) => 0,
            Err(Refusal::NotFormatted) => {
                println!("{}", path.display());
                1
            }
            Err(Refusal::Errors(report)) => {
                eprintln!("{report}");
                1
            }
            Err(Refusal::System(message)) => {
                eprintln!("error: {message}");
                3
            }
        };
        status = status.max(s);
    }
    status
}

enum Refusal {
    /// `--check` found a file that formatting would change.
    NotFormatted,
    /// The file does not parse: its diagnostics, rendered.
    Errors(String),
    /// The file cannot be read or written.
    System(String),
}

fn one(path: &Path, check_only: bool) -> Result<(), Refusal> {
    let stdin = path == Path::new("-");
    let text = if stdin {
        let mut s = String::new();
        std::io::Read::read_to_string(&mut std::io::stdin(), &mut s)
            .map_err(|e| Refusal::System(format!("cannot read stdin: {e}")))?;
        s
    } else {
        lang::source::read_text(path, lang::source::MAX_SCENE_BYTES)
            .map_err(|e| Refusal::System(format!("cannot read {}: {e}", path.display())))?
    };
    let name = if stdin {
        "<stdin>".to_string()
    } else {
        path.display().to_string()
    };
    check(&name, path, &text)
        .map_err(|p| Refusal::Errors(format!("{:?}", miette::Report::new(p))))?;
    let formatted = format(&text);
    if check_only {
        return if formatted == text {
            Ok(())
        } else {
            Err(Refusal::NotFormatted)
        };
    }
    if stdin {
        use std::io::Write;
        let mut out = std::io::stdout().lock();
        return out
            .write_all(formatted.as_bytes())
            .and_then(|_| out.flush())
            .map_err(|e| Refusal::System(format!("cannot write stdout: {e}")));
    }
    if formatted == text {
        return Ok(());
    }
    replace(path, &formatted)
        .map_err(|e| Refusal::System(format!("cannot write {}: {e}", path.display())))
}

/// Writes `text` to a temporary file beside `path` (with `path`'s
/// permissions) and renames it over `path`, so that the file is the old
/// text or the new, never a part of either.
fn replace(path: &Path, text: &str) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let tmp = dir.join(format!(".raytrace-fmt-{}.tmp", std::process::id()));
    let result = (|| {
        std::fs::write(&tmp, text)?;
        let permissions = std::fs::metadata(path)?.permissions();
        std::fs::set_permissions(&tmp, permissions)?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(s: &str) -> String {
        format(s)
    }

    #[test]
    fn blocks_are_indented_by_their_lines_and_closers_sit_with_their_opener() {
        let src = "sphere {\n        radius 1\nmaterial {\n colour red\n      }\n}\n";
        assert_eq!(
            f(src),
            "sphere {\n  radius 1\n  material {\n    colour red\n  }\n}\n"
        );
        // Two openers on one line indent the next line once.
        assert_eq!(
            f("group { union {\nsphere {}\n} }"),
            "group { union {\n  sphere {}\n} }\n"
        );
        assert_eq!(f("let xs = [\n1,\n2,\n]"), "let xs = [\n  1,\n  2,\n]\n");
    }

    #[test]
    fn spacing_is_made_uniform_only_where_the_grammar_ignores_it() {
        assert_eq!(
            f("let x=f( a ,b,r :0.2 ,  c)"),
            "let x = f(a, b, r: 0.2,  c)\n"
        );
        assert_eq!(f("sphere{radius 1}"), "sphere { radius 1 }\n");
        assert_eq!(f("fn g(a=1)=a*2"), "fn g(a = 1) = a*2\n");
        // A minus's spacing is meaning (`y -40` is two values); so is an
        // index's (`xs[0]` against `xs [0]`).
        assert_eq!(f("rotate y -40"), "rotate y -40\n");
        assert_eq!(f("let a = b - c"), "let a = b - c\n");
        assert_eq!(f("let a = xs[ 0 ]"), "let a = xs[0]\n");
        assert_eq!(f("matrix [1, 2]"), "matrix [1, 2]\n");
        assert_eq!(f("if a<=b and c == d { }"), "if a<=b and c == d {}\n");
        assert_eq!(
            f("for i in 0..=12 step 2 {}"),
            "for i in 0..=12 step 2 {}\n"
        );
    }

    #[test]
    fn aligned_columns_stay_aligned() {
        for src in [
            "sphere { centre <0, 1, 0>        radius 1    material chrome }\n",
            "material ruby   { colour #c01030 }\nlet White   = rgb(1, 1, 1)\n",
            "matrix [1, 0,  0, 1]\n",
        ] {
            assert_eq!(f(src), src);
        }
    }

    #[test]
    fn comments_and_strings_are_kept_byte_for_byte() {
        let src = "// head   \n\n\n/* a\n   block */ sphere { // why\n  radius 1/*x*/ }\n\
                   implicit \"x^2 +  y^2 = 1\" // eq";
        let out = f(src);
        assert_eq!(
            out,
            "// head\n\n/* a\n   block */ sphere { // why\n  radius 1/*x*/ }\nimplicit \"x^2 +  y^2 = 1\" // eq\n"
        );
    }

    #[test]
    fn blank_lines_are_at_most_one_and_never_at_a_block_s_edges() {
        assert_eq!(
            f("\n\na\n\n\n\nb {\n\n  c\n\n}\n\n\n"),
            "a\n\nb {\n  c\n}\n"
        );
        assert_eq!(f(""), "");
        assert_eq!(f("   \n\n"), "");
        // A tab is a column; two columns or more are an alignment, kept.
        assert_eq!(f("a\r\nb\tc\t d"), "a\nb c  d\n");
    }

    #[test]
    fn formatting_twice_gives_what_formatting_once_gave() {
        for src in [
            "a {\n b [ 1 ,\n2 ] ( c\n)\n}} ]\n",
            "x {\n}\n\n\n}\n",
            "\"unclosed\n{ /* open",
            ")))",
            "let a=b=c",
        ] {
            let once = f(src);
            assert_eq!(f(&once), once, "{src:?}");
        }
    }

    #[test]
    fn a_file_that_does_not_parse_is_refused_with_its_diagnostics() {
        let e = check("bad.rt", Path::new("bad.rt"), "sphere { radius 1 ").unwrap_err();
        let shown = format!("{:?}", miette::Report::new(e));
        assert!(shown.contains("bad.rt"), "{shown}");
        assert!(check("ok.rt", Path::new("ok.rt"), "sphere { radius 1 }").is_ok());
        assert!(check("c.rt", Path::new("c.rt"), "// \u{1b}[31m\n").is_err());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
        /// Any text, scene or not: formatting is idempotent, and keeps
        /// every non-blank character in order.
        #[test]
        fn idempotent_and_keeps_every_character(
            src in "[a-c0-9 \\n\\t{}\\[\\](),:=<>+/*\"#.-]{0,80}"
        ) {
            let once = f(&src);
            proptest::prop_assert_eq!(f(&once), once.clone());
            let ink = |s: &str| s.chars().filter(|c| !c.is_whitespace()).collect::<String>();
            proptest::prop_assert_eq!(ink(&once), ink(&src));
        }
    }
}
