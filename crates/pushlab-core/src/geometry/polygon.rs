//! The maths of simple polygons on plain vertex lists, below [`super::Outline`]: whether a vertex list
//! is a simple polygon (and if not, the first edge, vertex or pair of edges at fault), the inside test,
//! the first touch of a moving disc, and an ear-clipping triangulation.
//!
//! Edge `i` runs from vertex `i` to vertex `i + 1` (the last edge back to vertex 0), as everywhere in
//! pushlab's messages.

use crate::math;
use nalgebra::{Point2, Vector2};

/// The z component of the cross product of two planar vectors.
pub fn cross(a: Vector2<f64>, b: Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Signed area of a closed polygon (positive for counter-clockwise vertices).
pub(super) fn signed_area(vertices: &[Point2<f64>]) -> f64 {
    edges(vertices)
        .map(|(a, b)| cross(a.coords, b.coords))
        .sum::<f64>()
        / 2.0
}

fn edges(vertices: &[Point2<f64>]) -> impl Iterator<Item = (Point2<f64>, Point2<f64>)> + '_ {
    let n = vertices.len();
    (0..n).map(move |i| (vertices[i], vertices[(i + 1) % n]))
}

/// Why a closed vertex list is not a simple polygon: the first problem found, in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum NotSimple {
    /// Edge `edge` has no length (vertex `edge` repeats the next).
    ZeroLengthEdge { edge: usize },
    /// The outline turns straight back at `vertex`: the edges before and after it overlap.
    Spike { vertex: usize },
    /// Edges `first < second`, not neighbours, touch or cross.
    EdgesCross { first: usize, second: usize },
}

/// Whether the closed polygon through `vertices` (at least 3, finite) turns left or goes straight at
/// every vertex. For a polygon that goes round once (positive area, no spikes) this is convexity.
pub(super) fn turns_left_everywhere(vertices: &[Point2<f64>]) -> bool {
    let n = vertices.len();
    (0..n).all(|i| {
        let (a, b, c) = (vertices[i], vertices[(i + 1) % n], vertices[(i + 2) % n]);
        cross(b - a, c - b) >= -1e-12
    })
}

/// The total turning of the polygon's edges, in turns (1 for a convex polygon that goes round once
/// counter-clockwise, 2 for a pentagram).
fn winding_of_turns(vertices: &[Point2<f64>]) -> f64 {
    let n = vertices.len();
    let total: f64 = (0..n)
        .map(|i| {
            let (a, b, c) = (vertices[i], vertices[(i + 1) % n], vertices[(i + 2) % n]);
            let (u, v) = (b - a, c - b);
            math::atan2(cross(u, v), u.dot(&v))
        })
        .sum();
    total / std::f64::consts::TAU
}

/// Checks that `vertices` (at least 3, finite) form a simple polygon: no zero-length edge, no spike,
/// no two edges that touch or cross other than neighbours at their shared vertex.
///
/// A polygon that turns left everywhere and goes round once is convex and simple, which is checked in
/// linear time; any other costs a test of every pair of edges (quadratic, microseconds for the
/// outlines of real objects).
pub(super) fn check_simple(vertices: &[Point2<f64>]) -> Result<(), NotSimple> {
    let n = vertices.len();
    let scale = size_of(vertices).max(f64::MIN_POSITIVE);
    for edge in 0..n {
        if (vertices[(edge + 1) % n] - vertices[edge]).norm() <= 1e-12 * scale {
            return Err(NotSimple::ZeroLengthEdge { edge });
        }
    }
    for vertex in 0..n {
        let (a, b, c) = (
            vertices[(vertex + n - 1) % n],
            vertices[vertex],
            vertices[(vertex + 1) % n],
        );
        let (u, v) = (b - a, c - b);
        if cross(u, v).abs() <= 1e-12 * u.norm() * v.norm() && u.dot(&v) < 0.0 {
            return Err(NotSimple::Spike { vertex });
        }
    }
    if turns_left_everywhere(vertices) && (winding_of_turns(vertices) - 1.0).abs() < 1e-6 {
        return Ok(());
    }
    let tolerance = 1e-12 * scale * scale;
    for first in 0..n {
        for second in first + 2..n {
            if first == 0 && second == n - 1 {
                continue; // Neighbours through vertex 0.
            }
            let (a, b) = (vertices[first], vertices[(first + 1) % n]);
            let (c, d) = (vertices[second], vertices[(second + 1) % n]);
            if segments_meet(a, b, c, d, tolerance) {
                return Err(NotSimple::EdgesCross { first, second });
            }
        }
    }
    Ok(())
}

/// The largest extent of the vertices' bounding box.
fn size_of(vertices: &[Point2<f64>]) -> f64 {
    let (mut min, mut max) = (vertices[0], vertices[0]);
    for v in vertices {
        min = Point2::new(min.x.min(v.x), min.y.min(v.y));
        max = Point2::new(max.x.max(v.x), max.y.max(v.y));
    }
    (max.x - min.x).max(max.y - min.y)
}

