//! `pushlab`: the desktop app (no subcommand, or `open`) and the headless commands; built for
//! `wasm32`, the page (`pushlab::web`, see `scripts/web`).

#[cfg(not(target_arch = "wasm32"))]
mod cli;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::run()
}

/// In a page, `main` runs when the wasm module is initialised: it starts the app and returns.
#[cfg(target_arch = "wasm32")]
fn main() {
    wasm_bindgen_futures::spawn_local(async {
        if let Err(why) = pushlab::web::start().await {
            let why = why.as_string().unwrap_or_else(|| format!("{why:?}"));
            web_sys::console::error_1(&format!("pushlab could not start: {why}").into());
        }
    });
}
