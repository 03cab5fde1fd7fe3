//! End-to-end tests: one binary (link once), one module per area.

mod cli;
mod csg;
mod diagnostics;
mod eval;
mod examples;
mod geometry;
mod golden;
mod hostile;
mod lang;
mod looks;
mod mesh;
mod render;
mod support;
mod textures;
