//! The discrepancy workflow: baseline fit → localise → refit with each candidate effect →
//! score → name the effect with the strongest evidence, or none.

use crate::WorkflowError;
use crate::localise::{Localisation, localise};
use crate::quantization;
use crate::stats::{ar1_innovations, delta_bic, ljung_box};
use faer::Mat;
use mem::Measurement;
use models::{FitOutcome, FitRequest, Model, align, fit};
use plant::{Effect, ModeKind, ParamId, Sensor, SlewingModel};
use rayon::prelude::*;

/// Settings of [`diagnose`].
#[derive(Clone, Debug)]
pub struct DiagnoseOptions {
    /// Parameters refitted in the baseline and in every candidate.
    pub free: Vec<String>,
    /// An effect is named only if its BIC improves on the baseline's by more than this
    /// (10: "very strong" evidence on the Kass–Raftery scale).
    pub bic_threshold: f64,
    /// Restrict the candidates to these catalog names (all if empty).
    pub only: Vec<String>,
}

impl DiagnoseOptions {
    /// Threshold 10, every catalog effect.
    pub fn new(free: &[&str]) -> Self {
        Self { free: free.iter().map(|s| s.to_string()).collect(), bic_threshold: 10.0, only: Vec::new() }
    }
}

/// A parameter of an effect, as fitted.
#[derive(Clone, Debug)]
pub struct EffectParameter {
    /// Parameter name (`current_limit`, `offset_theta`, …).
    pub name: String,
    /// Fitted value.
    pub value: f64,
    /// Standard error.
    pub std_error: f64,
}

/// One candidate effect and its score.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// Catalog name.
    pub effect: String,
    /// Catalog name with its target, e.g. `output_offset(theta)`.
    pub label: String,
    /// ‖Y_error‖ after the refit (weighted like the baseline).
    pub error: f64,
    /// 1 − error/baseline error.
    pub reduction: f64,
    /// BIC(candidate) − BIC(baseline): negative is better.
    pub delta_bic: f64,
    /// −ΔBIC (larger is stronger evidence).
    pub score: f64,
    /// Smallest Ljung–Box p-value of the refitted residuals (whiteness).
    pub whiteness_p: f64,
    /// The effect's parameters.
    pub parameters: Vec<EffectParameter>,
    /// Why a candidate could not be scored, if it could not.
    pub failure: Option<String>,
    /// The refitted model.
    pub model: Option<SlewingModel>,
    /// The refit.
    pub outcome: Option<FitOutcome>,
}

/// The answer of [`diagnose`].
#[derive(Clone, Debug)]
pub struct Diagnosis {
    /// The baseline fit.
    pub baseline: FitOutcome,
    /// Where it disagrees with the data.
    pub localisation: Localisation,
    /// All candidates, strongest evidence first.
    pub candidates: Vec<Candidate>,
    /// Index of the named candidate, if one passes the threshold.
    pub chosen: Option<usize>,
}

impl Diagnosis {
    /// The named effect's catalog name, or `"none"`.
    pub fn effect(&self) -> &str {
        self.chosen.map_or("none", |i| self.candidates[i].effect.as_str())
    }
    /// The augmented model (the baseline's if none is named).
    pub fn augmented(&self) -> &SlewingModel {
        self.chosen
            .and_then(|i| self.candidates[i].model.as_ref())
            .unwrap_or_else(|| slewing(&self.baseline.fitted))
    }
    /// The augmented model's error (the baseline's if none is named).
    pub fn augmented_error(&self) -> f64 {
        self.chosen.map_or(self.baseline_error(), |i| self.candidates[i].error)
    }
    /// The baseline's error.
    pub fn baseline_error(&self) -> f64 {
        *self.baseline.report.error_history.last().expect("a history has its start")
    }
}

/// A candidate to try: the effect with its starting values and plausible bounds.
struct Trial {
    effect: Effect,
    label: String,
    bounds: Vec<(ParamId, (f64, f64))>,
}

