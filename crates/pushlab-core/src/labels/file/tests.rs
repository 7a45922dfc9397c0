#![allow(clippy::unwrap_used)]

use std::time::Duration;

use super::super::schema::names::*;
use super::super::{Event, RecordingMeta, Segment, Split};
use super::*;
use crate::atomic_file::{SaveStage, write_with_interrupt};
use crate::recording::PushSide;
use std::fs;

/// A fresh empty folder under the target directory's temp space.
pub(crate) fn temp_folder(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("pushlab-labels-test-{name}-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

pub(crate) fn sample_set() -> LabelSet {
    let mut set = LabelSet::default();
    set.recordings.insert(
        "push_000.csv".into(),
        RecordingLabels {
            meta: RecordingMeta {
                object: "rect1".into(),
                material: "abs".into(),
                com_offset: Some([0.0125, -0.004]),
                push_side: Some(PushSide::Left),
                split: Some(Split::Offline),
                notes: "pusher \"wobbles\" near the end\nsecond line".into(),
            },
            segments: vec![
                Segment::new(CONTACT, 3..90),
                Segment::new(STICKING, 3..40),
                Segment::new(SLIPPING, 40..90),
                Segment::new(BAD_TRACKING, 70..75),
            ],
            events: vec![
                Event {
                    label: CONTACT_MADE.into(),
                    frame: 3,
                },
                Event {
                    label: CONTACT_LOST.into(),
                    frame: 90,
                },
            ],
        },
    );
    set.recordings.insert(
        "push_001.csv".into(),
        RecordingLabels {
            meta: RecordingMeta {
                split: Some(Split::HeldOut),
                ..Default::default()
            },
            ..Default::default()
        },
    );
    set.normalise_and_validate().unwrap();
    set
}

#[test]
fn set_round_trips_through_the_file() {
    let set = sample_set();
    let text = to_json(&set);
    assert!(text.starts_with("{\n  \"format\": \"pushlab-labels\",\n  \"version\": 1,"));
    let back = parse(&text, Path::new("x.json")).unwrap();
    assert_eq!(back, set);
    // Writing the read-back set gives the same bytes: saving is stable.
    assert_eq!(to_json(&back), text);
}

#[test]
fn custom_schema_round_trips() {
    use super::super::schema::{LabelDef, LabelKind, Rgb};
    let mut set = LabelSet::default();
    set.schema.labels = vec![
        LabelDef {
            hotkey: Some("F2".into()),
            group: Some("wheel".into()),
            ..LabelDef::range("rolling", Rgb::new(1, 2, 3))
        },
        LabelDef {
            group: Some("wheel".into()),
            skip_in_training: true,
            ..LabelDef::range("skidding", Rgb::new(0xff, 0, 0x80))
        },
        LabelDef::event("bump", Rgb::new(0, 0, 0)),
    ];
    set.recordings.insert(
        "r.json".into(),
        RecordingLabels {
            segments: vec![
                Segment::new("rolling", 0..5),
                Segment::new("skidding", 5..9),
            ],
            events: vec![Event {
                label: "bump".into(),
                frame: 5,
            }],
            ..Default::default()
        },
    );
    let text = to_json(&set);
    assert!(text.contains("\"colour\": \"#ff0080\""), "{text}");
    let back = parse(&text, Path::new("l.json")).unwrap();
    assert_eq!(back, set);
    assert_eq!(back.schema.get("bump").unwrap().kind, LabelKind::Event);
    assert!(back.schema.excludes("rolling", "skidding"));
    // The default schema's labels are unknown to this file.
    let err = parse(
        &text.replace("\"label\": \"rolling\"", "\"label\": \"sticking\""),
        Path::new("l.json"),
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("unknown label \"sticking\""),
        "{err}"
    );
}

#[test]
fn opening_a_broken_file_reports_it() {
    let dir = temp_folder("broken");
    let path = path_in(&dir);
    fs::write(
        &path,
        "{\"format\": \"pushlab-labels\", \"version\": 1, \"recordings\": {\n",
    )
    .unwrap();
    let err = super::super::LabelDocument::open(&path)
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with(&format!(
            "{}: line 2, column 0: EOF while parsing",
            path.display()
        )),
        "{err}"
    );
}

#[test]
fn file_round_trips_through_disk() {
    let dir = temp_folder("disk");
    let path = path_in(&dir);
    assert_eq!(read_or_default(&path).unwrap(), LabelSet::default());
    write(&path, &sample_set()).unwrap();
    assert_eq!(read(&path).unwrap(), sample_set());
    let leftovers: Vec<_> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers, vec![std::ffi::OsString::from(LABELS_FILE_NAME)]);
}

