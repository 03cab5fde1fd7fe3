//! End-to-end tests: one binary (link once), one module per area.

mod cli;
mod diagnostics;
mod examples;
mod hostile;
mod lang;
mod mesh;
mod render;
mod support;
mod textures;
