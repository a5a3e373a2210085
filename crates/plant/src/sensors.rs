//! The experiment's sensors and the output matrix C.

use crate::Constants;
use crate::assemble::{Layout, Scalar, SecondOrder};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

/// A sensor of the slewing experiment (paper §IV).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Sensor {
    /// Potentiometer: hub angle θ \[rad\]; output name `theta`.
    Potentiometer,
    /// Tachometer: hub rate θ̇ \[rad/s\] (the motor's, θ̇_m, with backlash); output name
    /// `theta_dot`.
    Tachometer,
    /// Root strain gauge: surface strain at the root, (thickness/2)·Σ q_i φ_i″(0), in
    /// microstrain; output name `strain`.
    StrainGauge,
}

impl Sensor {
    /// The output's name (the CSV column header).
    pub fn output_name(self) -> &'static str {
        match self {
            Sensor::Potentiometer => "theta",
            Sensor::Tachometer => "theta_dot",
            Sensor::StrainGauge => "strain",
        }
    }

    /// The output's unit.
    pub fn unit(self) -> &'static str {
        match self {
            Sensor::Potentiometer => "rad",
            Sensor::Tachometer => "rad/s",
            Sensor::StrainGauge => "µε",
        }
    }
}

/// C (p × 2(n+1)) for the state x = [q; q̇]. The strain row depends on the mode shapes, hence
/// on the parameters, so C is generic like A.
pub fn output_matrix<D: Scalar>(c: &Constants<D>, so: &SecondOrder<D>, sensors: &[Sensor]) -> DMatrix<D> {
    let layout = Layout::of(c);
    let size = layout.n_dof;
    // With backlash the tachometer sits on the motor's shaft unless the file says otherwise.
    let tachometer = layout
        .motor
        .filter(|_| {
            c.effects.iter().any(|e| matches!(e, crate::Effect::Backlash { tachometer_on_motor: true, .. }))
        })
        .unwrap_or(0);
    let mut out = DMatrix::from_element(sensors.len(), layout.n_states, D::from(0.0));
    for (row, sensor) in sensors.iter().enumerate() {
        match sensor {
            Sensor::Potentiometer => out[(row, 0)] = D::from(1.0),
            Sensor::Tachometer => out[(row, size + tachometer)] = D::from(1.0),
            Sensor::StrainGauge => {
                for (i, mode) in so.modes.iter().enumerate() {
                    out[(row, i + 1)] = c.thickness * D::from(0.5e6) * mode.root_curvature;
                }
            }
        }
    }
    out
}
