//! MIT Push Dataset import: the real files in `../shared/mit-push/` (skipped when absent) and
//! synthetic files with known contents and known defects.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::skip;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::mit_push::{self, import_bytes, parse_file_name};
use pushlab_core::recording::{MitError, MitProblem, ObjectShape, load_paths};

fn mit_dir() -> Option<PathBuf> {
    skip::shared(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        "mit-push",
    )
}

#[test]
fn all_four_real_files_load_with_their_known_defects() {
    let Some(dir) = mit_dir() else { return };
    let report = load_paths(std::slice::from_ref(&dir));
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.recording_count(), 4);
    let names: Vec<&str> = report
        .sets
        .iter()
        .map(|s| s.setting.name.as_str())
        .collect();
    assert_eq!(
        names,
        [
            "mit-abs-ellip1",
            "mit-abs-hex",
            "mit-abs-rect1",
            "mit-plywood-hex"
        ]
    );
    for set in &report.sets {
        assert_eq!(set.setting.pusher_radius, 0.00475);
        assert_eq!(set.setting.pusher_friction, Some(0.25));
        assert_eq!(set.setting.h, None);
        assert_eq!(set.setting.sample_rate_hz, Some(250.0));
        let outline = set.setting.object.outline().expect("valid outline");
        assert!(outline.centroid().coords.norm() < 1e-9, "outline centred");
        for r in &set.recordings {
            let speed = r.entry.as_ref().unwrap().extra["mit_speed_mm_s"]
                .as_f64()
                .unwrap();
            let t = &r.trajectory;
            // Every push moves the pusher 50 mm; the recording covers at least the push.
            let travel = (t.frames[t.len() - 1].robot - t.frames[0].robot).norm();
            assert!(
                (0.045..0.055).contains(&travel),
                "{}: pusher travel {travel}",
                r.name
            );
            assert!(
                t.duration() >= 0.05 / (speed / 1000.0),
                "{}: {}",
                r.name,
                t.duration()
            );
            assert!(
                t.duration() < 0.05 / (speed / 1000.0) + 1.5,
                "{}: {}",
                r.name,
                t.duration()
            );
            assert!((t.mean_rate_hz() - 250.0).abs() < 1e-6);
            // The object starts about one object-radius plus pusher radius from the pusher.
            let gap = (t.frames[0].robot - t.frames[0].object.position).norm();
            assert!(
                (0.03..0.1).contains(&gap),
                "{}: pusher–object distance {gap}",
                r.name
            );
            // Times strictly increase and poses are finite.
            assert!(t.frames.windows(2).all(|w| w[1].time > w[0].time));
        }
    }
    let rect1 = &report.sets[2].recordings[0];
    assert_eq!(
        rect1.setting.object,
        ObjectShape::Polygon {
            vertices: vec![
                [0.045, 0.045],
                [-0.045, 0.045],
                [-0.045, -0.045],
                [0.045, -0.045]
            ]
        }
    );
    // A pose dropped is a warning; a frozen force sensor, which pushlab does not read, a note.
    assert_eq!(
        rect1.warnings,
        [
            "object_pose: 1 timestamp(s) step backwards (worst -0.1 ms); 1 row(s) out of order dropped"
        ]
    );
    let notes = rect1.notes.join("\n");
    assert!(
        notes.contains("ft_wrench is frozen: 287 of 293 rows"),
        "{notes}"
    );
    // Three rows apart of 295 is how the dataset's sensors start and stop: not a defect.
    assert!(!notes.contains("streams start or stop"), "{notes}");
    let entry = rect1.entry.as_ref().unwrap();
    assert!((entry.push_angle_deg.unwrap() - 0.349f64.to_degrees()).abs() < 1e-9);
    assert_eq!(entry.extra["mit_side"], 2.0);
    assert_eq!(entry.extra["mit_side_position"], 0.8);
    assert_eq!(rect1.setting.material.as_deref(), Some("abs"));
    // The other files' force streams are live.
    for set in [&report.sets[0], &report.sets[1], &report.sets[3]] {
        assert!(!set.recordings[0].notes.join(" ").contains("frozen"));
    }
}

