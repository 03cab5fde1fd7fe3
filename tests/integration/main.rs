//! End-to-end tests: one binary (link once), one module per area.

mod cli;
mod examples;
mod render;
mod support;
