//! The contact frame: where on the outline the pusher touches (or is nearest to), and the local frame
//! there in which the contact-frame model sees every push the same way.
//!
//! The frame's first axis is the inward normal of the outline at the nearest point `q`, the second the
//! tangent. Its handedness is chosen so that `q` lies on the positive side of the tangent as seen from
//! the geometric centre (ties: the side the pusher moves to): a push and its mirror image then look
//! identical to the network, so the model is mirror-symmetric by construction (the frame is a
//! reflection of the object frame for half of the pushes; Lynch's model and the motion cone are
//! reflection-equivariant, see `prior.rs`).
//!
//! On a non-convex outline the nearest point is found the same way, and the inside test is the
//! crossing rule. In a concave notch where two faces are equally near the pusher (on the bisector of
//! the corner between them), the lower-numbered edge is taken, as [`Outline::closest_boundary_point`]
//! does: the frame jumps from one face to the other as the pusher crosses that bisector, so a pusher
//! touching both faces at once is seen by the network as pushing on one of them (the same face the
//! simulator pushes on). Inside the footprint, nearest to a concave corner, the normal points from the
//! pusher to the corner.

use nalgebra::{Point2, Vector2};

use crate::geometry::Outline;
use crate::model::PhysicalBounds;

/// An object's outline and the pusher's radius as the contact-frame model uses them: each edge with
/// its direction, length and outward normal precomputed, so that the nearest point costs no square root
/// or division per edge.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactGeometry {
    edges: Vec<Edge>,
    /// The footprint's area centroid (the geometric centre), object frame.
    centroid: Point2<f64>,
    /// Radius of the pusher disc, metres.
    pusher_radius: f64,
    /// `h` of a uniform pressure over the footprint about its centroid: `θ_online(0)`'s `h`.
    uniform_h: f64,
    /// The largest extent of the bounding box.
    size: f64,
    /// Whether the outline is convex (the half-plane inside test and edge normals inside suffice).
    convex: bool,
    /// Where `θ_online` can physically be on this object.
    bounds: PhysicalBounds,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct Edge {
    start: Point2<f64>,
    /// The next vertex, for the crossing rule of a non-convex outline.
    end: Point2<f64>,
    /// Unit direction, counter-clockwise.
    direction: Vector2<f64>,
    length: f64,
    /// Outward unit normal.
    normal: Vector2<f64>,
}

/// The nearest boundary point and the local frame there, for one pusher position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ContactFrame {
    /// Nearest boundary point, object frame.
    pub point: Point2<f64>,
    /// Inward unit normal there: the frame's first axis.
    pub normal_in: Vector2<f64>,
    /// The frame's second axis: the tangent, `±` the normal turned a quarter counter-clockwise.
    pub tangent: Vector2<f64>,
    /// Distance from the pusher's rim to the outline (negative when they overlap), metres.
    pub gap: f64,
}

impl ContactGeometry {
    /// The geometry of an object with this outline pushed by a disc of this radius.
    pub fn new(outline: &Outline, pusher_radius: f64) -> Self {
        let edges = outline
            .edges()
            .map(|(a, b)| {
                let ab = b - a;
                let length = ab.norm();
                let direction = ab / length;
                Edge {
                    start: a,
                    end: b,
                    direction,
                    length,
                    normal: Vector2::new(direction.y, -direction.x),
                }
            })
            .collect();
        let centroid = outline.centroid();
        Self {
            edges,
            centroid,
            pusher_radius,
            uniform_h: outline.uniform_pressure_h(centroid, 200),
            size: outline.size(),
            convex: outline.is_convex(),
            bounds: PhysicalBounds::of(outline),
        }
    }

    /// Where `θ_online` can physically be on this object.
    pub fn bounds(&self) -> &PhysicalBounds {
        &self.bounds
    }

    /// Radius of the pusher disc, metres.
    pub fn pusher_radius(&self) -> f64 {
        self.pusher_radius
    }

    /// `h` of a uniform pressure over the footprint about its centroid, metres.
    pub fn uniform_h(&self) -> f64 {
        self.uniform_h
    }

    /// The largest extent of the object's bounding box, metres.
    pub fn size(&self) -> f64 {
        self.size
    }

