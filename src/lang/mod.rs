//! Stage 1, PARSE: `.rt` text → an AST with spans, no meaning yet.
//! (Placeholder until the front end lands.)

pub mod grammar;

use std::path::Path;

/// A parsed scene file with its includes.
#[derive(Debug)]
pub struct Program;

pub fn load(path: &Path) -> miette::Result<Program> {
    Err(miette::miette!("cannot parse {} yet", path.display()))
}
