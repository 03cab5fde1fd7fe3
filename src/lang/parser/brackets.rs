//! The bracket pass, before pest: an unclosed `{` is reported where it
//! was opened (with the statement it belongs to) rather than at the end of
//! the file, and nesting is capped before the recursive-descent parser
//! could overflow the stack.

use super::*;

pub(super) struct Open {
    ch: char,
    at: usize,
}

pub(super) fn closer(open: char) -> char {
    match open {
        '{' => '}',
        '(' => ')',
        '[' => ']',
        _ => '>',
    }
}

/// Matches brackets, skipping comments and strings, so that a block that is
/// never closed is reported at its `{` with the statement it belongs to,
/// rather than at the end of the file.
pub fn check_brackets(text: &str, file: FileId) -> Vec<Error> {
    let b = text.as_bytes();
    let mut errors = Vec::new();
    let mut stack: Vec<Open> = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        match c {
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'/' if b.get(i + 1) == Some(&b'*') => match text[i + 2..].find("*/") {
                Some(n) => {
                    i += 2 + n + 2;
                    continue;
                }
                None => {
                    errors.push(
                        Error::new(Span::new(file, i, i + 2), "this comment is never closed")
                            .label("comment starts here")
                            .help("end a block comment with `*/`"),
                    );
                    return errors;
                }
            },
            b'"' => {
                let end = text[i + 1..].find(['"', '\n']).map(|n| i + 1 + n);
                match end {
                    Some(e) if b[e] == b'"' => {
                        i = e + 1;
                        continue;
                    }
                    _ => {
                        let e = end.unwrap_or(b.len());
                        errors.push(
                            Error::new(Span::new(file, i, e), "this string is not closed")
                                .label("no closing `\"` on this line")
                                .help("strings end on the line they start"),
                        );
                        i = e;
                        continue;
                    }
                }
            }
            // `<=` and `>=` compare; a `<` or `>` may be a comparison too,
            // so a `>` closes only a `<` on top, and an unmatched `<` is
            // dropped when a block opens or a bracket around it closes
            // (a vector holds neither).
            b'<' | b'>' if b.get(i + 1) == Some(&b'=') => {
                i += 2;
                continue;
            }
            b'>' if stack.last().is_some_and(|o| o.ch == '<') => {
                stack.pop();
            }
            b'>' => {}
            b'{' | b'(' | b'[' | b'<' => {
                if c == b'{' {
                    while stack.last().is_some_and(|o| o.ch == '<') {
                        stack.pop();
                    }
                }
                stack.push(Open {
                    ch: c as char,
                    at: i,
                });
                if stack.len() > MAX_NESTING {
                    errors.push(
                        Error::new(Span::new(file, i, i + 1), "brackets nest too deeply")
                            .label(format!("more than {MAX_NESTING} levels deep here"))
                            .help(format!(
                                "blocks, vectors, lists and parentheses may nest at most {MAX_NESTING} deep"
                            )),
                    );
                    return errors;
                }
            }
            b'}' | b')' | b']' => {
                let c = c as char;
                match stack.iter().rposition(|o| closer(o.ch) == c) {
                    Some(k) => {
                        // Anything opened after the match and not closed.
                        for o in stack.drain(k + 1..).rev().filter(|o| o.ch != '<') {
                            errors.push(
                                Error::new(
                                    Span::new(file, o.at, o.at + 1),
                                    format!("`{}` is never closed", o.ch),
                                )
                                .label(format!("this `{}` needs a `{}`", o.ch, closer(o.ch)))
                                .note(
                                    Span::new(file, i, i + 1),
                                    format!("expected `{}` before this", closer(o.ch)),
                                ),
                            );
                        }
                        stack.pop();
                    }
                    None => errors.push(
                        Error::new(
                            Span::new(file, i, i + 1),
                            format!("unexpected `{c}`: nothing here is open"),
                        )
                        .label("nothing to close"),
                    ),
                }
            }
            _ => {}
        }
        i += 1;
    }
    for o in stack {
        if o.ch == '<' && looks_like_comparison(b, o.at) {
            continue;
        }
        errors.push(unclosed_at_eof(text, file, &o));
    }
    errors
}

