//! LeRobot's `meta/info.json`: the codebase version (which layout the files follow), the frame
//! rate, where the parquet and video files are (`data_path`, `video_path`: Python format strings)
//! and the features — dtype and shape each. Read field by field, so that an error names the field
//! and what was expected.

use std::path::{Component, Path, PathBuf};

use serde_json::{Map, Value};

use super::super::error::DatasetError;
use super::super::problem::DatasetProblem;
use super::super::table::VideoFeature;
use crate::json_problem::JsonProblem;
use crate::recording::read::read_file;

/// Where the metadata is, relative to the dataset's folder.
pub const INFO_FILE: &str = "meta/info.json";

/// How the frames are laid out in parquet files.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// v2.x: one file per episode, `data/chunk-{episode_chunk}/episode_{episode_index}.parquet`,
    /// the episodes listed in `meta/episodes.jsonl`.
    FilePerEpisode,
    /// v3.0: episodes concatenated in `data/chunk-{chunk_index}/file-{file_index}.parquet`, which
    /// file each is in listed in `meta/episodes/chunk-…/file-….parquet`.
    ConcatenatedEpisodes,
}

/// The codebase versions read, and their layouts. v2.0 and v2.1 differ only in their statistics
/// files, which are not read.
pub const SUPPORTED: [(&str, Layout); 3] = [
    ("v2.0", Layout::FilePerEpisode),
    ("v2.1", Layout::FilePerEpisode),
    ("v3.0", Layout::ConcatenatedEpisodes),
];

/// The dtypes read as numbers; `bool` and `string` features are left out, images and videos are
/// listed as cameras.
const NUMERIC: [&str; 11] = [
    "float16", "float32", "float64", "int8", "int16", "int32", "int64", "uint8", "uint16",
    "uint32", "uint64",
];

/// A numeric feature as `meta/info.json` declares it.
#[derive(Clone, Debug, PartialEq)]
pub struct NumericFeature {
    pub name: String,
    pub dtype: String,
    pub shape: Vec<usize>,
    /// Values per frame: the product of the shape.
    pub width: usize,
}

impl NumericFeature {
    /// What a frame's cell should hold, for messages: `16 float32 values (shape [16] in
    /// meta/info.json)`.
    pub fn expected(&self) -> String {
        let shape: Vec<String> = self.shape.iter().map(usize::to_string).collect();
        format!(
            "{} {} value(s) (shape [{}] in {INFO_FILE})",
            self.width,
            self.dtype,
            shape.join(", ")
        )
    }
}

/// What `meta/info.json` says.
#[derive(Clone, Debug, PartialEq)]
pub struct Info {
    /// `codebase_version`, one of [`SUPPORTED`].
    pub version: String,
    pub layout: Layout,
    /// Frames per second.
    pub fps: f64,
    /// The parquet files' path template.
    pub data_path: String,
    /// Episodes per chunk folder (v2.x: which chunk an episode's file is in).
    pub chunks_size: usize,
    /// The numeric features, by name (as a replay buffer's arrays are, and whatever order the JSON
    /// map keeps).
    pub features: Vec<NumericFeature>,
    /// Image and video features: (name, what they are).
    pub cameras: Vec<(String, String)>,
    pub videos: Vec<VideoFeature>,
    /// The image features' names (their pictures are in the parquet files).
    pub images: Vec<String>,
    /// `total_episodes` and `total_frames` as written, when there: the files are read whatever
    /// they say, and a disagreement is noted ([`Info::disagreements`]).
    pub totals: Vec<(&'static str, Value)>,
}

impl Info {
    /// Notes on the totals that disagree with the `episodes` and `frames` the files hold.
    pub fn disagreements(&self, episodes: usize, frames: usize) -> Vec<String> {
        (self.totals.iter())
            .filter_map(|(key, said)| {
                let (held, what) = match *key {
                    "total_episodes" => (episodes, "episodes"),
                    _ => (frames, "frames"),
                };
                (said.as_u64() != u64::try_from(held).ok()).then(|| {
                    format!(
                        "{INFO_FILE} says {key} {said} but the files hold {held} {what}: the files \
                         are read"
                    )
                })
            })
            .collect()
    }
}

/// The `codebase_version` of the LeRobot dataset in `dir`, if `dir` holds one (whatever version).
pub fn version_of(dir: &Path) -> Option<String> {
    let path = dir.join(INFO_FILE);
    if !crate::files::is_file(&path) {
        return None;
    }
    let value: Value = serde_json::from_slice(&crate::files::read(&path).ok()?).ok()?;
    value.get("codebase_version")?.as_str().map(str::to_owned)
}

/// Reads and checks `dir`'s `meta/info.json`.
pub fn read(dir: &Path) -> Result<Info, DatasetError> {
    let path = dir.join(INFO_FILE);
    let bytes = read_file(&path)?;
    let fail = |problem| DatasetError::Problem {
        path: path.clone(),
        problem,
    };
    let value: Value = serde_json::from_slice(&bytes)
        .map_err(|e| fail(DatasetProblem::Json(JsonProblem::of(&e))))?;
    parse(&value).map_err(fail)
}

fn field(field: &str, why: impl Into<String>) -> DatasetProblem {
    DatasetProblem::Field {
        field: field.into(),
        why: why.into(),
    }
}

/// A field that must be there.
fn required<'a>(
    object: &'a Map<String, Value>,
    name: &str,
    path: &str,
    expected: &str,
) -> Result<&'a Value, DatasetProblem> {
    object
        .get(name)
        .filter(|v| !v.is_null())
        .ok_or_else(|| field(path, format!("missing, expected {expected}")))
}

