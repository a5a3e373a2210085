//! The refits behind the evidence: a candidate's full refit, and the held-out refits of the
//! baseline and the shortlist on each fold, with and without the model's own parameters free.

use super::answer::last_error;
use super::catalog::{Located, Trial};
use super::evidence::{LikelihoodFit, block_length, folds};
use crate::WorkflowError;
use faer::Mat;
use mem::Measurement;
use models::{FitOutcome, FitRequest, Model, ModelEffect};

/// A refit stops when its next step would lower ‖Y_error‖² by less than this fraction: the
/// log-likelihood is then within a hundredth of a nat of its optimum per thousand residuals.
/// (10⁻⁴ saved a sixth of the time but changed two answers near the threshold on a held-out
/// draw: the reference fit's residual must be converged.)
const COST_TOLERANCE: f64 = 1e-5;

/// Iterations of a held-out refit, which starts from the full refit's values.
const HELD_OUT_ITERATIONS: usize = 20;

/// A fit on every sample.
pub struct Fitted {
    /// The fit.
    pub outcome: FitOutcome,
}

impl Fitted {
    /// Fits `model` with `free` to every sample of `data`.
    pub fn full(
        model: &Model,
        data: &Measurement,
        free: &[String],
        iterations: usize,
    ) -> Result<Self, WorkflowError> {
        Ok(Self { outcome: refit(model, data, free, None, iterations)? })
    }

    /// Fits `model` with `free` to every sample of `data`, to the fitter's own convergence: the
    /// baseline, which starts from the file's values. A linear model's fit to a strongly
    /// nonlinear decay crosses plateaus where a step lowers the error by less than
    /// [`COST_TOLERANCE`] before it finds the valley (a structure with a hardening storey, 15 %
    /// of its force at the peak: stopped there after 7 iterations at k1 = 1.2·10⁸ N/m, 46× the
    /// file's, ‖Y_error‖ 3,852; to convergence 58 iterations and 1,042), and every candidate
    /// starts where the baseline ends.
    pub fn converged(
        model: &Model,
        data: &Measurement,
        free: &[String],
        iterations: usize,
    ) -> Result<Self, WorkflowError> {
        Ok(Self { outcome: refit_to(model, data, free, None, iterations, Precision::Optimum)? })
    }
}

/// The two folds of a record: alternate blocks of about a second.
pub struct Folds {
    /// Sample weights of each fold (1 in it, 0 outside).
    pub weights: [Vec<f64>; 2],
}

impl Folds {
    /// The folds of `data`.
    pub fn new(data: &Measurement) -> Self {
        Self { weights: folds(data.n_samples(), block_length(data.n_samples(), data.interval())) }
    }
}

/// How far a refit goes before it stops.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Precision {
    /// Until a step lowers ‖Y_error‖² by less than [`COST_TOLERANCE`]: enough for evidence
    /// between candidates that each start near their optimum.
    Evidence,
    /// To the fitter's own convergence. A parameter whose direction is weak next to the
    /// others (a beam's length beside its EI/ρ and ρ: one singular value in 3·10³) starts
    /// with damped steps that lower the error by a few parts in 10⁶ each before the damping
    /// relaxes; the evidence tolerance would stop it there, where it started.
    Optimum,
}

pub(super) fn refit(
    model: &Model,
    data: &Measurement,
    free: &[String],
    sample_weights: Option<&[f64]>,
    iterations: usize,
) -> Result<FitOutcome, WorkflowError> {
    refit_to(model, data, free, sample_weights, iterations, Precision::Evidence)
}

/// [`refit`] to a chosen [`Precision`].
pub(super) fn refit_to(
    model: &Model,
    data: &Measurement,
    free: &[String],
    sample_weights: Option<&[f64]>,
    iterations: usize,
    precision: Precision,
) -> Result<FitOutcome, WorkflowError> {
    fit_by(model, data, free, sample_weights, iterations, precision, None)
}

/// [`refit_to`] on the whole record, by the likelihood `under` where given (generalised least
/// squares; a form test's refits on a record whose noise is coloured beyond AR(1)).
pub(super) fn refit_under(
    model: &Model,
    data: &Measurement,
    free: &[String],
    under: Option<&LikelihoodFit>,
    iterations: usize,
    precision: Precision,
) -> Result<FitOutcome, WorkflowError> {
    fit_by(model, data, free, None, iterations, precision, under)
}

