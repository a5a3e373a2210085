//! Noise on a recorded input (errors in variables): how much of a forced record's residual the
//! noise on its measured force accounts for.
//!
//! A model driven by a recorded force u_m = u + e responds to the noise e as well, so its
//! residual holds −G(e) beside the sensors' own noise v. With e white (a transducer's noise is,
//! across the band a shaker excites), output o's residual has the spectrum
//! S_o(f) = a_o + Σ_i β_i |G_oi(f)|² — a floor a_o from the sensor, and the model's frequency
//! response from input i squared, scaled by the variance β_i = σ_i² of that input's noise
//! (Pintelon & Schoukens, *System Identification: A Frequency Domain Approach*, 2nd ed., 2012,
//! §7.2). G_oi is read from the fitted model's own simulated response by H₁ (its Welch estimate
//! from the recorded inputs, solved jointly where several are excited so that correlated inputs
//! are kept apart: exact but for leakage, since the simulation holds no noise), and
//! (a_o, β_i) are fitted to the residual's Welch auto-spectra in the band the inputs excite by
//! Whittle's likelihood (iteratively reweighted least squares, each bin weighted by the inverse
//! square of its fitted level; Whittle 1953), every one of them held ≥ 0.
//!
//! Where the recorded force has a quiet band — bins far under the band it excites, flat, as a
//! chirp's or a band-limited force's above its band are — that band holds e alone, and β_i is
//! read there and held in the fit ([`RecordedInputs::quiet_levels`]): read from the residual,
//! an output-error fit has taken up part of the model's response to e.
//!
//! An effect that acts through the dynamics can take up part of the model's response to e — a
//! dry friction or a drag at the driven floor damps the small, quick motion e drives more than
//! the large one the force drives — and so gain on a record with nothing missing but a clean
//! force. What it removes is then at most a part of what e put there.

use super::{EXCITED, MAX_SEGMENT, NoiseResponse, spectra};
use faer::Mat;
use faer::linalg::solvers::SolveLstsq;
use mem::Measurement;
use serde::Serialize;

mod quiet;
mod whittle;

use quiet::quiet_level;
use whittle::whittle;

/// One recorded input's estimated noise.
#[derive(Clone, Debug, Serialize)]
pub struct InputNoiseLevel {
    /// The input's name.
    pub input: String,
    /// The noise's estimated RMS σ_i, in the input's units.
    pub rms: f64,
    /// σ_i as a share of the recorded input's RMS.
    pub share: f64,
}

/// What noise on the recorded inputs accounts for in a residual.
#[derive(Clone, Debug, Serialize)]
pub struct InputNoise {
    /// Per input.
    pub inputs: Vec<InputNoiseLevel>,
    /// The residual's (weighted) sum of squares that the inputs' noise accounts for, over the
    /// band the inputs excite: K Σ_o (2/L) Σ_f Σ_i β_i |G_oi(f)|² (L the segment length).
    pub residual_power: f64,
    /// `residual_power` as a share of the residual's sum of squares.
    pub share: f64,
    /// Per output, the fitted noise spectrum on the Welch bins 0…L/2 − 1 (in the residual's
    /// weighted units): a_o + Σ_i β_i |G_oi(f)|² where an input excites the bin, the sensor's
    /// floor a_o elsewhere — the residual's spectrum if nothing but the noise were left.
    #[serde(skip)]
    pub spectra: Vec<Vec<f64>>,
    /// Per output, the sensor's floor a_o of `spectra`: the spectrum without the inputs' noise.
    #[serde(skip)]
    pub floors: Vec<f64>,
    /// Per output, where the fitted model's exact response was given ([`NoiseResponse`]): the
    /// autocovariance Σ_i β_i γ_oi(l), l = 0, 1, …, of what the inputs' noise leaves in the
    /// residual (in its weighted units), without the sensor's floor. `None` where the response
    /// was read by H₁ from the simulation.
    #[serde(skip)]
    pub response_autocovariance: Option<Vec<Vec<f64>>>,
}

