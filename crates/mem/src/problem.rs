//! The identification problem: experiments and the parameters they share, validated as one.

use crate::{Experiment, MemError};

/// One parameter to estimate: its name, starting value, bounds and typical size.
#[derive(Clone, Debug, PartialEq)]
pub struct Parameter {
    /// Its name (in reports and messages).
    pub name: String,
    /// The starting value.
    pub initial: f64,
    /// Lower bound (−∞ for none).
    pub lower: f64,
    /// Upper bound (+∞ for none).
    pub upper: f64,
    /// A typical magnitude, for parameters whose value may be near zero (an initial velocity):
    /// relative changes are measured against max(|P|, typical).
    pub typical: Option<f64>,
}

impl Parameter {
    /// An unbounded parameter.
    pub fn new(name: impl Into<String>, initial: f64) -> Self {
        Self { name: name.into(), initial, lower: f64::NEG_INFINITY, upper: f64::INFINITY, typical: None }
    }
    /// With bounds lower ≤ P ≤ upper.
    pub fn with_bounds(mut self, lower: f64, upper: f64) -> Self {
        self.lower = lower;
        self.upper = upper;
        self
    }
    /// With a typical size.
    pub fn with_typical(mut self, typical: f64) -> Self {
        self.typical = Some(typical);
        self
    }
    /// The scale relative changes are measured against: max(|P|, typical), or |P0|, or 1.
    pub(crate) fn scale(&self, value: f64) -> f64 {
        let s = value.abs().max(self.typical.unwrap_or(0.0));
        if s > 0.0 {
            s
        } else if self.initial != 0.0 {
            self.initial.abs()
        } else {
            1.0
        }
    }
}

/// Experiments and the parameters they share: one validated description of what to fit.
pub struct Problem<'a> {
    pub(crate) experiments: Vec<Experiment<'a>>,
    pub(crate) parameters: Vec<Parameter>,
}

impl<'a> Problem<'a> {
    /// Validates the whole problem at once.
    ///
    /// # Errors
    /// [`MemError::Parameter`] for a repeated name, a non-finite start, bounds with lower ≥
    /// upper or a start outside them, a non-positive typical size; [`MemError::Shape`] and
    /// [`MemError::OutputNames`] if an experiment's model, data and weights disagree;
    /// [`MemError::InvalidData`] for fewer readings than parameters.
    pub fn new(experiments: Vec<Experiment<'a>>, parameters: Vec<Parameter>) -> Result<Self, MemError> {
        if experiments.is_empty() {
            return Err(MemError::Shape("at least one experiment is needed".into()));
        }
        if parameters.is_empty() {
            return Err(MemError::Shape("at least one parameter is needed".into()));
        }
        for (i, p) in parameters.iter().enumerate() {
            let bad = |message: String| Err(MemError::Parameter { name: p.name.clone(), message });
            if parameters[..i].iter().any(|q| q.name == p.name) {
                return bad("appears twice".into());
            }
            if !p.initial.is_finite() {
                return bad(format!("the starting value {} is not finite", p.initial));
            }
            if p.lower.is_nan() || p.upper.is_nan() || p.lower >= p.upper {
                return bad(format!("the bounds [{}, {}] need lower < upper", p.lower, p.upper));
            }
            if p.initial < p.lower || p.initial > p.upper {
                return bad(format!(
                    "the starting value {} lies outside its bounds [{}, {}]",
                    p.initial, p.lower, p.upper
                ));
            }
            if let Some(t) = p.typical
                && !(t.is_finite() && t > 0.0)
            {
                return bad(format!("the typical size {t} must be finite and > 0"));
            }
        }
        for (i, e) in experiments.iter().enumerate() {
            e.validate(i, parameters.len())?;
        }
        let readings: usize = experiments.iter().map(|e| e.data.n_samples() * e.data.n_outputs()).sum();
        if readings < parameters.len() {
            return Err(MemError::InvalidData(format!(
                "the records hold {readings} readings (samples × outputs), fewer than the {} parameters to fit; give a longer record or free fewer parameters",
                parameters.len()
            )));
        }
        Ok(Self { experiments, parameters })
    }

    /// A problem whose parameters are named p1, p2, … with no bounds, starting at `p0`.
    ///
    /// # Errors
    /// As [`Problem::new`].
    pub fn unnamed(experiments: Vec<Experiment<'a>>, p0: &[f64]) -> Result<Self, MemError> {
        let parameters =
            p0.iter().enumerate().map(|(i, v)| Parameter::new(format!("p{}", i + 1), *v)).collect();
        Self::new(experiments, parameters)
    }

    /// The experiments.
    pub fn experiments(&self) -> &[Experiment<'a>] {
        &self.experiments
    }
    /// The parameters.
    pub fn parameters(&self) -> &[Parameter] {
        &self.parameters
    }
    /// The starting values.
    pub fn initial(&self) -> Vec<f64> {
        self.parameters.iter().map(|p| p.initial).collect()
    }
    /// The names.
    pub fn names(&self) -> Vec<String> {
        self.parameters.iter().map(|p| p.name.clone()).collect()
    }
    /// "name = value, …" for messages.
    pub(crate) fn describe(&self, p: &[f64]) -> String {
        self.parameters.iter().zip(p).map(|(q, v)| format!("{} = {v}", q.name)).collect::<Vec<_>>().join(", ")
    }
}
