//! A time bound for tests: a regression that loops forever must fail the
//! run within a minute, not hang `cargo test` (or CI) for an hour.
//!
//! `let _watchdog = watchdog::start();` as a test's first line arms a timer
//! named after the test (the harness names each test's thread after it);
//! dropping the guard at the end of the test disarms it. If the test is
//! still running when the time is up, the timer writes which test overran
//! to stderr and ends the whole test process with a failure: a looping
//! thread cannot be stopped from outside, and leaving it to spin would
//! starve the tests after it. The bound is 60 s, or
//! `RAYTRACE_TEST_TIMEOUT_S` seconds (slow machines, debuggers).
//!
//! This file is shared, by `#[path]`, between the library's unit tests and
//! the integration tests; it uses only `std`.

use std::io::Write;
use std::sync::mpsc::{RecvTimeoutError, Sender, channel};
use std::time::Duration;

/// The default bound on one test's time.
const DEFAULT_LIMIT_S: u64 = 60;

/// The exit status of a test process stopped by the watchdog (that of
/// `timeout(1)`).
pub const TIMED_OUT: i32 = 124;

/// Disarms the timer when dropped (the test ended, passing or panicking).
pub struct Watchdog {
    _done: Sender<()>,
}

/// The bound: `RAYTRACE_TEST_TIMEOUT_S` if set to a positive number.
pub fn limit() -> Duration {
    let secs = std::env::var("RAYTRACE_TEST_TIMEOUT_S")
        .ok()
        .and_then(|s| s.trim().parse::<u64>().ok())
        .filter(|&s| s > 0)
        .unwrap_or(DEFAULT_LIMIT_S);
    Duration::from_secs(secs)
}

/// Arms the timer for the current test with [`limit`].
#[must_use = "the test is bounded only while the guard lives: `let _watchdog = …`"]
pub fn start() -> Watchdog {
    start_with(limit(), || {
        let _ = std::io::stderr().flush();
        std::process::exit(TIMED_OUT)
    })
}

/// Arms a timer that calls `on_timeout` (after reporting the test's name)
/// unless the guard is dropped within `limit`.
pub fn start_with(limit: Duration, on_timeout: impl FnOnce() + Send + 'static) -> Watchdog {
    let name = std::thread::current()
        .name()
        .unwrap_or("a test")
        .to_string();
    let (done, wait) = channel::<()>();
    std::thread::spawn(move || {
        // Dropping the sender (the guard) disconnects: the test ended.
        if let Err(RecvTimeoutError::Timeout) = wait.recv_timeout(limit) {
            // Straight to stderr: the harness captures only `eprint!`.
            let _ = writeln!(
                std::io::stderr(),
                "\nwatchdog: test `{name}` still running after {} s: stopped as a hang \
                 (an infinite loop?). Set RAYTRACE_TEST_TIMEOUT_S to allow longer.",
                limit.as_secs_f64()
            );
            on_timeout();
        }
    });
    Watchdog { _done: done }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};

    #[test]
    fn a_test_that_overruns_is_stopped_and_one_that_ends_is_not() {
        let fired = Arc::new(AtomicBool::new(false));
        let f = fired.clone();
        let guard = start_with(Duration::from_millis(20), move || {
            f.store(true, Ordering::SeqCst)
        });
        std::thread::sleep(Duration::from_millis(300));
        assert!(fired.load(Ordering::SeqCst), "the overrun was not caught");
        drop(guard);

        let fired = Arc::new(AtomicBool::new(false));
        let f = fired.clone();
        drop(start_with(Duration::from_millis(100), move || {
            f.store(true, Ordering::SeqCst)
        }));
        std::thread::sleep(Duration::from_millis(300));
        assert!(!fired.load(Ordering::SeqCst), "fired after the test ended");
    }
}
