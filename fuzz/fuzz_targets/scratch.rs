//! Where the targets that need files write them: memory-backed /dev/shm when
//! there is one (millions of small writes), else the temporary directory.

use std::path::{Path, PathBuf};

/// `name` with this process's id appended, in the scratch directory.
pub fn scratch_path(name: &str) -> PathBuf {
    let base = if Path::new("/dev/shm").is_dir() {
        PathBuf::from("/dev/shm")
    } else {
        std::env::temp_dir()
    };
    base.join(format!("{name}-{}", std::process::id()))
}
