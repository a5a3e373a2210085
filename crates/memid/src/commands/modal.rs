//! `memid modal`: closed-loop frequencies and damping ratios.

use crate::io::{Inputs, print};
use crate::output::{modal_json, modal_table};
use anyhow::Result;

/// Closed-loop frequencies (Hz) and damping ratios of a model (the paper's Table 2 columns).
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    #[command(flatten)]
    model: super::model_args::ModelArgs,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let model = args.model.load(&mut Inputs::default())?;
    let rows = model.modes()?;
    if args.json {
        print(&(serde_json::to_string_pretty(&modal_json(&rows))? + "\n"))
    } else {
        print(&modal_table(&rows, &model.coordinates()))
    }
}
