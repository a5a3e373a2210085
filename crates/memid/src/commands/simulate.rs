//! `memid simulate`: a model's free decay as CSV.

use crate::io::{Inputs, Outputs, Target};
use anyhow::{Result, anyhow, bail};
use rand::{Rng, SeedableRng};
use std::path::PathBuf;

/// Simulate a model's free decay into a CSV file (header `t,<outputs>`).
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
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

/// The largest number of values (samples × outputs) `simulate` writes: 2²⁸ (2 GiB of numbers,
/// several GiB of text).
const MAX_VALUES: f64 = (1u64 << 28) as f64;

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut inputs = Inputs::default();
    let model = args.model.load(&mut inputs)?;
    let target = Target::from_arg(&args.output);
    let mut outputs = Outputs::new(&inputs);
    outputs.check(&target)?;
    if !(args.duration.is_finite() && args.duration > 0.0) {
        bail!("--duration must be a positive number of seconds, got {}", args.duration);
    }
    if !(args.rate.is_finite() && args.rate > 0.0) {
        bail!("--rate must be a positive frequency in Hz, got {}", args.rate);
    }
    let samples = (args.duration * args.rate).floor() + 1.0;
    let names: Vec<String> = model.output_names().iter().map(|s| s.to_string()).collect();
    if samples * names.len() as f64 > MAX_VALUES {
        bail!(
            "--duration {} at --rate {} asks for {samples:.3e} samples of {} outputs, beyond the {MAX_VALUES:.0} values memid writes; shorten the record or lower the rate",
            args.duration,
            args.rate,
            names.len()
        );
    }
    let (h, n) = (1.0 / args.rate, samples as usize);
    let outputs_names: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    let levels = noise_levels(args.noise.as_deref(), &outputs_names)?;
    let mut y = models::simulate_model(&model, h, n)?;
    let mut rng = rand::rngs::StdRng::seed_from_u64(args.seed);
    for (o, std) in levels.iter().enumerate() {
        for k in 0..n {
            y[(k, o)] += std * rng.sample::<f64, _>(rand_distr::StandardNormal);
        }
    }
    if let Some((k, o)) =
        (0..n).flat_map(|k| (0..names.len()).map(move |o| (k, o))).find(|&(k, o)| !y[(k, o)].is_finite())
    {
        bail!(
            "the simulated `{}` is not finite at t = {} s (the model's response overflows); check the model's values",
            names[o],
            k as f64 * h
        );
    }
    let record = mem::Measurement::new(names.clone(), 0.0, h, y)?;
    outputs.stage(&target, record.to_csv().into_bytes())?;
    outputs.commit()?;
    if let Target::File(path) = &target {
        eprintln!("wrote {} samples of {} to {}", n, names.join(", "), path.display());
    }
    Ok(())
}
