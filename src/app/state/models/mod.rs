//! The models: those the app predicts with (`loaded`), the one in use and whether it fits the open
//! recordings (`in_use`), and offline training on a worker (`training`, on the recordings
//! `training_choice` picks).

pub(super) mod in_use;
pub mod loaded;
pub mod training;
pub(super) mod training_choice;

pub use self::loaded::Models;
