//! Planar geometry: poses, frame changes and convex object outlines.
//!
//! Names carry their frames: a `Pose2` is `world_from_object`, so `pose.point_in_world(p_in_object)`
//! maps a point given in the object frame to the world, and `pose.point_in_object(p_in_world)` back.
//! Angles in trajectories are kept unwrapped; differences of angles are wrapped to (−π, π].

use std::f64::consts::PI;

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

/// Pose of a planar body in the world (`world_from_object`): its position and its yaw.
///
/// The yaw is kept as a plain (possibly unwrapped) angle rather than a unit complex number so that a
/// trajectory can carry the total rotation of an object that turned more than half a turn.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose2 {
    /// Position of the object frame's origin in the world, metres.
    pub position: Point2<f64>,
    /// Yaw of the object's x axis in the world, radians. (Not `theta`: in this crate `θ` is always
    /// `θ_online`, the parameters learned online.)
    #[serde(alias = "theta")]
    pub yaw: f64,
}

impl Pose2 {
    /// A pose from its coordinates.
    pub fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self {
            position: Point2::new(x, y),
            yaw,
        }
    }

    /// The same transform as an `Isometry2`, for callers that compose transforms.
    pub fn world_from_object(&self) -> Isometry2<f64> {
        Isometry2::new(self.position.coords, self.yaw)
    }

    /// A point given in the object frame, expressed in the world.
    pub fn point_in_world(&self, point_in_object: Point2<f64>) -> Point2<f64> {
        self.position + rotate(point_in_object.coords, self.yaw)
    }

    /// A point given in the world, expressed in the object frame.
    pub fn point_in_object(&self, point_in_world: Point2<f64>) -> Point2<f64> {
        Point2::from(rotate(point_in_world - self.position, -self.yaw))
    }

    /// A free vector (a motion) given in the object frame, expressed in the world.
    pub fn vector_in_world(&self, vector_in_object: Vector2<f64>) -> Vector2<f64> {
        rotate(vector_in_object, self.yaw)
    }

    /// A free vector given in the world, expressed in the object frame.
    pub fn vector_in_object(&self, vector_in_world: Vector2<f64>) -> Vector2<f64> {
        rotate(vector_in_world, -self.yaw)
    }

    /// The pose reached by moving by `delta_in_object` (expressed in this pose's frame) and turning by
    /// `delta_yaw`: the inverse of [`Pose2::motion_to`].
    pub fn moved_by(&self, delta_in_object: Vector2<f64>, delta_yaw: f64) -> Pose2 {
        Pose2 {
            position: self.position + self.vector_in_world(delta_in_object),
            yaw: self.yaw + delta_yaw,
        }
    }

    /// The motion from this pose to `later`, expressed in this pose's frame (eqs. 3–4 of the paper):
    /// the translation in the object frame and the rotation wrapped to (−π, π].
    pub fn motion_to(&self, later: &Pose2) -> (Vector2<f64>, f64) {
        (
            self.vector_in_object(later.position - self.position),
            wrap_angle(later.yaw - self.yaw),
        )
    }
}

/// Rotates a vector by `angle` radians counter-clockwise.
pub fn rotate(v: Vector2<f64>, angle: f64) -> Vector2<f64> {
    let (s, c) = angle.sin_cos();
    Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Wraps an angle to (−π, π].
pub fn wrap_angle(angle: f64) -> f64 {
    let mut a = (angle + PI).rem_euclid(2.0 * PI) - PI;
    if a <= -PI {
        a += 2.0 * PI;
    }
    a
}

/// Unwraps a sequence of angles in place so that consecutive values never differ by more than π.
///
/// Returns how many wraps were removed, so that importers can report them.
pub fn unwrap_angles(angles: &mut [f64]) -> usize {
    let mut wraps = 0;
    let mut offset = 0.0;
    for i in 1..angles.len() {
        let raw_prev = angles[i - 1] - offset;
        let step = angles[i] - raw_prev;
        if step > PI {
            offset -= 2.0 * PI * ((step + PI) / (2.0 * PI)).floor();
            wraps += 1;
        } else if step < -PI {
            offset += 2.0 * PI * ((-step + PI) / (2.0 * PI)).floor();
            wraps += 1;
        }
        angles[i] += offset;
    }
    wraps
}

/// Why a list of vertices is not a usable object outline.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OutlineError {
    #[error("an outline needs at least 3 vertices, got {0}")]
    TooFewVertices(usize),
    #[error("vertex {index} is not finite")]
    NonFinite { index: usize },
    #[error("the outline is not convex and counter-clockwise at vertex {index}")]
    NotConvexCcw { index: usize },
    #[error("the outline has no area")]
    Degenerate,
    #[error("the outline's vertices go clockwise; list them counter-clockwise (in reverse order)")]
    Clockwise,
    #[error("a box needs a positive finite width and length, got {width} x {length}")]
    BadBox { width: f64, length: f64 },
}

