//! What a user chose for a bag, and what pushlab offers before they choose.
//!
//! A bag does not say which topics are the pusher and the object, nor what the object is. The user
//! says so once — in the app's dialog, or by hand — and the choice is remembered in a small JSON
//! file beside the bag (`run1.mcap` → `run1.mcap.pushlab-bag.json`), never inside it. From then on
//! the bag opens like any recording, in the app and in every CLI command that opens recordings,
//! because [`super::super::load_paths`] reads the remembered choice. The object comes from a
//! `setting.json` (a path, kept relative to the choice file so the folder can move) or is entered
//! (the setting itself is stored).
//!
//! The pre-selection ([`suggest`]) only picks a topic when its name makes the role obvious: a wrong
//! guess silently imports the pusher as the object, which is worse than asking.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::cdr::PoseType;
use super::error::BagError;
use super::problem::BagProblem;
use super::spec::TopicSpec;
use super::split::{ImportOptions, MAX_RATE_HZ};
use super::topic_info::{TF_STATIC, TopicInfo};
use crate::atomic_file::write_atomically;
use crate::json_problem;
use crate::recording::native::{NativeError, SETTING_FILE, check_setting, parse_setting};
use crate::recording::read::{file_beside, read_file};
use crate::recording::setting::Setting;

/// Appended to a bag's file or folder name to name its remembered choice.
pub const CHOICE_SUFFIX: &str = ".pushlab-bag.json";

/// The `format` value of a choice file, so that another tool's JSON is not taken for one.
const FORMAT: &str = "pushlab-bag-choice";

/// Where the object and the rest of the setting come from.
#[derive(Clone, Debug, PartialEq)]
pub enum SettingSource {
    /// A `setting.json` file (its `trajectories` are ignored).
    File(PathBuf),
    /// Entered by the user; its `trajectories` are ignored.
    Entered(Setting),
}

/// Which topics are the pusher and the object, where the setting comes from, and how to import.
#[derive(Clone, Debug, PartialEq)]
pub struct BagChoice {
    pub pusher: TopicSpec,
    pub object: TopicSpec,
    pub setting: SettingSource,
    pub options: ImportOptions,
    /// Camera topics whose frames are shown beside the push (none, one or several).
    pub cameras: Vec<String>,
}

/// The file as written: flat, readable, with a version.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChoiceFile {
    format: String,
    version: u32,
    pusher: String,
    object: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    setting_file: Option<PathBuf>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    setting: Option<Setting>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    split_gap_s: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    rate_hz: Option<f64>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    cameras: Vec<String>,
}

/// The remembered-choice file of a bag (an `.mcap` file or a rosbag2 folder): beside it, named
/// after it.
pub fn choice_path(bag: &Path) -> PathBuf {
    file_beside(bag, CHOICE_SUFFIX, "bag")
}

/// The choice remembered beside `bag`, if any. A file that exists but cannot be used is an error
/// naming it and the field.
pub fn remembered(bag: &Path) -> Result<Option<BagChoice>, BagError> {
    let path = choice_path(bag);
    if !crate::files::is_file(&path) {
        return Ok(None);
    }
    let bytes = read_file(&path)?;
    parse(&bytes, &path).map(Some)
}

fn bad(path: &Path, why: String) -> BagError {
    BagError::Problem {
        path: path.to_path_buf(),
        problem: BagProblem::BadChoice { why },
    }
}

