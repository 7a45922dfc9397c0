//! A mystery object: its outline in the open, its centre of mass, `h` and material hidden, all drawn
//! from one seed so that a teacher's link (`?sandbox=SEED&object=…`) gives a whole class the same
//! mystery. A teacher may set the hidden values instead.
//!
//! The draws stay where the bundled model was trained (the sample data's objects, 0.3–0.55 m, its
//! 175 mm pusher, its two materials at 10 Hz), so that what a student sees the model do is what it
//! does on data like its own: the COM anywhere in a box of ±6 cm about the centre that keeps it
//! well inside the outline, the material (pressure under the object and the pusher's friction)
//! either of the sample data's, and `h` what that pressure gives about that COM (Lynch's `h`, the
//! simulator's rule).

use crate::math;
use std::fmt;
use std::str::FromStr;

use nalgebra::{Point2, Vector2};

use crate::geometry::{Outline, OutlineError};
use crate::recording::{ObjectShape, Setting, ShapePreset};
use crate::rng::SplitMix64;
use crate::sim::pressure::DEFAULT_RESOLUTION;
use crate::sim::{PressureModel, SimObject, TrackingNoise, lynch_h};

/// The bundled model's pusher: the sample data's (`sample-data/spec.json`).
pub const PUSHER_RADIUS_M: f64 = 0.175;
/// Frames a second: the sample data's, the rate the bundled model was trained at.
pub const RATE_HZ: f64 = 10.0;
/// The fastest the pusher follows the pointer, m/s: the sample data's pushing speed.
pub const PUSHER_SPEED: f64 = 0.04;
/// The tracking noise a sandbox adds when asked: the sample data's (2 mm, 0.5°).
pub const SANDBOX_NOISE: TrackingNoise = TrackingNoise {
    position_sd: 0.002,
    yaw_sd: 0.5 * std::f64::consts::PI / 180.0,
};
/// The hidden COM is drawn in a square this far either side of the centre, metres (the sample
/// data's offsets are 5 cm), or a fifth of a smaller object's smaller half.
pub const COM_SPREAD_M: f64 = 0.06;
/// Metres per pixel of the T (gym-pusht's 120 px bar, 0.4 m wide: the size of the sample data's
/// boxes).
pub const T_METRES_PER_PX: f64 = 0.4 / 120.0;

/// Which object hides the mystery.
#[derive(Clone, Debug, PartialEq)]
pub enum MysteryObject {
    /// The sample data's first box, 0.3 × 0.4 m.
    Box,
    /// Push-T's T, 0.4 m across its bar.
    T,
    /// An ellipse 0.3 × 0.45 m (a 48-gon).
    Ellipse,
    /// The outline of a recording (the one shown): its name, footprint and pusher.
    Outline {
        name: String,
        shape: ObjectShape,
        pusher_radius: f64,
    },
}

impl MysteryObject {
    /// The name a link gives it: `box`, `t`, `ellipse`, or the recording's name.
    pub fn name(&self) -> &str {
        match self {
            MysteryObject::Box => "box",
            MysteryObject::T => "t",
            MysteryObject::Ellipse => "ellipse",
            MysteryObject::Outline { name, .. } => name,
        }
    }

    /// The footprint.
    pub fn shape(&self) -> ObjectShape {
        match self {
            MysteryObject::Box => ObjectShape::Box {
                width: 0.3,
                length: 0.4,
            },
            MysteryObject::T => ShapePreset::shape("push-t", T_METRES_PER_PX),
            MysteryObject::Ellipse => ObjectShape::Polygon {
                vertices: (0..48)
                    .map(|k| {
                        let a = std::f64::consts::TAU * k as f64 / 48.0;
                        [0.15 * math::cos(a), 0.225 * math::sin(a)]
                    })
                    .collect(),
            },
            MysteryObject::Outline { shape, .. } => shape.clone(),
        }
    }

    /// The pusher's radius: the bundled model's, or the recording's for its outline.
    pub fn pusher_radius(&self) -> f64 {
        match self {
            MysteryObject::Outline { pusher_radius, .. } => *pusher_radius,
            _ => PUSHER_RADIUS_M,
        }
    }
}

impl fmt::Display for MysteryObject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MysteryObject {
    type Err = String;

    /// `box`, `t` or `ellipse` (a recording's outline is chosen in the app, not named).
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "box" => Ok(Self::Box),
            "t" | "push-t" => Ok(Self::T),
            "ellipse" => Ok(Self::Ellipse),
            other => Err(format!(
                "unknown mystery object '{other}': expected box, t or ellipse"
            )),
        }
    }
}

/// What is hidden: the COM offset (COM − geometric centre, object frame, metres), the pressure
/// under the object and the pusher's friction; `h` follows from the first two.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hidden {
    pub com_offset: [f64; 2],
    pub pressure: PressureModel,
    pub pusher_friction: f64,
}

/// A mystery: the object, what is hidden, and the simulator's object and the setting it makes.
#[derive(Clone, Debug, PartialEq)]
pub struct Mystery {
    pub seed: u64,
    pub object: MysteryObject,
    pub hidden: Hidden,
    /// Lynch's `h` of the hidden pressure about the hidden COM, metres.
    pub h: f64,
    /// What the simulator pushes.
    pub sim: SimObject,
}

