//! `setting.json`: what a recording set is about — the object, the pusher, the material and, when
//! known, the true COM offset and `h`.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::geometry::{Outline, OutlineError};

/// The object's footprint as written in `setting.json`: `{"shape": "box", "width": W, "length":
/// L}`, `{"shape": "polygon", "vertices": [[x, y], …]}` or `{"shape": "preset", "preset": "push-t",
/// "metres_per_px": 0.001}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum ObjectShape {
    /// A box centred on the object frame: `width` along the object's x axis, `length` along y, metres.
    Box { width: f64, length: f64 },
    /// A simple polygon (convex or not; it must not touch or cross itself), vertices
    /// counter-clockwise in the object frame, metres. The object frame's origin should be its area
    /// centroid: pushlab reports COM offsets from the origin.
    Polygon { vertices: Vec<[f64; 2]> },
    /// A named outline (boxed: a setting stays as small as with a polygon's vertex list).
    Preset(Box<ShapePreset>),
}

/// A named outline (one of [`crate::geometry::PRESET_NAMES`]) in its own units scaled to metres:
/// `push-t` is gym-pusht's T in pixels (see [`crate::geometry::PushT`] for its frame).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapePreset {
    /// The preset's name.
    pub preset: String,
    /// Metres per unit of the preset (per pixel for `push-t`); 0.001 unless given.
    #[serde(default = "default_metres_per_px")]
    pub metres_per_px: f64,
}

impl ShapePreset {
    /// A preset shape, boxed into an [`ObjectShape`].
    pub fn shape(preset: impl Into<String>, metres_per_px: f64) -> ObjectShape {
        ObjectShape::Preset(Box::new(Self {
            preset: preset.into(),
            metres_per_px,
        }))
    }
}

fn default_metres_per_px() -> f64 {
    crate::geometry::PushT::DEFAULT_METRES_PER_PX
}

impl ObjectShape {
    /// The outline of the footprint, checked to be a simple counter-clockwise polygon.
    pub fn outline(&self) -> Result<Outline, OutlineError> {
        match self {
            ObjectShape::Box { width, length } => Outline::rectangle(*width, *length),
            ObjectShape::Polygon { vertices } => Outline::try_from(vertices.clone()),
            ObjectShape::Preset(p) => Outline::preset(&p.preset, p.metres_per_px),
        }
    }

    /// The JSON path of the field `error` (from [`ObjectShape::outline`]) is about, below the
    /// object's own key: `vertices` for a polygon's outline, `preset` or `metres_per_px` for a preset,
    /// nothing for a box (its message names width and length).
    pub fn field_of(&self, error: &OutlineError) -> Option<&'static str> {
        match (self, error) {
            (ObjectShape::Box { .. }, _) => None,
            (ObjectShape::Polygon { .. }, _) => Some("vertices"),
            (ObjectShape::Preset(_), OutlineError::BadScale(_)) => Some("metres_per_px"),
            (ObjectShape::Preset(_), _) => Some("preset"),
        }
    }

    /// What an outline of this shape was expected to be, for an error of [`ObjectShape::outline`]
    /// to add: a polygon's errors say what is wrong with its vertices; a box's and a preset's say
    /// what was expected themselves (`None`).
    pub fn outline_expected(&self) -> Option<&'static str> {
        match self {
            ObjectShape::Polygon { .. } => Some("a simple counter-clockwise outline"),
            ObjectShape::Box { .. } | ObjectShape::Preset(_) => None,
        }
    }
}

/// A box's footprint as a command line writes it, `WIDTHxLENGTH` in metres (`0.3x0.4`): width along
/// the object's x axis, length along y. Parsed here so that every tool reads it alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxSize {
    pub width: f64,
    pub length: f64,
}

impl From<BoxSize> for ObjectShape {
    fn from(size: BoxSize) -> Self {
        ObjectShape::Box {
            width: size.width,
            length: size.length,
        }
    }
}

/// Text that is not a [`BoxSize`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BoxSizeError {
    #[error("expected WIDTHxLENGTH in metres, e.g. 0.3x0.4, found '{0}'")]
    NotWidthByLength(String),
    #[error("the {side} '{found}' is not a number of metres above 0")]
    NotPositive { side: &'static str, found: String },
}

impl FromStr for BoxSize {
    type Err = BoxSizeError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let (width, length) = text
            .split_once(['x', 'X'])
            .ok_or_else(|| BoxSizeError::NotWidthByLength(text.to_owned()))?;
        let metres = |side: &'static str, part: &str| match part.trim().parse::<f64>() {
            Ok(m) if m.is_finite() && m > 0.0 => Ok(m),
            _ => Err(BoxSizeError::NotPositive {
                side,
                found: part.trim().to_owned(),
            }),
        };
        Ok(Self {
            width: metres("width", width)?,
            length: metres("length", length)?,
        })
    }
}

