//! The main window's tiles, as rerun's viewer lays out its views (egui_tiles): the recordings
//! browser, the scene, the cameras, the plots and the tools (Steer, Inspect, Train, Labels), each a
//! tab the user drags to rearrange, whose edges resize, and which View hides or shows. The
//! arrangement is remembered across restarts; View → Reset layout brings back the one below.
//!
//! Only the arrangement lives here: what each pane draws is its panel's, called by
//! [`PaneDrawer`](crate::app::PushlabApp) through [`egui_tiles::Behavior`].

use std::collections::BTreeSet;

use eframe::egui;
use egui_tiles::{Container, Linear, LinearDir, Tile, TileId, Tiles, Tree};
use serde::{Deserialize, Serialize};

/// One pane of the main window.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Pane {
    Browser,
    Scene,
    Cameras,
    Plots,
    Tools,
}

impl Pane {
    /// Every pane, in the View menu's order.
    pub const ALL: [Pane; 5] = [
        Pane::Browser,
        Pane::Scene,
        Pane::Cameras,
        Pane::Plots,
        Pane::Tools,
    ];

    /// Its tab's title.
    pub fn title(self) -> &'static str {
        match self {
            Pane::Browser => "Recordings",
            Pane::Scene => "Scene",
            Pane::Cameras => "Cameras",
            Pane::Plots => "Plots",
            Pane::Tools => "Tools",
        }
    }
}

/// The arrangement of the panes, and those the user hid.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Layout {
    tree: Tree<Pane>,
    hidden: BTreeSet<Pane>,
}

impl Default for Layout {
    /// Browser on the left, tools on the right, the scene with the cameras beside it above the
    /// plots in the middle: the window as it was before it was tiled.
    fn default() -> Self {
        let mut tiles = Tiles::default();
        let mut pane = |p| {
            let pane = tiles.insert_pane(p);
            tiles.insert_tab_tile(vec![pane])
        };
        let (browser, scene, cameras, plots, tools) = (
            pane(Pane::Browser),
            pane(Pane::Scene),
            pane(Pane::Cameras),
            pane(Pane::Plots),
            pane(Pane::Tools),
        );
        let seen = linear(
            &mut tiles,
            LinearDir::Horizontal,
            &[(scene, 1.0), (cameras, 1.0)],
        );
        let centre = linear(
            &mut tiles,
            LinearDir::Vertical,
            &[(seen, 470.0), (plots, 400.0)],
        );
        let root = linear(
            &mut tiles,
            LinearDir::Horizontal,
            &[(browser, 460.0), (centre, 590.0), (tools, 350.0)],
        );
        Self {
            tree: Tree::new(egui::Id::unique("pushlab-layout"), root, tiles),
            hidden: BTreeSet::new(),
        }
    }
}

/// A row or column of `children`, each with its share of the space.
fn linear(tiles: &mut Tiles<Pane>, dir: LinearDir, children: &[(TileId, f32)]) -> TileId {
    let mut container = Linear::new(dir, children.iter().map(|(id, _)| *id).collect());
    for (id, share) in children {
        container.shares.set_share(*id, *share);
    }
    tiles.insert_new(Tile::Container(Container::Linear(container)))
}

impl Layout {
    /// Whether the user keeps `pane` shown (the cameras show only when the recording has one).
    pub fn is_shown(&self, pane: Pane) -> bool {
        !self.hidden.contains(&pane)
    }

    /// Shows or hides `pane`.
    pub fn set_shown(&mut self, pane: Pane, shown: bool) {
        if shown {
            self.hidden.remove(&pane);
        } else {
            self.hidden.insert(pane);
        }
    }

    /// Back to the default arrangement, every pane shown.
    pub fn reset(&mut self) {
        *self = Self::default();
    }

    /// The tree to draw this frame, each pane visible when shown and, for the cameras, when
    /// `cameras` (the recording has a camera shown). A pane missing from a remembered tree (one
    /// written by an older pushlab) brings back the default arrangement.
    pub fn tree_for_frame(&mut self, cameras: bool) -> &mut Tree<Pane> {
        if Pane::ALL
            .iter()
            .any(|p| self.tree.tiles.find_pane(p).is_none())
        {
            let hidden = std::mem::take(&mut self.hidden);
            *self = Self::default();
            self.hidden = hidden;
        }
        for pane in Pane::ALL {
            let visible = self.is_shown(pane) && (pane != Pane::Cameras || cameras);
            if let Some(tile) = self.tree.tiles.find_pane(&pane) {
                self.tree.tiles.set_visible(tile, visible);
            }
        }
        &mut self.tree
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pane_is_in_the_default_layout_once() {
        let layout = Layout::default();
        for pane in Pane::ALL {
            let count = (layout.tree.tiles.iter())
                .filter(|(_, t)| matches!(t, Tile::Pane(p) if *p == pane))
                .count();
            assert_eq!(count, 1, "{pane:?}");
        }
    }

    #[test]
    fn hidden_panes_and_cameras_without_a_camera_are_not_drawn() {
        let mut layout = Layout::default();
        layout.set_shown(Pane::Plots, false);
        let tree = layout.tree_for_frame(false);
        let visible = |tree: &Tree<Pane>, pane| {
            let tile = tree.tiles.find_pane(&pane).expect("pane");
            tree.tiles.is_visible(tile)
        };
        assert!(!visible(tree, Pane::Plots));
        assert!(!visible(tree, Pane::Cameras), "no camera in the recording");
        assert!(visible(tree, Pane::Scene));
        let tree = layout.tree_for_frame(true);
        assert!(visible(tree, Pane::Cameras));
        layout.reset();
        assert!(layout.is_shown(Pane::Plots));
    }

    #[test]
    fn a_layout_survives_a_round_trip_through_storage() {
        let mut layout = Layout::default();
        layout.set_shown(Pane::Browser, false);
        let text = serde_json::to_string(&layout).expect("serialise");
        let back: Layout = serde_json::from_str(&text).expect("deserialise");
        assert_eq!(back, layout);
    }
}
