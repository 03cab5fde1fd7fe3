//! What the server knows about a checked document besides its mistakes:
//! every file the program read (the document and its includes), the names
//! it defines (`let`, `fn`, `material`, loop variables, parameters) with
//! where they are visible, the `include` strings, and an outline. Built
//! from the parser's items, so it knows exactly the forms `raytrace` does.

use super::positions::LineIndex;
use crate::lang::Program;
use crate::lang::ast::{FileId, FnBody, FnDef, ForSource, Item, Span};
use std::path::PathBuf;
use std::sync::Arc;

/// One file of the program.
#[derive(Debug)]
pub struct File {
    pub path: PathBuf,
    /// As shown in messages (`std/metals.rt` for the library).
    pub name: String,
    pub text: Arc<str>,
    pub lines: LineIndex,
    /// A file of the built-in standard library (no file on disk).
    pub standard: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DefKind {
    Let,
    Fn,
    Material,
    LoopVar,
    Param,
}

/// A name the program defines.
#[derive(Clone, Debug)]
pub struct Def {
    pub name: String,
    pub kind: DefKind,
    /// The name where it is defined.
    pub span: Span,
    /// The block it is local to (`None`: the top level, visible after it).
    pub scope: Option<Span>,
    /// One line for hovers: `let r = 0.5`, `fn pillar(h, r = 0.3)`.
    pub signature: String,
    /// What it is, when known: `0.5 (a number)`, `an object (`sphere`)`.
    pub value: Option<String>,
}

/// An `include "…"` string and the file it read.
#[derive(Clone, Debug)]
pub struct Include {
    /// The quoted string, in the including file.
    pub span: Span,
    pub target: FileId,
}

/// A line of the outline.
#[derive(Clone, Debug)]
pub struct Symbol {
    pub name: String,
    pub detail: Option<String>,
    pub kind: lsp_types::SymbolKind,
    /// The whole statement, and the part to select (its name).
    pub span: Span,
    pub selection: Span,
    pub children: Vec<Symbol>,
}

#[derive(Debug)]
pub struct Analysis {
    pub files: Vec<File>,
    pub root: FileId,
    pub defs: Vec<Def>,
    pub includes: Vec<Include>,
    pub outline: Vec<Symbol>,
}

impl Analysis {
    pub fn new(program: &Program, values: &[crate::eval::TopLevel]) -> Analysis {
        let sources = &program.sources;
        let files = (0..sources.len())
            .map(|i| {
                let f = sources.get(FileId(i as u32));
                File {
                    path: f.path.clone(),
                    name: f.name.clone(),
                    lines: LineIndex::new(&f.text),
                    text: f.text.clone(),
                    standard: f.name.starts_with(crate::stdlib::PREFIX)
                        && f.path.to_string_lossy().starts_with('<'),
                }
            })
            .collect();
        let includes = (0..sources.len())
            .filter_map(|i| {
                let f = sources.get(FileId(i as u32));
                f.included_from.map(|span| Include {
                    span,
                    target: FileId(i as u32),
                })
            })
            .collect();
        let mut a = Analysis {
            files,
            root: program.root,
            defs: Vec::new(),
            includes,
            outline: Vec::new(),
        };
        a.collect(&program.items, None);
        let by_span: std::collections::HashMap<Span, &crate::eval::TopLevel> =
            values.iter().map(|v| (v.span, v)).collect();
        for d in &mut a.defs {
            if d.scope.is_none()
                && let Some(v) = by_span.get(&d.span)
            {
                d.value = v.value.as_ref().map(|v| match v {
                    crate::eval::expr::Value::Items(_) => v.kind(),
                    _ => format!("{} ({})", v.show(), v.kind()),
                });
            }
        }
        let lets: std::collections::HashSet<String> = a
            .defs
            .iter()
            // Object values (`let wheel = union { … }`), which are placed by name.
            .filter(|d| d.kind == DefKind::Let && d.signature.ends_with("{ … }"))
            .map(|d| d.name.clone())
            .collect();
        a.outline = outline(&a, &lets, &program.items, program.root);
        a
    }

    pub fn file(&self, id: FileId) -> &File {
        &self.files[id.0 as usize]
    }

    /// The source text a span covers, on one line and cut to `max` characters.
    pub fn snippet(&self, span: Span, max: usize) -> String {
        let text = &self.file(span.file).text;
        let floor = |i| crate::lang::source::floor_char_boundary(text, i);
        let s = &text[floor(span.start)..floor(span.end.max(span.start))];
        let one: String = s.split_whitespace().collect::<Vec<_>>().join(" ");
        if one.chars().count() > max {
            let cut: String = one.chars().take(max).collect();
            format!("{cut}…")
        } else {
            one
        }
    }

    fn def(
        &mut self,
        name: &crate::lang::ast::Spanned<String>,
        kind: DefKind,
        scope: Option<Span>,
        signature: String,
    ) {
        self.defs.push(Def {
            name: name.node.clone(),
            kind,
            span: name.span,
            scope,
            signature,
            value: None,
        });
    }

