//! The analytical parts of the combined model: Lynch's quasi-static pushing model and the COM
//! correction (paper eqs. 9–11, 14, 15), each with a hand-written backward pass.
//!
//! The paper's typesetting of Lynch's equations is garbled; these are the corrected ones
//! (Lynch, Maekawa and Tanie 1992, sticking contact, ellipsoidal limit surface):
//! `ΔCOM_x = ((h²+cx²)ucx + cx·cy·ucy)/(h²+cx²+cy²)`,
//! `ΔCOM_y = ((h²+cy²)ucy + cx·cy·ucx)/(h²+cx²+cy²)`,
//! `Δω = (cx·ΔCOM_y − cy·ΔCOM_x)/h²`,
//! with the contact point `c` relative to the COM and its motion `u_c`, both in the object frame.

use crate::math;
use crate::real::Real;
use crate::simd::{MulAdd, Unfused};

/// Motion of the COM and rotation predicted by Lynch's model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ComMotion<T> {
    /// COM translation, object frame at t.
    pub translation: [T; 2],
    /// Rotation, radians.
    pub rotation: T,
}

/// Lynch's model: the COM motion caused by moving the contact point `contact` (relative to the COM)
/// by `contact_motion`, for the limit-surface parameter `h` (metres).
#[inline(always)]
pub fn lynch<T: Real>(contact: [T; 2], contact_motion: [T; 2], h: T) -> ComMotion<T> {
    lynch_forward::<T, Unfused>(contact, contact_motion, h).0
}

/// What [`lynch_forward`] computes that its backward pass needs again: the two reciprocals (the only
/// divisions of the model) and the outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct LynchCache<T> {
    /// `1 / (h² + cx² + cy²)`.
    inv_d: T,
    /// `1 / h²`.
    inv_h2: T,
}

/// [`lynch`], also returning what [`lynch_backward_cached`] reuses.
#[inline(always)]
pub(crate) fn lynch_forward<T: Real, A: MulAdd>(
    contact: [T; 2],
    contact_motion: [T; 2],
    h: T,
) -> (ComMotion<T>, LynchCache<T>) {
    let [cx, cy] = contact;
    let [ux, uy] = contact_motion;
    let h2 = h * h;
    let inv_h2 = T::one() / h2;
    let cxx = A::mul_add(cx, cx, h2);
    let cyy = A::mul_add(cy, cy, h2);
    let inv_d = T::one() / A::mul_add(cy, cy, cxx);
    let cxy = cx * cy;
    let nx = A::mul_add(cxx, ux, cxy * uy);
    let ny = A::mul_add(cyy, uy, cxy * ux);
    let dx = nx * inv_d;
    let dy = ny * inv_d;
    (
        ComMotion {
            translation: [dx, dy],
            rotation: A::mul_add(cx, dy, -(cy * dx)) * inv_h2,
        },
        LynchCache { inv_d, inv_h2 },
    )
}

/// Gradients of a scalar with respect to the inputs of [`lynch`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LynchGradient<T> {
    pub contact: [T; 2],
    pub contact_motion: [T; 2],
    pub h: T,
}

/// Backward pass of [`lynch`]: given the gradient of a scalar with respect to its outputs, the
/// gradient with respect to its inputs (reverse-mode, derived by hand; checked against finite
/// differences in the tests).
#[inline(always)]
pub fn lynch_backward<T: Real>(
    contact: [T; 2],
    contact_motion: [T; 2],
    h: T,
    d_out: &ComMotion<T>,
) -> LynchGradient<T> {
    let (out, cache) = lynch_forward::<T, Unfused>(contact, contact_motion, h);
    lynch_backward_cached::<T, Unfused>(contact, contact_motion, h, &out, &cache, d_out)
}

