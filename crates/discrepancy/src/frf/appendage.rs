//! Bodies hanging on a forced structure, by a scan of trial appendages reacting through it.
//!
//! A mode the model lacks that belongs to a body hung on the structure (a mass m_a on a spring
//! and damper at coordinate j, [`structure::Effect::Appendage`]) shows in a forced record in two
//! ways. At its own frequency it rings: the resonance scan ([`super::resonances_under`]) looks for
//! that, as a mode added to the outputs. Below it, it pushes back on its floor as a mass that
//! grows towards its frequency, m_a ω_a²/(ω_a² − ω²): the whole structure's response changes, and
//! a refit of the model's own masses takes much of that up (a 50 kg appendage at 20.7 Hz on floor
//! 2 of a 1,000 kg-a-floor building rang with 27.8 nats in its record, under the noise of its
//! force, while refitting the three floor masses gained 1,129; forced draw 20261360). A ringing
//! that weak no scan of added modes finds, but the reaction is there to be read.
//!
//! The scan asks the question the appendage candidate will: how much of the reference's residual
//! would a small appendage at (j, f_a, ζ_a) explain, once the reference's free parameters have
//! taken up what they can? The appendage enters A linearly in its mass, so at m_a → 0 the
//! change of the outputs is m_a g(j, f_a, ζ_a), g the exact sensitivity ∂y/∂m_a of the model
//! with the appendage (mem's Eq. 9 at a vanishing mass, the model's own num-dual derivatives). With
//! every output whitened by its noise's predictor and scaled to unit innovations (the likelihood
//! the candidates are scored under), g and the residual r projected off the span of the free
//! parameters' sensitivities S (Gram–Schmidt, no normal equations), the appendage's first-order
//! gain is ½ (rᵀg⊥)²/‖g⊥‖² nats at the mass m̂ = rᵀg⊥/‖g⊥‖².
//!
//! An appendage far above the band the inputs excite is a rigid mass on its floor: its gain
//! there ([`AppendageResonance::mass_gain`], at [`RIGID`] times the band's top) is what a change of
//! the floor's mass explains. A body is seeded at a coordinate only where the best frequency of
//! the band explains more than that by [`AppendageScan::margin`] nats and its mass is positive;
//! whether it is named is the candidate's tests' to decide (held out, resolved, against the
//! model's own masses refitted).

use super::spectra;
use faer::Mat;
use mem::{Measurement, NoisePredictor};
use rayon::prelude::*;
use structure::{Effect, StructureModel};

/// The relative spacing of the scan's frequencies (the refit locates the frequency; the seed
/// need only lie within a factor 2 of it).
pub const APPENDAGE_SPACING: f64 = 0.01;

/// The damping ratio of the scan's trial appendage.
pub const APPENDAGE_DAMPING: f64 = 0.01;

/// How far above the excited band's top a rigid mass is read ([`AppendageResonance::mass_gain`]).
pub const RIGID: f64 = 20.0;

/// The mass, as a share of its coordinate's, at which the sensitivity is taken: small enough
/// that it is the first-order change, large enough to keep the appendage's mass positive.
const VANISHING_MASS: f64 = 1e-9;

/// The best trial appendage at one coordinate.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AppendageResonance {
    /// The coordinate it hangs on.
    pub coordinate: String,
    /// Its frequency \[Hz\].
    pub frequency_hz: f64,
    /// The damping ratio of [`super::DAMPINGS`] that explains most at that frequency.
    pub damping_ratio: f64,
    /// Its least-squares mass, to first order (the model's mass unit).
    pub mass: f64,
    /// The residual's structure it explains to first order (nats).
    pub gain: f64,
    /// What the same coordinate's rigid mass explains (nats).
    pub mass_gain: f64,
}

/// One scan: the reference's model and fit, and the measurement model its residual is read under.
pub struct AppendageScan<'a> {
    /// The reference's fitted model (linear, second-order; anything else is not scanned).
    pub model: &'a StructureModel,
    /// Its free parameters, whose sensitivities are projected off.
    pub free: &'a [String],
    /// The record as fitted (its inputs drive the trial appendages).
    pub data: &'a Measurement,
    /// The reference's residual (K × p, unweighted).
    pub residual: &'a Mat<f64>,
    /// Per output, the predictor its noise is whitened by.
    pub noise: &'a [NoisePredictor],
    /// How much more than a rigid mass a body must explain to be seeded (nats).
    pub margin: f64,
}

