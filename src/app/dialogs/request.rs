//! What a dialog is asked for and what it answers, on both targets.

use std::path::PathBuf;

pub use crate::app::state::LabelExportFormat;

/// What the user asked a dialog for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DialogRequest {
    OpenFiles,
    OpenFolder,
    SaveScene,
    SavePlots,
    /// The plots as a vector figure (desktop only).
    SavePlotsSvg,
    /// A video of the push shown: GIF, MP4 or WebM (desktop only).
    SaveVideo,
    SaveLossCsv,
    LoadModel,
    SaveModel,
    ExportLabelsCsv,
    ExportLabelsJson,
    /// A `setting.json` describing a bag's object.
    BagSetting,
    /// A folder for the sandbox's pushes, saved as a recording set (a download in a page).
    SaveSandbox,
}

/// What a dialog returned (nothing arrives when it was cancelled).
#[derive(Clone, Debug, PartialEq)]
pub enum DialogResult {
    Open(Vec<PathBuf>),
    SaveScene(PathBuf),
    SavePlots(PathBuf),
    SavePlotsSvg(PathBuf),
    SaveVideo(PathBuf),
    SaveLossCsv(PathBuf),
    LoadModel(PathBuf),
    SaveModel(PathBuf),
    ExportLabels(PathBuf, LabelExportFormat),
    BagSetting(PathBuf),
    SaveSandbox(PathBuf),
    /// No dialog could be shown (neither the XDG desktop portal nor zenity answered).
    Unavailable(String),
}