/// The noise on `data`'s recorded inputs, from a fitted model's `simulated` outputs and its
/// `residual` (both K × p on the record's grid, weighted alike); `None` without inputs, with
/// fewer than 64 samples, or with fewer than five excited bins. Several residuals of one record
/// are read with [`RecordedInputs`], whose input spectra are then computed once.
pub fn input_noise(data: &Measurement, simulated: &Mat<f64>, residual: &Mat<f64>) -> Option<InputNoise> {
    RecordedInputs::of(data, residual.nrows())?.noise(simulated, residual, None)
}

fn auto(s: &[Vec<(f64, f64)>], b: usize) -> f64 {
    s.iter().map(|x| x[b].0.powi(2) + x[b].1.powi(2)).sum()
}

/// A record's inputs as [`input_noise`] reads them: names, RMS, segment transforms and
/// auto-spectra, and the bins they excite.
pub struct RecordedInputs {
    names: Vec<String>,
    rms: Vec<f64>,
    k: usize,
    length: usize,
    segments: Vec<Vec<Vec<(f64, f64)>>>,
    suu: Vec<Vec<f64>>,
    largest: Vec<f64>,
    excited: Vec<usize>,
    ceilings: Vec<f64>,
    quiet: Vec<Option<f64>>,
}

/// How far above the recorded input's own spectral floor its noise may be read
/// ([`RecordedInputs::ceilings`]).
pub const CEILING_MARGIN: f64 = 2.0;

/// The share of a recorded input's spectral bins, its lowest, whose mean is its floor.
pub const FLOOR_BINS: f64 = 0.25;

impl RecordedInputs {
    /// `data`'s inputs on a grid of `k` rows; `None` without inputs, with fewer than 64 samples,
    /// or with fewer than five excited bins.
    pub fn of(data: &Measurement, k: usize) -> Option<Self> {
        let names = data.inputs()?.names().to_vec();
        let m = names.len();
        if m == 0 || k < 64 {
            return None;
        }
        let held = spectra::held_inputs(data, k)?;
        let length = (k / 4).min(MAX_SEGMENT);
        let bins = length / 2;
        let segments: Vec<_> = (0..m).map(|i| spectra::segments(&|t| held[(t, i)], k, length)).collect();
        if segments.first().is_none_or(Vec::is_empty) {
            return None;
        }
        let suu: Vec<Vec<f64>> = segments.iter().map(|u| (0..bins).map(|b| auto(u, b)).collect()).collect();
        let largest: Vec<f64> = suu.iter().map(|s| s.iter().copied().fold(0.0, f64::max)).collect();
        let rms =
            (0..m).map(|i| ((0..k).map(|t| held[(t, i)].powi(2)).sum::<f64>() / k as f64).sqrt()).collect();
        let ceilings = suu.iter().zip(&segments).map(|(s, u)| ceiling(s, u.len(), length)).collect();
        let quiet = suu.iter().zip(&segments).map(|(s, u)| quiet_level(s, u.len(), length)).collect();
        let mut inputs =
            Self { names, rms, k, length, segments, suu, largest, excited: Vec::new(), ceilings, quiet };
        inputs.excited = (1..bins).filter(|&b| (0..m).any(|i| inputs.excites(i, b))).collect();
        (inputs.excited.len() >= 5).then_some(inputs)
    }

    /// The Welch segments' length (samples): a [`NoiseResponse`] given to [`Self::noise`] must
    /// hold at least this many lags less one.
    pub fn segment_length(&self) -> usize {
        self.length
    }

    /// Per input, the largest variance σ_i² its noise may be read at: `CEILING_MARGIN` (2) times
    /// its own spectral floor (the mean of its lowest quarter of Welch bins).
    pub fn ceilings(&self) -> &[f64] {
        &self.ceilings
    }

