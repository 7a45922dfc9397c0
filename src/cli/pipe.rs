//! Piping a command's output into `head` ends it quietly, as other command-line tools do.
//!
//! Rust ignores SIGPIPE, so `println!` into a closed pipe panics ("failed printing to stdout:
//! Broken pipe") — a backtrace for `pushlab validate DIR | head`. The headless commands restore the
//! default action: the process ends silently when the reader goes away. The app keeps Rust's
//! default; its windowing sockets must report a closed peer as an error, not end the process.

/// Restores the default SIGPIPE action (end the process) for a headless command.
#[cfg(unix)]
#[allow(unsafe_code)]
pub fn end_quietly_on_closed_pipe() {
    // SAFETY: called once at the start of `main`'s command dispatch, before any thread is started;
    // `signal` with SIG_DFL installs no handler code.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Elsewhere a closed pipe stays an error.
#[cfg(not(unix))]
pub fn end_quietly_on_closed_pipe() {}