    fn collect(&mut self, items: &[Item], scope: Option<Span>) {
        for (i, item) in items.iter().enumerate() {
            match item {
                Item::Let { name, value, .. } => {
                    let sig = format!("let {} = {}", name.node, self.snippet(value.span, 60));
                    self.def(name, DefKind::Let, scope, sig);
                }
                Item::LetItems {
                    name,
                    items: body,
                    span,
                } => {
                    let head = body
                        .first()
                        .map_or(String::new(), |h| self.snippet(h.span(), 30));
                    self.def(
                        name,
                        DefKind::Let,
                        scope,
                        format!("let {} = {head} {{ … }}", name.node),
                    );
                    let inner = body.iter().find_map(|b| match b {
                        Item::Block(b) => Some(b.span),
                        _ => None,
                    });
                    self.collect(body, inner.or(Some(*span)));
                }
                Item::Fn(def) => {
                    let sig = signature(self, def);
                    self.def(&def.name, DefKind::Fn, scope, sig.clone());
                    for p in &def.params {
                        self.def(
                            &p.name,
                            DefKind::Param,
                            Some(def.span),
                            format!("parameter of `{sig}`"),
                        );
                    }
                    if let FnBody::Items(b) = &def.body {
                        self.collect(&b.items, Some(b.span));
                    }
                }
                Item::For {
                    var,
                    source,
                    body,
                    span,
                } => {
                    let over = match source.as_ref() {
                        ForSource::Range { from, to, .. } => {
                            self.snippet(from.span.to(to.span), 40)
                        }
                        ForSource::Each(e) => self.snippet(e.span, 40),
                    };
                    self.def(
                        var,
                        DefKind::LoopVar,
                        Some(*span),
                        format!("loop variable: for {} in {over}", var.node),
                    );
                    self.collect(&body.items, Some(body.span));
                }
                Item::If {
                    then, otherwise, ..
                } => {
                    self.collect(&then.items, Some(then.span));
                    if let Some(o) = otherwise {
                        self.collect(std::slice::from_ref(o.as_ref()), scope);
                    }
                }
                Item::Block(b) => self.collect(&b.items, Some(b.span)),
                Item::Traced { items, .. } => self.collect(items, scope),
                _ if item.as_name().is_some_and(|n| n.node == "material") => {
                    // `material NAME { … }` declares; `material NAME` alone uses.
                    if let (Some(name), Some(Item::Block(b))) =
                        (items.get(i + 1).and_then(Item::as_name), items.get(i + 2))
                    {
                        let n = crate::lang::ast::Spanned::new(name.node.to_string(), name.span);
                        let sig = format!("material {} {}", name.node, self.snippet(b.span, 70));
                        self.def(&n, DefKind::Material, scope, sig);
                    }
                }
                _ => {}
            }
        }
    }

    /// The definitions of `name` visible at byte `at` of file `file`,
    /// innermost first: local ones whose block holds the place, then
    /// top-level ones (the last before the place first, then later ones,
    /// which are an error to use but still where the name is).
    pub fn visible(&self, name: &str, file: FileId, at: usize) -> Vec<&Def> {
        let holds = |s: Span| s.file == file && s.start <= at && at <= s.end;
        let mut local: Vec<&Def> = self
            .defs
            .iter()
            .filter(|d| d.name == name && d.scope.is_some_and(holds))
            .collect();
        local.sort_by_key(|d| d.scope.map_or(usize::MAX, |s| s.len()));
        let before = |d: &&Def| d.span.file != file || d.span.start <= at;
        let mut top: Vec<&Def> = self
            .defs
            .iter()
            .filter(|d| d.name == name && d.scope.is_none())
            .collect();
        // Before the place (in this file, or in an include) beats after.
        top.sort_by_key(|d| !before(d));
        let (b, a): (Vec<&Def>, Vec<&Def>) = top.into_iter().partition(before);
        local.extend(b.into_iter().rev());
        local.extend(a);
        local
    }

