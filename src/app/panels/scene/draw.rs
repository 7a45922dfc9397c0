//! Drawing the scene's parts through a [`Projection`]: footprints, the pusher, the contact, the COM
//! markers, the robot's path and trails, and the metres grid. Nothing here decides what to draw or
//! changes state; `scene::ui` does that.

use eframe::egui::{self, Color32, Pos2, Shape, Stroke, Vec2};
use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::inspect::{PushShape, Rollout};
use pushlab_core::model::{ObjectMotion, Prediction};
use pushlab_core::trajectory::{Frame, Trajectory};

use super::camera::Projection;
use crate::app::colors::{self, Palette};

/// How a footprint is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FootprintStyle {
    pub color: Color32,
    pub line: FootprintLine,
}

/// The outline's line, which tells measured from predicted poses apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FootprintLine {
    /// Solid and lightly filled: the measured pose now.
    Filled,
    /// Dashed: the measured pose at the target frame.
    Dashed,
    /// Solid outline: a predicted pose.
    Outline,
}

impl FootprintStyle {
    /// The measured pose at the frame shown, in `palette`'s colour for the truth.
    pub const fn measured_now(palette: &Palette) -> Self {
        Self {
            color: palette.truth,
            line: FootprintLine::Filled,
        }
    }

    /// The measured pose at the target frame.
    pub const fn measured_target(palette: &Palette) -> Self {
        Self {
            color: palette.truth,
            line: FootprintLine::Dashed,
        }
    }

    /// A pose predicted by the model of this colour.
    pub const fn predicted(color: Color32) -> Self {
        Self {
            color,
            line: FootprintLine::Outline,
        }
    }
}

/// The object's outline at `pose`, with a short line along its x axis so that rotation shows on
/// symmetric shapes.
pub fn footprint(
    painter: &egui::Painter,
    projection: &Projection,
    outline: &Outline,
    pose: &Pose2,
    style: FootprintStyle,
) {
    let points: Vec<Pos2> = outline
        .vertices()
        .iter()
        .map(|v| projection.to_screen(pose.point_in_world(*v)))
        .collect();
    let color = style.color;
    match style.line {
        FootprintLine::Dashed => {
            let mut closed = points.clone();
            closed.extend(points.first().copied());
            painter.extend(Shape::dashed_line(
                &closed,
                Stroke::new(1.5, color),
                6.0,
                4.0,
            ));
        }
        FootprintLine::Filled | FootprintLine::Outline => {
            let fill = if style.line == FootprintLine::Filled {
                color.gamma_multiply(0.12)
            } else {
                Color32::TRANSPARENT
            };
            if outline.is_convex() {
                painter.add(Shape::convex_polygon(points, fill, Stroke::new(2.0, color)));
            } else {
                // egui fills convex polygons only (a T would be filled across its notches): the
                // outline's own triangles fill it, and the line goes round on top.
                if fill != Color32::TRANSPARENT {
                    painter.add(filled_triangles(&points, outline.triangles(), fill));
                }
                painter.add(Shape::closed_line(points, Stroke::new(2.0, color)));
            }
        }
    }
    let centre = projection.to_screen(pose.position);
    let axis = projection.to_screen(pose.point_in_world(Point2::new(outline.size() * 0.15, 0.0)));
    painter.line_segment([centre, axis], Stroke::new(1.0, color.gamma_multiply(0.7)));
}

/// A mesh of `triangles` (indices into `points`) in one colour: a non-convex footprint's fill.
fn filled_triangles(points: &[Pos2], triangles: &[[usize; 3]], fill: Color32) -> Shape {
    let mut mesh = egui::Mesh::default();
    for &p in points {
        mesh.colored_vertex(p, fill);
    }
    for &[a, b, c] in triangles {
        // Indices of an outline's vertices: far below u32::MAX.
        mesh.add_triangle(a as u32, b as u32, c as u32);
    }
    Shape::mesh(mesh)
}

