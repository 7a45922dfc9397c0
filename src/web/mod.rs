//! pushlab in a browser tab: the same app (`crate::app`), started by eframe's web runner.
//!
//! What only a page has lives here: fetching the bundled files into the page's file tree before
//! the app starts, files dropped or picked (`page`, `dialogs`), downloads for saves, and the test
//! hook `window.pushlab` (`hook`). Everything else — panels, state, commands — is the desktop's.

pub mod address;
pub mod hook;
pub mod page;

use std::path::Path;

use pushlab_core::files::memory::TREE;
use wasm_bindgen::JsCast as _;
use wasm_bindgen::prelude::*;

use crate::app::dialogs::{browser, fetch};
use crate::app::platform::{APP_FOLDER, BUNDLED_ROOT};
use crate::app::{PushlabApp, initial_state};

/// The list of bundled files, relative to the site, that `scripts/web` writes beside the page.
const MANIFEST: &str = "bundled.json";

/// Starts the app in the canvas `pushlab_canvas`: fetches the bundled files, then runs.
pub async fn start() -> Result<(), JsValue> {
    show_panics_in_the_page();
    eframe::WebLogger::init(log::LevelFilter::Warn).ok();
    set_loading_text("fetching the sample data…");
    fetch_bundled().await?;
    set_loading_text("");
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document")?;
    let canvas = document
        .get_element_by_id("pushlab_canvas")
        .ok_or("the page has no canvas #pushlab_canvas")?
        .dyn_into::<web_sys::HtmlCanvasElement>()?;
    let runner = eframe::WebRunner::new();
    let started = runner
        .start(
            canvas,
            eframe::WebOptions::default(),
            Box::new(|cc| {
                let persisted = cc
                    .storage
                    .and_then(|s| eframe::get_value(s, crate::app::STORAGE_KEY))
                    .unwrap_or_default();
                if let Some(storage) = cc.storage {
                    page::restore_kept_files(storage);
                }
                let mut state = initial_state(&[], persisted);
                // Models trained for demos are kept among the page's files for the visit.
                state.keep_files_in(Some(std::path::PathBuf::from(APP_FOLDER)));
                let mut app = PushlabApp::new(state);
                if let Some(layout) = cc
                    .storage
                    .and_then(|s| eframe::get_value(s, crate::app::LAYOUT_KEY))
                {
                    app.view.layout = layout;
                }
                Ok(Box::new(page::Page::new(app, &cc.egui_ctx)))
            }),
        )
        .await;
    hook::keep_runner(runner);
    started?;
    let urls = address::query_values("url");
    if !urls.is_empty() {
        browser::open_urls(urls);
    }
    Ok(())
}

/// Fetches every file the manifest lists into the page's files under [`BUNDLED_ROOT`].
async fn fetch_bundled() -> Result<(), JsValue> {
    let manifest = fetch::bytes(MANIFEST).await.map_err(JsValue::from)?;
    let paths: Vec<String> =
        serde_json::from_slice(&manifest).map_err(|e| JsValue::from(format!("{MANIFEST}: {e}")))?;
    for (done, relative) in paths.iter().enumerate() {
        if done % 16 == 0 {
            set_loading_text(&format!(
                "fetching the sample data: {done} of {} files…",
                paths.len()
            ));
        }
        let bytes = fetch::bytes(relative).await.map_err(JsValue::from)?;
        TREE.write(&Path::new(BUNDLED_ROOT).join(relative), bytes);
    }
    Ok(())
}

/// The text under the page's title while it starts (`#pushlab_loading`).
fn set_loading_text(text: &str) {
    if let Some(element) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("pushlab_loading"))
    {
        element.set_text_content(Some(text));
    }
}

/// A panic's message is written into the page (`#pushlab_panic`) and the console, not only lost in
/// a blank canvas; eframe's own handler, installed after, calls this one.
fn show_panics_in_the_page() {
    std::panic::set_hook(Box::new(|info| {
        let message = format!("pushlab stopped: {info}");
        web_sys::console::error_1(&message.clone().into());
        if let Some(element) = web_sys::window()
            .and_then(|w| w.document())
            .and_then(|d| d.get_element_by_id("pushlab_panic"))
        {
            element.set_text_content(Some(&message));
            let _ = element.set_attribute("style", "display: block");
        }
    }));
}
