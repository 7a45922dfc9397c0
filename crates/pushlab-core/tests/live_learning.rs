//! Learning as a live session's frames arrive against the replay of its recording: a push of the
//! sample data sent as a robot would send it (the pusher as JSON, the object as CDR PoseStamped 3 ms
//! later, the object's stamps jittered, a message lost, one repeated out of order, the yaw crossing
//! ±π), learned from by `LiveLearner` message by message while `Recorder` writes every message, as
//! `pushlab live` does. The recording imported at the same rate and learned on by the run `pushlab
//! eval` makes must give the same θ, spread and losses at every frame the session learned, to the
//! bit, and the session must have learned all but the frames the import adds at the end.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use pushlab_core::experiment::{TrajectoryRun, UsedRecording};
use pushlab_core::learn::{OnlineConfig, Optimizer};
use pushlab_core::live::{Channel, LiveLearner, PoseReading, Recorder, Stream};
use pushlab_core::model_file::ModelFile;
use pushlab_core::recording::Setting;
use pushlab_core::recording::bag::{self, BagChoice, ImportOptions, SettingSource};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `[t, robot x, robot y, object x, object y, object yaw]` of a sample-data push.
fn push_rows() -> Vec<[f64; 6]> {
    let text =
        std::fs::read_to_string(repo().join("sample-data/box1-paper-ur-front/online_000.csv"))
            .unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        })
        .collect()
}

fn channel(id: u64, topic: &str, encoding: &str, schema: &str) -> Channel {
    Channel {
        id,
        topic: topic.into(),
        encoding: encoding.into(),
        schema_name: schema.into(),
        schema: String::new(),
        schema_encoding: Some(
            if encoding == "json" {
                "jsonschema"
            } else {
                "ros2msg"
            }
            .into(),
        ),
    }
}

fn json_pose(stamp: u64, x: f64, y: f64) -> Vec<u8> {
    format!(
        r#"{{"header":{{"stamp":{{"sec":{},"nanosec":{}}}}},"pose":{{"position":{{"x":{x},"y":{y},"z":0}},"orientation":{{"x":0,"y":0,"z":0,"w":1}}}}}}"#,
        stamp / 1_000_000_000,
        stamp % 1_000_000_000
    )
    .into_bytes()
}

/// Every message of the session in the order it arrives: channel, log time, payload.
fn session(rows: &[[f64; 6]]) -> Vec<(u64, u64, Vec<u8>)> {
    let base = 1_700_000_000_000_000_000u64;
    let ns = |t: f64| (t * 1e9).round() as u64;
    let mut messages = Vec::new();
    for (k, r) in rows.iter().enumerate() {
        let stamp = base + ns(r[0]);
        messages.push((1, stamp, json_pose(stamp, r[1], r[2])));
        if k == 40 {
            continue; // lost
        }
        // Jittered by up to ±1 ms, 3 ms after the pusher; the yaw turned to cross ±π.
        let jitter = [0i64, 700_000, -400_000, 1_000_000][k % 4];
        let object_stamp = (stamp as i64 + 3_000_000 + jitter) as u64;
        let yaw = (r[5] + PI - 2.8 + PI).rem_euclid(2.0 * PI) - PI;
        let payload = bag::encode_pose_stamped(object_stamp, "table", r[3], r[4], yaw);
        messages.push((2, object_stamp, payload.clone()));
        if k == 60 {
            // Sent again late: a stamp that does not increase, dropped by both.
            messages.push((2, object_stamp, payload));
        }
    }
    messages
}

