//! The model's physical, control and effect constants, generic over the scalar, and their names.

mod id;

pub use id::{MIN_DELAY, ParamId, SignRule};

use crate::effects::Effect;

/// Every constant of the closed-loop slewing model (SI units), generic over the scalar so that
/// num-dual numbers carry derivatives through the whole assembly.
#[derive(Clone, Debug, PartialEq)]
pub struct Constants<D> {
    /// Beam length L \[m\].
    pub length: D,
    /// EI/ρ \[N·m³/kg\] (printed in the paper: 0.857).
    pub ei_over_rho: D,
    /// Mass per unit length ρ \[kg/m\] (not printed in the paper; calibrated).
    pub mass_per_length: D,
    /// Hub radius a \[m\].
    pub hub_radius: D,
    /// Beam thickness \[m\] (converts root curvature to surface strain).
    pub thickness: D,
    /// Hub inertia I_H \[kg·m²\].
    pub hub_inertia: D,
    /// Motor inertia I_m \[kg·m²\].
    pub motor_inertia: D,
    /// Motor torque constant K_t \[N·m/A\].
    pub torque_constant: D,
    /// Back-EMF constant K_b \[V·s/rad\].
    pub back_emf_constant: D,
    /// Armature resistance R_a \[Ω\].
    pub armature_resistance: D,
    /// Power-amplifier voltage gain G \[V/V\] (not printed in the paper; calibrated).
    pub amplifier_gain: D,
    /// Position feedback gain K_p \[V/rad\].
    pub position_gain: D,
    /// Viscous damping C_v \[N·m·s/rad\].
    pub viscous_damping: D,
    /// Modal damping terms 2ζ_iω_i \[1/s\], one per flexible mode.
    pub modal_damping: Vec<D>,
    /// Effects added to the paper's model.
    pub effects: Vec<Effect<D>>,
}

/// The field of `Constants` that a core `ParamId` names, borrowed with the given reference kind.
macro_rules! core_field {
    ([$($borrow:tt)+] $s:ident, $id:expr) => {
        match $id {
            ParamId::ViscousDamping => Some($($borrow)+ $s.viscous_damping),
            ParamId::PositionGain => Some($($borrow)+ $s.position_gain),
            ParamId::ModalDamping(i) => (i >= 1 && i <= $s.modal_damping.len()).then(|| $($borrow)+ $s.modal_damping[i - 1]),
            ParamId::MassPerLength => Some($($borrow)+ $s.mass_per_length),
            ParamId::EiOverRho => Some($($borrow)+ $s.ei_over_rho),
            ParamId::Length => Some($($borrow)+ $s.length),
            ParamId::HubRadius => Some($($borrow)+ $s.hub_radius),
            ParamId::Thickness => Some($($borrow)+ $s.thickness),
            ParamId::HubInertia => Some($($borrow)+ $s.hub_inertia),
            ParamId::MotorInertia => Some($($borrow)+ $s.motor_inertia),
            ParamId::TorqueConstant => Some($($borrow)+ $s.torque_constant),
            ParamId::BackEmfConstant => Some($($borrow)+ $s.back_emf_constant),
            ParamId::ArmatureResistance => Some($($borrow)+ $s.armature_resistance),
            ParamId::AmplifierGain => Some($($borrow)+ $s.amplifier_gain),
            _ => None,
        }
    };
}