/// Whether the closed segments `ab` and `cd` share a point; orientations within `tolerance` (an
/// area) of zero count as collinear.
fn segments_meet(
    a: Point2<f64>,
    b: Point2<f64>,
    c: Point2<f64>,
    d: Point2<f64>,
    tolerance: f64,
) -> bool {
    let orient = |p: Point2<f64>, q: Point2<f64>, r: Point2<f64>| {
        let o = cross(q - p, r - p);
        if o.abs() <= tolerance {
            0.0
        } else {
            o.signum()
        }
    };
    let within = |p: Point2<f64>, q: Point2<f64>, r: Point2<f64>| {
        // r collinear with pq: does it lie between them?
        r.x >= p.x.min(q.x) - 1e-12
            && r.x <= p.x.max(q.x) + 1e-12
            && r.y >= p.y.min(q.y) - 1e-12
            && r.y <= p.y.max(q.y) + 1e-12
    };
    let (o1, o2, o3, o4) = (
        orient(a, b, c),
        orient(a, b, d),
        orient(c, d, a),
        orient(c, d, b),
    );
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && within(a, b, c))
        || (o2 == 0.0 && within(a, b, d))
        || (o3 == 0.0 && within(c, d, a))
        || (o4 == 0.0 && within(c, d, b))
}

