//! File dialogs in a page: the browser's picker for opening (the files picked are put among the
//! page's files and opened by path, as on the desktop), and for saving a file named under
//! [`DOWNLOADS`] that the browser then downloads. Also the files fetched by address and the files
//! dropped on the page: every way a user's file reaches a page, each put among the page's files
//! (`pushlab_core::files`) and opened by path as on the desktop.

use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::sync::mpsc::Sender;

use pushlab_core::files::memory::TREE;
use wasm_bindgen::JsCast as _;

use super::fetch;
use super::request::{DialogRequest, DialogResult, LabelExportFormat};

/// Where files the app saves in a page go before they are downloaded.
pub const DOWNLOADS: &str = "/downloads";

thread_local! {
    /// The app's context, to wake it when a fetch or a drop was read.
    static CONTEXT: RefCell<Option<eframe::egui::Context>> = const { RefCell::new(None) };
    /// Files fetched by address, waiting to be opened on the next frame.
    static OPENED: RefCell<Vec<DialogResult>> = const { RefCell::new(Vec::new()) };
    /// Reads and fetches under way (the page says it is busy meanwhile).
    static UNDER_WAY: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    /// Counts the folders made for picked and fetched files.
    static FOLDERS: RefCell<usize> = const { RefCell::new(0) };
}

fn next_folder(kind: &str) -> PathBuf {
    let k = FOLDERS.with(|n| {
        *n.borrow_mut() += 1;
        *n.borrow()
    });
    PathBuf::from(format!("/{kind}/{k}"))
}

/// Writes files into `folder` of the page's files, each at its path relative to what was given (a
/// folder picked or dropped keeps its tree: `pusht.zarr/data/state/.zarray`); returns what to
/// open: the folder when a set's `setting.json` is at its top, else each file and folder at its top
/// (a bag, a dataset's folder), which the loader tells apart as on the desktop.
pub fn put_files<N: AsRef<str>>(
    folder: &Path,
    files: impl IntoIterator<Item = (N, Vec<u8>)>,
) -> Vec<PathBuf> {
    let mut tops: Vec<PathBuf> = Vec::new();
    for (name, bytes) in files {
        // Only plain names: `..` or `/` in a path given by the browser never leaves the folder.
        let relative: PathBuf = Path::new(name.as_ref())
            .components()
            .filter_map(|c| match c {
                std::path::Component::Normal(part) => Some(part),
                _ => None,
            })
            .collect();
        let Some(top) = relative.components().next() else {
            continue;
        };
        TREE.write(&folder.join(&relative), bytes);
        let top = folder.join(top);
        if !tops.contains(&top) {
            tops.push(top);
        }
    }
    if tops
        .iter()
        .any(|p| p.file_name().is_some_and(|n| n == "setting.json"))
    {
        return vec![folder.to_path_buf()];
    }
    // JSON that is not an MIT recording, dropped beside one (a bag's remembered choice, the
    // object's setting it names), is read from beside it, not opened; dropped alone it is opened, so
    // that its error says what it is not.
    let companion = |p: &PathBuf| {
        let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
        name.is_some_and(|n| n.ends_with(".json") && !n.starts_with("motion_"))
    };
    if tops.iter().any(|p| !companion(p)) {
        tops.retain(|p| !companion(p));
    }
    tops
}

/// Opens files handed over by the page's script (a folder dropped or picked: each file's path
/// below it and its bytes), in a folder of their own, on a later frame.
pub fn open_given(files: Vec<(String, Vec<u8>)>) {
    let folder = next_folder("dropped");
    let paths = put_files(&folder, files);
    if !paths.is_empty() {
        OPENED.with(|o| o.borrow_mut().push(DialogResult::Open(paths)));
    }
    wake();
}

/// Keeps the app's context, to ask for a frame when files or commands arrive outside one.
pub fn keep_context(context: &eframe::egui::Context) {
    CONTEXT.with(|kept| *kept.borrow_mut() = Some(context.clone()));
}

/// Asks for a frame.
pub fn wake() {
    CONTEXT.with(|context| {
        if let Some(context) = context.borrow().as_ref() {
            context.request_repaint();
        }
    });
}

