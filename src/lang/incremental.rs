//! Re-parsing a file that changed a little (an editor's keystroke) without
//! parsing all of it again: pest reads about 3 MB a second, so a
//! 100,000-line scene took two seconds to parse on every keystroke.
//!
//! The text is cut into *chunks* at lines that surely start a new
//! top-level item; each chunk is parsed on its own, as if it were the
//! whole file, and kept by its text. On the next parse only the chunks
//! whose text is new are parsed; the others' items are copied with their
//! spans moved to where the chunk now starts. The result is exactly
//! [`parser::parse`]'s, errors included:
//!
//! - A cut is made only before a line whose first word is a name or a
//!   statement keyword, at bracket depth 0, outside comments and strings.
//!   No item of the grammar can go on with such a word after a line break
//!   (what can, `else`, `and`, `or`, `in`, `not`, `step`, operators,
//!   brackets and strings, is never cut before), so an item that parses
//!   within its chunk parses the same in the whole text, and ends there.
//! - A chunk that does not parse on its own (a syntax error, or a cut the
//!   grammar does not share, as inside a vector written over lines) is
//!   read by the whole-file parser's own steps on the whole text, from the
//!   chunk's start until an item ends just before a cut again, so every
//!   syntax error comes from the same parse as in a full parse.
//! - The bracket pass runs on the whole text first, as in a full parse: it
//!   is cheap, and it guarantees closed strings and comments for the
//!   cutting.

use super::ast::{Block, Expr, ExprKind, FileId, FnBody, FnDef, FnParam, ForSource, Item, Span};
use super::diagnostics::Error;
use super::parser::{self, Step};
use std::collections::HashMap;
use std::sync::Arc;

/// A chunk's items, parsed on their own (spans from the chunk's start),
/// with where the last ends; `None` when it did not parse on its own.
type Chunk = Option<(Vec<Result<Item, Error>>, usize)>;

/// The parses of the chunks of one file's last text, kept between parses
/// of that file.
#[derive(Default)]
pub struct ParseCache {
    chunks: HashMap<Box<str>, Arc<Chunk>>,
    /// How many chunks the last parse had, and how many of them it parsed.
    pub last_chunks: usize,
    pub last_parsed: usize,
}

impl ParseCache {
    pub fn new() -> ParseCache {
        ParseCache::default()
    }

    /// [`parser::parse`]'s result for `text`, re-parsing only what changed
    /// since the last call.
    pub fn parse(&mut self, text: &str, file: FileId) -> Result<Vec<Item>, Vec<Error>> {
        let errors = parser::check_brackets(text, file);
        if !errors.is_empty() {
            return Err(errors);
        }
        let starts = chunk_starts(text);
        let mut kept: HashMap<Box<str>, Arc<Chunk>> = HashMap::with_capacity(starts.len());
        let mut items = Vec::new();
        let mut errors = Vec::new();
        self.last_chunks = starts.len();
        self.last_parsed = 0;
        // Where the whole-file parse would stand: the end of the last item.
        let mut pos = 0;
        let mut k = 0;
        while k < starts.len() {
            let start = starts[k];
            let end = starts.get(k + 1).copied().unwrap_or(text.len());
            let piece = &text[start..end];
            let chunk = match kept.get(piece) {
                Some(c) => c.clone(),
                None => {
                    let (key, c) = match self.chunks.remove_entry(piece) {
                        Some(kc) => kc,
                        None => {
                            self.last_parsed += 1;
                            (Box::from(piece), Arc::new(parse_alone(piece, file)))
                        }
                    };
                    kept.insert(key, c.clone());
                    c
                }
            };
            if let Some((parsed, last_end)) = chunk.as_ref() {
                for r in parsed {
                    match r {
                        Ok(i) => items.push(moved_item(i, start, file)),
                        Err(e) => errors.push(moved_error(e, start, file)),
                    }
                }
                if !parsed.is_empty() {
                    pos = start + last_end;
                }
                k += 1;
                continue;
            }
            // The whole-file parse's steps from where it would stand: a
            // syntax error's "expected …" depends on where pest started.
            k = loop {
                match parser::step(text, pos, file) {
                    Step::End => break starts.len(),
                    Step::Syntax(e) => {
                        errors.push(e);
                        // The parse stops here, but the chunks after the
                        // mistake are kept for when it is fixed.
                        for (j, &s) in starts.iter().enumerate().skip(k + 1) {
                            let e = starts.get(j + 1).copied().unwrap_or(text.len());
                            if let Some((key, c)) = self.chunks.remove_entry(&text[s..e]) {
                                kept.insert(key, c);
                            }
                        }
                        self.chunks = kept;
                        return Err(errors);
                    }
                    Step::Item(r, next) => {
                        match r {
                            Ok(i) => items.push(i),
                            Err(e) => errors.push(e),
                        }
                        pos = next;
                        // Back on a cut: the chunks from there parse as
                        // in the whole text again.
                        if let Ok(m) = starts.binary_search(&skip_blank(text, pos)) {
                            break m;
                        }
                    }
                }
            };
        }
        self.chunks = kept;
        if errors.is_empty() {
            Ok(items)
        } else {
            Err(errors)
        }
    }
}