/// [`lynch_backward`] from the outputs and cache of the forward pass, which it would otherwise
/// recompute (two divisions).
#[inline(always)]
pub(crate) fn lynch_backward_cached<T: Real, A: MulAdd>(
    contact: [T; 2],
    contact_motion: [T; 2],
    h: T,
    out: &ComMotion<T>,
    cache: &LynchCache<T>,
    d_out: &ComMotion<T>,
) -> LynchGradient<T> {
    let two = T::one() + T::one();
    let [cx, cy] = contact;
    let [ux, uy] = contact_motion;
    let h2 = h * h;
    let [dx, dy] = out.translation;
    let (inv_d, inv_h2) = (cache.inv_d, cache.inv_h2);

    // Δω = (cx Δy − cy Δx) / h².
    let g_rot_h2 = d_out.rotation * inv_h2;
    let mut g_cx = g_rot_h2 * dy;
    let mut g_cy = -g_rot_h2 * dx;
    let g_dy = A::mul_add(g_rot_h2, cx, d_out.translation[1]);
    let g_dx = A::mul_add(-g_rot_h2, cy, d_out.translation[0]);
    // ∂(1/h²)/∂h = −2/h³: −2 g_rot Δω / h = −2 g_rot Δω h / h².
    let mut g_h = -two * d_out.rotation * out.rotation * h * inv_h2;
    // Δx = Nx / D, Δy = Ny / D.
    let g_nx = g_dx * inv_d;
    let g_ny = g_dy * inv_d;
    let g_d = -A::mul_add(g_dx, dx, g_dy * dy) * inv_d;
    let two_g_d = two * g_d;
    g_h = A::mul_add(two_g_d, h, g_h);
    g_cx = A::mul_add(two_g_d, cx, g_cx);
    g_cy = A::mul_add(two_g_d, cy, g_cy);
    // Nx = (h² + cx²) ux + cx cy uy.
    g_h = A::mul_add(g_nx * two * h, ux, g_h);
    g_cx = A::mul_add(g_nx, A::mul_add(two * cx, ux, cy * uy), g_cx);
    g_cy = A::mul_add(g_nx, cx * uy, g_cy);
    let cxy = cx * cy;
    let mut g_ux = g_nx * A::mul_add(cx, cx, h2);
    let mut g_uy = g_nx * cxy;
    // Ny = (h² + cy²) uy + cx cy ux.
    g_h = A::mul_add(g_ny * two * h, uy, g_h);
    g_cy = A::mul_add(g_ny, A::mul_add(two * cy, uy, cx * ux), g_cy);
    g_cx = A::mul_add(g_ny, cy * ux, g_cx);
    g_uy = A::mul_add(g_ny, A::mul_add(cy, cy, h2), g_uy);
    g_ux = A::mul_add(g_ny, cxy, g_ux);
    LynchGradient {
        contact: [g_cx, g_cy],
        contact_motion: [g_ux, g_uy],
        h: g_h,
    }
}

/// Eq. 15 in this crate's convention: the motion of the geometric centre from the COM motion,
/// `Δp = ΔCOM − (R(Δω) − I)·com_offset` (the paper writes `+ (R − I)v` with `v = −com_offset`).
#[inline(always)]
pub fn centre_motion<T: Real>(com: &ComMotion<T>, com_offset: [T; 2]) -> [T; 2] {
    centre_motion_rotated::<T, Unfused>(com, math::sin_cos(com.rotation), com_offset)
}

/// [`centre_motion`] with `(sin Δω, cos Δω)` given, so that the backward pass can reuse them.
#[inline(always)]
pub(crate) fn centre_motion_rotated<T: Real, A: MulAdd>(
    com: &ComMotion<T>,
    (s, c): (T, T),
    com_offset: [T; 2],
) -> [T; 2] {
    let [ox, oy] = com_offset;
    let cm1 = c - T::one();
    [
        com.translation[0] - A::mul_add(cm1, ox, -(s * oy)),
        com.translation[1] - A::mul_add(s, ox, cm1 * oy),
    ]
}