fn parse(value: &Value) -> Result<Info, DatasetProblem> {
    let object = value
        .as_object()
        .ok_or_else(|| field(".", "not an object, expected LeRobot's dataset info"))?;
    let versions: Vec<&str> = SUPPORTED.iter().map(|(v, _)| *v).collect();
    let expected_version = format!("one of {}", versions.join(", "));
    let version = required(
        object,
        "codebase_version",
        "codebase_version",
        &expected_version,
    )?;
    let version = version.as_str().unwrap_or_default();
    let layout = (SUPPORTED.iter())
        .find(|(v, _)| *v == version)
        .map(|(_, layout)| *layout)
        .ok_or_else(|| {
            field(
                "codebase_version",
                format!("\"{version}\", pushlab reads LeRobot datasets {expected_version}"),
            )
        })?;
    let fps = required(object, "fps", "fps", "the frames per second")?;
    let fps = fps
        .as_f64()
        .filter(|f| f.is_finite() && *f > 0.0)
        .ok_or_else(|| {
            field(
                "fps",
                format!("{fps}, expected a positive number of frames per second"),
            )
        })?;
    let data_path = text(object, "data_path", "the parquet files' path template")?;
    let chunks_size = match layout {
        Layout::FilePerEpisode => {
            let size = required(object, "chunks_size", "chunks_size", "episodes per chunk")?;
            size.as_u64()
                .filter(|&n| n > 0)
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| {
                    field(
                        "chunks_size",
                        format!("{size}, expected a positive whole number"),
                    )
                })?
        }
        Layout::ConcatenatedEpisodes => 0,
    };
    let features = required(object, "features", "features", "the dataset's features")?
        .as_object()
        .ok_or_else(|| field("features", "not an object, expected features by name"))?;
    let mut info = Info {
        version: version.to_owned(),
        layout,
        fps,
        data_path,
        chunks_size,
        features: Vec::new(),
        cameras: Vec::new(),
        videos: Vec::new(),
        images: Vec::new(),
        totals: (["total_episodes", "total_frames"].into_iter())
            .filter_map(|key| Some((key, object.get(key)?.clone())))
            .collect(),
    };
    for (name, feature) in features {
        let at = |key: &str| format!("features.{name}.{key}");
        let feature = feature.as_object().ok_or_else(|| {
            field(
                &format!("features.{name}"),
                "not an object, expected dtype and shape",
            )
        })?;
        let dtype = required(feature, "dtype", &at("dtype"), "the feature's type")?;
        let dtype = dtype
            .as_str()
            .ok_or_else(|| field(&at("dtype"), format!("{dtype}, expected a type name")))?;
        let numeric = NUMERIC.contains(&dtype);
        if !(numeric || matches!(dtype, "video" | "image")) {
            continue;
        }
        let shape = shape(required(
            feature,
            "shape",
            &at("shape"),
            "the feature's shape",
        )?)
        .map_err(|why| field(&at("shape"), why))?;
        let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
        match dtype {
            "video" => {
                let template = text(
                    object,
                    "video_path",
                    &format!("the videos' path template, since feature `{name}` is a video"),
                )?;
                info.cameras
                    .push((name.clone(), format!("video {}", dims.join("×"))));
                let size_px = frame_size(&shape, feature.get("names"))
                    .map_err(|why| field(&at("shape"), why))?;
                info.videos.push(VideoFeature {
                    name: name.clone(),
                    path_template: template,
                    size_px,
                    episodes: Vec::new(),
                });
            }
            "image" => {
                info.cameras.push((
                    name.clone(),
                    format!("images {} in parquet", dims.join("×")),
                ));
                info.images.push(name.clone());
            }
            _ => info.features.push(NumericFeature {
                name: name.clone(),
                dtype: dtype.to_owned(),
                width: shape.iter().product(),
                shape,
            }),
        }
    }
    info.features.sort_by(|a, b| a.name.cmp(&b.name));
    info.cameras.sort();
    info.videos.sort_by(|a, b| a.name.cmp(&b.name));
    info.images.sort();
    Ok(info)
}

