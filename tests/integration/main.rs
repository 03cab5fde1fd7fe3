//! End-to-end tests: one binary (link once), one module per area.

mod cli;
mod csg;
mod diagnostics;
mod examples;
mod golden;
mod hostile;
mod lang;
mod mesh;
mod placement;
mod render;
mod support;
mod textures;
