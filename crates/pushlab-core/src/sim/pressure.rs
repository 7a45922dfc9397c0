//! How the object's weight rests on the floor, and the `h` of Lynch's limit surface that follows.
//!
//! With Coulomb friction at the floor, the largest friction force is `μ∫p dA` and the largest friction
//! torque about the COM is `μ∫p|r − com| dA`; their ratio is Lynch's `c`, the `h` of the paper. The
//! ellipsoid limit surface uses only that ratio, so a pressure distribution matters here only through
//! its pressure-weighted mean distance from the COM.
//!
//! A real object's pressure centre sits under its COM (otherwise it would tip). When the COM is moved
//! off the centre (the paper puts a heavy object into a box), the simulator therefore reweights the
//! material's base distribution by `exp(g·r)` with the `g` that puts its centroid on the COM: the
//! smallest change, in the relative-entropy sense, that keeps every pressure positive.

use crate::math;
use nalgebra::{Matrix2, Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::geometry::Outline;

/// Grid resolution (cells along the longer side of the bounding box) for area pressures.
pub const DEFAULT_RESOLUTION: usize = 200;

/// The shape of a material's base pressure distribution over the footprint.
///
/// `ρ` below runs from 0 in the middle to 1 on the outline. For a convex outline it is the
/// footprint's gauge about its centroid (level sets that are scaled copies of the outline); a
/// non-convex footprint has no such copies inside it (the centroid of a T or a C need not even see its
/// whole outline), so there `ρ = 1 − d/d_max`, with `d` a point's distance to the outline and `d_max`
/// the largest over the footprint (level sets are the outline moved inward).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PressureModel {
    /// Equal pressure everywhere: a stiff flat bottom on a flat floor.
    Uniform,
    /// Pressure `∝ ρ⁴`, concentrated near the outline: a bottom that bows up (a cardboard box).
    Rim,
    /// Pressure `∝ (1 − ρ)²`, concentrated in the middle: a bottom that bulges down.
    #[serde(alias = "center")]
    Centre,
    /// Equal weight on one foot per corner, each 85 % of the way from the centroid to its vertex; on
    /// a non-convex outline one per convex corner, moved inward along its bisector by as much (a
    /// foot that would fall outside the footprint is refused, naming the vertex).
    Feet,
}

impl PressureModel {
    /// Every model, for help texts and tests.
    pub const ALL: [PressureModel; 4] = [
        PressureModel::Uniform,
        PressureModel::Rim,
        PressureModel::Centre,
        PressureModel::Feet,
    ];

    /// The lowercase name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            PressureModel::Uniform => "uniform",
            PressureModel::Rim => "rim",
            PressureModel::Centre => "centre",
            PressureModel::Feet => "feet",
        }
    }

    /// Other names accepted for this model (`center` for `centre`).
    pub fn aliases(self) -> &'static [&'static str] {
        match self {
            PressureModel::Centre => &["center"],
            _ => &[],
        }
    }

    /// The model with this name or alias.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|model| model.name() == name || model.aliases().contains(&name))
    }
}

/// A name that is not a [`PressureModel`]'s.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("'{0}' is not a pressure model, expected one of: {names}", names = PressureModel::ALL.map(PressureModel::name).join(", "))]
pub struct UnknownPressure(pub String);

impl std::str::FromStr for PressureModel {
    type Err = UnknownPressure;

    /// The model of this name or alias ([`PressureModel::from_name`]).
    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Self::from_name(name).ok_or_else(|| UnknownPressure(name.to_owned()))
    }
}

/// Why no pressure distribution balances the object.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PressureError {
    #[error(
        "the COM at ({x:.4}, {y:.4}) m from the object frame's origin (the geometric centre) is not \
         strictly inside the support of the {model} pressure; move it toward the middle of the \
         footprint"
    )]
    ComOutsideSupport { x: f64, y: f64, model: &'static str },
    #[error("the pressure grid has no cell inside the outline; increase the resolution")]
    Empty,
    #[error(
        "the foot at vertex {vertex} lies outside the footprint (the outline is too thin there); \
         choose another pressure model for this outline"
    )]
    FootOutside { vertex: usize },
}

