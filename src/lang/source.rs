//! Loaded files and the include chains between them. Every span in the AST
//! names a [`FileId`] here, so that a diagnostic can show the right file,
//! its line and column, and how it was included.

use super::ast::{FileId, Span};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// One loaded file.
#[derive(Debug)]
pub struct SourceFile {
    /// As shown in messages: the path as given for the root, and relative
    /// to the root's folder for includes where possible.
    pub name: String,
    pub path: PathBuf,
    pub text: Arc<str>,
    /// The span of the `include "…"` string that loaded this file.
    pub included_from: Option<Span>,
}

/// Every file of a program, indexed by [`FileId`]. A file included twice is
/// loaded twice (each copy has its own include chain).
#[derive(Debug, Default)]
pub struct Sources {
    files: Vec<SourceFile>,
}

impl Sources {
    pub fn add(&mut self, file: SourceFile) -> FileId {
        self.files.push(file);
        FileId((self.files.len() - 1) as u32)
    }

    pub fn get(&self, id: FileId) -> &SourceFile {
        &self.files[id.0 as usize]
    }

    pub fn len(&self) -> usize {
        self.files.len()
    }

    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// The source for miette: named, so reports print `file:line:col`.
    pub fn excerpt(&self, id: FileId) -> super::diagnostics::Excerpt {
        let f = self.get(id);
        super::diagnostics::Excerpt::new(&f.name, f.text.clone())
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, id: FileId, offset: usize) -> (usize, usize) {
        line_col(&self.get(id).text, offset)
    }

    /// `a.rt:3:9`
    pub fn location(&self, span: Span) -> String {
        let (l, c) = self.line_col(span.file, span.start);
        format!("{}:{l}:{c}", self.get(span.file).name)
    }

    /// The include chain of a file, innermost first: the spans of the
    /// `include` strings that led to it.
    pub fn chain(&self, id: FileId) -> Vec<Span> {
        let mut out = Vec::new();
        let mut cur = self.get(id).included_from;
        while let Some(s) = cur {
            out.push(s);
            if out.len() > self.files.len() {
                break; // cannot happen (cycles are refused), but never loop
            }
            cur = self.get(s.file).included_from;
        }
        out
    }

    /// The folder a path in this file is relative to.
    pub fn dir_of(&self, id: FileId) -> PathBuf {
        self.get(id)
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default()
    }
}

pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text[..floor_char_boundary(text, offset)];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

pub fn floor_char_boundary(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// Largest scene or include file read (far above any hand-written scene).
pub const MAX_SCENE_BYTES: u64 = 64 << 20;

/// Reads a file the user named, refusing what is not a regular file (a
/// folder, `/dev/zero`, a FIFO or a terminal would fail, never end, or
/// block) and anything over `limit` bytes, before reading it whole. The
/// error is a sentence for a diagnostic.
pub fn read_bounded(path: &Path, limit: u64) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let meta = std::fs::metadata(path).map_err(|e| e.to_string())?;
    if meta.is_dir() {
        return Err("it is a folder, not a file".into());
    }
    if !meta.is_file() {
        return Err("it is not a regular file (a device, pipe or socket)".into());
    }
    let too_big = |n: u64| format!("it is {n} bytes, above the limit of {limit} bytes");
    if meta.len() > limit {
        return Err(too_big(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    // The size can change between the look and the read: read one byte
    // more than allowed to tell.
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| e.to_string())?;
    if bytes.len() as u64 > limit {
        return Err(too_big(bytes.len() as u64));
    }
    Ok(bytes)
}

/// [`read_bounded`] for text.
pub fn read_text(path: &Path, limit: u64) -> Result<String, String> {
    String::from_utf8(read_bounded(path, limit)?).map_err(|e| {
        format!(
            "it is not UTF-8 text (a binary file?): the byte at offset {} is invalid",
            e.utf8_error().valid_up_to()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_and_columns_are_one_based() {
        let t = "ab\ncd\n€x";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 9), (3, 2));
    }
}
