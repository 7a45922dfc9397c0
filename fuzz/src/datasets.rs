//! The dataset readers' promises: a Push-T fixture folder (`crates/pushlab-core/tests/pusht/`)
//! copied once to a temporary folder, one of its files replaced by the fuzzer's bytes, and the
//! whole dataset read, turned into recordings with Push-T's pre-selection and, for a replay
//! buffer's images, a frame read and decoded. A fuzz input is one file of the fixture: its path in
//! `tests/pusht/`, a newline, then its bytes (`fuzz/run` writes each fixture file so as a seed), so
//! that every reader is reached with the other files intact.
//!
//! The promise: an error or a dataset whose table covers its frames and whose recordings keep
//! theirs (time strictly increasing, finite values); never a panic, a hang or an allocation of
//! what a corrupt length claims. Shared with `crates/pushlab-core/tests/datasets_fuzz_seeds.rs`,
//! which includes this file to keep the promise over the seeds on stable Rust: it uses `std` and
//! `pushlab_core` only.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, Once, OnceLock, PoisonError};

use pushlab_core::recording::camera::decode;
use pushlab_core::recording::dataset::{self, blosc, choice};
use pushlab_core::recording::{NoProgress, RecordingSet};
use pushlab_core::trajectory::Frame;

/// The replay buffer's folder in `tests/pusht/`.
pub const ZARR: &[&str] = &["replay.zarr"];
/// The LeRobot datasets' folders in `tests/pusht/`, one of each layout.
pub const LEROBOT: &[&str] = &["lerobot-v2.1", "lerobot-v3.0"];

/// LeRobot v2's list of episodes, in the dataset's folder.
const EPISODES_JSONL: &str = "meta/episodes.jsonl";

/// A blosc frame whose header claims more plain bytes than this is not decoded on its own.
const BLOSC_ALONE_MAX: usize = 1 << 22;

/// The Push-T fixtures: `crates/pushlab-core/tests/pusht/`, found from the crate that builds this
/// file (the fuzz crate or pushlab-core).
pub fn fixtures() -> PathBuf {
    let pusht = Path::new("crates/pushlab-core/tests/pusht");
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .map(|dir| dir.join(pusht))
        .find(|dir| dir.is_dir())
        .expect("the Push-T fixtures in crates/pushlab-core/tests/pusht")
}

/// Every file of `folders` the readers may read (videos are decoded by ffmpeg, not read here), by
/// its path in `tests/pusht/`, with its bytes.
pub fn fixture_files(folders: &[&str]) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, files: &mut BTreeMap<String, Vec<u8>>) {
        for entry in std::fs::read_dir(dir).expect("a fixture folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(root, &path, files);
            } else if path.extension().is_none_or(|e| e != "mp4") {
                let name = path.strip_prefix(root).expect("inside").to_string_lossy();
                let bytes = std::fs::read(&path).expect("a fixture file");
                files.insert(name.replace('\\', "/"), bytes);
            }
        }
    }
    let root = fixtures();
    let mut files = BTreeMap::new();
    for folder in folders {
        walk(&root, &root.join(folder), &mut files);
    }
    files
}

/// A fixture file as a fuzz input: its name, a newline, its bytes.
pub fn as_input(name: &str, bytes: &[u8]) -> Vec<u8> {
    let mut input = format!("{name}\n").into_bytes();
    input.extend_from_slice(bytes);
    input
}

/// A copy of fixture folders in a temporary folder, removed when dropped.
pub struct FixtureCopy {
    root: PathBuf,
    originals: BTreeMap<String, Vec<u8>>,
}

impl FixtureCopy {
    /// `folders` of `tests/pusht/` copied (less their videos).
    pub fn of(folders: &[&str]) -> Self {
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let root = std::env::temp_dir().join(format!(
            "pushlab-fuzz-{}-{}-{}",
            folders.join("+"),
            std::process::id(),
            COUNT.fetch_add(1, Ordering::Relaxed)
        ));
        let originals = fixture_files(folders);
        for (name, bytes) in &originals {
            let path = root.join(name);
            std::fs::create_dir_all(path.parent().expect("a parent")).expect("a temporary folder");
            std::fs::write(&path, bytes).expect("a temporary file");
        }
        Self { root, originals }
    }

