//! Measurement-side effects on any model: a sensor's offset b, scale error s and drift d act
//! on its reading as y′ = (1 + s)·y + b + d·t (t from the model's t = 0), after the dynamics.
//! Their sensitivities are exact and trivial — ∂y′/∂b = 1, ∂y′/∂s = y, ∂y′/∂d = t — and the
//! dynamics' sensitivities are scaled by (1 + s). A drift that levels off with time constant τ
//! adds d·τ(1 − e^{−t/τ}) instead: ∂/∂d = τ(1 − e^{−t/τ}), ∂/∂τ = d[(1 − e^{−t/τ}) − (t/τ)e^{−t/τ}].
//! Crosstalk adds another output's signal, y′ = y + g·y_j (y_j as the dynamics give it):
//! ∂y′/∂g = y_j, and the dynamics' sensitivities gain g·∂y_j/∂P.
//! Quantization, the fifth sensor effect, is a reading model
//! (`mem::Experiment::with_quantization`), not a transform.

use expm::Response;
use mem::{BoxedError, Grid, ResponseModel};
use plant::EffectKind;

/// Which transform a sensor term applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensorTerm {
    /// y + b.
    Offset,
    /// (1 + s)·y.
    Scale,
    /// y + d·t.
    Drift,
    /// y + g·y_from: output `from`'s signal picked up.
    Crosstalk {
        /// The output picked up.
        from: usize,
    },
}

impl SensorTerm {
    /// The term of a sensor effect kind whose term has no further data (not crosstalk).
    pub fn of(kind: EffectKind) -> Option<Self> {
        match kind {
            EffectKind::OutputOffset => Some(SensorTerm::Offset),
            EffectKind::SensorScale => Some(SensorTerm::Scale),
            EffectKind::SensorDrift => Some(SensorTerm::Drift),
            _ => None,
        }
    }
}

/// One sensor effect: on which output, which term, its value, and — when it is fitted — the
/// position of its parameter after the dynamics' parameters.
#[derive(Clone, Debug)]
pub struct SensorEffect {
    /// Output index.
    pub output: usize,
    /// The transform.
    pub term: SensorTerm,
    /// Its value (used when not free).
    pub value: f64,
    /// Its position in the parameter vector P, if fitted.
    pub free: Option<usize>,
    /// A drift's time constant τ, when it levels off: its value, its name and its position in
    /// P, if fitted.
    pub time_constant: Option<TimeConstant>,
}

/// The time constant τ \[s\] a drift levels off with (y + d·τ(1 − e^{−t/τ})).
#[derive(Clone, Debug)]
pub struct TimeConstant {
    /// The parameter's name (`drift_time_<output>`).
    pub name: String,
    /// Its value (used when not free).
    pub value: f64,
    /// Its position in the parameter vector P, if fitted.
    pub free: Option<usize>,
}

impl SensorEffect {
    /// The term's added reading at `time` and its derivatives by the effect's value and by the
    /// time constant (for a drift that levels off), given the values `v` and `tau`.
    fn added(&self, v: f64, tau: Option<f64>, time: f64) -> (f64, f64, f64) {
        match (self.term, tau) {
            (SensorTerm::Offset, _) => (v, 1.0, 0.0),
            (_, Some(tau)) => {
                // 1 − e^{−t/τ} as −expm1(−t/τ): exact to rounding however long τ (d·t in the limit).
                let risen = -(-time / tau).exp_m1();
                let shape = tau * risen;
                (v * shape, shape, v * (risen - time / tau * (1.0 - risen)))
            }
            _ => (v * time, time, 0.0),
        }
    }
}

/// A response model with sensor effects on its outputs.
pub struct WithSensors {
    inner: Box<dyn ResponseModel + Send + Sync>,
    effects: Vec<SensorEffect>,
    /// The positions in P of the inner model's parameters, in its order.
    physics: Vec<usize>,
    n_params: usize,
}

impl WithSensors {
    /// Wraps `inner`, whose parameters sit at `physics` in P; the free sensor effects name
    /// their own positions. Every position of P is one of them.
    pub fn new(
        inner: Box<dyn ResponseModel + Send + Sync>,
        effects: Vec<SensorEffect>,
        physics: Vec<usize>,
    ) -> Self {
        let n_params = physics.len()
            + effects.iter().filter(|e| e.free.is_some()).count()
            + effects.iter().filter(|e| e.time_constant.as_ref().is_some_and(|t| t.free.is_some())).count();
        Self { inner, effects, physics, n_params }
    }
}