/// The one refit every path makes: the RMS-weighted error, or the likelihood `under` (the held-out
/// refits, [`held_out`]).
fn fit_by(
    model: &Model,
    data: &Measurement,
    free: &[String],
    sample_weights: Option<&[f64]>,
    iterations: usize,
    precision: Precision,
    under: Option<&LikelihoodFit>,
) -> Result<FitOutcome, WorkflowError> {
    let refs: Vec<&str> = free.iter().map(|s| s.as_str()).collect();
    let mut request = FitRequest::new(&refs);
    request.max_iterations = iterations;
    request.derivative_check = mem::DerivativeCheck::Skip;
    request.integrator = models::Integrator::Exponential { max_step: max_step(model) };
    request.cost_tolerance = (precision == Precision::Evidence).then_some(COST_TOLERANCE);
    if let Some(w) = sample_weights {
        request.sample_weights = vec![w.to_vec()];
    }
    if let Some(under) = under {
        request.output_weights = Some(under.weights.clone());
        match &under.predictors {
            Some(predictors) => request.noise_predictors = Some(predictors.clone()),
            None => request.noise_correlation = Some(under.rho.clone()),
        }
    }
    Ok(models::fit(model, data, &request)?)
}

/// The exponential integrator's longest substep for `model`: the default, or a fortieth of
/// the period of a structure's highest oscillating mode if that is shorter (a force at a
/// coordinate acts on the time scale of the modes there), but never below a sixteenth of the
/// default — the linear part is exact however fast, and a refit that wanders to an extreme
/// stiffness must not cost hours. For the slewing rig, twice the default (1/640 s): the
/// integrator is second order, and at that substep the catalog's effects stay within 10⁻⁵ of
/// the adaptive solver's outputs (a dead band's motor rate within 6·10⁻⁴ of its peak, a few
/// hundredths of the sensor noise) — `models/tests/integration/exponential.rs` holds both substeps — for
/// half the cost of every candidate's fit.
pub(super) fn max_step(model: &Model) -> f64 {
    let default = models::exponential::DEFAULT_MAX_STEP;
    match model {
        Model::Structure(_) => model
            .modes()
            .ok()
            .and_then(|m| m.iter().filter(|r| r.damping_ratio < 1.0).map(|r| r.frequency_hz).reduce(f64::max))
            .filter(|f| *f > 0.0)
            .map_or(default, |f| default.min(1.0 / (40.0 * f)).max(default / 16.0)),
        Model::Slewing(_) => 2.0 * default,
    }
}

/// The model of a trial: `start` with the effect and its bounds.
pub(super) fn with_effect(
    start: &Model,
    trial: &Trial,
    effect: &ModelEffect,
) -> Result<Model, WorkflowError> {
    let mut model = start.clone();
    if let (Some(kind), Some(slewing)) = (trial.replaces, model.as_slewing_mut()) {
        slewing.remove_effect(kind, None)?;
    }
    model.add_effect(effect.clone())?;
    with_bounds(&mut model, trial)?;
    Ok(model)
}

/// Sets the bounds of a trial's parameters.
fn with_bounds(model: &mut Model, trial: &Trial) -> Result<(), WorkflowError> {
    for (name, b) in &trial.bounds {
        model.set_bounds(name, *b)?;
    }
    Ok(())
}

fn names(free: &[String], extra: impl IntoIterator<Item = String>) -> Vec<String> {
    let mut out = free.to_vec();
    for name in extra {
        if !out.contains(&name) {
            out.push(name);
        }
    }
    out
}

/// How far from its file value a free parameter of the reference may end (a factor either way)
/// before the candidates are refitted from the file's values too ([`Restart`]).
const RAN_OFF: f64 = 10.0;

/// A free parameter of the reference that ended more than a decade from the model file's value: the
/// diagnosis then refitted every candidate from the file's values too.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RanOff {
    /// The parameter.
    pub name: String,
    /// Its value in the model file.
    pub file: f64,
    /// Its value in the reference fit.
    pub fitted: f64,
}

/// A second start for every trial, where the reference ran far from the model file: the model
/// file's values of the free parameters, and the trials made at that model.
///
/// A linear model fitted to a record that a strong nonlinearity shapes can wander off to
/// parameters no structure has, where the error falls slowly and no effect added there finds
/// its way back. On the forced draw 20261363 a roof's dry friction (4 % of its storey's force
/// at the peak) drove the baseline's k₃ to 380× the file's and α to 40× in 100 iterations
/// (‖Y_error‖ 942, not converged). Every candidate started there: the friction at the roof,
/// scaled by that stiffness, ran to a force 37× the truth, and the answer was `none`. From the
/// file's values the same friction converges in 8 iterations to 2,734 N against the truth's
/// 2,620 N (‖Y_error‖ 13).
pub(super) struct Restart {
    /// The reference's model with its free parameters at the file's values.
    pub model: Model,
    /// The catalog's trials at that model (their starting values and bounds scaled by it).
    pub trials: Vec<Trial>,
}

