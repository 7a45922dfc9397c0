//! Look at simulated pushes: prints a table of a few pushes and writes an SVG of them, the box drawn
//! every second with its COM and the pusher disc, so that the turning direction and the sliding can be
//! judged by eye.
//!
//! ```sh
//! cargo run -p pushlab-core --example sim_plot -- /tmp/pushes.svg
//! ```

use std::fmt::Write as _;

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::recording::PushSide;
use pushlab_core::sim::{PressureModel, PushPlan, Sampling, SimObject, lynch_h, simulate_push};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "pushes.svg".to_owned());
    let outline = Outline::rectangle(0.3, 0.4)?;
    // (title, COM offset, pressure, pusher friction, contact offset, push angle)
    let cases = [
        (
            "right of COM, paper",
            [0.0, 0.0],
            PressureModel::Rim,
            0.45,
            -0.1,
            0.0,
        ),
        (
            "left of COM, paper",
            [0.0, 0.0],
            PressureModel::Rim,
            0.45,
            0.1,
            0.0,
        ),
        (
            "central, COM at UR",
            [0.05, 0.05],
            PressureModel::Rim,
            0.45,
            0.0,
            0.0,
        ),
        (
            "20° angle, plastic",
            [0.0, 0.0],
            PressureModel::Centre,
            0.2,
            0.0,
            20.0,
        ),
    ];
    let (cell, scale) = (600.0, 500.0);
    let mut svg = String::new();
    writeln!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{cell}" style="background:white">"#,
        cell * cases.len() as f64
    )?;
    for (i, (title, com, pressure, friction, offset, angle)) in cases.into_iter().enumerate() {
        let com_offset = Vector2::from(com);
        let object = SimObject {
            outline: outline.clone(),
            com_offset,
            h: lynch_h(&outline, pressure, com_offset, 200)?,
            pusher_radius: 0.175,
            pusher_friction: friction,
        };
        let start = Pose2::new(0.0, 0.0, 0.0);
        let plan = PushPlan {
            side: PushSide::Front,
            contact_offset: offset,
            push_angle_deg: angle,
            speed: 0.04,
            curvature: 0.0,
            approach: 0.02,
        };
        let path = plan.path(&outline, &start, 0.175)?;
        let push = simulate_push(&object, start, &path, &Sampling::default(), None)?;
        let last = push.truth.frames.last().ok_or("empty push")?;
        println!(
            "{title:>22}: h = {:.4} m, end pose x {:+.3} y {:+.3} θ {:+.1}°, sliding {:.0} %",
            object.h,
            last.object.position.x,
            last.object.position.y,
            last.object.yaw.to_degrees(),
            100.0 * push.sliding_fraction
        );
        // World (x right, y up) to SVG (y down), each case in its own cell.
        let to_svg = |p: Point2<f64>| {
            (
                i as f64 * cell + 0.35 * cell + p.x * scale,
                0.5 * cell - p.y * scale,
            )
        };
        writeln!(
            svg,
            r#"<text x="{}" y="20" font-size="16">{title}</text>"#,
            i as f64 * cell + 10.0
        )?;
        for (k, frame) in push.truth.frames.iter().enumerate().step_by(10) {
            let shade = 200 - (k * 2).min(200);
            let points: Vec<String> = outline
                .vertices()
                .iter()
                .map(|v| {
                    let (x, y) = to_svg(frame.object.point_in_world(*v));
                    format!("{x:.1},{y:.1}")
                })
                .collect();
            writeln!(
                svg,
                r#"<polygon points="{}" fill="none" stroke="rgb({shade},{shade},255)"/>"#,
                points.join(" ")
            )?;
            let (cx, cy) = to_svg(frame.object.point_in_world(Point2::from(com_offset)));
            writeln!(
                svg,
                r#"<circle cx="{cx:.1}" cy="{cy:.1}" r="3" fill="red"/>"#
            )?;
            let (rx, ry) = to_svg(frame.robot);
            writeln!(
                svg,
                r#"<circle cx="{rx:.1}" cy="{ry:.1}" r="{:.1}" fill="none" stroke="rgb(255,{shade},0)"/>"#,
                0.175 * scale
            )?;
        }
    }
    svg.push_str("</svg>\n");
    std::fs::write(&out, svg)?;
    println!("wrote {out}");
    Ok(())
}
