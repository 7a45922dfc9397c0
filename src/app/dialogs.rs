//! File dialogs, so that the window keeps drawing while one is open; results arrive through
//! [`Dialogs::poll`]. On the desktop: native dialogs (rfd, via the XDG desktop portal) on a worker
//! thread. In a page: the browser's file picker, the picked files put among the page's files, and
//! saves written there and downloaded (`browser`).

use std::sync::mpsc::{Receiver, Sender, channel};
#[cfg(not(target_arch = "wasm32"))]
use std::time::{Duration, Instant};

pub use self::request::{DialogRequest, DialogResult, LabelExportFormat};

#[cfg(target_arch = "wasm32")]
pub mod browser;
#[cfg(target_arch = "wasm32")]
pub mod fetch;
pub mod fetched_name;
mod request;

/// Dialogs in flight.
pub struct Dialogs {
    sender: Sender<Option<DialogResult>>,
    receiver: Receiver<Option<DialogResult>>,
    open: usize,
}

impl Default for Dialogs {
    fn default() -> Self {
        let (sender, receiver) = channel();
        Self {
            sender,
            receiver,
            open: 0,
        }
    }
}

impl Dialogs {
    /// Shows a dialog on a worker thread.
    pub fn open(&mut self, request: DialogRequest) {
        self.open += 1;
        show(request, self.sender.clone());
    }

    /// Whether a dialog is showing (the app keeps polling while one is).
    pub fn is_open(&self) -> bool {
        self.open > 0
    }

    /// The next finished dialog's result, if any.
    pub fn poll(&mut self) -> Option<DialogResult> {
        while let Ok(result) = self.receiver.try_recv() {
            self.open = self.open.saturating_sub(1);
            if result.is_some() {
                return result;
            }
        }
        None
    }
}

/// Shows a native dialog on a worker thread; its answer (or `None`, cancelled) goes to `sender`.
#[cfg(not(target_arch = "wasm32"))]
fn show(request: DialogRequest, sender: Sender<Option<DialogResult>>) {
    std::thread::spawn(move || {
        let started = Instant::now();
        let result = run_dialog(request);
        let result = result.or_else(|| unavailable_if_instant(started.elapsed()));
        // The receiver is gone only when the app closed.
        let _ = sender.send(result);
    });
}

/// Shows the browser's picker, or names the download a save becomes.
#[cfg(target_arch = "wasm32")]
fn show(request: DialogRequest, sender: Sender<Option<DialogResult>>) {
    browser::show(request, sender);
}

/// Nobody cancels a file dialog within a quarter of a second: a dialog that returned nothing that
/// fast never appeared. rfd then found neither the XDG desktop portal nor its zenity fallback, and
/// says so only in a log nobody reads, so the app says it instead.
#[cfg(not(target_arch = "wasm32"))]
const NO_DIALOG_WITHIN: Duration = Duration::from_millis(250);

#[cfg(not(target_arch = "wasm32"))]
fn unavailable_if_instant(elapsed: Duration) -> Option<DialogResult> {
    (elapsed < NO_DIALOG_WITHIN).then(|| {
        DialogResult::Unavailable(
            "no file dialog could be shown: install xdg-desktop-portal (with a GTK or KDE backend) or \
             zenity; meanwhile drop files on the window or run `pushlab open PATH…`"
                .to_owned(),
        )
    })
}

#[cfg(not(target_arch = "wasm32"))]
fn run_dialog(request: DialogRequest) -> Option<DialogResult> {
    use rfd::FileDialog;
    let png = |name: &str| {
        FileDialog::new()
            .add_filter("PNG image", &["png"])
            .set_file_name(name)
            .save_file()
    };
    match request {
        DialogRequest::OpenFiles => FileDialog::new()
            .set_title("Open recordings")
            .add_filter("Recordings", &["csv", "json", "h5", "mcap"])
            .pick_files()
            .map(DialogResult::Open),
        DialogRequest::OpenFolder => FileDialog::new()
            .set_title("Open a folder of recordings")
            .pick_folders()
            .map(DialogResult::Open),
        DialogRequest::SaveScene => png("scene.png").map(DialogResult::SaveScene),
        DialogRequest::SavePlots => png("plots.png").map(DialogResult::SavePlots),
        DialogRequest::SavePlotsSvg => FileDialog::new()
            .set_title("Export the plots as SVG or PDF")
            .add_filter("SVG figure", &["svg"])
            .add_filter("PDF figure", &["pdf"])
            .set_file_name("plots.svg")
            .save_file()
            .map(DialogResult::SavePlotsSvg),
        DialogRequest::SaveVideo => FileDialog::new()
            .set_title("Export a video of this push")
            .add_filter("Video", &["mp4", "webm", "gif"])
            .set_file_name("push.mp4")
            .save_file()
            .map(DialogResult::SaveVideo),
        DialogRequest::SaveLossCsv => FileDialog::new()
            .add_filter("CSV", &["csv"])
            .set_file_name("losses.csv")
            .save_file()
            .map(DialogResult::SaveLossCsv),
        DialogRequest::LoadModel => FileDialog::new()
            .set_title("Load a model")
            .add_filter("pushlab model", &["json"])
            .pick_file()
            .map(DialogResult::LoadModel),
        DialogRequest::SaveModel => FileDialog::new()
            .set_title("Save the model")
            .add_filter("pushlab model", &["json"])
            .set_file_name("model.json")
            .save_file()
            .map(DialogResult::SaveModel),
        DialogRequest::ExportLabelsCsv => FileDialog::new()
            .set_title("Export labels as CSV")
            .add_filter("CSV", &["csv"])
            .set_file_name("labels.csv")
            .save_file()
            .map(|p| DialogResult::ExportLabels(p, LabelExportFormat::Csv)),
        DialogRequest::ExportLabelsJson => FileDialog::new()
            .set_title("Export labels as JSON")
            .add_filter("JSON", &["json"])
            .set_file_name("labels-export.json")
            .save_file()
            .map(|p| DialogResult::ExportLabels(p, LabelExportFormat::Json)),
        DialogRequest::SaveSandbox => FileDialog::new()
            .set_title("Save the sandbox's pushes (a recording set, with the truth) into a folder")
            .pick_folder()
            .map(DialogResult::SaveSandbox),
        DialogRequest::BagSetting => FileDialog::new()
            .set_title("The bag's setting.json (object, pusher radius)")
            .add_filter("setting", &["json"])
            .pick_file()
            .map(DialogResult::BagSetting),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dialog_that_returns_nothing_at_once_is_reported_as_unavailable() {
        let Some(DialogResult::Unavailable(message)) =
            unavailable_if_instant(Duration::from_millis(3))
        else {
            panic!("an instant empty answer is not a cancel");
        };
        assert!(message.contains("zenity") && message.contains("pushlab open"));
        // A person who looked at the dialog and pressed Cancel.
        assert_eq!(unavailable_if_instant(Duration::from_secs(2)), None);
    }
}