    /// Per input, the noise's variance σ_i² read from the recorded input's own quiet band, where
    /// it has one (`quiet::quiet_level`); the Whittle fit of [`Self::noise`] then holds β_i there.
    pub fn quiet_levels(&self) -> &[Option<f64>] {
        &self.quiet
    }

    /// Whether input i excites bin b (its auto-spectrum there at least [`EXCITED`] of its largest).
    fn excites(&self, i: usize, b: usize) -> bool {
        let (s, largest) = (self.suu[i][b], self.largest[i]);
        largest > 0.0 && s > 0.0 && s >= EXCITED * largest
    }

    /// The noise on these inputs as one fit's weighted `simulated` outputs and `residual`
    /// (K × p) show it; `None` if their size is not the record's or the fit does not converge.
    ///
    /// With the fitted model's exact `response` to white noise on its inputs (same outputs,
    /// inputs and weights, at least a segment's lags), |G_oi|² at each bin is that response's
    /// expected windowed periodogram ([`NoiseResponse::expected_levels`]) rather than H₁ of the
    /// simulation — the power a mode narrower than a bin puts there, not the square of its
    /// window-averaged response —, the noise's spectrum holds it at every bin (the noise is
    /// white across the record's whole band, not only where the force excites), and its
    /// autocovariance is returned exactly.
    pub fn noise(
        &self,
        simulated: &Mat<f64>,
        residual: &Mat<f64>,
        response: Option<&NoiseResponse>,
    ) -> Option<InputNoise> {
        let (k, p, m, length) = (self.k, residual.ncols(), self.names.len(), self.length);
        if residual.nrows() != k || simulated.nrows() != k || simulated.ncols() != p {
            return None;
        }
        let bins = length / 2;
        let window = spectra::window_power(length);
        let residuals: Vec<_> = (0..p).map(|o| spectra::segments(&|t| residual[(t, o)], k, length)).collect();
        let segments = self.segments[0].len() as f64;
        // |G_oi(f)|² per output, bin and input: the model's exact response where it was given
        // and fits this record, else H₁ from the simulation over the inputs excited at that bin
        // (0 for the others).
        let window_values = spectra::window(length);
        let exact: Option<Vec<Vec<Vec<f64>>>> = response
            .filter(|r| r.outputs() == p && r.inputs() == m && r.lags() + 1 >= length)
            .and_then(|r| {
                (0..p)
                    .map(|o| (0..m).map(|i| r.expected_levels(o, i, length, &window_values)).collect())
                    .collect()
            });
        let mut gains = vec![vec![vec![0.0; m]; bins]; p];
        if let Some(levels) = &exact {
            for (o, per_output) in gains.iter_mut().enumerate() {
                for (b, per_bin) in per_output.iter_mut().enumerate() {
                    for (i, g) in per_bin.iter_mut().enumerate() {
                        *g = levels[o][i][b];
                    }
                }
            }
        } else {
            let outputs: Vec<_> =
                (0..p).map(|o| spectra::segments(&|t| simulated[(t, o)], k, length)).collect();
            for &b in &self.excited {
                let active: Vec<usize> = (0..m).filter(|&i| self.excites(i, b)).collect();
                for (o, per_output) in gains.iter_mut().enumerate() {
                    let response = frequency_response(&self.segments, &outputs[o], &active, b);
                    for (&i, h) in active.iter().zip(response) {
                        per_output[b][i] = h;
                    }
                }
            }
        }
        let gain = |o: usize, i: usize, b: usize| gains[o][b][i];
        // One row per (output, excited bin): P = W a_o + Σ_i β_i W |G_oi|², P the mean |R|².
        let rows: Vec<(usize, usize)> =
            (0..p).flat_map(|o| self.excited.iter().map(move |&b| (o, b))).collect();
        let level: Vec<f64> = rows.iter().map(|&(o, b)| auto(&residuals[o], b) / segments).collect();
        let design = Mat::from_fn(rows.len(), p + m, |r, c| {
            let (o, b) = rows[r];
            window * if c < p { f64::from(u8::from(c == o)) } else { gain(o, c - p, b) }
        });
        // The sensors' floors are free (≥ 0); an input's noise is held at the level its own quiet
        // band shows where it has one, else read between 0 and its ceiling.
        let bounds: Vec<(f64, f64)> = (0..p)
            .map(|_| (0.0, f64::INFINITY))
            .chain(self.ceilings.iter().zip(&self.quiet).map(|(&c, q)| q.map_or((0.0, c), |q| (q, q))))
            .collect();
        let theta = whittle(&design, &level, &bounds)?;
        let beta = &theta[p..];
        let per_output: f64 = (0..p)
            .flat_map(|o| self.excited.iter().map(move |&b| (o, b)))
            .map(|(o, b)| (0..m).map(|i| beta[i] * gain(o, i, b)).sum::<f64>())
            .sum::<f64>()
            * 2.0
            / length as f64;
        let residual_power = k as f64 * per_output;
        let spectra = (0..p)
            .map(|o| {
                let mut level = vec![theta[o]; bins];
                if exact.is_some() {
                    for (b, l) in level.iter_mut().enumerate() {
                        *l += (0..m).map(|i| beta[i] * gain(o, i, b)).sum::<f64>();
                    }
                } else {
                    for &b in &self.excited {
                        level[b] += (0..m).map(|i| beta[i] * gain(o, i, b)).sum::<f64>();
                    }
                }
                level
            })
            .collect();
        let response_autocovariance = exact.is_some().then(|| {
            let response = response.expect("exact levels come from a response");
            (0..p)
                .map(|o| {
                    (0..=response.lags())
                        .map(|l| (0..m).map(|i| beta[i] * response.autocovariance(o, i)[l]).sum())
                        .collect()
                })
                .collect()
        });
        let total: f64 = (0..p).map(|o| residual.col(o).squared_norm_l2()).sum();
        Some(InputNoise {
            inputs: self
                .names
                .iter()
                .zip(&self.rms)
                .zip(beta)
                .map(|((input, rms_u), beta)| {
                    let rms = beta.sqrt();
                    InputNoiseLevel { input: input.clone(), rms, share: rms / rms_u.max(f64::MIN_POSITIVE) }
                })
                .collect(),
            residual_power,
            share: if total > 0.0 { (residual_power / total).min(1.0) } else { 0.0 },
            spectra,
            floors: theta[..p].to_vec(),
            response_autocovariance,
        })
    }
}