/// A convex outline of an object's footprint in the object frame, counter-clockwise.
///
/// Convexity is checked once on construction so that every query (closest point, contact, pressure
/// integrals) can rely on it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<[f64; 2]>", into = "Vec<[f64; 2]>")]
pub struct Outline {
    vertices: Vec<Point2<f64>>,
}

/// Where a point lies with respect to an outline: the closest point on its boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryPoint {
    /// Closest point on the boundary, object frame.
    pub point: Point2<f64>,
    /// Outward unit normal of the boundary there (at a corner: the direction from the corner to the
    /// query point, or the bisector when the query point is the corner).
    pub normal: Vector2<f64>,
    /// Signed distance of the query point: positive outside, negative inside.
    pub signed_distance: f64,
    /// Index of the edge (from vertex `edge` to vertex `edge + 1`) the point lies on.
    pub edge: usize,
}

impl Outline {
    /// An outline from counter-clockwise vertices in the object frame; checks convexity.
    pub fn new(vertices: Vec<Point2<f64>>) -> Result<Self, OutlineError> {
        let n = vertices.len();
        if n < 3 {
            return Err(OutlineError::TooFewVertices(n));
        }
        if let Some(index) = vertices
            .iter()
            .position(|v| !(v.x.is_finite() && v.y.is_finite()))
        {
            return Err(OutlineError::NonFinite { index });
        }
        let outline = Self { vertices };
        let area = outline.area();
        if area < -1e-12 {
            return Err(OutlineError::Clockwise);
        }
        if area <= 1e-12 {
            return Err(OutlineError::Degenerate);
        }
        for i in 0..n {
            let a = outline.vertices[i];
            let b = outline.vertices[(i + 1) % n];
            let c = outline.vertices[(i + 2) % n];
            if cross(b - a, c - b) < -1e-12 {
                return Err(OutlineError::NotConvexCcw { index: (i + 1) % n });
            }
        }
        Ok(outline)
    }

    /// A box centred on the origin: `width` along the object's x axis, `length` along its y axis.
    pub fn rectangle(width: f64, length: f64) -> Result<Self, OutlineError> {
        if !(width.is_finite() && length.is_finite() && width > 0.0 && length > 0.0) {
            return Err(OutlineError::BadBox { width, length });
        }
        let (a, b) = (width / 2.0, length / 2.0);
        Self::new(vec![
            Point2::new(a, b),
            Point2::new(-a, b),
            Point2::new(-a, -b),
            Point2::new(a, -b),
        ])
    }

    /// A polygon with `segments` vertices approximating an ellipse with the given semi-axes, centred on
    /// `centre`. Used for round objects (the MIT dataset's ellipses).
    pub fn ellipse(
        centre: Point2<f64>,
        semi_x: f64,
        semi_y: f64,
        segments: usize,
    ) -> Result<Self, OutlineError> {
        let vertices = (0..segments)
            .map(|i| {
                let a = 2.0 * PI * i as f64 / segments as f64;
                Point2::new(centre.x + semi_x * a.cos(), centre.y + semi_y * a.sin())
            })
            .collect();
        Self::new(vertices)
    }

    /// The vertices, counter-clockwise, object frame.
    pub fn vertices(&self) -> &[Point2<f64>] {
        &self.vertices
    }

