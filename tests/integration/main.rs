//! End-to-end tests: one binary (link once), one module per area.
mod mesh;
