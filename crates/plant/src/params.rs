//! The model's physical and control constants, generic over the scalar, and their names.

use crate::PlantError;

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
    /// Power-amplifier voltage gain G \[V/V\] between the controller and the armature (not
    /// printed in the paper; calibrated).
    pub amplifier_gain: D,
    /// Position feedback gain K_p \[V/rad\].
    pub position_gain: D,
    /// Viscous damping C_v \[N·m·s/rad\].
    pub viscous_damping: D,
    /// Modal damping terms 2ζ_iω_i \[1/s\], one per flexible mode.
    pub modal_damping: Vec<D>,
}

/// A named, tunable constant of the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamId {
    /// `cv`: viscous damping C_v.
    ViscousDamping,
    /// `kp`: position gain K_p.
    PositionGain,
    /// `modal_damping_<i>` (1-based): 2ζ_iω_i.
    ModalDamping(usize),
    /// `rho`: mass per length.
    MassPerLength,
    /// `ei_over_rho`: EI/ρ.
    EiOverRho,
    /// `length`: beam length.
    Length,
    /// `hub_radius`: a.
    HubRadius,
    /// `hub_inertia`: I_H.
    HubInertia,
    /// `motor_inertia`: I_m.
    MotorInertia,
    /// `kt`: torque constant.
    TorqueConstant,
    /// `kb`: back-EMF constant.
    BackEmfConstant,
    /// `ra`: armature resistance.
    ArmatureResistance,
    /// `amplifier_gain`: G.
    AmplifierGain,
    /// `thickness`: beam thickness.
    Thickness,
}

const FIXED_NAMES: [(&str, ParamId); 13] = [
    ("cv", ParamId::ViscousDamping),
    ("kp", ParamId::PositionGain),
    ("rho", ParamId::MassPerLength),
    ("ei_over_rho", ParamId::EiOverRho),
    ("length", ParamId::Length),
    ("hub_radius", ParamId::HubRadius),
    ("hub_inertia", ParamId::HubInertia),
    ("motor_inertia", ParamId::MotorInertia),
    ("kt", ParamId::TorqueConstant),
    ("kb", ParamId::BackEmfConstant),
    ("ra", ParamId::ArmatureResistance),
    ("amplifier_gain", ParamId::AmplifierGain),
    ("thickness", ParamId::Thickness),
];

impl ParamId {
    /// Where the parameter lives in a model file, e.g. `control.viscous_damping`.
    pub fn field_path(self) -> String {
        match self {
            ParamId::ViscousDamping => "control.viscous_damping".into(),
            ParamId::PositionGain => "control.position_gain".into(),
            ParamId::ModalDamping(i) => format!("modal_damping[{}]", i - 1),
            ParamId::MassPerLength => "beam.mass_per_length".into(),
            ParamId::EiOverRho => "beam.ei_over_rho".into(),
            ParamId::Length => "beam.length".into(),
            ParamId::HubRadius => "beam.hub_radius".into(),
            ParamId::Thickness => "beam.thickness".into(),
            ParamId::HubInertia => "hub.inertia".into(),
            ParamId::MotorInertia => "motor.inertia".into(),
            ParamId::TorqueConstant => "motor.torque_constant".into(),
            ParamId::BackEmfConstant => "motor.back_emf_constant".into(),
            ParamId::ArmatureResistance => "motor.armature_resistance".into(),
            ParamId::AmplifierGain => "motor.amplifier_gain".into(),
        }
    }

    /// Whether the value must be strictly positive (else non-negative).
    pub fn must_be_positive(self) -> bool {
        matches!(
            self,
            ParamId::Length
                | ParamId::EiOverRho
                | ParamId::MassPerLength
                | ParamId::Thickness
                | ParamId::TorqueConstant
                | ParamId::ArmatureResistance
                | ParamId::AmplifierGain
        )
    }

    /// Checks a value against [`Self::must_be_positive`]; `Err` holds the requirement.
    pub fn check(self, value: f64) -> Result<(), String> {
        let ok = value.is_finite() && if self.must_be_positive() { value > 0.0 } else { value >= 0.0 };
        if ok {
            Ok(())
        } else if self.must_be_positive() {
            Err("must be finite and > 0".into())
        } else {
            Err("must be finite and ≥ 0".into())
        }
    }

    /// The parameter's name, as used on the command line and in model files.
    pub fn name(self) -> String {
        match self {
            ParamId::ModalDamping(i) => format!("modal_damping_{i}"),
            other => FIXED_NAMES
                .iter()
                .find(|(_, id)| *id == other)
                .map(|(n, _)| (*n).to_string())
                .expect("every fixed parameter has a name"),
        }
    }

    /// All parameter names of a model with `n_modes` flexible modes.
    pub fn all(n_modes: usize) -> Vec<ParamId> {
        let mut ids: Vec<ParamId> = FIXED_NAMES[..2].iter().map(|(_, id)| *id).collect();
        ids.extend((1..=n_modes).map(ParamId::ModalDamping));
        ids.extend(FIXED_NAMES[2..].iter().map(|(_, id)| *id));
        ids
    }

    /// Looks a name up.
    ///
    /// # Errors
    /// [`PlantError::UnknownParameter`] listing the valid names.
    pub fn parse(name: &str, n_modes: usize) -> Result<ParamId, PlantError> {
        ParamId::all(n_modes).into_iter().find(|id| id.name() == name).ok_or_else(|| {
            PlantError::UnknownParameter {
                name: name.to_string(),
                valid: ParamId::all(n_modes).iter().map(|id| id.name()).collect::<Vec<_>>().join(", "),
            }
        })
    }
}

/// The field of `Constants` that a `ParamId` names, borrowed with the given reference kind.
macro_rules! field {
    ([$($borrow:tt)+] $s:ident, $id:expr) => {
        match $id {
            ParamId::ViscousDamping => $($borrow)+ $s.viscous_damping,
            ParamId::PositionGain => $($borrow)+ $s.position_gain,
            ParamId::ModalDamping(i) => $($borrow)+ $s.modal_damping[i - 1],
            ParamId::MassPerLength => $($borrow)+ $s.mass_per_length,
            ParamId::EiOverRho => $($borrow)+ $s.ei_over_rho,
            ParamId::Length => $($borrow)+ $s.length,
            ParamId::HubRadius => $($borrow)+ $s.hub_radius,
            ParamId::HubInertia => $($borrow)+ $s.hub_inertia,
            ParamId::MotorInertia => $($borrow)+ $s.motor_inertia,
            ParamId::TorqueConstant => $($borrow)+ $s.torque_constant,
            ParamId::BackEmfConstant => $($borrow)+ $s.back_emf_constant,
            ParamId::ArmatureResistance => $($borrow)+ $s.armature_resistance,
            ParamId::AmplifierGain => $($borrow)+ $s.amplifier_gain,
            ParamId::Thickness => $($borrow)+ $s.thickness,
        }
    };
}

impl<D: Clone> Constants<D> {
    /// The value of one parameter.
    pub fn get(&self, id: ParamId) -> D {
        self.field(id).clone()
    }

    /// A mutable reference to one parameter.
    pub fn field_mut(&mut self, id: ParamId) -> &mut D {
        field!([&mut] self, id)
    }

    fn field(&self, id: ParamId) -> &D {
        field!([&] self, id)
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
        }
    }
}
