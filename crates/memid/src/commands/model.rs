//! `memid model`: the assembled matrices, to carry the model to other tools.

use crate::io::{Inputs, write_atomic};
use anyhow::Result;
use std::path::PathBuf;

/// Export the assembled matrices M, D, K, B, A, C and x(0) as JSON.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: super::model_args::ModelArgs,
    /// Print JSON (the only format; accepted for symmetry with the other commands).
    #[arg(long)]
    json: bool,
    /// Write to a file instead of standard output.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut inputs = Inputs::default();
    let model = args.model.load(&mut inputs)?;
    let text = serde_json::to_string_pretty(&model.matrices_json()?)?;
    match &args.output {
        Some(path) => {
            inputs.guard(path)?;
            write_atomic(path, text.as_bytes())?;
        }
        None => println!("{text}"),
    }
    Ok(())
}