/// Reads a choice file held in memory; `path` names it in messages and anchors a relative
/// `setting_file`.
pub fn parse(bytes: &[u8], path: &Path) -> Result<BagChoice, BagError> {
    let file: ChoiceFile =
        json_problem::from_file_bytes(bytes).map_err(|problem| bad(path, problem.to_string()))?;
    if file.format != FORMAT {
        return Err(bad(
            path,
            format!("\"format\" is \"{}\", expected \"{FORMAT}\"", file.format),
        ));
    }
    if file.version != 1 {
        return Err(bad(
            path,
            format!(
                "version {} is not supported, expected 1 (written by a newer pushlab?)",
                file.version
            ),
        ));
    }
    let topic = |field: &str, text: &str| {
        text.parse::<TopicSpec>()
            .map_err(|why| bad(path, format!("field `{field}`: {why}")))
    };
    let pusher = topic("pusher", &file.pusher)?;
    let object = topic("object", &file.object)?;
    let setting = match (file.setting_file, file.setting) {
        (Some(relative), None) => {
            let folder = path.parent().unwrap_or(Path::new("."));
            SettingSource::File(folder.join(relative))
        }
        (None, Some(setting)) => {
            check_setting(&setting).map_err(|(field, problem)| {
                bad(path, format!("field `setting.{field}`: {problem}"))
            })?;
            SettingSource::Entered(setting)
        }
        _ => {
            return Err(bad(
                path,
                "expected exactly one of `setting_file` and `setting`".to_owned(),
            ));
        }
    };
    let positive = |field: &str, value: Option<f64>| match value {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(bad(
            path,
            format!("field `{field}`: {v}, expected a positive number"),
        )),
        _ => Ok(value),
    };
    Ok(BagChoice {
        pusher,
        object,
        setting,
        options: ImportOptions {
            split_gap_s: positive("split_gap_s", file.split_gap_s)?,
            rate_hz: positive("rate_hz", file.rate_hz)?.map(|hz| hz.min(MAX_RATE_HZ)),
        },
        cameras: file.cameras,
    })
}

/// Remembers `choice` beside `bag`, atomically. A setting file in the choice file's folder or below
/// is stored relative to it.
pub fn remember(bag: &Path, choice: &BagChoice) -> std::io::Result<PathBuf> {
    let path = choice_path(bag);
    let folder = path.parent().unwrap_or(Path::new("."));
    let (setting_file, setting) = match &choice.setting {
        SettingSource::File(file) => {
            let relative = file.strip_prefix(folder).unwrap_or(file);
            (Some(relative.to_path_buf()), None)
        }
        SettingSource::Entered(setting) => {
            let mut setting = setting.clone();
            setting.trajectories.clear();
            (None, Some(setting))
        }
    };
    let file = ChoiceFile {
        format: FORMAT.to_owned(),
        version: 1,
        pusher: choice.pusher.to_string(),
        object: choice.object.to_string(),
        setting_file,
        setting,
        split_gap_s: choice.options.split_gap_s,
        rate_hz: choice.options.rate_hz,
        cameras: choice.cameras.clone(),
    };
    let mut json = serde_json::to_vec_pretty(&file).map_err(std::io::Error::other)?;
    json.push(b'\n');
    write_atomically(&path, &json)?;
    Ok(path)
}

impl SettingSource {
    /// The setting, read and checked when it is a file; an entered one was checked when entered
    /// ([`entered_box`]) or read ([`parse`]).
    pub fn resolve(&self) -> Result<Setting, NativeError> {
        match self {
            SettingSource::File(path) => parse_setting(&read_file(path)?, path),
            SettingSource::Entered(setting) => Ok(setting.clone()),
        }
    }
}

/// A setting entered by hand for a box-shaped object, sizes in metres, checked as a `setting.json`
/// would be; the error names the field and what was expected.
pub fn entered_box(
    name: &str,
    width: f64,
    length: f64,
    pusher_radius: f64,
    material: Option<&str>,
) -> Result<Setting, String> {
    let mut setting = Setting::of_object(
        name.trim(),
        crate::recording::ObjectShape::Box { width, length },
        pusher_radius,
    );
    setting.material = material
        .map(str::trim)
        .filter(|m| !m.is_empty())
        .map(str::to_owned);
    if setting.name.is_empty() {
        return Err("name: empty, expected a name for the setting".to_owned());
    }
    // The form's box is the setting's whole object: its problem needs no field name.
    check_setting(&setting).map_err(|(field, problem)| match field.as_str() {
        "object" => problem,
        _ => format!("{field}: {problem}"),
    })?;
    Ok(setting)
}

/// The `setting.json` files a bag's object may be described by, nearest first: inside a rosbag2
/// folder, then in the folder holding the bag. Only those that exist.
pub fn settings_beside(bag: &Path) -> Vec<PathBuf> {
    let mut candidates = Vec::new();
    if crate::files::is_dir(bag) {
        candidates.push(bag.join(SETTING_FILE));
    }
    if let Some(parent) = bag.parent() {
        let parent = if parent.as_os_str().is_empty() {
            Path::new(".")
        } else {
            parent
        };
        candidates.push(parent.join(SETTING_FILE));
    }
    candidates.retain(|p| crate::files::is_file(p));
    candidates
}