#[test]
fn a_single_real_json_and_h5_load_on_their_own() {
    let Some(dir) = mit_dir() else { return };
    let json = dir.join("motion_surface=plywood_shape=hex_a=0_v=150_i=1.000_s=0.000_t=-0.349.json");
    let h5 = dir.join("motion_surface=abs_shape=ellip1_a=0_v=20_i=0.000_s=0.675_t=0.349.h5");
    let report = load_paths(&[json, h5]);
    assert!(report.errors.is_empty(), "{:?}", report.errors);
    assert_eq!(report.sets.len(), 2);
    // 3.0 s of ellip1 at 250 Hz; first raw tip sample is at (0.406988, -0.000604298).
    let ellip = &report.sets[0].recordings[0];
    assert_eq!(ellip.trajectory.len(), 754);
    assert!((ellip.trajectory.frames[0].robot - Point2::new(0.406988, -0.000604298)).norm() < 1e-4);
}

#[test]
fn file_names_parse_into_parameters() {
    let n = parse_file_name(
        "motion_surface=pu_shape=tri2_a=-1000_v=10_i=1.500_s=0.250_t=-0.698_rep=0003",
    )
    .unwrap();
    assert_eq!(n.surface, "pu");
    assert_eq!(n.shape, "tri2");
    assert_eq!(n.accel_mm_s2, -1000.0);
    assert_eq!(n.speed_mm_s, 10.0);
    assert_eq!(n.side, 1.5);
    assert_eq!(n.side_position, 0.25);
    assert_eq!(n.angle_rad, -0.698);
    assert_eq!(n.rep, Some(3));
    for bad in [
        "surface=abs",
        "motion_surface=abs_shape=rect1_a=0_v=x_i=0_s=0_t=0",
        "motion_surface=abs_shape=rect1",
        "motion_surface=abs_shape=rect1_a=0_v=1_i=0_s=0_t=0_rep=x",
    ] {
        let err = parse_file_name(bad).unwrap_err();
        assert!(matches!(err, MitProblem::FileName { .. }), "{bad}: {err}");
    }
}