/// A chunk parsed as a file of its own: its items, or `None` at the first
/// syntax error.
fn parse_alone(text: &str, file: FileId) -> Chunk {
    let mut out = Vec::new();
    let mut pos = 0;
    loop {
        match parser::step(text, pos, file) {
            Step::End => return Some((out, pos)),
            Step::Syntax(_) => return None,
            Step::Item(r, next) => {
                out.push(r);
                pos = next;
            }
        }
    }
}

/// Words that may go on with the item before them (`else`, `and`, `or`,
/// `not`, and `in`, `step` of a `for`): never cut before.
const GOES_ON: &[&str] = &["else", "and", "or", "not", "in", "step"];

/// Where the chunks of `text` start: 0, then every line that surely
/// starts a new top-level item (see the module's comment). `text` has
/// passed the bracket pass, so its strings and comments are closed.
pub fn chunk_starts(text: &str) -> Vec<usize> {
    let b = text.as_bytes();
    let mut starts = vec![0];
    let mut depth = 0usize;
    let mut line_start = true;
    let mut i = 0;
    while i < b.len() {
        if line_start {
            line_start = false;
            while i < b.len() && matches!(b[i], b' ' | b'\t') {
                i += 1;
            }
            if depth == 0 && i > 0 && i < b.len() && (b[i].is_ascii_alphabetic() || b[i] == b'_') {
                let word_end = b[i..]
                    .iter()
                    .position(|c| !(c.is_ascii_alphanumeric() || *c == b'_'))
                    .map_or(b.len(), |n| i + n);
                if !GOES_ON.contains(&&text[i..word_end]) {
                    starts.push(i);
                }
            }
            continue;
        }
        match b[i] {
            b'\n' => {
                line_start = true;
                i += 1;
            }
            b'/' if b.get(i + 1) == Some(&b'/') => {
                i = b[i..]
                    .iter()
                    .position(|&c| c == b'\n')
                    .map_or(b.len(), |n| i + n);
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..].find("*/").map_or(b.len(), |n| i + 2 + n + 2);
            }
            b'"' => {
                i = match b[i + 1..].iter().position(|&c| c == b'"' || c == b'\n') {
                    Some(n) if b[i + 1 + n] == b'"' => i + 1 + n + 1,
                    Some(n) => i + 1 + n,
                    None => b.len(),
                };
            }
            b'{' | b'(' | b'[' => {
                depth += 1;
                i += 1;
            }
            b'}' | b')' | b']' => {
                depth = depth.saturating_sub(1);
                i += 1;
            }
            _ => i += 1,
        }
    }
    starts
}

/// Where the next token after `pos` starts: past blank space and
/// comments, as the grammar's WHITESPACE and COMMENT skip them (an
/// unclosed `/*` is no comment).
fn skip_blank(text: &str, mut pos: usize) -> usize {
    let b = text.as_bytes();
    loop {
        while pos < b.len() && matches!(b[pos], b' ' | b'\t' | b'\r' | b'\n') {
            pos += 1;
        }
        if b[pos..].starts_with(b"//") {
            pos = b[pos..]
                .iter()
                .position(|&c| c == b'\n')
                .map_or(b.len(), |n| pos + n);
        } else if b[pos..].starts_with(b"/*") {
            match text[pos + 2..].find("*/") {
                Some(n) => pos += 2 + n + 2,
                None => return pos,
            }
        } else {
            return pos;
        }
    }
}

fn moved(s: Span, by: usize, file: FileId) -> Span {
    Span::new(file, s.start + by, s.end + by)
}

fn moved_error(e: &Error, by: usize, file: FileId) -> Error {
    let mut e = e.clone();
    e.span = moved(e.span, by, file);
    for (s, _) in &mut e.notes {
        *s = moved(*s, by, file);
    }
    e
}

