//! A goal's ghost to drag: its centre moves it (keeping its yaw), its knob turns it about its
//! centre. The sandbox's Push to goal and a robot's Drive set their goals so; each says what a new
//! goal means with its own command (`sandbox`, `drive_goal`). Handles are large, for a finger and a
//! projector, as the sandbox's are.

use eframe::egui::{self, Pos2, Stroke};
use nalgebra::Point2;
use pushlab_core::geometry::{Outline, Pose2};

use super::camera::Projection;
use super::plan;
use crate::app::colors;

/// How near a press must be to a handle to grab it, points: a fingertip's reach.
pub const GRIP_RADIUS: f32 = 22.0;

/// How far beyond the object's extent the goal's knob sits, metres.
const KNOB_M: f64 = 0.06;

/// What of a goal is grabbed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GoalGrab {
    /// The ghost, moved keeping its yaw.
    Move { yaw: f64 },
    /// The knob, turning the goal about its centre.
    Turn { centre: Point2<f64> },
}

impl GoalGrab {
    /// The goal (`x, y, yaw`, world frame) a drag of this grab to `pointer` asks for; `None` when
    /// the pointer is on the centre it turns about (no direction).
    pub fn dragged_to(self, pointer: Point2<f64>) -> Option<[f64; 3]> {
        match self {
            Self::Move { yaw } => Some([pointer.x, pointer.y, yaw]),
            Self::Turn { centre } => {
                let d = pointer - centre;
                (d.norm() > 1e-3).then(|| [centre.x, centre.y, d.y.atan2(d.x)])
            }
        }
    }

    /// Whether `self` and `other` grab the same handle (for its highlight).
    fn same_handle(self, other: Self) -> bool {
        std::mem::discriminant(&self) == std::mem::discriminant(&other)
    }
}

/// A goal's handles where the user sees them this frame.
#[derive(Clone, Copy, Debug)]
pub struct GoalHandles {
    pub goal: Pose2,
    pub centre: Pos2,
    pub knob: Pos2,
}

impl GoalHandles {
    /// The handles of `goal` for an object of `outline`: the knob on the goal's x axis, beyond
    /// the outline.
    pub fn of(outline: &Outline, goal: Pose2, projection: &Projection) -> Self {
        let reach = outline.bounding_box().1.x.max(0.05) + KNOB_M;
        let knob = goal.point_in_world(Point2::new(reach, 0.0));
        Self {
            goal,
            centre: projection.to_screen(goal.position),
            knob: projection.to_screen(knob),
        }
    }

    /// What a press at `pointer` grabs: the knob first (it is the smaller target), then the
    /// centre.
    pub fn grab(&self, pointer: Pos2) -> Option<GoalGrab> {
        if pointer.distance(self.knob) < GRIP_RADIUS {
            return Some(GoalGrab::Turn {
                centre: self.goal.position,
            });
        }
        (pointer.distance(self.centre) < GRIP_RADIUS)
            .then_some(GoalGrab::Move { yaw: self.goal.yaw })
    }

    /// The ghost named `label` with its two handles, the one under the pointer (`hot`) bolder.
    pub fn draw(
        &self,
        painter: &egui::Painter,
        projection: &Projection,
        outline: &Outline,
        label: &str,
        hot: Option<GoalGrab>,
    ) {
        let color = colors::of(painter.ctx()).suggestion;
        plan::goal(painter, projection, outline, &self.goal, label);
        let width = |g: GoalGrab| match hot.is_some_and(|h| h.same_handle(g)) {
            true => 3.5,
            false => 2.0,
        };
        let moving = GoalGrab::Move { yaw: 0.0 };
        painter.circle_stroke(self.centre, 9.0, Stroke::new(width(moving), color));
        painter.line_segment(
            [self.centre, self.knob],
            Stroke::new(1.0, color.gamma_multiply(0.6)),
        );
        let turning = GoalGrab::Turn {
            centre: self.goal.position,
        };
        painter.circle(
            self.knob,
            7.0,
            color.gamma_multiply(0.3),
            Stroke::new(width(turning), color),
        );
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn the_knob_turns_the_goal_toward_the_pointer_and_the_centre_moves_it_keeping_its_yaw() {
        let turn = GoalGrab::Turn {
            centre: Point2::new(0.3, 0.1),
        };
        let [x, y, yaw] = turn.dragged_to(Point2::new(0.3, 0.4)).unwrap();
        assert_eq!((x, y), (0.3, 0.1));
        assert!((yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(turn.dragged_to(Point2::new(0.3, 0.1)), None);
        let moving = GoalGrab::Move { yaw: 0.4 };
        assert_eq!(
            moving.dragged_to(Point2::new(-0.2, 0.5)),
            Some([-0.2, 0.5, 0.4])
        );
    }
}
