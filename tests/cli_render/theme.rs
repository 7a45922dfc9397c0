//! `pushlab render --theme light`: the app's light colours, in the same places as the dark ones.

use eframe::egui::{Color32, Theme};
use nalgebra::Point2;
use pushlab::app::colors::LIGHT;
use pushlab::app::render::{SceneFrames, frames_shown};

use super::cli_common::{pushlab, temp_dir};
use super::{SIZE, centroid, distance, eval_com, gif_frames, recording, rgb_of, state};

/// Pixels within a small distance of `colour` (the GIF's palette holds it exactly).
fn near(colour: Color32) -> impl Fn([u8; 3]) -> bool {
    move |[r, g, b]: [u8; 3]| {
        u32::from(r.abs_diff(colour.r()))
            + u32::from(g.abs_diff(colour.g()))
            + u32::from(b.abs_diff(colour.b()))
            <= 40
    }
}

#[test]
fn a_light_render_draws_the_apps_light_colours_in_the_same_places() {
    let dir = temp_dir("render", "light");
    let out = dir.join("light.gif");
    let run = pushlab(&[
        "render",
        recording().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "320x200",
        "--fps",
        "10",
        "--frames",
        "10..13",
        "--layers",
        "com",
        "--theme",
        "light",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let frames = gif_frames(&out);
    let mut scene = SceneFrames::new(state(), SIZE, false, Theme::Light);
    scene.show(10);
    scene.draw();
    let trajectory = scene.state().recording().unwrap().trajectory.clone();
    // The recording frame each video frame shows (the dark test checks the count and timing).
    let times: Vec<f64> = trajectory.frames.iter().map(|f| f.time).collect();
    let shown = frames_shown(&times, 10..13, 10.0, 1.0);
    assert_eq!(frames.len(), shown.len());
    assert!(frames.len() >= 2);
    let com = eval_com(&dir);
    for (i, frame) in frames.iter().enumerate() {
        let (k, rgb) = (shown[i], rgb_of(frame));
        // Mostly the light background: the scene is paper, not the screen's near-black.
        let (_, paper) = centroid(&rgb, SIZE[0], near(LIGHT.background));
        assert!(
            paper > SIZE[0] * SIZE[1] * 7 / 10,
            "frame {i}: {paper} pixels of paper"
        );
        // The pusher's ring in the light theme's dark yellow, where the recording puts it.
        let (pusher, n) = centroid(&rgb, SIZE[0], near(LIGHT.robot));
        let want = scene.pixel_of(trajectory.frames[k].robot);
        assert!(n > 10, "frame {i}: the pusher's ring is drawn");
        assert!(
            distance(pusher, want) <= 2.0,
            "frame {i}: {pusher:?} against {want:?}"
        );
        // The COM marker in the light orange, where eval puts θ.
        let object = trajectory.frames[k].object;
        let want = scene.pixel_of(object.point_in_world(Point2::from(com[k])));
        let (marker, n) = centroid(&rgb, SIZE[0], near(LIGHT.online));
        assert!(n > 10, "frame {i}: the COM marker is drawn");
        assert!(
            distance(marker, want) <= 2.0,
            "frame {i}: {marker:?} against {want:?}"
        );
    }
    let run = pushlab(&[
        "render",
        recording().to_str().unwrap(),
        "--out",
        "x.gif",
        "--theme",
        "sepia",
    ]);
    assert!(
        run.stderr.contains("\"sepia\": expected dark or light"),
        "{}",
        run.stderr
    );
    let _ = std::fs::remove_dir_all(&dir);
}
