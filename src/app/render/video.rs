//! Writing rendered frames as a video: GIF in Rust (the `gif` crate, one palette made for the
//! scene's colours ([`super::palette`]), each frame only what changed since the one before), MP4
//! (H.264) and WebM (VP9)
//! through ffmpeg, the program pushlab already runs for LeRobot videos. Nothing is put under the
//! user's name before the last frame is written — a GIF is kept in memory (a few MB) and written
//! atomically, ffmpeg writes a temporary file beside it that is renamed into place — so a render
//! stopped or failed midway leaves no half-written file.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use anyhow::{Context as _, anyhow, bail};
use gif::{DisposalMethod, Encoder, Frame, Repeat};

use super::palette::{GifPalette, TRANSPARENT};
use crate::app::colors;

/// What the output's extension asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Container {
    Gif,
    Mp4,
    Webm,
}

impl Container {
    /// The container of `path`'s extension; an error names the extensions understood.
    pub fn of(path: &Path) -> anyhow::Result<Self> {
        let extension = (path.extension().and_then(|e| e.to_str()))
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        match extension.as_str() {
            "gif" => Ok(Self::Gif),
            "mp4" => Ok(Self::Mp4),
            "webm" => Ok(Self::Webm),
            _ => bail!(
                "{}: the video's extension says its format: .gif, .mp4 or .webm",
                path.display()
            ),
        }
    }
}

/// A video being written, frame by frame.
pub struct VideoWriter {
    target: PathBuf,
    temporary: PathBuf,
    size: [usize; 2],
    inner: Option<Inner>,
    /// The GIF's last frame, which the next one is drawn over.
    previous: Option<Vec<u8>>,
}

enum Inner {
    /// The encoder (made at the first frame), the delay between frames (hundredths of a second)
    /// and the palette.
    Gif(Option<Box<Encoder<Vec<u8>>>>, u16, Box<GifPalette>),
    Ffmpeg(Child, ChildStdin),
}

impl VideoWriter {
    /// Starts `path` at `size` pixels and `fps` frames a second (GIF keeps whole hundredths of a
    /// second between frames: 30 fps plays at 33).
    /// The GIF's palette is made for `colours`, the theme the frames are drawn in.
    pub fn create(
        path: &Path,
        size: [usize; 2],
        fps: f64,
        colours: &colors::Palette,
    ) -> anyhow::Result<Self> {
        let container = Container::of(path)?;
        // Said before the first frame is drawn, not after the last.
        let folder = (path.parent())
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        if !folder.is_dir() {
            bail!(
                "{}: cannot write: the folder {} does not exist",
                path.display(),
                folder.display()
            );
        }
        let name = path
            .file_name()
            .map_or_else(|| "video".into(), |n| n.to_string_lossy().into_owned());
        let temporary = path.with_file_name(format!(".{name}.{}.part", std::process::id()));
        let inner = match container {
            Container::Gif => {
                let (w, h) = (u16::try_from(size[0]), u16::try_from(size[1]));
                if w.is_err() || h.is_err() {
                    bail!("a GIF is at most 65535 pixels a side");
                }
                let delay = (100.0 / fps).round().clamp(1.0, 65535.0) as u16;
                Inner::Gif(None, delay, Box::new(GifPalette::for_theme(colours)))
            }
            Container::Mp4 | Container::Webm => ffmpeg(container, &temporary, size, fps)?,
        };
        Ok(Self {
            target: path.to_path_buf(),
            temporary,
            size,
            inner: Some(inner),
            previous: None,
        })
    }

    /// Adds one frame, RGBA bytes row by row.
    pub fn push(&mut self, rgba: Vec<u8>) -> anyhow::Result<()> {
        let [w, h] = self.size;
        match self.inner.as_mut() {
            Some(Inner::Gif(encoder, delay, palette)) => {
                let (part, left, top, pw, ph) = changed(self.previous.as_deref(), &rgba, w, h)
                    .ok_or_else(|| anyhow!("a frame of the wrong size"))?;
                if encoder.is_none() {
                    let made = Encoder::new(Vec::new(), w as u16, h as u16, &palette.bytes());
                    let mut made = made?;
                    made.set_repeat(Repeat::Infinite)?;
                    *encoder = Some(Box::new(made));
                }
                self.previous = Some(rgba);
                let indices: Vec<u8> = (part.chunks_exact(4))
                    .map(|p| match p[3] {
                        0 => TRANSPARENT,
                        _ => palette.index_of([p[0], p[1], p[2]]),
                    })
                    .collect();
                let mut frame =
                    Frame::from_indexed_pixels(pw as u16, ph as u16, indices, Some(TRANSPARENT));
                (frame.left, frame.top) = (left as u16, top as u16);
                frame.delay = *delay;
                frame.dispose = DisposalMethod::Keep;
                let encoder = encoder.as_mut().context("no encoder")?;
                encoder
                    .write_frame(&frame)
                    .with_context(|| format!("{}: cannot write", self.target.display()))
            }
            Some(Inner::Ffmpeg(_, stdin)) => stdin
                .write_all(&rgba)
                .context("ffmpeg stopped taking frames"),
            None => bail!("the video is finished"),
        }
    }