    /// The contact frame for a pusher at `pusher` moving by `motion` (both object frame).
    ///
    /// The nearest point and its outward normal follow [`Outline::closest_boundary_point`]: on an
    /// edge's interior the edge's normal, at a corner the direction from the corner to the pusher
    /// (from the pusher to the corner when it is inside a concave one); ties go to the lower-numbered
    /// edge.
    #[inline(always)]
    pub(crate) fn frame(&self, pusher: Point2<f64>, motion: Vector2<f64>) -> ContactFrame {
        let mut inside = true;
        let mut crossings_odd = false;
        let mut best = (f64::INFINITY, pusher, Vector2::x(), false);
        for e in &self.edges {
            let from_start = pusher - e.start;
            if self.convex {
                if from_start.dot(&e.normal) > 1e-12 {
                    inside = false;
                }
            } else if (e.start.y > pusher.y) != (e.end.y > pusher.y) {
                let x = e.start.x
                    + (pusher.y - e.start.y) * (e.end.x - e.start.x) / (e.end.y - e.start.y);
                crossings_odd ^= pusher.x < x;
            }
            let along = from_start.dot(&e.direction);
            let t = along.clamp(0.0, e.length);
            let q = e.start + e.direction * t;
            let distance_sq = (pusher - q).norm_squared();
            if distance_sq < best.0 {
                best = (distance_sq, q, e.normal, t > 0.0 && t < e.length);
            }
        }
        if !self.convex {
            inside = crossings_odd;
        }
        let (distance_sq, point, edge_normal, on_interior) = best;
        let distance = distance_sq.sqrt();
        let normal = if on_interior || distance < 1e-12 || (inside && self.convex) {
            edge_normal
        } else if inside {
            (point - pusher) / distance
        } else {
            (pusher - point) / distance
        };
        let signed_distance = if inside { -distance } else { distance };
        let normal_in = -normal;
        let quarter = Vector2::new(-normal_in.y, normal_in.x);
        // Which side of the centre the contact is on decides the handedness; a push through the middle
        // is decided by where the pusher moves.
        let key = quarter.dot(&(point - self.centroid));
        let tie = 1e-12 * self.size.max(1e-9);
        let side = if key.abs() > tie {
            key
        } else {
            quarter.dot(&motion)
        };
        let tangent = if side < 0.0 { -quarter } else { quarter };
        ContactFrame {
            point,
            normal_in,
            tangent,
            gap: signed_distance - self.pusher_radius,
        }
    }
}

impl ContactFrame {
    /// A vector in the contact frame's coordinates `(normal, tangent)`.
    #[inline(always)]
    pub fn in_frame(&self, v: Vector2<f64>) -> [f64; 2] {
        [v.dot(&self.normal_in), v.dot(&self.tangent)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_point_matches_the_outline_query_and_the_frame_is_orthonormal() {
        let outline = Outline::ellipse(Point2::new(0.01, -0.02), 0.06, 0.09, 24).expect("valid");
        let geometry = ContactGeometry::new(&outline, 0.01);
        for (i, p) in [
            [-0.2, 0.03],
            [0.01, 0.2],
            [0.3, -0.3],
            [0.02, -0.01],
            [0.07, 0.0],
        ]
        .into_iter()
        .enumerate()
        {
            let p = Point2::from(p);
            let expected = outline.closest_boundary_point(p);
            let frame = geometry.frame(p, Vector2::new(0.01, 0.0));
            assert!((frame.point - expected.point).norm() < 1e-12, "point {i}");
            assert!(
                (frame.normal_in + expected.normal).norm() < 1e-12,
                "normal {i}"
            );
            assert!((frame.gap - (expected.signed_distance - 0.01)).abs() < 1e-12);
            assert!(frame.normal_in.dot(&frame.tangent).abs() < 1e-15);
            assert!((frame.tangent.norm() - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn on_the_t_the_frame_matches_the_outline_query_also_in_its_notches() {
        use crate::geometry::PushT;
        let outline = PushT::outline(0.001).expect("the T");
        let geometry = ContactGeometry::new(&outline, 0.015);
        let local = |x: f64, y: f64| PushT::object_from_local(Point2::new(x, y), 0.001);
        for p in [
            local(40.0, 60.0),  // In the right notch, nearer the stem.
            local(40.0, 35.0),  // In the right notch, nearer the bar.
            local(35.0, 50.0),  // On the notch's bisector: both faces equally near.
            local(12.0, 27.0),  // Inside, nearest the concave corner (15, 30).
            local(-70.0, 10.0), // Outside the bar's end.
            local(0.0, 100.0),  // Inside the stem.
        ] {
            let expected = outline.closest_boundary_point(p);
            let frame = geometry.frame(p, Vector2::new(0.0, -0.01));
            assert!((frame.point - expected.point).norm() < 1e-12, "{p}");
            assert!((frame.normal_in + expected.normal).norm() < 1e-12, "{p}");
            assert!((frame.gap - (expected.signed_distance - 0.015)).abs() < 1e-12);
        }
        // Inside near the concave corner the inward normal points away from it, into the T.
        let frame = geometry.frame(local(12.0, 27.0), Vector2::zeros());
        let away = (local(12.0, 27.0) - local(15.0, 30.0)).normalize();
        assert!((frame.normal_in - away).norm() < 1e-12);
        // On the bisector the lower-numbered face, the bar's inner edge (edge 2, y = 30 px), wins.
        let tie = outline.closest_boundary_point(local(35.0, 50.0));
        assert_eq!(tie.edge, 2);
    }

    #[test]
    fn the_tangent_points_away_from_the_centre_and_mirrors() {
        let outline = Outline::rectangle(0.3, 0.4).expect("valid box");
        let geometry = ContactGeometry::new(&outline, 0.05);
        // Front face at x = −0.15, contact above the centre: the tangent points to +y.
        let up = geometry.frame(Point2::new(-0.25, 0.08), Vector2::new(0.01, 0.0));
        assert!((up.tangent - Vector2::y()).norm() < 1e-15);
        assert!((up.normal_in - Vector2::x()).norm() < 1e-15);
        let down = geometry.frame(Point2::new(-0.25, -0.08), Vector2::new(0.01, 0.0));
        assert!((down.tangent + Vector2::y()).norm() < 1e-15);
        // Through the middle, the motion decides.
        let middle = geometry.frame(Point2::new(-0.25, 0.0), Vector2::new(0.01, -0.002));
        assert!((middle.tangent + Vector2::y()).norm() < 1e-15);
        assert!((middle.gap - 0.05).abs() < 1e-15);
    }
}
