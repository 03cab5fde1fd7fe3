//! A guard around third-party decoders (PLY, images) fed user bytes. A panic
//! inside one must not take the render down, and must not print Rust's panic
//! message before our own diagnostic either: the user would see a "bug"
//! report for what is only a malformed file.
//!
//! The process-wide panic hook is wrapped once; it stays silent while the
//! current thread is inside [`catch_quietly`] and defers to the previous hook
//! everywhere else, so real bugs still report (and a fuzzer's abort-on-panic
//! hook still fires on panics that nothing catches).

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

thread_local! {
    static QUIET: Cell<bool> = const { Cell::new(false) };
}

static WRAP_HOOK: Once = Once::new();

/// Runs `f`, turning a panic into `None` without printing anything.
pub fn catch_quietly<T>(f: impl FnOnce() -> T) -> Option<T> {
    WRAP_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let outer = QUIET.replace(true);
    let result = catch_unwind(AssertUnwindSafe(f));
    QUIET.set(outer);
    result.ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_becomes_none_and_a_value_passes_through() {
        assert_eq!(catch_quietly(|| 7), Some(7));
        let r: Option<()> = catch_quietly(|| panic!("mangled input"));
        assert_eq!(r, None);
        // Nested guards restore the outer state.
        assert_eq!(
            catch_quietly(|| catch_quietly(|| panic!("inner")).is_none()),
            Some(true)
        );
        assert!(!QUIET.with(Cell::get));
    }
}
