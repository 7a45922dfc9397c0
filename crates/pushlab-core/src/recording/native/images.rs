//! A native set's camera frames: an image sequence per recording, in a folder beside its CSV.
//!
//! ```text
//! push_003.csv
//! push_003.images/frames.csv        time,file       (one camera)
//! push_003.images/000000.jpg …
//! push_004.images/front/frames.csv  (several cameras: one folder each, named by the camera)
//! ```
//!
//! `frames.csv` has the header `time,file`, then one row a frame: the time in seconds on the
//! recording's clock (the CSV's `time` column) and the image's file name in the same folder (JPEG or
//! PNG, told by its first bytes). Rows may come in any order; a frame is read only when shown, so a
//! missing or corrupt image is that frame's error, not the recording's. `pushlab import BAG
//! --camera TOPIC` writes this form, compressed images copied byte for byte and raw ones as PNG.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::error::NativeError;
use crate::atomic_file::write_atomically;
use crate::files;
use crate::recording::camera::{
    CameraStream, EncodedImage, FrameProblem, FrameReader, FrameSource, ImageFormat, sniff,
};

/// The name of the frame list in an image folder.
pub const FRAMES_FILE: &str = "frames.csv";
/// The header of a frame list.
pub const FRAMES_HEADER: &str = "time,file";

/// The image folder of the recording stored in `csv`: `NAME.images` beside `NAME.csv`.
pub fn images_dir(csv: &Path) -> PathBuf {
    let stem = csv
        .file_stem()
        .map_or_else(Default::default, |s| s.to_owned());
    let mut name = stem;
    name.push(".images");
    csv.with_file_name(name)
}

/// The cameras of the recording stored in `csv`: none without an image folder; the folder's own
/// `frames.csv` (a camera named after the recording), and one camera per subfolder with one.
pub fn read_cameras(csv: &Path) -> Result<Vec<CameraStream>, NativeError> {
    let dir = images_dir(csv);
    if !files::is_dir(&dir) {
        return Ok(Vec::new());
    }
    let mut cameras = Vec::new();
    if files::is_file(&dir.join(FRAMES_FILE)) {
        cameras.push(read_camera(&dir, "camera")?);
    }
    let mut subfolders: Vec<PathBuf> = files::read_dir(&dir)
        .map_err(|e| NativeError::io(&dir, e))?
        .into_iter()
        .map(|e| e.path)
        .filter(|p| files::is_file(&p.join(FRAMES_FILE)))
        .collect();
    subfolders.sort();
    for folder in subfolders {
        let name = folder
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        cameras.push(read_camera(&folder, &name)?);
    }
    Ok(cameras)
}

/// The camera whose frame list is in `dir`.
fn read_camera(dir: &Path, name: &str) -> Result<CameraStream, NativeError> {
    let path = dir.join(FRAMES_FILE);
    let text = files::read_to_string(&path).map_err(|e| NativeError::io(&path, e))?;
    let bad = |line: usize, why: String| NativeError::FrameList {
        path: path.clone(),
        line,
        why,
    };
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, header)) if header.trim() == FRAMES_HEADER => {}
        found => {
            return Err(bad(
                1,
                format!(
                    "header is '{}', expected `{FRAMES_HEADER}`",
                    found.map_or("", |(_, h)| h.trim())
                ),
            ));
        }
    }
    let mut frames: Vec<(f64, String)> = Vec::new();
    for (index, line) in lines {
        let line_no = index + 1;
        if line.trim().is_empty() {
            continue;
        }
        let Some((time, file)) = line.split_once(',') else {
            return Err(bad(line_no, format!("'{line}', expected TIME,FILE")));
        };
        let time: f64 = time
            .trim()
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite())
            .ok_or_else(|| {
                bad(
                    line_no,
                    format!("time '{}' is not a finite number", time.trim()),
                )
            })?;
        let file = file.trim();
        if file.is_empty() || file.contains(['/', '\\']) || file == ".." {
            return Err(bad(
                line_no,
                format!("file '{file}', expected a file name in the same folder"),
            ));
        }
        frames.push((time, file.to_owned()));
    }
    frames.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (times, files) = frames.into_iter().unzip();
    let source = Arc::new(FolderFrames {
        dir: dir.to_path_buf(),
        files,
    });
    Ok(CameraStream::new(name.to_owned(), times, source))
}