/// Σ over segments of conj(A) B at bin `b`.
fn cross(a: &[Vec<(f64, f64)>], c: &[Vec<(f64, f64)>], b: usize) -> (f64, f64) {
    a.iter().zip(c).fold((0.0, 0.0), |(re, im), (a, c)| {
        (re + a[b].0 * c[b].0 + a[b].1 * c[b].1, im + a[b].0 * c[b].1 - a[b].1 * c[b].0)
    })
}

/// |H_i(f_b)|² for the `active` inputs from one output's segments `y`: H₁ of several inputs,
/// the least-squares solution of Σ_j S_{u_i u_j} H_j = S_{u_i y} over the segments (Bendat &
/// Piersol, *Random Data*, §7.2), which keeps apart inputs that are correlated; for one input
/// S_{uy}/S_{uu}. The complex system is solved as its real form
/// [[Re S, −Im S], [Im S, Re S]] [Re H; Im H] = [Re s; Im s].
fn frequency_response(
    u: &[Vec<Vec<(f64, f64)>>],
    y: &[Vec<(f64, f64)>],
    active: &[usize],
    b: usize,
) -> Vec<f64> {
    let n = active.len();
    if n == 1 {
        let (re, im) = cross(&u[active[0]], y, b);
        let suu: f64 = u[active[0]].iter().map(|x| x[b].0.powi(2) + x[b].1.powi(2)).sum();
        return vec![(re * re + im * im) / (suu * suu)];
    }
    let s: Vec<Vec<(f64, f64)>> =
        active.iter().map(|&i| active.iter().map(|&j| cross(&u[i], &u[j], b)).collect()).collect();
    let q: Vec<(f64, f64)> = active.iter().map(|&i| cross(&u[i], y, b)).collect();
    let a = Mat::from_fn(2 * n, 2 * n, |r, c| {
        let (re, im) = s[r % n][c % n];
        match (r < n, c < n) {
            (true, true) | (false, false) => re,
            (true, false) => -im,
            (false, true) => im,
        }
    });
    let rhs = Mat::from_fn(2 * n, 1, |r, _| if r < n { q[r].0 } else { q[r - n].1 });
    let h = a.qr().solve_lstsq(&rhs);
    (0..n).map(|i| h[(i, 0)].powi(2) + h[(n + i, 0)].powi(2)).collect()
}