    /// Iterates the edges as (start, end) pairs, counter-clockwise.
    pub fn edges(&self) -> impl Iterator<Item = (Point2<f64>, Point2<f64>)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }

    /// Signed area (positive for counter-clockwise), m².
    pub fn area(&self) -> f64 {
        self.edges()
            .map(|(a, b)| cross(a.coords, b.coords))
            .sum::<f64>()
            / 2.0
    }

    /// Area centroid of the footprint, object frame.
    pub fn centroid(&self) -> Point2<f64> {
        let area = self.area();
        let mut c = Vector2::zeros();
        for (a, b) in self.edges() {
            c += (a.coords + b.coords) * cross(a.coords, b.coords);
        }
        Point2::from(c / (6.0 * area))
    }

    /// Whether a point lies inside the outline or on its boundary.
    pub fn contains(&self, p: Point2<f64>) -> bool {
        self.edges().all(|(a, b)| cross(b - a, p - a) >= -1e-12)
    }

    /// The closest boundary point to `p` with the outward normal there and the signed distance.
    pub fn closest_boundary_point(&self, p: Point2<f64>) -> BoundaryPoint {
        let inside = self.contains(p);
        let mut best: Option<BoundaryPoint> = None;
        for (edge, (a, b)) in self.edges().enumerate() {
            let ab = b - a;
            let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            let q = a + ab * t;
            let distance = (p - q).norm();
            if best.is_none_or(|b| distance < b.signed_distance.abs()) {
                let edge_normal = Vector2::new(ab.y, -ab.x).normalize();
                let on_edge_interior = t > 0.0 && t < 1.0;
                let normal = if on_edge_interior || inside || distance < 1e-12 {
                    edge_normal
                } else {
                    (p - q) / distance
                };
                best = Some(BoundaryPoint {
                    point: q,
                    normal,
                    signed_distance: if inside { -distance } else { distance },
                    edge,
                });
            }
        }
        // An outline has at least three edges, so `best` is always set.
        best.unwrap_or(BoundaryPoint {
            point: p,
            normal: Vector2::x(),
            signed_distance: 0.0,
            edge: 0,
        })
    }

    /// Where the centre of a disc pusher of radius `radius` sits when it touches the outline at the
    /// boundary point nearest to `pusher_centre`: the contact point and its outward normal. Returns
    /// `None` when the disc is farther than `tolerance` from the outline.
    pub fn disc_contact(
        &self,
        pusher_centre: Point2<f64>,
        radius: f64,
        tolerance: f64,
    ) -> Option<BoundaryPoint> {
        let closest = self.closest_boundary_point(pusher_centre);
        (closest.signed_distance - radius <= tolerance).then_some(closest)
    }

    /// Lynch's `h` for a uniform pressure over the footprint about `com`: the mean distance of the
    /// footprint's points from the COM, `h = (1/A)∫|r − com| dA`, which is the ratio of the maximal
    /// friction torque to the maximal friction force (Lynch & Mason's `c`).
    ///
    /// Integrated with a midpoint rule over a `resolution × resolution` grid of the bounding box;
    /// 400 gives about four significant digits for a box.
    ///
    /// Which grid points are inside is decided column by column, one edge at a time for the whole
    /// column, with the products of [`Outline::contains`]: a loop the compiler vectorises (four
    /// points at a time in the AVX2 copy), where testing point by point (stopping at the first edge a
    /// point fails) was 13 % of `pushlab train` on the MIT files, whose ellipses have 64 edges.
    pub fn uniform_pressure_h(&self, com: Point2<f64>, resolution: usize) -> f64 {
        self.uniform_pressure_h_dispatch(com, resolution)
    }

    crate::simd::dispatch_simd! {
        /// [`Outline::uniform_pressure_h`] in the AVX2 copy when the CPU has it (the same bits).
        fn uniform_pressure_h_dispatch(&self, com: Point2<f64>, resolution: usize) -> f64
            => unfused uniform_pressure_h_portable, uniform_pressure_h_avx2
    }

    #[inline(always)]
    fn uniform_pressure_h_portable(&self, com: Point2<f64>, resolution: usize) -> f64 {
        let (min, max) = self.bounding_box();
        let (dx, dy) = (
            (max.x - min.x) / resolution as f64,
            (max.y - min.y) / resolution as f64,
        );
        let ys: Vec<f64> = (0..resolution)
            .map(|j| min.y + (j as f64 + 0.5) * dy)
            .collect();
        let edges: Vec<(Point2<f64>, Vector2<f64>)> =
            self.edges().map(|(a, b)| (a, b - a)).collect();
        let mut inside = vec![true; resolution];
        let (mut sum, mut count) = (0.0, 0usize);
        for i in 0..resolution {
            let x = min.x + (i as f64 + 0.5) * dx;
            inside.fill(true);
            for (a, ab) in &edges {
                // `cross(ab, p − a) ≥ −1e-12`, as in `contains`.
                let x_from_a = x - a.x;
                for (flag, &y) in inside.iter_mut().zip(&ys) {
                    *flag &= ab.x * (y - a.y) - ab.y * x_from_a >= -1e-12;
                }
            }
            for (&flag, &y) in inside.iter().zip(&ys) {
                if flag {
                    sum += (Point2::new(x, y) - com).norm();
                    count += 1;
                }
            }
        }
        if count == 0 { 0.0 } else { sum / count as f64 }
    }

    /// Lower-left and upper-right corners of the axis-aligned bounding box, object frame.
    pub fn bounding_box(&self) -> (Point2<f64>, Point2<f64>) {
        let mut min = self.vertices[0];
        let mut max = self.vertices[0];
        for v in &self.vertices {
            min = Point2::new(min.x.min(v.x), min.y.min(v.y));
            max = Point2::new(max.x.max(v.x), max.y.max(v.y));
        }
        (min, max)
    }

    /// A size scale of the object: the largest extent of its bounding box.
    pub fn size(&self) -> f64 {
        let (min, max) = self.bounding_box();
        (max.x - min.x).max(max.y - min.y)
    }
}

