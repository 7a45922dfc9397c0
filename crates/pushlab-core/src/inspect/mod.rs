//! Looking inside online learning, beyond the paper's point estimate: the loss over a grid of
//! `θ_online` ([`landscape`]) shows why the estimate moves as it does and which directions the data
//! leave undetermined; rolling the model forward ([`rollout`]) shows what it would do next.
//! The posterior of `θ_online` itself lives with the learning (`learn::uncertainty`).

pub mod landscape;
pub mod rollout;

pub use landscape::{ComGrid, Landscape, com_landscape, h_slice};
pub use rollout::{Rollout, rollout};
