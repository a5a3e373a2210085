//! Closed-loop modal analysis: frequencies and damping ratios (paper Table 2).

use crate::{PlantError, SlewingModel};
use faer::Mat;
use serde::Serialize;

/// What a closed-loop mode mostly moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum ModeKind {
    /// The servo (hub) mode: hub rotation against the position loop.
    Servo,
    /// A flexible beam mode (1-based, in frequency order among the flexible modes; an
    /// unmodeled mode of the effects counts among them).
    Flexible(usize),
    /// The pole of the loop's transport delay ([`crate::Effect::TimeDelay`]'s Padé state, near
    /// −2/τ): the mode whose eigenvector lies most in the delay state.
    Delay,
}

impl ModeKind {
    /// The name tables and JSON give the mode: `servo`, `flexible_<i>` or `delay`.
    pub fn name(self) -> String {
        match self {
            ModeKind::Servo => "servo".into(),
            ModeKind::Flexible(i) => format!("flexible_{i}"),
            ModeKind::Delay => "delay".into(),
        }
    }
}

/// One closed-loop mode.
#[derive(Clone, Debug, Serialize)]
pub struct ModalRow {
    /// Servo or flexible.
    pub kind: ModeKind,
    /// Undamped natural frequency |s|/2π \[Hz\] (the quantity Table 2 lists).
    pub frequency_hz: f64,
    /// Damping ratio −Re(s)/|s|.
    pub damping_ratio: f64,
    /// The eigenvalue s = re + i·im (upper half plane).
    pub eigenvalue: (f64, f64),
}

/// One eigenvalue of a real system matrix with the moduli of its eigenvector's first entries.
#[derive(Clone, Debug)]
pub struct RawMode {
    /// |s|/2π \[Hz\].
    pub frequency_hz: f64,
    /// −Re(s)/|s|.
    pub damping_ratio: f64,
    /// s = (re, im), im ≥ 0.
    pub eigenvalue: (f64, f64),
    /// |v_i| for the first `n_dof` entries of the unit eigenvector (the displacements for A in
    /// [q; q̇] form): the head of `magnitudes`.
    pub displacement: Vec<f64>,
    /// |v_i| for every entry of the unit eigenvector.
    pub magnitudes: Vec<f64>,
}

/// Modes of any real A: one per complex pair (taking Im s > 0) or real eigenvalue, sorted by
/// frequency.
///
/// # Errors
/// [`PlantError::Eigen`] if faer's eigen-decomposition does not converge.
pub fn modes_of(a: &Mat<f64>, n_dof: usize) -> Result<Vec<RawMode>, PlantError> {
    let eig = a.eigen().map_err(|e| PlantError::Eigen(format!("{e:?}")))?;
    let s = eig.S();
    let u = eig.U();
    let mut rows: Vec<RawMode> = Vec::new();
    for k in 0..a.nrows() {
        let ev = s[k];
        if ev.im < 0.0 {
            continue;
        }
        let modulus = (ev.re * ev.re + ev.im * ev.im).sqrt();
        let magnitudes: Vec<f64> = {
            let m: Vec<f64> = (0..a.nrows()).map(|i| u[(i, k)].re.hypot(u[(i, k)].im)).collect();
            let norm = m.iter().map(|v| v * v).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
            m.into_iter().map(|v| v / norm).collect()
        };
        rows.push(RawMode {
            frequency_hz: modulus / (2.0 * std::f64::consts::PI),
            damping_ratio: if modulus > 0.0 { -ev.re / modulus } else { 1.0 },
            eigenvalue: (ev.re, ev.im),
            displacement: magnitudes[..n_dof].to_vec(),
            magnitudes,
        });
    }
    rows.sort_by(|x, y| x.frequency_hz.total_cmp(&y.frequency_hz));
    Ok(rows)
}

impl SlewingModel {
    /// Closed-loop frequencies (Hz) and damping ratios, with the servo mode identified as the
    /// mode whose hub rotation carries the largest share of the mass-weighted motion
    /// Σ_j M_jj |v_j|², and the flexible modes numbered in frequency order. A loop delay's
    /// Padé pole is listed as [`ModeKind::Delay`]. A channel read late
    /// ([`crate::Effect::SensorLag`]) is outside the loop: its state feeds no other, so A is
    /// block triangular and its pole −2/τ_s is no mode of the rig; it is left out, and the
    /// eigenvalues are those of the loop's block alone (with it, the stiff pole of a short lag
    /// would cost the others their accuracy).
    ///
    /// # Errors
    /// As [`SlewingModel::state_space`].
    pub fn modal(&self) -> Result<Vec<ModalRow>, PlantError> {
        let ss = self.state_space()?;
        let layout = self.layout();
        let n_dof = layout.n_dof;
        // The loop's states: every state but the lags', wherever the layout put them.
        let kept: Vec<usize> = (0..layout.n_states).filter(|i| !layout.lags.contains(&Some(*i))).collect();
        let a = Mat::from_fn(kept.len(), kept.len(), |i, j| ss.a[(kept[i], kept[j])]);
        let rows = modes_of(&a, n_dof)?;
        let delay = layout.delay.and_then(|d| kept.iter().position(|&i| i == d)).and_then(|w| {
            rows.iter()
                .enumerate()
                .max_by(|x, y| x.1.magnitudes[w].total_cmp(&y.1.magnitudes[w]))
                .map(|(i, _)| i)
        });
        let hub_share = |shape: &Vec<f64>| {
            let total: f64 = (0..n_dof).map(|j| ss.m[(j, j)] * shape[j] * shape[j]).sum();
            ss.m[(0, 0)] * shape[0] * shape[0] / total.max(f64::MIN_POSITIVE)
        };
        let servo = rows
            .iter()
            .enumerate()
            .filter(|(i, _)| Some(*i) != delay)
            .max_by(|x, y| hub_share(&x.1.displacement).total_cmp(&hub_share(&y.1.displacement)))
            .map(|(i, _)| i);
        let mut flexible = 0;
        Ok(rows
            .into_iter()
            .enumerate()
            .map(|(i, raw)| {
                let kind = if Some(i) == servo {
                    ModeKind::Servo
                } else if Some(i) == delay {
                    ModeKind::Delay
                } else {
                    flexible += 1;
                    ModeKind::Flexible(flexible)
                };
                ModalRow {
                    kind,
                    frequency_hz: raw.frequency_hz,
                    damping_ratio: raw.damping_ratio,
                    eigenvalue: raw.eigenvalue,
                }
            })
            .collect())
    }
}
