//! Command-line parsing and dispatch. Each subcommand lives in its own module; this one only routes.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use self::exit::EXIT_USAGE;

mod cameras_out;
mod control;
mod exit;
mod experiment;
mod import;
mod import_dataset;
mod interrupt;
mod labels;
mod live;
mod load_bar;
mod model_arg;
mod pipe;
mod render;
mod simulate;
mod suggest;
mod validate;

/// Predict and learn how a pushed object moves.
///
/// Without a subcommand, opens the desktop app on the bundled sample data.
#[derive(Debug, Parser)]
#[command(name = "pushlab", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Open recordings (set folders, CSV files, MIT Push Dataset files, or folders of them) in the app.
    Open {
        /// Files or folders to open.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Connect to a robot's Foxglove WebSocket server, record every message it sends, show the
    /// pusher's and the object's poses as they arrive and, with --setting, learn θ online from them.
    Live(live::LiveArgs),
    /// Set splits, inspect and export a recording set's labels (`pushlab-labels.json`).
    Labels {
        #[command(subcommand)]
        command: labels::LabelsCommand,
    },
    /// Generate recording sets with the quasi-static push simulator (true COM offset and h known).
    Simulate(Box<simulate::SimulateArgs>),
    /// Import a ROS 2 bag (.mcap file or rosbag2 folder), or a Push-T dataset (a zarr replay buffer
    /// or a LeRobot dataset folder, one push per episode), into a native recording set.
    Import(Box<import::ImportArgs>),
    /// Load recordings and report, one line per recording, ok / warnings / error (exit 1 on any error);
    /// for a ROS 2 bag, list its topics with their types, counts and rates.
    Validate(validate::ValidateArgs),
    /// Train the combined model (and with --baseline the pure network) offline; write a model file.
    Train(experiment::train::TrainArgs),
    /// Reproduce the paper's tables: offline, fixed and online NMSE; optional JSON report and figure.
    Eval(Box<experiment::eval::EvalArgs>),
    /// Run a list of experiments (a JSON spec) for every model kind and physics only, in parallel,
    /// into one table.
    Suite(experiment::suite::SuiteArgs),
    /// Rank an object's next pushes by how much each is expected to shrink the COM's uncertainty,
    /// after the pushes already learned; or measure the ranking against random orders.
    Suggest(Box<suggest::SuggestArgs>),
    /// Push the sandbox's mystery object to a goal with a controller that plans with the model
    /// it learns as it pushes (or θ fixed, physics alone, the true θ).
    Control(Box<control::ControlArgs>),
    /// Play a recording with the model, learning online as the app does, and write the scene as a
    /// video: GIF, MP4 or WebM.
    Render(Box<render::RenderArgs>),
}

/// Parses the command line and runs the chosen command.
pub fn run() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => {
            let code = if err.use_stderr() { EXIT_USAGE } else { 0 };
            // Printing help or a usage error can only fail if stdout/stderr are gone.
            let _ = err.print();
            return ExitCode::from(code);
        }
    };
    if cli
        .command
        .as_ref()
        .is_some_and(|c| !matches!(c, Command::Open { .. }))
    {
        pipe::end_quietly_on_closed_pipe();
    }
    match cli.command {
        Some(Command::Labels { command }) => {
            exit::exit_code(labels::run(command).map_err(exit::Failure::from))
        }
        Some(Command::Validate(args)) => validate::run(&args),
        Some(Command::Live(args)) => exit::exit_code(live::run(&args)),
        Some(Command::Import(args)) => {
            exit::exit_code(import::run(&args).map_err(exit::Failure::from))
        }
        Some(Command::Train(args)) => exit::exit_code(experiment::train::run(&args)),
        Some(Command::Eval(args)) => exit::exit_code(experiment::eval::run(&args)),
        Some(Command::Suite(args)) => exit::exit_code(experiment::suite::run(&args)),
        Some(Command::Suggest(args)) => exit::exit_code(suggest::run(&args)),
        Some(Command::Control(args)) => exit::exit_code(control::run(&args)),
        Some(Command::Render(args)) => exit::exit_code(render::run(&args)),
        Some(Command::Simulate(args)) => {
            exit::exit_code(simulate::run(&args).map_err(exit::Failure::from))
        }
        None => run_app(Vec::new()),
        Some(Command::Open { paths }) => run_app(paths),
    }
}

/// Opens the desktop app on `paths` (the bundled sample data when empty).
fn run_app(paths: Vec<PathBuf>) -> ExitCode {
    match pushlab::app::run(paths) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("pushlab: {err:#}");
            ExitCode::from(1)
        }
    }
}
