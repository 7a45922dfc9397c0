//! The usual window: the timeline along the bottom and, above it, the tiled panes of
//! [`Layout`](super::layout::Layout), each drawn by its panel.

use eframe::egui;
use egui_tiles::{TileId, UiResponse};

use super::dialogs::Dialogs;
use super::layout::Pane;
use super::panels;
use super::panels::camera::CameraView;
use super::panels::scene::SceneView;
use super::state::{AppState, Command};
use super::view::{SideTab, View};

/// Draws the timeline and the panes.
pub fn ui(ui: &mut egui::Ui, state: &AppState, view: &mut View, commands: &mut Vec<Command>) {
    if !view.hide_timeline {
        panels::timeline::bottom_bar(ui, state, commands);
    }
    let View {
        layout,
        scene,
        cameras,
        side_tab,
        dialogs,
        plots_rect,
        ..
    } = view;
    let mut drawer = PaneDrawer {
        state,
        scene,
        cameras,
        side_tab,
        dialogs,
        plots_rect,
        commands,
    };
    let tree = layout.tree_for_frame(state.cameras().any_shown());
    egui::CentralPanel::default().show(ui, |ui| tree.ui(&mut drawer, ui));
}

/// Draws each pane with its panel, lending it the view's parts it keeps.
struct PaneDrawer<'a> {
    state: &'a AppState,
    scene: &'a mut SceneView,
    cameras: &'a mut CameraView,
    side_tab: &'a mut SideTab,
    dialogs: &'a mut Dialogs,
    plots_rect: &'a mut egui::Rect,
    commands: &'a mut Vec<Command>,
}

impl egui_tiles::Behavior<Pane> for PaneDrawer<'_> {
    fn tab_title_for_pane(&mut self, pane: &Pane) -> egui::WidgetText {
        pane.title().into()
    }

    fn pane_ui(&mut self, ui: &mut egui::Ui, _tile: TileId, pane: &mut Pane) -> UiResponse {
        let (state, commands) = (self.state, &mut *self.commands);
        match pane {
            Pane::Browser => {
                egui::Frame::new()
                    .inner_margin(6.0)
                    .show(ui, |ui| panels::browser::ui(ui, state, commands));
            }
            Pane::Scene => panels::scene::ui(ui, state, self.scene, commands),
            Pane::Cameras => panels::camera::ui(ui, state, self.cameras),
            Pane::Plots => {
                *self.plots_rect = ui.max_rect();
                panels::plots::ui(ui, state, commands);
            }
            Pane::Tools => {
                egui::Frame::new().inner_margin(6.0).show(ui, |ui| {
                    tools(ui, state, self.side_tab, self.dialogs, commands);
                });
            }
        }
        UiResponse::None
    }

    fn simplification_options(&self) -> egui_tiles::SimplificationOptions {
        egui_tiles::SimplificationOptions {
            all_panes_must_have_tabs: true,
            ..Default::default()
        }
    }

    fn gap_width(&self, _style: &egui::Style) -> f32 {
        2.0
    }
}

/// The tools: Steer, Inspect, Train and Labels, one at a time.
fn tools(
    ui: &mut egui::Ui,
    state: &AppState,
    tab: &mut SideTab,
    dialogs: &mut Dialogs,
    commands: &mut Vec<Command>,
) {
    ui.horizontal(|ui| {
        for (choice, label) in [
            (SideTab::Steer, "Steer"),
            (SideTab::Inspect, "Inspect"),
            (SideTab::Train, "Train"),
            (SideTab::Labels, "Labels"),
        ] {
            ui.selectable_value(tab, choice, label);
        }
    });
    ui.separator();
    egui::ScrollArea::vertical().show(ui, |ui| match tab {
        SideTab::Steer => panels::steer::ui(ui, state, commands),
        SideTab::Inspect => panels::inspector::ui(ui, state),
        SideTab::Train => panels::training::ui(ui, state, dialogs, commands),
        SideTab::Labels => panels::labels::ui(ui, state, dialogs, commands),
    });
}