/// Which face of the object the pusher pushes on.
///
/// `Front` is the face at −x pushed toward +x; `Left` is the face at +y pushed toward −y; `Back` and
/// `Right` are their opposites.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PushSide {
    Front,
    Left,
    Back,
    Right,
}

impl PushSide {
    /// All sides, in the order front, left, back, right.
    pub const ALL: [PushSide; 4] = [
        PushSide::Front,
        PushSide::Left,
        PushSide::Back,
        PushSide::Right,
    ];

    /// The direction of a straight push on this side, object frame (unit vector).
    pub fn push_direction(self) -> [f64; 2] {
        match self {
            PushSide::Front => [1.0, 0.0],
            PushSide::Left => [0.0, -1.0],
            PushSide::Back => [-1.0, 0.0],
            PushSide::Right => [0.0, 1.0],
        }
    }

    /// The lowercase name used in files.
    pub fn name(self) -> &'static str {
        match self {
            PushSide::Front => "front",
            PushSide::Left => "left",
            PushSide::Back => "back",
            PushSide::Right => "right",
        }
    }
}

/// A name that is not a [`PushSide`]'s.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("'{0}' is not a side, expected one of: {names}", names = PushSide::ALL.map(PushSide::name).join(", "))]
pub struct UnknownSide(pub String);

impl FromStr for PushSide {
    type Err = UnknownSide;

    /// The side of this [`PushSide::name`].
    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|side| side.name() == name)
            .ok_or_else(|| UnknownSide(name.to_owned()))
    }
}

/// One trajectory listed in `setting.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryEntry {
    /// CSV file name, relative to the set's folder.
    pub file: String,
    /// Where along the pushed face the push started, metres from the face's middle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_offset: Option<f64>,
    /// Angle of the push from the face normal, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub push_angle_deg: Option<f64>,
    /// Keys pushlab does not know: kept so that a rewrite never loses them.
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

/// The contents of `setting.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Setting {
    /// Name of the setting, e.g. "box1-paper-center-front".
    pub name: String,
    /// The object's footprint.
    pub object: ObjectShape,
    /// Radius of the pusher disc, metres.
    pub pusher_radius: f64,
    /// Free-text name of the floor/object material pair.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// Floor friction coefficient, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor_friction: Option<f64>,
    /// Pusher–object friction coefficient, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pusher_friction: Option<f64>,
    /// True COM − geometric centre in the object frame, metres; `None` when unknown.
    #[serde(default)]
    pub com_offset: Option<[f64; 2]>,
    /// True `h` of Lynch's model, metres; `None` when unknown.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub h: Option<f64>,
    /// The pushed face, when all trajectories of the set push the same one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub push_side: Option<PushSide>,
    /// Nominal sampling rate, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample_rate_hz: Option<f64>,
    /// The trajectories of the set, in order.
    #[serde(default)]
    pub trajectories: Vec<TrajectoryEntry>,
    /// Keys pushlab does not know: kept so that a rewrite never loses them.
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

impl Setting {
    /// A setting that knows only its object and pusher radius: material, friction, COM, `h`, side
    /// and rate unknown, no trajectories (an object entered by hand, a test's).
    pub fn of_object(name: impl Into<String>, object: ObjectShape, pusher_radius: f64) -> Self {
        Self {
            name: name.into(),
            object,
            pusher_radius,
            material: None,
            floor_friction: None,
            pusher_friction: None,
            com_offset: None,
            h: None,
            push_side: None,
            sample_rate_hz: None,
            trajectories: Vec::new(),
            extra: serde_json::Map::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sides_and_box_sizes_parse_and_refusals_name_what_is_accepted() {
        for side in PushSide::ALL {
            assert_eq!(side.name().parse(), Ok(side));
        }
        assert_eq!(
            "up".parse::<PushSide>().map_err(|e| e.to_string()),
            Err("'up' is not a side, expected one of: front, left, back, right".to_owned())
        );
        assert_eq!(
            "0.3x0.4".parse(),
            Ok(BoxSize {
                width: 0.3,
                length: 0.4
            })
        );
        assert_eq!(
            " 0.3 X 0.4 ".parse::<BoxSize>().map(ObjectShape::from),
            Ok(ObjectShape::Box {
                width: 0.3,
                length: 0.4
            })
        );
        let refusal = |text: &str| text.parse::<BoxSize>().map_err(|e| e.to_string());
        assert_eq!(
            refusal("0.3by0.4"),
            Err("expected WIDTHxLENGTH in metres, e.g. 0.3x0.4, found '0.3by0.4'".to_owned())
        );
        assert_eq!(
            refusal("0x0.4"),
            Err("the width '0' is not a number of metres above 0".to_owned())
        );
        assert_eq!(
            refusal("0.3xabc"),
            Err("the length 'abc' is not a number of metres above 0".to_owned())
        );
        assert!(refusal("infx1").is_err());
    }
}
