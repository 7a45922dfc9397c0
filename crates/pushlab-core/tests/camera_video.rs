//! Video files as cameras, decoded by ffmpeg: a lossless video of frames with known pixels, written
//! here by ffmpeg itself, reads back exactly — played forward, stepped ahead, jumped back and
//! started mid-file (an episode's frames within a longer file, as LeRobot v3.0 packs them). Without
//! ffmpeg each frame says how to get it; past the file's end a frame says so.
//!
//! The tests that need ffmpeg skip with a message when it is not on the PATH (`scripts/test`
//! installs it on a fresh machine).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::skip;
use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::Arc;

use pushlab_core::recording::camera::{
    CameraStream, EncodedImage, FrameProblem, VideoFrames, decode, find_ffmpeg,
};

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;
const FPS: f64 = 10.0;
const FRAMES: usize = 40;

/// Frame `i`'s pixels: a colour that names the frame, and a gradient that names the pixel.
fn pixels(i: usize) -> Vec<u8> {
    let mut rgb = Vec::with_capacity((WIDTH * HEIGHT * 3) as usize);
    for y in 0..HEIGHT as usize {
        for x in 0..WIDTH as usize {
            rgb.extend_from_slice(&[(i * 6) as u8, (x * 7) as u8, (y * 9 + i) as u8]);
        }
    }
    rgb
}

/// A lossless H.264 (RGB) MP4 of [`FRAMES`] frames at [`FPS`], with a key frame every 16 frames so
/// that seeking lands between key frames; or none, with a message, without ffmpeg.
fn video(name: &str) -> Option<PathBuf> {
    let Ok(ffmpeg) = find_ffmpeg() else {
        skip::skip("ffmpeg on the PATH (apt install ffmpeg)");
        return None;
    };
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("camera_video");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    let mut child = Command::new(ffmpeg)
        .args([
            "-y",
            "-loglevel",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgb24",
        ])
        .args(["-s", &format!("{WIDTH}x{HEIGHT}"), "-r", "10", "-i", "-"])
        .args(["-c:v", "libx264rgb", "-qp", "0", "-g", "16", "-bf", "2"])
        .arg(&path)
        .stdin(Stdio::piped())
        .spawn()
        .expect("run ffmpeg");
    let mut stdin = child.stdin.take().unwrap();
    for i in 0..FRAMES {
        stdin.write_all(&pixels(i)).unwrap();
    }
    drop(stdin);
    assert!(child.wait().unwrap().success(), "ffmpeg wrote the video");
    Some(path)
}

fn stream(path: PathBuf, first: usize, count: usize) -> CameraStream {
    let file_times: Vec<f64> = (first..first + count).map(|i| i as f64 / FPS).collect();
    let times = (0..count).map(|i| i as f64 / FPS).collect();
    let frames = VideoFrames::new(path, (WIDTH, HEIGHT), FPS, file_times, find_ffmpeg());
    CameraStream::new("observation.image".into(), times, Arc::new(frames))
}

fn rgb_of(image: &EncodedImage) -> Vec<u8> {
    let rgba = decode(image).expect("decodes");
    assert_eq!((rgba.width, rgba.height), (WIDTH, HEIGHT));
    rgba.pixels
        .chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

#[test]
fn a_videos_frames_read_back_exactly_forward_ahead_and_back() {
    let Some(path) = video("forward.mp4") else {
        return;
    };
    let stream = stream(path, 0, FRAMES);
    let mut reader = stream.reader();
    for i in 0..FRAMES {
        let image = reader.read(i).unwrap();
        assert_eq!(rgb_of(&image), pixels(i), "frame {i} played forward");
    }
    for i in [3, 30, 31, 35, 2, 17, 16, 39, 0] {
        let image = reader.read(i).unwrap();
        assert_eq!(rgb_of(&image), pixels(i), "frame {i} after a jump");
    }
}

#[test]
fn an_episode_within_a_longer_video_starts_at_its_own_first_frame() {
    let Some(path) = video("packed.mp4") else {
        return;
    };
    // Frames 21..33 of the file are this episode's 0..12, as LeRobot v3.0 packs episodes.
    let stream = stream(path, 21, 12);
    let mut reader = stream.reader();
    for i in [0, 1, 2, 11, 5] {
        let image = reader.read(i).unwrap();
        assert_eq!(rgb_of(&image), pixels(21 + i), "episode frame {i}");
    }
    let past = reader.read(12).unwrap_err();
    assert!(
        past.to_string().contains("past the video's 12 frames"),
        "{past}"
    );
}

#[test]
fn a_frame_past_the_files_end_says_the_file_ends() {
    let Some(path) = video("short.mp4") else {
        return;
    };
    // The stream claims ten frames more than the file holds.
    let stream = stream(path.clone(), 30, 20);
    let mut reader = stream.reader();
    assert_eq!(rgb_of(&reader.read(9).unwrap()), pixels(39));
    let FrameProblem::Unreadable(why) = reader.read(10).unwrap_err() else {
        panic!("an unreadable frame");
    };
    assert!(
        why.contains(&path.display().to_string())
            && why.contains("ends before the frame at 4.000 s"),
        "{why}"
    );
}

#[test]
fn without_ffmpeg_each_frame_says_how_to_get_it() {
    let missing = Err("decoding it needs the ffmpeg program, which is not on the PATH".to_owned());
    let frames = VideoFrames::new(
        "episode.mp4".into(),
        (WIDTH, HEIGHT),
        FPS,
        vec![0.0],
        missing,
    );
    let stream = CameraStream::new("cam".into(), vec![0.0], Arc::new(frames));
    let why = stream.reader().read(0).unwrap_err().to_string();
    assert!(why.contains("needs the ffmpeg program"), "{why}");
}

#[test]
fn a_file_ffmpeg_cannot_read_is_an_error_with_ffmpegs_words() {
    if find_ffmpeg().is_err() {
        skip::skip("ffmpeg on the PATH (apt install ffmpeg)");
        return;
    }
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("camera_video");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("not-a-video.mp4");
    std::fs::write(&path, b"these bytes are no video").unwrap();
    let stream = stream(path.clone(), 0, 3);
    let why = stream.reader().read(0).unwrap_err().to_string();
    assert!(
        why.contains("ffmpeg cannot decode") && why.contains("not-a-video.mp4"),
        "{why}"
    );
}