    /// Ends the video and puts it under its name.
    pub fn finish(mut self) -> anyhow::Result<PathBuf> {
        match self.inner.take() {
            Some(Inner::Gif(encoder, _, _)) => {
                let bytes = match encoder {
                    Some(encoder) => encoder.into_inner()?,
                    None => bail!("{}: no frame to write", self.target.display()),
                };
                pushlab_core::files::write_atomically(&self.target, &bytes)
                    .with_context(|| format!("{}: cannot write", self.target.display()))?;
                return Ok(self.target.clone());
            }
            Some(Inner::Ffmpeg(child, stdin)) => {
                drop(stdin);
                let output = child.wait_with_output().context("ffmpeg did not end")?;
                if !output.status.success() {
                    bail!(
                        "ffmpeg could not write {}: {}",
                        self.target.display(),
                        String::from_utf8_lossy(&output.stderr).trim()
                    );
                }
            }
            None => {}
        }
        std::fs::rename(&self.temporary, &self.target)
            .with_context(|| format!("{}: cannot write", self.target.display()))?;
        Ok(self.target.clone())
    }
}

impl Drop for VideoWriter {
    /// A video not finished leaves nothing behind.
    fn drop(&mut self) {
        if let Some(Inner::Ffmpeg(mut child, stdin)) = self.inner.take() {
            drop(stdin);
            let _ = child.kill();
            let _ = child.wait();
        }
        let _ = std::fs::remove_file(&self.temporary);
    }
}

/// What a GIF frame must hold to turn `previous` into `rgba` (both `w` × `h`, opaque): the
/// rectangle of the pixels that changed, those that did not made transparent so that the frame
/// before shows through them (a still background then costs next to nothing); a frame like the
/// one before is one transparent pixel. RGBA bytes, left, top, width and height, pixels.
fn changed(
    previous: Option<&[u8]>,
    rgba: &[u8],
    w: usize,
    h: usize,
) -> Option<(Vec<u8>, usize, usize, usize, usize)> {
    if rgba.len() != w * h * 4 {
        return None;
    }
    let Some(previous) = previous.filter(|p| p.len() == rgba.len()) else {
        return Some((rgba.to_vec(), 0, 0, w, h));
    };
    let differs = |x: usize, y: usize| {
        let at = (y * w + x) * 4;
        rgba[at..at + 4] != previous[at..at + 4]
    };
    let (mut x0, mut y0, mut x1, mut y1) = (w, h, 0, 0);
    for y in 0..h {
        for x in 0..w {
            if differs(x, y) {
                (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x + 1), y1.max(y + 1));
            }
        }
    }
    if x0 >= x1 {
        return Some((vec![0; 4], 0, 0, 1, 1));
    }
    let (pw, ph) = (x1 - x0, y1 - y0);
    let mut part = vec![0; pw * ph * 4];
    for y in y0..y1 {
        for x in x0..x1 {
            if differs(x, y) {
                let (from, to) = ((y * w + x) * 4, ((y - y0) * pw + (x - x0)) * 4);
                part[to..to + 4].copy_from_slice(&rgba[from..from + 4]);
            }
        }
    }
    Some((part, x0, y0, pw, ph))
}

/// ffmpeg reading raw RGBA frames on its standard input, writing `temporary` as MP4 (H.264,
/// yuv420p, as every player takes) or WebM (VP9).
fn ffmpeg(
    container: Container,
    temporary: &Path,
    [w, h]: [usize; 2],
    fps: f64,
) -> anyhow::Result<Inner> {
    let program = pushlab_core::recording::camera::find_ffmpeg()
        .map_err(|why| anyhow!("an .mp4 or .webm is written by ffmpeg (a .gif is not): {why}"))?;
    let (format, codec): (&str, &[&str]) = match container {
        Container::Mp4 => (
            "mp4",
            &["-c:v", "libx264", "-preset", "veryfast", "-crf", "20"],
        ),
        _ => (
            "webm",
            &[
                "-c:v",
                "libvpx-vp9",
                "-b:v",
                "0",
                "-crf",
                "33",
                "-deadline",
                "realtime",
                "-cpu-used",
                "8",
                "-row-mt",
                "1",
            ],
        ),
    };
    let mut child = Command::new(&program)
        .args([
            "-y",
            "-loglevel",
            "error",
            "-f",
            "rawvideo",
            "-pix_fmt",
            "rgba",
        ])
        .args([
            "-s",
            &format!("{w}x{h}"),
            "-r",
            &format!("{fps}"),
            "-i",
            "-",
        ])
        .args(codec)
        .args(["-pix_fmt", "yuv420p", "-f", format])
        .arg(temporary)
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .with_context(|| format!("cannot run {}", program.display()))?;
    let stdin = child.stdin.take().context("ffmpeg has no input")?;
    Ok(Inner::Ffmpeg(child, stdin))
}
