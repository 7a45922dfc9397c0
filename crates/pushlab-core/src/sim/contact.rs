//! One quasi-static step of Lynch and Mason's pusher–slider: how the object moves when the pusher's
//! contact point moves by a small `u`.
//!
//! Everything here is in the COM frame: the object's axes with the origin at the centre of mass. The
//! limit surface is the ellipsoid `fx² + fy² + (m/h)² = f_max²`, so a contact force `f` at `c` moves
//! the object with the twist `(f, (c × f)/h²)` (up to a positive factor), and its contact point with
//! `M f = f + ((c × f)/h²) c⊥`, `c⊥ = (−c_y, c_x)`. `M` maps the friction cone at the contact onto the
//! *motion cone*: a contact motion inside it sticks, one outside it slides along the edge and the object
//! moves as if pushed along the nearer boundary of the cone.

use nalgebra::Vector2;

use crate::geometry::cross;

/// What the contact does during a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactMode {
    /// The pusher does not press on the object (it moves away or along the surface): nothing moves.
    Separating,
    /// The contact point moves with the pusher (the push lies inside the motion cone).
    Sticking,
    /// The pusher slides along the edge in the `+t` direction relative to the object, where `t` is the
    /// inward normal turned by +90°; the contact force lies on that edge of the friction cone.
    SlidingPositive,
    /// The pusher slides along the edge in the `−t` direction relative to the object.
    SlidingNegative,
}

impl ContactMode {
    /// Whether the pusher slides along the object's edge.
    pub fn is_sliding(self) -> bool {
        matches!(
            self,
            ContactMode::SlidingPositive | ContactMode::SlidingNegative
        )
    }
}

/// How the object moves during one step, COM frame at the start of the step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectStep {
    /// Sticking, sliding or separating.
    pub mode: ContactMode,
    /// Motion of the COM, metres (first order in the step).
    pub com_motion: Vector2<f64>,
    /// Rotation of the object, radians.
    pub rotation: f64,
}

impl ObjectStep {
    fn at_rest(mode: ContactMode) -> Self {
        Self {
            mode,
            com_motion: Vector2::zeros(),
            rotation: 0.0,
        }
    }

    /// The motion of the object's material point at `point` (COM frame) during the step.
    pub fn motion_of_point(&self, point: Vector2<f64>) -> Vector2<f64> {
        self.com_motion + self.rotation * Vector2::new(-point.y, point.x)
    }
}

/// The paper's eqs. (9)–(11): the object's motion when the contact point `contact` (relative to the
/// COM) sticks to the pusher and moves by `contact_motion`.
pub fn lynch_sticking(
    contact: Vector2<f64>,
    contact_motion: Vector2<f64>,
    h: f64,
) -> (Vector2<f64>, f64) {
    let (cx, cy) = (contact.x, contact.y);
    let (ux, uy) = (contact_motion.x, contact_motion.y);
    let h2 = h * h;
    let denominator = h2 + cx * cx + cy * cy;
    let dx = ((h2 + cx * cx) * ux + cx * cy * uy) / denominator;
    let dy = ((h2 + cy * cy) * uy + cx * cy * ux) / denominator;
    let rotation = (cx * dy - cy * dx) / h2;
    (Vector2::new(dx, dy), rotation)
}

/// The contact point's motion produced by a contact force `force` at `contact`: `M f` (up to the
/// positive factor of the limit surface).
fn contact_motion_from_force(contact: Vector2<f64>, force: Vector2<f64>, h: f64) -> Vector2<f64> {
    force + Vector2::new(-contact.y, contact.x) * (cross(contact, force) / (h * h))
}

/// The two edges of the motion cone at a contact, as contact-point motions: the images of the
/// friction-cone edges `n ± μ t`, in the order (`+t` edge, `−t` edge).
pub fn motion_cone(
    contact: Vector2<f64>,
    inward_normal: Vector2<f64>,
    friction: f64,
    h: f64,
) -> [Vector2<f64>; 2] {
    let tangent = Vector2::new(-inward_normal.y, inward_normal.x);
    [1.0, -1.0].map(|sign| {
        contact_motion_from_force(contact, inward_normal + tangent * (sign * friction), h)
    })
}