/// A recorded input's noise variance ceiling from its auto-spectrum `suu` (Σ over `segments`
/// segments of |U_b|², bins 0…L/2 − 1 of a segment of `length`): [`CEILING_MARGIN`] times the
/// mean of its lowest [`FLOOR_BINS`] bins (DC aside) over segments and window power — the level
/// white noise of that variance has in every bin.
///
/// A transducer's noise is white across the whole band, the force a shaker applies is not: where
/// the force excites nothing (a chirp's or a low-passed noise's bins above its band) the recorded
/// force is its noise alone, and the noise read from a residual cannot be larger. A residual the
/// model's resonances shape — a nonlinear force's left-over, a misfit — looks to the Whittle fit
/// like the force's noise through the model (12 % read on a 1 %-noise record of a softening
/// spring, draw 20261304 `A_cubic_strong_s1`); the ceiling holds the read to what the force's
/// own record shows. A force as broad as the record's band has no such floor, and its ceiling
/// does not bind.
fn ceiling(suu: &[f64], segments: usize, length: usize) -> f64 {
    let mut levels: Vec<f64> = suu.iter().skip(1).copied().filter(|l| l.is_finite()).collect();
    if levels.is_empty() || segments == 0 {
        return f64::INFINITY;
    }
    levels.sort_by(f64::total_cmp);
    let lowest = ((levels.len() as f64 * FLOOR_BINS).ceil() as usize).clamp(1, levels.len());
    let mean = levels[..lowest].iter().sum::<f64>() / lowest as f64;
    CEILING_MARGIN * mean / (segments as f64 * spectra::window_power(length))
}

#[cfg(test)]
mod tests {
    use super::input_noise;
    use crate::frf::tests::{driven_oscillator, forced_record, normals};
    use faer::Mat;

    /// An oscillator driven by a broadband force u and read with white noise of 1 % of its RMS;
    /// the force recorded as u + σ n. Its exact model, driven by the record, leaves
    /// y − G(u + σ n). Returns the estimated σ as a share of the recorded force's RMS, and the
    /// share of the residual put down to it.
    fn estimated(sigma: f64) -> (f64, f64) {
        let (f, zeta, h, k) = (12.5, 0.02, 0.005, 4000);
        let u = normals(11, k);
        let clean = driven_oscillator(f, zeta, h, &u);
        let rms = (clean.iter().map(|y| y * y).sum::<f64>() / k as f64).sqrt();
        let sensor = normals(12, k);
        let y: Vec<f64> = clean.iter().zip(&sensor).map(|(y, v)| y + 0.01 * rms * v).collect();
        let recorded: Vec<f64> = u.iter().zip(normals(13, k)).map(|(u, n)| u + sigma * n).collect();
        let simulated = driven_oscillator(f, zeta, h, &recorded);
        let data = forced_record(&recorded, &y, h);
        let noise = input_noise(
            &data,
            &Mat::from_fn(k, 1, |t, _| simulated[t]),
            &Mat::from_fn(k, 1, |t, _| y[t] - simulated[t]),
        )
        .unwrap();
        (noise.inputs[0].share, noise.share)
    }

