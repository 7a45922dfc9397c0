//! The contact-frame model's physical prior for the contact motion: what the contact point would do
//! if the object were an ideal quasi-static slider with Coulomb friction at the contact. The network
//! only corrects it, so a push unlike anything seen offline degrades toward physics instead of toward
//! an extrapolated network.
//!
//! Two parts, both in the contact frame (first axis the inward normal, second the tangent):
//! - **Sweep** (does not depend on `θ_online`): over a horizon of many frames the pusher may start
//!   short of the object; only the part of its motion after it reaches the outline pushes. With the
//!   gap `g` (less a tolerance for tracking noise) and the pusher's normal motion `m_n`, the pushing
//!   motion is `m · clamp((m_n − max(g, 0)) / m_n, 0, 1)`, and nothing when the pusher moves away.
//! - **Motion cone** (Mason; Lynch, Maekawa and Tanie 1992): with the ellipsoidal limit surface of
//!   `h`, a sticking contact at `c` (relative to the COM) moved by `u` needs the force direction
//!   `f ∝ (h² u + c (c·u))` — the COM motion of Lynch's model. When `f` leaves the friction cone
//!   `|f_t| ≤ μ f_n`, the contact slides: the force lies on the cone's edge `f = (1, ±μ)`, the object
//!   twists as that force makes it (`v ∝ f`, `ω ∝ (c × f) / h²`), and the contact point's velocity
//!   `v_c = f + (c × f)/h² · c⊥` is scaled so that its normal part equals the pusher's. Fed to
//!   Lynch's model, that contact motion gives exactly the sliding motion.
//!
//! Both are equivariant under rotations and reflections of the frame (they use dot products, and the
//! cross product enters twice), which the contact frame's mirror canonicalisation relies on.

use crate::real::Real;

/// Smallest normal component of the sliding contact velocity direction for which the cone's sliding
/// solution is used; below it (a contact far off the COM line with a tiny `h`) the sticking motion is.
const MIN_SLIDING_NORMAL: f64 = 1e-3;

/// The swept pushing motion in the contact frame: see the module documentation.
#[inline(always)]
pub fn swept_motion(motion: [f64; 2], gap: f64, tolerance: f64) -> [f64; 2] {
    let normal = motion[0];
    if normal <= 1e-12 {
        return [0.0, 0.0];
    }
    let fraction = ((normal - (gap - tolerance).max(0.0)) / normal).clamp(0.0, 1.0);
    [motion[0] * fraction, motion[1] * fraction]
}

/// What the cone's forward pass keeps for its backward pass.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ConePass<T> {
    /// Whether the contact slides (the sliding quantities below are only meaningful then).
    sliding: bool,
    /// `±μ`: the tangential part of the force on the cone's edge.
    edge: T,
    /// `(c × f) / h²`.
    w: T,
    /// The contact velocity direction `v_c`.
    vc: [T; 2],
    /// The swept motion's normal component.
    push: T,
}

/// The gradient of a scalar with respect to the cone prior's inputs.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct ConeGradient<T> {
    pub contact: [T; 2],
    pub h: T,
    pub friction: T,
}

/// The contact motion the motion cone allows for the swept motion `swept` at the COM-relative contact
/// point `contact` (contact frame), with Lynch's `h` and friction coefficient `friction`.
#[inline(always)]
pub(crate) fn cone_forward<T: Real>(
    contact: [T; 2],
    swept: [T; 2],
    h: T,
    friction: T,
    pass: &mut ConePass<T>,
) -> [T; 2] {
    let h2 = h * h;
    let [c0, c1] = contact;
    // The force direction of a sticking contact (Lynch's COM motion, without its positive divisor).
    let along = c0 * swept[0] + c1 * swept[1];
    let f_n = h2 * swept[0] + c0 * along;
    let f_t = h2 * swept[1] + c1 * along;
    pass.sliding = false;
    if !(f_n > T::zero() && f_t.abs() > friction * f_n) {
        return swept;
    }
    let edge = if f_t > T::zero() { friction } else { -friction };
    let cross = c0 * edge - c1;
    let w = cross / h2;
    let vc = [T::one() - w * c1, edge + w * c0];
    if vc[0] < T::of(MIN_SLIDING_NORMAL) {
        return swept;
    }
    *pass = ConePass {
        sliding: true,
        edge,
        w,
        vc,
        push: swept[0],
    };
    [swept[0], swept[0] * vc[1] / vc[0]]
}

