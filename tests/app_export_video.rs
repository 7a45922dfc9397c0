//! File → Export video of this push…: the render on a worker with the push as on screen (here only
//! the COM layer, as the user left the legend), a progress bar and Cancel in the status bar; the
//! file decoded has the frames asked for; Cancel stops it and leaves no file.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::common;

use std::time::{Duration, Instant};

use eframe::egui::Theme;
use egui_kittest::kittest::Queryable;
use image::AnimationDecoder;
use pushlab::app::render::{RenderOptions, SceneFrames, carry_to, work_for};
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, Persisted};

fn options() -> RenderOptions {
    RenderOptions {
        size: [160, 100],
        fps: 10.0,
        frames: Some(0..30),
        ..RenderOptions::default()
    }
}

#[test]
fn a_video_of_the_push_is_written_off_the_ui_thread_with_progress_and_cancel() {
    let dir = common::scratch_dir("export-video");
    let set = common::sample_dir("box1-paper-ur-front");
    let mut state =
        pushlab::app::initial_state(&[set.join("online_000.csv")], Persisted::default());
    let only_com = state.settings().layers.only("com").unwrap();
    state.apply(Command::SetLayers(only_com));
    let mut harness = common::harness(pushlab::app::PushlabApp::new(state), 1.0 / 60.0);

    let gif = dir.join("push.gif");
    let state = &mut harness.state_mut().state;
    let work = work_for(state, gif.clone(), options()).unwrap();
    state.start_video_export(gif.clone(), work);
    harness.run_steps(1);
    assert!(
        harness
            .query_by_label_contains("writing push.gif")
            .is_some(),
        "the status bar's progress bar"
    );
    harness.get_by_label("Cancel");
    let started = Instant::now();
    while harness.state().state.video_export().is_some() {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "the video is written"
        );
        harness.run_steps(1);
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = harness
        .state()
        .state
        .status()
        .unwrap_or_default()
        .to_owned();
    assert_eq!(
        status,
        format!("wrote the video of the push to {}", gif.display())
    );
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&gif).unwrap(),
    ))
    .unwrap();
    let frames: Vec<image::Frame> = decoder.into_frames().collect::<Result<_, _>>().unwrap();
    assert_eq!(
        frames.len(),
        30,
        "30 frames of a 10 Hz push at 10 frames a second"
    );
    // As on screen: the COM layer only, so no footprint's blue or white is drawn, and the COM's
    // orange is.
    let blue = |p: &image::Rgba<u8>| p[2] > 200 && p[0] < 140;
    let orange = |p: &image::Rgba<u8>| p[0] > 215 && (110..190).contains(&p[1]) && p[2] < 90;
    let last = frames.last().unwrap().buffer();
    assert!(last.pixels().any(orange) && !last.pixels().any(blue));

    // Cancel: the render stops at its next frame and writes nothing.
    let mp4 = dir.join("stopped.gif");
    let state = &mut harness.state_mut().state;
    let work = work_for(
        state,
        mp4.clone(),
        RenderOptions {
            frames: None,
            ..options()
        },
    )
    .unwrap();
    state.start_video_export(mp4.clone(), work);
    harness.run_steps(1);
    harness.get_by_label("Cancel").click();
    harness.run_steps(2);
    assert!(harness.state().state.video_export().is_none());
    let status = harness
        .state()
        .state
        .status()
        .unwrap_or_default()
        .to_owned();
    assert_eq!(
        status,
        format!("stopped writing {}: nothing written", mp4.display())
    );
    std::thread::sleep(Duration::from_secs(2));
    assert!(!mp4.exists());
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 1, "only the first video: {left:?}");
    // A name of no video format is said, and nothing starts.
    let state = &harness.state().state;
    let refused = work_for(state, dir.join("push.avi"), options())
        .err()
        .unwrap();
    assert!(refused.contains(".gif, .mp4 or .webm"), "{refused}");
}

