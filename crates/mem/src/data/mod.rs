//! Measured records: uniform sampling, named outputs, measured inputs, decimation that the
//! model goes through too, CSV reading.

mod csv;
mod decimate;

pub use csv::csv_header;
pub use decimate::Decimation;

use crate::{Grid, MemError, ResponseModel};
use expm::{Hold, Response};
use faer::Mat;

/// Measured inputs: m named signals on the model's sample grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Inputs {
    names: Vec<String>,
    values: Mat<f64>,
    hold: Hold,
}

impl Inputs {
    /// Input names.
    pub fn names(&self) -> &[String] {
        &self.names
    }
    /// K × m values (raw samples when the outputs are decimated).
    pub fn values(&self) -> &Mat<f64> {
        &self.values
    }
    /// How the input is held between samples.
    pub fn hold(&self) -> Hold {
        self.hold
    }
}

/// p outputs sampled at a uniform interval h from `start` (seconds after the model's t = 0),
/// possibly with measured inputs and decimated.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    names: Vec<String>,
    interval: f64,
    start: f64,
    values: Mat<f64>,
    inputs: Option<Inputs>,
    decimation: Option<Decimation>,
    /// Per output, the fraction of the raw record's energy the decimation filter removed.
    discarded: Vec<f64>,
}

/// Relative deviation of a time stamp from the uniform grid that still counts as uniform
/// (room for times printed with a few decimals).
const UNIFORM_TOLERANCE: f64 = 1e-4;

/// The largest number of samples a record may have (2³¹: 16 GiB per output column).
pub const MAX_SAMPLES: usize = 1 << 31;

fn check_values(names: &[String], values: &Mat<f64>, what: &str) -> Result<(), MemError> {
    if names.len() != values.ncols() {
        return Err(MemError::InvalidData(format!("{} names for {} {what}", names.len(), values.ncols())));
    }
    for (o, name) in names.iter().enumerate() {
        if names[..o].contains(name) {
            return Err(MemError::InvalidData(format!("the {what} name `{name}` appears twice")));
        }
        for k in 0..values.nrows() {
            if !values[(k, o)].is_finite() {
                return Err(MemError::Sample {
                    sample: k,
                    message: format!("{what} `{name}` has the non-finite value {}", values[(k, o)]),
                });
            }
        }
    }
    Ok(())
}

impl Measurement {
    /// Samples `values` (K × p) at t_k = start + k·interval.
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for a non-positive or non-finite interval, a non-finite start,
    /// fewer than two samples, a name count that differs from p, a repeated name, or a
    /// NaN/infinite value (naming its sample and output).
    pub fn new(names: Vec<String>, start: f64, interval: f64, values: Mat<f64>) -> Result<Self, MemError> {
        if !(interval.is_finite() && interval > 0.0) {
            return Err(MemError::InvalidData(format!(
                "the sample interval must be finite and > 0, got {interval}"
            )));
        }
        if !start.is_finite() {
            return Err(MemError::InvalidData(format!("the start time must be finite, got {start}")));
        }
        if values.nrows() < 2 {
            return Err(MemError::InvalidData(format!("need at least 2 samples, got {}", values.nrows())));
        }
        if values.ncols() == 0 {
            return Err(MemError::InvalidData("need at least one output".into()));
        }
        check_values(&names, &values, "output")?;
        let discarded = vec![0.0; values.ncols()];
        Ok(Self { names, interval, start, values, inputs: None, decimation: None, discarded })
    }

    /// From time stamps that must increase strictly and uniformly.
    ///
    /// # Errors
    /// As [`Self::new`], and [`MemError::Sample`] naming the first sample whose time is
    /// not increasing or off the uniform grid by more than 1e-4·h.
    pub fn from_times(times: &[f64], names: Vec<String>, values: Mat<f64>) -> Result<Self, MemError> {
        let (start, h) = uniform_grid(times, values.nrows())?;
        Self::new(names, start, h, values)
    }