/// Shows the picker (opening) or names the download (saving); the answer goes to `sender`.
pub fn show(request: DialogRequest, sender: Sender<Option<DialogResult>>) {
    let download = |name: &str| PathBuf::from(DOWNLOADS).join(name);
    let saved = match request {
        DialogRequest::SaveScene => Some(DialogResult::SaveScene(download("scene.png"))),
        DialogRequest::SavePlots => Some(DialogResult::SavePlots(download("plots.png"))),
        DialogRequest::SaveLossCsv => Some(DialogResult::SaveLossCsv(download("losses.csv"))),
        DialogRequest::SaveModel => Some(DialogResult::SaveModel(download("model.json"))),
        // Each file of the set downloads on its own (setting.json, push_000.csv, …).
        DialogRequest::SaveSandbox => Some(DialogResult::SaveSandbox(download("sandbox"))),
        DialogRequest::ExportLabelsCsv => Some(DialogResult::ExportLabels(
            download("labels.csv"),
            LabelExportFormat::Csv,
        )),
        DialogRequest::ExportLabelsJson => Some(DialogResult::ExportLabels(
            download("labels-export.json"),
            LabelExportFormat::Json,
        )),
        DialogRequest::OpenFiles
        | DialogRequest::OpenFolder
        | DialogRequest::LoadModel
        | DialogRequest::BagSetting
        // Not offered in a page (the figure's font would double the download).
        | DialogRequest::SavePlotsSvg
        | DialogRequest::SaveVideo => None,
    };
    if let Some(saved) = saved {
        // The receiver is gone only when the app closed.
        let _ = sender.send(Some(saved));
        return;
    }
    if request == DialogRequest::OpenFolder && pick_folder() {
        // The page's script reads the folder and hands its files to `open_given`.
        let _ = sender.send(None);
        return;
    }
    wasm_bindgen_futures::spawn_local(async move {
        let picker = match request {
            DialogRequest::LoadModel | DialogRequest::BagSetting => {
                rfd::AsyncFileDialog::new().add_filter("JSON", &["json"])
            }
            _ => {
                rfd::AsyncFileDialog::new().add_filter("Recordings", &["csv", "json", "h5", "mcap"])
            }
        };
        let picked = match request {
            DialogRequest::OpenFiles | DialogRequest::OpenFolder => picker.pick_files().await,
            _ => picker.pick_file().await.map(|f| vec![f]),
        };
        let Some(picked) = picked else {
            let _ = sender.send(None);
            return;
        };
        let mut files = Vec::new();
        for handle in &picked {
            files.push((handle.file_name(), handle.read().await));
        }
        let folder = next_folder("opened");
        let paths = put_files(&folder, files);
        let result = match (request, paths.first()) {
            (DialogRequest::LoadModel, Some(path)) => DialogResult::LoadModel(path.clone()),
            (DialogRequest::BagSetting, Some(path)) => DialogResult::BagSetting(path.clone()),
            _ => DialogResult::Open(paths),
        };
        let _ = sender.send(Some(result));
    });
}

/// Shows the browser's folder picker through the page's script (`window.pushlab_pick_folder`, an
/// `<input webkitdirectory>`: rfd picks files only in a page); `false` when the page has none.
fn pick_folder() -> bool {
    let Some(window) = web_sys::window() else {
        return false;
    };
    let pick = js_sys::Reflect::get(&window, &"pushlab_pick_folder".into())
        .ok()
        .and_then(|f| f.dyn_into::<js_sys::Function>().ok());
    pick.is_some_and(|pick| pick.call0(&window).is_ok())
}

