//! Looking inside online learning, beyond the paper's point estimate: the loss over a grid of
//! `θ_online` ([`landscape`]) shows why the estimate moves as it does and which directions the data
//! leave undetermined; rolling the model forward ([`rollout`]) shows what it would do next, and what a push not yet
//! made would teach ([`next_push`]).
//! The posterior of `θ_online` itself lives with the learning (`learn::uncertainty`).

pub mod contour;
pub mod landscape;
pub mod next_push;
pub mod rollout;

pub use contour::{Contour, DEFAULT_QUANTILES, contour_levels, contours};
pub use landscape::{
    ComGrid, Landscape, LandscapeFrames, MAX_LANDSCAPE_SAMPLES, com_landscape,
    com_landscape_in_slices, h_slice, landscape_samples,
};
pub use next_push::{PushShape, information_along, information_of, predicted_poses, shape_of};
pub use rollout::{Rollout, ahead, rollout};