#[test]
fn minimal_file_gets_the_default_schema() {
    let text = r#"{"format": "pushlab-labels", "version": 1,
        "recordings": {"a.csv": {"meta": {"split": "online"}}}}"#;
    let set = parse(text, Path::new("l.json")).unwrap();
    assert_eq!(set.schema, LabelSchema::default());
    assert_eq!(set.split_of("a.csv"), Some(Split::Online));
}

fn error_of(text: &str) -> String {
    parse(text, Path::new("/data/set/pushlab-labels.json"))
        .unwrap_err()
        .to_string()
}

#[test]
fn malformed_json_names_file_line_and_column() {
    let msg = error_of("{\n  \"format\": \"pushlab-labels\",\n  \"version\": 1,,\n}");
    assert_eq!(
        msg,
        "/data/set/pushlab-labels.json: line 3, column 16: key must be a string"
    );
    let msg = error_of(
        "{\"format\": \"pushlab-labels\", \"version\": 1,\n \"recordings\": {\"a.csv\": {\"meta\": {\"split\": \"train\"}}}}",
    );
    // The field first, then where it is.
    assert!(
        msg.starts_with(
            "/data/set/pushlab-labels.json: recordings.a.csv.meta.split: unknown variant `train`"
        ),
        "{msg}"
    );
    assert!(msg.contains("offline"), "{msg}");
    assert!(msg.ends_with("(line 2, column 51)"), "{msg}");
    let msg = error_of(
        "{\"format\": \"pushlab-labels\", \"version\": 1, \"recordings\": {\"a.csv\": {\"segmnts\": []}}}",
    );
    assert!(msg.contains("unknown field `segmnts`"), "{msg}");
}

#[test]
fn newer_and_unknown_versions_fail_naming_both_versions() {
    let msg = error_of(r#"{"format": "pushlab-labels", "version": 2, "recordings": {}}"#);
    assert_eq!(
        msg,
        "/data/set/pushlab-labels.json: labels file version 2 is not supported: this pushlab \
         reads versions 1 to 1 (it was written by a newer pushlab; update pushlab to read it)"
    );
    let msg = error_of(r#"{"format": "pushlab-labels", "version": 0}"#);
    assert!(msg.contains("version 0 is not supported"), "{msg}");
    assert!(msg.contains("no pushlab ever wrote this version"), "{msg}");
    let msg = error_of(r#"{"format": "pushlab-labels", "version": "1"}"#);
    assert!(msg.contains("version \"1\" is not supported"), "{msg}");
    assert!(msg.contains("whole number"), "{msg}");
    let msg = error_of(r#"{"format": "pushlab-labels"}"#);
    assert!(msg.contains("version missing"), "{msg}");
}

#[test]
fn other_json_files_are_refused_by_format() {
    let msg = error_of(r#"{"frames": []}"#);
    assert_eq!(
        msg,
        "/data/set/pushlab-labels.json: not a pushlab labels file: expected \"format\": \
         \"pushlab-labels\", found no \"format\" field"
    );
    let msg = error_of(r#"{"format": "pushlab-model", "version": 1}"#);
    assert!(msg.ends_with("found \"pushlab-model\""), "{msg}");
}

#[test]
fn rule_violations_name_the_field() {
    let msg = error_of(
        r#"{"format": "pushlab-labels", "version": 1, "recordings": {"a.csv": {"segments": [
            {"label": "sticking", "start": 0, "end": 10},
            {"label": "slidng", "start": 10, "end": 20}]}}}"#,
    );
    assert!(
        msg.starts_with("/data/set/pushlab-labels.json: recordings.\"a.csv\".segments[1].label: unknown label \"slidng\""),
        "{msg}"
    );
    let msg = error_of(
        r#"{"format": "pushlab-labels", "version": 1, "recordings": {"a.csv": {"segments": [
            {"label": "sticking", "start": 0, "end": 10},
            {"label": "slipping", "start": 5, "end": 20}]}}}"#,
    );
    assert!(msg.contains("recordings.\"a.csv\".segments: \"sticking\" (frames 0..10) and \"slipping\" (frames 5..20) overlap"), "{msg}");
    let msg = error_of(
        r#"{"format": "pushlab-labels", "version": 1, "recordings": {"a.csv": {"segments": [
            {"label": "sticking", "start": 10, "end": 10}]}}}"#,
    );
    assert!(
        msg.contains("segments[0].end: a segment must end after it starts"),
        "{msg}"
    );
    let msg = error_of(
        r#"{"format": "pushlab-labels", "version": 1, "recordings": {"a.csv": {"events": [
            {"label": "sticking", "frame": 3}]}}}"#,
    );
    assert!(
        msg.contains("events[0].label: \"sticking\" is a range label, expected a point event"),
        "{msg}"
    );
}

