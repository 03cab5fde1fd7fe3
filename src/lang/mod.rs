//! Stage 1, PARSE: `.rt` text → a [`Program`]: the items of the scene file
//! with every `include` spliced in, each with its place in its file, and no
//! meaning yet (that is `scene::build`'s job). Nothing downstream of this
//! module sees pest.

pub mod ast;
pub mod diagnostics;
pub mod grammar;
pub mod incremental;
pub mod parser;
pub mod source;

use ast::{FileId, Item, Span};
use diagnostics::{Error, Problems};
use incremental::ParseCache;
use source::{SourceFile, Sources};
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

/// How deeply includes may nest (a chain of distinct files; cycles are
/// caught separately).
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// The budgets below hold for the whole scene, not per file: a file that
/// includes the next twice, 31 times over, is 2^31 includes of a small
/// file, and a nesting limit checked per file is passed by spreading the
/// nesting over files.
///
/// The most bytes of scene text read for one scene, root and every include
/// counted each time it is included.
pub const MAX_TOTAL_BYTES: u64 = source::MAX_SCENE_BYTES;
/// The most `include`s one scene may perform (each time counts).
pub const MAX_INCLUDES: usize = 4096;
/// How deeply blocks may nest in the whole scene, across includes: the
/// parser's per-file cap, applied to the spliced program.
pub const MAX_BLOCK_DEPTH: usize = parser::MAX_NESTING;

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
    let (program, errors) = load_text_all(path, text);
    if errors.is_empty() {
        Ok(program)
    } else {
        Err(program.problems(errors))
    }
}

/// As [`load_text`], giving the program (whatever of it parsed) with the
/// errors as they are, for a caller that shows them itself (the language
/// server publishes each in its own file).
pub fn load_text_all(path: &Path, text: String) -> (Program, Vec<Error>) {
    load_text_cached(path, text, None)
}

/// As [`load_text_all`], the root file parsed through `cache`, which
/// re-parses only what changed since its last text (an editor's
/// keystroke); the result is the same as without it.
pub fn load_text_cached(
    path: &Path,
    text: String,
    cache: Option<&mut ParseCache>,
) -> (Program, Vec<Error>) {
    let mut loader = Loader {
        sources: Sources::default(),
        errors: Vec::new(),
        bytes: text.len() as u64,
        includes: 0,
        over_budget: false,
        cache,
    };
    let name = path.display().to_string();
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    let (root, items) = loader.file(name, path.to_path_buf(), text, None, &[canonical], 0);
    let program = Program {
        sources: loader.sources,
        root,
        items,
    };
    (program, loader.errors)
}

struct Loader<'c> {
    sources: Sources,
    errors: Vec<Error>,
    /// Scene bytes read so far, every copy of every include counted.
    bytes: u64,
    /// `include`s performed so far.
    includes: usize,
    /// Set once a whole-scene budget is spent: one error says so, and no
    /// further file is read.
    over_budget: bool,
    /// For the root file only: included files are read from disk afresh.
    cache: Option<&'c mut ParseCache>,
}