/// A what-if rollout: each predicted pose as a ghost footprint fading with the steps ahead, and the
/// recorded pose at the last step dashed beside it.
pub fn what_if(
    painter: &egui::Painter,
    projection: &Projection,
    outline: &Outline,
    rollout: &Rollout,
    trajectory: &Trajectory,
) {
    let palette = colors::of(painter.ctx());
    let steps = rollout.poses.len().max(1) as f32;
    for (i, (_, pose)) in rollout.poses.iter().enumerate() {
        let fade = 0.75 - 0.6 * (i as f32 / steps);
        let points: Vec<Pos2> = outline
            .vertices()
            .iter()
            .map(|v| projection.to_screen(pose.point_in_world(*v)))
            .collect();
        painter.add(Shape::closed_line(
            points,
            Stroke::new(1.0, palette.online.gamma_multiply(fade)),
        ));
    }
    if let Some((frame, _)) = rollout.poses.last()
        && let Some(recorded) = trajectory.frames.get(*frame)
    {
        footprint(
            painter,
            projection,
            outline,
            &recorded.object,
            FootprintStyle {
                color: palette.truth.gamma_multiply(0.6),
                line: FootprintLine::Dashed,
            },
        );
    }
}

/// The 95 % ellipse of the estimated COM: half-axes (metres) and the major axis's angle, both in the
/// object frame at `pose`, around the COM offset `com`. With the object's `outline`, filled only
/// inside the footprint, where the COM can be (online learning keeps it there), and dashed outside:
/// the first frames' ellipse is the prior's, wider than the object, and filled whole it covered the
/// scene (`geometry::clip`).
pub fn com_ellipse(
    painter: &egui::Painter,
    projection: &Projection,
    pose: &Pose2,
    outline: Option<&Outline>,
    com: [f64; 2],
    axes: [f64; 2],
    angle: f64,
) {
    let palette = colors::of(painter.ctx());
    if !(axes[0].is_finite() && axes[1].is_finite()) {
        return;
    }
    let (sin, cos) = angle.sin_cos();
    let in_object: Vec<Point2<f64>> = (0..128)
        .map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / 128.0;
            let (a, b) = (axes[0] * t.cos(), axes[1] * t.sin());
            Point2::new(com[0] + a * cos - b * sin, com[1] + a * sin + b * cos)
        })
        .collect();
    let screen = |p: &Point2<f64>| projection.to_screen(pose.point_in_world(*p));
    let fill = palette.online.gamma_multiply(0.10);
    let stroke = Stroke::new(1.5, palette.online.gamma_multiply(0.8));
    let Some(outline) = outline else {
        let points = in_object.iter().map(screen).collect();
        painter.add(Shape::convex_polygon(points, fill, stroke));
        return;
    };
    // The fill: the footprint's convex pieces inside the ellipse, as one mesh (no seams between them).
    let mut mesh = egui::Mesh::default();
    for piece in outline.clipped_to_convex(&in_object) {
        let first = mesh.vertices.len() as u32;
        for p in &piece {
            mesh.colored_vertex(screen(p), fill);
        }
        for k in 1..piece.len() as u32 - 1 {
            mesh.add_triangle(first, first + k, first + k + 1);
        }
    }
    painter.add(Shape::mesh(mesh));
    // The line: solid inside the footprint, faint and dashed outside it, so that the ellipse's size
    // and direction still read where it is wider than the object.
    let inside: Vec<bool> = in_object.iter().map(|p| outline.contains(*p)).collect();
    if inside.iter().all(|&i| i) {
        painter.add(Shape::closed_line(
            in_object.iter().map(screen).collect(),
            stroke,
        ));
        return;
    }
    let outside_stroke = Stroke::new(1.0, palette.online.gamma_multiply(0.45));
    let n = in_object.len();
    // Start at a change from inside to outside, so that every run of one kind is whole.
    let start = (0..n)
        .find(|&k| inside[k] != inside[(k + n - 1) % n])
        .unwrap_or(0);
    let mut run: Vec<Pos2> = vec![screen(&in_object[start])];
    for step in 1..=n {
        let k = (start + step) % n;
        run.push(screen(&in_object[k]));
        let segment_inside = inside[(k + n - 1) % n] && inside[k];
        let next_inside = inside[k] && inside[(k + 1) % n];
        if step == n || segment_inside != next_inside {
            if segment_inside {
                painter.add(Shape::line(std::mem::take(&mut run), stroke));
            } else {
                painter.extend(Shape::dashed_line(&run, outside_stroke, 6.0, 4.0));
                run.clear();
            }
            run.push(screen(&in_object[k]));
        }
    }
}

/// The object pose reached by `motion` from `pose`, with the motion multiplied by `gain`.
pub fn exaggerated(pose: &Pose2, motion: &ObjectMotion, gain: f64) -> Pose2 {
    pose.moved_by(
        Vector2::new(motion.translation[0], motion.translation[1]) * gain,
        motion.rotation * gain,
    )
}