/// Fetches files by address into one folder per directory of the address (so a CSV and the
/// `setting.json` beside it on the server sit together) and opens them; a CSV brings the
/// `setting.json` beside it. A refused fetch is said with the address and the reason.
pub fn open_urls(urls: Vec<String>) {
    UNDER_WAY.with(|n| n.set(n.get() + 1));
    wasm_bindgen_futures::spawn_local(async move {
        let folder = next_folder("fetched");
        let mut names = Vec::new();
        let mut wanted = urls.clone();
        for url in &urls {
            if url.ends_with(".csv") {
                let beside = match url.rsplit_once('/') {
                    Some((dir, _)) => format!("{dir}/setting.json"),
                    None => "setting.json".to_owned(),
                };
                if !wanted.contains(&beside) {
                    wanted.push(beside);
                }
            }
        }
        for url in wanted {
            match fetch::file(&url).await {
                Ok((bytes, disposition)) => {
                    let name = super::fetched_name::file_name(&url, disposition.as_deref());
                    TREE.write(&folder.join(&name), bytes);
                    names.push(name);
                }
                Err(why) => OPENED.with(|o| o.borrow_mut().push(DialogResult::Unavailable(why))),
            }
        }
        let paths = if names.iter().any(|n| n == "setting.json") {
            vec![folder]
        } else {
            names.iter().map(|n| folder.join(n)).collect()
        };
        if !paths.is_empty() {
            OPENED.with(|o| o.borrow_mut().push(DialogResult::Open(paths)));
        }
        UNDER_WAY.with(|n| n.set(n.get().saturating_sub(1)));
        wake();
    });
}

/// Reads files dropped on the page into a folder of their own (two drops never mix) and opens them
/// (on a later frame); one the browser cannot read is said by name. A dropped folder never gets
/// here: the page's script walks it and hands its files to [`open_given`].
pub fn read_dropped(dropped: Vec<eframe::egui::DroppedFileHandle>) {
    let folder = next_folder("dropped");
    UNDER_WAY.with(|n| n.set(n.get() + 1));
    wasm_bindgen_futures::spawn_local(async move {
        let mut files = Vec::new();
        for file in &dropped {
            let name = file.path().display().to_string();
            match file.bytes_async().await {
                Ok(bytes) => files.push((name, bytes)),
                Err(why) => OPENED.with(|o| {
                    o.borrow_mut().push(DialogResult::Unavailable(format!(
                        "{name}: the browser could not read the dropped file: {}",
                        browser_words(&why)
                    )));
                }),
            }
        }
        let paths = put_files(&folder, files);
        if !paths.is_empty() {
            OPENED.with(|o| o.borrow_mut().push(DialogResult::Open(paths)));
        }
        UNDER_WAY.with(|n| n.set(n.get().saturating_sub(1)));
        wake();
    });
}

/// The browser's own words in eframe's error for a file it could not read, which is the debug form
/// of a JavaScript value (`JsValue(NotReadableError: …)` and a stack line, `undefined` in a page).
fn browser_words(why: &str) -> &str {
    let first = why.lines().next().unwrap_or(why);
    first.strip_prefix("JsValue(").unwrap_or(first)
}

/// Whether files dropped or asked for by address are still being read or fetched.
pub fn under_way() -> bool {
    UNDER_WAY.with(|n| n.get() > 0)
}

/// What fetches finished since the last frame: files to open, or why a fetch was refused.
pub fn take_opened() -> Vec<DialogResult> {
    OPENED.with(|o| std::mem::take(&mut *o.borrow_mut()))
}

/// Hands every file the app saved under [`DOWNLOADS`] to the browser as a download (once a frame:
/// only the files under that folder are looked at).
pub fn download_saved() {
    for (path, bytes) in TREE.take_under(Path::new(DOWNLOADS)) {
        let name = path
            .file_name()
            .map_or_else(|| "pushlab".into(), |n| n.to_string_lossy().into_owned());
        if let Err(why) = download(&name, &bytes) {
            web_sys::console::error_1(&why);
        }
    }
}

fn download(name: &str, bytes: &[u8]) -> Result<(), wasm_bindgen::JsValue> {
    let array = js_sys::Uint8Array::from(bytes);
    let parts = js_sys::Array::of1(&array);
    let blob = web_sys::Blob::new_with_u8_array_sequence(&parts)?;
    let url = web_sys::Url::create_object_url_with_blob(&blob)?;
    let document = web_sys::window()
        .and_then(|w| w.document())
        .ok_or("no document")?;
    let anchor: web_sys::HtmlAnchorElement = document.create_element("a")?.dyn_into()?;
    anchor.set_href(&url);
    anchor.set_download(name);
    anchor.click();
    web_sys::Url::revoke_object_url(&url)
}
