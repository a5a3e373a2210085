//! `memid`: tune a slewing-beam model to a measured free decay by the matrix exponential method.
//!
//! Every command reads RON model files and CSV data and writes new files; none overwrites its
//! inputs. Errors are one line on stderr with exit status 2.

mod commands;
mod io;
mod output;
mod plot;
mod progress;
mod report;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// memid — identification of system parameters by the matrix exponential method.
#[derive(Parser)]
#[command(name = "memid", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a model's free decay into a CSV file.
    Simulate(commands::simulate::Args),
    /// Fit parameters of a model to a measured free decay (the MEM).
    Fit(commands::fit::Args),
    /// Closed-loop frequencies and damping ratios of a model.
    Modal(commands::modal::Args),
    /// Modal parameters of a measured free decay by ERA.
    Era(commands::era::Args),
    /// Export the assembled matrices as JSON.
    Model(commands::model::Args),
    /// The paper's two runs on the embedded slewing experiment, with a report.
    Demo(commands::demo::Args),
    /// Find the physical effect a model is missing, add it, and show the gap shrink.
    Diagnose(commands::diagnose::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Simulate(a) => commands::simulate::run(a),
        Command::Fit(a) => commands::fit::run(a),
        Command::Modal(a) => commands::modal::run(a),
        Command::Era(a) => commands::era::run(a),
        Command::Model(a) => commands::model::run(a),
        Command::Demo(a) => commands::demo::run(a),
        Command::Diagnose(a) => commands::diagnose::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("memid: error: {}", format!("{e:#}").replace('\n', " "));
            ExitCode::from(2)
        }
    }
}