/// One quasi-static step: the object's motion when the pusher touching it at `contact` (COM frame),
/// with the object's inward surface normal `inward_normal` there (unit), moves by `pusher_motion`
/// (object axes). `friction` is the pusher–object Coulomb coefficient, `h` Lynch's `c` (metres).
///
/// The step is first order: in the limit of small `pusher_motion` it is exact. The normal component of
/// the contact point's motion always equals the pusher's, so the pusher neither penetrates nor leaves
/// the object to first order.
pub fn pusher_slider_step(
    contact: Vector2<f64>,
    inward_normal: Vector2<f64>,
    friction: f64,
    h: f64,
    pusher_motion: Vector2<f64>,
) -> ObjectStep {
    let normal_motion = inward_normal.dot(&pusher_motion);
    if normal_motion <= 0.0 {
        return ObjectStep::at_rest(ContactMode::Separating);
    }
    let tangent = Vector2::new(-inward_normal.y, inward_normal.x);

    // Sticking: the COM motion is proportional to the contact force (the limit surface is a sphere in
    // force once the moment is scaled by h), so the force needed to stick is the COM motion itself.
    let (com_motion, rotation) = lynch_sticking(contact, pusher_motion, h);
    let force_normal = inward_normal.dot(&com_motion);
    let force_tangent = tangent.dot(&com_motion);
    if force_normal > 0.0 && force_tangent.abs() <= friction * force_normal {
        return ObjectStep {
            mode: ContactMode::Sticking,
            com_motion,
            rotation,
        };
    }

    // Sliding: the force lies on one edge of the friction cone, scaled so that the normal motions of
    // pusher and contact point agree. Of the two edges, the right one is where the pusher's slip along
    // the edge points the same way as the friction force it exerts.
    let preferred = if force_tangent >= 0.0 { 1.0 } else { -1.0 };
    let mut fallback = None;
    for sign in [preferred, -preferred] {
        let force = inward_normal + tangent * (sign * friction);
        let edge_motion = contact_motion_from_force(contact, force, h);
        let edge_normal = inward_normal.dot(&edge_motion);
        if edge_normal <= 0.0 {
            continue;
        }
        let scale = normal_motion / edge_normal;
        let slip = tangent.dot(&(pusher_motion - edge_motion * scale));
        let step = ObjectStep {
            mode: if sign > 0.0 {
                ContactMode::SlidingPositive
            } else {
                ContactMode::SlidingNegative
            },
            com_motion: force * scale,
            rotation: scale * cross(contact, force) / (h * h),
        };
        if sign * slip >= -1e-12 * pusher_motion.norm() {
            return step;
        }
        fallback.get_or_insert(step);
    }
    // For a single point contact on an ellipsoid limit surface one edge is always consistent (checked
    // over random contacts in the tests); the fallback only guards against rounding at the boundary.
    fallback.unwrap_or(ObjectStep::at_rest(ContactMode::Separating))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::noise::NoiseStream;

    /// Over many random contacts and pushes, the chosen sliding edge is consistent: the pusher's slip
    /// has the sign of the friction force, and the object's contact point follows the pusher's normal
    /// motion exactly.
    #[test]
    fn sliding_solutions_are_consistent_over_random_contacts() {
        let mut rng = NoiseStream::new(7);
        let mut sliding = 0;
        for _ in 0..20_000 {
            let contact = Vector2::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3));
            let angle = rng.uniform(-std::f64::consts::PI, std::f64::consts::PI);
            let inward = Vector2::new(angle.cos(), angle.sin());
            let friction = rng.uniform(0.0, 1.5);
            let h = rng.uniform(0.02, 0.3);
            let push_angle = rng.uniform(-1.5, 1.5) + angle;
            let u = Vector2::new(push_angle.cos(), push_angle.sin()) * 1e-3;
            let step = pusher_slider_step(contact, inward, friction, h, u);
            let moved = step.motion_of_point(contact);
            assert!(
                (inward.dot(&moved) - inward.dot(&u)).abs() < 1e-12,
                "normal motion mismatch {step:?}"
            );
            let tangent = Vector2::new(-inward.y, inward.x);
            let slip = tangent.dot(&(u - moved));
            match step.mode {
                ContactMode::Sticking => assert!(slip.abs() < 1e-12),
                ContactMode::SlidingPositive => {
                    sliding += 1;
                    assert!(slip > -1e-15, "slip {slip} against the force, {step:?}");
                }
                ContactMode::SlidingNegative => {
                    sliding += 1;
                    assert!(slip < 1e-15, "slip {slip} against the force, {step:?}");
                }
                ContactMode::Separating => panic!("pushing into the object separated: {step:?}"),
            }
        }
        assert!(sliding > 1000, "too few sliding cases to mean anything");
    }
}