    /// The noise put on the recorded force is read back from the residual to within a fifth,
    /// and accounts for most of it (the force's noise drives the oscillator at its resonance,
    /// 5 % of the force against the sensor's 1 % of the response); a clean record shows
    /// almost none.
    #[test]
    fn the_noise_on_a_recorded_force_is_read_from_the_residual() {
        let (share, of_residual) = estimated(0.05);
        assert!((0.04..0.06).contains(&share), "σ/RMS(u) = {share}");
        assert!(of_residual > 0.5, "{of_residual}");
        let (share, of_residual) = estimated(0.0);
        assert!(share < 0.005, "σ/RMS(u) = {share} on a clean record");
        assert!(of_residual < 0.05, "{of_residual}");
    }

    /// The oscillator of [`estimated`], its force recorded with 3 % noise and read by a white
    /// sensor (0.5 % of the response's RMS). Given the model's exact response, the noise is read
    /// to within a tenth and its autocovariance is returned; H₁ of the simulation reads it
    /// further off (the square of a window-averaged response at the resonance, narrower than a
    /// bin, is not the window-averaged power the residual's periodogram holds).
    #[test]
    fn the_exact_response_reads_the_forces_noise_closer_than_h1() {
        let (f, zeta, h, k, sigma) = (12.5, 0.01, 0.005, 4000, 0.03);
        let u = normals(51, k);
        let clean = driven_oscillator(f, zeta, h, &u);
        let rms = (clean.iter().map(|y| y * y).sum::<f64>() / k as f64).sqrt();
        let y: Vec<f64> = clean.iter().zip(normals(52, k)).map(|(y, n)| y + 0.005 * rms * n).collect();
        let recorded: Vec<f64> = u.iter().zip(normals(53, k)).map(|(u, n)| u + sigma * n).collect();
        let simulated = driven_oscillator(f, zeta, h, &recorded);
        let data = forced_record(&recorded, &y, h);
        let (a, b) = crate::frf::tests::oscillator(f, zeta);
        let c = Mat::from_fn(1, 2, |_, j| f64::from(u8::from(j == 0)));
        let inputs = super::RecordedInputs::of(&data, k).unwrap();
        let response = crate::frf::NoiseResponse::new(
            &crate::frf::tests::space(&a, &b, &c, None),
            mem::Hold::Zero,
            h,
            &[1.0],
            inputs.segment_length(),
        )
        .unwrap();
        let (sim, res) =
            (Mat::from_fn(k, 1, |t, _| simulated[t]), Mat::from_fn(k, 1, |t, _| y[t] - simulated[t]));
        let exact = inputs.noise(&sim, &res, Some(&response)).unwrap();
        let by_h1 = inputs.noise(&sim, &res, None).unwrap();
        let truth = sigma / (recorded.iter().map(|x| x * x).sum::<f64>() / k as f64).sqrt();
        let (read, h1) = (exact.inputs[0].share, by_h1.inputs[0].share);
        assert!((read / truth - 1.0).abs() < 0.1, "read {read}, put {truth} (H₁: {h1})");
        assert!((h1 / truth - 1.0).abs() > (read / truth - 1.0).abs(), "H₁ {h1}, exact {read}, put {truth}");
        assert!(exact.response_autocovariance.is_some() && by_h1.response_autocovariance.is_none());
    }

