//! How far a trained model's learned COM lands from the truth on an object it never trained on —
//! the part of the COM's uncertainty that no statistic from inside one push can see.
//!
//! Why: on an object the network did not train on, its error is the same along the whole push, so
//! every frame agrees on the same wrong COM and the posterior (`learn::uncertainty`) narrows around
//! it. Measured on real MIT pushes of a held-out shape, its 95 % ellipse held the true COM in 23–40 %
//! of pushes with Gauss–Newton; a sandwich covariance or a physical prior moved that by at most one
//! push per shape. The bias can only be measured where the truth is known: training measures it by
//! leaving each of its objects out in turn (`experiment::calibrate_com_misfit_in_slices`), and the posterior
//! adds it to the COM's covariance as an isotropic spread of `per_h × h` (`θ_online(0)`'s `h`, so it
//! carries over to objects of another size).

use serde::{Deserialize, Serialize};

/// The COM misfit a model was calibrated with, per optimiser: the standard deviation added to each
/// COM component's posterior variance, in units of `θ_online(0)`'s `h`. All zero for a model that
/// was not calibrated (trained on one object, or on recordings without a known COM).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ComMisfit {
    /// With online gradient descent.
    pub gd_per_h: f64,
    /// With Gauss–Newton.
    pub gauss_newton_per_h: f64,
    /// The pushes it was measured on (online on an object left out of training, COM known).
    pub pushes: usize,
    /// The objects left out in turn.
    pub objects: usize,
}

impl ComMisfit {
    /// Whether it was measured at all.
    pub fn is_calibrated(&self) -> bool {
        self.pushes > 0
    }
}
