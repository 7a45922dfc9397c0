//! The sandbox in the scene: what a student grabs and what is drawn for the lesson. The pusher disc
//! to drag (held, it follows the pointer at the pusher's speed), the guess of the centre of mass
//! (a "?" to drag onto the object), an arrow drawn from the outline to make a push, and after the
//! reveal the true COM with the guess's and the model's distance to it. Handles are large, for a
//! finger and a projector. Reads the state's sandbox and sends its commands.

use eframe::egui::{self, Color32, Pos2, Stroke, Vec2};
use nalgebra::Point2;
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::sandbox::push_drawn;

use super::camera::Projection;
use super::goal_handles::GRIP_RADIUS;
use super::goal_handles::{GoalGrab, GoalHandles};
use crate::app::colors;
use crate::app::state::sources::sandbox::SandboxCommand;
use crate::app::state::{AppState, Command};

/// How near the outline a press starts an arrow, points.
pub const OUTLINE_REACH: f32 = 18.0;

/// What of the sandbox can be grabbed this frame, where the user sees it.
#[derive(Clone, Debug)]
pub struct Grips {
    pub pusher: Pos2,
    /// The pusher's radius on screen, points.
    pub pusher_radius: f32,
    pub guess: Pos2,
    pub outline: Outline,
    pub pose: Pose2,
    /// The goal's ghost and its handles.
    pub goal: Option<GoalHandles>,
}

/// What a press in the scene grabs, when the sandbox is shown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Grab {
    Pusher,
    Guess,
    /// An arrow from this world point on the outline.
    Arrow(Point2<f64>),
    /// The goal's ghost or its knob.
    Goal(GoalGrab),
}

impl Grips {
    /// The sandbox's grips, when its object is what the scene shows.
    pub fn of(
        state: &AppState,
        projection: &Projection,
        pose: &Pose2,
        robot: Point2<f64>,
    ) -> Option<Self> {
        let session = state.sandbox().filter(|_| state.sandbox_shown())?;
        let mystery = session.sandbox().mystery();
        let guess = session.guess().map_or_else(
            || mystery.sim.outline.centroid(),
            |[x, y]| Point2::new(x, y),
        );
        Some(Self {
            pusher: projection.to_screen(robot),
            pusher_radius: (mystery.sim.pusher_radius as f32 * projection.scale()).max(3.0),
            guess: projection.to_screen(pose.point_in_world(guess)),
            goal: (session.goal()).map(|g| GoalHandles::of(&mystery.sim.outline, g, projection)),
            outline: mystery.sim.outline.clone(),
            pose: *pose,
        })
    }

    /// What a press at `pointer` grabs: the pusher (anywhere on its disc), the guess, or the start
    /// of an arrow near the outline.
    pub fn grab(&self, pointer: Pos2, projection: &Projection) -> Option<Grab> {
        if pointer.distance(self.pusher) < self.pusher_radius.max(GRIP_RADIUS) {
            return Some(Grab::Pusher);
        }
        if pointer.distance(self.guess) < GRIP_RADIUS {
            return Some(Grab::Guess);
        }
        if let Some(grab) = self.goal.and_then(|g| g.grab(pointer)) {
            return Some(Grab::Goal(grab));
        }
        let world = projection.to_world(pointer);
        let boundary = self
            .outline
            .closest_boundary_point(self.pose.point_in_object(world));
        let reach = f64::from(OUTLINE_REACH / projection.scale());
        (boundary.signed_distance.abs() < reach)
            .then(|| Grab::Arrow(self.pose.point_in_world(boundary.point)))
    }
}

/// The command a drag of `grab` to `pointer` sends while dragging.
pub fn dragged(grab: Grab, pointer: Point2<f64>, pose: &Pose2) -> Option<Command> {
    match grab {
        Grab::Pusher => Some(Command::Sandbox(SandboxCommand::Hold([
            pointer.x, pointer.y,
        ]))),
        Grab::Guess => {
            let at = pose.point_in_object(pointer);
            Some(Command::Sandbox(SandboxCommand::Guess([at.x, at.y])))
        }
        Grab::Goal(grab) => {
            (grab.dragged_to(pointer)).map(|goal| Command::Sandbox(SandboxCommand::SetGoal(goal)))
        }
        Grab::Arrow(_) => None,
    }
}

