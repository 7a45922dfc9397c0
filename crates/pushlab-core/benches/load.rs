//! Loading speed: all of `../shared/mit-push/` (skipped when absent) and a generated native set of
//! 100,000 samples. Targets (issue 3): well under 1 s and under 0.5 s.
//!
//! Run: `cargo bench -p pushlab-core --bench load`.

// The platform's sin, cos and hypot are fine for synthetic poses here; the core's own calls
// go through pushlab_core::math (its clippy.toml).
#![allow(clippy::disallowed_methods)]
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{Criterion, criterion_group, criterion_main};
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::{Setting, TrajectoryEntry, load_paths, write_set};
use pushlab_core::trajectory::{Frame, Trajectory};

const SAMPLES: usize = 100_000;
const TRAJECTORIES: usize = 10;

/// Writes a set of `SAMPLES` samples in `TRAJECTORIES` CSVs with realistic full-precision values.
fn native_set(dir: &Path) {
    let per = SAMPLES / TRAJECTORIES;
    let trajectories: Vec<Trajectory> = (0..TRAJECTORIES)
        .map(|k| {
            Trajectory::new(
                (0..per)
                    .map(|i| {
                        let t = i as f64 / 250.0;
                        Frame {
                            time: t,
                            robot: [0.3 + 0.01 * t + k as f64 * 1e-3, (t * 0.7).sin() * 0.01]
                                .into(),
                            object: Pose2::new(
                                0.35 + 0.01 * t,
                                (t * 0.3).cos() * 0.02,
                                0.1 * t.sqrt(),
                            ),
                        }
                    })
                    .collect(),
            )
        })
        .collect();
    let setting: Setting = serde_json::from_value(serde_json::json!({
        "name": "bench",
        "object": {"shape": "box", "width": 0.09, "length": 0.09},
        "pusher_radius": 0.005,
    }))
    .unwrap();
    let setting = Setting {
        trajectories: (0..TRAJECTORIES)
            .map(|k| TrajectoryEntry {
                file: format!("traj_{k:03}.csv"),
                contact_offset: None,
                push_angle_deg: None,
                extra: Default::default(),
            })
            .collect(),
        ..setting
    };
    write_set(dir, &setting, &trajectories).unwrap();
}

fn bench_load(c: &mut Criterion) {
    let mit = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/mit-push");
    if mit.is_dir() {
        let paths = [mit];
        c.bench_function("load all of shared/mit-push (4 files)", |b| {
            b.iter(|| {
                let report = load_paths(black_box(&paths));
                assert_eq!(report.recording_count(), 4);
                report
            })
        });
    } else {
        eprintln!("skipped: {} is absent (real MIT Push files)", mit.display());
    }

    let dir: PathBuf =
        std::env::temp_dir().join(format!("pushlab-bench-load-{}", std::process::id()));
    native_set(&dir);
    let paths = [dir.clone()];
    let mut group = c.benchmark_group("native");
    group.sample_size(20);
    group.bench_function("load a 100,000-sample set (10 CSVs)", |b| {
        b.iter(|| {
            let report = load_paths(black_box(&paths));
            assert_eq!(
                report.sets[0]
                    .recordings
                    .iter()
                    .map(|r| r.trajectory.len())
                    .sum::<usize>(),
                SAMPLES
            );
            report
        })
    });
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench_load);
criterion_main!(benches);
