//! `memid`: tune a state-space model (the slewing rig, or any structure file) to measured records
//! — free decays or forced responses — by the matrix exponential method.
//!
//! Every command reads RON model files and CSV data and writes new files; none overwrites its
//! inputs. Errors are one line on stderr with exit status 2.

// The commands' doc comments are their `--help` text, printed as written: `t,<outputs>[,<inputs>]`
// and `[s]` there are literal usage, not links or HTML for rustdoc.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

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
#[command(name = "memid", version, about, allow_negative_numbers = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a model's response (a free decay, or driven by measured inputs) into a CSV file.
    Simulate(commands::simulate::Args),
    /// Fit parameters of a model to measured records, free decays or forced (the MEM).
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

/// The short usage printed when no command is given.
const USAGE: &str = "usage: memid <simulate|fit|modal|era|model|demo|diagnose> [options]; `memid --help` lists them, `memid <command> --help` explains one";

/// One line for an error chain: each cause appended once (an error whose message already
/// quotes its source is not followed by it again).
fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if !line.contains(&text) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&text);
        }
    }
    line.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A clap error message on one line: its lines up to the usage block, trimmed and joined.
fn clap_line(text: &str) -> String {
    let lines =
        text.lines().take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"));
    let joined = lines.map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join(" ");
    joined.trim_start_matches("error: ").to_string()
}

fn main() -> ExitCode {
    io::install_signal_cleanup();
    if std::env::args_os().len() <= 1 {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            return match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    match io::print(&e.render().to_string()) {
                        Err(e) if e.downcast_ref::<io::BrokenPipe>().is_none() => ExitCode::from(2),
                        _ => ExitCode::SUCCESS,
                    }
                }
                ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand | ErrorKind::MissingSubcommand => {
                    eprintln!("{USAGE}");
                    ExitCode::from(2)
                }
                _ => {
                    // clap's own message (with what it lists: the missing arguments, a tip), on
                    // one line, without its usage block.
                    let text = e.render().to_string();
                    let message = clap_line(&text);
                    let message = if message.is_empty() { "invalid arguments" } else { &message };
                    eprintln!("memid: error: {message} (see `memid --help`)");
                    ExitCode::from(2)
                }
            };
        }
    };
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
        // The reader of standard output went away: end quietly, as Unix tools do.
        Err(e) if e.downcast_ref::<io::BrokenPipe>().is_some() => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("memid: error: {}", one_line(&e));
            ExitCode::from(2)
        }
    }
}