/// A pressure distribution as weighted points of the footprint, object frame; weights sum to 1.
#[derive(Clone, Debug, PartialEq)]
pub struct PressureDistribution {
    points: Vec<Point2<f64>>,
    weights: Vec<f64>,
}

impl PressureDistribution {
    /// The base distribution of `model` over `outline`. Area models are sampled at the centres of a
    /// grid with `resolution` cells along the bounding box's longer side.
    pub fn new(
        outline: &Outline,
        model: PressureModel,
        resolution: usize,
    ) -> Result<Self, PressureError> {
        let centroid = outline.centroid();
        if model == PressureModel::Feet {
            let points = feet(outline, centroid)?;
            let weights = vec![1.0 / points.len() as f64; points.len()];
            return Ok(Self { points, weights });
        }
        let (min, max) = outline.bounding_box();
        let cell = (max.x - min.x).max(max.y - min.y) / resolution.max(1) as f64;
        let (nx, ny) = (
            ((max.x - min.x) / cell).ceil() as usize,
            ((max.y - min.y) / cell).ceil() as usize,
        );
        let mut points = Vec::new();
        for i in 0..nx {
            for j in 0..ny {
                let p = Point2::new(
                    min.x + (i as f64 + 0.5) * cell,
                    min.y + (j as f64 + 0.5) * cell,
                );
                if outline.contains(p) {
                    points.push(p);
                }
            }
        }
        let rhos: Vec<f64> = if model == PressureModel::Uniform {
            vec![0.0; points.len()]
        } else if outline.is_convex() {
            points
                .iter()
                .map(|&p| gauge(outline, centroid, p))
                .collect()
        } else {
            let depths: Vec<f64> = points
                .iter()
                .map(|&p| -outline.closest_boundary_point(p).signed_distance)
                .collect();
            let deepest = depths.iter().copied().fold(0.0, f64::max);
            depths
                .iter()
                .map(|d| {
                    if deepest > 0.0 {
                        1.0 - d / deepest
                    } else {
                        1.0
                    }
                })
                .collect()
        };
        let mut weights: Vec<f64> = rhos
            .iter()
            .map(|&rho| match model {
                PressureModel::Uniform | PressureModel::Feet => 1.0,
                PressureModel::Rim => rho.powi(4),
                PressureModel::Centre => (1.0 - rho).max(0.0).powi(2),
            })
            .collect();
        let total: f64 = weights.iter().sum();
        if points.is_empty() || total <= 0.0 {
            return Err(PressureError::Empty);
        }
        weights.iter_mut().for_each(|w| *w /= total);
        Ok(Self { points, weights })
    }

    /// The pressure centre (weighted centroid), object frame.
    pub fn centroid(&self) -> Point2<f64> {
        let mut c = Vector2::zeros();
        for (p, w) in self.points.iter().zip(&self.weights) {
            c += p.coords * *w;
        }
        Point2::from(c)
    }

    /// The pressure-weighted mean distance from `com`: Lynch's `h` (max friction torque about `com`
    /// over max friction force), metres.
    pub fn h_about(&self, com: Point2<f64>) -> f64 {
        self.points
            .iter()
            .zip(&self.weights)
            .map(|(p, w)| w * (p - com).norm())
            .sum()
    }

