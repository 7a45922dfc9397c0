//! The label schema: which labels exist, how they look, which key paints them, and which of them
//! exclude each other.
//!
//! The schema is stored in the labels file next to the labels themselves, so that colours, hotkeys
//! and exclusive groups travel with the annotations they describe.

use std::collections::BTreeSet;
use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// An sRGB colour, 8 bits per channel. Written as `"#rrggbb"` in files so people can edit it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgb(pub [u8; 3]);

impl Rgb {
    /// A colour from its red, green and blue channels.
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Self([r, g, b])
    }
}

impl fmt::Display for Rgb {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [r, g, b] = self.0;
        write!(f, "#{r:02x}{g:02x}{b:02x}")
    }
}

impl FromStr for Rgb {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let hex = text
            .strip_prefix('#')
            .filter(|h| h.len() == 6 && h.chars().all(|c| c.is_ascii_hexdigit()))
            .ok_or_else(|| format!("expected a colour like \"#1f77b4\", found {text:?}"))?;
        let channel = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|e| e.to_string());
        Ok(Self([channel(0)?, channel(2)?, channel(4)?]))
    }
}

impl Serialize for Rgb {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

/// Whether a label covers a span of frames or marks one instant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LabelKind {
    /// Painted over a range of frames (`contact`, `sticking`, `bad tracking`).
    #[default]
    Range,
    /// Placed at one frame (`contact made`, `contact lost`).
    Event,
}

/// One label of the schema.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LabelDef {
    /// Unique name; also the key used in segments and exports.
    pub name: String,
    /// Colour of its band on the timeline.
    pub colour: Rgb,
    /// Key that paints (ranges) or places (events) it, as an egui key name (`"1"`, `"S"`, `"F2"`).
    /// Unique within the schema; `None` for labels only reachable by mouse.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hotkey: Option<String>,
    /// Range or point event.
    #[serde(default)]
    pub kind: LabelKind,
    /// Exclusive group: two range labels of the same group never cover the same frame, so painting
    /// one cuts the other. `None` for labels that may overlap anything (`bad tracking`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
    /// Frames covered by this label are left out of training and evaluation (`bad tracking`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub skip_in_training: bool,
}

impl LabelDef {
    /// A range label with no group, hotkey or skip flag; adjust the fields as needed.
    pub fn range(name: &str, colour: Rgb) -> Self {
        Self {
            name: name.to_owned(),
            colour,
            hotkey: None,
            kind: LabelKind::Range,
            group: None,
            skip_in_training: false,
        }
    }

    /// A point-event label with no hotkey.
    pub fn event(name: &str, colour: Rgb) -> Self {
        Self {
            kind: LabelKind::Event,
            ..Self::range(name, colour)
        }
    }

    fn with_hotkey(mut self, key: &str) -> Self {
        self.hotkey = Some(key.to_owned());
        self
    }

    fn in_group(mut self, group: &str) -> Self {
        self.group = Some(group.to_owned());
        self
    }
}

/// The set of labels a labels file uses.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LabelSchema {
    /// The labels in display order (the order of bands and of the cheat-sheet).
    pub labels: Vec<LabelDef>,
}

/// Names of the default labels, so code that needs one (the pipeline, tests) does not repeat strings.
pub mod names {
    /// In contact with the object.
    pub const CONTACT: &str = "contact";
    /// Pusher and object apart.
    pub const NO_CONTACT: &str = "no contact";
    /// The contact point does not slide along the object's face.
    pub const STICKING: &str = "sticking";
    /// The contact point slides along the object's face.
    pub const SLIPPING: &str = "slipping";
    /// Object or pusher pose unreliable; these frames are skipped by training and evaluation.
    pub const BAD_TRACKING: &str = "bad tracking";
    /// The frame at which contact begins.
    pub const CONTACT_MADE: &str = "contact made";
    /// The frame at which contact ends.
    pub const CONTACT_LOST: &str = "contact lost";
    /// Exclusive group of `contact` and `no contact`.
    pub const GROUP_CONTACT: &str = "contact";
    /// Exclusive group of `sticking` and `slipping`.
    pub const GROUP_CONTACT_MODE: &str = "contact mode";
}

impl Default for LabelSchema {
    /// The schema for pushing: contact state, contact mode (sticking or slipping), bad tracking, and
    /// the contact made / lost events. Hotkeys are digits, as in CVAT, so they never collide with the
    /// player's letter and arrow keys.
    fn default() -> Self {
        use names::*;
        Self {
            labels: vec![
                LabelDef::range(CONTACT, Rgb::new(0x2c, 0xa0, 0x2c))
                    .with_hotkey("1")
                    .in_group(GROUP_CONTACT),
                LabelDef::range(NO_CONTACT, Rgb::new(0xa0, 0xa0, 0xa0))
                    .with_hotkey("2")
                    .in_group(GROUP_CONTACT),
                LabelDef::range(STICKING, Rgb::new(0x1f, 0x77, 0xb4))
                    .with_hotkey("3")
                    .in_group(GROUP_CONTACT_MODE),
                LabelDef::range(SLIPPING, Rgb::new(0xff, 0x7f, 0x0e))
                    .with_hotkey("4")
                    .in_group(GROUP_CONTACT_MODE),
                LabelDef {
                    skip_in_training: true,
                    ..LabelDef::range(BAD_TRACKING, Rgb::new(0xd6, 0x27, 0x28)).with_hotkey("5")
                },
                LabelDef::event(CONTACT_MADE, Rgb::new(0x17, 0xbe, 0xcf)).with_hotkey("6"),
                LabelDef::event(CONTACT_LOST, Rgb::new(0x94, 0x67, 0xbd)).with_hotkey("7"),
            ],
        }
    }
}

