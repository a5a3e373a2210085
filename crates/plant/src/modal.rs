//! Closed-loop modal analysis: frequencies and damping ratios (paper Table 2).

use crate::{PlantError, SlewingModel};
use faer::Mat;
use serde::Serialize;

/// What a closed-loop mode mostly moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModeKind {
    /// The servo (hub) mode: hub rotation against the position loop.
    Servo,
    /// A flexible beam mode (1-based, in frequency order among the flexible modes).
    Flexible(usize),
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
    /// |v_i| for the first `n_dof` entries of the eigenvector (the displacements for A in
    /// [q; q̇] form).
    pub displacement: Vec<f64>,
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
        rows.push(RawMode {
            frequency_hz: modulus / (2.0 * std::f64::consts::PI),
            damping_ratio: if modulus > 0.0 { -ev.re / modulus } else { 1.0 },
            eigenvalue: (ev.re, ev.im),
            displacement: (0..n_dof).map(|i| (u[(i, k)].re.powi(2) + u[(i, k)].im.powi(2)).sqrt()).collect(),
        });
    }
    rows.sort_by(|x, y| x.frequency_hz.total_cmp(&y.frequency_hz));
    Ok(rows)
}

impl SlewingModel {
    /// Closed-loop frequencies (Hz) and damping ratios, with the servo mode identified as the
    /// mode whose hub rotation carries the largest share of the mass-weighted motion
    /// Σ_j M_jj |v_j|², and the flexible modes numbered in frequency order.
    ///
    /// # Errors
    /// As [`SlewingModel::state_space`].
    pub fn modal(&self) -> Result<Vec<ModalRow>, PlantError> {
        let ss = self.state_space()?;
        let n_dof = self.n_modes() + 1;
        let rows = modes_of(&ss.a, n_dof)?;
        let hub_share = |shape: &Vec<f64>| {
            let total: f64 = (0..n_dof).map(|j| ss.m[(j, j)] * shape[j] * shape[j]).sum();
            ss.m[(0, 0)] * shape[0] * shape[0] / total.max(f64::MIN_POSITIVE)
        };
        let servo = rows
            .iter()
            .enumerate()
            .max_by(|x, y| hub_share(&x.1.displacement).total_cmp(&hub_share(&y.1.displacement)))
            .map(|(i, _)| i);
        let mut flexible = 0;
        Ok(rows
            .into_iter()
            .enumerate()
            .map(|(i, raw)| {
                let kind = if Some(i) == servo {
                    ModeKind::Servo
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