    /// Two correlated forces (u₂ = 0.6 u₁ + 0.8 n), each driving its own oscillator read by
    /// its own sensor, recorded with 5 % and 2 % noise: each input's noise is read to within a
    /// fifth. H₁ of each input alone would credit output 1 with a response to u₂ (through u₂'s
    /// correlation with u₁) and mix the two noises.
    #[test]
    fn the_noises_on_two_correlated_recorded_forces_are_told_apart() {
        let (h, k) = (0.005, 4000);
        let u1 = normals(21, k);
        let u2: Vec<f64> = u1.iter().zip(normals(22, k)).map(|(a, n)| 0.6 * a + 0.8 * n).collect();
        let (sigma1, sigma2) = (0.05, 0.02);
        let r1: Vec<f64> = u1.iter().zip(normals(23, k)).map(|(u, n)| u + sigma1 * n).collect();
        let r2: Vec<f64> = u2.iter().zip(normals(24, k)).map(|(u, n)| u + sigma2 * n).collect();
        let (f1, f2, zeta) = (12.5, 31.0, 0.02);
        let clean = [driven_oscillator(f1, zeta, h, &u1), driven_oscillator(f2, zeta, h, &u2)];
        let simulated = [driven_oscillator(f1, zeta, h, &r1), driven_oscillator(f2, zeta, h, &r2)];
        let sensors = [normals(25, k), normals(26, k)];
        let y: Vec<Vec<f64>> = (0..2)
            .map(|o| {
                let rms = (clean[o].iter().map(|y| y * y).sum::<f64>() / k as f64).sqrt();
                clean[o].iter().zip(&sensors[o]).map(|(y, v)| y + 0.01 * rms * v).collect()
            })
            .collect();
        let values = Mat::from_fn(k, 4, |t, c| match c {
            0 => r1[t],
            1 => r2[t],
            _ => y[c - 2][t],
        });
        let data =
            mem::Measurement::new(vec!["u1".into(), "u2".into(), "y1".into(), "y2".into()], 0.0, h, values)
                .unwrap()
                .with_inputs(&["u1", "u2"], mem::Hold::Zero)
                .unwrap();
        let noise = input_noise(
            &data,
            &Mat::from_fn(k, 2, |t, o| simulated[o][t]),
            &Mat::from_fn(k, 2, |t, o| y[o][t] - simulated[o][t]),
        )
        .unwrap();
        let rms = |u: &[f64]| (u.iter().map(|x| x * x).sum::<f64>() / k as f64).sqrt();
        let read = [noise.inputs[0].rms, noise.inputs[1].rms];
        let truth = [sigma1, sigma2];
        for i in 0..2 {
            assert!(
                (read[i] / truth[i] - 1.0).abs() < 0.2,
                "input {i}: read {}, put {} ({:?})",
                read[i],
                truth[i],
                noise.inputs
            );
        }
        assert!((noise.inputs[1].share - read[1] / rms(&r2)).abs() < 1e-12);
    }

    /// Welch auto-spectrum of `u` as [`super::RecordedInputs`] reads it, and its segments' count.
    fn auto_spectrum(u: &[f64], length: usize) -> (Vec<f64>, usize) {
        let segments = crate::frf::spectra::segments(&|t| u[t], u.len(), length);
        ((0..length / 2).map(|b| super::auto(&segments, b)).collect(), segments.len())
    }

