//! A sandbox session kept as a recording set like any other: `setting.json` with the truth written
//! in (the hidden COM offset, `h`, the material, and the mystery's seed and object under
//! `sandbox`), one native CSV per push as it was recorded, and beside each its pusher's path
//! (`push_000.pusher-path.csv`, `t,x,y`), with the object's pose where the push began in the
//! setting's entry (`object_start`). `pushlab eval --carry-theta` on the set gives the θ the
//! session showed; `pushlab simulate --sandbox SEED --object NAME --pointer-path
//! push_000.pusher-path.csv` writes its first push's poses again. Files are written atomically.

use std::path::Path;

use crate::files::write_atomically;
use crate::recording::{Setting, TrajectoryEntry, WriteError, write_set};
use crate::trajectory::Trajectory;

use super::table::Sandbox;

/// The set a session writes (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct SandboxSet {
    pub setting: Setting,
    pub trajectories: Vec<Trajectory>,
    /// Each push's pusher path as `t,x,y` CSV text, by file name.
    pub pusher_paths: Vec<(String, String)>,
}

impl SandboxSet {
    /// The set of `sandbox`'s finished pushes, `recorded` their trajectories as recorded (the
    /// first `sandbox.made().len()` are used).
    pub fn of(sandbox: &Sandbox, recorded: &[Trajectory]) -> Self {
        let mut setting = sandbox.mystery().setting();
        let mut trajectories = Vec::new();
        let mut pusher_paths = Vec::new();
        for (index, (made, trajectory)) in sandbox.made().iter().zip(recorded).enumerate() {
            let file = format!("push_{index:03}.csv");
            let path_file = format!("push_{index:03}.pusher-path.csv");
            let mut extra = serde_json::Map::new();
            extra.insert("pusher_path".into(), path_file.clone().into());
            let start = made.object_start;
            extra.insert(
                "object_start".into(),
                serde_json::json!([start.position.x, start.position.y, start.yaw]),
            );
            setting.trajectories.push(TrajectoryEntry {
                file,
                contact_offset: None,
                push_angle_deg: None,
                extra,
            });
            trajectories.push(trajectory.clone());
            pusher_paths.push((path_file, made.pointer_path().to_csv()));
        }
        Self {
            setting,
            trajectories,
            pusher_paths,
        }
    }

    /// Writes the set into `dir` (made if missing), every file atomically.
    pub fn write(&self, dir: &Path) -> Result<(), WriteError> {
        write_set(dir, &self.setting, &self.trajectories)?;
        for (file, text) in &self.pusher_paths {
            let path = dir.join(file);
            write_atomically(&path, text.as_bytes())
                .map_err(|source| WriteError::Io { path, source })?;
        }
        Ok(())
    }
}