    /// Moves the named columns from the outputs into the measured inputs (held by `hold`).
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for a name the record lacks, for a decimated record (attach
    /// inputs before decimating), or if no output would be left.
    pub fn with_inputs(self, inputs: &[&str], hold: Hold) -> Result<Self, MemError> {
        if inputs.is_empty() {
            return Ok(self);
        }
        if self.decimation.is_some() || self.inputs.is_some() {
            return Err(MemError::InvalidData(
                "inputs must be attached once, before the record is decimated".into(),
            ));
        }
        let index = |n: &str| {
            self.names.iter().position(|m| m == n).ok_or_else(|| {
                MemError::InvalidData(format!(
                    "the data have no input column `{n}` (columns: {})",
                    self.names.join(", ")
                ))
            })
        };
        let input_columns = inputs.iter().map(|n| index(n)).collect::<Result<Vec<_>, _>>()?;
        let output_columns: Vec<usize> =
            (0..self.names.len()).filter(|c| !input_columns.contains(c)).collect();
        if output_columns.is_empty() {
            return Err(MemError::InvalidData("every column is an input: no output is left to fit".into()));
        }
        let k = self.n_samples();
        let take = |cols: &[usize]| Mat::from_fn(k, cols.len(), |r, c| self.values[(r, cols[c])]);
        let names = |cols: &[usize]| cols.iter().map(|c| self.names[*c].clone()).collect::<Vec<_>>();
        Ok(Self {
            inputs: Some(Inputs { names: names(&input_columns), values: take(&input_columns), hold }),
            discarded: vec![0.0; output_columns.len()],
            values: take(&output_columns),
            names: names(&output_columns),
            ..self
        })
    }

    /// Output names.
    pub fn names(&self) -> &[String] {
        &self.names
    }
    /// Number of outputs p.
    pub fn n_outputs(&self) -> usize {
        self.values.ncols()
    }
    /// Number of samples K.
    pub fn n_samples(&self) -> usize {
        self.values.nrows()
    }
    /// Sample interval h.
    pub fn interval(&self) -> f64 {
        self.interval
    }
    /// Time of the first sample, in seconds after the model's t = 0 (where x(0) holds).
    pub fn start(&self) -> f64 {
        self.start
    }
    /// K × p values.
    pub fn values(&self) -> &Mat<f64> {
        &self.values
    }
    /// The same record with other output values (K × p, the same shape; inputs, decimation
    /// and names kept): readings corrected or set aside by a workflow.
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for another shape, [`MemError::Sample`] for a NaN/infinite
    /// value (naming its sample and output).
    pub fn with_values(&self, values: Mat<f64>) -> Result<Self, MemError> {
        if (values.nrows(), values.ncols()) != (self.values.nrows(), self.values.ncols()) {
            return Err(MemError::InvalidData(format!(
                "{} × {} values for a record of {} samples of {} outputs",
                values.nrows(),
                values.ncols(),
                self.values.nrows(),
                self.values.ncols()
            )));
        }
        check_values(&self.names, &values, "output")?;
        Ok(Self {
            names: self.names.clone(),
            interval: self.interval,
            start: self.start,
            values,
            inputs: self.inputs.clone(),
            decimation: self.decimation.clone(),
            discarded: self.discarded.clone(),
        })
    }
    /// The measured inputs, if any.
    pub fn inputs(&self) -> Option<&Inputs> {
        self.inputs.as_ref()
    }
    /// The decimation the values went through, if any (the model goes through it too).
    pub fn decimation(&self) -> Option<&Decimation> {
        self.decimation.as_ref()
    }
    /// Per output, the fraction of the raw record's energy (about its mean) that decimation
    /// removed: signal above the filter's band that the fit cannot use (0 without decimation).
    pub fn discarded(&self) -> &[f64] {
        &self.discarded
    }
    /// The time stamps.
    pub fn times(&self) -> Vec<f64> {
        (0..self.n_samples()).map(|k| self.start + k as f64 * self.interval).collect()
    }

    /// The noise-free response of `model` at `p`: `n_samples` samples every `interval` from
    /// t = 0, named by the model's outputs (a twin experiment's data).
    ///
    /// # Errors
    /// The model's failure, or non-finite outputs.
    pub fn simulate(
        model: &dyn ResponseModel,
        p: &[f64],
        interval: f64,
        n_samples: usize,
    ) -> Result<Self, MemError> {
        let names = model.output_names();
        let mut out = Response::zeros(n_samples, names.len(), p.len());
        model.respond(p, &Grid::free(interval), &mut out).map_err(|source| MemError::Model {
            experiment: 0,
            parameters: format!("{p:?}"),
            source,
        })?;
        Self::new(names, 0.0, interval, out.outputs)
    }

    /// The grid the model must be simulated on: (start, interval, samples) — the raw grid when
    /// the record was decimated.
    pub fn model_grid(&self) -> (f64, f64, usize) {
        match &self.decimation {
            Some(d) => (self.start, d.raw_interval(), d.raw_samples()),
            None => (self.start, self.interval, self.n_samples()),
        }
    }

    /// The named outputs only, in the given order.
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for a name the measurement lacks.
    pub fn select(&self, names: &[&str]) -> Result<Self, MemError> {
        let columns = names
            .iter()
            .map(|n| {
                self.names.iter().position(|m| m == n).ok_or_else(|| {
                    MemError::InvalidData(format!(
                        "the data have no column `{n}` (columns: {})",
                        self.names.join(", ")
                    ))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if columns.is_empty() {
            return Err(MemError::InvalidData("select at least one output".into()));
        }
        let values = Mat::from_fn(self.n_samples(), columns.len(), |k, o| self.values[(k, columns[o])]);
        check_values(&names.iter().map(|n| n.to_string()).collect::<Vec<_>>(), &values, "output")?;
        Ok(Self {
            names: names.iter().map(|n| n.to_string()).collect(),
            values,
            discarded: columns.iter().map(|c| self.discarded[*c]).collect(),
            ..self.clone()
        })
    }

    /// 1/RMS of each output (1 for an output that is identically zero), so that outputs in
    /// different units (rad, rad/s, strain) weigh alike in the fit.
    pub fn rms_weights(&self) -> Vec<f64> {
        (0..self.n_outputs())
            .map(|o| {
                let ms = (0..self.n_samples()).map(|k| self.values[(k, o)].powi(2)).sum::<f64>()
                    / self.n_samples() as f64;
                if ms > 0.0 && ms.is_finite() { 1.0 / ms.sqrt() } else { 1.0 }
            })
            .collect()
    }

    /// Keeps every `factor`-th sample (the first one included) after the root-raised-cosine
    /// low-pass filter of [`Decimation`]; the fit puts the model's outputs and sensitivities
    /// through the same filter at the raw rate, so decimating adds no bias. Inputs stay at the
    /// raw rate (they drive the model there).
    ///
    /// # Errors
    /// [`MemError::InvalidData`] for factor 0, a factor with fewer than 2 samples left, or a
    /// record decimated already.
    pub fn decimate(&self, factor: usize) -> Result<Self, MemError> {
        if factor == 0 {
            return Err(MemError::InvalidData("the decimation factor must be ≥ 1".into()));
        }
        if factor == 1 {
            return Ok(self.clone());
        }
        if self.decimation.is_some() {
            return Err(MemError::InvalidData("the record is decimated already".into()));
        }
        let k_in = self.n_samples();
        if factor > k_in - 1 {
            return Err(MemError::InvalidData(format!(
                "decimating {k_in} samples by {factor} leaves fewer than 2; use a factor ≤ {}",
                (k_in - 1).max(1)
            )));
        }
        let operator = Decimation::new(factor, k_in, self.interval);
        let values = operator.apply_columns(&self.values);
        let discarded = (0..self.n_outputs())
            .map(|o| {
                let column = self.values.col(o).try_as_col_major().expect("an owned Mat is column-major");
                operator.removed_fraction(column.as_slice())
            })
            .collect();
        Ok(Self {
            names: self.names.clone(),
            interval: self.interval * factor as f64,
            start: self.start,
            values,
            inputs: self.inputs.clone(),
            decimation: Some(operator),
            discarded,
        })
    }
}

/// Where a record that is not uniform breaks its own step: the first step that differs from the
/// record's usual one (the lower median of its steps) by more than √[`UNIFORM_TOLERANCE`] of
/// it (1 %), said as a gap (samples missing) or a short step. `None` where no single step does
/// (a slow drift of the stamps), which the caller reports against the mean grid.
fn step_break(times: &[f64]) -> Option<MemError> {
    let steps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let usual = sorted[(sorted.len() - 1) / 2];
    let k = steps.iter().position(|d| (d - usual).abs() > UNIFORM_TOLERANCE.sqrt() * usual)?;
    let (before, t, step) = (times[k], times[k + 1], steps[k]);
    let what = if step > usual {
        let missing = (step / usual).round() as i64 - 1;
        format!("a gap of {step} s, about {missing} sample(s) missing")
    } else {
        format!("a step of {step} s")
    };
    Some(MemError::Sample {
        sample: k + 1,
        message: format!(
            "time is not uniformly sampled: {t} after {before} is {what}, where the record's step is {usual} s; \
             give a uniformly sampled record (fill or cut at the gap)"
        ),
    })
}

/// (start, h) of strictly increasing, uniform time stamps.
fn uniform_grid(times: &[f64], n_rows: usize) -> Result<(f64, f64), MemError> {
    if times.len() != n_rows {
        return Err(MemError::InvalidData(format!("{} time stamps for {n_rows} samples", times.len())));
    }
    if times.len() < 2 {
        return Err(MemError::InvalidData(format!("need at least 2 samples, got {}", times.len())));
    }
    for (k, t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(MemError::Sample { sample: k, message: format!("the time {t} is not finite") });
        }
    }
    for (k, w) in times.windows(2).enumerate() {
        if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
            return Err(MemError::Sample {
                sample: k + 1,
                message: format!("time is not increasing ({} after {})", w[1], w[0]),
            });
        }
    }
    let h = (times[times.len() - 1] - times[0]) / (times.len() - 1) as f64;
    if !(h.is_finite() && h > 0.0) {
        return Err(MemError::InvalidData(format!("the sample interval {h} is not a positive number")));
    }
    if let Some((k, expected)) = (0..times.len())
        .map(|k| (k, times[0] + k as f64 * h))
        .find(|(k, expected)| (times[*k] - expected).abs() > UNIFORM_TOLERANCE * h)
    {
        return Err(step_break(times).unwrap_or_else(|| MemError::Sample {
            sample: k,
            message: format!(
                "time is not uniformly sampled: {} where {expected} was expected (h = {h})",
                times[k]
            ),
        }));
    }
    Ok((times[0], h))
}