impl Restart {
    /// The reference's free parameters that ended, off their bounds, more than [`RAN_OFF`]
    /// times from their (nonzero) file value or on the other side of zero.
    pub(super) fn ran_off(file: &Model, reference: &FitOutcome) -> Vec<RanOff> {
        let report = &reference.report;
        Self::ran_off_of(file, &report.names, &report.parameters, &report.on_bound)
    }

    /// [`Self::ran_off`] of fitted `values` (with their `on_bound` sides) of the parameters `names`.
    fn ran_off_of(
        file: &Model,
        names: &[String],
        values: &[f64],
        on_bound: &[Option<mem::Side>],
    ) -> Vec<RanOff> {
        names
            .iter()
            .enumerate()
            .filter_map(|(i, name)| {
                let (was, now) = (file.value(name).ok()?, *values.get(i)?);
                let off_bounds = on_bound.get(i).is_none_or(Option::is_none);
                let ratio = now / was;
                (off_bounds
                    && was != 0.0
                    && ratio.is_finite()
                    && (ratio <= 0.0 || !(1.0 / RAN_OFF..=RAN_OFF).contains(&ratio)))
                .then(|| RanOff { name: name.clone(), file: was, fitted: now })
            })
            .collect()
    }

    /// The reference's fitted model with its free parameters at the file's values (`None` if
    /// one cannot be set there).
    pub(super) fn model(file: &Model, reference: &FitOutcome, free: &[String]) -> Option<Model> {
        let mut model = reference.fitted.clone();
        for name in free {
            model.set(name, file.value(name).ok()?).ok()?;
        }
        Some(model)
    }

    /// For each of `trials`, the index of the same trial here (the same label and kind, its
    /// n-th occurrence for the n-th), if there is one.
    pub(super) fn matching(&self, trials: &[Trial]) -> Vec<Option<usize>> {
        let key = |t: &Trial| (t.kind, t.label.clone());
        let mut used = vec![false; self.trials.len()];
        trials
            .iter()
            .map(|t| {
                let j = (0..self.trials.len()).find(|&j| !used[j] && key(&self.trials[j]) == key(t))?;
                used[j] = true;
                Some(j)
            })
            .collect()
    }
}

/// The refit with the smaller error of two (a finite error before a non-finite one; the first
/// on a tie), or the one that did not fail.
pub(super) fn better(
    a: Result<FitOutcome, WorkflowError>,
    b: Result<FitOutcome, WorkflowError>,
) -> Result<FitOutcome, WorkflowError> {
    match (a, b) {
        (Ok(a), Ok(b)) => {
            let (ea, eb) = (last_error(&a), last_error(&b));
            Ok(if eb < ea || (eb.is_finite() && !ea.is_finite()) { b } else { a })
        }
        (Err(_), b) => b,
        (a, Err(_)) => a,
    }
}

/// Refits `model`, which carries the trial's effect already (a candidate's own fit), with `free`
/// and the trial's own parameters free, on every sample.
pub(super) fn refit_with_effect(
    model: &Model,
    trial: &Trial,
    free: &[String],
    data: &Measurement,
    iterations: usize,
) -> Result<FitOutcome, WorkflowError> {
    refit(model, data, &names(free, trial.freed.iter().cloned()), None, iterations)
}

