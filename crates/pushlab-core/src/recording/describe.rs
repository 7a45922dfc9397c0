//! What a push's setting and trajectory entry say about it, side by side for every recording: the
//! object, the surface, the pushed side, where along it and at what angle, and how fast — from the
//! MIT file name's parameters (kept under `mit_*` keys by the importer) or a native set's
//! `setting.json`.

use super::mit_push::{KEY_REP, KEY_SHAPE, KEY_SIDE, KEY_SIDE_POSITION, KEY_SPEED};
use super::{ObjectShape, Recording};

/// The parameters of one push, each `None` where the recording does not say.
#[derive(Clone, Debug, PartialEq)]
pub struct PushParameters {
    /// The object: the MIT shape's name, a box's width × length in millimetres, a polygon's
    /// vertex count (`6-gon`) or a preset's name (`push-t`).
    pub shape: String,
    /// The surface (the setting's material).
    pub surface: Option<String>,
    /// A native set's pushed face (`front`, `left`, …).
    pub side: Option<String>,
    /// A native push's contact offset: metres from the face's middle, positive to the left of the
    /// push direction.
    pub contact_offset: Option<f64>,
    /// The MIT file name's `i`: which side of the shape is pushed (an index into the shape's
    /// sides, not a native face: the two are different things and get different columns).
    pub mit_side: Option<f64>,
    /// The MIT file name's `s`: where along that side the push starts, a fraction 0..1.
    pub mit_position: Option<f64>,
    /// Push angle from the side's normal, degrees.
    pub angle_deg: Option<f64>,
    /// The MIT name's nominal pusher speed, or the pusher's speed over a native push
    /// ([`crate::trajectory::Trajectory::pusher_speed`]), mm/s.
    pub speed_mm_s: Option<f64>,
    /// The MIT name's repetition number.
    pub repetition: Option<u32>,
}

impl PushParameters {
    /// The parameters of `recording`.
    pub fn of(recording: &Recording) -> Self {
        let setting = &recording.setting;
        let entry = recording.entry.as_ref();
        let number = |key: &str| {
            entry
                .and_then(|e| e.extra.get(key))
                .and_then(|v| v.as_f64())
        };
        let shape = match (
            setting.extra.get(KEY_SHAPE).and_then(|v| v.as_str()),
            &setting.object,
        ) {
            (Some(mit), _) => mit.to_owned(),
            (None, ObjectShape::Box { width, length }) => {
                format!("{:.0}×{:.0}", width * 1e3, length * 1e3)
            }
            (None, ObjectShape::Polygon { vertices }) => format!("{}-gon", vertices.len()),
            (None, ObjectShape::Preset(p)) => p.preset.clone(),
        };
        Self {
            shape,
            surface: setting.material.clone(),
            side: setting.push_side.map(|s| s.name().to_owned()),
            contact_offset: entry.and_then(|e| e.contact_offset),
            mit_side: number(KEY_SIDE),
            mit_position: number(KEY_SIDE_POSITION),
            angle_deg: entry.and_then(|e| e.push_angle_deg),
            speed_mm_s: number(KEY_SPEED)
                .or_else(|| recording.trajectory.pusher_speed().map(|v| v * 1e3)),
            repetition: number(KEY_REP).map(|r| r as u32),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::{Path, PathBuf};

    use crate::recording::load_paths;

    fn shared(folder: &str) -> Option<PathBuf> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared")
            .join(folder);
        if crate::files::is_dir(&dir) {
            Some(dir)
        } else {
            eprintln!("skipped: {} is missing", dir.display());
            None
        }
    }

    #[test]
    fn an_mit_file_shows_its_name_parameters() {
        let Some(dir) = shared("mit-push") else {
            return;
        };
        let report = load_paths(&[dir]);
        let rect = report
            .sets
            .iter()
            .flat_map(|s| &s.recordings)
            .find(|r| r.name.contains("rect1"))
            .expect("the rect1 file");
        // motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.800_t=0.349
        let p = PushParameters::of(rect);
        assert_eq!(p.shape, "rect1");
        assert_eq!(p.surface.as_deref(), Some("abs"));
        assert_eq!(p.mit_side, Some(2.0));
        assert_eq!(p.mit_position, Some(0.8));
        // An MIT push has no native face or contact offset: its i and s are not those.
        assert_eq!((p.side, p.contact_offset), (None, None));
        assert!((p.angle_deg.expect("an angle") - 0.349f64.to_degrees()).abs() < 1e-9);
        assert_eq!(p.speed_mm_s, Some(75.0));
    }

    #[test]
    fn a_native_push_shows_its_setting_and_measured_speed() {
        let dir =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample-data/box1-paper-center-left");
        let report = load_paths(&[dir]);
        let set = &report.sets[0];
        let r = &set.recordings[0];
        let p = PushParameters::of(r);
        assert_eq!(p.shape, "300×400");
        assert_eq!(p.surface.as_deref(), Some("paper"));
        assert_eq!(p.side.as_deref(), Some("left"));
        let entry = r.entry.as_ref().expect("listed in setting.json");
        assert_eq!(p.contact_offset, entry.contact_offset);
        assert_eq!((p.mit_side, p.mit_position), (None, None));
        // The sample data pushes at 40 mm/s (sample-data/README.md), with 2 mm tracking noise.
        let speed = p.speed_mm_s.expect("a speed");
        assert!((39.0..41.0).contains(&speed), "{speed} mm/s");
    }
}