/// A video's frame size, (width, height) pixels, from its shape: the dimensions its `names` call
/// `height` and `width`, else LeRobot's usual order, height × width × channels.
fn frame_size(shape: &[usize], names: Option<&Value>) -> Result<(u32, u32), String> {
    let named = |wanted: &str| {
        let names = names?.as_array()?;
        let at = names.iter().position(|n| n.as_str() == Some(wanted))?;
        shape.get(at).copied()
    };
    let (width, height) = match (named("width"), named("height"), shape) {
        (Some(width), Some(height), _) => (width, height),
        (_, _, [height, width, 1 | 3 | 4]) => (*width, *height),
        _ => {
            return Err(format!(
                "{shape:?}, expected a video's height × width × channels (or `names` saying \
                 which is the height and the width)"
            ));
        }
    };
    let side = |n: usize| u32::try_from(n).map_err(|_| format!("a side of {n} pixels"));
    Ok((side(width)?, side(height)?))
}

fn text(object: &Map<String, Value>, name: &str, expected: &str) -> Result<String, DatasetProblem> {
    let value = required(object, name, name, expected)?;
    value
        .as_str()
        .map(str::to_owned)
        .ok_or_else(|| field(name, format!("{value}, expected {expected} as text")))
}

/// A shape: positive whole numbers; values per frame is their product.
fn shape(value: &Value) -> Result<Vec<usize>, String> {
    let bad = || format!("{value}, expected a list of positive whole numbers such as [2]");
    let dims = value.as_array().ok_or_else(bad)?;
    let shape: Vec<usize> = (dims.iter())
        .map(|d| {
            d.as_u64()
                .filter(|&n| n > 0)
                .and_then(|n| usize::try_from(n).ok())
        })
        .collect::<Option<_>>()
        .ok_or_else(bad)?;
    let width = shape.iter().try_fold(1usize, |w, &d| w.checked_mul(d));
    match width {
        Some(w) if w <= 1 << 20 => Ok(shape),
        _ => Err(format!("{value}, too many values per frame")),
    }
}

/// The file that `template` (the info's `data_path` or `video_path`, `name`) names with these
/// fields, inside the dataset's folder `dir`. A dataset downloaded from a hub is not trusted: a
/// template whose expansion leaves the folder (a `..`, an absolute path, or a symbolic link that
/// points out of it) is refused naming the field, and nothing outside is opened.
pub fn file_in(
    dir: &Path,
    template: &str,
    name: &str,
    values: &[(&str, usize)],
) -> Result<PathBuf, DatasetProblem> {
    let relative = fill_template(template, name, values)?;
    let inside = Path::new(&relative)
        .components()
        .all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
    let path = dir.join(&relative);
    // A link is followed only to check where it lands; a file that is not there is left for the
    // reader to name.
    let linked_out = match (
        crate::files::canonicalize(dir),
        crate::files::canonicalize(&path),
    ) {
        (Ok(root), Ok(target)) => !target.starts_with(root),
        _ => false,
    };
    if !inside || linked_out {
        return Err(field(
            name,
            format!(
                "\"{template}\" gives \"{relative}\", which leaves the dataset's folder (by `..`, an \
                 absolute path or a symbolic link out); a dataset's files must be inside it"
            ),
        ));
    }
    Ok(path)
}

