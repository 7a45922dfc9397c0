//! The dataset's objects (outlines from the shape data shipped with pushlab) and the setting that
//! the pushes of one surface and shape share, with each push's name parameters kept under `mit_*`
//! keys of its trajectory entry.

use std::collections::HashMap;
use std::sync::{Arc, OnceLock};

use nalgebra::Vector2;
use serde::Deserialize;

use super::problem::MitProblem;
use super::{MitPush, PUSHER_FRICTION, PUSHER_RADIUS, RESAMPLE_HZ};
use crate::geometry::Outline;
use crate::recording::{ObjectShape, Recording, Setting, TrajectoryEntry};

/// One of the dataset's objects, from the shape data shipped with pushlab.
#[derive(Clone, Debug)]
pub struct MitShape {
    /// Outline in pushlab's convention: centred on the footprint's geometric centre.
    pub outline: Outline,
    /// Where that centre lies in the dataset's object frame.
    pub centroid_in_mit_frame: Vector2<f64>,
    /// COM − geometric centre, object frame, when the dataset gives the COM.
    pub com_offset: Option<[f64; 2]>,
}

#[derive(Deserialize)]
struct ShapeFile {
    shapes: HashMap<String, ShapeFact>,
}

#[derive(Deserialize)]
struct ShapeFact {
    vertices: Vec<[f64; 2]>,
    com: Option<[f64; 2]>,
}

/// Outlines of the eleven objects (see `data/derive_mit_shapes.py` for how they were derived).
const SHAPES_JSON: &str = include_str!("../../../data/mit_shapes.json");

/// The shape called `name` (rect1..3, tri1..3, ellip1..3, hex, butter).
pub fn shape(name: &str) -> Result<MitShape, MitProblem> {
    static SHAPES: OnceLock<HashMap<String, MitShape>> = OnceLock::new();
    let shapes = SHAPES.get_or_init(|| {
        // The file is ours and checked by a test; a broken one leaves every shape unknown.
        let file: ShapeFile = serde_json::from_str(SHAPES_JSON).unwrap_or(ShapeFile {
            shapes: HashMap::new(),
        });
        file.shapes
            .into_iter()
            .filter_map(|(name, fact)| {
                let in_mit_frame = Outline::try_from(fact.vertices).ok()?;
                let c = in_mit_frame.centroid().coords;
                let centred: Vec<[f64; 2]> = in_mit_frame
                    .vertices()
                    .iter()
                    .map(|v| [v.x - c.x, v.y - c.y])
                    .collect();
                let outline = Outline::try_from(centred).ok()?;
                let com_offset = fact.com.map(|com| [com[0] - c.x, com[1] - c.y]);
                Some((
                    name,
                    MitShape {
                        outline,
                        centroid_in_mit_frame: c,
                        com_offset,
                    },
                ))
            })
            .collect()
    });
    shapes
        .get(name)
        .cloned()
        .ok_or_else(|| MitProblem::UnknownShape(name.to_string()))
}

/// The setting shared by every push of one surface and shape; the pushes (file name, push) are
/// listed as its trajectories.
pub(crate) fn setting_for(
    surface: &str,
    shape_name: &str,
    pushes: &[(&str, &MitPush)],
) -> Result<Setting, MitProblem> {
    let shape = shape(shape_name)?;
    let vertices = shape
        .outline
        .vertices()
        .iter()
        .map(|v| [v.x, v.y])
        .collect();
    let mut extra = serde_json::Map::new();
    extra.insert("source".into(), "MIT Push Dataset".into());
    extra.insert(KEY_SHAPE.into(), shape_name.into());
    Ok(Setting {
        name: format!("mit-{surface}-{shape_name}"),
        object: ObjectShape::Polygon { vertices },
        pusher_radius: PUSHER_RADIUS,
        material: Some(surface.to_string()),
        floor_friction: None,
        pusher_friction: Some(PUSHER_FRICTION),
        com_offset: shape.com_offset,
        h: None,
        push_side: None,
        sample_rate_hz: Some(RESAMPLE_HZ),
        trajectories: pushes
            .iter()
            .map(|(file, push)| entry_for(file, push))
            .collect(),
        extra,
    })
}

/// Key of a trajectory entry's MIT side index (the dataset's `i`).
pub const KEY_SIDE: &str = "mit_side";
/// Key of a trajectory entry's position along the MIT side, 0..1 (the dataset's `s`).
pub const KEY_SIDE_POSITION: &str = "mit_side_position";
/// Key of a trajectory entry's nominal pusher speed, mm/s (the dataset's `v`).
pub const KEY_SPEED: &str = "mit_speed_mm_s";
/// Key of a trajectory entry's repetition number, when the file name has one.
pub const KEY_REP: &str = "mit_rep";
/// Key of a setting's MIT shape name (`rect1`, `hex`…).
pub const KEY_SHAPE: &str = "mit_shape";

/// The trajectory entry of one push: the push angle in degrees, the rest of the name's parameters
/// under `mit_*` keys (the dataset's side index and side position do not map onto pushlab's four
/// box faces, so they are kept as given).
fn entry_for(file: &str, push: &MitPush) -> TrajectoryEntry {
    let n = &push.name;
    let mut extra = serde_json::Map::new();
    extra.insert(KEY_SIDE.into(), n.side.into());
    extra.insert(KEY_SIDE_POSITION.into(), n.side_position.into());
    extra.insert(KEY_SPEED.into(), n.speed_mm_s.into());
    extra.insert("mit_accel_mm_s2".into(), n.accel_mm_s2.into());
    if let Some(rep) = n.rep {
        extra.insert(KEY_REP.into(), rep.into());
    }
    extra.insert("mit_start_unix_s".into(), push.start_unix_s.into());
    TrajectoryEntry {
        file: file.to_string(),
        contact_offset: None,
        push_angle_deg: Some(n.angle_rad.to_degrees()),
        extra,
    }
}

/// Turns imported pushes of one surface and shape into recordings sharing one setting.
pub(crate) fn recordings_for(
    surface: &str,
    shape_name: &str,
    pushes: Vec<(std::path::PathBuf, MitPush)>,
) -> Result<(Arc<Setting>, Vec<Recording>), MitProblem> {
    let names: Vec<String> = pushes
        .iter()
        .map(|(p, _)| {
            p.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        })
        .collect();
    let listed: Vec<(&str, &MitPush)> = names
        .iter()
        .map(String::as_str)
        .zip(pushes.iter().map(|(_, p)| p))
        .collect();
    let setting = Arc::new(setting_for(surface, shape_name, &listed)?);
    let recordings = pushes
        .into_iter()
        .enumerate()
        .map(|(i, (path, push))| Recording {
            name: crate::recording::native::file_stem(&path),
            source: path,
            setting: Arc::clone(&setting),
            entry: setting.trajectories.get(i).cloned(),
            trajectory: Arc::new(push.trajectory),
            warnings: push.warnings,
            notes: push.notes,
            cameras: Vec::new(),
        })
        .collect();
    Ok((setting, recordings))
}
