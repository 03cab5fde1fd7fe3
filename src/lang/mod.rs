//! Stage 1, PARSE: `.rt` text → a [`Program`]: the items of the scene file
//! with every `include` spliced in, each with its place in its file, and no
//! meaning yet (that is `scene::build`'s job). Nothing downstream of this
//! module sees pest.

pub mod ast;
pub mod diagnostics;
pub mod grammar;
pub mod parser;
pub mod source;

use ast::{FileId, Item, Span};
use diagnostics::{Error, Problems};
use source::{SourceFile, Sources};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// How deeply includes may nest (a chain of distinct files; cycles are
/// caught separately).
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// A parsed scene file with its includes spliced in, in order.
#[derive(Debug)]
pub struct Program {
    pub sources: Sources,
    pub root: FileId,
    pub items: Vec<Item>,
}

impl Program {
    /// The root file's name as shown in messages.
    pub fn name(&self) -> &str {
        &self.sources.get(self.root).name
    }

    /// Turns build errors into the report for this program.
    pub fn problems(&self, errors: Vec<Error>) -> Problems {
        Problems::new(&self.sources, self.name(), errors)
    }
}

/// Reads and parses a scene file and everything it includes. Every syntax
/// error of every file is reported together.
pub fn load(path: &Path) -> Result<Program, Problems> {
    let text = source::read_text(path, source::MAX_SCENE_BYTES)
        .map_err(|e| Problems::plain(format!("cannot read {}: {e}", path.display())))?;
    load_text(path, text)
}

/// As [`load`], with the root file's text given (includes are still read
/// relative to `path`'s folder).
pub fn load_text(path: &Path, text: String) -> Result<Program, Problems> {
    let mut loader = Loader {
        sources: Sources::default(),
        errors: Vec::new(),
    };
    let name = path.display().to_string();
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    let (root, items) = loader.file(name, path.to_path_buf(), text, None, &[canonical]);
    let program = Program {
        sources: loader.sources,
        root,
        items,
    };
    if loader.errors.is_empty() {
        Ok(program)
    } else {
        Err(program.problems(loader.errors))
    }
}

struct Loader {
    sources: Sources,
    errors: Vec<Error>,
}

impl Loader {
    fn file(
        &mut self,
        name: String,
        path: PathBuf,
        text: String,
        included_from: Option<Span>,
        chain: &[PathBuf],
    ) -> (FileId, Vec<Item>) {
        let id = self.sources.add(SourceFile {
            name,
            path,
            text: Arc::from(text),
            included_from,
        });
        let text = self.sources.get(id).text.clone();
        let items = match parser::parse(&text, id) {
            Ok(items) => items,
            Err(errs) => {
                self.errors.extend(errs);
                return (id, Vec::new());
            }
        };
        (id, self.splice(items, id, chain))
    }

    /// Replaces each `include` (at any depth) by the included file's items.
    fn splice(&mut self, items: Vec<Item>, id: FileId, chain: &[PathBuf]) -> Vec<Item> {
        let mut out = Vec::with_capacity(items.len());
        for item in items {
            match item {
                Item::Include {
                    text,
                    string,
                    content,
                    ..
                } => out.extend(self.include(&text, string, content, id, chain)),
                Item::Block(mut b) => {
                    b.items = self.splice(std::mem::take(&mut b.items), id, chain);
                    out.push(Item::Block(b));
                }
                other => out.push(other),
            }
        }
        out
    }

    fn include(
        &mut self,
        rel: &str,
        string: Span,
        content: Span,
        from: FileId,
        chain: &[PathBuf],
    ) -> Vec<Item> {
        let dir = self.sources.dir_of(from);
        let path = clean(&dir.join(rel));
        let Ok(canonical) = path.canonicalize() else {
            let e = Error::new(string, format!("cannot find the included file `{rel}`"))
                .label(format!("looked for {}", path.display()))
                .help("an include path is relative to the folder of the file that includes it");
            self.errors.push(e);
            return Vec::new();
        };
        if let Some(k) = chain.iter().position(|p| *p == canonical) {
            let names: Vec<String> = chain[k..]
                .iter()
                .chain(std::iter::once(&canonical))
                .map(|p| {
                    p.file_name()
                        .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
                })
                .collect();
            self.errors.push(
                Error::new(string, "include cycle")
                    .label("this includes a file that is already being included")
                    .help(format!("the chain is {}", names.join(" → "))),
            );
            return Vec::new();
        }
        if chain.len() >= MAX_INCLUDE_DEPTH {
            self.errors.push(
                Error::new(string, "includes nest too deeply")
                    .label(format!("more than {MAX_INCLUDE_DEPTH} files deep")),
            );
            return Vec::new();
        }
        let text = match source::read_text(&canonical, source::MAX_SCENE_BYTES) {
            Ok(t) => t,
            Err(e) => {
                self.errors.push(
                    Error::new(string, format!("cannot read the included file `{rel}`")).label(e),
                );
                return Vec::new();
            }
        };
        let _ = content;
        let mut chain = chain.to_vec();
        chain.push(canonical);
        let name = path.display().to_string();
        self.file(name, path, text, Some(string), &chain).1
    }
}

/// `a/./b/../c` → `a/c`, without touching the file system (for names in
/// messages; symbolic links do not matter there).
fn clean(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            c => out.push(c),
        }
    }
    out
}
