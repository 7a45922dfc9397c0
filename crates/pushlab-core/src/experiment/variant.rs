//! Model variants a suite can compare: the two kinds as `train` makes them, and ablations that
//! measure what each part of the contact-frame model buys and whether the paper model is helped by
//! augmenting its offline data with the outline's symmetries.

use nalgebra::{Matrix2, Vector2};
use serde::{Deserialize, Serialize};

use crate::geometry::Outline;
use crate::learn::TrainConfig;
use crate::model::contact::ContactOptions;
use crate::model::{ModelKind, ObjectMotion, Sample, SampleInput};

/// A model kind with its training options, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum ModelVariant {
    /// The model of a kind as `pushlab train` makes it.
    Kind(ModelKind),
    /// The contact-frame network correcting the raw pusher motion instead of the physical prior.
    ContactNoPrior,
    /// The contact-frame model's physical prior alone (sweep + motion cone, `μ` trained), no network.
    ContactPriorOnly,
    /// The paper model trained on its offline pushes and their images under the outline's symmetries.
    PaperAugmented,
}

impl ModelVariant {
    /// Every variant.
    pub const ALL: [ModelVariant; 5] = [
        ModelVariant::Kind(ModelKind::Contact),
        ModelVariant::ContactNoPrior,
        ModelVariant::ContactPriorOnly,
        ModelVariant::Kind(ModelKind::Paper),
        ModelVariant::PaperAugmented,
    ];

    /// The name in suite files and tables.
    pub fn name(self) -> &'static str {
        match self {
            ModelVariant::Kind(kind) => kind.name(),
            ModelVariant::ContactNoPrior => "contact-no-prior",
            ModelVariant::ContactPriorOnly => "contact-prior-only",
            ModelVariant::PaperAugmented => "paper-augmented",
        }
    }

    /// The variant of a name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|v| v.name() == name)
    }

    /// The kind of model it trains.
    pub fn kind(self) -> ModelKind {
        match self {
            ModelVariant::Kind(kind) => kind,
            ModelVariant::ContactNoPrior | ModelVariant::ContactPriorOnly => ModelKind::Contact,
            ModelVariant::PaperAugmented => ModelKind::Paper,
        }
    }

    /// `config` with this variant's options.
    pub fn configure(self, config: &TrainConfig) -> TrainConfig {
        let (contact, augment_symmetries) = match self {
            ModelVariant::Kind(_) => (ContactOptions::default(), false),
            ModelVariant::ContactNoPrior => (
                ContactOptions {
                    prior: false,
                    network: true,
                },
                false,
            ),
            ModelVariant::ContactPriorOnly => (
                ContactOptions {
                    prior: true,
                    network: false,
                },
                false,
            ),
            ModelVariant::PaperAugmented => (ContactOptions::default(), true),
        };
        TrainConfig {
            contact,
            augment_symmetries,
            ..*config
        }
    }
}

impl TryFrom<String> for ModelVariant {
    type Error = String;
    fn try_from(name: String) -> Result<Self, String> {
        Self::from_name(&name).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|v| v.name()).collect();
            format!(
                "unknown model {name:?}; expected one of {}",
                names.join(", ")
            )
        })
    }
}

impl From<ModelVariant> for String {
    fn from(v: ModelVariant) -> Self {
        v.name().to_owned()
    }
}

/// The mirrors and quarter turns about the object frame's origin that map `outline` onto itself
/// (the identity first): for a rectangle the two mirrors and the half turn, for a square all eight.
pub fn symmetries(outline: &Outline) -> Vec<Matrix2<f64>> {
    let candidates = [
        Matrix2::new(1.0, 0.0, 0.0, 1.0),
        Matrix2::new(0.0, -1.0, 1.0, 0.0),
        Matrix2::new(-1.0, 0.0, 0.0, -1.0),
        Matrix2::new(0.0, 1.0, -1.0, 0.0),
        Matrix2::new(1.0, 0.0, 0.0, -1.0),
        Matrix2::new(-1.0, 0.0, 0.0, 1.0),
        Matrix2::new(0.0, 1.0, 1.0, 0.0),
        Matrix2::new(0.0, -1.0, -1.0, 0.0),
    ];
    let tolerance = 1e-9 * outline.size().max(1e-9);
    let vertices = outline.vertices();
    candidates
        .into_iter()
        .filter(|t| {
            vertices.iter().all(|v| {
                let image = t * v.coords;
                vertices
                    .iter()
                    .any(|w| (w.coords - image).norm() <= tolerance)
            })
        })
        .collect()
}

/// A sample's image under the orthogonal map `t`: positions, motions and the translation map, and
/// the rotation changes sign under a mirror.
pub fn transformed(sample: &Sample, t: &Matrix2<f64>) -> Sample {
    let map = |v: [f64; 2]| {
        let image = t * Vector2::from(v);
        [image.x, image.y]
    };
    Sample {
        input: SampleInput {
            robot_in_object: map(sample.input.robot_in_object),
            robot_motion_in_object: map(sample.input.robot_motion_in_object),
        },
        target: ObjectMotion {
            translation: map(sample.target.translation),
            rotation: sample.target.rotation * t.determinant().signum(),
        },
        frame: sample.frame,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rectangle_has_four_symmetries_and_a_square_eight() {
        let rectangle = Outline::rectangle(0.3, 0.4).expect("valid");
        assert_eq!(symmetries(&rectangle).len(), 4);
        let square = Outline::rectangle(0.3, 0.3).expect("valid");
        assert_eq!(symmetries(&square).len(), 8);
        let triangle =
            Outline::try_from(vec![[0.1, 0.0], [-0.05, 0.08], [-0.05, -0.02]]).expect("valid");
        assert_eq!(symmetries(&triangle).len(), 1);
    }

    #[test]
    fn variants_round_trip_their_names() {
        for v in ModelVariant::ALL {
            assert_eq!(ModelVariant::from_name(v.name()), Some(v));
        }
        assert!(ModelVariant::try_from("nope".to_owned()).is_err());
    }
}
