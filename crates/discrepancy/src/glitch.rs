//! Glitches: readings far outside the record's own motion — a spike, or a dropout of one to a
//! few samples — set aside before a diagnosis.
//!
//! A glitch is not physics and not part of the measurement model (Gaussian AR(1) noise, module
//! [`crate::diagnose::evidence`]): one reading 30× an output's RMS off inflates that output's
//! profiled variance a thousandfold, and every candidate's gain with it shrinks to nothing (on
//! the blind development set with one such reading put into each record, 26 of 66 answers
//! changed, most to `none`, some to a delay or a quantizer). So before anything is fitted, a run
//! of one to [`MAX_RUN`] adjacent readings y_k … y_{k+L−1} of an output is a **glitch** when
//! each of them departs from both readings that bound the run (y_{k−1} and y_{k+L}; at an end of
//! the record the two next to the run) in the same direction, each by more than
//!
//! ```text
//! T = max(GLITCH_FACTOR · q₉₅(|Δy|),  STEP_FACTOR · median(|Δy| > 0)),
//! ```
//!
//! with q₉₅(|Δy|) the 95th percentile of the output's sample-to-sample changes (the signal's
//! own fastest motion and its noise, unmoved by a few glitches) and the median nonzero change
//! (a quantized sensor's step: a reading that blips one level up and back is not a glitch). A
//! step change of the signal departs from the readings on one side only, and is kept; so is a
//! plateau longer than [`MAX_RUN`] samples. The longest run from a reading is taken first. A
//! glitch is replaced by the straight line through the two bounding readings (for one reading
//! inside the record, their mean; at an end, the line through the two next to it, extended) and
//! reported, one [`Glitch`] per reading.
//!
//! On the 2,048 records of the seen studies and fixtures (slewing and structure, dev, held-out
//! and fresh draws, the blind development set) no reading is a glitch, runs included; one
//! reading moved by 3× its output's standard deviation or more is found in 64 of 66 blind
//! records (by 1×, in 31).

use mem::Measurement;
use serde::Serialize;

/// How many times the 95th percentile of an output's sample-to-sample changes a glitch departs
/// from each neighbour.
pub const GLITCH_FACTOR: f64 = 20.0;

/// The longest run of adjacent glitched readings recognised (a dropout of a few samples).
pub const MAX_RUN: usize = 5;

/// How many times the median nonzero sample-to-sample change (a quantized sensor's step) a
/// glitch departs from each neighbour.
pub const STEP_FACTOR: f64 = 5.0;

/// A reading set aside as a glitch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Glitch {
    /// The output.
    pub output: String,
    /// Its sample index in the record.
    pub sample: usize,
    /// Its time \[s\].
    pub time: f64,
    /// The reading.
    pub reading: f64,
    /// What replaced it: the line through the readings that bound its run (for one reading, its
    /// neighbours' mean; at an end, the line through the two next to it).
    pub replaced_by: f64,
}

/// The samples of `values` that are glitches, with their replacements (module docs), in order.
pub fn find(values: &[f64]) -> Vec<(usize, f64)> {
    let n = values.len();
    if n < 3 {
        return Vec::new();
    }
    let mut changes: Vec<f64> = values.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    changes.sort_by(f64::total_cmp);
    let q95 = changes[((changes.len() - 1) as f64 * 0.95).round() as usize];
    let nonzero = &changes[changes.partition_point(|c| *c <= 0.0)..];
    let step = nonzero.get(nonzero.len() / 2).copied().unwrap_or(0.0);
    let bar = (GLITCH_FACTOR * q95).max(STEP_FACTOR * step);
    if !(bar > 0.0 && bar.is_finite()) {
        return Vec::new();
    }
    let mut found = Vec::new();
    let mut k = 0;
    while k < n {
        // The longest run from k first: a run whose readings differ is not cut short by its first.
        match (1..=MAX_RUN).rev().find_map(|length| glitch_run(values, k, length, bar)) {
            Some(replaced) => {
                let length = replaced.len();
                found.extend(replaced.into_iter().enumerate().map(|(i, v)| (k + i, v)));
                k += length;
            }
            None => k += 1,
        }
    }
    found
}