/// Frames that are files of a folder, in the stream's order.
struct FolderFrames {
    dir: PathBuf,
    files: Vec<String>,
}

impl FrameSource for FolderFrames {
    fn reader(&self) -> Box<dyn FrameReader> {
        Box::new(FolderReader {
            dir: self.dir.clone(),
            files: self.files.clone(),
        })
    }

    fn location(&self) -> PathBuf {
        self.dir.clone()
    }
}

struct FolderReader {
    dir: PathBuf,
    files: Vec<String>,
}

impl FrameReader for FolderReader {
    fn read(&mut self, index: usize) -> Result<EncodedImage, FrameProblem> {
        let name = self
            .files
            .get(index)
            .ok_or_else(|| FrameProblem::Unreadable(format!("there is no frame {index}")))?;
        let path = self.dir.join(name);
        let bytes = files::read(&path)
            .map_err(|e| FrameProblem::Unreadable(format!("{}: {e}", path.display())))?;
        let format = sniff(&bytes).ok_or_else(|| {
            FrameProblem::UnknownEncoding(format!("{name} (neither JPEG nor PNG bytes)"))
        })?;
        Ok(EncodedImage { format, bytes })
    }
}

/// Writes a camera's frames as an image sequence into `dir` (created): each frame's file, then
/// `frames.csv` (atomically, last, so that a folder with a frame list is complete). `frames` gives
/// each frame's time and image; JPEG and PNG bytes are written as they are, named by their order.
pub fn write_camera(
    dir: &Path,
    frames: impl IntoIterator<Item = (f64, EncodedImage)>,
) -> std::io::Result<usize> {
    std::fs::create_dir_all(dir)?;
    let mut list = String::from(FRAMES_HEADER);
    list.push('\n');
    let mut count = 0;
    for (time, image) in frames {
        let extension = match image.format {
            ImageFormat::Jpeg => "jpg",
            ImageFormat::Png => "png",
            ImageFormat::Raw { .. } => {
                return Err(std::io::Error::other(
                    "a raw frame must be encoded as PNG before it is written",
                ));
            }
        };
        let name = format!("{count:06}.{extension}");
        std::fs::write(dir.join(&name), &image.bytes)?;
        list.push_str(&format!("{time},{name}\n"));
        count += 1;
    }
    write_atomically(&dir.join(FRAMES_FILE), list.as_bytes())?;
    Ok(count)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("pushlab-images-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn png(shade: u8) -> EncodedImage {
        let image = ::image::GrayImage::from_pixel(4, 3, ::image::Luma([shade]));
        let mut out = std::io::Cursor::new(Vec::new());
        image.write_to(&mut out, ::image::ImageFormat::Png).unwrap();
        EncodedImage {
            format: ImageFormat::Png,
            bytes: out.into_inner(),
        }
    }

    #[test]
    fn frames_written_read_back_in_time_order_byte_for_byte() {
        let dir = scratch("round-trip");
        let csv = dir.join("push_000.csv");
        let frames = vec![(0.2, png(20)), (0.0, png(0)), (0.1, png(10))];
        assert_eq!(write_camera(&images_dir(&csv), frames.clone()).unwrap(), 3);
        let cameras = read_cameras(&csv).unwrap();
        assert_eq!(cameras.len(), 1);
        let camera = &cameras[0];
        assert_eq!(camera.times(), [0.0, 0.1, 0.2]);
        let mut reader = camera.reader();
        assert_eq!(reader.read(1).unwrap(), frames[2].1, "the frame at 0.1 s");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn a_bad_frame_list_names_its_line_and_a_missing_image_is_that_frames_error() {
        let dir = scratch("bad");
        let csv = dir.join("push_000.csv");
        let images = images_dir(&csv);
        std::fs::create_dir_all(&images).unwrap();
        std::fs::write(
            images.join(FRAMES_FILE),
            "time,file\n0.0,a.png\nnan,b.png\n",
        )
        .unwrap();
        let e = read_cameras(&csv).unwrap_err().to_string();
        assert!(
            e.contains("frames.csv line 3") && e.contains("'nan'"),
            "{e}"
        );
        std::fs::write(images.join(FRAMES_FILE), "time,file\n0.0,gone.png\n").unwrap();
        let camera = read_cameras(&csv).unwrap().remove(0);
        let problem = camera.reader().read(0).unwrap_err().to_string();
        assert!(problem.contains("gone.png"), "{problem}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
