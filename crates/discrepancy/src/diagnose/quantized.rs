//! Quantization as a measurement model: a candidate per sensor whose raw readings hold a
//! lattice (`crate::quantization`), refitted with the quantizer when the lattice matters.

use super::answer::last_error;
use super::{Candidate, EffectParameter, Evidence, Verdict, run, strength};
use crate::WorkflowError;
use crate::quantization;
use mem::Measurement;
use models::Model;
use plant::EffectKind;
use run::Fitted;

/// The false-alarm probability of one lattice reading (one-sided), for the blurred lattice and
/// the sawtooth alike: without a quantizer each z is a mean of [`quantization::BATCHES`] batch
/// means over their spread, with the step and phase taken from the other half of the samples,
/// so Student's t₁₉; the bar this sets is 5.63. Both were checked on the study's draws
/// (docs/diagnose.md, "The bar from t₁₉" and "The blurred lattice's bar from the same calibration"): the sawtooth's 6,834 readings of 1,644
/// unquantized sensor records followed t₁₉'s tail (30 above 3 where it expects 25, 3 above 4
/// where it expects 2.6), the largest 3.89; the blurred test's 2,385 records of the
/// development set, six held-out draws (seeds 3307–8821) and the blind set (`examples/lattice_null.rs`) 11
/// above 3 where it expects 8.8 and 2 above 4 where it expects 0.9, the largest 4.66.
const LATTICE_FALSE_ALARM: f64 = 1e-5;

/// One candidate per sensor not yet quantized whose raw readings hold a lattice; named
/// (`Outscored` until chosen) when the lattice matters, refitted with the quantizer on `data`
/// (the record as fitted, decimated if asked).
pub(super) fn quantization_candidates(
    start: &Model,
    raw: &Measurement,
    data: &Measurement,
    reference: &Fitted,
    free: &[String],
) -> Result<Vec<Candidate>, WorkflowError> {
    let baseline = &reference.outcome;
    let response = baseline.fitted.response(&[])?;
    let fitted = mem::sampled_response(response.as_ref(), raw, &[])?.outputs;
    // The model's own poles, to correct its response before a sawtooth is read about it (an
    // empty list, and no correction but a constant, if the modes cannot be had).
    let poles: Vec<(f64, f64)> =
        baseline.fitted.modes().map(|rows| rows.iter().map(|r| r.eigenvalue).collect()).unwrap_or_default();
    let times = raw.times();
    let bar = quantization::batch_threshold(LATTICE_FALSE_ALARM);
    let thresholds = quantization::Thresholds { blurred: bar, sawtooth: bar };
    let mut out = Vec::new();
    let quantized = start.quantization();
    for (o, name) in start.output_names().iter().enumerate() {
        if quantized[o].is_some() {
            continue;
        }
        let values: Vec<f64> = (0..raw.n_samples()).map(|k| raw.values()[(k, o)]).collect();
        let predicted: Vec<f64> = (0..raw.n_samples()).map(|k| fitted[(k, o)]).collect();
        let corrected = quantization::modal_corrected(&values, &predicted, &times, &poles);
        let Some(lattice) = quantization::detect_about(&values, &[&predicted, &corrected], thresholds) else {
            continue;
        };
        let (sensor, effect) = match start {
            Model::Slewing(m) => {
                let sensor = m.sensors()[o];
                (Some(sensor), plant::Effect::SensorQuantization { sensor, step: lattice.step }.into())
            }
            Model::Structure(_) => (
                None,
                structure::Effect::SensorQuantization { output: name.clone(), step: lattice.step }.into(),
            ),
        };
        let mut candidate = Candidate {
            kind: EffectKind::SensorQuantization,
            sensor,
            output: Some(o),
            label: format!("sensor_quantization({name})"),
            replaces: None,
            parameters: vec![EffectParameter {
                name: format!("quantization_step_{name}"),
                value: lattice.step,
                std_error: None,
            }],
            evidence: Evidence::default(),
            lattice: Some(lattice),
            verdict: if lattice.matters() { Verdict::Outscored } else { Verdict::NoLattice },
            model: None,
            outcome: None,
        };
        if lattice.matters() {
            let mut model = start.clone();
            model.add_effect(effect)?;
            match run::refit(&model, data, free, None, 60) {
                Ok(outcome) => {
                    candidate.evidence.reduction = 1.0 - last_error(&outcome) / last_error(baseline);
                    candidate.evidence.whiteness_p = strength::whiteness(&outcome);
                    candidate.model = Some(outcome.fitted.clone());
                    candidate.outcome = Some(outcome);
                }
                Err(e) => candidate.verdict = Verdict::Failed(e.to_string()),
            }
        }
        out.push(candidate);
    }
    Ok(out)
}