/// A copy of a chunk's item with every span `by` bytes later.
fn moved_item(i: &Item, by: usize, file: FileId) -> Item {
    if by == 0 && i.span().file == file {
        return i.clone();
    }
    let mut i = i.clone();
    shift_item(&mut i, by, file);
    i
}

fn shift_item(i: &mut Item, by: usize, file: FileId) {
    let m = |s: &mut Span| *s = moved(*s, by, file);
    match i {
        Item::Let { name, value, span } => {
            m(&mut name.span);
            shift_expr(value, by, file);
            m(span);
        }
        Item::Value(e) => shift_expr(e, by, file),
        Item::Str { span, content, .. } => {
            m(span);
            m(content);
        }
        Item::Include {
            span,
            string,
            content,
            ..
        } => {
            m(span);
            m(string);
            m(content);
        }
        Item::List(l) => {
            m(&mut l.span);
            for e in &mut l.node {
                shift_expr(e, by, file);
            }
        }
        Item::Block(b) => shift_block(b, by, file),
        Item::LetItems { name, items, span } => {
            m(&mut name.span);
            for i in items {
                shift_item(i, by, file);
            }
            m(span);
        }
        Item::For {
            var,
            source,
            body,
            span,
        } => {
            m(&mut var.span);
            match source.as_mut() {
                ForSource::Range { from, to, step, .. } => {
                    shift_expr(from, by, file);
                    shift_expr(to, by, file);
                    if let Some(s) = step {
                        shift_expr(s, by, file);
                    }
                }
                ForSource::Each(e) => shift_expr(e, by, file),
            }
            shift_block(body, by, file);
            m(span);
        }
        Item::If {
            cond,
            then,
            otherwise,
            span,
        } => {
            shift_expr(cond, by, file);
            shift_block(then, by, file);
            if let Some(o) = otherwise {
                shift_item(o, by, file);
            }
            m(span);
        }
        // Shared with the chunk's copy: rebuilt rather than changed.
        Item::Fn(def) => *def = Arc::new(moved_fn(def, by, file)),
        // Made by the evaluator, never by the parser.
        Item::Traced { items, .. } => {
            for i in items {
                shift_item(i, by, file);
            }
        }
    }
}

fn moved_fn(def: &FnDef, by: usize, file: FileId) -> FnDef {
    let expr = |e: &Expr| {
        let mut e = e.clone();
        shift_expr(&mut e, by, file);
        e
    };
    let mut name = def.name.clone();
    name.span = moved(name.span, by, file);
    FnDef {
        name,
        params: def
            .params
            .iter()
            .map(|p| {
                let mut name = p.name.clone();
                name.span = moved(name.span, by, file);
                FnParam {
                    name,
                    default: p.default.as_ref().map(expr),
                }
            })
            .collect(),
        body: match &def.body {
            FnBody::Expr(e) => FnBody::Expr(expr(e)),
            FnBody::Items(b) => {
                let mut b = b.clone();
                shift_block(&mut b, by, file);
                FnBody::Items(b)
            }
        },
        span: moved(def.span, by, file),
    }
}

fn shift_block(b: &mut Block, by: usize, file: FileId) {
    b.span = moved(b.span, by, file);
    for i in &mut b.items {
        shift_item(i, by, file);
    }
}

fn shift_expr(e: &mut Expr, by: usize, file: FileId) {
    e.span = moved(e.span, by, file);
    match &mut e.kind {
        ExprKind::Number(_)
        | ExprKind::Name(_)
        | ExprKind::Hex(_)
        | ExprKind::Value(_)
        | ExprKind::Bound(..) => {}
        ExprKind::Vector(v) | ExprKind::List(v) => {
            for x in v {
                shift_expr(x, by, file);
            }
        }
        ExprKind::Call { name, args, named } => {
            name.span = moved(name.span, by, file);
            for a in args {
                shift_expr(a, by, file);
            }
            for (n, a) in named {
                n.span = moved(n.span, by, file);
                shift_expr(a, by, file);
            }
        }
        ExprKind::Neg(x) | ExprKind::Not(x) => shift_expr(x, by, file),
        ExprKind::Index { base, index } => {
            shift_expr(base, by, file);
            shift_expr(index, by, file);
        }
        ExprKind::Binary { lhs, rhs, .. } => {
            shift_expr(lhs, by, file);
            shift_expr(rhs, by, file);
        }
    }
}

#[cfg(test)]
#[path = "incremental_tests.rs"]
mod tests;
