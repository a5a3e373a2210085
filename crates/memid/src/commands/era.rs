//! `memid era`: modal parameters of a measured free decay.

use crate::io::print;
use crate::output::{era_json, era_table};
use anyhow::Result;
use std::path::PathBuf;

/// The Eigensystem Realization Algorithm on a measured free decay (Table 2's "Measurements").
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Measured data (CSV with header t,<outputs>).
    #[arg(long)]
    data: PathBuf,
    /// Realization order (twice the number of modes sought, plus room for noise modes).
    #[arg(long, default_value_t = 8, value_parser = super::at_least_one)]
    order: usize,
    /// Keep every R-th sample after an anti-aliasing filter.
    #[arg(long, value_name = "R", value_parser = super::at_least_one)]
    decimate: Option<usize>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut data = mem::Measurement::read_csv(&args.data)?;
    if let Some(r) = args.decimate {
        data = data.decimate(r)?;
    }
    let result = era::identify(data.values().as_ref(), data.interval(), args.order)?;
    if args.json {
        print(&(serde_json::to_string_pretty(&era_json(&result))? + "\n"))
    } else {
        print(&era_table(&result))
    }
}
