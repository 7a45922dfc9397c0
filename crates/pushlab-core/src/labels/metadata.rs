//! What a recording is: per-recording metadata fields, including the train/test split.

use serde::{Deserialize, Serialize};

use crate::recording::PushSide;

/// Which experiment a recording belongs to. Training and evaluation select recordings by split.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Split {
    /// Used for offline training of the network (the paper's `D_offline`).
    Offline,
    /// Streamed to online learning of `θ_online` (the paper's online experiments).
    Online,
    /// Kept out of both, for a final evaluation.
    HeldOut,
}

impl Split {
    /// All splits, in file order.
    pub const ALL: [Split; 3] = [Split::Offline, Split::Online, Split::HeldOut];

    /// The name used in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Split::Offline => "offline",
            Split::Online => "online",
            Split::HeldOut => "held-out",
        }
    }

    /// Parses [`Split::name`]; also accepts `held_out` and `heldout`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "offline" => Some(Split::Offline),
            "online" => Some(Split::Online),
            "held-out" | "held_out" | "heldout" => Some(Split::HeldOut),
            _ => None,
        }
    }
}

/// Metadata of one recording. Every field is optional: people fill in what they know.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordingMeta {
    /// What was pushed (`"rect1"`, `"ellip2"`, `"box 9 cm"`).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub object: String,
    /// Surface material (`"abs"`, `"plywood"`).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub material: String,
    /// The labelled COM, metres, in the object frame: `COM − geometric centre` (the crate's COM
    /// offset, since the object frame's origin is the geometric centre).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub com_offset: Option<[f64; 2]>,
    /// Which face was pushed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub push_side: Option<PushSide>,
    /// The experiment split.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub split: Option<Split>,
    /// Free text.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub notes: String,
}

/// One metadata field with its new value: the unit of a metadata edit, so undo restores exactly the
/// field that was changed and typing into one text box becomes one undo step.
#[derive(Clone, Debug, PartialEq)]
pub enum MetaField {
    /// Sets [`RecordingMeta::object`].
    Object(String),
    /// Sets [`RecordingMeta::material`].
    Material(String),
    /// Sets [`RecordingMeta::com_offset`]; `None` clears it.
    ComOffset(Option<[f64; 2]>),
    /// Sets [`RecordingMeta::push_side`].
    PushSide(Option<PushSide>),
    /// Sets [`RecordingMeta::split`].
    Split(Option<Split>),
    /// Sets [`RecordingMeta::notes`].
    Notes(String),
}

impl MetaField {
    /// The field's name in files, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            MetaField::Object(_) => "object",
            MetaField::Material(_) => "material",
            MetaField::ComOffset(_) => "com_offset",
            MetaField::PushSide(_) => "push_side",
            MetaField::Split(_) => "split",
            MetaField::Notes(_) => "notes",
        }
    }

    /// Whether consecutive edits of this field are typed text, merged into one undo step.
    pub fn is_text(&self) -> bool {
        matches!(
            self,
            MetaField::Object(_) | MetaField::Material(_) | MetaField::Notes(_)
        )
    }

    /// Writes the value into `meta`.
    pub fn apply(self, meta: &mut RecordingMeta) {
        match self {
            MetaField::Object(v) => meta.object = v,
            MetaField::Material(v) => meta.material = v,
            MetaField::ComOffset(v) => meta.com_offset = v,
            MetaField::PushSide(v) => meta.push_side = v,
            MetaField::Split(v) => meta.split = v,
            MetaField::Notes(v) => meta.notes = v,
        }
    }
}

impl RecordingMeta {
    /// Whether no field is set.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// Checks values a type cannot: the COM offset must be finite.
    pub fn validate(&self) -> Result<(), (String, String)> {
        if let Some(com) = self.com_offset
            && !com.iter().all(|v| v.is_finite())
        {
            return Err((
                "com_offset".into(),
                format!("expected two finite numbers in metres, found {com:?}"),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn split_names_round_trip() {
        for split in Split::ALL {
            assert_eq!(Split::from_name(split.name()), Some(split));
            let json = serde_json::to_string(&split).unwrap();
            assert_eq!(json, format!("\"{}\"", split.name()));
        }
        assert_eq!(Split::from_name("Held_Out"), Some(Split::HeldOut));
        assert_eq!(Split::from_name("train"), None);
    }

    #[test]
    fn empty_meta_writes_nothing() {
        assert_eq!(
            serde_json::to_string(&RecordingMeta::default()).unwrap(),
            "{}"
        );
    }

    #[test]
    fn non_finite_com_is_rejected() {
        let meta = RecordingMeta {
            com_offset: Some([f64::NAN, 0.0]),
            ..Default::default()
        };
        assert_eq!(meta.validate().unwrap_err().0, "com_offset");
    }
}