/// The replacements of the `length` readings from `k` on, if they are a run of glitches: each
/// departs from both readings that bound the run — y_{k−1} and y_{k+length}; at an end of the
/// record the two next to the run — in the same direction, by more than `bar`. They are
/// replaced by the straight line through those two readings: interpolated between them inside
/// the record (one reading: their mean), extrapolated at an end.
fn glitch_run(values: &[f64], k: usize, length: usize, bar: f64) -> Option<Vec<f64>> {
    let n = values.len();
    if k + length > n || n < length + 2 {
        return None;
    }
    let (a, b) = if k == 0 {
        (length, length + 1)
    } else if k + length == n {
        (k - 1, k - 2)
    } else {
        (k - 1, k + length)
    };
    let (ya, yb) = (values[a], values[b]);
    let run = &values[k..k + length];
    // Both departures on the run's side (compared by sign: a product of tiny ones underflows).
    let upward = run[0] > ya;
    let departs = |v: f64| {
        let (left, right) = (v - ya, v - yb);
        (left > 0.0) == upward && (right > 0.0) == upward && left.abs().min(right.abs()) > bar
    };
    if !run.iter().all(|v| departs(*v)) {
        return None;
    }
    let (pa, pb) = (a as f64, b as f64);
    Some(
        (k..k + length)
            .map(|j| {
                let w = (j as f64 - pa) / (pb - pa);
                (1.0 - w) * ya + w * yb
            })
            .collect(),
    )
}