    /// Every name visible at a place, each once (innermost wins).
    pub fn names_at(&self, file: FileId, at: usize) -> Vec<&Def> {
        let mut out: Vec<&Def> = Vec::new();
        for d in &self.defs {
            let visible = match d.scope {
                None => true,
                Some(s) => s.file == file && s.start <= at && at <= s.end,
            };
            if visible && !out.iter().any(|o| o.name == d.name) {
                out.push(d);
            }
        }
        out
    }
}

fn signature(a: &Analysis, def: &FnDef) -> String {
    let params: Vec<String> = def
        .params
        .iter()
        .map(|p| match &p.default {
            Some(d) => format!("{} = {}", p.name.node, a.snippet(d.span, 20)),
            None => p.name.node.clone(),
        })
        .collect();
    let body = match &def.body {
        FnBody::Expr(e) => format!(" = {}", a.snippet(e.span, 50)),
        FnBody::Items(_) => " { … }".to_string(),
    };
    format!("fn {}({}){body}", def.name.node, params.join(", "))
}

/// The outline of the document's own statements (not its includes').
fn outline(
    a: &Analysis,
    lets: &std::collections::HashSet<String>,
    items: &[Item],
    file: FileId,
) -> Vec<Symbol> {
    use lsp_types::SymbolKind as K;
    let mut out = Vec::new();
    let mut i = 0;
    while i < items.len() {
        let item = &items[i];
        i += 1;
        if item.span().file != file {
            continue;
        }
        let sym = |name: String,
                   kind: K,
                   span: Span,
                   selection: Span,
                   detail: Option<String>,
                   children| Symbol {
            name,
            detail,
            kind,
            span,
            selection,
            children,
        };
        match item {
            Item::Let { name, value, span } => out.push(sym(
                name.node.clone(),
                K::CONSTANT,
                *span,
                name.span,
                Some(a.snippet(value.span, 40)),
                Vec::new(),
            )),
            Item::LetItems {
                name,
                items: body,
                span,
            } => {
                let head = body
                    .first()
                    .and_then(Item::as_name)
                    .map(|n| n.node.to_string());
                let kind = match head.as_deref() {
                    Some("material") => K::STRUCT,
                    Some(h) if crate::scene::is_object(h) => K::OBJECT,
                    _ => K::CONSTANT,
                };
                let children = outline(a, lets, body, file)
                    .into_iter()
                    .flat_map(|s| s.children)
                    .collect();
                out.push(sym(
                    name.node.clone(),
                    kind,
                    *span,
                    name.span,
                    head,
                    children,
                ));
            }
            Item::Fn(def) => out.push(sym(
                def.name.node.clone(),
                K::FUNCTION,
                def.span,
                def.name.span,
                Some(signature(a, def)),
                match &def.body {
                    FnBody::Items(b) => outline(a, lets, &b.items, file),
                    FnBody::Expr(_) => Vec::new(),
                },
            )),
            Item::For {
                var, body, span, ..
            } => out.push(sym(
                format!("for {}", var.node),
                K::NAMESPACE,
                *span,
                var.span,
                None,
                outline(a, lets, &body.items, file),
            )),
            Item::If {
                then,
                span,
                otherwise,
                ..
            } => {
                let mut children = outline(a, lets, &then.items, file);
                if let Some(o) = otherwise {
                    children.extend(outline(a, lets, std::slice::from_ref(o.as_ref()), file));
                }
                out.push(sym(
                    "if".into(),
                    K::NAMESPACE,
                    *span,
                    Span::new(span.file, span.start, span.start + 2),
                    None,
                    children,
                ));
            }
            Item::Block(b) => out.extend(outline(a, lets, &b.items, file)),
            _ => {
                let Some(word) = item.as_name() else { continue };
                let w = word.node;
                // A statement: the word, perhaps a string or a name, and its block.
                let mut end = item.span();
                let mut detail = None;
                let mut name = w.to_string();
                let mut children = Vec::new();
                let mut j = i;
                if let Some(Item::Str { text, span, .. }) = items.get(j) {
                    detail = Some(format!("\"{text}\""));
                    end = end.to(*span);
                    j += 1;
                }
                if w == "material"
                    && let Some(n) = items.get(j).and_then(Item::as_name)
                    && matches!(items.get(j + 1), Some(Item::Block(_)))
                {
                    name = format!("material {}", n.node);
                    j += 1;
                }
                let kind = match w {
                    "camera" => K::EVENT,
                    "light" | "ambient" | "environment" => K::EVENT,
                    "render" => K::PACKAGE,
                    "material" => K::STRUCT,
                    _ if crate::scene::is_object(w) => K::OBJECT,
                    _ if lets.contains(w) => K::OBJECT,
                    _ => continue,
                };
                if let Some(Item::Block(b)) = items.get(j) {
                    end = end.to(b.span);
                    children = outline(a, lets, &b.items, file)
                        .into_iter()
                        .filter(|s| s.kind == K::OBJECT || s.kind == K::NAMESPACE)
                        .collect();
                    j += 1;
                } else if !matches!(w, "ambient") {
                    // A name alone is a use (`material gold` in a block), or
                    // an object value placed as it is.
                    if !(kind == K::OBJECT && lets.contains(w)) {
                        continue;
                    }
                }
                if w == "ambient" {
                    // `ambient COLOUR intensity K …` runs to the next statement.
                    while let Some(next) = items.get(j) {
                        let stop = next.as_name().is_some_and(|n| {
                            crate::lang::parser::STATEMENT_KEYWORDS.contains(&n.node)
                                && n.node != "ambient"
                        }) || !matches!(next, Item::Value(_) | Item::Block(_));
                        if stop {
                            break;
                        }
                        end = end.to(next.span());
                        j += 1;
                    }
                }
                i = j;
                out.push(sym(name, kind, end, word.span, detail, children));
            }
        }
    }
    out
}
