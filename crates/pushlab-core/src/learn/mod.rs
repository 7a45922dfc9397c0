//! Learning: the losses (eqs. 5–8), offline training of the network (eq. 12) and online learning of
//! `θ_online` (eq. 13, Algorithm 1).

mod adam;
mod loss;
mod offline;
mod online;
mod score_batches;
pub mod uncertainty;

pub use loss::{Loss, LossScale, Nmse, mean_std_across, moving_average};
pub use offline::{
    ContactTrajectory, TrainConfig, TrainError, TrainProgress, Trained, TrainingReport,
    paper_theta0, train_contact, train_paper, train_pure_nn, training_trajectories,
};
pub use online::{ContactLearner, OnlineConfig, OnlineLearner, OnlineModel, OnlineStep};
pub use uncertainty::{OnlineState, Optimizer, Posterior, learn_step};
