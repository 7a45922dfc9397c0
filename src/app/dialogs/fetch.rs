//! Fetching a file by its web address: the bundled files, `?url=` and `command({open_url})`.

use wasm_bindgen::JsCast as _;
use wasm_bindgen_futures::JsFuture;

/// The bytes at `url` (relative to the page or absolute), or why not: the address and the reason
/// (a network refusal such as CORS, or the HTTP status).
pub async fn bytes(url: &str) -> Result<Vec<u8>, String> {
    file(url).await.map(|(bytes, _)| bytes)
}

/// The bytes at `url` and the response's `Content-Disposition` (the server's name for the file),
/// or why not, as [`bytes`].
pub async fn file(url: &str) -> Result<(Vec<u8>, Option<String>), String> {
    let window = web_sys::window().ok_or("no window")?;
    let refused = |why: wasm_bindgen::JsValue| {
        format!(
            "{url}: could not fetch: {} (a server that does not allow this page to read it \
             (CORS), or no server at that address)",
            why.as_string()
                .or_else(|| js_sys::Error::from(why).message().as_string())
                .unwrap_or_default()
        )
    };
    let response = JsFuture::from(window.fetch_with_str(url))
        .await
        .map_err(refused)?;
    let response: web_sys::Response = response
        .dyn_into()
        .map_err(|_| format!("{url}: the fetch gave no response"))?;
    if !response.ok() {
        return Err(format!(
            "{url}: the server answered {} {}",
            response.status(),
            response.status_text()
        ));
    }
    let disposition = response.headers().get("content-disposition").ok().flatten();
    let buffer = response
        .array_buffer()
        .map_err(|_| format!("{url}: the response has no body"))?;
    let buffer = JsFuture::from(buffer)
        .await
        .map_err(|_| format!("{url}: the body could not be read"))?;
    Ok((js_sys::Uint8Array::new(&buffer).to_vec(), disposition))
}