fn servo_rate(model: &SlewingModel) -> f64 {
    let omega = model
        .modal()
        .ok()
        .and_then(|rows| rows.into_iter().find(|r| r.kind == ModeKind::Servo))
        .map_or(1.0, |r| 2.0 * std::f64::consts::PI * r.frequency_hz);
    omega * model.initial_state()[0].abs().max(1e-3)
}

/// The catalog's candidates for this model and residual, with data-driven starting values.
fn trials(model: &SlewingModel, localisation: &Localisation) -> Vec<Trial> {
    let c = model.constants();
    let theta0 = model.initial_state()[0].abs().max(1e-3);
    let ks = c.amplifier_gain * c.position_gain * c.torque_constant / c.armature_resistance;
    let rate = servo_rate(model);
    // The current the loop demands at the start; a limit far above it is never reached.
    let demand = c.amplifier_gain * c.position_gain * theta0 / c.armature_resistance;
    let drag = 0.2 * c.viscous_damping.max(1e-3) / rate;
    let mut out = vec![
        Trial {
            effect: Effect::AmplifierSaturation { current_limit: 0.5 * demand, sharp: false },
            label: "amplifier_saturation".into(),
            bounds: vec![(ParamId::CurrentLimit, (0.01 * demand, 3.0 * demand))],
        },
        Trial {
            // Smoothing over 1 % of the peak rate: close to a true dry-friction switch.
            effect: Effect::CoulombFriction { torque: 0.02 * ks * theta0, smoothing_velocity: 0.01 * rate },
            label: "coulomb_friction".into(),
            bounds: vec![(ParamId::CoulombTorque, (0.0, ks * theta0))],
        },
        Trial {
            effect: Effect::QuadraticDrag { hub: drag },
            label: "quadratic_drag".into(),
            bounds: vec![(ParamId::DragHub, (0.0, 1000.0 * drag))],
        },
        Trial {
            effect: Effect::TimeDelay { delay: 0.02 },
            label: "time_delay".into(),
            bounds: vec![(ParamId::Delay, (1e-4, 2.0))],
        },
    ];
    for s in model.sensors() {
        out.push(Trial {
            effect: Effect::OutputOffset { sensor: *s, offset: 0.0 },
            label: format!("output_offset({})", s.output_name()),
            bounds: Vec::new(),
        });
    }
    let existing: Vec<f64> =
        model.modal().map(|rows| rows.iter().map(|r| r.frequency_hz).collect()).unwrap_or_default();
    if let Some(m) = localisation
        .residual_modes
        .iter()
        .find(|m| existing.iter().all(|f| (m.frequency_hz / f - 1.0).abs() > 0.1))
    {
        out.push(Trial {
            effect: Effect::UnmodeledMode {
                frequency_hz: m.frequency_hz,
                damping_ratio: m.damping_ratio.clamp(0.005, 0.3),
                coupling: 0.02,
            },
            label: "unmodeled_mode".into(),
            bounds: vec![
                (ParamId::ExtraModeFrequency, (0.5 * m.frequency_hz, 2.0 * m.frequency_hz)),
                (ParamId::ExtraModeDamping, (0.0, 0.5)),
                (ParamId::ExtraModeCoupling, (-0.5, 0.5)),
            ],
        });
    }
    out.retain(|t| !model.effects().iter().any(|e| e.kind() == t.effect.kind() && same_target(e, &t.effect)));
    out
}

fn same_target(a: &Effect, b: &Effect) -> bool {
    match (a, b) {
        (Effect::OutputOffset { sensor: x, .. }, Effect::OutputOffset { sensor: y, .. })
        | (Effect::SensorQuantization { sensor: x, .. }, Effect::SensorQuantization { sensor: y, .. }) => {
            x == y
        }
        _ => true,
    }
}

/// Per output, the innovation sum of squares of the weighted residual under an AR(1) error
/// model (see [`ar1_innovations`]): what the per-output likelihood of [`delta_bic`] compares.
fn channel_errors(residual: &Mat<f64>, weights: &[f64]) -> Vec<f64> {
    (0..residual.ncols())
        .map(|o| {
            ar1_innovations(&(0..residual.nrows()).map(|k| weights[o] * residual[(k, o)]).collect::<Vec<_>>())
        })
        .collect()
}