    /// The distribution reweighted by `exp(g·r)` so that its pressure centre lies on `com`.
    ///
    /// `g` minimises the convex `log Σ wᵢ exp(g·(rᵢ − com))` (Newton's method with backtracking); a
    /// minimum exists exactly when `com` is strictly inside the convex hull of the points.
    pub fn balanced_at(
        &self,
        com: Point2<f64>,
        model: PressureModel,
    ) -> Result<Self, PressureError> {
        let outside = || PressureError::ComOutsideSupport {
            x: com.x,
            y: com.y,
            model: model.name(),
        };
        let offsets: Vec<Vector2<f64>> = self.points.iter().map(|p| p - com).collect();
        let scale = offsets.iter().map(|d| d.norm()).fold(0.0, f64::max);
        if scale <= 0.0 {
            return Err(outside());
        }
        let objective = |g: Vector2<f64>| log_sum_exp(&self.weights, &offsets, g);
        let mut g = Vector2::zeros();
        for _ in 0..100 {
            let tilted = tilted_weights(&self.weights, &offsets, g);
            let mut mean = Vector2::zeros();
            for (d, w) in offsets.iter().zip(&tilted) {
                mean += d * *w;
            }
            let balanced = Self {
                points: self.points.clone(),
                weights: tilted,
            };
            // A pressure centre within 1e-9 of the object's size of the COM: far below any other
            // error, and about where rounding in the sums stops Newton's method.
            if mean.norm() <= 1e-9 * scale {
                return Ok(balanced);
            }
            let mut covariance = Matrix2::zeros();
            for (d, w) in offsets.iter().zip(&balanced.weights) {
                let e = d - mean;
                covariance += e * e.transpose() * *w;
            }
            let Some(inverse) = covariance.try_inverse() else {
                return Err(outside());
            };
            let direction = -(inverse * mean);
            let (f0, slope) = (objective(g), mean.dot(&direction));
            // Near the minimum the decrease Newton promises falls below the rounding of the objective
            // (about 1e-16 of it), where the Armijo test would only see noise and stall: a step that
            // keeps the objective within rounding is accepted, and the gradient decides when to stop.
            let rounding = 1e-14 * (1.0 + f0.abs());
            let mut step = 1.0;
            while objective(g + direction * step) > f0 + 1e-4 * step * slope + rounding {
                step *= 0.5;
                if step < 1e-12 {
                    // No more progress: rounding, if the pressure centre is already that close.
                    return if mean.norm() <= 1e-6 * scale {
                        Ok(balanced)
                    } else {
                        Err(outside())
                    };
                }
            }
            g += direction * step;
            if !(g.x.is_finite() && g.y.is_finite()) || g.norm() * scale > 700.0 {
                return Err(outside());
            }
        }
        Err(outside())
    }
}

/// Lynch's `h` of an object whose weight rests on the floor by `model`, balanced over its COM at
/// `com_offset` (COM − geometric centre, object frame; the object frame's origin is taken as the
/// geometric centre).
pub fn lynch_h(
    outline: &Outline,
    model: PressureModel,
    com_offset: Vector2<f64>,
    resolution: usize,
) -> Result<f64, PressureError> {
    let com = Point2::from(com_offset);
    let base = PressureDistribution::new(outline, model, resolution)?;
    Ok(base.balanced_at(com, model)?.h_about(com))
}

/// The feet of [`PressureModel::Feet`]: 85 % of the way from the centroid to each vertex of a convex
/// outline. A non-convex footprint's straight line from the centroid to a corner may leave it (the T's
/// bar corners seen from its stem), so there a foot stands at each convex corner, moved inward along
/// the corner's bisector by the same 15 % of its distance from the centroid, and is checked to stand
/// on the footprint.
fn feet(outline: &Outline, centroid: Point2<f64>) -> Result<Vec<Point2<f64>>, PressureError> {
    let vertices = outline.vertices();
    if outline.is_convex() {
        return Ok(vertices
            .iter()
            .map(|v| centroid + (v - centroid) * 0.85)
            .collect());
    }
    let n = vertices.len();
    let mut feet = Vec::with_capacity(n);
    for (vertex, &v) in vertices.iter().enumerate() {
        let (before, after) = (vertices[(vertex + n - 1) % n], vertices[(vertex + 1) % n]);
        let (incoming, outgoing) = ((v - before).normalize(), (after - v).normalize());
        if crate::geometry::cross(incoming, outgoing) <= 0.0 {
            continue; // A reflex or straight corner has no foot.
        }
        let inward = (outgoing - incoming).normalize();
        let foot = v + inward * (0.15 * (v - centroid).norm());
        if !outline.contains(foot) {
            return Err(PressureError::FootOutside { vertex });
        }
        feet.push(foot);
    }
    Ok(feet)
}

