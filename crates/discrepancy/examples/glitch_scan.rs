//! How often [`discrepancy::glitch::find`] calls a reading a glitch: on records as they are (every
//! call is a false one there, unless the record holds real glitches), and with one glitch put in.
//!
//!     cargo run --release -p discrepancy --example glitch_scan -- FILE.csv [FILE.csv …]
//!     cargo run --release -p discrepancy --example glitch_scan -- --inject MAG SEED FILE.csv [FILE.csv …]
//!
//! Without `--inject`, every output column of every record is scanned and each reading found is
//! printed. With `--inject`, one reading of one output of each record (both drawn with the
//! seeded generator) is moved by ±MAG × that output's standard deviation first, and the scan
//! counts the records where exactly that reading, and nothing else, is found.

use discrepancy::glitch::find;
use rand::{Rng, SeedableRng};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let inject = if args.first().is_some_and(|a| a == "--inject") {
        let magnitude: f64 = args.get(1).ok_or("--inject needs MAG and SEED")?.parse()?;
        let seed: u64 = args.get(2).ok_or("--inject needs MAG and SEED")?.parse()?;
        args.drain(..3);
        Some((magnitude, rand::rngs::StdRng::seed_from_u64(seed)))
    } else {
        None
    };
    if args.is_empty() {
        return Err("usage: glitch_scan [--inject MAG SEED] FILE.csv [FILE.csv …]".into());
    }
    let (mut records, mut found_total, mut exact) = (0usize, 0usize, 0usize);
    let mut inject = inject;
    for file in &args {
        let record =
            mem::Measurement::read_csv(std::path::Path::new(file)).map_err(|e| format!("{file}: {e}"))?;
        records += 1;
        let mut columns: Vec<Vec<f64>> = (0..record.n_outputs())
            .map(|o| (0..record.n_samples()).map(|k| record.values()[(k, o)]).collect())
            .collect();
        let put = inject.as_mut().map(|(magnitude, rng)| {
            let (o, k) = (rng.random_range(0..columns.len()), rng.random_range(0..record.n_samples()));
            let column = &mut columns[o];
            let mean = column.iter().sum::<f64>() / column.len() as f64;
            let sd = (column.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / column.len() as f64).sqrt();
            let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            column[k] += sign * *magnitude * sd;
            (o, k)
        });
        let mut found = Vec::new();
        for (o, column) in columns.iter().enumerate() {
            found.extend(find(column).into_iter().map(|(k, _)| (o, k)));
        }
        found_total += found.len();
        match put {
            Some(put) => exact += usize::from(found == [put]),
            None => {
                for (o, k) in &found {
                    println!("{file}: `{}` sample {k}", record.names()[*o]);
                }
            }
        }
    }
    match inject {
        Some((magnitude, _)) => println!(
            "{records} records, one reading moved by {magnitude} × its output's standard deviation: found exactly in \
             {exact}, {found_total} readings called glitches in all"
        ),
        None => println!("{records} records, {found_total} readings called glitches"),
    }
    Ok(())
}