/// The pusher disc (at least a few points wide, so a 5 mm rod stays visible).
pub fn pusher(painter: &egui::Painter, projection: &Projection, centre: Point2<f64>, radius: f64) {
    let palette = colors::of(painter.ctx());
    let radius = (radius as f32 * projection.scale()).max(3.0);
    painter.circle(
        projection.to_screen(centre),
        radius,
        palette.robot.gamma_multiply(0.35),
        Stroke::new(2.0, palette.robot),
    );
}

/// The predicted contact point `c` and its motion `u_c` (times `gain`).
pub fn contact(
    painter: &egui::Painter,
    projection: &Projection,
    pose: &Pose2,
    prediction: &Prediction,
    gain: f64,
) {
    let palette = colors::of(painter.ctx());
    let Some(c) = prediction.contact else {
        return;
    };
    let c_world = pose.point_in_world(Point2::from(c));
    let p = projection.to_screen(c_world);
    painter.circle_filled(p, 4.0, palette.contact);
    if let Some(u) = prediction.contact_motion {
        let u_world = pose.vector_in_world(Vector2::new(u[0], u[1])) * gain;
        let tip = projection.to_screen(c_world + u_world);
        painter.arrow(p, tip - p, Stroke::new(2.0, palette.contact));
    }
}

/// A suggested next push (`rank`, 1 the best): an arrow in the pusher's direction ending where the
/// pusher would touch the object (`pose`), `length` metres long, numbered at its tail.
pub fn next_push(
    painter: &egui::Painter,
    projection: &Projection,
    pose: &Pose2,
    shape: &PushShape,
    length: f64,
    rank: usize,
) {
    let palette = colors::of(painter.ctx());
    let contact = pose.point_in_world(Point2::from(shape.contact_in_object));
    let direction = pose.vector_in_world(Vector2::from(shape.direction_in_object));
    let tail = projection.to_screen(contact - direction * length);
    let tip = projection.to_screen(contact);
    let width = if rank == 1 { 3.0 } else { 2.0 };
    painter.arrow(
        tail,
        tip - tail,
        Stroke::new(width + 1.5, palette.background),
    );
    painter.arrow(tail, tip - tail, Stroke::new(width, palette.suggestion));
    let away = (tail - tip).normalized() * 10.0;
    painter.text(
        tail + away,
        egui::Align2::CENTER_CENTER,
        rank.to_string(),
        egui::FontId::proportional(14.0),
        palette.suggestion,
    );
}

/// The true COM: a cross.
pub fn true_com(painter: &egui::Painter, at: Pos2) {
    let palette = colors::of(painter.ctx());
    let s = 7.0;
    let stroke = Stroke::new(2.0, palette.truth);
    painter.line_segment([at - Vec2::splat(s), at + Vec2::splat(s)], stroke);
    painter.line_segment([at + Vec2::new(-s, s), at + Vec2::new(s, -s)], stroke);
}

/// The COM of the best θ for the whole push (the Steer tab's): an orange ring, the estimated COM's
/// colour, hollow so that the estimate can sit inside it.
pub fn best_com(painter: &egui::Painter, at: Pos2) {
    let palette = colors::of(painter.ctx());
    painter.circle_stroke(at, 9.0, Stroke::new(3.5, Color32::BLACK));
    painter.circle_stroke(at, 9.0, Stroke::new(2.0, palette.online));
}

/// The COM labelled in the recording's metadata: a diamond, larger while hovered or dragged.
pub fn com_label(painter: &egui::Painter, at: Pos2, hot: bool) {
    let palette = colors::of(painter.ctx());
    let s = if hot { 8.0 } else { 6.5 };
    let diamond = vec![
        at + Vec2::new(0.0, -s),
        at + Vec2::new(s, 0.0),
        at + Vec2::new(0.0, s),
        at + Vec2::new(-s, 0.0),
    ];
    painter.add(Shape::convex_polygon(
        diamond,
        palette.com_label,
        Stroke::new(1.5, Color32::BLACK),
    ));
}

/// The COM estimated online: an orange dot, larger while hovered or dragged.
pub fn estimated_com(painter: &egui::Painter, at: Pos2, hot: bool) {
    let palette = colors::of(painter.ctx());
    painter.circle(
        at,
        if hot { 7.0 } else { 5.5 },
        palette.online,
        Stroke::new(1.5, Color32::BLACK),
    );
}