/// Whether the `<` at `at` reads as "less than" rather than a vector: a
/// value before it and a space after (`x < 1`, not `= <1, 2, 3`).
pub(super) fn looks_like_comparison(b: &[u8], at: usize) -> bool {
    let before = b[..at].iter().rev().find(|c| !c.is_ascii_whitespace());
    let value_before =
        before.is_some_and(|c| c.is_ascii_alphanumeric() || matches!(c, b')' | b']' | b'_' | b'.'));
    let space_after = b.get(at + 1).is_some_and(|c| c.is_ascii_whitespace());
    value_before && space_after
}

pub(super) fn unclosed_at_eof(text: &str, file: FileId, o: &Open) -> Error {
    // The last character of the file, so the label shows.
    let end = text.trim_end().len();
    let end = if end == 0 {
        0
    } else {
        crate::lang::source::floor_char_boundary(text, end - 1)
    };
    let end_span = Span::new(file, end, text.trim_end().len());
    if o.ch != '{' {
        return Error::new(
            Span::new(file, o.at, o.at + 1),
            format!("`{}` is never closed", o.ch),
        )
        .label(format!("this `{}` needs a `{}`", o.ch, closer(o.ch)))
        .note(end_span, "the file ends here");
    }
    let owner = block_owner(text, o.at);
    let what = owner
        .as_deref()
        .map_or("this block".to_string(), |w| format!("the block of `{w}`"));
    let mut err = Error::new(
        Span::new(file, o.at, o.at + 1),
        format!("{what} is never closed"),
    )
    .label(format!("{what} opens here"))
    .note(end_span, "the file ends before its `}`");
    if let Some((line, col_span, word)) = next_statement(text, o.at) {
        let name = owner.as_deref().unwrap_or("the block");
        err = err
            .help(format!(
                "did you mean to close `{name}` before `{word}` on line {line}?"
            ))
            .note(
                Span::new(file, col_span.0, col_span.1),
                format!("`{word}` starts a new statement"),
            );
    } else {
        err = err.help("add a `}` where the block should end");
    }
    err
}

/// The words before a `{` on its line: `sphere`, `material gold`,
/// `mesh "x.ply"`.
pub(super) fn block_owner(text: &str, brace: usize) -> Option<String> {
    let line_start = text[..brace].rfind('\n').map_or(0, |n| n + 1);
    let before = text[line_start..brace].trim();
    let before = before.rsplit(['{', '}']).next().unwrap_or("").trim();
    let words: Vec<&str> = before.split_whitespace().collect();
    match words.as_slice() {
        [] => None,
        [.., a, b] if STATEMENT_KEYWORDS.contains(a) => Some(format!("{a} {b}")),
        [.., b] => Some((*b).to_string()),
    }
}

pub(super) fn indent(line: &str) -> usize {
    line.len() - line.trim_start().len()
}

/// The first later line, indented no deeper than the line of the `{`,
/// that starts with a statement keyword: (line number, span of the word,
/// the word).
pub(super) fn next_statement(text: &str, brace: usize) -> Option<(usize, (usize, usize), String)> {
    let line_start = text[..brace].rfind('\n').map_or(0, |n| n + 1);
    let own_indent = indent(&text[line_start..]);
    let after = text[brace..].find('\n')? + brace + 1;
    let mut offset = after;
    let first_line = text[..after].matches('\n').count() + 1;
    for (line_no, line) in (first_line..).zip(text[after..].split('\n')) {
        let word: String = line
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if indent(line) <= own_indent && STATEMENT_KEYWORDS.contains(&word.as_str()) {
            let s = offset + indent(line);
            return Some((line_no, (s, s + word.len()), word));
        }
        offset += line.len() + 1;
    }
    None
}
