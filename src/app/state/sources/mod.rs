//! Where recordings come from: files and folders opened (`opening`), ROS 2 bags and Push-T datasets
//! once their topics or features are chosen (`choosing`, `bag_import`, `dataset_import`), and a
//! live robot's server (`live`, with the push that grows as its frames arrive: `live_feed`).

pub mod bag_import;
pub(super) mod choosing;
pub mod dataset_import;
pub mod driving;
pub(super) mod grow;
pub mod growing;
pub mod live;
pub mod live_drive;
pub(super) mod live_drive_steps;
pub(super) mod live_feed;
pub(super) mod opening;
pub mod sandbox;
pub(super) mod sandbox_feed;
pub(super) mod sandbox_goal;
