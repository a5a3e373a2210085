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
    let rows = model.modal()?;
    if let Some(row) = rows.iter().find(|r| !(r.frequency_hz.is_finite() && r.damping_ratio.is_finite())) {
        anyhow::bail!(
            "the model's {} mode is not finite ({} Hz): its matrices overflow; check the model's values",
            crate::output::kind(row.kind),
            row.frequency_hz
        );
    }
    if args.json {
        print(&(serde_json::to_string_pretty(&modal_json(&rows))? + "\n"))
    } else {
        print(&modal_table(&rows))
    }
}