/// The backward pass of [`cone_forward`] from the gradient with respect to its output.
#[inline(always)]
pub(crate) fn cone_backward<T: Real>(
    contact: [T; 2],
    h: T,
    pass: &ConePass<T>,
    d_output: [T; 2],
) -> ConeGradient<T> {
    if !pass.sliding {
        return ConeGradient {
            contact: [T::zero(); 2],
            h: T::zero(),
            friction: T::zero(),
        };
    }
    let [c0, c1] = contact;
    let two = T::one() + T::one();
    let h2 = h * h;
    // Output = (push, push · vc1 / vc0): only the tangential part depends on the inputs.
    let d_t = d_output[1];
    let d_vc0 = -d_t * pass.push * pass.vc[1] / (pass.vc[0] * pass.vc[0]);
    let d_vc1 = d_t * pass.push / pass.vc[0];
    // vc = (1 − w c1, edge + w c0).
    let d_w = -d_vc0 * c1 + d_vc1 * c0;
    let mut d_c0 = d_vc1 * pass.w;
    let mut d_c1 = -d_vc0 * pass.w;
    let mut d_edge = d_vc1;
    // w = (c0 edge − c1) / h².
    let d_cross = d_w / h2;
    let d_h = -two * pass.w * d_w / h;
    d_c0 = d_c0 + d_cross * pass.edge;
    d_c1 = d_c1 - d_cross;
    d_edge = d_edge + d_cross * c0;
    // edge = ±μ.
    let d_friction = if pass.edge > T::zero() {
        d_edge
    } else {
        -d_edge
    };
    ConeGradient {
        contact: [d_c0, d_c1],
        h: d_h,
        friction: d_friction,
    }
}

#[cfg(test)]
impl<T> ConePass<T> {
    /// Whether the last forward pass slid (for tests that must exercise the sliding branch).
    pub fn sliding_for_tests(&self) -> bool {
        self.sliding
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::lynch;

    fn cone(contact: [f64; 2], swept: [f64; 2], h: f64, mu: f64) -> [f64; 2] {
        cone_forward(contact, swept, h, mu, &mut ConePass::default())
    }

    #[test]
    fn sweep_keeps_the_motion_after_contact() {
        assert_eq!(swept_motion([0.04, 0.01], 0.01, 0.0), [0.03, 0.0075]);
        assert_eq!(swept_motion([0.04, 0.01], 0.012, 0.002), [0.03, 0.0075]);
        assert_eq!(swept_motion([0.04, 0.01], -0.003, 0.0), [0.04, 0.01]);
        assert_eq!(swept_motion([0.04, 0.01], 0.05, 0.0), [0.0, 0.0]);
        assert_eq!(swept_motion([-0.01, 0.01], 0.0, 0.0), [0.0, 0.0]);
    }

    #[test]
    fn a_push_inside_the_cone_sticks_and_one_outside_slides_on_the_cone_edge() {
        // Contact on the COM line, pushed straight: sticks whatever μ.
        assert_eq!(cone([-0.15, 0.0], [0.01, 0.0], 0.1, 0.1), [0.01, 0.0]);
        // A steep push with little friction slides: the normal part is kept, the tangential part
        // shrinks, and the force (Lynch's COM motion for the returned contact motion) lies on the
        // cone's edge.
        let (c, u, h, mu) = ([-0.15, 0.05], [0.01, 0.02], 0.1, 0.3);
        let slid = cone(c, u, h, mu);
        assert_eq!(slid[0], 0.01);
        assert!(slid[1].abs() < 0.02);
        let com = lynch(c, slid, h);
        let ratio = com.translation[1] / com.translation[0];
        assert!((ratio - mu).abs() < 1e-12, "force ratio {ratio}");
        // The sliding solution moves continuously into the sticking one at the cone's edge.
        let sticking = lynch(c, u, h);
        let edge_mu = sticking.translation[1] / sticking.translation[0];
        let just_outside = cone(c, u, h, edge_mu * (1.0 - 1e-9));
        assert!((just_outside[1] - u[1]).abs() < 1e-9, "{just_outside:?}");
    }

    #[test]
    fn cone_is_mirror_equivariant() {
        let a = cone([-0.15, 0.05], [0.01, 0.02], 0.1, 0.3);
        let b = cone([-0.15, -0.05], [0.01, -0.02], 0.1, 0.3);
        assert!(a[1] != 0.02, "the test push must slide");
        assert_eq!(a[0], b[0]);
        assert!((a[1] + b[1]).abs() < 1e-18);
    }

    #[test]
    fn cone_backward_matches_central_differences() {
        let (c, u, h, mu) = ([-0.15, 0.05], [0.01, 0.02], 0.1, 0.3);
        let weights = [0.7, -1.3];
        let f = |c: [f64; 2], h: f64, mu: f64| {
            let out = cone(c, u, h, mu);
            weights[0] * out[0] + weights[1] * out[1]
        };
        let mut pass = ConePass::default();
        cone_forward(c, u, h, mu, &mut pass);
        assert!(pass.sliding);
        let g = cone_backward(c, h, &pass, weights);
        let eps = 1e-7;
        let numeric = [
            (f([c[0] + eps, c[1]], h, mu) - f([c[0] - eps, c[1]], h, mu)) / (2.0 * eps),
            (f([c[0], c[1] + eps], h, mu) - f([c[0], c[1] - eps], h, mu)) / (2.0 * eps),
            (f(c, h + eps, mu) - f(c, h - eps, mu)) / (2.0 * eps),
            (f(c, h, mu + eps) - f(c, h, mu - eps)) / (2.0 * eps),
        ];
        let analytic = [g.contact[0], g.contact[1], g.h, g.friction];
        for (k, (a, n)) in analytic.iter().zip(numeric).enumerate() {
            assert!(
                (a - n).abs() <= 1e-6 * a.abs().max(n.abs()).max(1e-9),
                "input {k}: {a} vs {n}"
            );
        }
    }
}
