//! File → Export video of this push…: the render on a worker, its share done and Cancel. The state
//! holds the work only as a job the app's shell hands it (`app::render` drives a state of its own
//! and imports this one, so this module never names it: imports run one way).

use std::path::{Path, PathBuf};

use super::AppState;
use super::job::{Job, JobContext, Polled};

/// The render's work, given its job context: the file written, or why not.
pub type VideoWork = Box<dyn FnOnce(&JobContext) -> Option<Result<PathBuf, String>> + Send>;

/// A video being written: where to, and the job.
pub struct VideoExport {
    path: PathBuf,
    job: Job<Result<PathBuf, String>>,
}

impl AppState {
    /// Starts writing a video of the push shown to `path` by `work` off the UI thread; one at a
    /// time (a second replaces the first, which stops and writes nothing).
    pub fn start_video_export(&mut self, path: PathBuf, work: VideoWork) {
        self.status = Some(format!(
            "writing a video of the push to {}…",
            path.display()
        ));
        self.video_export = Some(VideoExport {
            path,
            job: Job::spawn(work),
        });
    }

    /// The video being written and the share done.
    pub fn video_export(&self) -> Option<(&Path, f32)> {
        (self.video_export.as_ref()).map(|v| (v.path.as_path(), v.job.progress()))
    }

    /// Takes the video's end, said on the status line. Returns whether one is still being written.
    pub(super) fn poll_video_export(&mut self) -> bool {
        let Some(export) = &self.video_export else {
            return false;
        };
        let said = match export.job.poll() {
            Polled::Running => return true,
            Polled::Done(Ok(path)) => format!("wrote the video of the push to {}", path.display()),
            Polled::Done(Err(why)) => format!("could not write the video: {why}"),
            Polled::Stopped => "the video was stopped: nothing written".to_owned(),
        };
        self.status = Some(said);
        self.video_export = None;
        false
    }

    /// Cancel: the render stops at its next frame and leaves no file.
    pub(super) fn cancel_video_export(&mut self) -> String {
        match self.video_export.take() {
            Some(export) => {
                export.job.cancel();
                format!("stopped writing {}: nothing written", export.path.display())
            }
            None => "no video is being written".to_owned(),
        }
    }
}
