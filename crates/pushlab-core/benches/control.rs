//! The controller measured on goal–object pairs in pushlab's simulator (the sandbox's): each pair a
//! mystery object (hidden COM and `h` from its seed) and a goal drawn 20–40 cm away and up to ±45°
//! turned; every controller (`online`, `fixed`, `physics`, `truth`) on every pair. Prints the
//! success rate, the median time and pusher path to the goal, the final errors, and a control
//! step's cost (percentiles over every step of every run, each run on one core).
//!
//! `cargo bench -p pushlab-core --bench control -- --pairs 100 [--first 31]
//! [--object box|t|ellipse] [--noise] [--threads N] [--csv OUT.csv] [--way-weight W]
//! [--with online,weighted] [--track ALPHA,BETA] [--time-limit 120] [--lookahead]
//! [--planner-seed K]`
//!
//! The planner's weights were chosen on pairs 1-30 (`--first 1 --pairs 30`); the guide's table is
//! of pairs 31-130, which tuning never saw. `--track` plans from poses filtered for tracking
//! noise (`control::track`); `--lookahead` weighs the best pushes as the first of two
//! (`control::lookahead`, measured and left off); `--planner-seed K` draws the planner's samples
//! from another stream (the object and goal stay the pair's): the table's spread from the planner's
//! own randomness.

// The platform's sin, cos and hypot are fine for distances here; the core's own calls
// go through pushlab_core::math (its clippy.toml).
#![allow(clippy::disallowed_methods)]

use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

use pushlab_core::control::goal::pair_goal;
use pushlab_core::control::{Goal, PlanWith, PlannerConfig, SandboxControl};
use pushlab_core::learn::OnlineConfig;
use pushlab_core::model_file::ModelFile;
use pushlab_core::sandbox::mystery::SANDBOX_NOISE;
use pushlab_core::sandbox::{Mystery, MysteryObject};

struct Args {
    pairs: u64,
    /// The first pair's seed: the planner's weights were chosen on pairs 1-30, so the measured
    /// table starts at 31.
    first: u64,
    object: MysteryObject,
    noise: bool,
    threads: usize,
    csv: Option<String>,
    planner: PlannerConfig,
    /// The controllers run (`--with online,weighted`); all by default.
    with: Vec<PlanWith>,
    /// Seconds before a run is called failed.
    time_limit_s: f64,
    /// Added to each pair's seed for the planner's draws only (the object and goal stay the
    /// pair's): how much the planner's own randomness moves the table.
    planner_seed: u64,
}

fn args() -> Args {
    let mut a = Args {
        pairs: 100,
        first: 31,
        object: MysteryObject::Box,
        noise: false,
        threads: 2,
        csv: None,
        planner: PlannerConfig::default(),
        with: PlanWith::ALL.to_vec(),
        time_limit_s: 120.0,
        planner_seed: 0,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--pairs" => a.pairs = value(&mut it, &arg, "a count of pairs"),
            "--object" => a.object = value(&mut it, &arg, "box, t or ellipse"),
            "--noise" => a.noise = true,
            "--first" => a.first = value(&mut it, &arg, "the first pair's seed"),
            "--threads" => a.threads = value(&mut it, &arg, "a count of threads"),
            "--csv" => a.csv = Some(value(&mut it, &arg, "a file to write")),
            "--time-limit" => a.time_limit_s = value(&mut it, &arg, "seconds"),
            "--with" => {
                let names: String = value(&mut it, &arg, "controllers, comma-separated");
                a.with = (names.split(','))
                    .map(|n| {
                        PlanWith::from_name(n).unwrap_or_else(|| {
                            refuse(&format!(
                                "--with: '{n}' is none of {}",
                                PlanWith::expected()
                            ))
                        })
                    })
                    .collect();
            }
            "--way-weight" => a.planner.way_weight = value(&mut it, &arg, "metres per metre"),
            "--track" => {
                let text: String = value(&mut it, &arg, "ALPHA,BETA");
                match pushlab_core::control::track::TrackConfig::parse(&text) {
                    Ok(track) => a.planner.track = Some(track),
                    Err(why) => refuse(&format!("--track {why}")),
                }
            }
            "--keep-margin" => a.planner.keep_margin_m = value(&mut it, &arg, "metres"),
            "--lookahead" => a.planner.lookahead = true,
            "--planner-seed" => a.planner_seed = value(&mut it, &arg, "a seed"),
            "--help" | "-h" => {
                println!("{USAGE}");
                std::process::exit(0);
            }
            "--bench" => {} // cargo bench's own flag
            other => refuse(&format!("unknown argument '{other}'")),
        }
    }
    a
}

const USAGE: &str = "cargo bench -p pushlab-core --bench control -- --pairs 100 [--first 31] \
[--object box|t|ellipse] [--noise] [--threads N] [--csv OUT.csv] [--way-weight W] \
[--with online,weighted] [--track ALPHA,BETA] [--time-limit 120] [--keep-margin M] [--lookahead] [--planner-seed K]";

/// Says what is wrong with the arguments, with the usage, and exits 2: a typo must not measure
/// something else.
fn refuse(why: &str) -> ! {
    eprintln!("control bench: {why}\nusage: {USAGE}");
    std::process::exit(2)
}

