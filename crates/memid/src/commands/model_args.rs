//! The model arguments every model-reading command shares.

use crate::io::{Inputs, load_model};
use anyhow::Result;
use models::Model;
use std::path::PathBuf;

/// `--model FILE [--set NAME=VALUE ...]`.
#[derive(clap::Args)]
pub struct ModelArgs {
    /// Model file (RON).
    #[arg(long)]
    pub model: PathBuf,
    /// Override a parameter, NAME=VALUE (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
}

impl ModelArgs {
    /// Loads the model, applies the overrides and records the file as an input.
    pub fn load(&self, inputs: &mut Inputs) -> Result<Model> {
        load_model(&self.model, &self.set, inputs)
    }
}