/// Whether `p` lies inside the simple polygon or within 1e-12 of its boundary (in the units of
/// `cross(edge, p − start)`, the measure the convex test uses): the even–odd crossing rule, which for
/// a simple polygon is the winding rule.
pub(super) fn contains_simple(vertices: &[Point2<f64>], p: Point2<f64>) -> bool {
    let mut inside = false;
    for (a, b) in edges(vertices) {
        let ab = b - a;
        let ap = p - a;
        let along = ap.dot(&ab);
        if cross(ab, ap).abs() <= 1e-12 && along >= 0.0 && along <= ab.norm_squared() {
            return true;
        }
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * ab.x / ab.y;
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// The earliest `t` in `[0, 1]` at which a disc of `radius` whose centre moves from `start` by
/// `motion` comes within `radius` of the segment `ab` (0 when it already is), if it does: the first
/// hit of the ray on the segment's capsule.
pub(super) fn disc_sweep_hits_segment(
    start: Point2<f64>,
    motion: Vector2<f64>,
    radius: f64,
    a: Point2<f64>,
    b: Point2<f64>,
) -> Option<f64> {
    let ab = b - a;
    let length_sq = ab.norm_squared();
    let distance_sq_at = |p: Point2<f64>| {
        let t = ((p - a).dot(&ab) / length_sq).clamp(0.0, 1.0);
        (p - (a + ab * t)).norm_squared()
    };
    if distance_sq_at(start) <= radius * radius {
        return Some(0.0);
    }
    let mut best: Option<f64> = None;
    let mut consider = |t: f64| {
        if (0.0..=1.0).contains(&t) && best.is_none_or(|b| t < b) {
            best = Some(t);
        }
    };
    // The capsule's flat sides: the lines at ±radius from ab, between its ends.
    let normal = Vector2::new(ab.y, -ab.x) / length_sq.sqrt();
    let (offset, rate) = ((start - a).dot(&normal), motion.dot(&normal));
    if rate != 0.0 {
        for side in [radius, -radius] {
            let t = (side - offset) / rate;
            let along = (start + motion * t - a).dot(&ab);
            if along >= 0.0 && along <= length_sq {
                consider(t);
            }
        }
    }
    // Its round ends: circles of `radius` about a and b.
    let m2 = motion.norm_squared();
    if m2 > 0.0 {
        for c in [a, b] {
            let d = start - c;
            let (half_b, cc) = (d.dot(&motion), d.norm_squared() - radius * radius);
            let discriminant = half_b * half_b - m2 * cc;
            if discriminant >= 0.0 {
                consider((-half_b - discriminant.sqrt()) / m2);
            }
        }
    }
    best
}

/// Triangles (vertex indices, counter-clockwise) that tile the simple counter-clockwise polygon:
/// a fan when it is convex, ear clipping otherwise (quadratic in the vertices; once per outline).
pub(super) fn triangulate(vertices: &[Point2<f64>], convex: bool) -> Vec<[usize; 3]> {
    let n = vertices.len();
    if convex {
        return (1..n - 1).map(|i| [0, i, i + 1]).collect();
    }
    let mut remaining: Vec<usize> = (0..n).collect();
    let mut triangles = Vec::with_capacity(n - 2);
    while remaining.len() > 3 {
        let m = remaining.len();
        let ear = (0..m).find(|&k| {
            let (i, j, l) = (
                remaining[(k + m - 1) % m],
                remaining[k],
                remaining[(k + 1) % m],
            );
            let (a, b, c) = (vertices[i], vertices[j], vertices[l]);
            if cross(b - a, c - b) <= 0.0 {
                return false; // A reflex (or straight) corner is no ear.
            }
            remaining
                .iter()
                .all(|&o| o == i || o == j || o == l || !in_triangle(vertices[o], a, b, c))
        });
        // A simple polygon always has an ear; rounding on nearly straight corners could hide it, and
        // then the smallest-angle corner is cut so that drawing never stalls.
        let k = ear.unwrap_or(0);
        triangles.push([
            remaining[(k + m - 1) % m],
            remaining[k],
            remaining[(k + 1) % m],
        ]);
        remaining.remove(k);
    }
    triangles.push([remaining[0], remaining[1], remaining[2]]);
    triangles
}

/// Whether `p` lies in the closed counter-clockwise triangle `abc`.
fn in_triangle(p: Point2<f64>, a: Point2<f64>, b: Point2<f64>, c: Point2<f64>) -> bool {
    cross(b - a, p - a) >= 0.0 && cross(c - b, p - b) >= 0.0 && cross(a - c, p - c) >= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn points(xy: &[[f64; 2]]) -> Vec<Point2<f64>> {
        xy.iter().map(|&p| Point2::from(p)).collect()
    }

    #[test]
    fn simple_polygons_pass_and_each_fault_is_named() {
        let l_shape = points(&[[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]);
        assert_eq!(check_simple(&l_shape), Ok(()));
        let bow_tie = points(&[[0., 0.], [1., 1.], [1., 0.], [0., 1.]]);
        assert_eq!(
            check_simple(&bow_tie),
            Err(NotSimple::EdgesCross {
                first: 0,
                second: 2
            })
        );
        let repeated = points(&[[0., 0.], [1., 0.], [1., 0.], [0., 1.]]);
        assert_eq!(
            check_simple(&repeated),
            Err(NotSimple::ZeroLengthEdge { edge: 1 })
        );
        // A sharp but open corner is fine; a spike returns along the same line.
        let sharp = points(&[[0., 0.], [2., 0.], [3., 0.], [2., 0.01], [0., 1.]]);
        assert_eq!(check_simple(&sharp), Ok(()));
        let true_spike = points(&[[0., 0.], [2., 0.], [3., 0.], [2., 0.], [2., 1.], [0., 1.]]);
        assert_eq!(
            check_simple(&true_spike),
            Err(NotSimple::Spike { vertex: 2 })
        );
        // A vertex touching a non-neighbouring edge is not simple either.
        let touching = points(&[[0., 0.], [2., 0.], [2., 2.], [1., 0.], [0., 2.]]);
        assert!(matches!(
            check_simple(&touching),
            Err(NotSimple::EdgesCross { .. })
        ));
        let pentagram: Vec<Point2<f64>> = (0..5)
            .map(|k| {
                let a = std::f64::consts::TAU * (2 * k) as f64 / 5.0;
                Point2::new(a.cos(), a.sin())
            })
            .collect();
        assert!(turns_left_everywhere(&pentagram));
        assert!(matches!(
            check_simple(&pentagram),
            Err(NotSimple::EdgesCross { .. })
        ));
    }

    #[test]
    fn the_inside_test_of_an_l() {
        let l_shape = points(&[[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]);
        assert!(contains_simple(&l_shape, Point2::new(0.5, 1.5)));
        assert!(contains_simple(&l_shape, Point2::new(1.5, 0.5)));
        assert!(!contains_simple(&l_shape, Point2::new(1.5, 1.5)));
        assert!(contains_simple(&l_shape, Point2::new(1.0, 1.5))); // On the boundary.
        assert!(contains_simple(&l_shape, Point2::new(1.0, 1.0))); // The reflex corner.
        assert!(!contains_simple(&l_shape, Point2::new(-0.1, 1.0)));
    }

    #[test]
    fn a_sweeping_disc_first_touches_a_segment_where_the_capsule_begins() {
        let (a, b) = (Point2::new(0.0, 0.0), Point2::new(1.0, 0.0));
        // Straight down onto the flat side: the centre stops 0.1 above it.
        let t = disc_sweep_hits_segment(Point2::new(0.5, 1.0), Vector2::new(0.0, -2.0), 0.1, a, b);
        assert!((t.expect("hits") - 0.45).abs() < 1e-15);
        // Along the line onto the end: the centre stops 0.1 before b.
        let t = disc_sweep_hits_segment(Point2::new(3.0, 0.0), Vector2::new(-4.0, 0.0), 0.1, a, b);
        assert!((t.expect("hits") - 1.9 / 4.0).abs() < 1e-15);
        assert_eq!(
            disc_sweep_hits_segment(Point2::new(3.0, 1.0), Vector2::new(-4.0, 0.0), 0.1, a, b),
            None
        );
    }

    #[test]
    fn triangles_of_an_l_cover_its_area() {
        let l_shape = points(&[[0., 0.], [2., 0.], [2., 1.], [1., 1.], [1., 2.], [0., 2.]]);
        let triangles = triangulate(&l_shape, false);
        assert_eq!(triangles.len(), 4);
        let area: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| l_shape[i]);
                let doubled = cross(b - a, c - a);
                assert!(doubled > 0.0, "{t:?} is not counter-clockwise");
                doubled / 2.0
            })
            .sum();
        assert!((area - 3.0).abs() < 1e-15);
    }
}