/// The value after `flag`, parsed, or a refusal naming what was expected.
fn value<T: std::str::FromStr>(it: &mut impl Iterator<Item = String>, flag: &str, what: &str) -> T {
    let text = it.next().unwrap_or_default();
    text.parse()
        .unwrap_or_else(|_| refuse(&format!("{flag} '{text}': expected {what}")))
}

/// One run's numbers.
struct Row {
    pair: u64,
    with: PlanWith,
    reached: bool,
    time_s: f64,
    path_m: f64,
    position_m: f64,
    yaw_deg: f64,
    step_us: Vec<f64>,
    com_offset_m: f64,
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn percentile(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let args = args();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/default-model.json");
    let model = ModelFile::load(&path).expect("the bundled model").combined;
    let jobs: Mutex<Vec<(u64, PlanWith)>> = Mutex::new(
        (args.first..args.first + args.pairs)
            .flat_map(|p| args.with.iter().map(move |&w| (p, w)))
            .rev()
            .collect(),
    );
    let rows = Mutex::new(Vec::new());
    let started = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..args.threads.max(1) {
            s.spawn(|| {
                while let Some((pair, with)) = jobs.lock().expect("jobs").pop() {
                    let row = run(&model, &args, pair, with);
                    rows.lock().expect("rows").push(row);
                }
            });
        }
    });
    let mut rows = rows.into_inner().expect("rows");
    rows.sort_by_key(|r| (r.pair, r.with.name()));
    println!(
        "{} pairs (seeds {}-{}), {} object, noise {}, track {:?}, {:.0} s",
        args.pairs,
        args.first,
        args.first + args.pairs - 1,
        args.object,
        args.noise,
        args.planner.track,
        started.elapsed().as_secs_f64()
    );
    println!(
        "| plans with | reached | median time (s) | median pusher path (m) | median final error (mm, °) | step p50 / p99 / max (ms) |"
    );
    println!("|---|---|---|---|---|---|");
    for &with in &args.with {
        let mine: Vec<&Row> = rows.iter().filter(|r| r.with == with).collect();
        let reached = mine.iter().filter(|r| r.reached).count();
        let mut times: Vec<f64> = mine
            .iter()
            .filter(|r| r.reached)
            .map(|r| r.time_s)
            .collect();
        let mut paths: Vec<f64> = mine
            .iter()
            .filter(|r| r.reached)
            .map(|r| r.path_m)
            .collect();
        let mut pos: Vec<f64> = mine.iter().map(|r| r.position_m * 1e3).collect();
        let mut yaw: Vec<f64> = mine.iter().map(|r| r.yaw_deg.abs()).collect();
        let mut steps: Vec<f64> = mine
            .iter()
            .flat_map(|r| r.step_us.iter().copied())
            .collect();
        println!(
            "| {} | {}/{} ({:.0} %) | {:.1} | {:.2} | {:.1}, {:.2} | {:.2} / {:.2} / {:.2} |",
            with.name(),
            reached,
            mine.len(),
            100.0 * reached as f64 / mine.len().max(1) as f64,
            median(&mut times),
            median(&mut paths),
            median(&mut pos),
            median(&mut yaw),
            percentile(&mut steps, 0.5) / 1e3,
            percentile(&mut steps, 0.99) / 1e3,
            percentile(&mut steps, 1.0) / 1e3,
        );
    }
    for r in rows
        .iter()
        .filter(|r| !r.reached && std::env::var("FAILED").is_ok())
    {
        println!(
            "failed: pair {} {} error {:.1} mm {:.1}°",
            r.pair,
            r.with.name(),
            r.position_m * 1e3,
            r.yaw_deg
        );
    }
    if let Some(csv) = &args.csv {
        let mut out = String::from(
            "pair,plans_with,com_offset_m,reached,time_s,pusher_path_m,final_position_m,final_yaw_deg\n",
        );
        for r in &rows {
            out.push_str(&format!(
                "{},{},{:.4},{},{:.1},{:.4},{:.5},{:.3}\n",
                r.pair,
                r.with.name(),
                r.com_offset_m,
                r.reached,
                r.time_s,
                r.path_m,
                r.position_m,
                r.yaw_deg
            ));
        }
        std::fs::write(csv, out).expect("the CSV written");
    }
}

fn run(model: &pushlab_core::model::CombinedModel, args: &Args, pair: u64, with: PlanWith) -> Row {
    let mystery = Mystery::draw(pair, args.object.clone()).expect("a mystery");
    let goal = pair_goal(pair);
    let noise = args.noise.then_some(SANDBOX_NOISE);
    let mut control = SandboxControl::new(
        mystery,
        noise,
        model,
        with,
        OnlineConfig::default(),
        Goal::at(goal),
        args.planner.drawing_from(pair, args.planner_seed),
    )
    .expect("the controller on the mystery");
    let mut step_us = Vec::new();
    while !control.is_done() && control.outcome().time_s < args.time_limit_s {
        let t = Instant::now();
        let decision = control.decide();
        step_us.push(t.elapsed().as_secs_f64() * 1e6);
        control.carry_out(decision);
    }
    let outcome = control.outcome();
    Row {
        pair,
        with,
        reached: outcome.reached,
        time_s: outcome.time_s,
        path_m: outcome.pusher_path_m,
        position_m: outcome.final_position_error_m,
        yaw_deg: outcome.final_yaw_error_rad.to_degrees(),
        step_us,
        com_offset_m: {
            let [x, y] = control.sandbox().mystery().hidden.com_offset;
            x.hypot(y)
        },
    }
}
