//! The page's address: the link it was opened with, and the link of what is shown, kept in the
//! address bar as it changes (without adding to the history: Back leaves the page, as a video's
//! position does not fill the history either).

use crate::app::link::Link;
use crate::app::platform::Instant;

/// Most often the address bar is rewritten when paused: soon after a seek or a θ set.
const EVERY_S: f64 = 0.25;
/// Most often while playing, when the frame changes every frame. Chromium's `replaceState` is not
/// cheap: at four times a second it was 13 % of the app's time on the page's thread while playing
/// (a CDP profile, headless chromium, this machine). Help → Copy link copies the view of the moment
/// whatever the bar says, and pausing rewrites the bar within [`EVERY_S`].
const EVERY_S_PLAYING: f64 = 2.0;

/// The address without its query (`http://host/path/`).
pub fn page_address() -> Option<String> {
    let location = web_sys::window()?.location();
    Some(format!(
        "{}{}",
        location.origin().ok()?,
        location.pathname().ok()?
    ))
}

/// The query the page was opened with.
pub fn opened_query() -> String {
    (web_sys::window().and_then(|w| w.location().search().ok())).unwrap_or_default()
}

/// Writes the link of what is shown into the address bar when it changed, at most every
/// [`EVERY_S`] ([`EVERY_S_PLAYING`] while playing); `url=` values the page was opened with are
/// kept (they say what was fetched).
#[derive(Default)]
pub struct AddressBar {
    written: String,
    at: Option<Instant>,
}

impl AddressBar {
    pub fn follow(&mut self, link: &Link, playing: bool) {
        let every = if playing { EVERY_S_PLAYING } else { EVERY_S };
        if self.at.is_some_and(|at| at.elapsed().as_secs_f64() < every) {
            return;
        }
        let mut query = link.to_query();
        for url in query_values("url") {
            query.push_str(&format!("&url={}", js_sys::encode_uri_component(&url)));
        }
        if query == self.written {
            return;
        }
        let Some(history) = web_sys::window().and_then(|w| w.history().ok()) else {
            return;
        };
        if history
            .replace_state_with_url(&wasm_bindgen::JsValue::NULL, "", Some(&format!("?{query}")))
            .is_ok()
        {
            self.written = query;
            self.at = Some(Instant::now());
        }
    }
}

/// Every value of `name` in the page's address (`?url=a&url=b`).
pub fn query_values(name: &str) -> Vec<String> {
    let Some(search) = web_sys::window().and_then(|w| w.location().search().ok()) else {
        return Vec::new();
    };
    let Ok(params) = web_sys::UrlSearchParams::new_with_str(&search) else {
        return Vec::new();
    };
    let values = params.get_all(name);
    (0..values.length())
        .filter_map(|i| values.get(i).as_string())
        .collect()
}
