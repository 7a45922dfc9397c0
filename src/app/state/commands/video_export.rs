//! File → Export video of this push…: the render on a worker, its share done and Cancel. The state
//! holds the work only as a job the app's shell hands it (`app::render` drives a state of its own
//! and imports this one, so this module never names it: imports run one way).

use std::path::{Path, PathBuf};

use crate::app::state::job::{Job, JobContext, Polled};

/// The render's work, given its job context: the file written, or why not.
pub type VideoWork = Box<dyn FnOnce(&JobContext) -> Option<Result<PathBuf, String>> + Send>;

/// A video being written: where to, and the job.
pub struct VideoExport {
    path: PathBuf,
    job: Job<Result<PathBuf, String>>,
}

impl VideoExport {
    /// Starts `work` writing `path` off the UI thread.
    pub fn start(path: PathBuf, work: VideoWork) -> Self {
        Self {
            path,
            job: Job::spawn(work),
        }
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The share of the frames written.
    pub fn progress(&self) -> f32 {
        self.job.progress()
    }

    /// How it ended, in a sentence; `None` while it runs.
    pub fn ended(&self) -> Option<String> {
        Some(match self.job.poll() {
            Polled::Running => return None,
            Polled::Done(Ok(path)) => format!("wrote the video of the push to {}", path.display()),
            Polled::Done(Err(why)) => format!("could not write the video: {why}"),
            Polled::Stopped => "the video was stopped: nothing written".to_owned(),
        })
    }

    /// Stops it at its next frame (it leaves no file); what to say.
    pub fn cancel(self) -> String {
        self.job.cancel();
        format!("stopped writing {}: nothing written", self.path.display())
    }
}
