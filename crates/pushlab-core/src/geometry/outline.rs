//! An object's footprint: a simple polygon, counter-clockwise, convex or not.

use crate::math;
use std::f64::consts::PI;

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

use super::polygon::{
    NotSimple, check_simple, contains_simple, cross, disc_sweep_hits_segment, signed_area,
    triangulate, turns_left_everywhere,
};

/// Why a list of vertices is not a usable object outline. Edge `i` runs from vertex `i` to vertex
/// `i + 1` (the last edge back to vertex 0), vertices counted from 0.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OutlineError {
    #[error("an outline needs at least 3 vertices, got {0}")]
    TooFewVertices(usize),
    #[error("vertex {index} is not finite")]
    NonFinite { index: usize },
    #[error("edge {edge} has no length: vertex {edge} repeats the next; remove one of them")]
    ZeroLengthEdge { edge: usize },
    #[error(
        "the outline turns straight back at vertex {vertex} (a spike of no width); remove vertex \
         {vertex}"
    )]
    Spike { vertex: usize },
    #[error(
        "edges {first} and {second} touch or cross; an outline must go round once without meeting \
         itself"
    )]
    SelfIntersecting { first: usize, second: usize },
    #[error("the outline has no area")]
    Degenerate,
    #[error("the outline's vertices go clockwise; list them counter-clockwise (in reverse order)")]
    Clockwise,
    #[error("a box needs a positive finite width and length, got {width} x {length} m")]
    BadBox { width: f64, length: f64 },
    #[error("unknown preset '{name}', expected one of: {}", known.join(", "))]
    UnknownPreset {
        name: String,
        known: &'static [&'static str],
    },
    #[error("a preset's scale must be a positive finite number of metres per unit, got {0}")]
    BadScale(f64),
}

/// An object's footprint in the object frame: a simple polygon (it goes round once and never meets
/// itself), counter-clockwise, convex or not.
///
/// Checked once on construction, so that every query (closest point, contact, pressure integrals) can
/// rely on it. Whether it is convex is kept: convex outlines take the fast half-plane tests (and the
/// results they always gave), others the general ones.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "Vec<[f64; 2]>", into = "Vec<[f64; 2]>")]
pub struct Outline {
    vertices: Vec<Point2<f64>>,
    convex: bool,
    /// Counter-clockwise triangles of vertex indices that tile the footprint (for drawing).
    triangles: Vec<[usize; 3]>,
}

/// Where a point lies with respect to an outline: the closest point on its boundary.
///
/// When two edges are equally near (a point on the bisector of a notch, outside a concave corner),
/// the lower-numbered edge is the one reported: the point and normal jump from one face to the other
/// as the query point crosses the bisector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundaryPoint {
    /// Closest point on the boundary, object frame.
    pub point: Point2<f64>,
    /// Outward unit normal of the boundary there. On an edge's interior, the edge's normal; at a
    /// vertex, the direction from the vertex to the query point when it is outside (a convex
    /// corner), from the query point to the vertex when it is inside (a concave corner seen from
    /// within); the edge's normal when the query point is the vertex.
    pub normal: Vector2<f64>,
    /// Signed distance of the query point: positive outside, negative inside.
    pub signed_distance: f64,
    /// Index of the edge (from vertex `edge` to vertex `edge + 1`) the point lies on.
    pub edge: usize,
}