/// The record with every glitch of every output replaced, and the glitches. A record without
/// one comes back as it was, uncopied.
///
/// # Errors
/// None in practice (the replacements are finite means of finite readings); the record's own
/// validation is kept.
pub fn set_aside(data: Measurement) -> Result<(Measurement, Vec<Glitch>), mem::MemError> {
    let mut found = Vec::new();
    for (o, name) in data.names().iter().enumerate() {
        let column: Vec<f64> = (0..data.n_samples()).map(|k| data.values()[(k, o)]).collect();
        found.extend(find(&column).into_iter().map(|(k, replaced_by)| Glitch {
            output: name.clone(),
            sample: k,
            time: data.start() + k as f64 * data.interval(),
            reading: column[k],
            replaced_by,
        }));
    }
    if found.is_empty() {
        return Ok((data, found));
    }
    let mut values = data.values().clone();
    for g in &found {
        let o = data.names().iter().position(|n| *n == g.output).expect("an output of the record");
        values[(g.sample, o)] = g.replaced_by;
    }
    Ok((data.with_values(values)?, found))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn noisy_decay(n: usize, seed: u64) -> Vec<f64> {
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        (0..n)
            .map(|k| {
                let t = k as f64 * 0.005;
                0.03 * (-0.3 * t).exp() * (21.6 * t).cos()
                    + 3e-4 * rng.sample::<f64, _>(rand_distr::StandardNormal)
            })
            .collect()
    }

    #[test]
    fn a_spike_or_a_dropout_is_a_glitch_and_is_replaced_by_its_neighbours_mean() {
        let clean = noisy_decay(2001, 1);
        for (at, by) in [(700, 0.5), (1500, -0.1), (0, 0.2), (2000, -0.3)] {
            let mut y = clean.clone();
            y[at] += by;
            let found = find(&y);
            assert_eq!(found.len(), 1, "{at}: {found:?}");
            let (k, replaced) = found[0];
            assert_eq!(k, at);
            let expected = match at {
                0 => 2.0 * y[1] - y[2],
                2000 => 2.0 * y[1999] - y[1998],
                _ => 0.5 * (y[at - 1] + y[at + 1]),
            };
            assert_eq!(replaced, expected);
            // The same record in units 10¹⁷⁰ times larger: departures near 10⁻¹⁷⁰, whose
            // product underflows to zero, are still compared by sign.
            let tiny: Vec<f64> = y.iter().map(|v| v * 1e-170).collect();
            assert_eq!(find(&tiny).iter().map(|(k, _)| *k).collect::<Vec<_>>(), [at], "{at} in tiny units");
        }
    }

    #[test]
    fn a_dropout_of_a_few_readings_is_one_glitch_run_replaced_by_a_line() {
        let clean = noisy_decay(2001, 7);
        // Runs of 2 to MAX_RUN readings inside the record and at either end, level (a dropout to
        // one value) or not (a spike that decays).
        for (at, length, level) in
            [(700, 2, true), (1200, 3, false), (0, 4, true), (1996, 5, false), (40, 5, true)]
        {
            let mut y = clean.clone();
            for i in 0..length {
                y[at + i] = if level { -0.4 } else { 0.6 - 0.05 * i as f64 };
            }
            let found = find(&y);
            let ks: Vec<usize> = found.iter().map(|(k, _)| *k).collect();
            assert_eq!(ks, (at..at + length).collect::<Vec<_>>(), "{at}+{length}");
            // The line through the two readings that bound the run, computed here from them.
            let (a, b) = match at {
                0 => (length, length + 1),
                _ if at + length == y.len() => (at - 1, at - 2),
                _ => (at - 1, at + length),
            };
            for (k, replaced) in found {
                let expected = y[a] + (y[b] - y[a]) * (k as f64 - a as f64) / (b as f64 - a as f64);
                assert!((replaced - expected).abs() < 1e-12, "{at}+{length} at {k}: {replaced} {expected}");
                assert!((replaced - clean[k]).abs() < 0.01, "{at}+{length} at {k}: {replaced} {}", clean[k]);
            }
        }
        // A plateau longer than MAX_RUN is the signal's, and is kept.
        let mut y = clean.clone();
        y[900..900 + MAX_RUN + 1].iter_mut().for_each(|v| *v = -0.4);
        assert!(find(&y).is_empty());
    }

    #[test]
    fn noise_a_step_of_the_signal_and_a_quantizers_blips_are_not_glitches() {
        assert!(find(&noisy_decay(2001, 2)).is_empty());
        // A step of the signal departs from one neighbour only.
        let mut stepped = noisy_decay(2001, 3);
        stepped[1000..].iter_mut().for_each(|v| *v += 0.5);
        assert!(find(&stepped).is_empty());
        // An ADC whose readings blip one level up and back while the signal rests between levels.
        let step = 0.01;
        let mut rng = rand::rngs::StdRng::seed_from_u64(4);
        let adc: Vec<f64> = (0..2000)
            .map(|k| {
                let v = if k < 300 { 0.2 * (1.0 - k as f64 / 300.0) } else { 0.004 };
                step * ((v + 0.002 * rng.sample::<f64, _>(rand_distr::StandardNormal)) / step).round()
            })
            .collect();
        assert!(adc.windows(3).any(|w| w[0] == w[2] && w[1] != w[0]), "the record has blips");
        assert!(find(&adc).is_empty());
    }

    #[test]
    fn set_aside_replaces_and_reports_each_glitch_in_its_output() {
        let (q1, mut q3) = (noisy_decay(400, 5), noisy_decay(400, 6));
        q3[123] = 7.0;
        let values = faer::Mat::from_fn(400, 2, |k, o| if o == 0 { q1[k] } else { q3[k] });
        let data = Measurement::new(vec!["q1".into(), "q3".into()], 0.0, 0.005, values).unwrap();
        let (cleaned, glitches) = set_aside(data).unwrap();
        assert_eq!(glitches.len(), 1);
        let g = &glitches[0];
        assert_eq!((g.output.as_str(), g.sample, g.reading), ("q3", 123, 7.0));
        assert!((g.time - 0.615).abs() < 1e-12);
        assert_eq!(cleaned.values()[(123, 1)], g.replaced_by);
        assert_eq!(cleaned.values()[(122, 1)], q3[122]);
        assert_eq!(cleaned.values()[(123, 0)], q1[123]);
        // Nothing to set aside: the record comes back as it was.
        let (same, none) = set_aside(cleaned.clone()).unwrap();
        assert!(none.is_empty());
        assert_eq!(same, cleaned);
    }
}