#[test]
fn all_eleven_shapes_ship_with_pushlab() {
    for name in [
        "rect1", "rect2", "rect3", "tri1", "tri2", "tri3", "ellip1", "ellip2", "ellip3", "hex",
        "butter",
    ] {
        let shape = mit_push::shape(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(shape.outline.centroid().coords.norm() < 1e-12, "{name}");
        let size = shape.outline.size();
        assert!((0.08..0.2).contains(&size), "{name}: size {size}");
    }
    let rect3 = mit_push::shape("rect3").unwrap();
    let (min, max) = rect3.outline.bounding_box();
    assert!(((max - min) - Vector2::new(0.13501, 0.08994)).norm() < 1e-9);
    let ellip3 = mit_push::shape("ellip3").unwrap();
    assert!((ellip3.outline.area() - PI * 0.0525 * 0.0785).abs() < 0.01 * PI * 0.0525 * 0.0785);
    // A right triangle with legs 125.9 mm and 125.87 mm; its centroid sits a third of the way in
    // from the right-angle corner, which is at (45, 45) mm in the dataset's frame.
    let tri1 = mit_push::shape("tri1").unwrap();
    let corner = Vector2::new(0.045, 0.045);
    let expected = corner + Vector2::new(-0.1259, -0.12587) / 3.0;
    assert!((tri1.centroid_in_mit_frame - expected).norm() < 1e-9);
    assert!((tri1.outline.area() - 0.5 * 0.1259 * 0.12587).abs() < 1e-12);
    assert!(mit_push::shape("triangle").is_err());
}

/// Rows `[t, a, b, c]` as JSON.
fn rows(rows: &[[f64; 4]]) -> serde_json::Value {
    serde_json::Value::Array(rows.iter().map(|r| serde_json::json!(r)).collect())
}

struct Synthetic {
    tip: Vec<[f64; 4]>,
    object: Vec<[f64; 4]>,
    force: Vec<[f64; 4]>,
}

impl Synthetic {
    /// A push at 250 Hz for `n` samples with streams offset in time; the object slides along x and
    /// turns at 0.5 rad/s starting from `yaw0`; its frame's origin follows `x = 0.3 + 0.02 t`.
    fn new(n: usize, yaw0: f64) -> Self {
        let t0 = 1_461_697_707.0;
        let tip = (0..n).map(|i| {
            let t = t0 + i as f64 * 0.004;
            [t, 0.25 + 0.02 * (t - t0), 0.01, 0.0]
        });
        let object = (0..n).map(|i| {
            let t = t0 - 0.001 + i as f64 * 0.004;
            [
                t,
                0.3 + 0.02 * (t - t0),
                -0.02,
                mit_wrap(yaw0 + 0.5 * (t - t0)),
            ]
        });
        let force = (0..n).map(|i| [t0 + i as f64 * 0.004 + 0.002, (i as f64).sin(), 0.1, 0.0]);
        Self {
            tip: tip.collect(),
            object: object.collect(),
            force: force.collect(),
        }
    }

    fn json(&self) -> Vec<u8> {
        serde_json::to_vec(&serde_json::json!({
            "tip_pose": rows(&self.tip), "object_pose": rows(&self.object), "ft_wrench": rows(&self.force)
        }))
        .unwrap()
    }

    fn h5(&self) -> Vec<u8> {
        let mut builder = hdf5_pure::FileBuilder::new();
        for (key, rows) in [
            ("tip_pose", &self.tip),
            ("object_pose", &self.object),
            ("ft_wrench", &self.force),
        ] {
            let flat: Vec<f64> = rows.iter().flatten().copied().collect();
            builder
                .create_dataset(key)
                .with_f64_data(&flat)
                .with_shape(&[rows.len() as u64, 4]);
        }
        builder.finish().unwrap()
    }
}

/// The dataset's yaw convention: (−π, π].
fn mit_wrap(a: f64) -> f64 {
    pushlab_core::geometry::wrap_angle(a)
}

const TRI_NAME: &str = "motion_surface=delrin_shape=tri1_a=0_v=20_i=0.000_s=0.500_t=0.000";

#[test]
fn triangle_poses_move_to_the_footprint_centroid() {
    let synthetic = Synthetic::new(200, 1.0);
    for (bytes, ext) in [(synthetic.json(), "json"), (synthetic.h5(), "h5")] {
        let path = PathBuf::from(format!("{TRI_NAME}.{ext}"));
        let push = import_bytes(&bytes, &path).unwrap_or_else(|e| panic!("{e}"));
        let centroid = mit_push::shape("tri1").unwrap().centroid_in_mit_frame;
        assert!(
            centroid.norm() > 0.004,
            "the triangle's frame is off its centroid"
        );
        let t0 = 1_461_697_707.0;
        assert!((push.start_unix_s - t0).abs() < 1e-6);
        for frame in &push.trajectory.frames {
            let t = frame.time; // seconds since t0
            let yaw = 1.0 + 0.5 * t;
            let origin = Pose2::new(0.3 + 0.02 * t, -0.02, yaw);
            let expected = origin.point_in_world(Point2::from(centroid));
            assert!(
                (frame.object.position - expected).norm() < 1e-7,
                "{ext} t={t}"
            );
            assert!((frame.object.yaw - yaw).abs() < 1e-6);
            assert!((frame.robot - Point2::new(0.25 + 0.02 * t, 0.01)).norm() < 1e-7);
        }
        // Grid: 4 ms steps over the overlap of tip and object streams.
        assert_eq!(push.trajectory.len(), 199);
        assert!((push.trajectory.frames[1].time - 0.004).abs() < 1e-12);
        assert!(push.warnings.is_empty(), "{:?}", push.warnings);
    }
}

#[test]
fn defects_are_reported_with_numbers() {
    // Yaw crossing ±π, object stamps stepping back, a tracking gap, a frozen force stream and
    // unequal stream lengths.
    let mut s = Synthetic::new(300, PI - 0.2);
    s.object[50][0] = s.object[49][0] - 0.0019;
    s.object[80][0] = s.object[79][0] - 0.0005;
    s.object.drain(150..170); // 84 ms gap
    s.tip.truncate(280); // stops 80 ms before the object, 82 ms before the force stream
    for row in &mut s.force {
        row[1] = 1.9e-21;
        row[2] = -1.9e-21;
        row[3] = 0.0;
    }
    let path = PathBuf::from(format!("{TRI_NAME}.json"));
    let push = import_bytes(&s.json(), &path).unwrap();
    // Rows dropped and a gap interpolated across are warnings: the frames are not all the file had.
    let w = push.warnings.join("\n");
    assert!(w.contains("object_pose: 2 timestamp(s) step backwards (worst -1.9 ms); 2 row(s) out of order dropped"), "{w}");
    assert!(
        w.contains("object_pose: 1 gap(s) over 50 ms (longest 84.0 ms)"),
        "{w}"
    );
    assert_eq!(push.warnings.len(), 2);
    // An angle unwrapped, a sensor pushlab does not read, streams put on one clock: notes.
    let n = push.notes.join("\n");
    assert!(
        n.contains("object yaw wraps at ±π 1 time(s); unwrapped"),
        "{n}"
    );
    assert!(n.contains("ft_wrench is frozen: 299 of 299 rows"), "{n}");
    assert!(
        n.contains("streams start or stop up to 82.0 ms apart (tip_pose 280, object_pose 280, ft_wrench 300 rows)"),
        "{n}"
    );
    assert_eq!(push.notes.len(), 3);
    // Yaw is continuous through the wrap and through the gap.
    let thetas: Vec<f64> = push
        .trajectory
        .frames
        .iter()
        .map(|f| f.object.yaw)
        .collect();
    assert!(
        thetas.windows(2).all(|w| (w[1] - w[0]).abs() < 0.01),
        "yaw jumps"
    );
    assert!(thetas.last().unwrap() > &PI);
}

fn mit_error(bytes: &[u8], name: &str) -> (MitError, String) {
    let err = import_bytes(bytes, Path::new(name)).unwrap_err();
    let text = err.to_string();
    (err, text)
}

#[test]
fn unusable_files_are_refused_naming_file_and_problem() {
    let json_name = format!("{TRI_NAME}.json");
    let h5_name = format!("{TRI_NAME}.h5");

    let s = Synthetic::new(5, 0.0);
    let (_, e) = mit_error(&s.json(), &json_name);
    assert_eq!(
        e,
        format!("{json_name}: `tip_pose` has only 5 usable rows, expected at least 10")
    );

    let mut s = Synthetic::new(100, 0.0);
    s.object[7][2] = f64::NAN;
    let (err, e) = mit_error(&s.h5(), &h5_name);
    assert!(matches!(
        err,
        MitError::Problem {
            problem: MitProblem::NonFinite {
                key: "object_pose",
                row: 7,
                column: 2,
                ..
            },
            ..
        }
    ));
    assert_eq!(
        e,
        format!("{h5_name}: `object_pose` row 7 column 2 is NaN, expected a finite number")
    );

    let (_, e) = mit_error(br#"{"tip_pose": [], "object_pose": []}"#, &json_name);
    assert_eq!(
        e,
        format!(
            "{json_name}: missing `ft_wrench`, expected the three streams tip_pose, object_pose and ft_wrench"
        )
    );

    let (_, e) = mit_error(
        br#"{"tip_pose": [[1, 2, 3]], "object_pose": [], "ft_wrench": []}"#,
        &json_name,
    );
    assert!(
        e.starts_with(&format!(
            "{json_name}: not valid JSON for an MIT push: invalid length 3"
        )),
        "{e}"
    );

    let (_, e) = mit_error(b"", &json_name);
    assert!(e.contains("not valid JSON"), "{e}");
    let (_, e) = mit_error(b"\x89HDF\r\n\x1a\n", &h5_name);
    assert!(
        e.starts_with(&format!("{h5_name}: not a readable HDF5 file")),
        "{e}"
    );

    // An HDF5 file without one of the datasets.
    let mut builder = hdf5_pure::FileBuilder::new();
    builder
        .create_dataset("tip_pose")
        .with_f64_data(&[0.0; 8])
        .with_shape(&[2, 4]);
    let (_, e) = mit_error(&builder.finish().unwrap(), &h5_name);
    assert!(e.contains("missing `object_pose`"), "{e}");
    // A dataset of the wrong shape.
    let mut builder = hdf5_pure::FileBuilder::new();
    for key in ["tip_pose", "object_pose", "ft_wrench"] {
        builder
            .create_dataset(key)
            .with_f64_data(&[0.0; 9])
            .with_shape(&[3, 3]);
    }
    let (_, e) = mit_error(&builder.finish().unwrap(), &h5_name);
    assert_eq!(
        e,
        format!("{h5_name}: `tip_pose` has shape [3, 3], expected N x 4 float64")
    );

    // Streams that do not overlap.
    let mut s = Synthetic::new(100, 0.0);
    for row in &mut s.object {
        row[0] += 10.0;
    }
    let (_, e) = mit_error(&s.json(), &json_name);
    assert!(e.contains("overlap for only 0.000 s"), "{e}");

    let s = Synthetic::new(100, 0.0);
    let (_, e) = mit_error(
        &s.json(),
        "motion_surface=abs_shape=star_a=0_v=1_i=0_s=0_t=0.json",
    );
    assert!(e.contains("unknown shape 'star'"), "{e}");
    let (_, e) = mit_error(&s.json(), "push.json");
    assert!(
        e.starts_with("push.json: file name is not an MIT Push Dataset name"),
        "{e}"
    );
}

#[test]
fn mit_files_in_one_folder_group_by_surface_and_shape() {
    let dir = std::env::temp_dir().join(format!("pushlab-mit-group-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let s = Synthetic::new(60, 0.0);
    for name in [
        "motion_surface=abs_shape=rect1_a=0_v=10_i=0.000_s=0.500_t=0.000.json",
        "motion_surface=abs_shape=rect1_a=0_v=20_i=0.000_s=0.500_t=0.000.h5",
        "motion_surface=pu_shape=rect1_a=0_v=10_i=0.000_s=0.500_t=0.000.json",
    ] {
        let bytes = if name.ends_with("h5") {
            s.h5()
        } else {
            s.json()
        };
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    std::fs::write(
        dir.join("motion_surface=abs_shape=rect1_a=0_v=30_i=0.000_s=0.500_t=0.000.json"),
        "{",
    )
    .unwrap();
    std::fs::write(dir.join("shapes.json"), "{}").unwrap();
    let report = load_paths(std::slice::from_ref(&dir));
    assert_eq!(report.sets.len(), 2);
    assert_eq!(report.sets[0].recordings.len(), 2);
    assert_eq!(report.sets[0].setting.trajectories.len(), 2);
    assert_eq!(report.sets[1].setting.material.as_deref(), Some("pu"));
    assert_eq!(
        report.errors.len(),
        1,
        "only the broken MIT file, not shapes.json"
    );
    assert!(report.errors[0].to_string().contains("v=30"));
}
