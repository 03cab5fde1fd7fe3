//! The standard library: scene files compiled into the binary and read by
//! `include "std/NAME.rt"` (see `lang::Loader::include`). Each is plain
//! `.rt` text, parsed like any include and counted in the include budgets;
//! `docs/std.md` lists what each defines, with a swatch of every material.
//!
//! Adding a file is one line in [`FILES`]; then `scripts/std_swatches.sh`
//! renders its materials' swatches and docs/std.md gets its section (a
//! test checks that every material is shown there).

/// Every standard file: its name after `std/`, and its text.
pub const FILES: &[(&str, &str)] = &[
    ("colours.rt", include_str!("colours.rt")),
    ("metals.rt", include_str!("metals.rt")),
    ("glass.rt", include_str!("glass.rt")),
    ("woods.rt", include_str!("woods.rt")),
    ("stones.rt", include_str!("stones.rt")),
];

/// The folder an include names to reach the library: `include "std/metals.rt"`.
pub const PREFIX: &str = "std/";

/// The text of `std/NAME` (the name as written after `std/`).
pub fn get(name: &str) -> Option<&'static str> {
    FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, text)| *text)
}

/// Every file's name as an include writes it, `std/colours.rt` …
pub fn include_names() -> impl Iterator<Item = String> {
    FILES.iter().map(|(n, _)| format!("{PREFIX}{n}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_unique_scene_files() {
        let mut names: Vec<&str> = FILES.iter().map(|(n, _)| *n).collect();
        assert!(names.iter().all(|n| n.ends_with(".rt") && !n.contains('/')));
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), FILES.len());
        assert!(get("metals.rt").unwrap().contains("material gold"));
        assert!(get("metal.rt").is_none());
    }
}
