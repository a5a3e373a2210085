//! `memid model`: the assembled matrices, to carry the model to other tools.

use crate::io::{Inputs, Outputs, Target};
use anyhow::Result;
use std::path::PathBuf;

/// Export the assembled matrices M, D, K, B, A, C and x(0) as JSON.
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
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
    let target = args.output.as_deref().map_or(Target::Stdout, Target::from_arg);
    let mut outputs = Outputs::new(&inputs);
    outputs.check(&target)?;
    let text = serde_json::to_string_pretty(&model.matrices_json()?)? + "\n";
    crate::output::ensure_finite_json(&text, "the assembled matrices")?;
    outputs.stage(&target, text.into_bytes())?;
    outputs.commit()
}