    /// `read` on the copy with the file that `input` names holding the rest of `input`, then the
    /// file restored; `None` when `input` names no file of the copy. `read` is given the copy, the
    /// file's name and its bytes.
    fn with_input<T>(&self, input: &[u8], read: impl FnOnce(&Self, &str, &[u8]) -> T) -> Option<T> {
        let newline = input.iter().take(100).position(|&b| b == b'\n')?;
        let name = std::str::from_utf8(&input[..newline]).ok()?;
        self.originals.get(name)?;
        let bytes = &input[newline + 1..];
        self.write(name, bytes);
        let result = read(self, name, bytes);
        self.restore(name);
        Some(result)
    }

    fn write(&self, name: &str, bytes: &[u8]) {
        std::fs::write(self.root.join(name), bytes).expect("write a file of the copy");
    }

    fn restore(&self, name: &str) {
        self.write(name, &self.originals[name]);
    }
}

impl Drop for FixtureCopy {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.root);
    }
}

/// What a dataset read promises: the table covers its frames, and each recording's time is
/// strictly increasing and its values finite. Returns the recordings.
fn read_dataset(dir: &Path) -> Option<RecordingSet> {
    let table = dataset::read_table(dir, &NoProgress).ok()?;
    let frames = table.episodes.last().map_or(0, |e| e.end);
    assert!(
        table.episodes.first().is_none_or(|e| e.start == 0)
            && table.episodes.windows(2).all(|w| w[0].end == w[1].start),
        "episodes {:?} do not follow each other",
        table.episodes
    );
    for feature in &table.features {
        assert_eq!(
            feature.values.len(),
            feature.width * frames,
            "{}",
            feature.name
        );
    }
    if let Some(times) = &table.times {
        assert_eq!(times.len(), frames);
    }
    let choice = choice::suggest(&table)?;
    let set = dataset::to_set(dir, &table, &choice, None).ok()?;
    assert_eq!(set.recordings.len(), table.episodes.len());
    for recording in &set.recordings {
        let frames = &recording.trajectory.frames;
        let later =
            |w: &[Frame]| w[1].time.partial_cmp(&w[0].time) == Some(std::cmp::Ordering::Greater);
        if let Some(k) = frames.windows(2).position(|w| !later(w)) {
            panic!(
                "{}: time not strictly increasing: frame {k} at {} s, frame {} at {} s",
                recording.name,
                frames[k].time,
                k + 1,
                frames[k + 1].time
            );
        }
        assert!(
            frames.iter().all(|f| {
                f.time.is_finite()
                    && f.object.yaw.is_finite()
                    && f.object.position.iter().all(|c| c.is_finite())
                    && f.robot.iter().all(|c| c.is_finite())
            }),
            "{}: a value not finite",
            recording.name
        );
    }
    Some(set)
}