    /// A linear chirp 1 → 40 Hz over 10 s at 200 Hz (its own form here, with 0.2 s cosine
    /// tapers) recorded with white noise of 1 % of its RMS: its quiet band above 40 Hz gives the
    /// noise's variance to within a tenth, leakage at the band's edges left out. A white force
    /// has no quiet band; a force low-passed four times at 10 Hz, recorded without noise, falls
    /// below a thousandth of its peak without a flat floor, and no noise is read from it.
    #[test]
    fn the_noise_is_read_from_a_band_limited_forces_quiet_band_only() {
        let (h, k) = (0.005, 2001);
        let duration = (k - 1) as f64 * h;
        let chirp: Vec<f64> = (0..k)
            .map(|t| {
                let time = t as f64 * h;
                let phase = 2.0 * std::f64::consts::PI * (time + 39.0 * time * time / (2.0 * duration));
                let taper =
                    |x: f64| if x < 0.2 { 0.5 - 0.5 * (std::f64::consts::PI * x / 0.2).cos() } else { 1.0 };
                taper(time) * taper(duration - time) * phase.sin()
            })
            .collect();
        let rms = (chirp.iter().map(|x| x * x).sum::<f64>() / k as f64).sqrt();
        let noise = normals(61, k);
        let recorded: Vec<f64> = chirp.iter().zip(&noise).map(|(u, e)| u + 0.01 * rms * e).collect();
        let length = k / 4;
        let (suu, segments) = auto_spectrum(&recorded, length);
        let read = super::quiet_level(&suu, segments, length).expect("a quiet band above 40 Hz");
        let put = (0.01 * rms).powi(2);
        assert!((read / put - 1.0).abs() < 0.1, "read {read}, put {put}");

        let (white, segments) = auto_spectrum(&normals(62, k), length);
        assert_eq!(super::quiet_level(&white, segments, length), None);

        // Four first-order low-passes at 10 Hz (exact discretisation of each, from rest).
        let a = (-2.0 * std::f64::consts::PI * 10.0 * h).exp();
        let mut low = normals(63, k);
        for _ in 0..4 {
            let mut y = 0.0;
            for x in &mut low {
                y = a * y + (1.0 - a) * *x;
                *x = y;
            }
        }
        let (falling, segments) = auto_spectrum(&low, length);
        let largest = falling.iter().copied().fold(0.0, f64::max);
        assert!(falling.iter().filter(|l| **l < super::quiet::QUIET * largest).count() > length / 4);
        assert_eq!(super::quiet_level(&falling, segments, length), None);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(48))]
        /// Any record — short or long, one or two inputs and outputs, values from 10⁻¹² to 10¹²,
        /// an input that is all zeros, a residual that is exactly zero — gives either no estimate
        /// or finite levels ≥ 0 and a share in [0, 1]; never a panic or a NaN.
        #[test]
        fn any_record_gives_finite_levels_or_none(
            k in 64usize..600,
            p in 1usize..3,
            m in 1usize..3,
            seed in 0u64..10_000,
            exponent in -12i32..12,
            silent_input in proptest::bool::ANY,
            perfect in proptest::bool::ANY,
        ) {
            let scale = 10f64.powi(exponent);
            let draw = |s: u64| normals(seed * 8 + s, k);
            let inputs: Vec<Vec<f64>> = (0..m as u64)
                .map(|i| if silent_input && i == 0 { vec![0.0; k] } else { draw(i).iter().map(|x| scale * x).collect() })
                .collect();
            let mut names: Vec<String> = (0..m).map(|i| format!("u{i}")).collect();
            names.extend((0..p).map(|o| format!("y{o}")));
            let simulated: Vec<Vec<f64>> = (0..p as u64).map(|o| draw(4 + o)).collect();
            let values = Mat::from_fn(k, m + p, |t, c| if c < m { inputs[c][t] } else { simulated[c - m][t] });
            let input_names: Vec<&str> = names[..m].iter().map(String::as_str).collect();
            let data = mem::Measurement::new(names.clone(), 0.0, 0.005, values)
                .unwrap()
                .with_inputs(&input_names, mem::Hold::Zero)
                .unwrap();
            let residual = Mat::from_fn(k, p, |t, o| if perfect { 0.0 } else { 0.01 * simulated[o][(t * 7 + 3) % k] });
            if let Some(noise) = input_noise(&data, &Mat::from_fn(k, p, |t, o| simulated[o][t]), &residual) {
                proptest::prop_assert!(noise.residual_power.is_finite() && noise.residual_power >= 0.0);
                proptest::prop_assert!((0.0..=1.0).contains(&noise.share), "{}", noise.share);
                for level in &noise.inputs {
                    proptest::prop_assert!(level.rms.is_finite() && level.rms >= 0.0, "{level:?}");
                    proptest::prop_assert!(level.share.is_finite() && level.share >= 0.0, "{level:?}");
                }
            }
        }
    }
}
