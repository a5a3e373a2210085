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
    /// Every sensor of the rig, in [`Sensor::index`] order.
    pub const ALL: [Sensor; 3] = [Sensor::Potentiometer, Sensor::Tachometer, Sensor::StrainGauge];

    /// How many sensors the rig has.
    pub const COUNT: usize = Self::ALL.len();

    /// The sensor's place among the [`Sensor::COUNT`] (for per-sensor tables).
    pub const fn index(self) -> usize {
        match self {
            Sensor::Potentiometer => 0,
            Sensor::Tachometer => 1,
            Sensor::StrainGauge => 2,
        }
    }

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

/// The sensor's undelayed reading y = c·x as a row over the state (`layout.n_states` long):
/// the potentiometer's hub angle, the tachometer's rate (the motor's with backlash unless the
/// file says otherwise), the strain gauge's root strain from the mode shapes.
pub fn reading<D: Scalar>(c: &Constants<D>, so: &SecondOrder<D>, layout: &Layout, sensor: Sensor) -> Vec<D> {
    let size = layout.n_dof;
    let mut row = vec![D::from(0.0); layout.n_states];
    match sensor {
        Sensor::Potentiometer => row[0] = D::from(1.0),
        Sensor::Tachometer => {
            // With backlash the tachometer sits on the motor's shaft unless the file says otherwise.
            let tachometer = layout
                .motor
                .filter(|_| {
                    c.effects
                        .iter()
                        .any(|e| matches!(e, crate::Effect::Backlash { tachometer_on_motor: true, .. }))
                })
                .unwrap_or(0);
            row[size + tachometer] = D::from(1.0);
        }
        Sensor::StrainGauge => {
            for (i, mode) in so.modes.iter().enumerate() {
                row[i + 1] = c.thickness * D::from(0.5e6) * mode.root_curvature;
            }
        }
    }
    row
}

/// C (p × n_states): each sensor's [`reading`], or for a sensor read late
/// ([`crate::Effect::SensorLag`]) −y + w_s, the Padé(1,1) of its delayed reading. The strain
/// row depends on the mode shapes, hence on the parameters, so C is generic like A.
pub fn output_matrix<D: Scalar>(c: &Constants<D>, so: &SecondOrder<D>, sensors: &[Sensor]) -> DMatrix<D> {
    let layout = Layout::of(c);
    let mut out = DMatrix::from_element(sensors.len(), layout.n_states, D::from(0.0));
    for (row, sensor) in sensors.iter().enumerate() {
        let y = reading(c, so, &layout, *sensor);
        let lag = layout.lags[sensor.index()];
        for (j, value) in y.into_iter().enumerate() {
            out[(row, j)] = if lag.is_some() { -value } else { value };
        }
        if let Some(w) = lag {
            out[(row, w)] = D::from(1.0);
        }
    }
    out
}
