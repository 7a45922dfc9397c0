//! `window.pushlab`: the page's hook for end-to-end tests and a teacher's script. The page's
//! `index.html` defines `window.pushlab = { state, command }` over the two functions exported here;
//! what they read and send is `crate::app::hook`'s.

use std::cell::RefCell;

use wasm_bindgen::prelude::*;

use crate::app::hook::{HookCommand, Shown};

thread_local! {
    /// `state()`'s answer as of the newest frame drawn.
    static SHOWN: RefCell<Option<Shown>> = const { RefCell::new(None) };
    /// Commands waiting for the next frame.
    static INBOX: RefCell<Vec<HookCommand>> = const { RefCell::new(Vec::new()) };
    /// The runner, kept for the page's life (dropping it would stop the app).
    static RUNNER: RefCell<Option<eframe::WebRunner>> = const { RefCell::new(None) };
}

/// What is shown, as JSON (see `crate::app::hook::Shown`); `null` before the first frame. A command
/// sent and not yet done makes it `busy`, so a script waiting for `!busy` sees its effect.
#[wasm_bindgen]
pub fn pushlab_state() -> String {
    let waiting = INBOX.with(|inbox| !inbox.borrow().is_empty());
    SHOWN.with(|shown| {
        let mut shown = shown.borrow().clone();
        if let Some(shown) = shown.as_mut() {
            shown.busy |= waiting;
        }
        serde_json::to_string(&shown).unwrap_or_else(|_| "null".to_owned())
    })
}

/// Queues a command for the next frame; a malformed one is refused at once with the reason.
#[wasm_bindgen]
pub fn pushlab_command(json: &str) -> Result<(), JsValue> {
    let command = crate::app::hook::parse(json).map_err(JsValue::from)?;
    INBOX.with(|inbox| inbox.borrow_mut().push(command));
    crate::app::dialogs::browser::wake();
    Ok(())
}

/// Opens files the page's script read from a folder dropped or picked: `paths[i]` (below the
/// folder given, starting with its name) holds `contents[i]`.
#[wasm_bindgen]
pub fn pushlab_open_files(
    paths: Vec<String>,
    contents: Vec<js_sys::Uint8Array>,
) -> Result<(), JsValue> {
    if paths.len() != contents.len() {
        return Err(JsValue::from(format!(
            "open_files: {} paths but {} contents",
            paths.len(),
            contents.len()
        )));
    }
    let files = paths
        .into_iter()
        .zip(contents.into_iter().map(|bytes| bytes.to_vec()))
        .collect();
    crate::app::dialogs::browser::open_given(files);
    Ok(())
}

/// Whether the app panicked, and with what (for the page's own check).
#[wasm_bindgen]
pub fn pushlab_panic() -> Option<String> {
    RUNNER.with(|runner| {
        let runner = runner.borrow();
        let summary = runner.as_ref()?.panic_summary()?;
        Some(summary.message())
    })
}

pub(super) fn keep_runner(runner: eframe::WebRunner) {
    RUNNER.with(|kept| *kept.borrow_mut() = Some(runner));
}

pub(super) fn take_commands() -> Vec<HookCommand> {
    INBOX.with(|inbox| std::mem::take(&mut *inbox.borrow_mut()))
}

pub(super) fn set_shown(shown: Shown) {
    SHOWN.with(|kept| *kept.borrow_mut() = Some(shown));
}