/// The smallest Ljung–Box p-value over the outputs.
fn whiteness(residual: &Mat<f64>) -> f64 {
    (0..residual.ncols())
        .map(|o| ljung_box(&(0..residual.nrows()).map(|k| residual[(k, o)]).collect::<Vec<_>>(), 20).1)
        .fold(1.0, f64::min)
}

/// What every candidate is scored against.
struct Reference<'a> {
    data: &'a Measurement,
    /// The baseline's ‖Y_error‖.
    error: f64,
    /// The baseline's [`channel_errors`].
    channels: Vec<f64>,
}

impl Reference<'_> {
    /// A refitted candidate with its effect's parameters, scored: error, ΔBIC with one added
    /// parameter per effect parameter, whiteness.
    fn score(
        &self,
        effect: String,
        label: String,
        outcome: FitOutcome,
        parameters: Vec<EffectParameter>,
    ) -> Candidate {
        let error = *outcome.report.error_history.last().expect("history");
        let residual = outcome.first().residual();
        let delta_bic = delta_bic(
            &channel_errors(&residual, &outcome.first().weights),
            &self.channels,
            self.data.n_samples(),
            parameters.len(),
        );
        Candidate {
            effect,
            label,
            error,
            reduction: 1.0 - error / self.error,
            delta_bic,
            score: -delta_bic,
            whiteness_p: whiteness(&residual),
            parameters,
            failure: None,
            model: Some(slewing(&outcome.fitted).clone()),
            outcome: Some(outcome),
        }
    }
}

/// Runs the workflow.
///
/// # Errors
/// Failures of the baseline fit (candidates that fail are reported, not fatal).
pub fn diagnose(
    model: &SlewingModel,
    data: &Measurement,
    options: &DiagnoseOptions,
) -> Result<Diagnosis, WorkflowError> {
    let wrapped = Model::Slewing(model.clone());
    let data = align(&wrapped, data)?;
    let free: Vec<&str> = options.free.iter().map(|s| s.as_str()).collect();
    let mut request = FitRequest::new(&free);
    request.derivative_check = mem::DerivativeCheck::Skip;
    let baseline = fit(&wrapped, &data, &request)?;
    let localisation = localise(&data, &baseline);
    let reference = Reference {
        data: &data,
        error: *baseline.report.error_history.last().expect("history"),
        channels: channel_errors(&baseline.first().residual(), &baseline.first().weights),
    };
    let wanted = |kind: &str| options.only.is_empty() || options.only.iter().any(|o| o == kind);
    let start = slewing(&baseline.fitted);
    let mut candidates: Vec<Candidate> = trials(start, &localisation)
        .into_par_iter()
        .filter(|t| wanted(t.effect.kind()))
        .map(|trial| {
            let kind = trial.effect.kind().to_string();
            let params: Vec<ParamId> = ParamId::of_effect(&trial.effect);
            let attempt = || -> Result<FitOutcome, WorkflowError> {
                let mut augmented = start.clone();
                augmented.add_effect(trial.effect.clone())?;
                for (id, b) in &trial.bounds {
                    augmented.set_bounds(*id, *b);
                }
                let mut names = options.free.clone();
                names.extend(params.iter().map(|p| p.name()));
                let refs: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
                let mut request = FitRequest::new(&refs);
                request.max_iterations = 60;
                request.derivative_check = mem::DerivativeCheck::Skip;
                Ok(fit(&Model::Slewing(augmented), &data, &request)?)
            };
            match attempt() {
                Ok(outcome) => {
                    let parameters = params
                        .iter()
                        .map(|p| {
                            let i = outcome
                                .report
                                .names
                                .iter()
                                .position(|n| *n == p.name())
                                .expect("effect parameter was freed");
                            EffectParameter {
                                name: p.name(),
                                value: outcome.report.parameters[i],
                                std_error: outcome.report.std_error(i).unwrap_or(f64::INFINITY),
                            }
                        })
                        .collect();
                    reference.score(kind, trial.label, outcome, parameters)
                }
                Err(e) => failed(kind, trial.label, e.to_string()),
            }
        })
        .collect();
    let mut localisation = localisation;
    if wanted("sensor_quantization") {
        let found = quantization_candidates(start, &reference, &options.free);
        for c in &found {
            if let Some(p) = c.parameters.first() {
                localisation.findings.push(format!(
                    "the samples of {} sit on a lattice of step {:.5} (± {:.1e}): a quantized sensor",
                    c.label.trim_start_matches("sensor_quantization"),
                    p.value,
                    p.std_error
                ));
            }
        }
        candidates.extend(found);
    }
    candidates.sort_by(|a, b| b.score.total_cmp(&a.score));
    let chosen = candidates
        .iter()
        .position(|c| c.failure.is_none() && c.delta_bic < -options.bic_threshold && strength_is_resolved(c));
    Ok(Diagnosis { baseline, localisation, candidates, chosen })
}