/// The COM marker's centroid (the online orange) in the first frame of `gif`, pixels.
fn first_com_marker(gif: &std::path::Path) -> [f32; 2] {
    let file = std::io::BufReader::new(std::fs::File::open(gif).unwrap());
    let decoder = image::codecs::gif::GifDecoder::new(file).unwrap();
    let first = decoder.into_frames().next().unwrap().unwrap();
    let (mut sum, mut n) = ([0.0f32; 2], 0.0f32);
    for (x, y, p) in first.buffer().enumerate_pixels() {
        if p[0] > 215 && (110..190).contains(&p[1]) && p[2] < 90 {
            sum = [sum[0] + x as f32 + 0.5, sum[1] + y as f32 + 0.5];
            n += 1.0;
        }
    }
    assert!(n > 5.0, "the COM marker is drawn");
    [sum[0] / n, sum[1] / n]
}

#[test]
fn a_push_that_carried_theta_on_is_exported_going_on_from_it() {
    let dir = common::scratch_dir("export-video-carried");
    let set = common::sample_dir("box1-paper-ur-front");
    let pushes = [set.join("online_000.csv"), set.join("online_001.csv")];
    let defaults = Persisted::default();
    let persisted = Persisted {
        layers: defaults.layers.only("com").unwrap(),
        carry_theta: true,
        ..defaults
    };
    // The window played online_000 to its end, then showed online_001, which went on from there.
    let mut state = pushlab::app::initial_state(&pushes, persisted);
    assert_eq!(carry_to(&mut state, &pushes[1]).unwrap(), 1);
    let run = state.run().unwrap();
    assert_eq!(run.continued_from(), Some("online_000"));
    let carried = run.theta_at(0).com_offset;
    let theta0 = run.theta0().com_offset;

    // The export's own state, opening the push alone, goes on as the window's run did: θ, and
    // physics alone beside it with its weights, frame for frame.
    let with_carry = || Persisted {
        carry_theta: true,
        ..Persisted::default()
    };
    let mut alone = pushlab::app::initial_state(&pushes[1..], with_carry());
    let mut window_copy = pushlab::app::initial_state(&pushes, with_carry());
    assert_eq!(carry_to(&mut window_copy, &pushes[1]).unwrap(), 1);
    alone.go_on_as(run.carried().expect("carried on"));
    for state in [&mut alone, &mut window_copy] {
        for _ in 0..40 {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
    }
    let (a, w) = (alone.run().unwrap(), window_copy.run().unwrap());
    assert_eq!(a.theta_at(40), w.theta_at(40));
    let beside = |r: &pushlab_core::learn::OnlineRun| r.physics_beside().map(|p| p.theta_at(40));
    assert!(beside(a).is_some());
    assert_eq!(beside(a), beside(w));
    assert_eq!(a.model_weight(), w.model_weight());
    assert_ne!(
        a.model_weight().unwrap().frames()[0].weight,
        pushlab_core::learn::ModelWeight::new(Default::default()).weight(),
        "the weights went on from the push before"
    );

    let gif = dir.join("carried.gif");
    let options = RenderOptions {
        size: [480, 300],
        frames: Some(0..2),
        ..options()
    };
    let work = work_for(&state, gif.clone(), options.clone()).unwrap();
    state.start_video_export(gif.clone(), work);
    let started = Instant::now();
    while state.video_export().is_some() {
        assert!(started.elapsed() < Duration::from_secs(120));
        state.advance(0.0);
        std::thread::sleep(Duration::from_millis(20));
    }
    assert!(gif.exists(), "{:?}", state.status());

    // Where the scene draws either θ's COM at frame 0 in a frame of this size.
    let mut scene = SceneFrames::new(state, options.size, false, Theme::Dark);
    scene.show(0);
    scene.draw();
    let object = scene.state().recording().unwrap().trajectory.frames[0].object;
    let at = |com: [f64; 2]| scene.pixel_of(object.point_in_world(nalgebra::Point2::from(com)));
    let (want, not) = (at(carried), at(theta0));
    let drawn = first_com_marker(&gif);
    let distance =
        |a: [f32; 2], b: [f32; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    assert!(
        distance(want, not) > 4.0,
        "the carried θ {want:?} is not θ_online(0)'s {not:?}"
    );
    assert!(
        distance(drawn, want) <= 2.0,
        "the first frame's COM marker at {drawn:?}, the carried θ's at {want:?} (θ_online(0)'s at {not:?})"
    );
}
