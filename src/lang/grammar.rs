//! The one pest parser for both entry rules: `scene` (grammar/scene.pest)
//! and `equation` (grammar/equation.pest, used for the strings of
//! `implicit "…"`). Nothing outside `lang` and `implicit`'s parser imports
//! pest.

#[derive(pest_derive::Parser)]
#[grammar = "../grammar/scene.pest"]
#[grammar = "../grammar/equation.pest"]
pub struct RtParser;
