//! The experiment's sensors (their rows of C are assembled in `assemble` and `output`).

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
