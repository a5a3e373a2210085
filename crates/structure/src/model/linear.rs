//! The linear state space of a [`StructureModel`] at given parameter values, for any scalar,
//! its second-order matrices and modes, and [`mem::StateSpaceModel`].

use super::StructureModel;
use crate::StructureError;
use crate::effects::{Effect, EffectKind};
use crate::modes::{StructureMode, modes_of};
use mem::{Scalar, SecondOrder, StateSpace};

impl StructureModel {
    /// A, C, x(0), B, D at the parameter values `p` (all parameters, declaration order), for any
    /// scalar: `f64` for values, a num-dual number seeded on some parameters for exact
    /// derivatives. B and D are `None` for a model without inputs.
    ///
    /// # Errors
    /// [`StructureError::ParameterCount`] if `p` has the wrong length;
    /// [`StructureError::Assembly`] if the model cannot be formed at `p` (a singular mass matrix,
    /// modal damping without positive definite M and K, a non-finite entry).
    ///
    /// With added effects, `p` holds their parameters too (after the file's, as in
    /// [`parameter_names`](Self::parameter_names)) and an unmodeled mode's two states follow
    /// the structure's; sensor effects and forces are not part of the linear model (see
    /// [`crate::effects`]).
    pub fn state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, StructureError> {
        self.assemble(p, false)
    }

    /// The linear model at `p` when it is linear for the parameters that move
    /// ([`is_linear_for`](Self::is_linear_for)): [`state_space`](Self::state_space) with each
    /// drag of exponent 1, c·v, in D at its coordinate (linear physics there, a force on the
    /// nonlinear path).
    ///
    /// # Errors
    /// As [`state_space`](Self::state_space).
    pub fn linear_state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, StructureError> {
        self.assemble(p, true)
    }

    fn assemble<D: Scalar>(&self, p: &[D], linear_drag: bool) -> Result<StateSpace<D>, StructureError> {
        let n_file = self.checked.params.len();
        let expected = self.values.len() + self.effect_parameters().len();
        if p.len() != expected {
            return Err(StructureError::ParameterCount { expected, got: p.len() });
        }
        let dampers: Vec<(usize, D)> = if linear_drag {
            self.effect_offsets()
                .into_iter()
                .filter_map(|(effect, start)| match effect {
                    Effect::Drag { coordinate, .. } if p[start + 1].re() == 1.0 => {
                        Some((self.coordinate_index(coordinate)?, p[start]))
                    }
                    _ => None,
                })
                .collect()
        } else {
            Vec::new()
        };
        let mut space = self.checked.compiled.state_space_damped(&p[..n_file], &dampers)?;
        for (effect, start) in self.effect_offsets() {
            match effect {
                Effect::UnmodeledMode { driven_by, .. } => {
                    let input =
                        driven_by.as_ref().and_then(|d| self.input_names().iter().position(|i| i == d));
                    crate::effects::append_mode(&mut space, &p[start..], input);
                }
                Effect::Appendage { coordinate, .. } => {
                    let Some(j) = self.coordinate_index(coordinate) else { continue };
                    let compiled = &self.checked.compiled;
                    let values = compiled.values(&p[..n_file])?;
                    let (g, _) = compiled.force_columns(&values, &[j])?;
                    let n = self.coordinates().len();
                    // G = [0; −M⁻¹e_j]: the reaction's column is its negative.
                    let reaction =
                        mem::nalgebra::DVector::from_iterator(g.nrows(), g.column(0).iter().map(|&v| -v));
                    crate::effects::append_appendage(&mut space, &p[start..], j, n, &reaction, |delta| {
                        compiled.acceleration_share(delta, &values, n)
                    });
                }
                _ => {}
            }
        }
        Ok(space)
    }

    /// M, D, K and F (if there are inputs) at the parameter values `p`; `None` for a
    /// first-order file.
    ///
    /// # Errors
    /// As [`state_space`](Self::state_space).
    pub fn second_order<D: Scalar>(&self, p: &[D]) -> Result<Option<SecondOrder<D>>, StructureError> {
        let values = self.checked.compiled.values(&p[..self.checked.params.len().min(p.len())])?;
        self.checked.compiled.second_order_at(&values)
    }

    /// The modes at the current values: the eigenvalues of A, one per complex-conjugate pair
    /// (λ with Im λ > 0) or real eigenvalue, sorted by undamped frequency |λ|/2π, with damping
    /// ratio −Re λ/|λ| and, for a second-order file, the mode shape over the coordinates. With
    /// proportional (e.g. Rayleigh or modal) damping |λ| = ω_n, the undamped natural frequency
    /// of K φ = ω² M φ.
    ///
    /// # Errors
    /// As [`state_space`](Self::state_space); [`StructureError::Eigen`] if the eigenvalues do
    /// not converge.
    pub fn modes(&self) -> Result<Vec<StructureMode>, StructureError> {
        let space = self.checked.compiled.state_space::<f64>(&self.values)?;
        modes_of(&space.a, self.is_second_order().then(|| self.coordinates().len()))
    }
}

impl mem::StateSpaceModel for StructureModel {
    fn parameter_names(&self) -> Vec<String> {
        StructureModel::parameter_names(self)
    }
    fn output_names(&self) -> Vec<String> {
        StructureModel::output_names(self)
    }
    fn input_names(&self) -> Vec<String> {
        StructureModel::input_names(self)
    }
    fn state_space<D: Scalar>(&self, p: &[D]) -> Result<StateSpace<D>, mem::BoxedError> {
        // Sensor effects and forces are not linear state-space parts: fitting without them
        // would be a silently wrong answer.
        if let Some(e) = self
            .effects
            .iter()
            .find(|e| !matches!(e.kind(), EffectKind::UnmodeledMode | EffectKind::Appendage))
        {
            return Err(Box::new(StructureError::InvalidEffect {
                reason: format!(
                    "the model's {:?} is not part of its linear state space; fit it through models::Model",
                    e.kind()
                ),
            }));
        }
        Ok(StructureModel::state_space(self, p)?)
    }
}