/// The zarr replay buffer reader (`.zarray` metadata, blosc, zstd and LZ4 chunks, `episode_ends`)
/// on a copy of `tests/pusht/replay.zarr/` with one file replaced, and the file on its own as a
/// blosc frame of the size it claims. Returns the episodes read.
pub fn zarr_in(copy: &FixtureCopy, input: &[u8]) -> Option<usize> {
    copy.with_input(input, |copy, name, bytes| {
        let claimed = bytes.get(4..8).map_or(0, |b| {
            u32::from_le_bytes(b.try_into().expect("4 bytes")) as usize
        });
        if claimed <= BLOSC_ALONE_MAX
            && let Ok(plain) = blosc::decompress(bytes, claimed)
        {
            assert_eq!(plain.len(), claimed);
        }
        let set = read_dataset(&copy.root.join("replay.zarr"))?;
        // An image chunk (or the images' `.zarray`): the frame at its first row (the fixture's
        // chunks hold 32 rows) read and decoded.
        if let Some(image) = name.strip_prefix("replay.zarr/data/img/") {
            let chunk: usize = image.split('.').next()?.parse().unwrap_or(0);
            let mut row = chunk * 32;
            for recording in &set.recordings {
                if row < recording.trajectory.len() {
                    for camera in &recording.cameras {
                        if let Ok(frame) = camera.reader().read(row)
                            && let Ok(image) = decode(&frame)
                        {
                            let (w, h) = (image.width as usize, image.height as usize);
                            assert_eq!(image.pixels.len(), 4 * w * h);
                        }
                    }
                    break;
                }
                row -= recording.trajectory.len();
            }
        }
        Some(set.recordings.len())
    })?
}

/// The LeRobot reader (`meta/info.json`, `meta/episodes.jsonl`, v3.0's episode metadata and the
/// data files, parquet rows) on a copy of `tests/pusht/lerobot-v2.1/` and `lerobot-v3.0/` with one
/// file replaced. Returns the episodes read.
pub fn lerobot_in(copy: &FixtureCopy, input: &[u8]) -> Option<usize> {
    let_the_reader_catch_parquet_panics();
    copy.with_input(input, |copy, name, _| {
        let folder = name.split('/').next()?;
        // A v2 episode's data file is read with that episode alone listed: what the other seven
        // files would add is the same every time, and slows the fuzzer eightfold.
        let listing = format!("{folder}/{EPISODES_JSONL}");
        let alone = (name.strip_prefix(&format!("{folder}/data/")))
            .and_then(|file| file.rsplit_once("episode_")?.1.strip_suffix(".parquet"))
            .and_then(|index| index.parse::<usize>().ok())
            .and_then(|index| {
                let listed = std::str::from_utf8(copy.originals.get(&listing)?).ok()?;
                let key = format!("\"episode_index\": {index},");
                listed.lines().find(|line| line.contains(&key))
            });
        if let Some(line) = alone {
            copy.write(&listing, line.as_bytes());
        }
        let read = read_dataset(&copy.root.join(folder)).map(|set| set.recordings.len());
        if alone.is_some() {
            copy.restore(&listing);
        }
        read
    })?
}

/// The parquet crate panics on some corrupt data, and the LeRobot reader catches that as the file's
/// error (`parquet_rows::append_file`); libFuzzer's panic hook would abort first. So a panic raised
/// in a crate from the registry is left to unwind to that catch, named once per place on stderr; a
/// panic nobody catches still ends in libfuzzer-sys's own catch, which aborts, and a panic in
/// pushlab's code goes to the hook as before.
fn let_the_reader_catch_parquet_panics() {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        let seen: Mutex<BTreeSet<String>> = Mutex::new(BTreeSet::new());
        std::panic::set_hook(Box::new(move |info| {
            let Some(place) = info
                .location()
                .filter(|l| l.file().contains("/registry/src/"))
            else {
                return previous(info);
            };
            let place = place.to_string();
            let mut seen = seen.lock().unwrap_or_else(PoisonError::into_inner);
            if seen.insert(place.clone()) {
                eprintln!("a panic for the reader to catch, at {place}");
            }
        }));
    });
}

/// [`zarr_in`] on this process's copy.
pub fn zarr(input: &[u8]) -> Option<usize> {
    static COPY: OnceLock<FixtureCopy> = OnceLock::new();
    zarr_in(COPY.get_or_init(|| FixtureCopy::of(ZARR)), input)
}

/// [`lerobot_in`] on this process's copy.
pub fn lerobot(input: &[u8]) -> Option<usize> {
    static COPY: OnceLock<FixtureCopy> = OnceLock::new();
    lerobot_in(COPY.get_or_init(|| FixtureCopy::of(LEROBOT)), input)
}