/// The effect field that an effect `ParamId` names.
macro_rules! effect_field {
    ([$($borrow:tt)+] $effects:expr, $id:expr) => {
        $effects.into_iter().find_map(|e| match (e, $id) {
            (Effect::AmplifierSaturation { current_limit, .. }, ParamId::CurrentLimit) => Some(current_limit),
            (Effect::VoltageSaturation { voltage_limit, .. }, ParamId::VoltageLimit) => Some(voltage_limit),
            (Effect::AmplifierSaturation { knee: Some(n), .. }, ParamId::CurrentKnee) => Some(n),
            (Effect::VoltageSaturation { knee: Some(n), .. }, ParamId::VoltageKnee) => Some(n),
            (Effect::CoulombFriction { torque, .. }, ParamId::CoulombTorque) => Some(torque),
            (Effect::CoulombFriction { static_peak: Some(p), .. }, ParamId::StaticPeak) => Some(p),
            (Effect::CoulombFriction { stribeck_velocity: Some(v), .. }, ParamId::StribeckVelocity) => {
                Some(v)
            }
            (Effect::QuadraticDrag { hub, .. }, ParamId::DragHub) => Some(hub),
            (Effect::QuadraticDrag { exponent: Some(p), .. }, ParamId::DragExponent) => Some(p),
            (Effect::CubicStiffness { coefficient, .. }, ParamId::CubicStiffness) => Some(coefficient),
            (Effect::CubicStiffness { linear: Some(k), .. }, ParamId::HubStiffness) => Some(k),
            (Effect::CubicStiffness { quintic: Some(k), .. }, ParamId::QuinticStiffness) => Some(k),
            (Effect::CubicStiffness { rate: Some(k), .. }, ParamId::StiffnessRate) => Some(k),
            (Effect::TimeDelay { delay }, ParamId::Delay) => Some(delay),
            (Effect::Backlash { dead_band, .. }, ParamId::Backlash) => Some(dead_band),
            (Effect::Backlash { gear_frequency_hz, .. }, ParamId::GearFrequency) => Some(gear_frequency_hz),
            (Effect::OutputOffset { sensor, offset }, ParamId::Offset(s)) if *sensor == s => Some(offset),
            (Effect::SensorScale { sensor, scale }, ParamId::Scale(s)) if *sensor == s => Some(scale),
            (Effect::SensorDrift { sensor, rate, .. }, ParamId::Drift(s)) if *sensor == s => Some(rate),
            (Effect::SensorCrosstalk { sensor, from, gain }, ParamId::Crosstalk(s, f))
                if *sensor == s && *from == f =>
            {
                Some(gain)
            }
            (Effect::SensorLag { sensor, lag }, ParamId::Lag(s)) if *sensor == s => Some(lag),
            (Effect::SensorDrift { sensor, time_constant: Some(tau), .. }, ParamId::DriftTime(s))
                if *sensor == s =>
            {
                Some(tau)
            }
            (
                Effect::UnmodeledMode { stiffness_coupling: Some(k), .. },
                ParamId::ExtraModeStiffnessCoupling,
            ) => Some(k),
            (Effect::UnmodeledMode { damping_coupling: Some(c), .. }, ParamId::ExtraModeDampingCoupling) => {
                Some(c)
            }
            (Effect::UnmodeledMode { frequency_hz, .. }, ParamId::ExtraModeFrequency) => Some(frequency_hz),
            (Effect::UnmodeledMode { damping_ratio, .. }, ParamId::ExtraModeDamping) => Some(damping_ratio),
            (Effect::UnmodeledMode { coupling, .. }, ParamId::ExtraModeCoupling) => Some(coupling),
            _ => None,
        })
    };
}

impl<D: Clone> Constants<D> {
    /// The value of one parameter.
    ///
    /// # Panics
    /// If the parameter belongs to an effect the model does not have (ids obtained from
    /// [`crate::SlewingModel::parameter`] always exist).
    pub fn get(&self, id: ParamId) -> D {
        self.try_get(id).expect("the parameter exists in this model")
    }

    /// The value of one parameter, if the model has it.
    pub fn try_get(&self, id: ParamId) -> Option<D> {
        core_field!([&] self, id).or_else(|| effect_field!([&] self.effects.iter(), id)).cloned()
    }

    /// A mutable reference to one parameter.
    ///
    /// # Panics
    /// As [`Self::get`].
    pub fn field_mut(&mut self, id: ParamId) -> &mut D {
        if let Some(f) = core_field!([&mut] self, id) {
            return f;
        }
        effect_field!([&mut] self.effects.iter_mut(), id).expect("the parameter exists in this model")
    }

    /// Every parameter this model has: the core ones and those of its effects.
    pub fn parameter_ids(&self) -> Vec<ParamId> {
        let mut ids = ParamId::all(self.modal_damping.len());
        for e in &self.effects {
            ids.extend(ParamId::of_effect(e));
        }
        ids
    }

    /// Converts every value with `f` (e.g. f64 → dual number).
    pub fn map<E>(&self, f: impl Fn(&D) -> E) -> Constants<E> {
        Constants {
            length: f(&self.length),
            ei_over_rho: f(&self.ei_over_rho),
            mass_per_length: f(&self.mass_per_length),
            hub_radius: f(&self.hub_radius),
            thickness: f(&self.thickness),
            hub_inertia: f(&self.hub_inertia),
            motor_inertia: f(&self.motor_inertia),
            torque_constant: f(&self.torque_constant),
            back_emf_constant: f(&self.back_emf_constant),
            armature_resistance: f(&self.armature_resistance),
            amplifier_gain: f(&self.amplifier_gain),
            position_gain: f(&self.position_gain),
            viscous_damping: f(&self.viscous_damping),
            modal_damping: self.modal_damping.iter().map(&f).collect(),
            effects: self.effects.iter().map(|e| e.map(&f)).collect(),
        }
    }
}
