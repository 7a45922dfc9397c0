//! A video file's frames (a LeRobot dataset's `videos/…/*.mp4`), decoded by the `ffmpeg` program
//! when shown.
//!
//! pushlab links no video codec: the decoders LeRobot's files need (AV1, H.264, HEVC) are large C
//! libraries, and a user who records video has `ffmpeg` already or can install it in one command.
//! Without it the recording still opens and plays; each frame then says how to get it.
//!
//! A reader keeps one `ffmpeg` process streaming raw RGB from the frame last asked for, so playing
//! forward decodes each frame once; a jump backward, or further ahead than a few seconds, restarts
//! it at the frame's time (ffmpeg seeks to the key frame before and decodes up to the frame). Memory
//! is one frame and the process's own buffers, whatever the file's length.

use std::ffi::OsString;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::Arc;
use std::thread::JoinHandle;

use super::{EncodedImage, FrameProblem, FrameReader, FrameSource, ImageFormat, RawEncoding};

/// The environment variable naming the `ffmpeg` program, where it is not on the PATH as `ffmpeg`.
pub const FFMPEG_VARIABLE: &str = "PUSHLAB_FFMPEG";

/// How far ahead of the stream's position a frame may be for the stream to decode up to it rather
/// than restart there: about what a restart costs in decoding.
const MAX_FRAMES_SKIPPED: usize = 60;

/// The most of ffmpeg's messages kept for an error: the last, which say why it stopped.
const MAX_MESSAGE_BYTES: usize = 2048;

/// Where the `ffmpeg` program is: `$PUSHLAB_FFMPEG`, else `ffmpeg` on the PATH; else why not, with
/// how to get it.
pub fn find_ffmpeg() -> Result<PathBuf, String> {
    if cfg!(target_arch = "wasm32") {
        return Err(
            "its frames are in a video, which pushlab decodes with the ffmpeg program, and a \
                    browser tab cannot run programs: open the dataset with the desktop app \
                    (pushlab open) to see them"
                .to_owned(),
        );
    }
    locate_ffmpeg(std::env::var_os(FFMPEG_VARIABLE), std::env::var_os("PATH"))
}

/// [`find_ffmpeg`] given the variable's value and the PATH.
fn locate_ffmpeg(variable: Option<OsString>, paths: Option<OsString>) -> Result<PathBuf, String> {
    if let Some(program) = variable {
        let program = PathBuf::from(program);
        return if program.is_file() {
            Ok(program)
        } else {
            Err(format!(
                "{FFMPEG_VARIABLE} names {}, which is not a file",
                program.display()
            ))
        };
    }
    let name = if cfg!(windows) {
        "ffmpeg.exe"
    } else {
        "ffmpeg"
    };
    let on_path = paths.and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join(name))
            .find(|program| program.is_file())
    });
    on_path.ok_or_else(|| {
        "its frames are in a video, and decoding it needs the ffmpeg program, which is not on the \
         PATH: install ffmpeg (apt install ffmpeg, brew install ffmpeg, or ffmpeg.org) and open the \
         dataset again, or set PUSHLAB_FFMPEG to the program"
            .to_owned()
    })
}

/// Frames of one video file: the episode's frame `i` is the frame shown at `file_times_s[i]`
/// seconds into the file, each `width` × `height` pixels.
#[derive(Debug)]
pub struct VideoFrames {
    /// Shared with every reader, which adds only its stream.
    video: Arc<Video>,
}

/// What a reader needs of its file to start a stream.
#[derive(Debug)]
struct Video {
    path: PathBuf,
    width: u32,
    height: u32,
    file_times_s: Vec<f64>,
    /// Half the time between frames: seeking this much before a frame's time finds that frame,
    /// not the next, whatever the rounding of its timestamp.
    half_period_s: f64,
    ffmpeg: Result<PathBuf, String>,
}

impl VideoFrames {
    /// The frames of `path` at `file_times_s` (increasing, one per frame of a constant `fps`),
    /// decoded by `ffmpeg` (see [`find_ffmpeg`]) and scaled to `width` × `height` if the file's
    /// differ.
    pub fn new(
        path: PathBuf,
        (width, height): (u32, u32),
        fps: f64,
        file_times_s: Vec<f64>,
        ffmpeg: Result<PathBuf, String>,
    ) -> Self {
        Self {
            video: Arc::new(Video {
                path,
                width,
                height,
                file_times_s,
                half_period_s: 0.5 / fps,
                ffmpeg,
            }),
        }
    }
}

impl Video {
    fn frame_bytes(&self) -> usize {
        self.width as usize * self.height as usize * 3
    }
}

impl FrameSource for VideoFrames {
    fn reader(&self) -> Box<dyn FrameReader> {
        Box::new(VideoReader {
            video: Arc::clone(&self.video),
            stream: None,
        })
    }

    fn location(&self) -> PathBuf {
        self.video.path.clone()
    }
}

struct VideoReader {
    video: Arc<Video>,
    stream: Option<Decoding>,
}

