//! The effects of a [`StructureModel`]: adding them, the quantization of its
//! outputs, and the forces at its coordinates with their columns G and H (`crate::effects`).

use super::StructureModel;
use crate::StructureError;
use crate::effects::{Effect, Target};
use mem::Scalar;

/// One force effect, ready to evaluate: f at a state x = [q; q̇] of `n` coordinates, with its
/// parameters at `start` in P.
#[derive(Clone, Debug)]
pub struct ForceLaw {
    effect: Effect,
    n: usize,
    coordinate: usize,
    start: usize,
    len: usize,
}

impl ForceLaw {
    /// The force at time `t` (from the release, x(0)), state `x` and parameters `p` (all of the
    /// model's).
    pub fn force<D: Scalar>(&self, t: f64, x: &[D], p: &[D]) -> D {
        self.effect.force(t, x, self.n, self.coordinate, &p[self.start..])
    }

    /// The states it depends on: its coordinate's displacement and velocity.
    pub fn states(&self) -> [usize; 2] {
        [self.coordinate, self.n + self.coordinate]
    }

    /// For a dry friction at parameters `p` (all of the model's): its coordinate's index, its
    /// level at rest (sliding level plus any static peak) and its smoothing velocity; `None` for
    /// another law.
    pub fn friction_at_rest(&self, p: &[f64]) -> Option<(usize, f64, f64)> {
        let theta = p.get(self.start..self.start + self.len)?;
        self.effect.friction_at_rest(theta).map(|(level, vs)| (self.coordinate, level, vs))
    }

    /// Whether the parameter at `slot` of P is one of its own.
    pub fn uses(&self, slot: usize) -> bool {
        (self.start..self.start + self.len).contains(&slot)
    }
}

/// A force effect's coordinate and its force column, G = [0; −M⁻¹e_j], with the acceleration
/// outputs' share H of it (module [`crate::effects`]).
#[derive(Clone, Debug)]
pub struct ForceParts<D: mem::Scalar> {
    /// G (N × m), one column per force effect, in the effects' order.
    pub g: mem::nalgebra::DMatrix<D>,
    /// H (p × m).
    pub h: mem::nalgebra::DMatrix<D>,
}

impl StructureModel {
    /// The added effects, in order.
    pub fn effects(&self) -> &[Effect] {
        &self.effects
    }

    /// Adds an effect.
    ///
    /// # Errors
    /// [`StructureError::InvalidEffect`] for an unknown output or coordinate, a force on a
    /// first-order model, an impossible value, a second effect of the same kind at the same
    /// place, or a second unmodeled mode.
    pub fn add_effect(&mut self, effect: Effect) -> Result<(), StructureError> {
        let invalid = |reason: String| Err(StructureError::InvalidEffect { reason });
        if let Some(reason) = effect.invalid(
            &self.output_names(),
            &self.coordinates(),
            &self.input_names(),
            self.is_second_order(),
        ) {
            return invalid(reason);
        }
        if self.effects.iter().any(|e| e.kind() == effect.kind() && e.target() == effect.target()) {
            return invalid(format!(
                "the model already has a {:?} there; one of a kind per place",
                effect.kind()
            ));
        }
        let names = self.parameter_names();
        if let Some((n, _)) =
            effect.parameters(&self.output_names()).into_iter().find(|(n, _)| names.contains(n))
        {
            return invalid(format!("its parameter `{n}` is already a parameter of the model; rename it"));
        }
        self.effects.push(effect);
        Ok(())
    }

    /// Whether the model is linear (no force effect).
    pub fn is_linear(&self) -> bool {
        !self.effects.iter().any(Effect::is_force)
    }

    /// Whether the model is linear with `free` the parameters that may move: its only forces,
    /// if any, are drags of exponent 1 whose exponent is not in `free` — linear dampers c·v,
    /// which [`linear_state_space`](Self::linear_state_space) puts in D. The exact exponential
    /// path then applies.
    pub fn is_linear_for(&self, free: &[&str]) -> bool {
        let outputs = self.output_names();
        self.effects.iter().filter(|e| e.is_force()).all(|e| match e {
            Effect::Drag { exponent, .. } => {
                *exponent == 1.0
                    && e.parameters(&outputs).get(1).is_some_and(|(n, _)| !free.contains(&n.as_str()))
            }
            _ => false,
        })
    }

    /// The quantization step of each output, if its sensor is quantized.
    pub fn quantization(&self) -> Vec<Option<f64>> {
        self.output_names()
            .iter()
            .map(|o| {
                self.effects.iter().find_map(|e| match e {
                    Effect::SensorQuantization { output, step } if output == o => Some(*step),
                    _ => None,
                })
            })
            .collect()
    }

    /// The effects' parameters in P, each effect's slice: (effect, start in P).
    pub(super) fn effect_offsets(&self) -> Vec<(&Effect, usize)> {
        let outputs = self.output_names();
        let mut at = self.checked.params.len();
        self.effects
            .iter()
            .map(|e| {
                let start = at;
                at += e.parameters(&outputs).len();
                (e, start)
            })
            .collect()
    }

    /// The force effects with their coordinates' indices and their parameters' start in P.
    fn force_effects(&self) -> Vec<(&Effect, usize, usize)> {
        self.effect_offsets()
            .into_iter()
            .filter(|(e, _)| e.is_force())
            .filter_map(|(e, start)| match e.target() {
                Target::Coordinate(c) => Some((e, self.coordinate_index(c)?, start)),
                _ => None,
            })
            .collect()
    }

    /// The force effects as laws to evaluate many times (in the order of the columns of
    /// [`force_parts`](Self::force_parts)).
    pub fn force_laws(&self) -> Vec<ForceLaw> {
        let n = self.coordinates().len();
        self.force_effects()
            .into_iter()
            .map(|(e, j, start)| ForceLaw {
                effect: e.clone(),
                n,
                coordinate: j,
                start,
                len: e.parameters(&[]).len(),
            })
            .collect()
    }

    /// G and H of the force effects at `p` (`None` for a linear model).
    ///
    /// # Errors
    /// As [`state_space`](Self::state_space).
    pub fn force_parts<D: Scalar>(&self, p: &[D]) -> Result<Option<ForceParts<D>>, StructureError> {
        let forces = self.force_effects();
        if forces.is_empty() {
            return Ok(None);
        }
        let values = self.checked.compiled.values(&p[..self.checked.params.len()])?;
        let columns: Vec<usize> = forces.iter().map(|(_, j, _)| *j).collect();
        let (g, h) = self.checked.compiled.force_columns(&values, &columns)?;
        let n_states = self.n_states_with_effects();
        let mut wide = mem::nalgebra::DMatrix::from_element(n_states, g.ncols(), D::from(0.0));
        wide.view_mut((0, 0), (g.nrows(), g.ncols())).copy_from(&g);
        Ok(Some(ForceParts { g: wide, h }))
    }

    /// The number of states with those the effects add (an unmodeled mode's or an
    /// appendage's two).
    fn n_states_with_effects(&self) -> usize {
        self.n_states() + self.effects.iter().map(Effect::added_states).sum::<usize>()
    }
}