#[test]
fn hand_written_touching_segments_are_merged_on_load() {
    let set = parse(
        r#"{"format": "pushlab-labels", "version": 1, "recordings": {"a.csv": {"segments": [
            {"label": "sticking", "start": 10, "end": 20},
            {"label": "sticking", "start": 0, "end": 10}]}}}"#,
        Path::new("l.json"),
    )
    .unwrap();
    assert_eq!(
        set.recordings["a.csv"].segments,
        vec![Segment::new(STICKING, 0..20)]
    );
}

#[test]
fn failed_save_leaves_the_old_file_and_no_temporary() {
    let dir = temp_folder("interrupt");
    let path = path_in(&dir);
    write(&path, &sample_set()).unwrap();
    let old = fs::read(&path).unwrap();
    let mut changed = sample_set();
    changed.recordings.remove("push_000.csv");
    let err = write_with_interrupt(&path, to_json(&changed).as_bytes(), &mut |stage| {
        assert_eq!(stage, SaveStage::TempWritten);
        // The temporary file is complete at this point: a valid new file beside the old one.
        let temps: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p != &path)
            .collect();
        assert_eq!(temps.len(), 1);
        assert_eq!(read(&temps[0]).unwrap(), changed);
        Err(io::Error::other("simulated crash before rename"))
    })
    .unwrap_err();
    assert!(err.to_string().contains("simulated crash"));
    assert_eq!(fs::read(&path).unwrap(), old);
    assert_eq!(
        fs::read_dir(&dir).unwrap().count(),
        1,
        "temporary file left behind"
    );
}

#[test]
fn save_error_names_the_file_and_keeps_the_old_one() {
    let dir = temp_folder("readonly");
    let path = dir.join("missing-folder").join(LABELS_FILE_NAME);
    let msg = write(&path, &sample_set()).unwrap_err().to_string();
    assert!(msg.starts_with("cannot save labels to "), "{msg}");
    assert!(msg.contains("missing-folder/pushlab-labels.json"), "{msg}");
    assert!(msg.ends_with("the previous file is unchanged"), "{msg}");
}

const CHILD_ENV: &str = "PUSHLAB_LABELS_CHILD_SAVER";

/// Run as a child process by `killed_saves_leave_old_or_new_file`: saves two different label
/// sets alternately into the folder named by the environment, as fast as it can, until killed.
/// Without the variable (a normal test run) it returns at once.
#[test]
fn child_saver() {
    let Some(dir) = std::env::var_os(CHILD_ENV) else {
        return;
    };
    let path = path_in(Path::new(&dir));
    let (a, b) = two_versions();
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    while std::time::Instant::now() < deadline {
        write(&path, &a).unwrap();
        write(&path, &b).unwrap();
    }
}

/// Two label sets whose files differ a lot in size, so a torn write would be detectable.
fn two_versions() -> (LabelSet, LabelSet) {
    let a = sample_set();
    let mut b = sample_set();
    for i in 0..200 {
        b.recordings.insert(
            format!("push_{i:03}_extra.csv"),
            RecordingLabels {
                segments: vec![Segment::new(STICKING, i..i + 50)],
                ..Default::default()
            },
        );
    }
    (a, b)
}

/// Kills a process that is saving in a loop at many moments; after each kill the labels file
/// must parse and be exactly one of the two versions being saved.
#[test]
fn killed_saves_leave_old_or_new_file() {
    let dir = temp_folder("kill");
    let path = path_in(&dir);
    let (a, b) = two_versions();
    write(&path, &a).unwrap();
    let exe = std::env::current_exe().unwrap();
    let mut seen_b = false;
    for round in 0..25u64 {
        let mut child = std::process::Command::new(&exe)
            .args([
                "--exact",
                "labels::file::tests::child_saver",
                "--nocapture",
                "--test-threads=1",
            ])
            .env(CHILD_ENV, &dir)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Vary the moment of the kill: 20 to 80 ms into the child's life.
        std::thread::sleep(Duration::from_millis(20 + (round * 37) % 61));
        child.kill().unwrap();
        child.wait().unwrap();
        let on_disk = read(&path).unwrap_or_else(|e| panic!("round {round}: {e}"));
        assert!(
            on_disk == a || on_disk == b,
            "round {round}: unexpected content"
        );
        seen_b |= on_disk == b;
    }
    assert!(
        seen_b,
        "the child never completed a save; the test did not exercise anything"
    );
}
