//! `memid modal`: closed-loop frequencies and damping ratios.

use crate::io::Inputs;
use crate::output::{modal_json, modal_table};
use anyhow::Result;

/// Closed-loop frequencies (Hz) and damping ratios of a model (the paper's Table 2 columns).
#[derive(clap::Args)]
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
    if args.json {
        println!("{}", serde_json::to_string_pretty(&modal_json(&rows))?);
    } else {
        print!("{}", modal_table(&rows));
    }
    Ok(())
}