#[test]
fn a_live_session_learns_what_the_replay_of_its_recording_learns_to_the_bit() {
    let model = ModelFile::load(&repo().join("assets/default-model.json")).unwrap();
    let setting_path = repo().join("sample-data/box1-paper-ur-front/setting.json");
    let setting: Setting = SettingSource::File(setting_path.clone()).resolve().unwrap();
    let rate = 10.0;
    let channels = [
        channel(1, "/pusher", "json", "pushlab.Pose"),
        channel(2, "/object", "cdr", "geometry_msgs/msg/PoseStamped"),
    ];
    let readings = channels
        .each_ref()
        .map(|c| PoseReading::for_channel(c, None).unwrap());

    for optimizer in [Optimizer::Gd, Optimizer::GaussNewton] {
        let config = OnlineConfig {
            optimizer,
            ..OnlineConfig::default()
        };
        let dir = std::env::temp_dir().join(format!(
            "pushlab-live-learning-{}-{optimizer:?}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("session.mcap");

        // The session: every message recorded and learned from as it arrives.
        let mut recorder = Recorder::create(&out).unwrap();
        let mut learner = LiveLearner::new(&model.combined, &setting, config, rate).unwrap();
        let mut frontiers = Vec::new();
        for (channel, log_time, payload) in session(&push_rows()) {
            let slot = usize::try_from(channel - 1).unwrap();
            recorder.write(&channels[slot], log_time, &payload).unwrap();
            let pose = readings[slot].read_single(&payload).unwrap().unwrap();
            let stream = [Stream::Pusher, Stream::Object][slot];
            let _ = learner.take(stream, &pose, log_time);
            learner.learn();
            frontiers.push(learner.run().frontier());
        }
        recorder.finish().unwrap();
        let live = learner.run();
        assert_eq!(learner.refused().out_of_order, [0, 1], "the repeated one");
        assert!(
            frontiers.windows(2).any(|w| w[1] > w[0]) && frontiers[frontiers.len() / 2] > 0,
            "learning went on while the messages arrived"
        );

        // The replay: the recording imported at the same rate, learned by eval's run.
        let choice = BagChoice {
            pusher: "/pusher".parse().unwrap(),
            object: "/object".parse().unwrap(),
            setting: SettingSource::File(setting_path.clone()),
            options: ImportOptions {
                rate_hz: Some(rate),
                split_gap_s: None,
            },
            cameras: Vec::new(),
        };
        let set = bag::open(&out, &choice).unwrap();
        let recording = set.recordings.into_iter().next().unwrap();
        let frames = recording.trajectory.len();
        let used = UsedRecording::new(recording, None, Vec::new());
        let replay = TrajectoryRun::learn(&model.combined, &used, 0, &config).unwrap();
        let replay = &replay.run;

        let learned = live.frontier();
        assert!(
            learned + 2 >= replay.frontier() && learned <= replay.frontier() && learned > 50,
            "{optimizer:?}: the session learned {learned} of the replay's {} samples ({frames} frames)",
            replay.frontier()
        );
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for frame in 0..=learned {
            let (a, b) = (live.theta_at(frame), replay.theta_at(frame));
            assert_eq!(
                bits(&[a.com_offset[0], a.com_offset[1], a.h]),
                bits(&[b.com_offset[0], b.com_offset[1], b.h]),
                "{optimizer:?}: θ at frame {frame}"
            );
            assert_eq!(
                live.spread_at(frame),
                replay.spread_at(frame),
                "σ at {frame}"
            );
        }
        assert_eq!(live.learned(), &replay.learned()[..learned]);
        assert_eq!(live.fixed(), &replay.fixed()[..live.fixed().len()]);
        let start = live.theta_at(0);
        let end = live.theta_at(learned);
        assert!(
            (end.com_offset[0] - start.com_offset[0]).abs()
                + (end.com_offset[1] - start.com_offset[1]).abs()
                > 1e-4,
            "{optimizer:?}: θ moved: {start:?} → {end:?}"
        );
        // Predicted ahead from every frame, and scored once the frame came.
        let frames_seen = live.trajectory().len();
        let (ahead_frame, _) = learner.ahead().expect("a prediction ahead");
        assert_eq!(ahead_frame, frames_seen - 1 + live.horizon());
        let score = learner.ahead_score();
        assert_eq!(score.predictions, frames_seen - 2 * live.horizon());
        assert!(
            score.mean_position_m > 0.0 && score.mean_position_m < 0.03,
            "{optimizer:?}: {score:?}"
        );
        assert!(
            score.baseline_position_m > 0.0 && score.baseline_yaw_rad > 0.0,
            "{score:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
