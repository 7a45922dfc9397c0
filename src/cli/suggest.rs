//! `pushlab suggest`: an object's next pushes ranked by how much each is expected to shrink the
//! COM's uncertainty (the core's `experiment::suggest`), after the pushes already learned; with
//! `--measure-orders N`, the measurement of the ranking: the object's pushes learned in the ranked
//! order, the worst and `N` random orders, the COM error after each.

use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::atomic_file::write_atomically;
use pushlab_core::experiment::suggest::{
    self, Choice, Criterion, LearnedPush, ObjectPushes, PushGrid, Ranking,
};
use pushlab_core::experiment::{self, UsedRecording};
use pushlab_core::learn::OnlineConfig;
use pushlab_core::model::CombinedModel;
use pushlab_core::recording::{PushSide, Recording};
use serde_json::json;

use crate::cli::exit::Failure;
use crate::cli::experiment::args::{OnlineArgs, positive, positive_real};
use crate::cli::model_arg::load_model;

/// The pushes after which `--measure-orders` reports the COM error.
const AFTER: [usize; 5] = [1, 2, 3, 5, 9];

#[derive(Debug, Args)]
pub struct SuggestArgs {
    /// Recording sets, files or folders holding the object's pushes: the candidates.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// The object: its setting's name, or the end of it (`rect1` for `mit-abs-rect1`); needed
    /// when the recordings push more than one.
    #[arg(long, value_name = "NAME")]
    pub object: Option<String>,
    /// The model to predict with (default: the app's, assets/default-model.json).
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<PathBuf>,
    /// Pushes already learned, in order (recording names, comma-separated): θ and the posterior go
    /// on from them, as `pushlab eval --carry-theta` carries them, and they are not suggested.
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    pub after: Vec<String>,
    /// How the COM's uncertainty is measured: `area` (the COM ellipse's area), `spread` (the mean
    /// COM variance, the expected squared error) or `axis` (the ellipse's longest axis).
    #[arg(long, value_name = "CRITERION", default_value_t = Criterion::default())]
    pub criterion: Criterion,
    /// Rank a grid of pushes laid out on the object instead of its recordings: every side of
    /// --grid-sides × --grid-offsets × --grid-angles, each a straight push --grid-length long at the
    /// recordings' pusher speed and frame rate.
    #[arg(long)]
    pub grid: bool,
    /// The grid's sides [default: front,left,back,right].
    #[arg(
        long,
        value_name = "SIDE,...",
        value_delimiter = ',',
        requires = "grid"
    )]
    pub grid_sides: Option<Vec<PushSide>>,
    /// The grid's contact offsets, as fractions of each face's half length (−1 to 1)
    /// [default: -0.6,0,0.6].
    #[arg(
        long,
        value_name = "F,...",
        value_delimiter = ',',
        allow_negative_numbers = true,
        requires = "grid"
    )]
    pub grid_offsets: Option<Vec<f64>>,
    /// The grid's push angles from the face's normal, degrees, counter-clockwise positive
    /// [default: -20,0,20].
    #[arg(
        long,
        value_name = "DEG,...",
        value_delimiter = ',',
        allow_negative_numbers = true,
        requires = "grid"
    )]
    pub grid_angles: Option<Vec<f64>>,
    /// How far each grid push goes once it touches, metres [default: 0.1].
    #[arg(long, value_name = "M", value_parser = positive_real, requires = "grid")]
    pub grid_length: Option<f64>,
    /// Print only the best N.
    #[arg(long, value_name = "N", value_parser = positive)]
    pub top: Option<usize>,
    /// Measure the ranking instead: learn the object's pushes one after another, θ carried, in the
    /// ranked order, the worst order and N random orders, and report the COM error after 1, 2, 3,
    /// 5 and 9 pushes (the recordings must know the true COM).
    #[arg(long, value_name = "N", value_parser = positive)]
    pub measure_orders: Option<usize>,
    /// Seeds the random orders of --measure-orders.
    #[arg(long, value_name = "S", default_value_t = 0)]
    pub seed: u64,
    /// Write the ranking (or the measurement) as JSON.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    // How θ learns, as in `pushlab eval`.
    #[command(flatten)]
    pub online: OnlineArgs,
}

