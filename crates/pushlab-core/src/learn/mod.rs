//! Learning, above the models: offline training of the network (eq. 12), online learning of
//! `θ_online` (eq. 13, Algorithm 1) with its posterior, and the metrics over many predictions (eq. 7).

mod adam;
mod config;
mod metrics;
mod offline;
mod run;
mod score_batches;
mod step;
pub mod uncertainty;
mod weighting;

pub use config::{OnlineConfig, Optimizer};
pub use metrics::{Nmse, mean_std_across, moving_average};
pub use offline::{
    ContactTrajectory, TrainConfig, TrainError, TrainProgress, TrainStage, Trained, TrainingEnding,
    TrainingReport, paper_theta0, train_contact, train_contact_in_slices, train_paper,
    train_paper_in_slices, train_pure_nn, train_pure_nn_in_slices, training_trajectories,
};
pub use run::{KEYFRAME, MeanLosses, OnlineRun};
pub use step::{OnlineState, learn_step, learn_step_in_place};
pub use uncertainty::{Posterior, PushInformation, Spread};
pub use weighting::{FrameTime, MAX_LOG_ODDS, ModelWeight, WeightConfig, WeightedFrame, Weights};
