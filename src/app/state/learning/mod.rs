//! Learning: the online run on the recording shown (θ and the losses per frame) and everything
//! that learns beside it — learning far ahead on a worker, the best θ, the loss landscape, the
//! ranking of the next push — with the plots' series of the run. `frame_moves` says what a move of
//! the frame learns.

pub(super) mod ahead;
pub mod best_fit;
pub mod envelope;
pub(super) mod frame_moves;
pub mod landscape;
pub mod next_push;
pub mod online;
pub mod run_plots;