impl TryFrom<Vec<[f64; 2]>> for Outline {
    type Error = OutlineError;
    fn try_from(vertices: Vec<[f64; 2]>) -> Result<Self, Self::Error> {
        Self::new(vertices.into_iter().map(Point2::from).collect())
    }
}

impl From<Outline> for Vec<[f64; 2]> {
    fn from(outline: Outline) -> Self {
        outline.vertices.iter().map(|v| [v.x, v.y]).collect()
    }
}

/// The z component of the cross product of two planar vectors.
pub fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn frame_changes_round_trip() {
        let pose = Pose2::new(0.3, -1.2, 2.5);
        let p = Point2::new(0.05, 0.07);
        let back = pose.point_in_object(pose.point_in_world(p));
        assert!((back - p).norm() < 1e-15);
        let v = Vector2::new(-0.2, 0.4);
        assert!((pose.vector_in_object(pose.vector_in_world(v)) - v).norm() < 1e-15);
        // Same as nalgebra's isometry.
        let iso = pose.world_from_object();
        assert!((iso * p - pose.point_in_world(p)).norm() < 1e-15);
    }

    #[test]
    fn point_in_world_rotates_then_translates() {
        let pose = Pose2::new(1.0, 2.0, PI / 2.0);
        let p = pose.point_in_world(Point2::new(1.0, 0.0));
        assert!(close(p.x, 1.0, 1e-12) && close(p.y, 3.0, 1e-12));
    }

    #[test]
    fn motion_to_and_moved_by_are_inverse() {
        let a = Pose2::new(0.1, 0.2, 3.0);
        let b = Pose2::new(0.15, 0.18, 3.5);
        let (d, dyaw) = a.motion_to(&b);
        let c = a.moved_by(d, dyaw);
        assert!((c.position - b.position).norm() < 1e-15);
        assert!(close(c.yaw, b.yaw, 1e-12));
    }

    #[test]
    fn wrap_angle_maps_into_half_open_interval() {
        assert!(close(wrap_angle(PI), PI, 1e-15));
        assert!(close(wrap_angle(-PI), PI, 1e-15));
        assert!(close(wrap_angle(3.0 * PI / 2.0), -PI / 2.0, 1e-12));
        assert!(close(wrap_angle(-7.0), -7.0 + 2.0 * PI, 1e-12));
    }

    #[test]
    fn unwrap_removes_jumps_and_counts_them() {
        let mut a = vec![3.0, -3.1, -2.9, 3.1, 0.0];
        let wraps = unwrap_angles(&mut a);
        assert_eq!(wraps, 2);
        for w in a.windows(2).take(3) {
            assert!((w[1] - w[0]).abs() < PI);
        }
        assert!(close(a[1], -3.1 + 2.0 * PI, 1e-12));
    }

    #[test]
    fn rectangle_area_centroid_and_closest_point() {
        let r = Outline::rectangle(0.2, 0.1).expect("valid box");
        assert!(close(r.area(), 0.02, 1e-15));
        assert!(r.centroid().coords.norm() < 1e-15);
        let q = r.closest_boundary_point(Point2::new(-0.15, 0.01));
        assert!(close(q.point.x, -0.1, 1e-15) && close(q.point.y, 0.01, 1e-15));
        assert!(close(q.normal.x, -1.0, 1e-15));
        assert!(close(q.signed_distance, 0.05, 1e-15));
        let inside = r.closest_boundary_point(Point2::new(0.09, 0.0));
        assert!(close(inside.signed_distance, -0.01, 1e-15));
        assert!(close(inside.normal.x, 1.0, 1e-15));
    }

    #[test]
    fn clockwise_or_concave_outlines_are_refused() {
        let cw = vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        let error = Outline::try_from(cw).expect_err("clockwise");
        assert_eq!(error, OutlineError::Clockwise);
        assert!(
            error
                .to_string()
                .contains("counter-clockwise (in reverse order)")
        );
        let flat = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        assert_eq!(Outline::try_from(flat), Err(OutlineError::Degenerate));
        let concave = vec![[0.0, 0.0], [1.0, 0.0], [0.2, 0.2], [0.0, 1.0]];
        assert!(matches!(
            Outline::try_from(concave),
            Err(OutlineError::NotConvexCcw { .. })
        ));
        assert_eq!(
            Outline::try_from(vec![[0.0, 0.0], [1.0, 0.0]]),
            Err(OutlineError::TooFewVertices(2))
        );
    }

    #[test]
    fn uniform_pressure_h_is_the_point_by_point_midpoint_rule_bit_for_bit() {
        let outlines = [
            Outline::rectangle(0.3, 0.4).expect("valid box"),
            Outline::ellipse(Point2::new(0.01, -0.02), 0.06, 0.09, 64).expect("valid ellipse"),
            Outline::try_from(vec![[0.1, -0.05], [0.02, 0.08], [-0.09, -0.01]]).expect("triangle"),
        ];
        for outline in outlines {
            for (com, resolution) in [(outline.centroid(), 200), (Point2::new(0.01, 0.02), 37)] {
                let (min, max) = outline.bounding_box();
                let (dx, dy) = (
                    (max.x - min.x) / resolution as f64,
                    (max.y - min.y) / resolution as f64,
                );
                let (mut sum, mut count) = (0.0, 0usize);
                for i in 0..resolution {
                    for j in 0..resolution {
                        let p = Point2::new(
                            min.x + (i as f64 + 0.5) * dx,
                            min.y + (j as f64 + 0.5) * dy,
                        );
                        if outline.contains(p) {
                            sum += (p - com).norm();
                            count += 1;
                        }
                    }
                }
                let expected = sum / count as f64;
                assert_eq!(outline.uniform_pressure_h(com, resolution), expected);
            }
        }
    }

    #[test]
    fn uniform_pressure_h_of_a_disc_is_two_thirds_of_its_radius() {
        // Closed form: (1/(πR²))∫∫ r dA = 2R/3.
        let disc = Outline::ellipse(Point2::origin(), 0.1, 0.1, 256).expect("valid disc");
        let h = disc.uniform_pressure_h(Point2::origin(), 400);
        assert!(close(h, 0.2 / 3.0, 2e-4), "h = {h}");
    }
}
