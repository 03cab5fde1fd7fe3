//! Stage 2, EVALUATE: between parsing (`lang`) and building (`scene::build`).
//! Expressions, values and names live here; the builder receives items
//! whose values are already worked out.

pub mod expr;