impl AppendageScan<'_> {
    /// The coordinates' best trial appendages that explain more than a rigid mass by
    /// [`Self::margin`], best first; none without inputs, for a first-order or nonlinear model,
    /// or where a response cannot be computed.
    pub fn run(&self) -> Vec<AppendageResonance> {
        self.scan().unwrap_or_default()
    }

    fn scan(&self) -> Option<Vec<AppendageResonance>> {
        let model = self.model;
        let (k, p) = (self.residual.nrows(), self.residual.ncols());
        if !model.is_second_order() || !model.is_linear() || self.noise.len() != p || k < 64 {
            return None;
        }
        if model
            .effects()
            .iter()
            .any(|e| matches!(e, Effect::Appendage { .. } | Effect::UnmodeledMode { .. }))
        {
            return None;
        }
        let inputs = self.data.inputs()?;
        if inputs.names().is_empty() {
            return None;
        }
        let held = spectra::held_inputs(self.data, k)?;
        let (low, high) = super::excited_band(&held, k, self.data.interval())?;
        // Each output whitened by its predictor and scaled to unit innovations.
        let scales: Vec<f64> = (0..p)
            .map(|o| {
                let w = self.noise[o].whitened(&column(self.residual, o));
                (w.iter().map(|v| v * v).sum::<f64>() / k as f64).sqrt()
            })
            .collect();
        if scales.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
            return None;
        }
        let scales = &scales;
        let whiten = |of: &dyn Fn(usize, usize) -> f64| -> Vec<f64> {
            (0..p)
                .flat_map(|o| {
                    let series: Vec<f64> = (0..k).map(|t| of(t, o)).collect();
                    self.noise[o].whitened(&series).into_iter().map(move |v| v / scales[o])
                })
                .collect()
        };
        let r = whiten(&|t, o| self.residual[(t, o)]);
        // The free parameters' sensitivities, whitened alike: the span the refit takes up.
        let names: Vec<&str> = self.free.iter().map(String::as_str).collect();
        let reference = models::StructureFitModel::new(model.clone(), &names).ok()?;
        let values: Vec<f64> = reference.parameters().iter().map(|q| q.initial).collect();
        let response = mem::sampled_response(&reference.response(), self.data, &values).ok()?;
        if response.outputs.nrows() != k {
            return None;
        }
        let mut free = Mat::zeros(k * p, names.len());
        for i in 0..names.len() {
            let s = whiten(&|t, o| response.sensitivities[(t * p + o, i)]);
            for (row, v) in s.into_iter().enumerate() {
                free[(row, i)] = v;
            }
        }
        let basis = super::scan::basis(&free);
        let project = |mut g: Vec<f64>| -> Vec<f64> {
            for q in &basis {
                let d: f64 = q.iter().zip(&g).map(|(a, b)| a * b).sum();
                g.iter_mut().zip(q).for_each(|(x, qi)| *x -= d * qi);
            }
            g
        };
        // One trial appendage: its first-order gain (nats) and mass.
        let so = model.second_order::<f64>(&model.values()).ok().flatten()?;
        let trial = |coordinate: &str, j: usize, f: f64, zeta: f64| -> Option<(f64, f64)> {
            let mut with = model.clone();
            let name = format!("appendage_mass_{coordinate}");
            with.add_effect(Effect::Appendage {
                coordinate: coordinate.to_string(),
                mass: VANISHING_MASS * so.m[(j, j)],
                frequency_hz: f,
                damping_ratio: zeta,
                release_force: None,
            })
            .ok()?;
            let fit = models::StructureFitModel::new(with, &[name.as_str()]).ok()?;
            let at: Vec<f64> = fit.parameters().iter().map(|q| q.initial).collect();
            let out = mem::sampled_response(&fit.response(), self.data, &at).ok()?;
            let g = project(whiten(&|t, o| out.sensitivities[(t * p + o, 0)]));
            let norm: f64 = g.iter().map(|v| v * v).sum();
            let dot: f64 = g.iter().zip(&r).map(|(a, b)| a * b).sum();
            (norm > 0.0 && norm.is_finite() && dot.is_finite()).then(|| (0.5 * dot * dot / norm, dot / norm))
        };
        let steps = ((high / low).ln() / APPENDAGE_SPACING.ln_1p()).floor() as usize;
        let grid: Vec<f64> =
            (0..=steps).map(|i| low * (APPENDAGE_SPACING.ln_1p() * i as f64).exp()).collect();
        if grid.len() < 5 {
            return None;
        }
        let trial = &trial;
        let coordinates = model.coordinates();
        let mut found: Vec<AppendageResonance> = coordinates
            .par_iter()
            .enumerate()
            .filter_map(|(j, c)| {
                let gains: Vec<Option<(f64, f64)>> =
                    grid.par_iter().map(|&f| trial(c, j, f, APPENDAGE_DAMPING)).collect();
                let rigid = trial(c, j, RIGID * high, APPENDAGE_DAMPING)?.0;
                // The best interior maximum of a positive mass.
                let value = |i: usize| gains[i].filter(|(_, m)| *m > 0.0).map_or(0.0, |(g, _)| g);
                let best = (1..grid.len() - 1)
                    .filter(|&i| value(i) > value(i - 1) && value(i) >= value(i + 1))
                    .max_by(|&a, &b| value(a).total_cmp(&value(b)))?;
                let f = grid[best];
                let (zeta, (gain, mass)) = super::DAMPINGS
                    .iter()
                    .filter_map(|&z| Some((z, trial(c, j, f, z)?)))
                    .filter(|(_, (_, m))| *m > 0.0)
                    .max_by(|a, b| a.1.0.total_cmp(&b.1.0))?;
                (gain >= rigid + self.margin).then(|| AppendageResonance {
                    coordinate: c.clone(),
                    frequency_hz: f,
                    damping_ratio: zeta,
                    mass,
                    gain,
                    mass_gain: rigid,
                })
            })
            .collect();
        found.sort_by(|a, b| b.gain.total_cmp(&a.gain));
        Some(found)
    }
}

/// Column `o` of `m`.
fn column(m: &Mat<f64>, o: usize) -> Vec<f64> {
    (0..m.nrows()).map(|t| m[(t, o)]).collect()
}
