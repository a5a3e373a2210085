//! `memid simulate`: a model's free decay as CSV.

use crate::io::{Inputs, csv_text, write_atomic};
use anyhow::{Result, anyhow, bail};
use rand::{Rng, SeedableRng};
use std::path::PathBuf;

/// Simulate a model's free decay into a CSV file (header `t,<outputs>`).
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    model: super::model_args::ModelArgs,
    /// Duration [s].
    #[arg(long)]
    duration: f64,
    /// Sample rate [Hz].
    #[arg(long)]
    rate: f64,
    /// White Gaussian sensor noise: one standard deviation for every output (in each output's
    /// unit), or per output as NAME=STD[,NAME=STD...].
    #[arg(long)]
    noise: Option<String>,
    /// Seed of the noise.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Output CSV file.
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
}

/// Standard deviations per output from `--noise`.
fn noise_levels(spec: Option<&str>, outputs: &[&str]) -> Result<Vec<f64>> {
    let Some(spec) = spec else { return Ok(vec![0.0; outputs.len()]) };
    if let Ok(all) = spec.trim().parse::<f64>() {
        if !(all.is_finite() && all >= 0.0) {
            bail!("--noise {spec}: the standard deviation must be finite and ≥ 0");
        }
        return Ok(vec![all; outputs.len()]);
    }
    let mut levels = vec![0.0; outputs.len()];
    for part in spec.split(',') {
        let (name, value) = part
            .split_once('=')
            .ok_or_else(|| anyhow!("--noise `{part}`: expected NAME=STD or a single number"))?;
        let index = outputs.iter().position(|o| *o == name.trim()).ok_or_else(|| {
            anyhow!(
                "--noise: unknown output `{}`; the model's outputs are {}",
                name.trim(),
                outputs.join(", ")
            )
        })?;
        let v: f64 =
            value.trim().parse().map_err(|_| anyhow!("--noise `{part}`: `{value}` is not a number"))?;
        if !(v.is_finite() && v >= 0.0) {
            bail!("--noise `{part}`: the standard deviation must be finite and ≥ 0");
        }
        levels[index] = v;
    }
    Ok(levels)
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut inputs = Inputs::default();
    let model = args.model.load(&mut inputs)?;
    inputs.guard(&args.output)?;
    if !(args.duration.is_finite() && args.duration > 0.0) {
        bail!("--duration must be a positive number of seconds, got {}", args.duration);
    }
    if !(args.rate.is_finite() && args.rate > 0.0) {
        bail!("--rate must be a positive frequency in Hz, got {}", args.rate);
    }
    let h = 1.0 / args.rate;
    let n = (args.duration * args.rate).floor() as usize + 1;
    let outputs = model.output_names();
    let levels = noise_levels(args.noise.as_deref(), &outputs)?;
    let mut y = models::simulate_model(&model, h, n)?;
    let mut rng = rand::rngs::StdRng::seed_from_u64(args.seed);
    for (o, std) in levels.iter().enumerate() {
        for k in 0..n {
            y[(k, o)] += std * rng.sample::<f64, _>(rand_distr::StandardNormal);
        }
    }
    let times: Vec<f64> = (0..n).map(|k| k as f64 * h).collect();
    let names: Vec<String> = outputs.iter().map(|s| s.to_string()).collect();
    write_atomic(&args.output, csv_text(&names, &times, &y).as_bytes())?;
    eprintln!("wrote {} samples of {} to {}", n, names.join(", "), args.output.display());
    Ok(())
}
