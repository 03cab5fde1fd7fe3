//! Where tests find the workspace's shared data (the Stanford bunny, which
//! the project may not ship): `RAYTRACE_SHARED` if set, else `../shared`
//! beside the repository. A test that needs a file that is not there
//! fails, saying what it looked for, unless `RAYTRACE_SKIP_SHARED=1` says
//! to skip such tests (then [`file`] answers `None` and the test returns).
//! A silent skip would let a test pass without ever running.
//!
//! Shared, by `#[path]`, between the library's unit tests and the
//! integration tests; it uses only `std`.

use std::path::PathBuf;

/// The shared data folder's `data/` directory.
pub fn data_dir() -> PathBuf {
    let root = match std::env::var_os("RAYTRACE_SHARED") {
        Some(dir) => PathBuf::from(dir),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"),
    };
    root.join("data")
}

/// Whether `RAYTRACE_SKIP_SHARED` asks to skip tests whose data is absent.
pub fn skip_allowed() -> bool {
    std::env::var("RAYTRACE_SKIP_SHARED").is_ok_and(|v| v == "1")
}

/// The shared file `name` (in `data/`): `None` only when it is absent and
/// skipping is allowed; absent otherwise is a test failure.
pub fn file(name: &str) -> Option<PathBuf> {
    let path = data_dir().join(name);
    if path.is_file() {
        return Some(path);
    }
    assert!(
        skip_allowed(),
        "this test needs the shared file {} (not found). Point RAYTRACE_SHARED at the \
         folder holding data/{name}, or set RAYTRACE_SKIP_SHARED=1 to skip the tests \
         that need it",
        path.display()
    );
    // Straight to stderr: the harness would swallow `eprintln!` of a
    // passing test, and a skip must be seen.
    use std::io::Write;
    let _ = writeln!(
        std::io::stderr(),
        "skipped (RAYTRACE_SKIP_SHARED=1): {} is absent",
        path.display()
    );
    None
}
