//! How the scene's camera moves from frame to frame: held by the view, followed by the scene panel,
//! set by keys (F, A). Its own module, below all three, so that the keys' table names neither the
//! view nor a panel (the view holds the panels' states, and the cheat-sheet panel reads the table).

/// How the scene's camera moves from frame to frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CameraMode {
    /// Keep the object and what is predicted for it in view; the zoom is the user's.
    #[default]
    Follow,
    /// Show the whole push: every robot and object position.
    FitAll,
    /// Stay where the user panned and zoomed.
    Free,
}

impl CameraMode {
    /// Every mode, in the order the toolbar shows them.
    pub const ALL: [CameraMode; 3] = [CameraMode::Follow, CameraMode::FitAll, CameraMode::Free];

    /// The toolbar's name of the mode.
    pub fn name(self) -> &'static str {
        match self {
            CameraMode::Follow => "Follow",
            CameraMode::FitAll => "Fit all",
            CameraMode::Free => "Free",
        }
    }

    /// What the mode does, for its tooltip.
    pub fn help(self) -> &'static str {
        match self {
            CameraMode::Follow => {
                "Keep the object and its predicted poses in view while it moves (key F); zooming keeps following"
            }
            CameraMode::FitAll => "Show the whole push (key A, or double-click the scene)",
            CameraMode::Free => {
                "Stay where you panned and zoomed (dragging the scene switches to this)"
            }
        }
    }
}