/// Runs `pushlab suggest`.
pub fn run(args: &SuggestArgs) -> Result<(), Failure> {
    let (file, model_name) = load_model(args.model.as_deref())?;
    let model = file.combined;
    let loaded = experiment::load(&args.paths, None, model.horizon());
    for skipped in &loaded.skipped {
        eprintln!("skipped {}", skipped.message());
    }
    if loaded.used.is_empty() {
        return Err(Failure::Failed(anyhow!(
            "nothing usable in the paths given: {}",
            loaded.why_nothing(model.horizon())
        )));
    }
    let used = loaded.used;
    let object = suggest::find_object(&used, args.object.as_deref())
        .map_err(|e| Failure::Usage(anyhow!("{e}")))?;
    let config = args.online.config();
    println!(
        "object {}: {} pushes; {model_name}, horizon {}; {}",
        object.name,
        object.pushes.len(),
        model.horizon(),
        config.optimizer.name()
    );
    match args.measure_orders {
        Some(orders) => measure(args, &model, &used, &object, &config, orders),
        None => rank(args, &model, &used, &object, &config),
    }
}

fn rank(
    args: &SuggestArgs,
    model: &CombinedModel,
    used: &[UsedRecording],
    object: &ObjectPushes,
    config: &OnlineConfig,
) -> Result<(), Failure> {
    let after = pushes_named(used, object, &args.after)?;
    let candidates: Vec<usize> = object
        .pushes
        .iter()
        .copied()
        .filter(|p| !after.contains(p))
        .collect();
    if candidates.is_empty() && !args.grid {
        return Err(Failure::Usage(anyhow!(
            "every push of {} is in --after: nothing left to suggest",
            object.name
        )));
    }
    let failed = |e: suggest::SuggestError| Failure::Failed(anyhow!("{e}"));
    let state =
        suggest::state_after(model, used, &object.pushes, &after, config).map_err(failed)?;
    let learner = experiment::model_on(model, &used[object.pushes[0]])
        .map_err(|e| Failure::Failed(anyhow!("{e}")))?;
    let grid = match args.grid {
        true => Some(grid_pushes(args, &used[object.pushes[0]].recording)?),
        false => None,
    };
    let given: Vec<(usize, &Recording)> = match &grid {
        Some(pushes) => pushes.iter().enumerate().collect(),
        None => candidates
            .iter()
            .map(|&p| (p, &used[p].recording))
            .collect(),
    };
    let ranking = suggest::rank(
        learner.as_ref(),
        model.horizon(),
        &state,
        &given,
        args.criterion,
    )
    .map_err(|e| Failure::Failed(anyhow!("{e}")))?;
    let learned = match after.as_slice() {
        [] => "nothing learned yet".to_owned(),
        names => format!(
            "after {}",
            names
                .iter()
                .map(|&p| used[p].recording.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    println!(
        "{learned}: COM σ now {:.1} mm ({}); no push takes it below the model's COM misfit, {:.1} mm",
        ranking.com_std_now_m * 1e3,
        criterion_words(args.criterion),
        ranking.com_misfit_m * 1e3
    );
    print_ranking(&ranking, args.top);
    if let Some(path) = &args.json {
        let value = json!({
            "object": object.name,
            "model": args.model,
            "optimizer": config.optimizer.name(),
            "after": args.after,
            "ranking": ranking,
        });
        write_json(path, &value)?;
    }
    Ok(())
}

/// The grid of `--grid`'s options on the object of `like`; points that cannot be pushed are said.
fn grid_pushes(args: &SuggestArgs, like: &Recording) -> Result<Vec<Recording>, Failure> {
    // The core's grid, with what the options change.
    let defaults = PushGrid::default();
    let grid = PushGrid {
        sides: args.grid_sides.clone().unwrap_or(defaults.sides),
        offsets: args.grid_offsets.clone().unwrap_or(defaults.offsets),
        angles_deg: args.grid_angles.clone().unwrap_or(defaults.angles_deg),
        length_m: args.grid_length.unwrap_or(defaults.length_m),
    };
    if let Some(bad) = grid.offsets.iter().find(|f| f.is_nan() || f.abs() >= 1.0) {
        return Err(Failure::Usage(anyhow!(
            "--grid-offsets {bad}: an offset is a fraction of the face's half length, between -1 \
             and 1"
        )));
    }
    let pushes = grid
        .pushes(like)
        .map_err(|e| Failure::Failed(anyhow!("the object's outline: {e}")))?;
    for skipped in &pushes.skipped {
        eprintln!("grid push left out: {skipped}");
    }
    if pushes.pushes.is_empty() {
        return Err(Failure::Usage(anyhow!(
            "no push of the grid can be made on {}",
            like.setting.name
        )));
    }
    println!(
        "a grid of {} pushes, {:.0} cm each at {:.1} cm/s, {:.0} Hz",
        pushes.pushes.len(),
        grid.length_m * 1e2,
        pushes.speed * 1e2,
        pushes.rate_hz
    );
    Ok(pushes.pushes)
}

fn criterion_words(criterion: Criterion) -> &'static str {
    match criterion {
        Criterion::Spread => "√ of the mean COM variance, from the frames and the model's misfit",
        Criterion::Area => "the COM ellipse's area as a σ, from the frames and the model's misfit",
        Criterion::Axis => "the COM ellipse's longest axis, from the frames and the model's misfit",
    }
}

fn print_ranking(ranking: &Ranking, top: Option<usize>) {
    let shown = &ranking.suggestions[..ranking.suggestions.len().min(top.unwrap_or(usize::MAX))];
    // As wide as the longest name shown: an MIT file's name is 60 characters, a set's push 10.
    let width = shown
        .iter()
        .map(|s| s.name.chars().count())
        .max()
        .unwrap_or(0)
        .max("push".len());
    println!(
        "{:>4}  {:<width$} {:>4} {:>9} {:>6} {:>7}  {:>11} {:>8}",
        "rank", "push", "face", "offset", "angle", "length", "COM σ after", "shrinks"
    );
    let now = ranking.com_std_now_m;
    for (i, s) in shown.iter().enumerate() {
        let shape = match &s.shape {
            // A rounding's sign ("-0.0") says nothing.
            Some(p) => format!(
                "{:>4} {:>+6.1} cm {:>+5.0}° {:>4.0} cm",
                p.face,
                unsigned_zero(p.offset_m * 1e2, 0.05),
                unsigned_zero(p.angle_rad.to_degrees(), 0.5),
                p.length_m * 1e2
            ),
            None => format!("{:>31}", "misses the object"),
        };
        let shrink = if now > 0.0 {
            100.0 * (1.0 - s.com_std_after_m / now)
        } else {
            0.0
        };
        println!(
            "{:>4}  {:<width$} {shape}  {:>8.1} mm {:>6.0} %",
            i + 1,
            s.name,
            s.com_std_after_m * 1e3,
            shrink
        );
    }
}

fn measure(
    args: &SuggestArgs,
    model: &CombinedModel,
    used: &[UsedRecording],
    object: &ObjectPushes,
    config: &OnlineConfig,
    orders: usize,
) -> Result<(), Failure> {
    let truth = used[object.pushes[0]].recording.setting.com_offset;
    if truth.is_none() {
        return Err(Failure::Usage(anyhow!(
            "--measure-orders needs the true COM to measure against, and the recordings of {} do \
             not give it (a native set's setting.json gives it as com_offset)",
            object.name
        )));
    }
    let bar = ProgressBar::with_draw_target(Some(orders as u64 + 2), ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} orders ({eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message("learning");
    let count = object.pushes.len();
    let order = |choice| {
        let learned = suggest::learn_in_order(
            model,
            used,
            &object.pushes,
            config,
            choice,
            args.criterion,
            count,
        )
        .map_err(|e| Failure::Failed(anyhow!("{e}")));
        bar.inc(1);
        learned
    };
    let ranked = order(Choice::Ranked)?;
    let worst = order(Choice::Worst)?;
    let random = (0..orders as u64)
        .map(|r| order(Choice::Random(args.seed.wrapping_add(r))))
        .collect::<Result<Vec<_>, _>>()?;
    bar.finish_and_clear();

    let after: Vec<usize> = AFTER.into_iter().filter(|&n| n <= count).collect();
    let error_after = |o: &[LearnedPush], n: usize| o.get(n - 1).and_then(|l| l.com_error_m);
    println!(
        "COM error after n pushes, mm (θ carried; random: median [10–90 %] of {orders} orders)"
    );
    println!("{:>3} {:>8} {:>8} {:>22}", "n", "ranked", "worst", "random");
    let mut rows = Vec::new();
    for &n in &after {
        let mut randoms: Vec<f64> = random.iter().filter_map(|o| error_after(o, n)).collect();
        randoms.sort_by(f64::total_cmp);
        let q = |p: f64| quantile(&randoms, p);
        let mm = |v: Option<f64>| v.map_or("-".to_owned(), |v| format!("{:.1}", v * 1e3));
        println!(
            "{n:>3} {:>8} {:>8} {:>8} [{:>5}–{:>5}]",
            mm(error_after(&ranked, n)),
            mm(error_after(&worst, n)),
            mm(q(0.5)),
            mm(q(0.1)),
            mm(q(0.9))
        );
        rows.push(json!({
            "after": n,
            "ranked_m": error_after(&ranked, n),
            "worst_m": error_after(&worst, n),
            "random_median_m": q(0.5),
            "random_p10_m": q(0.1),
            "random_p90_m": q(0.9),
        }));
    }
    if let Some(path) = &args.json {
        let names: Vec<&str> = object
            .pushes
            .iter()
            .map(|&p| used[p].recording.name.as_str())
            .collect();
        let value = json!({
            "object": object.name,
            "model": args.model,
            "optimizer": config.optimizer.name(),
            "criterion": args.criterion,
            "seed": args.seed,
            "truth_com_m": truth,
            "pushes": names,
            "summary": rows,
            "ranked": ranked,
            "worst": worst,
            "random": random,
        });
        write_json(path, &value)?;
    }
    Ok(())
}

/// `x`, or 0 when it would print as zero (below `half_step`), so that no "-0.0" is printed.
fn unsigned_zero(x: f64, half_step: f64) -> f64 {
    if x.abs() < half_step { 0.0 } else { x }
}

/// The `p`-quantile of sorted values (the nearest rank below), `None` when there are none.
fn quantile(sorted: &[f64], p: f64) -> Option<f64> {
    let last = sorted.len().checked_sub(1)?;
    Some(sorted[((last as f64) * p).round() as usize])
}

/// The recordings named in `names`, in that order, all among the object's pushes.
fn pushes_named(
    used: &[UsedRecording],
    object: &ObjectPushes,
    names: &[String],
) -> Result<Vec<usize>, Failure> {
    names
        .iter()
        .map(|name| {
            object
                .pushes
                .iter()
                .copied()
                .find(|&p| used[p].recording.name == *name)
                .ok_or_else(|| {
                    let known: Vec<&str> = object
                        .pushes
                        .iter()
                        .map(|&p| used[p].recording.name.as_str())
                        .collect();
                    Failure::Usage(anyhow!(
                        "--after {name}: no push of {} is called that; its pushes are {}",
                        object.name,
                        known.join(", ")
                    ))
                })
        })
        .collect()
}

fn write_json(path: &std::path::Path, value: &serde_json::Value) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(value).map_err(|e| anyhow!("{e}"))?;
    write_atomically(path, text.as_bytes())
        .map_err(|e| Failure::Failed(anyhow!("cannot write {}: {e}", path.display())))?;
    println!("wrote {}", path.display());
    Ok(())
}
