//! The part of a footprint inside a convex region: what the scene shows of the COM's 95 % ellipse.
//!
//! Online learning keeps the COM inside the object's footprint (`model::PhysicalBounds`), so the part
//! of the ellipse outside the footprint is no place the COM can be. At the first frames the ellipse is
//! the prior's, wider than the object (σ = 2h), and drawn whole it covered the scene; drawn within the
//! footprint it says "anywhere in the object" until the pushes narrow it.
//!
//! Sutherland–Hodgman clipping of each of the outline's triangles by the convex region: a
//! non-convex outline (the Push-T T) is clipped triangle by triangle, so every piece is convex.

use nalgebra::Point2;

use super::Outline;
use super::polygon::{cross, signed_area};

/// The polygon `subject` clipped to the convex polygon `convex` (either orientation): the vertices of
/// their intersection, empty where they do not overlap. `subject` must be convex too for the result
/// to be one polygon (a non-convex subject gives its pieces joined by zero-width seams).
pub fn clip_to_convex(subject: &[Point2<f64>], convex: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let mut region = convex.to_vec();
    if signed_area(&region) < 0.0 {
        region.reverse();
    }
    let mut output = subject.to_vec();
    let n = region.len();
    for i in 0..n {
        if output.is_empty() {
            break;
        }
        let (a, b) = (region[i], region[(i + 1) % n]);
        let side = |p: Point2<f64>| cross(b - a, p - a);
        let input = std::mem::take(&mut output);
        for (k, &p) in input.iter().enumerate() {
            let q = input[(k + 1) % input.len()];
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                output.push(p);
            }
            // The edge crosses the line: its crossing point, once.
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                output.push(p + (q - p) * t);
            }
        }
    }
    output
}

impl Outline {
    /// The footprint's part inside the convex polygon `convex`, as convex pieces (one per triangle of
    /// the outline that overlaps it), in the outline's frame.
    pub fn clipped_to_convex(&self, convex: &[Point2<f64>]) -> Vec<Vec<Point2<f64>>> {
        let vertices = self.vertices();
        self.triangles()
            .iter()
            .map(|t| clip_to_convex(&t.map(|i| vertices[i]), convex))
            .filter(|piece| piece.len() >= 3)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::PushT;

    fn area(pieces: &[Vec<Point2<f64>>]) -> f64 {
        pieces.iter().map(|p| signed_area(p).abs()).sum()
    }

    fn disc(centre: Point2<f64>, radius: f64, clockwise: bool) -> Vec<Point2<f64>> {
        let mut points: Vec<_> = (0..64)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 64.0;
                centre + nalgebra::Vector2::new(t.cos(), t.sin()) * radius
            })
            .collect();
        if clockwise {
            points.reverse();
        }
        points
    }

    #[test]
    fn a_square_clipped_by_a_triangle_keeps_the_half_under_its_diagonal() {
        let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]].map(Point2::from);
        let triangle = [[-1.0, -1.0], [3.0, -1.0], [-1.0, 3.0]].map(Point2::from);
        let piece = clip_to_convex(&square, &triangle);
        assert!((signed_area(&piece) - 1.0).abs() < 1e-12, "{piece:?}");
        // The square's corner (1, 1) on the triangle's edge x + y = 2: still the whole square.
        let touching = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]].map(Point2::from);
        assert!((signed_area(&clip_to_convex(&square, &touching)) - 1.0).abs() < 1e-12);
        let half = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]].map(Point2::from);
        assert!((signed_area(&clip_to_convex(&square, &half)) - 0.5).abs() < 1e-12);
        let apart = [[2.0, 2.0], [3.0, 2.0], [2.0, 3.0]].map(Point2::from);
        assert!(clip_to_convex(&square, &apart).is_empty());
    }

    #[test]
    fn a_footprint_within_a_disc_is_whichever_is_inside_the_other() {
        let rectangle = Outline::rectangle(0.3, 0.4).expect("box");
        for clockwise in [false, true] {
            // A disc larger than the box holds all of it; a small one inside is all disc.
            let large = rectangle.clipped_to_convex(&disc(Point2::origin(), 1.0, clockwise));
            assert!((area(&large) - 0.12).abs() < 1e-12, "{}", area(&large));
            let small = disc(Point2::new(0.05, -0.1), 0.04, clockwise);
            let inside = rectangle.clipped_to_convex(&small);
            assert!((area(&inside) - signed_area(&small).abs()).abs() < 1e-12);
        }
        // Centred on a corner, a disc of radius r keeps a quarter of itself.
        let corner = disc(Point2::new(0.15, 0.2), 0.05, false);
        let quarter = area(&rectangle.clipped_to_convex(&corner));
        assert!(
            (quarter - signed_area(&corner) / 4.0).abs() < 1e-12,
            "{quarter}"
        );
    }

    #[test]
    fn the_t_is_clipped_triangle_by_triangle_and_its_notches_stay_empty() {
        let t = PushT::outline(0.001).expect("the T");
        let whole = t.clipped_to_convex(&disc(Point2::origin(), 10.0, false));
        assert!((area(&whole) - t.area()).abs() < 1e-12 * t.area().max(1.0));
        for piece in &whole {
            assert!(
                signed_area(piece) > 0.0,
                "pieces keep the outline's orientation"
            );
        }
        // A small disc in a notch beside the stem, outside the T, leaves nothing.
        let notch = PushT::object_from_local(Point2::new(40.0, 60.0), 0.001);
        assert!(!t.contains(notch));
        assert!(t.clipped_to_convex(&disc(notch, 0.005, false)).is_empty());
    }
}
