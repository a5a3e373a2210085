//! `memid modal`: closed-loop frequencies and damping ratios.

use crate::io::{Inputs, load_model};
use crate::output::{modal_json, modal_table};
use anyhow::Result;
use std::path::PathBuf;

/// Closed-loop frequencies (Hz) and damping ratios of a model (the paper's Table 2 columns).
#[derive(clap::Args)]
pub struct Args {
    /// Model file (RON).
    #[arg(long)]
    model: PathBuf,
    /// Override a parameter, NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let model = load_model(&args.model, &args.set, &mut Inputs::default())?;
    let rows = model.modal()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&modal_json(&rows))?);
    } else {
        print!("{}", modal_table(&rows));
    }
    Ok(())
}
