//! The blurred-lattice test's null distribution, measured on a study's records.
//!
//!     cargo run --release -p discrepancy --example lattice_null -- [--floor K] DIR [DIR …]
//!
//! Each DIR is a study set written by `studies/diagnose/generate.py`, or the blind set (a
//! `truth.json` and `data/`). For every sensor of every record that the truth does not quantize, the blurred
//! lattice test ([`discrepancy::quantization::blurred`]) is run on the raw readings with no bar,
//! and its confirmation z is collected. The smallest step it looks at is half the sensor's
//! noise σ, taken from the truth (the diagnosis takes it from the residual about the reference
//! fit or its modal correction, whichever is smaller, which adds what misfit is left and so
//! looks at steps no smaller). The counts above a few levels are
//! printed beside what Student's t with [`discrepancy::quantization::BATCHES`] − 1 degrees of
//! freedom expects, the null of a mean of batch means whose phase comes from the other half;
//! then how many of the quantized sensors' records reach the bars. With `--floor K` the
//! smallest step is K/2 noise σ instead (the diagnosis's floor, half that residual's RMS, is
//! K/2 σ when the misfit makes the residual K times the noise).

use discrepancy::quantization::{BATCHES, batch_threshold, blurred};
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut dirs: Vec<String> = std::env::args().skip(1).collect();
    let mut floor = 1.0;
    if dirs.first().is_some_and(|a| a == "--floor") {
        floor = dirs
            .get(1)
            .and_then(|k| k.parse::<f64>().ok())
            .filter(|k| *k > 0.0)
            .ok_or("--floor needs a positive number K (the smallest step is K/2 noise σ)")?;
        dirs.drain(..2);
    }
    if dirs.is_empty() {
        return Err(
            "usage: lattice_null [--floor K] DIR [DIR …] (study sets of studies/diagnose/generate.py)".into(),
        );
    }
    let mut z = Vec::new();
    let mut quantized_z = Vec::new();
    let mut skipped = 0usize;
    for dir in &dirs {
        let text = std::fs::read_to_string(Path::new(dir).join("truth.json"))
            .map_err(|e| format!("{dir}/truth.json: {e}"))?;
        let truth: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{dir}/truth.json: {e}"))?;
        let cases =
            truth.get("cases").unwrap_or(&truth).as_array().ok_or(format!("{dir}/truth.json: no cases"))?;
        for case in cases {
            let data = case["data"].as_str().ok_or(format!("{dir}/truth.json: a case without `data`"))?;
            let quantized: Vec<&str> = case["truth"]["effects"]
                .as_array()
                .map(|effects| {
                    effects
                        .iter()
                        // The study's truth names the effect, the blind set's its kind.
                        .filter(|e| e["effect"] == "sensor_quantization" || e["kind"] == "quant")
                        .filter_map(|e| e["sensor"].as_str())
                        .collect()
                })
                .unwrap_or_default();
            let record = mem::Measurement::read_csv(&Path::new(dir).join(data))?;
            for (o, name) in record.names().iter().enumerate() {
                let Some(sigma) = case["truth"]["noise"]["std"][name.as_str()].as_f64() else {
                    skipped += 1;
                    continue;
                };
                let values: Vec<f64> = (0..record.n_samples()).map(|k| record.values()[(k, o)]).collect();
                let range = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                match blurred(&values, (0.5 * floor * sigma).max(1e-6 * range), f64::NEG_INFINITY) {
                    Some((_, statistic, _, _)) if quantized.contains(&name.as_str()) => {
                        quantized_z.push(statistic)
                    }
                    Some((_, statistic, _, _)) => z.push(statistic),
                    None => skipped += 1,
                }
            }
        }
    }
    let t = StudentsT::new(0.0, 1.0, (BATCHES - 1) as f64)?;
    // The diagnosis's bar: t's quantile at a false alarm of 1e-5 a reading.
    let bar = batch_threshold(1e-5);
    println!("{} unquantized sensor records read ({skipped} not testable)", z.len());
    println!("| z above | records | Student's t{} expects |", BATCHES - 1);
    println!("| --- | --- | --- |");
    for level in [2.0, 3.0, 4.0, 5.0, bar, 8.0] {
        let seen = z.iter().filter(|v| **v > level).count();
        println!("| {level:.2} | {seen} | {:.2} |", z.len() as f64 * (1.0 - t.cdf(level)));
    }
    let max = z.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = z.iter().copied().fold(f64::INFINITY, f64::min);
    println!("largest z {max:.2}, smallest {min:.2}");
    let over = |bar: f64| quantized_z.iter().filter(|v| **v >= bar).count();
    println!(
        "quantized sensor records: {} read, z ≥ {:.2} (t{}'s 1e-5 quantile) in {}, z ≥ 8 in {}",
        quantized_z.len(),
        bar,
        BATCHES - 1,
        over(bar),
        over(8.0)
    );
    Ok(())
}
