//! One module per panel. Each draws from `&AppState` and pushes [`Command`]s; none mutates the state
//! directly except its own view options (layers, camera).
//!
//! [`Command`]: crate::app::state::Command

pub mod axes;
pub mod bag_dialog;
pub mod browser;
pub mod camera;
pub mod dataset_dialog;
pub mod gap_band;
pub mod inspector;
pub mod label_bands;
pub mod label_schema;
pub mod labels;
pub mod landscape;
pub mod live;
pub mod live_drive;
pub mod menu;
pub mod plots;
pub mod presentation;
pub mod proposal_band;
pub mod sandbox;
pub mod sandbox_goal;
pub mod scene;
pub mod shortcuts;
pub mod steer;
pub mod timeline;
pub mod training;
