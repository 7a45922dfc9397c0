//! What the window keeps for itself, apart from the app's state: the layout of its panes, the
//! scene's and the cameras' zoom, the tools' tab, open dialogs, pending screenshots. Panels may
//! change these directly; everything else they ask for with a command.

use super::keys::ViewChange;
use std::sync::mpsc::{Receiver, Sender, channel};

use eframe::egui;

use super::dialogs::Dialogs;
use super::frame_rate::FrameRate;
use super::layout::{Layout, Pane};
use super::link::ViewPart;
use super::panels::camera::CameraView;
use super::panels::scene::SceneView;

/// The tools pane's tabs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SideTab {
    Steer,
    Inspect,
    Train,
    Labels,
}

/// View state that is not app state.
pub struct View {
    /// Where the panes are, and which the user hid (remembered across restarts).
    pub layout: Layout,
    pub scene: SceneView,
    pub side_tab: SideTab,
    pub dialogs: Dialogs,
    /// Messages from screenshots saved on the renderer's thread.
    pub screenshot_status: (Sender<String>, Receiver<String>),
    /// Where the plots were drawn last frame (for PNG export; the scene keeps its own rect).
    pub plots_rect: egui::Rect,
    /// Whether the keyboard cheat-sheet is showing.
    pub show_shortcuts: bool,
    /// Frames per second and CPU time per frame, for the menu bar.
    pub frame_rate: FrameRate,
    /// The presentation layout (demo mode): large scene, plots, buttons and narration.
    pub presentation: bool,
    /// The camera panel's zoom and textures.
    pub cameras: CameraView,
    /// High-contrast colours and larger text, for a projector (`projector`).
    pub projector: bool,
    /// The light theme (on paper, in daylight) rather than the dark one.
    pub light: bool,
    /// Controls a classroom link hid (`link::HIDEABLE`): the timeline and the menu bar here; the
    /// browser and tools panes are hidden through the layout.
    pub hide_timeline: bool,
    pub hide_menu: bool,
    /// The page's address without its query, in a browser tab (Help → Copy link); `None` on the
    /// desktop.
    pub page_address: Option<String>,
}

impl View {
    /// What of the view a link holds (see `link`): the layouts, projector mode and the controls
    /// hidden — the browser and tools panes by the layout, the timeline and menu bar here.
    pub fn link_part(&self) -> ViewPart {
        let hidden = [
            ("browser", !self.layout.is_shown(Pane::Browser)),
            ("tools", !self.layout.is_shown(Pane::Tools)),
            ("timeline", self.hide_timeline),
            ("menu", self.hide_menu),
        ];
        ViewPart {
            present: self.presentation,
            projector: self.projector,
            light: self.light,
            hide: (hidden.into_iter())
                .filter(|&(_, hidden)| hidden)
                .map(|(name, _)| name.to_owned())
                .collect(),
        }
    }

    /// Shows the view a link asks for (what [`Self::link_part`] reads); panes it does not hide
    /// stay as the user had them.
    pub fn follow_link_part(&mut self, part: &ViewPart) {
        let hidden = |name: &str| part.hide.iter().any(|h| h == name);
        self.presentation = part.present;
        self.projector = part.projector;
        self.light = part.light;
        if hidden("browser") {
            self.layout.set_shown(Pane::Browser, false);
        }
        if hidden("tools") {
            self.layout.set_shown(Pane::Tools, false);
        }
        self.hide_timeline = hidden("timeline");
        self.hide_menu = hidden("menu");
    }
}

impl Default for View {
    fn default() -> Self {
        Self {
            layout: Layout::default(),
            scene: SceneView::default(),
            side_tab: SideTab::Steer,
            dialogs: Dialogs::default(),
            screenshot_status: channel(),
            plots_rect: egui::Rect::NOTHING,
            show_shortcuts: false,
            frame_rate: FrameRate::default(),
            presentation: false,
            cameras: CameraView::default(),
            projector: false,
            light: false,
            hide_timeline: false,
            hide_menu: false,
            page_address: None,
        }
    }
}

impl View {
    /// Carries out what a key asked of the view.
    pub fn apply_key(&mut self, change: ViewChange) {
        match change {
            ViewChange::ToggleCheatSheet => self.show_shortcuts = !self.show_shortcuts,
            ViewChange::TogglePresentation => self.presentation = !self.presentation,
            ViewChange::ToggleMenuBar => self.hide_menu = !self.hide_menu,
            ViewChange::Camera(mode) => self.scene.mode = mode,
        }
    }
}