/// Why a mystery cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MysteryError {
    #[error("the object's outline: {0}")]
    Outline(#[from] OutlineError),
    #[error("the COM offset ({x:.3}, {y:.3}) m lies outside the object")]
    ComOutside { x: f64, y: f64 },
    #[error("the pusher's friction {0} is not a finite number ≥ 0")]
    BadFriction(f64),
    #[error("{0}")]
    Pressure(String),
}

/// The sample data's two materials: how the weight rests (pressure) and the pusher's friction.
const MATERIALS: [(&str, PressureModel, f64); 2] = [
    ("paper", PressureModel::Rim, 0.45),
    ("plastic", PressureModel::Centre, 0.2),
];

impl Mystery {
    /// The mystery of `seed` on `object`: the hidden COM and material drawn from the seed (the
    /// same seed, the same mystery, on every machine and in the page).
    pub fn draw(seed: u64, object: MysteryObject) -> Result<Self, MysteryError> {
        let outline = object.shape().outline()?;
        // A small outline (a recording's) gets a spread to its size: a fifth of its smaller half.
        let (low, high) = outline.bounding_box();
        let spread = COM_SPREAD_M.min(0.2 * (high.x - low.x).min(high.y - low.y));
        let mut rng = SplitMix64::new(seed);
        let (_, pressure, pusher_friction) = MATERIALS[rng.below(MATERIALS.len())];
        // The COM well inside the outline: drawn again until a disc of a third of the spread about
        // it fits (a few draws at most on the bundled shapes).
        let mut com = [0.0; 2];
        for _ in 0..64 {
            let point = Point2::new(
                (2.0 * rng.uniform() - 1.0) * spread,
                (2.0 * rng.uniform() - 1.0) * spread,
            ) + centroid_of(&outline);
            if depth_inside(&outline, point) > spread / 3.0 {
                com = [point.x, point.y];
                break;
            }
        }
        Self::with_hidden(
            seed,
            object,
            Hidden {
                com_offset: com,
                pressure,
                pusher_friction,
            },
        )
    }

    /// A mystery whose hidden values are given (a teacher's choice).
    pub fn with_hidden(
        seed: u64,
        object: MysteryObject,
        hidden: Hidden,
    ) -> Result<Self, MysteryError> {
        let outline = object.shape().outline()?;
        let [x, y] = hidden.com_offset;
        if !(x.is_finite() && y.is_finite()) || depth_inside(&outline, Point2::new(x, y)) <= 0.0 {
            return Err(MysteryError::ComOutside { x, y });
        }
        if !(hidden.pusher_friction.is_finite() && hidden.pusher_friction >= 0.0) {
            return Err(MysteryError::BadFriction(hidden.pusher_friction));
        }
        let com_offset = Vector2::new(x, y);
        let h = lynch_h(&outline, hidden.pressure, com_offset, DEFAULT_RESOLUTION)
            .map_err(|e| MysteryError::Pressure(e.to_string()))?;
        Ok(Self {
            seed,
            sim: SimObject {
                outline,
                com_offset,
                h,
                pusher_radius: object.pusher_radius(),
                pusher_friction: hidden.pusher_friction,
            },
            object,
            hidden,
            h,
        })
    }

    /// The setting while the mystery is hidden: the object, the pusher and the frame rate, and
    /// the seed and object it was drawn from, nothing of what is hidden (what a student's pushes
    /// open with, so that no layer or column shows the truth before the reveal).
    pub fn public_setting(&self) -> Setting {
        let mut setting = Setting::of_object(
            format!("sandbox-{}-{}", self.object.name(), self.seed),
            self.object.shape(),
            self.object.pusher_radius(),
        );
        setting.sample_rate_hz = Some(RATE_HZ);
        setting.extra.insert(
            "sandbox".into(),
            serde_json::json!({"seed": self.seed, "object": self.object.name()}),
        );
        setting
    }

    /// The setting a recording of this mystery is saved with: the truth written in (the COM offset,
    /// `h`, the material), as the simulator writes its sets.
    pub fn setting(&self) -> Setting {
        let mut setting = self.public_setting();
        let material = MATERIALS
            .iter()
            .find(|(_, p, f)| *p == self.hidden.pressure && *f == self.hidden.pusher_friction)
            .map(|(name, ..)| (*name).to_owned());
        setting.material = material;
        setting.pusher_friction = Some(self.hidden.pusher_friction);
        setting.com_offset = Some(self.hidden.com_offset);
        setting.h = Some(self.h);
        setting.extra.insert(
            "sandbox".into(),
            serde_json::json!({
                "seed": self.seed,
                "object": self.object.name(),
                "pressure": self.hidden.pressure.name(),
            }),
        );
        setting
    }
}

/// The outline's area centroid: where the object frame's origin should be (a preset's may not be
/// exactly, so the COM is drawn about the centroid).
fn centroid_of(outline: &Outline) -> Vector2<f64> {
    outline.centroid().coords
}

/// How far `point` lies inside the outline (negative outside), metres.
fn depth_inside(outline: &Outline, point: Point2<f64>) -> f64 {
    -outline.closest_boundary_point(point).signed_distance
}
