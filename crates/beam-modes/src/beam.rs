//! Beam properties.

use crate::BeamError;
use num_dual::DualNum;

/// A uniform Euler–Bernoulli beam spring-hinged at its root (at radius `hub_radius` from the
/// slewing axis) and free at its tip. SI units throughout.
///
/// Generic over the scalar so that num-dual numbers carry exact derivatives with respect to any
/// property through every result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam<D> {
    /// Length L \[m\].
    pub length: D,
    /// Flexural rigidity EI \[N·m²\].
    pub flexural_rigidity: D,
    /// Mass per unit length ρ \[kg/m\].
    pub mass_per_length: D,
    /// Hub radius a: distance from the slewing axis to the beam root \[m\].
    pub hub_radius: D,
    /// Rotational spring stiffness at the root k \[N·m/rad\]; 0 is a pinned root.
    pub root_stiffness: D,
}

impl<D: DualNum<Primitive = f64> + Copy> Beam<D> {
    /// Checks that every property is physically possible.
    ///
    /// # Errors
    /// [`BeamError::InvalidProperty`] naming the first bad property.
    pub fn validate(&self) -> Result<(), BeamError> {
        let positive = [
            ("length", self.length.re()),
            ("flexural_rigidity", self.flexural_rigidity.re()),
            ("mass_per_length", self.mass_per_length.re()),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(BeamError::InvalidProperty { name, value, requirement: "finite and > 0" });
            }
        }
        let non_negative =
            [("hub_radius", self.hub_radius.re()), ("root_stiffness", self.root_stiffness.re())];
        for (name, value) in non_negative {
            if !(value.is_finite() && value >= 0.0) {
                return Err(BeamError::InvalidProperty { name, value, requirement: "finite and ≥ 0" });
            }
        }
        Ok(())
    }

    /// The dimensionless root stiffness κ = kL/EI.
    pub fn kappa(&self) -> D {
        self.root_stiffness * self.length / self.flexural_rigidity
    }

    /// √(EI/ρ) \[m²/s\]: ω = (λ/L)²·√(EI/ρ).
    pub fn wave_constant(&self) -> D {
        (self.flexural_rigidity / self.mass_per_length).sqrt()
    }
}
