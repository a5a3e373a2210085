//! `memid simulate`: a model's response (a free decay, or the response to measured inputs) as CSV.

use crate::io::{Inputs, Outputs, Target, read_measurement};
use anyhow::{Result, anyhow, bail};
use rand::{Rng, SeedableRng};
use std::path::PathBuf;

/// Simulate a model's response into a CSV file: a free decay (header `t,<outputs>`), or, for a
/// model with inputs, the response to the inputs of `--inputs` (header `t,<inputs>,<outputs>`).
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    #[command(flatten)]
    model: super::model_args::ModelArgs,
    /// Duration [s] (not with --inputs, whose samples set the grid).
    #[arg(long)]
    duration: Option<f64>,
    /// Sample rate [Hz] (not with --inputs).
    #[arg(long)]
    rate: Option<f64>,
    /// The inputs that drive the model: a CSV with header `t,<the model's input names>`.
    #[arg(long, value_name = "FILE")]
    inputs: Option<PathBuf>,
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
    let drive = match &args.inputs {
        Some(path) => Some(read_measurement(path, &mut inputs)?),
        None => None,
    };
    let target = Target::from_arg(&args.output);
    let mut outputs = Outputs::new(&inputs);
    outputs.check(&target)?;
    let input_names = model.input_names();
    let (start, h, n, drive) = match (drive, &args.duration, &args.rate) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            bail!("--inputs sets the sample grid; drop --duration and --rate")
        }
        (Some(record), None, None) => {
            if input_names.is_empty() {
                bail!("the model has no inputs; drop --inputs and give --duration and --rate");
            }
            let missing: Vec<&String> = input_names.iter().filter(|n| !record.names().contains(n)).collect();
            if !missing.is_empty() {
                bail!(
                    "--inputs: the file lacks the model's input columns {}",
                    missing.iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
                );
            }
            let refs: Vec<&str> = input_names.iter().map(|s| s.as_str()).collect();
            let only = record.select(&refs)?;
            let values = only.values().clone();
            // A measurement whose columns are all inputs: hold them as the model says.
            let holder = mem::Measurement::new(
                input_names.iter().chain(std::iter::once(&"_".to_string())).cloned().collect(),
                record.start(),
                record.interval(),
                faer::Mat::from_fn(values.nrows(), values.ncols() + 1, |k, c| {
                    if c < values.ncols() { values[(k, c)] } else { 0.0 }
                }),
            )?
            .with_inputs(&refs, model.hold())?;
            (record.start(), record.interval(), record.n_samples(), Some(holder))
        }
        (None, Some(duration), Some(rate)) => {
            if !input_names.is_empty() {
                bail!(
                    "the model is driven by {}: give --inputs FILE with those columns",
                    input_names.join(", ")
                );
            }
            if !(duration.is_finite() && *duration > 0.0) {
                bail!("--duration must be a positive number of seconds, got {duration}");
            }
            if !(rate.is_finite() && *rate > 0.0) {
                bail!("--rate must be a positive frequency in Hz, got {rate}");
            }
            let samples = (duration * rate).floor() + 1.0;
            let count = model.output_names().len() as f64;
            if samples * count > MAX_VALUES {
                bail!(
                    "--duration {duration} at --rate {rate} asks for {samples:.3e} samples of {count} outputs, beyond the {MAX_VALUES:.0} values memid writes; shorten the record or lower the rate"
                );
            }
            (0.0, 1.0 / rate, samples as usize, None)
        }
        _ => bail!("give --duration and --rate (or --inputs for a model with inputs)"),
    };
    let names = model.output_names();
    let output_refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    let levels = noise_levels(args.noise.as_deref(), &output_refs)?;
    let grid = mem::Grid { start, interval: h, inputs: drive.as_ref().and_then(|d| d.inputs()) };
    let mut y = model.simulate(&grid, n)?;
    let mut rng = rand::rngs::StdRng::seed_from_u64(args.seed);
    for (o, std) in levels.iter().enumerate() {
        for k in 0..n {
            y[(k, o)] += std * rng.sample::<f64, _>(rand_distr::StandardNormal);
        }
    }
    // Columns: t, the inputs (as given), then the outputs.
    let mut text = mem::csv_header(input_names.iter().chain(&names).map(String::as_str));
    for k in 0..n {
        text += &format!("{}", start + k as f64 * h);
        if let Some(inputs) = drive.as_ref().and_then(|d| d.inputs()) {
            for c in 0..inputs.values().ncols() {
                text += &format!(",{:e}", inputs.values()[(k, c)]);
            }
        }
        for o in 0..names.len() {
            text += &format!(",{:e}", y[(k, o)]);
        }
        text.push('\n');
    }
    outputs.stage(&target, text.into_bytes())?;
    outputs.commit()?;
    if let Target::File(path) = &target {
        eprintln!("wrote {} samples of {} to {}", n, names.join(", "), path.display());
    }
    Ok(())
}