impl FrameReader for VideoReader {
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem> {
        let program =
            (self.video.ffmpeg.as_ref()).map_err(|why| FrameProblem::Unreadable(why.clone()))?;
        let Some(&time_s) = self.video.file_times_s.get(index) else {
            return Err(FrameProblem::Unreadable(format!(
                "frame {index} is past the video's {} frames",
                self.video.file_times_s.len()
            )));
        };
        let ahead = (self.stream.as_ref())
            .and_then(|stream| index.checked_sub(stream.next_index))
            .filter(|&ahead| ahead <= MAX_FRAMES_SKIPPED);
        let (mut stream, skip) = match (self.stream.take(), ahead) {
            (Some(stream), Some(ahead)) => (stream, ahead),
            _ => (Decoding::start(program, &self.video, time_s, index)?, 0),
        };
        let mut bytes = vec![0; self.video.frame_bytes()];
        for _ in 0..=skip {
            stream.next_frame(&mut bytes, time_s)?;
        }
        self.stream = Some(stream);
        Ok(EncodedImage {
            format: ImageFormat::Raw {
                encoding: RawEncoding::Rgb8,
                width: self.video.width,
                height: self.video.height,
                step: self.video.width * 3,
                big_endian: false,
            },
            bytes,
        })
    }
}

/// One `ffmpeg` process decoding the file from a frame on; killed when dropped.
struct Decoding {
    child: Child,
    stdout: ChildStdout,
    /// What ffmpeg says, read on its own thread (so that a flood of messages never blocks it)
    /// and kept to its last lines, for the error of a frame it could not give.
    said: Option<JoinHandle<String>>,
    path: PathBuf,
    /// The episode's frame the next read gives.
    next_index: usize,
}

impl Decoding {
    fn start(
        program: &Path,
        video: &Video,
        time_s: f64,
        index: usize,
    ) -> Result<Self, FrameProblem> {
        let from_s = (time_s - video.half_period_s).max(0.0);
        let mut child = Command::new(program)
            .args(["-nostdin", "-hide_banner", "-loglevel", "error"])
            .args(["-ss", &format!("{from_s:.6}"), "-i"])
            .arg(&video.path)
            .args(["-map", "0:v:0", "-fps_mode", "passthrough"])
            .args(["-vf", &format!("scale={}:{}", video.width, video.height)])
            .args(["-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| {
                FrameProblem::Unreadable(format!("cannot run {}: {e}", program.display()))
            })?;
        let stdout = child.stdout.take().ok_or_else(|| {
            FrameProblem::Unreadable(format!("{} gave no output", program.display()))
        })?;
        let said = child.stderr.take().map(|mut stderr| {
            #[cfg_attr(
                target_arch = "wasm32",
                expect(
                    clippy::disallowed_methods,
                    reason = "a page cannot run ffmpeg: spawning it fails above"
                )
            )]
            std::thread::spawn(move || {
                let mut said = Vec::new();
                let mut buffer = [0; 4096];
                while let Ok(n @ 1..) = stderr.read(&mut buffer) {
                    said.extend_from_slice(&buffer[..n]);
                    let excess = said.len().saturating_sub(MAX_MESSAGE_BYTES);
                    said.drain(..excess);
                }
                String::from_utf8_lossy(&said).into_owned()
            })
        });
        Ok(Self {
            child,
            stdout,
            said,
            path: video.path.clone(),
            next_index: index,
        })
    }

    /// Reads the next frame into `bytes`; at the file's end or a decoding error, says so with
    /// ffmpeg's own message.
    fn next_frame(&mut self, bytes: &mut [u8], time_s: f64) -> Result<(), FrameProblem> {
        match self.stdout.read_exact(bytes) {
            Ok(()) => {
                self.next_index += 1;
                Ok(())
            }
            Err(_) => {
                let _ = self.child.wait();
                let said = (self.said.take())
                    .and_then(|said| said.join().ok())
                    .unwrap_or_default();
                let said = said.trim();
                Err(FrameProblem::Unreadable(if said.is_empty() {
                    format!(
                        "{} ends before the frame at {time_s:.3} s",
                        self.path.display()
                    )
                } else {
                    format!("ffmpeg cannot decode {}: {said}", self.path.display())
                }))
            }
        }
    }
}

impl Drop for Decoding {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ffmpeg_is_found_on_the_path_or_where_the_variable_says() {
        let dir = std::env::temp_dir().join(format!("pushlab-ffmpeg-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a folder");
        let program = dir.join(if cfg!(windows) {
            "ffmpeg.exe"
        } else {
            "ffmpeg"
        });
        std::fs::write(&program, b"").expect("a file");
        let paths = std::env::join_paths([PathBuf::from("/nowhere"), dir.clone()]).ok();
        assert_eq!(locate_ffmpeg(None, paths.clone()), Ok(program.clone()));
        let named = Some(program.clone().into_os_string());
        assert_eq!(locate_ffmpeg(named, None), Ok(program.clone()));
        let wrong = locate_ffmpeg(Some("/no/such/ffmpeg".into()), paths).expect_err("no file");
        assert_eq!(
            wrong,
            "PUSHLAB_FFMPEG names /no/such/ffmpeg, which is not a file"
        );
        let absent = locate_ffmpeg(None, Some("/nowhere".into())).expect_err("not on the PATH");
        assert!(
            absent.contains("not on the PATH: install ffmpeg (apt install ffmpeg"),
            "{absent}"
        );
        std::fs::remove_dir_all(&dir).expect("cleaned up");
    }
}
