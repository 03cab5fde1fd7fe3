//! End-to-end tests: one binary (link once), one module per area.

mod cli;
mod diagnostics;
mod examples;
mod lang;
mod render;
mod support;
mod textures;