impl Outline {
    /// An outline from counter-clockwise vertices in the object frame; checks that they form a simple
    /// polygon and names the first edge, vertex or pair of edges at fault.
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
        check_simple(&vertices).map_err(|problem| match problem {
            NotSimple::ZeroLengthEdge { edge } => OutlineError::ZeroLengthEdge { edge },
            NotSimple::Spike { vertex } => OutlineError::Spike { vertex },
            NotSimple::EdgesCross { first, second } => {
                OutlineError::SelfIntersecting { first, second }
            }
        })?;
        let area = signed_area(&vertices);
        if area < -1e-12 {
            return Err(OutlineError::Clockwise);
        }
        if area <= 1e-12 {
            return Err(OutlineError::Degenerate);
        }
        let convex = turns_left_everywhere(&vertices);
        let triangles = triangulate(&vertices, convex);
        Ok(Self {
            vertices,
            convex,
            triangles,
        })
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
                Point2::new(
                    centre.x + semi_x * math::cos(a),
                    centre.y + semi_y * math::sin(a),
                )
            })
            .collect();
        Self::new(vertices)
    }

    /// The vertices, counter-clockwise, object frame.
    pub fn vertices(&self) -> &[Point2<f64>] {
        &self.vertices
    }

    /// Whether the outline is convex (it turns left or goes straight at every vertex).
    pub fn is_convex(&self) -> bool {
        self.convex
    }

    /// Triangles of vertex indices, counter-clockwise, that tile the footprint without overlap: a fan
    /// for a convex outline, ear clipping otherwise. For filling a non-convex footprint, which a
    /// convex-polygon fill would paint across its notches.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }

    /// Iterates the edges as (start, end) pairs, counter-clockwise.
    pub fn edges(&self) -> impl Iterator<Item = (Point2<f64>, Point2<f64>)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }

    /// Signed area (positive for counter-clockwise), m².
    pub fn area(&self) -> f64 {
        signed_area(&self.vertices)
    }

    /// Area centroid of the footprint (its geometric centre), object frame: the shoelace formula,
    /// exact for any simple polygon. It may lie outside a non-convex footprint (a thin C).
    pub fn centroid(&self) -> Point2<f64> {
        let area = self.area();
        let mut c = Vector2::zeros();
        for (a, b) in self.edges() {
            c += (a.coords + b.coords) * cross(a.coords, b.coords);
        }
        Point2::from(c / (6.0 * area))
    }

    /// Whether a point lies inside the outline or on its boundary: the half-planes of the edges for a
    /// convex outline, the crossing rule otherwise.
    pub fn contains(&self, p: Point2<f64>) -> bool {
        if self.convex {
            self.edges().all(|(a, b)| cross(b - a, p - a) >= -1e-12)
        } else {
            contains_simple(&self.vertices, p)
        }
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
                // Inside a convex outline the nearest point is never a vertex (but at the vertex
                // itself); inside a concave corner it is, and the outward direction is toward it.
                let normal = if on_edge_interior || distance < 1e-12 || (inside && self.convex) {
                    edge_normal
                } else if inside {
                    (q - p) / distance
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
    ///
    /// One contact, the nearest: a disc in a concave corner that touches two faces at once gets the
    /// deeper one (the lower-numbered edge when both are equally near, see [`BoundaryPoint`]).
    pub fn disc_contact(
        &self,
        pusher_centre: Point2<f64>,
        radius: f64,
        tolerance: f64,
    ) -> Option<BoundaryPoint> {
        let closest = self.closest_boundary_point(pusher_centre);
        (closest.signed_distance - radius <= tolerance).then_some(closest)
    }

    /// The earliest fraction `t ∈ [0, 1]` of the motion `start → start + motion` at which a disc of
    /// `radius` centred on the moving point first comes within `radius` of the outline (0 when it
    /// already is), if it does: exact for any outline (the first hit of the motion on the edges'
    /// capsules), where searching the gap along the motion assumes it has one minimum (a convex
    /// outline).
    pub fn disc_first_touch(
        &self,
        start: Point2<f64>,
        motion: Vector2<f64>,
        radius: f64,
    ) -> Option<f64> {
        self.edges()
            .filter_map(|(a, b)| disc_sweep_hits_segment(start, motion, radius, a, b))
            .min_by(f64::total_cmp)
    }

    /// Lynch's `h` for a uniform pressure over the footprint about `com`: the mean distance of the
    /// footprint's points from the COM, `h = (1/A)∫|r − com| dA`, which is the ratio of the maximal
    /// friction torque to the maximal friction force (Lynch & Mason's `c`).
    ///
    /// Integrated with a midpoint rule over a `resolution × resolution` grid of the bounding box;
    /// 400 gives about four significant digits for a box. Only the grid points the outline
    /// [`contains`](Outline::contains) count, so a non-convex footprint's notches are left out.
    ///
    /// For a convex outline, which grid points are inside is decided column by column, one edge at a
    /// time for the whole column, with the products of [`Outline::contains`]: a loop the compiler
    /// vectorises (four points at a time in the AVX2 copy), where testing point by point (stopping at
    /// the first edge a point fails) was 13 % of `pushlab train` on the MIT files, whose ellipses have
    /// 64 edges. A non-convex outline is tested point by point with the crossing rule.
    pub fn uniform_pressure_h(&self, com: Point2<f64>, resolution: usize) -> f64 {
        if self.convex {
            self.uniform_pressure_h_dispatch(com, resolution)
        } else {
            self.uniform_pressure_h_point_by_point(com, resolution)
        }
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

    fn uniform_pressure_h_point_by_point(&self, com: Point2<f64>, resolution: usize) -> f64 {
        let (min, max) = self.bounding_box();
        let (dx, dy) = (
            (max.x - min.x) / resolution as f64,
            (max.y - min.y) / resolution as f64,
        );
        let (mut sum, mut count) = (0.0, 0usize);
        for i in 0..resolution {
            let x = min.x + (i as f64 + 0.5) * dx;
            for j in 0..resolution {
                let p = Point2::new(x, min.y + (j as f64 + 0.5) * dy);
                if contains_simple(&self.vertices, p) {
                    sum += (p - com).norm();
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

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
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
    fn clockwise_degenerate_or_self_crossing_outlines_are_refused_naming_the_fault() {
        let refusal = |vertices: Vec<[f64; 2]>| {
            Outline::try_from(vertices)
                .expect_err("refused")
                .to_string()
        };
        let cw = vec![[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]];
        assert_eq!(Outline::try_from(cw.clone()), Err(OutlineError::Clockwise));
        assert!(refusal(cw).contains("counter-clockwise (in reverse order)"));
        // All on one line: the outline turns straight back at its first vertex.
        let flat = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        assert_eq!(
            refusal(flat),
            "the outline turns straight back at vertex 0 (a spike of no width); remove vertex 0"
        );
        let repeated = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(
            refusal(repeated),
            "edge 1 has no length: vertex 1 repeats the next; remove one of them"
        );
        let bow_tie = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        assert_eq!(
            refusal(bow_tie),
            "edges 0 and 2 touch or cross; an outline must go round once without meeting itself"
        );
        assert_eq!(
            Outline::try_from(vec![[0.0, 0.0], [1.0, 0.0]]),
            Err(OutlineError::TooFewVertices(2))
        );
        // A concave quadrilateral (a dart) is a simple outline now.
        let dart = Outline::try_from(vec![[0.0, 0.0], [1.0, 0.0], [0.2, 0.2], [0.0, 1.0]])
            .expect("a simple non-convex outline");
        assert!(!dart.is_convex());
        assert!(Outline::rectangle(0.2, 0.1).expect("valid").is_convex());
    }

    /// An L of two unit squares: (0,0)–(2,1) and (0,1)–(1,2), the reflex corner at (1, 1).
    fn l_shape() -> Outline {
        Outline::try_from(vec![
            [0.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
        ])
        .expect("an L is simple")
    }

    #[test]
    fn an_l_has_the_area_centroid_and_inside_of_its_two_squares() {
        let l = l_shape();
        assert!(close(l.area(), 3.0, 1e-15));
        // Centroid: the area-weighted mean of the squares' centres (1, 0.5) ×2 and (0.5, 1.5) ×1.
        let c = l.centroid();
        assert!(close(c.x, 2.5 / 3.0, 1e-15) && close(c.y, 2.5 / 3.0, 1e-15));
        assert!(l.contains(Point2::new(1.9, 0.9)) && l.contains(Point2::new(0.1, 1.9)));
        assert!(!l.contains(Point2::new(1.5, 1.5)), "the notch");
        assert!(
            l.contains(Point2::new(1.0, 1.0)),
            "the reflex corner itself"
        );
    }

    #[test]
    fn closest_points_at_a_concave_corner() {
        let l = l_shape();
        // Inside, nearest to the reflex corner: the normal points from the point to the corner.
        let q = l.closest_boundary_point(Point2::new(0.9, 0.9));
        assert!((q.point - Point2::new(1.0, 1.0)).norm() < 1e-15);
        assert!(close(q.signed_distance, -0.1 * 2f64.sqrt(), 1e-15));
        let diagonal = Vector2::new(1.0, 1.0).normalize();
        assert!((q.normal - diagonal).norm() < 1e-15, "{}", q.normal);
        // Outside in the notch, whose faces are edge 2 (y = 1, normal +y) and edge 3 (x = 1, normal
        // +x): the nearer face.
        let q = l.closest_boundary_point(Point2::new(1.1, 1.5));
        assert_eq!(q.edge, 3);
        assert!((q.point - Point2::new(1.0, 1.5)).norm() < 1e-15);
        assert!((q.normal - Vector2::x()).norm() < 1e-15);
        assert!(close(q.signed_distance, 0.1, 1e-15));
        let q = l.closest_boundary_point(Point2::new(1.5, 1.1));
        assert_eq!(q.edge, 2);
        assert!((q.normal - Vector2::y()).norm() < 1e-15);
        // On the notch's bisector both faces are equally near: the lower-numbered edge is reported.
        let q = l.closest_boundary_point(Point2::new(1.3, 1.3));
        assert_eq!(q.edge, 2);
        assert!((q.point - Point2::new(1.3, 1.0)).norm() < 1e-15);
        // A disc of radius 0.35 centred there touches both faces: one contact, the same face.
        let contact = l
            .disc_contact(Point2::new(1.3, 1.3), 0.35, 1e-9)
            .expect("touching");
        assert_eq!(contact.edge, 2);
    }

    #[test]
    fn a_moving_disc_first_touches_the_nearest_face_in_its_way() {
        let l = l_shape();
        // Down the notch toward the inner face y = 1: the centre stops at y = 1.2.
        let t = l
            .disc_first_touch(Point2::new(1.5, 3.0), Vector2::new(0.0, -3.0), 0.2)
            .expect("hits");
        assert!(close(t, 1.8 / 3.0, 1e-15), "{t}");
        // A disc too wide for the notch (radius 0.8 on x = 1.5) is stopped by the upper arm's
        // corner (1, 2), with its centre at y = 2 + √(0.8² − 0.5²).
        let t = l
            .disc_first_touch(Point2::new(1.5, 4.0), Vector2::new(0.0, -4.0), 0.8)
            .expect("hits");
        assert!(close(4.0 - 4.0 * t, 2.0 + 0.39f64.sqrt(), 1e-12), "{t}");
        assert_eq!(
            l.disc_first_touch(Point2::new(3.0, 3.0), Vector2::new(1.0, 0.0), 0.2),
            None
        );
    }

    #[test]
    fn triangles_tile_a_non_convex_outline() {
        let l = l_shape();
        let area: f64 = l
            .triangles()
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| l.vertices()[i]);
                cross(b - a, c - a) / 2.0
            })
            .sum();
        assert!(close(area, 3.0, 1e-15));
        assert_eq!(
            Outline::rectangle(1.0, 2.0)
                .expect("valid")
                .triangles()
                .len(),
            2
        );
    }

    #[test]
    fn uniform_pressure_h_is_the_point_by_point_midpoint_rule_bit_for_bit() {
        let outlines = [
            Outline::rectangle(0.3, 0.4).expect("valid box"),
            Outline::ellipse(Point2::new(0.01, -0.02), 0.06, 0.09, 64).expect("valid ellipse"),
            Outline::try_from(vec![[0.1, -0.05], [0.02, 0.08], [-0.09, -0.01]]).expect("triangle"),
            l_shape(),
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
