//! The analytical tail every combined model ends with: Lynch's model on a COM-relative contact point
//! and contact motion, then the motion correction (eq. 15), with its backward pass.
//!
//! Each model kind computes the contact point and the contact motion its own way (the paper's network
//! in the object frame, the contact-frame network with its physical prior) and hands them to this one
//! tail, so Lynch and eq. 15 and their chain rule are written once.

use super::physics::{
    ComMotion, LynchCache, centre_motion_backward_rotated, centre_motion_rotated,
    lynch_backward_cached, lynch_forward,
};
use super::{ObjectMotion, Prediction};
use crate::math;
use crate::real::Real;
use crate::simd::MulAdd;

/// What the tail's forward pass keeps for its backward pass.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TailPass<T> {
    /// Contact point relative to the COM, object frame.
    pub contact: [T; 2],
    /// Contact motion, object frame.
    pub contact_motion: [T; 2],
    pub com: ComMotion<T>,
    lynch: LynchCache<T>,
    /// `(sin Δω, cos Δω)` of the predicted rotation.
    rotation_sin_cos: (T, T),
    /// Predicted motion of the geometric centre.
    pub centre: [T; 2],
}

/// The gradient of a scalar with respect to the tail's inputs.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct TailGradient<T> {
    /// With respect to the COM-relative contact point.
    pub contact: [T; 2],
    pub contact_motion: [T; 2],
    /// With respect to the COM offset through eq. 15 only (the contact point's own dependence on the
    /// COM offset is the caller's).
    pub com_offset: [T; 2],
    pub h: T,
}

impl<T: Real> TailPass<T> {
    /// Lynch's model and eq. 15 for `theta = [com_x, com_y, h]`. Written field by field into `self`
    /// before the call to `sin_cos`: every vector register is caller-saved, so values kept only in
    /// registers across the call would all be spilled.
    #[inline(always)]
    pub fn forward<A: MulAdd>(&mut self, contact: [T; 2], contact_motion: [T; 2], theta: &[T; 3]) {
        self.contact = contact;
        self.contact_motion = contact_motion;
        (self.com, self.lynch) = lynch_forward::<T, A>(contact, contact_motion, theta[2]);
        self.rotation_sin_cos = math::sin_cos(self.com.rotation);
        self.centre =
            centre_motion_rotated::<T, A>(&self.com, self.rotation_sin_cos, [theta[0], theta[1]]);
    }

    /// The predicted `[Δp_x, Δp_y, Δω]`.
    #[inline(always)]
    pub fn output(&self) -> [T; 3] {
        [self.centre[0], self.centre[1], self.com.rotation]
    }

    /// The backward pass from the gradient with respect to `[Δp_x, Δp_y, Δω]`.
    #[inline(always)]
    pub fn backward<A: MulAdd>(&self, theta: &[T; 3], d_output: [T; 3]) -> TailGradient<T> {
        let (d_com, d_offset) = centre_motion_backward_rotated::<T, A>(
            self.rotation_sin_cos,
            [theta[0], theta[1]],
            [d_output[0], d_output[1]],
            d_output[2],
        );
        let d_lynch = lynch_backward_cached::<T, A>(
            self.contact,
            self.contact_motion,
            theta[2],
            &self.com,
            &self.lynch,
            &d_com,
        );
        TailGradient {
            contact: d_lynch.contact,
            contact_motion: d_lynch.contact_motion,
            com_offset: d_offset,
            h: d_lynch.h,
        }
    }

    /// The public prediction: the contact point shifted back from the COM to the geometric centre.
    #[inline(always)]
    pub fn prediction(&self, theta: &[T; 3]) -> Prediction {
        let f = |x: T| x.as_f64();
        Prediction {
            motion: ObjectMotion {
                translation: [f(self.centre[0]), f(self.centre[1])],
                rotation: f(self.com.rotation),
            },
            contact: Some([f(self.contact[0] + theta[0]), f(self.contact[1] + theta[1])]),
            contact_motion: Some([f(self.contact_motion[0]), f(self.contact_motion[1])]),
        }
    }
}