/// A polyline of world points (the robot's whole path, already thinned).
pub fn path(painter: &egui::Painter, projection: &Projection, points: &[Point2<f64>]) {
    let palette = colors::of(painter.ctx());
    if points.len() > 1 {
        let screen = points.iter().map(|p| projection.to_screen(*p)).collect();
        painter.add(Shape::line(
            screen,
            Stroke::new(1.0, palette.robot.gamma_multiply(0.25)),
        ));
    }
}

/// Seconds of history a trail shows.
pub const TRAIL_SECONDS: f64 = 6.0;
/// Most segments of one trail, whatever the frame rate.
pub const TRAIL_SEGMENTS: usize = 120;

/// Fading trails of the robot and the object over the last [`TRAIL_SECONDS`] before `now`, at most
/// [`TRAIL_SEGMENTS`] segments each (every k-th frame at high rates).
pub fn trails(painter: &egui::Painter, projection: &Projection, frames: &[Frame], now: usize) {
    let palette = colors::of(painter.ctx());
    let Some(current) = frames.get(now) else {
        return;
    };
    let start = frames[..now].partition_point(|f| f.time < current.time - TRAIL_SECONDS);
    let stride = (now - start).div_ceil(TRAIL_SEGMENTS).max(1);
    let mut k = now;
    while k > start {
        let previous = k.saturating_sub(stride).max(start);
        let age = ((current.time - frames[previous].time) / TRAIL_SECONDS).clamp(0.0, 1.0) as f32;
        let alpha = (1.0 - age).powi(2) * 0.9;
        let (a, b) = (frames[previous], frames[k]);
        painter.line_segment(
            [projection.to_screen(a.robot), projection.to_screen(b.robot)],
            Stroke::new(2.5, palette.robot.gamma_multiply(alpha)),
        );
        painter.line_segment(
            [
                projection.to_screen(a.object.position),
                projection.to_screen(b.object.position),
            ],
            Stroke::new(2.0, palette.truth.gamma_multiply(alpha * 0.7)),
        );
        k = previous;
    }
}

/// A metres grid whose spacing follows the zoom: minor lines 20–200 points apart, every tenth
/// major and labelled. Drawn over `area` (the whole scene).
pub fn grid(painter: &egui::Painter, projection: &Projection, area: egui::Rect) {
    let palette = colors::of(painter.ctx());
    let mut spacing = 1e-3_f64;
    while (spacing as f32) * projection.scale() < 20.0 {
        spacing *= 10.0;
    }
    let (lo, hi) = (
        projection.to_world(area.left_bottom()),
        projection.to_world(area.right_top()),
    );
    let label_font = egui::FontId::proportional(10.0);
    for axis in 0..2 {
        let (from, to) = if axis == 0 {
            (lo.x, hi.x)
        } else {
            (lo.y, hi.y)
        };
        let first = (from / spacing).floor() as i64;
        let last = (to / spacing).ceil() as i64;
        if last - first > 400 {
            continue;
        }
        for i in first..=last {
            let value = i as f64 * spacing;
            let major = i.rem_euclid(10) == 0;
            let color = if major {
                palette.grid_major
            } else {
                palette.grid
            };
            let (a, b) = if axis == 0 {
                let x = projection.to_screen(Point2::new(value, 0.0)).x;
                (Pos2::new(x, area.top()), Pos2::new(x, area.bottom()))
            } else {
                let y = projection.to_screen(Point2::new(0.0, value)).y;
                (Pos2::new(area.left(), y), Pos2::new(area.right(), y))
            };
            painter.line_segment([a, b], Stroke::new(1.0, color));
            if major {
                let (pos, align) = if axis == 0 {
                    (
                        Pos2::new(a.x + 3.0, area.bottom() - 3.0),
                        egui::Align2::LEFT_BOTTOM,
                    )
                } else {
                    (
                        Pos2::new(area.right() - 3.0, a.y - 2.0),
                        egui::Align2::RIGHT_BOTTOM,
                    )
                };
                painter.text(
                    pos,
                    align,
                    format_metres(value),
                    label_font.clone(),
                    palette.grid_label,
                );
            }
        }
    }
}

fn format_metres(value: f64) -> String {
    if value.abs() < 1e-12 {
        "0 m".to_owned()
    } else {
        format!("{value:.3} m")
    }
}