/// The gauge of a convex outline about an interior point: the smallest `s` with `p` inside the
/// outline scaled by `s` about `centre`.
fn gauge(outline: &Outline, centre: Point2<f64>, p: Point2<f64>) -> f64 {
    outline
        .edges()
        .map(|(a, b)| {
            let e = b - a;
            let outward = Vector2::new(e.y, -e.x);
            (p - centre).dot(&outward) / (a - centre).dot(&outward)
        })
        .fold(0.0, f64::max)
}

fn log_sum_exp(weights: &[f64], offsets: &[Vector2<f64>], g: Vector2<f64>) -> f64 {
    let max = offsets.iter().map(|d| g.dot(d)).fold(f64::MIN, f64::max);
    let sum: f64 = weights
        .iter()
        .zip(offsets)
        .map(|(w, d)| w * math::exp(g.dot(d) - max))
        .sum();
    max + math::ln(sum)
}

fn tilted_weights(weights: &[f64], offsets: &[Vector2<f64>], g: Vector2<f64>) -> Vec<f64> {
    let max = offsets.iter().map(|d| g.dot(d)).fold(f64::MIN, f64::max);
    let mut tilted: Vec<f64> = weights
        .iter()
        .zip(offsets)
        .map(|(w, d)| w * math::exp(g.dot(d) - max))
        .collect();
    let total: f64 = tilted.iter().sum();
    tilted.iter_mut().for_each(|w| *w /= total);
    tilted
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn pressure_models_parse_by_name_or_alias_and_a_refusal_names_them_all() {
        for model in PressureModel::ALL {
            assert_eq!(model.name().parse(), Ok(model));
        }
        assert_eq!("center".parse(), Ok(PressureModel::Centre));
        assert_eq!(
            "wood".parse::<PressureModel>().map_err(|e| e.to_string()),
            Err(
                "'wood' is not a pressure model, expected one of: uniform, rim, centre, feet"
                    .into()
            )
        );
    }

    #[test]
    fn balancing_converges_where_the_objective_is_within_rounding() {
        // A hexagon with vertices rounded to a micrometre: Newton's last steps promise decreases of
        // the objective below its rounding, which once stalled the line search and refused a COM well
        // inside the footprint.
        let hexagon = Outline::try_from(vec![
            [0.18, 0.0],
            [0.09, 0.155885],
            [-0.09, 0.155885],
            [-0.18, 0.0],
            [-0.09, -0.155885],
            [0.09, -0.155885],
        ])
        .unwrap();
        let com = Vector2::new(-0.03, 0.04);
        let base = PressureDistribution::new(&hexagon, PressureModel::Uniform, 200).unwrap();
        let balanced = base
            .balanced_at(Point2::from(com), PressureModel::Uniform)
            .unwrap();
        assert!((balanced.centroid() - Point2::from(com)).norm() < 1e-9);
        let h = lynch_h(&hexagon, PressureModel::Uniform, com, 200).unwrap();
        assert!(h > 0.09 && h < 0.11, "h = {h}");
    }

    #[test]
    fn uniform_disc_has_h_of_two_thirds_of_its_radius() {
        // Closed form: (1/(πR²))∫∫ r dA = 2R/3.
        let disc = Outline::ellipse(Point2::origin(), 0.1, 0.1, 256).unwrap();
        let h = lynch_h(&disc, PressureModel::Uniform, Vector2::zeros(), 400).unwrap();
        assert!((h - 0.2 / 3.0).abs() < 2e-4, "h = {h}");
    }

    #[test]
    fn uniform_square_matches_the_closed_form() {
        // Mean distance from the centre of a square of side s: s(√2 + ln(1 + √2))/6.
        let s = 0.3;
        let square = Outline::rectangle(s, s).unwrap();
        let h = lynch_h(&square, PressureModel::Uniform, Vector2::zeros(), 400).unwrap();
        let exact = s * (2f64.sqrt() + (1.0 + 2f64.sqrt()).ln()) / 6.0;
        assert!((h - exact).abs() < 1e-5, "h = {h}, exact {exact}");
    }

    #[test]
    fn feet_at_the_corners_give_their_distance() {
        let s = 0.4;
        let square = Outline::rectangle(s, s).unwrap();
        let h = lynch_h(&square, PressureModel::Feet, Vector2::zeros(), 10).unwrap();
        assert!((h - 0.85 * s / 2f64.sqrt()).abs() < 1e-12, "h = {h}");
    }

    #[test]
    fn materials_order_h_from_rim_to_centre() {
        let b = Outline::rectangle(0.3, 0.4).unwrap();
        let h = |m| lynch_h(&b, m, Vector2::zeros(), 200).unwrap();
        let (rim, uniform, centre) = (
            h(PressureModel::Rim),
            h(PressureModel::Uniform),
            h(PressureModel::Centre),
        );
        assert!(
            rim > uniform + 0.01 && uniform > centre + 0.01,
            "{rim} {uniform} {centre}"
        );
    }

    #[test]
    fn balancing_puts_the_pressure_centre_on_the_com() {
        let b = Outline::rectangle(0.3, 0.4).unwrap();
        for model in PressureModel::ALL {
            let base = PressureDistribution::new(&b, model, 100).unwrap();
            let com = Point2::new(0.05, -0.06);
            let balanced = base.balanced_at(com, model).unwrap();
            assert!((balanced.centroid() - com).norm() < 1e-9, "{model:?}");
            assert!(
                balanced
                    .weights
                    .iter()
                    .all(|w| *w > 0.0 || model != PressureModel::Uniform)
            );
        }
    }

    /// `∫∫ |r| dA` over the rectangle `[x0, x1] × [y0, y1]`, in closed form: the antiderivative
    /// `G = x·y·r/3 + x³·ln(y + r)/6 + y³·ln(x + r)/6` (r = |(x, y)|) at the four corners.
    fn distance_integral_over_rectangle(x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
        let g = |x: f64, y: f64| {
            let r = x.hypot(y);
            let mut value = x * y * r / 3.0;
            if x != 0.0 && y + r > 0.0 {
                value += x.powi(3) * (y + r).ln() / 6.0;
            }
            if y != 0.0 && x + r > 0.0 {
                value += y.powi(3) * (x + r).ln() / 6.0;
            }
            value
        };
        g(x1, y1) - g(x0, y1) - g(x1, y0) + g(x0, y0)
    }

    /// Lynch's `h` of a uniform pressure over the Push-T T about a point on its axis, pixels, from
    /// the closed forms of its two rectangles (bar and stem), independent of any outline code.
    fn t_uniform_h_px(about_local_y: f64) -> f64 {
        let y = about_local_y;
        let bar = distance_integral_over_rectangle(-60.0, 60.0, -y, 30.0 - y);
        let stem = distance_integral_over_rectangle(-15.0, 15.0, 30.0 - y, 120.0 - y);
        (bar + stem) / 6300.0
    }

    #[test]
    fn the_closed_form_of_a_square_is_the_known_one() {
        let exact = (2f64.sqrt() + (1.0 + 2f64.sqrt()).ln()) / 6.0;
        assert!((distance_integral_over_rectangle(-0.5, 0.5, -0.5, 0.5) - exact).abs() < 1e-15);
    }

    #[test]
    fn uniform_h_over_the_push_t_matches_its_two_rectangles() {
        use crate::geometry::PushT;
        let scale = 0.001;
        let t = PushT::outline(scale).unwrap();
        // About the geometric centre (local y = 285/7 px): ≈ 39.93 mm.
        let exact = t_uniform_h_px(285.0 / 7.0) * scale;
        assert!((exact - 0.039925).abs() < 1e-6, "{exact}");
        let h = lynch_h(&t, PressureModel::Uniform, Vector2::zeros(), 400).unwrap();
        assert!((h - exact).abs() < 2e-5, "h = {h}, exact {exact}");
        let grid = t.uniform_pressure_h(Point2::origin(), 400);
        assert!((grid - exact).abs() < 2e-5, "grid {grid}, exact {exact}");
        // The mean distance is below the radius of gyration √(J/A), J from the rectangles' polar
        // moments moved to the centroid (parallel axes): a check that `h` is the mean, not the RMS.
        let polar = |w: f64, l: f64, centre_y: f64| {
            w * l * (w * w + l * l) / 12.0 + w * l * (centre_y - 285.0 / 7.0).powi(2)
        };
        let gyration = ((polar(120.0, 30.0, 15.0) + polar(30.0, 90.0, 75.0)) / 6300.0).sqrt();
        assert!(exact / scale < gyration && gyration < 1.2 * exact / scale);
        // About the true COM, local (0, 45) px: uniform weight, another point.
        let com = PushT::com_offset(scale);
        let exact_com = t_uniform_h_px(45.0) * scale;
        let grid = t.uniform_pressure_h(Point2::from(com), 400);
        assert!((grid - exact_com).abs() < 2e-5, "{grid} {exact_com}");
        // Balanced over that COM, the pressure centre lies on it.
        let base = PressureDistribution::new(&t, PressureModel::Uniform, 200).unwrap();
        let balanced = base
            .balanced_at(Point2::from(com), PressureModel::Uniform)
            .unwrap();
        assert!((balanced.centroid() - Point2::from(com)).norm() < 1e-9);
    }

    #[test]
    fn every_model_works_on_the_t_and_orders_h_from_rim_to_centre() {
        let t = crate::geometry::PushT::outline(0.001).unwrap();
        let h = |m| lynch_h(&t, m, Vector2::zeros(), 200).unwrap();
        let (rim, uniform, centre) = (
            h(PressureModel::Rim),
            h(PressureModel::Uniform),
            h(PressureModel::Centre),
        );
        assert!(
            rim > uniform && uniform > centre,
            "{rim} {uniform} {centre}"
        );
        // Six feet, one per convex corner (the two inner corners carry none), all on the T.
        let feet = PressureDistribution::new(&t, PressureModel::Feet, 10).unwrap();
        assert_eq!(feet.points.len(), 6);
        assert!(feet.points.iter().all(|p| t.contains(*p)));
        // A C of 2 % thick arms is too thin for feet moved in by 15 % of their distance from its
        // centroid.
        let c = Outline::try_from(vec![
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.02],
            [0.02, 0.02],
            [0.02, 0.98],
            [1.0, 0.98],
            [1.0, 1.0],
            [0.0, 1.0],
        ])
        .unwrap();
        let err = PressureDistribution::new(&c, PressureModel::Feet, 10).unwrap_err();
        assert!(
            err.to_string().contains("lies outside the footprint"),
            "{err}"
        );
    }

    #[test]
    fn a_com_outside_the_feet_is_refused() {
        let b = Outline::rectangle(0.3, 0.4).unwrap();
        let err = lynch_h(&b, PressureModel::Feet, Vector2::new(0.14, 0.0), 10).unwrap_err();
        assert!(err.to_string().contains("not strictly inside"), "{err}");
    }
}