/// Refits `start` with the trial's effect on every sample (or on the weighted ones), from each
/// of its starting values, and keeps the refit with the smallest error.
pub fn fit_trial(
    start: &Model,
    trial: &Trial,
    free: &[String],
    data: &Measurement,
    sample_weights: Option<&[f64]>,
    iterations: usize,
) -> Result<Fitted, WorkflowError> {
    let free = names(free, trial.freed.iter().cloned());
    let mut best: Option<Result<FitOutcome, WorkflowError>> = None;
    for effect in std::iter::once(&trial.effect).chain(&trial.alternatives) {
        let attempt = with_effect(start, trial, effect)
            .and_then(|model| refit(&model, data, &free, sample_weights, iterations));
        best = Some(match best {
            None => attempt,
            Some(b) => better(b, attempt),
        });
    }
    let mut outcome = best.expect("a trial has a start")?;
    // A resonance pressing on a bound of its search range is followed there (`Located`).
    let bound = |name: &str| trial.bounds.iter().find(|(n, _)| n == name).map(|(_, b)| *b);
    if let Some(located) = trial.located.as_ref() {
        let mut range = bound(&located.name);
        for _ in 0..Located::MAX_MOVES {
            let report = &outcome.report;
            let Some(i) = report.names.iter().position(|n| *n == located.name) else { break };
            let (Some(side), Some(now)) = (report.on_bound[i], range) else { break };
            let Some(next) = located.moved(now, report.parameters[i], side) else { break };
            let mut model = outcome.fitted.clone();
            model.set_bounds(&located.name, next)?;
            let Ok(moved) = refit(&model, data, &free, sample_weights, iterations) else { break };
            if last_error(&moved) > last_error(&outcome) {
                break;
            }
            range = Some(next);
            outcome = moved;
        }
    }
    Ok(Fitted { outcome })
}

/// What a held-out refit starts from.
pub enum HeldOut<'a> {
    /// The reference model.
    Reference(&'a Model),
    /// A trial, from its full refit if it has one.
    Candidate(&'a Trial, Option<&'a Model>),
}

/// Fits on fold `fold` (the reference's parameters `free`, and a candidate's own) and returns
/// the residual of its prediction of every sample (the other fold's are scored).
pub fn held_out(
    from: HeldOut<'_>,
    fold: usize,
    folds: &Folds,
    free: &[String],
    data: &Measurement,
    under: &LikelihoodFit,
) -> Result<Mat<f64>, WorkflowError> {
    let train = &folds.weights[fold];
    let outcome = match from {
        HeldOut::Reference(model) => {
            fit_by(model, data, free, Some(train), HELD_OUT_ITERATIONS, Precision::Evidence, Some(under))?
        }
        HeldOut::Candidate(trial, fitted) => {
            // The full refit's model carries its trial's bounds (a resonance's range as it
            // was last moved).
            let model = match fitted {
                Some(m) => m.clone(),
                None => return Err(WorkflowError::Unscored(trial.label.clone())),
            };
            let free = names(free, trial.freed.iter().cloned());
            fit_by(&model, data, &free, Some(train), HELD_OUT_ITERATIONS, Precision::Evidence, Some(under))?
        }
    };
    Ok(outcome.first().residual())
}

#[cfg(test)]
mod tests {
    use super::Restart;
    use models::Model;

    /// The shear building's file (k₁ 2.5, k₂ 2.25, k₃ 1.875 MN/m, α 0.375 s⁻¹, β 1.25·10⁻³ s):
    /// 20261363's reference (k₃ 380× the file's, α 40×) ran off in both; a parameter within a
    /// decade, one on its bound at zero and one whose file value is zero did not; one that
    /// crossed zero did.
    #[test]
    fn a_reference_runs_off_where_a_parameter_ends_beyond_a_decade_of_its_file_value() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/shear_building.ron");
        let text = std::fs::read_to_string(path).unwrap();
        let file = Model::from_ron(&text, "shear_building.ron").unwrap();
        let names: Vec<String> = ["k1", "k2", "k3", "alpha", "beta"].map(String::from).to_vec();
        let ran = |values: &[f64], on_bound: &[Option<mem::Side>]| -> Vec<String> {
            Restart::ran_off_of(&file, &names, values, on_bound).into_iter().map(|r| r.name).collect()
        };
        let free = [None; 5];
        assert_eq!(
            ran(&[2.57e6, 1.35e6, 7.11e8, 14.99, 0.0], &[None, None, None, None, Some(mem::Side::Lower)]),
            ["k3", "alpha"]
        );
        assert!(ran(&[2.4e7, 2.3e5, 1.875e6, 3.0, 1.3e-4], &free).is_empty(), "within a decade each way");
        assert_eq!(ran(&[2.6e7, 2.2e5, 1.875e6, 0.375, 1.25e-3], &free), ["k1", "k2"]);
        assert_eq!(ran(&[2.5e6, 2.25e6, -1.0e6, 0.375, 1.25e-3], &free), ["k3"], "across zero");
        let mut zero = file.clone();
        zero.set("beta", 0.0).unwrap();
        assert!(Restart::ran_off_of(&zero, &names[4..], &[1.0], &[None]).is_empty(), "no decade of zero");
    }
}
