//! Re-parsing a file that changed a little (an editor's keystroke) without
//! parsing all of it again: pest reads about 3 MB a second, so a
//! 100,000-line scene took two seconds to parse on every keystroke.
//!
//! The text is cut into *chunks* at lines that surely start a new
//! top-level item; each chunk is parsed on its own, as if it were the
//! whole file, and kept by its text. On the next parse only the chunks
//! whose text is new are parsed; the others' items are reused, their
//! spans moved to where the chunk now starts (lent to the result and
//! given back, see [`ParseCache`]). The result is exactly
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

/// A chunk's items, parsed on their own, with where the last ends (from
/// the chunk's start).
struct Parsed {
    results: Vec<Result<Item, Error>>,
    last_end: usize,
    /// Whether its items may be lent to a parse's result rather than
    /// copied: all parsed, and no `include` (the loader replaces those by
    /// the included items, which [`ParseCache::reclaim`] could not tell
    /// apart).
    lendable: bool,
    /// While lent: how many items, where the first went in the parse's
    /// result, and the chunk's start then.
    lent: Option<(usize, usize, usize)>,
}

struct Entry {
    /// Where the chunk started when its spans were made.
    at: usize,
    /// `None` when the chunk did not parse on its own.
    parse: Option<Parsed>,
}

/// Where each item of the last parse's result came from, in order.
enum Slot {
    /// Items lent by an entry: (the entry, how many, the chunk's start, the
    /// first item's start).
    Lent(usize, usize, usize, usize),
    /// One item made or copied for the result; whether it is an `include`.
    Own(bool),
}