/// Backward pass of [`centre_motion`]: from the gradient with respect to the centre motion `d_centre`
/// (and any direct gradient on the rotation, `d_rotation`), the gradient with respect to the COM
/// motion and the COM offset.
#[inline(always)]
pub fn centre_motion_backward<T: Real>(
    com: &ComMotion<T>,
    com_offset: [T; 2],
    d_centre: [T; 2],
    d_rotation: T,
) -> (ComMotion<T>, [T; 2]) {
    centre_motion_backward_rotated::<T, Unfused>(
        math::sin_cos(com.rotation),
        com_offset,
        d_centre,
        d_rotation,
    )
}

/// [`centre_motion_backward`] with `(sin Δω, cos Δω)` of the forward pass.
#[inline(always)]
pub(crate) fn centre_motion_backward_rotated<T: Real, A: MulAdd>(
    (s, c): (T, T),
    com_offset: [T; 2],
    d_centre: [T; 2],
    d_rotation: T,
) -> (ComMotion<T>, [T; 2]) {
    let [ox, oy] = com_offset;
    let [gx, gy] = d_centre;
    let cm1 = c - T::one();
    // ∂Δp/∂o = −(R − I); its transpose applied to the gradient.
    let d_offset = [-A::mul_add(cm1, gx, s * gy), -A::mul_add(-s, gx, cm1 * gy)];
    // ∂Δp/∂Δω = −R'(Δω)·o with R' = [[−s, −c], [c, −s]].
    let d_rot = d_rotation
        - A::mul_add(
            gx,
            A::mul_add(-s, ox, -(c * oy)),
            gy * A::mul_add(c, ox, -(s * oy)),
        );
    (
        ComMotion {
            translation: d_centre,
            rotation: d_rot,
        },
        d_offset,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    #[test]
    fn lynch_against_hand_computed_values() {
        // h = 0.05, c = (−0.1, 0.02), u_c = (0.01, 0.0):
        // D = 0.0025 + 0.01 + 0.0004 = 0.0129
        // Δx = (0.0125 · 0.01) / 0.0129 = 0.00968992…, Δy = (−0.002 · 0.01) / 0.0129 = −0.00155039…
        // Δω = (−0.1 · −0.00155039 − 0.02 · 0.00968992) / 0.0025 = (0.000155039 − 0.000193798) / 0.0025
        //    = −0.0155039…
        let m = lynch([-0.1, 0.02], [0.01, 0.0], 0.05);
        assert!(close(m.translation[0], 0.0125 * 0.01 / 0.0129, 1e-14));
        assert!(close(m.translation[1], -0.002 * 0.01 / 0.0129, 1e-14));
        let expected_rot =
            (-0.1 * (-0.002 * 0.01 / 0.0129) - 0.02 * (0.0125 * 0.01 / 0.0129)) / 0.0025;
        assert!(close(m.rotation, expected_rot, 1e-14));
        assert!(close(m.rotation, -0.015_503_875_968_992_248, 1e-12));
    }

    #[test]
    fn push_through_the_com_along_a_face_normal_translates_without_rotation() {
        // Front face at x = −a, pushed toward +x at its middle: c = (−a, 0), u_c = (u, 0).
        let m = lynch([-0.1, 0.0], [0.02, 0.0], 0.04);
        assert!(close(m.translation[0], 0.02, 1e-15));
        assert_eq!(m.translation[1], 0.0);
        assert_eq!(m.rotation, 0.0);
        // Left face at y = +b pushed toward −y.
        let m = lynch([0.0, 0.07], [0.0, -0.01], 0.04);
        assert_eq!(m.translation[0], 0.0);
        assert!(close(m.translation[1], -0.01, 1e-15));
        assert_eq!(m.rotation, 0.0);
    }

    #[test]
    fn mirrored_contact_points_give_mirrored_motion() {
        // Mirror about the object's x axis: (x, y) → (x, −y); rotations change sign.
        let a = lynch([-0.1, 0.03], [0.02, 0.005], 0.05);
        let b = lynch([-0.1, -0.03], [0.02, -0.005], 0.05);
        assert!(close(a.translation[0], b.translation[0], 1e-15));
        assert!(close(a.translation[1], -b.translation[1], 1e-15));
        assert!(close(a.rotation, -b.rotation, 1e-15));
        // A push below the COM on the front face (c_y < 0) turns the object counter-clockwise.
        assert!(b.rotation > 0.0 && a.rotation < 0.0);
    }

    #[test]
    fn sliding_free_limit_cases() {
        // h → ∞: the object barely turns and translates with the contact.
        let m = lynch([-0.1, 0.05], [0.01, 0.0], 1e3);
        assert!(close(m.translation[0], 0.01, 1e-6));
        assert!(m.rotation.abs() < 1e-9);
    }

    #[test]
    fn lynch_backward_matches_central_differences() {
        let c = [-0.08, 0.031];
        let u = [0.012, -0.004];
        let h = 0.045;
        let weights = ComMotion {
            translation: [0.7, -1.3],
            rotation: 0.4,
        };
        let f = |c: [f64; 2], u: [f64; 2], h: f64| {
            let m = lynch(c, u, h);
            weights.translation[0] * m.translation[0]
                + weights.translation[1] * m.translation[1]
                + weights.rotation * m.rotation
        };
        let g = lynch_backward(c, u, h, &weights);
        let eps = 1e-7;
        let num = |k: usize| {
            let mut p = [c[0], c[1], u[0], u[1], h];
            let mut m = p;
            p[k] += eps;
            m[k] -= eps;
            (f([p[0], p[1]], [p[2], p[3]], p[4]) - f([m[0], m[1]], [m[2], m[3]], m[4]))
                / (2.0 * eps)
        };
        let analytic = [
            g.contact[0],
            g.contact[1],
            g.contact_motion[0],
            g.contact_motion[1],
            g.h,
        ];
        for (k, a) in analytic.iter().enumerate() {
            let n = num(k);
            assert!(
                (a - n).abs() / a.abs().max(n.abs()) <= 1e-5,
                "input {k}: {a} vs {n}"
            );
        }
    }

    #[test]
    fn centre_motion_of_a_pure_rotation_about_an_offset_com() {
        // The COM stays put and the object turns by a quarter turn about it: the centre, at −o from the
        // COM, swings to −R·o, so it moves by −(R − I)·o.
        let com = ComMotion {
            translation: [0.0, 0.0],
            rotation: std::f64::consts::FRAC_PI_2,
        };
        let d = centre_motion(&com, [0.1, 0.0]);
        // Centre at (−0.1, 0) relative to the COM goes to (0, −0.1): moves by (0.1, −0.1).
        assert!(close(d[0], 0.1, 1e-15) && close(d[1], -0.1, 1e-15));
    }

    #[test]
    fn centre_motion_backward_matches_central_differences() {
        let o = [0.013, -0.021];
        let com = ComMotion {
            translation: [0.01, 0.002],
            rotation: 0.3,
        };
        let (wx, wy, wr) = (0.9, -0.4, 0.25);
        let f = |t: [f64; 2], r: f64, o: [f64; 2]| {
            let d = centre_motion(
                &ComMotion {
                    translation: t,
                    rotation: r,
                },
                o,
            );
            wx * d[0] + wy * d[1] + wr * r
        };
        let (g_com, g_o) = centre_motion_backward(&com, o, [wx, wy], wr);
        let eps = 1e-7;
        let x0 = [
            com.translation[0],
            com.translation[1],
            com.rotation,
            o[0],
            o[1],
        ];
        let analytic = [
            g_com.translation[0],
            g_com.translation[1],
            g_com.rotation,
            g_o[0],
            g_o[1],
        ];
        for k in 0..5 {
            let mut p = x0;
            let mut m = x0;
            p[k] += eps;
            m[k] -= eps;
            let n = (f([p[0], p[1]], p[2], [p[3], p[4]]) - f([m[0], m[1]], m[2], [m[3], m[4]]))
                / (2.0 * eps);
            let a = analytic[k];
            assert!(
                (a - n).abs() / a.abs().max(n.abs()) <= 1e-6,
                "input {k}: {a} vs {n}"
            );
        }
    }
}
