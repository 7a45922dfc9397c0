//! Contour lines of a [`Landscape`]: where the loss crosses chosen levels, as line segments in the
//! landscape's own coordinates (COM offset, metres). Marching squares over the cell centres, with
//! each crossing placed by linear interpolation along the cell edge; a square with a cell that has
//! no loss (`NaN`) draws nothing.
//!
//! The levels are quantiles of the cells' losses rather than evenly spaced values: the loss of a push
//! spans orders of magnitude between the valley and the object's far corners, and evenly spaced
//! levels would all crowd the corners while the valley, the interesting part, got none.

use super::Landscape;

/// A contour at one level: its segments, each `[from, to]` as `[x, y]` in metres.
#[derive(Clone, Debug, PartialEq)]
pub struct Contour {
    pub level: f64,
    pub segments: Vec<[[f64; 2]; 2]>,
}

/// The fractions of cells below each level [`contour_levels`] chooses by default: dense near the
/// minimum, where the valley's shape is.
pub const DEFAULT_QUANTILES: [f64; 7] = [0.02, 0.05, 0.1, 0.2, 0.35, 0.55, 0.8];

/// The loss below which each fraction of the landscape's cells (with a loss) lies; an empty list for
/// a landscape without any loss. Equal levels (a flat landscape) are kept once.
pub fn contour_levels(landscape: &Landscape, quantiles: &[f64]) -> Vec<f64> {
    let mut losses: Vec<f64> = landscape
        .loss
        .iter()
        .copied()
        .filter(|l| l.is_finite())
        .collect();
    if losses.is_empty() {
        return Vec::new();
    }
    losses.sort_by(f64::total_cmp);
    let last = losses.len() - 1;
    let mut levels: Vec<f64> = quantiles
        .iter()
        .map(|q| losses[((q.clamp(0.0, 1.0) * last as f64).round() as usize).min(last)])
        .collect();
    levels.dedup();
    levels
}

/// The contour lines of `landscape` at each of `levels`.
pub fn contours(landscape: &Landscape, levels: &[f64]) -> Vec<Contour> {
    levels
        .iter()
        .map(|&level| Contour {
            level,
            segments: segments_at(landscape, level),
        })
        .collect()
}

/// Marching squares at one level. Corners of a square are cell centres, numbered counter-clockwise
/// from the lower left: 0 (ix, iy), 1 (ix+1, iy), 2 (ix+1, iy+1), 3 (ix, iy+1).
fn segments_at(landscape: &Landscape, level: f64) -> Vec<[[f64; 2]; 2]> {
    let grid = &landscape.grid;
    let cells = grid.cells;
    let value = |ix: usize, iy: usize| landscape.loss[iy * cells + ix];
    let point = |ix: usize, iy: usize| [grid.cell_centre(0, ix), grid.cell_centre(1, iy)];
    let mut segments = Vec::new();
    for iy in 0..cells.saturating_sub(1) {
        for ix in 0..cells.saturating_sub(1) {
            let corners = [(ix, iy), (ix + 1, iy), (ix + 1, iy + 1), (ix, iy + 1)];
            let values = corners.map(|(x, y)| value(x, y));
            if values.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let above = values.map(|v| v > level);
            // Where the level crosses edge e (from corner e to corner e+1), if it does.
            let crossing = |e: usize| -> Option<[f64; 2]> {
                let (a, b) = (e, (e + 1) % 4);
                if above[a] == above[b] {
                    return None;
                }
                let t = (level - values[a]) / (values[b] - values[a]);
                let (pa, pb) = (
                    point(corners[a].0, corners[a].1),
                    point(corners[b].0, corners[b].1),
                );
                Some([pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])])
            };
            let crossed: Vec<[f64; 2]> = (0..4).filter_map(crossing).collect();
            match crossed.len() {
                2 => segments.push([crossed[0], crossed[1]]),
                4 => {
                    // A saddle: the mean of the corners says whether the middle is above, and so
                    // which pairs of crossings belong together (edges 0–1 and 2–3, or 3–0 and 1–2).
                    let middle_above = values.iter().sum::<f64>() / 4.0 > level;
                    if middle_above == above[0] {
                        segments.push([crossed[0], crossed[3]]);
                        segments.push([crossed[1], crossed[2]]);
                    } else {
                        segments.push([crossed[0], crossed[1]]);
                        segments.push([crossed[2], crossed[3]]);
                    }
                }
                _ => {}
            }
        }
    }
    segments
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inspect::ComGrid;

    fn bowl(cells: usize, f: impl Fn(f64, f64) -> f64) -> Landscape {
        let grid = ComGrid {
            centre: [0.01, -0.02],
            half_width: 0.05,
            cells,
        };
        let mut loss = Vec::new();
        for iy in 0..cells {
            for ix in 0..cells {
                loss.push(f(grid.cell_centre(0, ix), grid.cell_centre(1, iy)));
            }
        }
        Landscape {
            grid,
            h: 0.05,
            loss,
        }
    }

    #[test]
    fn a_round_bowls_contour_is_a_closed_circle_at_its_radius() {
        let (cx, cy) = (0.01, -0.02);
        let landscape = bowl(64, |x, y| (x - cx).powi(2) + (y - cy).powi(2));
        let radius: f64 = 0.03;
        let contour = &contours(&landscape, &[radius * radius])[0];
        assert!(contour.segments.len() > 100, "{}", contour.segments.len());
        let cell = landscape.grid.cell_size();
        for point in contour.segments.iter().flatten() {
            let r = (point[0] - cx).hypot(point[1] - cy);
            // Linear interpolation of a quadratic errs by a fraction of a cell.
            assert!((r - radius).abs() < 0.1 * cell, "r = {r}");
        }
        // Closed: every end point is shared by exactly two segments.
        let key = |p: &[f64; 2]| ((p[0] * 1e9).round() as i64, (p[1] * 1e9).round() as i64);
        let mut ends = std::collections::HashMap::new();
        for point in contour.segments.iter().flatten() {
            *ends.entry(key(point)).or_insert(0) += 1;
        }
        assert!(ends.values().all(|&n| n == 2));
    }

    #[test]
    fn a_level_outside_the_range_and_cells_without_loss_draw_nothing() {
        let landscape = bowl(16, |x, y| x * x + y * y);
        assert!(contours(&landscape, &[-1.0])[0].segments.is_empty());
        assert!(contours(&landscape, &[1e6])[0].segments.is_empty());
        let mut holed = landscape.clone();
        holed.loss.iter_mut().for_each(|l| *l = f64::NAN);
        assert!(contours(&holed, &[0.001])[0].segments.is_empty());
        assert!(contour_levels(&holed, &DEFAULT_QUANTILES).is_empty());
    }

    #[test]
    fn levels_are_quantiles_of_the_cells_losses() {
        // Losses 0, 1, …, 99 over a 10 × 10 grid.
        let mut landscape = bowl(10, |_, _| 0.0);
        landscape
            .loss
            .iter_mut()
            .enumerate()
            .for_each(|(i, l)| *l = i as f64);
        assert_eq!(
            contour_levels(&landscape, &[0.0, 0.1, 0.5, 1.0]),
            vec![0.0, 10.0, 50.0, 99.0]
        );
        // A flat landscape keeps one level.
        let flat = bowl(10, |_, _| 2.0);
        assert_eq!(contour_levels(&flat, &DEFAULT_QUANTILES), vec![2.0]);
    }
}
