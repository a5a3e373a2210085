//! What a model must provide: the linear capability trait and the general response trait.

use crate::error::BoxedError;
use crate::{Measurement, MemError};
use expm::Response;
use faer::Mat;

/// A linear state-space model at one parameter vector P: everything the MEM needs.
#[derive(Clone, Debug)]
pub struct Linearized {
    /// A(P), N × N.
    pub a: Mat<f64>,
    /// ∂A/∂P_i, one N × N matrix per parameter.
    pub da: Vec<Mat<f64>>,
    /// C(P), p × N.
    pub c: Mat<f64>,
    /// ∂C/∂P_i if C depends on P (the paper assumes it does not, Eq. 6–7).
    pub dc: Option<Vec<Mat<f64>>>,
    /// x(0), length N.
    pub x0: Vec<f64>,
    /// ∂x(0)/∂P, N × j, if x(0) depends on P (the paper assumes it does not, Eq. 10).
    pub dx0: Option<Mat<f64>>,
}

/// A parameterised family of linear models ẋ = A(P)x, y = C(P)x from x(0) (paper Eqs. 1–2).
///
/// Implement this for your own model to tune it with [`crate::Fit`]; wrap it in
/// [`LinearResponse`] to use it as a [`ResponseModel`].
pub trait LinearModel {
    /// The model's own error type.
    type Error: std::error::Error + Send + Sync + 'static;
    /// Number of states N.
    fn n_states(&self) -> usize;
    /// Number of parameters j.
    fn n_params(&self) -> usize;
    /// Number of outputs p.
    fn n_outputs(&self) -> usize;
    /// A, ∂A/∂P_i, C, x(0) (and optionally ∂C/∂P_i, ∂x(0)/∂P_i) at P.
    ///
    /// # Errors
    /// Whatever makes the model impossible at P (e.g. a negative inertia).
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error>;
}

/// Anything that can produce outputs and output sensitivities at K uniform samples:
/// the interface the [`crate::Fit`] iteration works through.
pub trait ResponseModel {
    /// Number of parameters j.
    fn n_params(&self) -> usize;
    /// Number of outputs p.
    fn n_outputs(&self) -> usize;
    /// Fills `out` (its size sets K) with y(t_k) and ∂y(t_k)/∂P at t_k = k·h.
    ///
    /// # Errors
    /// The model's failure, boxed.
    fn respond(&self, p: &[f64], h: f64, out: &mut Response) -> Result<(), BoxedError>;
}

/// The MEM for a [`LinearModel`]: one exponential and its Fréchet derivatives per evaluation,
/// then the sensitivity propagator (paper Eq. 9 at constant h) — or, for larger
/// well-conditioned models, the same quantities in modal coordinates (`expm::free_decay`).
#[derive(Clone, Debug)]
pub struct LinearResponse<M>(pub M);

impl<M: LinearModel> ResponseModel for LinearResponse<M> {
    fn n_params(&self) -> usize {
        self.0.n_params()
    }
    fn n_outputs(&self) -> usize {
        self.0.n_outputs()
    }
    fn respond(&self, p: &[f64], h: f64, out: &mut Response) -> Result<(), BoxedError> {
        let lin = self.0.linearize(p)?;
        let da: Vec<_> = lin.da.iter().map(|d| d.as_ref()).collect();
        let dc: Option<Vec<_>> = lin.dc.as_ref().map(|dc| dc.iter().map(|d| d.as_ref()).collect());
        expm::free_decay(
            lin.a.as_ref(),
            &da,
            lin.c.as_ref(),
            dc.as_deref(),
            &lin.x0,
            lin.dx0.as_ref().map(|d| d.as_ref()),
            h,
            out,
            expm::Strategy::Auto,
        )?;
        Ok(())
    }
}

/// The residual of an interval reading: the distance of the model's output from
/// [y − half_width, y + half_width], signed, for the plain residual `r` = y − ŷ (0 inside;
/// `r` itself for an exact reading, half_width = 0). See [`Experiment::with_quantization`].
pub fn interval_residual(r: f64, half_width: f64) -> f64 {
    r - r.clamp(-half_width, half_width)
}

/// One experiment: a model and the measurement it must reproduce, with output weights.
pub struct Experiment<'a> {
    /// The model (with this experiment's initial condition and sensors).
    pub model: &'a (dyn ResponseModel + Sync),
    /// The measured free decay.
    pub data: &'a Measurement,
    /// Weight per output (residuals are multiplied by it); see [`Measurement::rms_weights`].
    pub weights: Vec<f64>,
    /// Half-width of the reading's interval per output (0: an exact reading); see
    /// [`Experiment::with_quantization`].
    pub half_widths: Vec<f64>,
}

impl<'a> Experiment<'a> {
    /// An experiment with unit weights (the paper's Eq. 22 error).
    pub fn new(model: &'a (dyn ResponseModel + Sync), data: &'a Measurement) -> Self {
        Self { model, data, weights: vec![1.0; data.n_outputs()], half_widths: vec![0.0; data.n_outputs()] }
    }

    /// Uses weights 1/RMS(measured output), so outputs of different units count alike.
    pub fn normalized(model: &'a (dyn ResponseModel + Sync), data: &'a Measurement) -> Self {
        Self { model, data, weights: data.rms_weights(), half_widths: vec![0.0; data.n_outputs()] }
    }

    /// Declares quantized outputs: `steps[o] = Some(Δ)` means output o was read by a quantizer
    /// of step Δ, so a reading y only says that the value lies in [y − Δ/2, y + Δ/2]. Its
    /// residual is then the distance from the model's output to that interval,
    /// r = sign(y − ŷ)·max(0, |y − ŷ| − Δ/2) — interval-censored least squares — and rows
    /// inside the interval carry no sensitivity. A model that is right to within the step is
    /// not charged for the quantizer's rounding; a continuous residual would be, by Δ²/12 per
    /// sample however good the model.
    pub fn with_quantization(mut self, steps: &[Option<f64>]) -> Self {
        self.half_widths = steps.iter().map(|s| s.map_or(0.0, |d| 0.5 * d)).collect();
        self
    }

    /// Checks that model, data and weights fit together.
    pub(crate) fn validate(&self, index: usize, n_params: usize) -> Result<(), MemError> {
        if self.model.n_outputs() != self.data.n_outputs() {
            return Err(MemError::Shape(format!(
                "experiment {index}: the model has {} outputs but the data have {}",
                self.model.n_outputs(),
                self.data.n_outputs()
            )));
        }
        if self.model.n_params() != n_params {
            return Err(MemError::Shape(format!(
                "experiment {index}: the model has {} parameters, P has {n_params}",
                self.model.n_params()
            )));
        }
        if self.weights.len() != self.data.n_outputs()
            || self.weights.iter().any(|w| !(w.is_finite() && *w >= 0.0))
        {
            return Err(MemError::Shape(format!(
                "experiment {index}: need one finite weight ≥ 0 per output"
            )));
        }
        if self.half_widths.len() != self.data.n_outputs()
            || self.half_widths.iter().any(|w| !(w.is_finite() && *w >= 0.0))
        {
            return Err(MemError::Shape(format!(
                "experiment {index}: need one finite quantization step ≥ 0 per output"
            )));
        }
        Ok(())
    }
}