/// `template` with its `{key}` and `{key:03d}` fields filled from `values`, as Python's
/// `str.format` does for LeRobot's path templates; `name` is the template's field, for errors.
pub fn fill_template(
    template: &str,
    name: &str,
    values: &[(&str, usize)],
) -> Result<String, DatasetProblem> {
    let mut out = String::with_capacity(template.len() + 8);
    let mut rest = template;
    while let Some(open) = rest.find('{') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let close = after
            .find('}')
            .ok_or_else(|| field(name, format!("\"{template}\": a `{{` without its `}}`")))?;
        let (key, spec) = after[..close]
            .split_once(':')
            .unwrap_or((&after[..close], ""));
        let value = (values.iter())
            .find(|(k, _)| *k == key)
            .map(|(_, v)| *v)
            .ok_or_else(|| {
                let keys: Vec<String> = values.iter().map(|(k, _)| format!("{{{k}}}")).collect();
                field(
                    name,
                    format!(
                        "\"{template}\": unknown field {{{key}}}, expected {}",
                        keys.join(", ")
                    ),
                )
            })?;
        let digits = spec.strip_suffix('d').unwrap_or(spec);
        let width = if digits.is_empty() {
            Some(0)
        } else {
            digits
                .strip_prefix('0')
                .unwrap_or(digits)
                .parse::<usize>()
                .ok()
        };
        match width {
            Some(width) if spec.is_empty() || spec.ends_with('d') => {
                out.push_str(&format!("{value:0width$}"));
            }
            _ => {
                return Err(field(
                    name,
                    format!("\"{template}\": format `{spec}` of {{{key}}}, expected such as `03d`"),
                ));
            }
        }
        rest = &after[close + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn path_templates_fill_as_python_formats_them() {
        let template = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet";
        let path = fill_template(
            template,
            "data_path",
            &[("episode_chunk", 1), ("episode_index", 1042)],
        );
        assert_eq!(path, Ok("data/chunk-001/episode_001042.parquet".into()));
        assert_eq!(
            fill_template("a/{x}.b", "p", &[("x", 7)]),
            Ok("a/7.b".into())
        );
        let error = fill_template(template, "data_path", &[("chunk_index", 0)]).expect_err("keys");
        assert!(
            error
                .to_string()
                .contains("unknown field {episode_chunk}, expected {chunk_index}"),
            "{error}"
        );
        assert!(fill_template("{x:3f}", "p", &[("x", 1)]).is_err());
        assert!(fill_template("{x", "p", &[("x", 1)]).is_err());
    }

    #[test]
    fn a_template_that_leaves_the_dataset_is_refused_naming_the_field() {
        let dir = std::env::temp_dir().join(format!("pushlab-template-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("data")).expect("dir");
        let fields = [("episode_index", 3)];
        let inside = file_in(
            &dir,
            "data/e_{episode_index:03d}.parquet",
            "data_path",
            &fields,
        );
        assert_eq!(inside, Ok(dir.join("data/e_003.parquet")));
        for template in [
            "../../../../etc/episode_{episode_index:06d}.parquet",
            "data/../../e_{episode_index}.parquet",
            "/etc/e_{episode_index}.parquet",
        ] {
            let error = file_in(&dir, template, "data_path", &fields).expect_err(template);
            let message = error.to_string();
            assert!(
                message.starts_with("field `data_path`: \"")
                    && message.contains("which leaves the dataset's folder"),
                "{message}"
            );
        }
        #[cfg(unix)]
        {
            let outside = dir.with_extension("outside");
            std::fs::create_dir_all(&outside).expect("outside");
            std::fs::write(outside.join("e_3.mp4"), b"x").expect("file");
            let _ = std::fs::remove_file(dir.join("videos"));
            std::os::unix::fs::symlink(&outside, dir.join("videos")).expect("link");
            let error = file_in(&dir, "videos/e_{episode_index}.mp4", "video_path", &fields)
                .expect_err("a link out");
            assert!(
                error.to_string().starts_with("field `video_path`"),
                "{error}"
            );
            let _ = std::fs::remove_dir_all(&outside);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn an_unknown_version_names_the_supported_ones() {
        let value = serde_json::json!({"codebase_version": "v1.6", "fps": 10});
        let error = parse(&value).expect_err("v1.6");
        assert_eq!(
            error.to_string(),
            "field `codebase_version`: \"v1.6\", pushlab reads LeRobot datasets one of v2.0, \
             v2.1, v3.0"
        );
    }
}