impl Loader<'_> {
    fn file(
        &mut self,
        name: String,
        path: PathBuf,
        text: String,
        included_from: Option<Span>,
        chain: &[PathBuf],
        depth: usize,
    ) -> (FileId, Vec<Item>) {
        // A byte-order mark, as some Windows editors write, is no text.
        let text = match text.strip_prefix('\u{feff}') {
            Some(rest) => rest.to_owned(),
            None => text,
        };
        let id = self.sources.add(SourceFile {
            name,
            path,
            text: Arc::from(text),
            included_from,
        });
        let text = self.sources.get(id).text.clone();
        if let Some(e) = control_character(&text, id) {
            self.errors.push(e);
            return (id, Vec::new());
        }
        let parsed = match (included_from, self.cache.as_deref_mut()) {
            (None, Some(cache)) => cache.parse(&text, id),
            _ => parser::parse(&text, id),
        };
        let items = match parsed {
            Ok(items) => items,
            Err(errs) => {
                match included_from {
                    Some(at)
                        if !is_scene_name(&self.sources.get(id).path)
                            || errs.iter().any(|e| e.span.start <= first_token(&text)) =>
                    {
                        self.errors
                            .push(not_a_scene(at, &self.sources.get(id).name));
                    }
                    _ => self.errors.extend(errs),
                }
                return (id, Vec::new());
            }
        };
        (id, self.splice(items, id, chain, depth))
    }

    /// Replaces each `include` (at any depth) by the included file's items.
    /// `depth` is how many blocks enclose `items` in the whole scene, the
    /// including files' blocks counted.
    fn splice(
        &mut self,
        items: Vec<Item>,
        id: FileId,
        chain: &[PathBuf],
        depth: usize,
    ) -> Vec<Item> {
        let mut out = Vec::with_capacity(items.len());
        for item in items {
            match item {
                Item::Include {
                    text,
                    string,
                    content,
                    ..
                } => out.extend(self.include(&text, string, content, id, chain, depth)),
                // A file's own blocks nest at most MAX_BLOCK_DEPTH deep
                // (the bracket pass sees to it): a block at the top of a
                // file at the top of the scene, with no include inside, is
                // kept as it is rather than rebuilt (100,000 of them in a
                // large scene).
                Item::Block(b) if depth == 0 && !incremental::holds_include(&b.items) => {
                    out.push(Item::Block(b));
                }
                Item::Block(mut b) => {
                    if depth + 1 > MAX_BLOCK_DEPTH {
                        self.errors.push(
                            Error::new(b.span, "blocks nest too deeply across includes")
                                .label(format!("more than {MAX_BLOCK_DEPTH} blocks deep here"))
                                .help(format!(
                                    "blocks may nest at most {MAX_BLOCK_DEPTH} deep in the whole scene, the blocks around each `include` counted"
                                )),
                        );
                        continue;
                    }
                    b.items = self.splice(std::mem::take(&mut b.items), id, chain, depth + 1);
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
        depth: usize,
    ) -> Vec<Item> {
        if self.over_budget {
            return Vec::new();
        }
        let dir = self.sources.dir_of(from);
        let path = clean(&dir.join(rel));
        // `std/NAME` is the built-in library's file when it has one (a file
        // of the user's at that path is then not read: `./std/NAME` reaches
        // it), else a file on disk like any other.
        let standard = rel
            .strip_prefix(crate::stdlib::PREFIX)
            .and_then(crate::stdlib::get);
        let canonical = match standard {
            Some(_) => PathBuf::from(format!("<{rel}>")),
            None => match path.canonicalize() {
                Ok(c) => c,
                Err(_) => {
                    self.errors.push(missing_include(rel, &path, string));
                    return Vec::new();
                }
            },
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
        self.includes += 1;
        if self.includes > MAX_INCLUDES {
            self.over_budget = true;
            self.errors.push(
                Error::new(string, "too many includes")
                    .label(format!("include number {}", MAX_INCLUDES + 1))
                    .help(format!(
                        "a scene may perform at most {MAX_INCLUDES} includes in all (a file included twice counts twice)"
                    )),
            );
            return Vec::new();
        }
        let left = MAX_TOTAL_BYTES.saturating_sub(self.bytes);
        let read = match standard {
            Some(t) if t.len() as u64 > left => Err("above the limit".to_string()),
            Some(t) => Ok(t.to_string()),
            None => source::read_text(&canonical, left),
        };
        let text = match read {
            Ok(t) => t,
            Err(e) if e.contains("above the limit") => {
                self.over_budget = true;
                self.errors.push(
                    Error::new(string, "the scene's included text is too large")
                        .label(format!("this include passes {MAX_TOTAL_BYTES} bytes in all"))
                        .help(format!(
                            "a scene and all its includes may read at most {MAX_TOTAL_BYTES} bytes (a file included twice counts twice)"
                        )),
                );
                return Vec::new();
            }
            Err(e) => {
                self.errors.push(
                    Error::new(string, format!("cannot read the included file `{rel}`")).label(e),
                );
                return Vec::new();
            }
        };
        let _ = content;
        self.bytes += text.len() as u64;
        let (name, path) = match standard {
            Some(_) => (rel.to_string(), canonical.clone()),
            None => (path.display().to_string(), path),
        };
        let mut chain = chain.to_vec();
        chain.push(canonical);
        self.file(name, path, text, Some(string), &chain, depth).1
    }
}

/// An include whose file is not there; under `std/`, with the library's
/// closest name.
fn missing_include(rel: &str, path: &Path, string: Span) -> Error {
    let e = Error::new(string, format!("cannot find the included file `{rel}`"));
    if rel.starts_with(crate::stdlib::PREFIX) {
        let names: Vec<String> = crate::stdlib::include_names().collect();
        let e = e.label("not a file of the standard library");
        return match diagnostics::did_you_mean(rel, names.iter().map(String::as_str)) {
            Some(hint) => e.help(hint),
            None => e.help(format!("the standard library has {}", names.join(", "))),
        };
    }
    e.label(format!("looked for {}", path.display()))
        .help("an include path is relative to the folder of the file that includes it")
}

/// The first control character in a scene's text (tabs and line breaks
/// aside), as an error. Terminal escapes would be echoed into the user's
/// terminal by the excerpt of a later error (`ESC[31m` also reads as an
/// unclosed `[`), and only binary data or a mangled file holds them.
pub(crate) fn control_character(text: &str, file: FileId) -> Option<Error> {
    let (at, c) = text
        .char_indices()
        .find(|&(_, c)| c.is_control() && !matches!(c, '\t' | '\n' | '\r'))?;
    let name = match c {
        '\u{1b}' => " (ESC, a terminal escape)".to_string(),
        '\0' => " (NUL)".to_string(),
        _ => String::new(),
    };
    Some(
        Error::new(
            Span::new(file, at, at + c.len_utf8()),
            format!(
                "the text holds a control character U+{:04X}{name}",
                c as u32
            ),
        )
        .label("here")
        .help("a scene is plain text; is this a scene file?"),
    )
}

/// Whether a file's name says it is a scene (`.rt`, or `.inc` as POV-Ray
/// users name theirs): a file named otherwise that does not parse is
/// reported as no scene, without echoing its lines.
fn is_scene_name(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("rt") || e.eq_ignore_ascii_case("inc"))
}

/// Where the first token of a file starts: after blank space and
/// comments. An included file whose first token is already wrong is no
/// scene at all.
fn first_token(text: &str) -> usize {
    let mut rest = text;
    loop {
        let trimmed = rest.trim_start();
        if let Some(r) = trimmed.strip_prefix("//") {
            rest = r.find('\n').map_or("", |i| &r[i..]);
        } else if let Some(r) = trimmed.strip_prefix("/*") {
            match r.find("*/") {
                Some(i) => rest = &r[i + 2..],
                None => return text.len(),
            }
        } else {
            return text.len() - trimmed.len();
        }
    }
}

/// One error at the `include`, instead of the included file's lines echoed
/// in a cascade of syntax errors.
fn not_a_scene(at: Span, name: &str) -> Error {
    Error::new(at, format!("`{name}` is not a scene file"))
        .label("included here")
        .help("it does not parse as a scene: include only `.rt` scene files")
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