/// Parameters whose value 0 means "no effect": the effect is named only if the fit tells its
/// strength from zero (|value| > 2 standard errors). Otherwise a candidate could win on a
/// change of the error that its own uncertainty cannot distinguish from no change.
const STRENGTHS: [&str; 5] = ["coulomb_torque", "drag_hub", "delay", "extra_mode_coupling", "offset_"];

fn strength_is_resolved(c: &Candidate) -> bool {
    c.parameters
        .iter()
        .filter(|p| STRENGTHS.iter().any(|s| p.name.starts_with(s)))
        .all(|p| p.value.abs() > 2.0 * p.std_error)
}

fn failed(effect: String, label: String, why: String) -> Candidate {
    Candidate {
        effect,
        label,
        error: f64::NAN,
        reduction: f64::NAN,
        delta_bic: f64::INFINITY,
        score: f64::NEG_INFINITY,
        whiteness_p: f64::NAN,
        parameters: Vec::new(),
        failure: Some(why),
        model: None,
        outcome: None,
    }
}

/// Quantization is detected as a lattice in the measured samples; the model is then refitted
/// with that sensor quantized, which makes its readings intervals [y − Δ/2, y + Δ/2] and its
/// residual the distance of the model's output to them (`mem::Experiment::with_quantization`).
/// Δ comes from the lattice, not from the fit, so the candidate is only tried where the data
/// prove the quantizer (2nR² > 40).
fn quantization_candidates(
    start: &SlewingModel,
    reference: &Reference<'_>,
    free: &[String],
) -> Vec<Candidate> {
    let data = reference.data;
    let sensors: Vec<Sensor> = start.sensors().to_vec();
    let mut out = Vec::new();
    for (o, sensor) in sensors.iter().enumerate() {
        if start.quantization()[o].is_some() {
            continue;
        }
        let values: Vec<f64> = (0..data.n_samples()).map(|k| data.values()[(k, o)]).collect();
        let range = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let Some(lattice) = quantization::detect(&values, 1e-4 * range, 40.0) else { continue };
        let label = format!("sensor_quantization({})", sensor.output_name());
        let attempt = || -> Result<FitOutcome, WorkflowError> {
            let mut model = start.clone();
            model.add_effect(Effect::SensorQuantization { sensor: *sensor, step: lattice.step })?;
            let refs: Vec<&str> = free.iter().map(|s| s.as_str()).collect();
            let mut request = FitRequest::new(&refs);
            request.max_iterations = 60;
            request.derivative_check = mem::DerivativeCheck::Skip;
            Ok(fit(&Model::Slewing(model), data, &request)?)
        };
        let parameter = EffectParameter {
            name: format!("quantization_step_{}", sensor.output_name()),
            value: lattice.step,
            std_error: lattice.std_error,
        };
        out.push(match attempt() {
            Ok(outcome) => reference.score("sensor_quantization".into(), label, outcome, vec![parameter]),
            Err(e) => failed("sensor_quantization".into(), label, e.to_string()),
        });
    }
    out
}

/// The slewing model inside a fitted model (diagnose works on slewing models).
fn slewing(model: &Model) -> &SlewingModel {
    model.as_slewing().expect("diagnose fits slewing models only")
}