impl LabelSchema {
    /// The label called `name`.
    pub fn get(&self, name: &str) -> Option<&LabelDef> {
        self.labels.iter().find(|l| l.name == name)
    }

    /// The label whose hotkey is `key` (an egui key name), for the app's keyboard handling.
    pub fn by_hotkey(&self, key: &str) -> Option<&LabelDef> {
        self.labels.iter().find(|l| {
            l.hotkey
                .as_deref()
                .is_some_and(|k| k.eq_ignore_ascii_case(key))
        })
    }

    /// The exclusive group of the range label `name`, if it has one.
    pub fn group_of(&self, name: &str) -> Option<&str> {
        self.get(name).and_then(|l| l.group.as_deref())
    }

    /// Whether two labels may not cover the same frame.
    pub fn excludes(&self, a: &str, b: &str) -> bool {
        a != b
            && match (self.group_of(a), self.group_of(b)) {
                (Some(ga), Some(gb)) => ga == gb,
                _ => false,
            }
    }

    /// The exclusive groups, each with its labels in schema order.
    pub fn groups(&self) -> Vec<(String, Vec<String>)> {
        let mut groups: Vec<(String, Vec<String>)> = Vec::new();
        for label in &self.labels {
            let Some(group) = &label.group else { continue };
            match groups.iter_mut().find(|(g, _)| g == group) {
                Some((_, members)) => members.push(label.name.clone()),
                None => groups.push((group.clone(), vec![label.name.clone()])),
            }
        }
        groups
    }

    /// Checks that names and hotkeys are unique and non-empty and that events have no group.
    /// Returns the offending field (`labels[3].hotkey`) and what is wrong.
    pub fn validate(&self) -> Result<(), (String, String)> {
        let mut names = BTreeSet::new();
        let mut keys = BTreeSet::new();
        for (i, label) in self.labels.iter().enumerate() {
            let field = |f: &str| format!("labels[{i}].{f}");
            if label.name.trim().is_empty() {
                return Err((field("name"), "a label name must not be empty".into()));
            }
            if !names.insert(label.name.as_str()) {
                return Err((
                    field("name"),
                    format!("the label name {:?} is used twice", label.name),
                ));
            }
            if let Some(key) = &label.hotkey {
                if key.trim().is_empty() {
                    return Err((field("hotkey"), "a hotkey must not be empty".into()));
                }
                if !keys.insert(key.to_ascii_uppercase()) {
                    return Err((
                        field("hotkey"),
                        format!("the hotkey {key:?} is used by two labels"),
                    ));
                }
            }
            if label.kind == LabelKind::Event && label.group.is_some() {
                return Err((
                    field("group"),
                    format!(
                        "{:?} is a point event; only range labels can be in an exclusive group",
                        label.name
                    ),
                ));
            }
            if label.group.as_deref().is_some_and(|g| g.trim().is_empty()) {
                return Err((field("group"), "a group name must not be empty".into()));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    #[test]
    fn colour_round_trips_through_hex() {
        let c: Rgb = "#1F77b4".parse().unwrap();
        assert_eq!(c, Rgb::new(0x1f, 0x77, 0xb4));
        assert_eq!(c.to_string(), "#1f77b4");
        let err = "1f77b4".parse::<Rgb>().unwrap_err();
        assert!(err.contains("\"#1f77b4\""), "{err}");
        assert!("#12345".parse::<Rgb>().is_err());
        assert!("#12345g".parse::<Rgb>().is_err());
    }

    #[test]
    fn default_schema_has_the_pushing_groups() {
        let schema = LabelSchema::default();
        schema.validate().unwrap();
        assert!(schema.excludes(names::STICKING, names::SLIPPING));
        assert!(schema.excludes(names::CONTACT, names::NO_CONTACT));
        assert!(!schema.excludes(names::STICKING, names::CONTACT));
        assert!(!schema.excludes(names::BAD_TRACKING, names::SLIPPING));
        assert!(!schema.excludes(names::STICKING, names::STICKING));
        assert_eq!(schema.by_hotkey("4").unwrap().name, names::SLIPPING);
        assert_eq!(
            schema.get(names::CONTACT_LOST).unwrap().kind,
            LabelKind::Event
        );
        assert!(schema.get(names::BAD_TRACKING).unwrap().skip_in_training);
        assert_eq!(
            schema.groups(),
            vec![
                (
                    "contact".to_owned(),
                    vec!["contact".into(), "no contact".into()]
                ),
                (
                    "contact mode".to_owned(),
                    vec!["sticking".into(), "slipping".into()]
                ),
            ]
        );
    }

    #[test]
    fn validation_names_the_offending_field() {
        let mut schema = LabelSchema::default();
        schema.labels[4].hotkey = Some("1".into());
        let (field, message) = schema.validate().unwrap_err();
        assert_eq!(field, "labels[4].hotkey");
        assert!(message.contains("\"1\""), "{message}");

        let mut schema = LabelSchema::default();
        schema.labels[2].name = "contact".into();
        assert_eq!(schema.validate().unwrap_err().0, "labels[2].name");

        let mut schema = LabelSchema::default();
        schema.labels[5].group = Some("contact".into());
        let (field, message) = schema.validate().unwrap_err();
        assert_eq!(field, "labels[5].group");
        assert!(message.contains("point event"), "{message}");
    }
}