/// The parses of the chunks of one file's last text, kept between parses
/// of that file.
///
/// Copying 100,000 items costs as much as an evaluation, so a chunk's
/// items are moved into the result and, once the caller is done with the
/// program, moved back by [`ParseCache::reclaim`]. A chunk whose items
/// were not given back is parsed again.
#[derive(Default)]
pub struct ParseCache {
    index: HashMap<Box<str>, usize>,
    entries: Vec<Entry>,
    layout: Vec<Slot>,
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
        self.layout.clear();
        let errors = parser::check_brackets(text, file);
        if !errors.is_empty() {
            return Err(errors);
        }
        let starts = chunk_starts(text);
        let mut old_index = std::mem::take(&mut self.index);
        let mut old_entries: Vec<Option<Entry>> = std::mem::take(&mut self.entries)
            .into_iter()
            .map(Some)
            .collect();
        let mut index: HashMap<Box<str>, usize> = HashMap::with_capacity(starts.len());
        let mut entries: Vec<Entry> = Vec::with_capacity(starts.len());
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
            let e = match index.get(piece) {
                Some(&e) => e,
                None => {
                    let old = old_index
                        .remove_entry(piece)
                        .and_then(|(key, i)| Some((key, old_entries.get_mut(i)?.take()?)))
                        // Items never given back are gone.
                        .filter(|(_, e)| e.parse.as_ref().is_none_or(|p| p.lent.is_none()));
                    let (key, entry) = match old {
                        Some(ke) => ke,
                        None => {
                            self.last_parsed += 1;
                            (Box::from(piece), parse_alone(piece, file))
                        }
                    };
                    entries.push(entry);
                    index.insert(key, entries.len() - 1);
                    entries.len() - 1
                }
            };
            let entry = &mut entries[e];
            let by = start.wrapping_sub(entry.at) as isize;
            if let Some(p) = entry.parse.as_mut() {
                if let Some((n, first, was)) = p.lent {
                    // The same text twice: a copy of the first's items.
                    let by = start.wrapping_sub(was) as isize;
                    let copies: Vec<Item> = items[first..first + n]
                        .iter()
                        .map(|i| moved_item(i, by, file))
                        .collect();
                    self.layout
                        .extend(copies.iter().map(|i| Slot::Own(is_include(i))));
                    items.extend(copies);
                } else if p.lendable && !p.results.is_empty() {
                    let n = p.results.len();
                    let first = items.len();
                    // Lendable: every result is an item.
                    for mut i in p.results.drain(..).flatten() {
                        if by != 0 || i.span().file != file {
                            shift_item(&mut i, by, file);
                        }
                        items.push(i);
                    }
                    p.lent = Some((n, first, start));
                    if let Some(i) = items.get(first) {
                        self.layout.push(Slot::Lent(e, n, start, i.span().start));
                    }
                } else {
                    for r in &p.results {
                        match r {
                            Ok(i) => {
                                self.layout.push(Slot::Own(is_include(i)));
                                items.push(moved_item(i, by, file));
                            }
                            Err(x) => errors.push(moved_error(x, by, file)),
                        }
                    }
                }
                if p.lent.is_some() || !p.results.is_empty() {
                    pos = start + p.last_end;
                }
                k += 1;
                continue;
            }
            // The whole-file parse's steps from where it would stand: a
            // syntax error's "expected …" depends on where pest started.
            k = loop {
                match parser::step(text, pos, file) {
                    Step::End => break starts.len(),
                    Step::Syntax(x) => {
                        errors.push(x);
                        // The parse stops here, but the chunks after the
                        // mistake are kept for when it is fixed.
                        for (j, &s) in starts.iter().enumerate().skip(k + 1) {
                            let e = starts.get(j + 1).copied().unwrap_or(text.len());
                            let old = old_index
                                .remove_entry(&text[s..e])
                                .and_then(|(key, i)| Some((key, old_entries.get_mut(i)?.take()?)));
                            if let Some((key, entry)) = old
                                && !index.contains_key(&key)
                            {
                                entries.push(entry);
                                index.insert(key, entries.len() - 1);
                            }
                        }
                        break starts.len();
                    }
                    Step::Item(r, next) => {
                        match r {
                            Ok(i) => {
                                self.layout.push(Slot::Own(is_include(&i)));
                                items.push(i);
                            }
                            Err(x) => errors.push(x),
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
        self.index = index;
        self.entries = entries;
        if errors.is_empty() {
            Ok(items)
        } else {
            // The loader drops a file's items when it has errors: its
            // chunks' items come back now.
            self.give_back(items, None);
            Err(errors)
        }
    }

    /// Takes back the items the last [`parse`](Self::parse) lent, from the
    /// program built of them (`items`: its root file's items with every
    /// `include` spliced in, `root` that file). Only the lent items are
    /// kept; the rest are dropped.
    pub fn reclaim(&mut self, items: Vec<Item>, root: FileId) {
        self.give_back(items, Some(root));
    }

    /// `spliced`: the root file's id when the includes have been replaced
    /// by the included files' items (whose spans are in other files).
    fn give_back(&mut self, items: Vec<Item>, spliced: Option<FileId>) {
        let mut it = items.into_iter().peekable();
        for slot in std::mem::take(&mut self.layout) {
            match slot {
                Slot::Lent(e, n, at, first) => {
                    // Not where it was lent: something else changed the
                    // program, and what is left stays unclaimed.
                    if it.peek().is_none_or(|i| i.span().start != first) {
                        return;
                    }
                    let back: Vec<Result<Item, Error>> = it.by_ref().take(n).map(Ok).collect();
                    if back.len() != n {
                        return;
                    }
                    let Some(entry) = self.entries.get_mut(e) else {
                        return;
                    };
                    if let Some(p) = entry.parse.as_mut() {
                        p.results = back;
                        p.lent = None;
                        entry.at = at;
                    }
                }
                Slot::Own(true) if spliced.is_some() => {
                    while it.peek().is_some_and(|i| Some(i.span().file) != spliced) {
                        it.next();
                    }
                }
                Slot::Own(_) => {
                    it.next();
                }
            }
        }
    }
}

fn is_include(i: &Item) -> bool {
    matches!(i, Item::Include { .. })
}

/// Whether an `include` is among the items, at any depth.
pub(super) fn holds_include(items: &[Item]) -> bool {
    items.iter().any(|i| match i {
        Item::Include { .. } => true,
        Item::Block(b) => holds_include(&b.items),
        Item::LetItems { items, .. } | Item::Traced { items, .. } => holds_include(items),
        Item::For { body, .. } => holds_include(&body.items),
        Item::If {
            then, otherwise, ..
        } => {
            holds_include(&then.items)
                || otherwise
                    .as_deref()
                    .is_some_and(|o| holds_include(std::slice::from_ref(o)))
        }
        Item::Fn(f) => match &f.body {
            FnBody::Items(b) => holds_include(&b.items),
            FnBody::Expr(_) => false,
        },
        Item::Let { .. } | Item::Value(_) | Item::Str { .. } | Item::List(_) => false,
    })
}

/// A chunk parsed as a file of its own: its items, or no parse at the
/// first syntax error.
fn parse_alone(text: &str, file: FileId) -> Entry {
    let mut results = Vec::new();
    let mut pos = 0;
    loop {
        match parser::step(text, pos, file) {
            Step::End => break,
            Step::Syntax(_) => return Entry { at: 0, parse: None },
            Step::Item(r, next) => {
                results.push(r);
                pos = next;
            }
        }
    }
    let lendable = results.iter().all(|r| r.is_ok())
        && !results.iter().any(|r| {
            r.as_ref()
                .is_ok_and(|i| holds_include(std::slice::from_ref(i)))
        });
    Entry {
        at: 0,
        parse: Some(Parsed {
            results,
            last_end: pos,
            lendable,
            lent: None,
        }),
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

fn moved(s: Span, by: isize, file: FileId) -> Span {
    Span::new(
        file,
        s.start.wrapping_add_signed(by),
        s.end.wrapping_add_signed(by),
    )
}

fn moved_error(e: &Error, by: isize, file: FileId) -> Error {
    let mut e = e.clone();
    e.span = moved(e.span, by, file);
    for (s, _) in &mut e.notes {
        *s = moved(*s, by, file);
    }
    e
}

/// A copy of a chunk's item with every span `by` bytes later.
fn moved_item(i: &Item, by: isize, file: FileId) -> Item {
    if by == 0 && i.span().file == file {
        return i.clone();
    }
    let mut i = i.clone();
    shift_item(&mut i, by, file);
    i
}

fn shift_item(i: &mut Item, by: isize, file: FileId) {
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

fn moved_fn(def: &FnDef, by: isize, file: FileId) -> FnDef {
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

fn shift_block(b: &mut Block, by: isize, file: FileId) {
    b.span = moved(b.span, by, file);
    for i in &mut b.items {
        shift_item(i, by, file);
    }
}

fn shift_expr(e: &mut Expr, by: isize, file: FileId) {
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
