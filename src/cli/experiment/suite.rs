//! `pushlab suite SPEC.json`: many experiments, every model (kind or ablation) and the physics-only
//! model, into one table (and with `--json`, one report; with `--markdown` and `--latex`, the table
//! for a paper: [`super::suite_tables`]). The spec's format is `pushlab_core::experiment::suite`'s.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, anyhow};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::atomic_file::write_atomically;
use pushlab_core::experiment::suite::{ExperimentResult, SuiteSpec, run_suite};
use pushlab_core::experiment::variant::ModelVariant;
use pushlab_core::learn::Nmse;
use serde::Serialize;

use super::suite_tables;
use super::train_progress::{cancel_flag, cancelled};
use crate::cli::exit::Failure;

/// Arguments of `pushlab suite`.
#[derive(Debug, Args)]
pub struct SuiteArgs {
    /// The suite: a JSON file listing the experiments (see the guide, docs/src/experiments.md);
    /// paths in it are relative to its folder.
    #[arg(value_name = "SPEC.json")]
    pub spec: PathBuf,
    /// Write every number as JSON.
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    /// Write the table as Markdown (a pipe table, the best online numbers in bold).
    #[arg(long, value_name = "OUT.md")]
    pub markdown: Option<PathBuf>,
    /// Write the table as a LaTeX booktabs tabular (for \input in a paper).
    #[arg(long, value_name = "OUT.tex")]
    pub latex: Option<PathBuf>,
    /// Experiments run at once [default: the number of cores].
    #[arg(long, value_name = "N", value_parser = super::args::positive)]
    pub jobs: Option<usize>,
    /// Compare these models instead of the spec's "models", comma-separated: contact, paper, or the
    /// ablations contact-no-prior, contact-prior-only, paper-augmented.
    #[arg(long, value_name = "MODEL,...", value_delimiter = ',', value_parser = model_variant)]
    pub models: Vec<ModelVariant>,
}

/// A model (kind or ablation) by name.
fn model_variant(text: &str) -> Result<ModelVariant, String> {
    ModelVariant::from_name(text.trim()).ok_or_else(|| {
        let names: Vec<&str> = ModelVariant::ALL.iter().map(|v| v.name()).collect();
        format!(
            "unknown model {text:?}; expected one of {}",
            names.join(", ")
        )
    })
}

/// The JSON report of a suite.
#[derive(Debug, Serialize)]
struct SuiteReport<'a> {
    spec: &'a SuiteSpec,
    experiments: &'a [ExperimentResult],
    seconds: f64,
    workers: usize,
    pushlab_version: &'static str,
}

/// Runs `pushlab suite`.
pub fn run(args: &SuiteArgs) -> Result<(), Failure> {
    let mut spec = SuiteSpec::load(&args.spec).map_err(|e| Failure::Usage(anyhow!("{e}")))?;
    if !args.models.is_empty() {
        spec.models.clone_from(&args.models);
    }
    let base = args.spec.parent().unwrap_or(Path::new(".")).to_path_buf();
    let workers = args.jobs.unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    let cancel = cancel_flag();
    let bar = ProgressBar::with_draw_target(
        Some(spec.experiments.len() as u64),
        ProgressDrawTarget::stderr(),
    );
    if let Ok(style) =
        ProgressStyle::with_template("suite [{bar:30}] {pos}/{len} experiments {msg} ({elapsed})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    let started = Instant::now();
    let results = run_suite(
        &spec,
        &base,
        workers,
        &|result, done| {
            bar.set_position(done as u64);
            bar.set_message(format!("({} done)", result.name));
        },
        cancel,
    );
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    print_table(&spec, &results);
    println!(
        "{} experiment(s) in {seconds:.1} s on {workers} worker(s)",
        results.len()
    );
    if let Some(path) = &args.json {
        let report = SuiteReport {
            spec: &spec,
            experiments: &results,
            seconds,
            workers,
            pushlab_version: env!("CARGO_PKG_VERSION"),
        };
        let mut json = serde_json::to_vec_pretty(&report).context("cannot encode the report")?;
        json.push(b'\n');
        write_atomically(path, &json)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    let tables: [(&Option<PathBuf>, suite_tables::Table); 2] = [
        (&args.markdown, suite_tables::markdown),
        (&args.latex, suite_tables::latex),
    ];
    for (path, table) in tables {
        if let Some(path) = path {
            write_atomically(path, table(&spec, &results).as_bytes())
                .with_context(|| format!("cannot write {}", path.display()))?;
            println!("wrote {}", path.display());
        }
    }
    if cancelled() {
        return Err(Failure::Failed(anyhow!(
            "stopped by Ctrl-C after {} of {} experiments",
            results.len(),
            spec.experiments.len()
        )));
    }
    let failed: Vec<&ExperimentResult> = results.iter().filter(|r| !r.errors.is_empty()).collect();
    if !failed.is_empty() {
        return Err(Failure::Failed(anyhow!(
            "{} experiment(s) could not run completely: {}",
            failed.len(),
            failed
                .iter()
                .map(|r| format!("{} ({})", r.name, r.errors.join("; ")))
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    Ok(())
}

/// One row per experiment; per model kind offline, fixed and online NMSE (pos/rot), then the
/// physics-only model fixed and online, and the experiment's first model weighed with it online.
fn print_table(spec: &SuiteSpec, results: &[ExperimentResult]) {
    let cell = |n: Option<&Nmse>| match n {
        Some(n) => format!("{:.3}/{:.3}", n.pos, n.rot),
        None => "–".to_owned(),
    };
    const CORNER: &str = "NMSE pos/rot";
    let width = results
        .iter()
        .map(|r| r.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(CORNER.len());
    println!();
    let mut header = format!("{CORNER:<width$}");
    let mut second = format!("{:<width$}", "");
    for model in &spec.models {
        header.push_str(&format!(" | {:^41}", model.name()));
        second.push_str(&format!(
            " | {:>13} {:>13} {:>13}",
            "offline", "fixed", "online"
        ));
    }
    if spec.physics {
        header.push_str(&format!(" | {:^27} | {:^13}", "physics only", "weighted"));
        second.push_str(&format!(
            " | {:>13} {:>13} | {:>13}",
            "fixed", "online", "online"
        ));
    }
    println!("{header}");
    println!("{second}");
    for r in results {
        let mut line = format!("{:<width$}", r.name);
        for model in &spec.models {
            let k = r.models.iter().find(|k| k.model == *model);
            line.push_str(&format!(
                " | {:>13} {:>13} {:>13}",
                cell(k.map(|k| &k.offline)),
                cell(k.map(|k| &k.fixed)),
                cell(k.map(|k| &k.online))
            ));
        }
        if spec.physics {
            let p = r.physics.as_ref();
            line.push_str(&format!(
                " | {:>13} {:>13} | {:>13}",
                cell(p.map(|p| &p.fixed)),
                cell(p.map(|p| &p.online)),
                cell(p.and_then(|p| p.weighted.as_ref()))
            ));
        }
        println!("{line}");
        for e in &r.errors {
            println!("{:<width$}   error: {e}", "");
        }
    }
    println!();
}
