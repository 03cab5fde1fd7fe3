//! End-to-end tests: one binary (link once), one module per area.

mod accel;
mod adaptive;
mod cli;
mod csg;
mod diagnostics;
mod eval;
mod examples;
mod farm;
mod fmt;
mod geometry;
mod golden;
mod hostile;
mod integrator;
mod lang;
mod looks;
mod lsp;
mod many;
mod material_parts;
mod media;
mod mesh;
mod mesh_formats;
mod patterns;
mod placement;
mod render;
#[path = "../../src/shared_data.rs"]
mod shared_data;
mod speed;
mod stdlib;
mod support;
mod textures;
mod watch;
#[path = "../../src/watchdog.rs"]
mod watchdog;
