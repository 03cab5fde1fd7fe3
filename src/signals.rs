//! Ending on a signal as a shell expects: every catchable signal that would
//! terminate the program removes the half-written image first, then exits
//! with 128 + the signal's number (130 for Ctrl-C, 143 for SIGTERM, 129
//! for SIGHUP).
//!
//! A signal handler may do almost nothing safely, so it only writes the
//! signal's number into a pipe; a thread reading the pipe does the work
//! (the self-pipe pattern).

use std::sync::atomic::{AtomicI32, Ordering};

/// The signals whose default action ends the process and that can be
/// caught. SIGPIPE is left ignored, as Rust sets it (a closed pipe is an
/// I/O error, reported as one).
pub const HANDLED: [libc::c_int; 11] = [
    libc::SIGHUP,
    libc::SIGINT,
    libc::SIGQUIT,
    libc::SIGTERM,
    libc::SIGUSR1,
    libc::SIGUSR2,
    libc::SIGALRM,
    libc::SIGXCPU,
    libc::SIGXFSZ,
    libc::SIGVTALRM,
    libc::SIGPROF,
];

static PIPE_WRITE: AtomicI32 = AtomicI32::new(-1);

extern "C" fn on_signal(signal: libc::c_int) {
    let byte = signal as u8;
    let fd = PIPE_WRITE.load(Ordering::Relaxed);
    // SAFETY: write(2) is async-signal-safe; the buffer is one live byte.
    unsafe {
        libc::write(fd, (&byte as *const u8).cast(), 1);
    }
}

/// Installs the handlers; on a signal `cleanup` runs on a helper thread
/// and the process exits with 128 + the signal. Returns false if the
/// handlers could not be installed (the program then runs without them).
pub fn install(cleanup: fn()) -> bool {
    let mut fds = [0 as libc::c_int; 2];
    // SAFETY: pipe(2) fills the two-element array it is given.
    if unsafe { libc::pipe(fds.as_mut_ptr()) } != 0 {
        return false;
    }
    PIPE_WRITE.store(fds[1], Ordering::Relaxed);
    let read = fds[0];
    std::thread::spawn(move || {
        let mut byte = 0u8;
        loop {
            // SAFETY: reads one byte into a live local.
            let n = unsafe { libc::read(read, (&mut byte as *mut u8).cast(), 1) };
            if n == 1 {
                cleanup();
                std::process::exit(128 + i32::from(byte));
            }
            if n == 0 {
                return;
            }
        }
    });
    for signal in HANDLED {
        // SAFETY: a zeroed sigaction with a plain handler and an empty mask
        // is valid; `on_signal` has the C signature sigaction expects.
        unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
            action.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            if libc::sigaction(signal, &action, std::ptr::null_mut()) != 0 {
                return false;
            }
        }
    }
    true
}
