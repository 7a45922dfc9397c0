//! The `pushlab` package as a library: the desktop app, so that the UI tests in `tests/` can drive it
//! exactly as the binary does.

pub mod app;