impl ResponseModel for WithSensors {
    fn n_params(&self) -> usize {
        self.n_params
    }
    fn output_names(&self) -> Vec<String> {
        self.inner.output_names()
    }
    fn input_names(&self) -> Vec<String> {
        self.inner.input_names()
    }
    fn accuracy(&self) -> f64 {
        self.inner.accuracy()
    }
    fn growth_rate(&self, p: &[f64]) -> Option<f64> {
        let inner: Vec<f64> = self.physics.iter().map(|&i| p[i]).collect();
        self.inner.growth_rate(&inner)
    }
    fn respond(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        self.sense(p, grid, out, true)
    }
    fn respond_outputs(&self, p: &[f64], grid: &Grid<'_>, out: &mut Response) -> Result<(), BoxedError> {
        self.sense(p, grid, out, false)
    }
}

impl WithSensors {
    /// The dynamics' response as the sensors read it, with the sensitivities if `sensitivities`
    /// (the outputs are the same bits either way).
    fn sense(
        &self,
        p: &[f64],
        grid: &Grid<'_>,
        out: &mut Response,
        sensitivities: bool,
    ) -> Result<(), BoxedError> {
        let j = if sensitivities { self.physics.len() } else { 0 };
        let (k, n_out) = (out.outputs.nrows(), out.outputs.ncols());
        let mut raw = Response::zeros(k, n_out, j);
        let inner: Vec<f64> = self.physics.iter().map(|&i| p[i]).collect();
        if sensitivities {
            self.inner.respond(&inner, grid, &mut raw)?;
        } else {
            self.inner.respond_outputs(&inner, grid, &mut raw)?;
        }
        out.outputs.copy_from(&raw.outputs);
        if sensitivities {
            out.sensitivities.fill(0.0);
            for (c, &i) in self.physics.iter().enumerate() {
                out.sensitivities.as_mut().col_mut(i).copy_from(raw.sensitivities.col(c));
            }
        }
        let value = |e: &SensorEffect| e.free.map_or(e.value, |i| p[i]);
        // Scales first (they multiply the dynamics' output and sensitivities), then the sums.
        for e in self.effects.iter().filter(|e| e.term == SensorTerm::Scale) {
            let factor = 1.0 + value(e);
            for t in 0..k {
                out.outputs[(t, e.output)] *= factor;
                if !sensitivities {
                    continue;
                }
                for &i in &self.physics {
                    out.sensitivities[(t * n_out + e.output, i)] *= factor;
                }
                if let Some(i) = e.free {
                    out.sensitivities[(t * n_out + e.output, i)] = raw.outputs[(t, e.output)];
                }
            }
        }
        for e in self.effects.iter() {
            let SensorTerm::Crosstalk { from } = e.term else { continue };
            let g = value(e);
            for t in 0..k {
                out.outputs[(t, e.output)] += g * raw.outputs[(t, from)];
                if !sensitivities {
                    continue;
                }
                for (c, &i) in self.physics.iter().enumerate() {
                    out.sensitivities[(t * n_out + e.output, i)] +=
                        g * raw.sensitivities[(t * n_out + from, c)];
                }
                if let Some(i) = e.free {
                    out.sensitivities[(t * n_out + e.output, i)] = raw.outputs[(t, from)];
                }
            }
        }
        for e in self.effects.iter().filter(|e| matches!(e.term, SensorTerm::Offset | SensorTerm::Drift)) {
            let v = value(e);
            let tau = e.time_constant.as_ref().map(|c| c.free.map_or(c.value, |i| p[i]));
            let tau_free = e.time_constant.as_ref().and_then(|c| c.free);
            for t in 0..k {
                let time = grid.start + t as f64 * grid.interval;
                let (add, slope, by_tau) = e.added(v, tau, time);
                out.outputs[(t, e.output)] += add;
                if sensitivities {
                    if let Some(i) = e.free {
                        out.sensitivities[(t * n_out + e.output, i)] = slope;
                    }
                    if let Some(i) = tau_free {
                        out.sensitivities[(t * n_out + e.output, i)] = by_tau;
                    }
                }
            }
        }
        Ok(())
    }
}
