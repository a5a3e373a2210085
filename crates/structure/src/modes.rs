//! The modes of a model: eigenvalues of A, frequencies, damping ratios and mode shapes.

use crate::StructureError;
use mem::nalgebra::DMatrix;
use serde::Serialize;

/// One mode of the first-order model at the current parameter values.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StructureMode {
    /// Undamped natural frequency |λ|/2π \[Hz\].
    pub frequency_hz: f64,
    /// Damping ratio −Re λ/|λ| (1 for a real negative eigenvalue).
    pub damping_ratio: f64,
    /// The eigenvalue λ = (re, im) with im ≥ 0 \[1/s\].
    pub eigenvalue: (f64, f64),
    /// For a second-order model, the mode shape over the coordinates: the displacement part of
    /// the eigenvector, rotated so that its largest component is real positive, scaled so that
    /// it is 1, and its real part taken. `None` for a first-order model.
    pub shape: Option<Vec<f64>>,
}

/// The modes of A: one per complex-conjugate pair (Im λ > 0) or real eigenvalue, sorted by
/// |λ|; with `n_coordinates`, the displacement part of each eigenvector as the mode shape.
pub(crate) fn modes_of(
    a: &DMatrix<f64>,
    n_coordinates: Option<usize>,
) -> Result<Vec<StructureMode>, StructureError> {
    let n = a.nrows();
    let a = faer::Mat::from_fn(n, n, |i, j| a[(i, j)]);
    let eigen = a.eigen().map_err(|e| StructureError::Eigen { reason: format!("{e:?}") })?;
    let (s, u) = (eigen.S(), eigen.U());
    let mut modes = Vec::new();
    for k in 0..n {
        let lambda = s[k];
        if lambda.im < 0.0 {
            continue;
        }
        let modulus = lambda.re.hypot(lambda.im);
        let shape = n_coordinates.map(|m| {
            let component = |i: usize| (u[(i, k)].re, u[(i, k)].im);
            let largest = (0..m)
                .max_by(|&i, &j| {
                    let size = |i| component(i).0.hypot(component(i).1);
                    size(i).total_cmp(&size(j))
                })
                .unwrap_or(0);
            let (c, d) = component(largest);
            let norm = c * c + d * d;
            // Re(v_i / v_largest).
            (0..m)
                .map(|i| {
                    let (a, b) = component(i);
                    if norm > 0.0 { (a * c + b * d) / norm } else { 0.0 }
                })
                .collect()
        });
        modes.push(StructureMode {
            frequency_hz: modulus / (2.0 * std::f64::consts::PI),
            damping_ratio: if modulus > 0.0 { -lambda.re / modulus } else { 1.0 },
            eigenvalue: (lambda.re, lambda.im),
            shape,
        });
    }
    modes.sort_by(|x, y| x.frequency_hz.total_cmp(&y.frequency_hz));
    Ok(modes)
}