/// The command letting go of `grab` at `pointer` sends.
pub fn released(
    state: &AppState,
    grab: Grab,
    pointer: Point2<f64>,
    grips: &Grips,
) -> Option<Command> {
    match grab {
        Grab::Pusher => Some(Command::Sandbox(SandboxCommand::Release([
            pointer.x, pointer.y,
        ]))),
        Grab::Guess | Grab::Goal(_) => None,
        Grab::Arrow(from) => Some(
            match push_drawn(&grips.outline, &grips.pose, from, pointer) {
                Some(choice) => Command::Sandbox(SandboxCommand::Push(choice)),
                None if state.sandbox().is_some() => Command::Report(
                    "draw the arrow from the outline into the object, as long as the push"
                        .to_owned(),
                ),
                None => return None,
            },
        ),
    }
}

/// Draws the sandbox's handles and, after the reveal, the truth; `arrow` is the arrow being drawn.
pub fn draw(
    painter: &egui::Painter,
    state: &AppState,
    projection: &Projection,
    grips: &Grips,
    arrow: Option<(Point2<f64>, Point2<f64>)>,
    hot: Option<Grab>,
) {
    let palette = colors::of(painter.ctx());
    let Some(session) = state.sandbox() else {
        return;
    };
    // The pusher's handle: a ring a finger can find.
    let ring = grips.pusher_radius.max(GRIP_RADIUS * 0.6);
    let width = if hot == Some(Grab::Pusher) { 4.0 } else { 2.5 };
    painter.circle_stroke(grips.pusher, ring + 4.0, Stroke::new(width, palette.robot));
    // The guess: a "?" until placed, then a cross in a circle.
    let guess_color = Color32::from_rgb(90, 200, 255);
    let size = if hot == Some(Grab::Guess) { 16.0 } else { 13.0 };
    painter.circle(
        grips.guess,
        size,
        guess_color.gamma_multiply(0.25),
        Stroke::new(2.5, guess_color),
    );
    let label = if session.guess().is_some() { "+" } else { "?" };
    painter.text(
        grips.guess,
        egui::Align2::CENTER_CENTER,
        label,
        egui::FontId::proportional(size * 1.4),
        guess_color,
    );
    goal_and_plan(painter, session, projection, grips, hot);
    if let Some((from, to)) = arrow {
        let (tail, tip) = (projection.to_screen(from), projection.to_screen(to));
        painter.arrow(tail, tip - tail, Stroke::new(4.0, palette.suggestion));
    }
    if let Some(score) = session.score() {
        let truth = projection.to_screen(grips.pose.point_in_world(Point2::from(score.true_com_m)));
        super::draw::true_com(painter, truth);
        let line = |to: Pos2, color: Color32| {
            painter.line_segment([to, truth], Stroke::new(1.5, color.gamma_multiply(0.8)));
        };
        line(grips.guess, guess_color);
        let model =
            projection.to_screen(grips.pose.point_in_world(Point2::from(score.model_com_m)));
        line(model, palette.online);
        painter.text(
            truth + Vec2::new(12.0, -12.0),
            egui::Align2::LEFT_BOTTOM,
            "true COM",
            egui::FontId::proportional(14.0),
            palette.truth,
        );
    }
}

/// The goal's ghost with its handles, and while the controller pushes, the object's predicted
/// arc ahead of it and the pusher's way to its next push.
fn goal_and_plan(
    painter: &egui::Painter,
    session: &crate::app::state::sources::sandbox::SandboxSession,
    projection: &Projection,
    grips: &Grips,
    hot: Option<Grab>,
) {
    if let Some(handles) = grips.goal {
        let hot = match hot {
            Some(Grab::Goal(grab)) => Some(grab),
            _ => None,
        };
        handles.draw(painter, projection, &grips.outline, "goal", hot);
    }
    let Some(driving) = session.driving() else {
        return;
    };
    super::plan::plan(painter, projection, &grips.outline, driving.plan());
}