/// Everything a bag's topics offer as a pose stream: each readable topic, and each frame of a
/// readable TF topic — its own child frames and those of `/tf_static`, since a static offset such as
/// `tool0 → tip` is reached through the topic's tree ([`super::tf_tree`]). `/tf_static` alone is
/// not offered (a chain without a moving link has no times). In topic order.
pub fn candidates(topics: &[TopicInfo]) -> Vec<TopicSpec> {
    let statics: &[String] = topics
        .iter()
        .find(|t| t.topic == TF_STATIC && t.pose_type() == Some(PoseType::TfMessage))
        .map_or(&[], |t| &t.child_frames);
    let mut specs = Vec::new();
    for info in topics {
        match info.pose_type() {
            None => {}
            Some(PoseType::TfMessage) if info.topic == TF_STATIC => {}
            Some(PoseType::TfMessage) => {
                let mut frames: Vec<&String> = info.child_frames.iter().collect();
                frames.extend(statics.iter().filter(|f| !info.child_frames.contains(f)));
                specs.extend(frames.into_iter().map(|frame| TopicSpec {
                    topic: info.topic.clone(),
                    child_frame: Some(frame.clone()),
                }));
            }
            Some(_) => specs.push(TopicSpec {
                topic: info.topic.clone(),
                child_frame: None,
            }),
        }
    }
    specs
}

/// Name parts that say "this is the pusher".
const PUSHER_WORDS: [&str; 9] = [
    "pusher", "probe", "finger", "tip", "tool", "ee", "eef", "effector", "robot",
];

/// Name parts that say "this is the object".
const OBJECT_WORDS: [&str; 8] = [
    "object", "obj", "box", "block", "puck", "target", "item", "slider",
];

/// What a spec's name says it is: pusher, object, both or neither.
fn roles(spec: &TopicSpec) -> (bool, bool) {
    let text = spec.to_string().to_ascii_lowercase();
    let words: Vec<&str> = text
        .split(|c: char| !c.is_ascii_alphabetic())
        .filter(|w| !w.is_empty())
        .collect();
    let says = |list: &[&str]| words.iter().any(|w| list.contains(w));
    (says(&PUSHER_WORDS), says(&OBJECT_WORDS))
}

/// The pusher and object pre-selected among a bag's readable streams: a stream is chosen for a role
/// when it is the only one whose name says that role and not the other; when one role is found so
/// and exactly two streams are readable, the other takes the other role. Otherwise nothing is
/// chosen for that role.
pub fn suggest(topics: &[TopicInfo]) -> (Option<TopicSpec>, Option<TopicSpec>) {
    let specs = candidates(topics);
    let only = |want_pusher: bool| {
        let mut matching = specs.iter().filter(|s| {
            let (pusher, object) = roles(s);
            if want_pusher {
                pusher && !object
            } else {
                object && !pusher
            }
        });
        match (matching.next(), matching.next()) {
            (Some(one), None) => Some(one.clone()),
            _ => None,
        }
    };
    let (mut pusher, mut object) = (only(true), only(false));
    if specs.len() == 2 {
        let other = |chosen: &TopicSpec| specs.iter().find(|s| *s != chosen).cloned();
        match (&pusher, &object) {
            (Some(p), None) => object = other(p),
            (None, Some(o)) => pusher = other(o),
            _ => {}
        }
    }
    (pusher, object)
}

/// The camera topics pre-selected when a bag is opened: those whose name says camera or image
/// (`/camera/color/image_raw/compressed`, `/overhead_cam/image`), since a bag may carry depth or
/// debug images nobody labels by.
pub fn suggest_cameras(topics: &[TopicInfo]) -> Vec<String> {
    (topics.iter())
        .filter(|t| t.is_camera())
        .filter(|t| {
            let name = t.topic.to_ascii_lowercase();
            ["cam", "image"].iter().any(|w| name.contains(w))
        })
        .map(|t| t.topic.clone())
        .collect()
}

#[cfg(test)]
mod tests;
