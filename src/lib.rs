//! The `pushlab` package as a library: the app, so that the UI tests in `tests/` can drive it
//! exactly as the binary does, and (on `wasm32`) the page that runs it in a browser tab.

pub mod app;
#[cfg(not(target_arch = "wasm32"))]
pub mod figures;
#[cfg(target_arch = "wasm32")]
pub mod web;

// A unit test that needs data beside the repository says so and is counted (see the file).
#[cfg(test)]
#[path = "../tests/skip.rs"]
mod skip;
