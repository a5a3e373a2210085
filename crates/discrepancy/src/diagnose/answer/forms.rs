//! The tests of a named effect's form and its rival accounts as the answer reports them: a
//! spring's terms ([`SpringForm`]), the law in time set against a structure force
//! ([`TimeLaw`]), the dampers set against a structure's mode ([`DampingRival`]), a friction's
//! static peak ([`StaticPeak`]) and a saturation's knee ([`SaturationKnee`]).

use super::EffectParameter;
#[cfg(doc)]
use super::Verdict;
use serde::Serialize;

/// One term of a named spring's form refitted beside it (step 8 of
/// [module `diagnose`](mod@crate::diagnose)): an asymmetric part, k₂q_c² (`quadratic_<c>`) or
/// kₛq_c⁴|q_c| (`sided_<c>`), or a linear stiffness that changes with time k₁′·t·q_c (`stiffness_rate_<c>`), each beside the
/// spring and a symmetric refinement of its form k₅q_c⁵.
#[derive(Clone, Debug, Serialize)]
pub struct SpringTerm {
    /// The term as refitted beside the spring.
    pub parameter: EffectParameter,
    /// In-sample gain of adding it (nats) beside the spring and its quintic term.
    pub gain: f64,
    /// In-sample gain of the symmetric quintic term k₅q_c⁵ beside the spring (nats).
    pub symmetric_gain: f64,
    /// Whether the data demand it: it is determined inside its range and gains at least the
    /// held-out threshold and a tenth of the spring's own gain, or lies 5 standard errors from
    /// zero (step 8 of
    /// [module `diagnose`](mod@crate::diagnose)).
    pub demanded: bool,
}

/// The form of a named symmetric spring (a structure's `cubic_stiffness` at coordinate c, or
/// the slewing rig's at the hub), tested beside it (step 8 of
/// [module `diagnose`](mod@crate::diagnose)). When the data demand either term, the spring
/// stands for physics the catalog does not hold, and nothing is named.
#[derive(Clone, Debug, Serialize)]
pub struct SpringForm {
    /// Its asymmetric part, k₂q_c² or the one-sided kₛq_c⁴|q_c| (`sided_<c>`, at the quintic's
    /// power: a stop or a contact beyond a gap), whichever the data demand, else whichever gains
    /// more: demanded, the restoring force is stiffer on one side than the other (a stop, a
    /// contact, a gap that closes one way; [`Verdict::Asymmetric`]). Not tested
    /// (`None`) for the slewing rig's hub spring, whose free decay stays on one side of zero.
    pub asymmetric: Option<SpringTerm>,
    /// A linear stiffness that changes with time, k₁′·t·q_c: demanded, the stiffness changes
    /// during the record (a storey that degrades, a motor's torque constant that fades) rather
    /// than with amplitude ([`Verdict::TimeVarying`]).
    pub changing: SpringTerm,
    /// In-sample gain of the spring with its quintic over the reference (nats): the spring's
    /// account, set against [`TimeLaw`].
    pub gain: f64,
}

/// The rival to a named structure force (module `time_law`): no such force, but a linear
/// stiffness at one of the structure's coordinates that changes with time by a law of its own,
/// Δk(t)·q_j with Δk piecewise linear through (0, 0) and evenly spaced times to the record's end
/// (the `change` of [`structure::Effect::CubicStiffness`]), the best of every coordinate's. The
/// named force keeps its name only where it explains the record better than the law by the
/// held-out threshold in sample; else it is set aside ([`Verdict::TimeVarying`]).
#[derive(Clone, Debug, Serialize)]
pub struct TimeLaw {
    /// The coordinate q_j it acts at.
    pub coordinate: String,
    /// The law's times tᵢ \[s from the release\].
    pub times: Vec<f64>,
    /// Δk(tᵢ), refitted from the reference (`stiffness_change_<c>_<i>`).
    pub values: Vec<EffectParameter>,
    /// In-sample gain of the law alone over the reference (nats).
    pub gain: f64,
    /// In-sample gain of the named force's account over the reference (nats): a spring with its
    /// quintic, a drag or a friction as refitted.
    pub effect_gain: f64,
    /// Whether the law explains the record as well as the named force: `effect_gain − gain`
    /// short of the held-out threshold. Then the force is set aside.
    pub as_well: bool,
}

/// The rival to a named mode, drag or dry friction on a structure (module `damping`): no such
/// effect, but a linear damper at every coordinate without a drag, all refitted at once — the
/// model's damping distributed otherwise than its form gives. The effect keeps its name only
/// where it explains the record better than the dampers by the held-out threshold in sample;
/// else it is set aside ([`Verdict::DampingDistribution`]).
#[derive(Clone, Debug, Serialize)]
pub struct DampingRival {
    /// The dampers c_j refitted from the reference (`drag_<c>`, exponent 1) \[N·s/m\].
    pub dampers: Vec<EffectParameter>,
    /// In-sample gain of the dampers over the reference (nats).
    pub gain: f64,
    /// In-sample gain of the named effect over the reference (nats).
    pub effect_gain: f64,
    /// Whether the dampers explain the record as well as the effect: `effect_gain − gain` short
    /// of the held-out threshold. Then the effect is set aside.
    pub as_well: bool,
}

/// The static peak of a named dry friction, refitted beside it (step 8 of
/// [module `diagnose`](mod@crate::diagnose); module `friction`): τ = −(F_c + ΔF e^{−(θ̇/v_st)²})
/// tanh(θ̇/v_s).
#[derive(Clone, Debug, Serialize)]
pub struct StaticPeak {
    /// ΔF = F_s − F_c (`static_peak`): how far the breakaway level exceeds the sliding one.
    pub peak: EffectParameter,
    /// v_st (`stribeck_velocity`): the rate over which the peak falls.
    pub stribeck_velocity: EffectParameter,
    /// F_c, refitted beside the peak.
    pub coulomb_torque: EffectParameter,
    /// In-sample gain of the peak over Coulomb's constant level, both refitted to convergence
    /// (nats).
    pub gain: f64,
    /// Whether the data demand it: it gains at least the held-out threshold and ΔF, v_st and
    /// F_c are determined inside their ranges. Demanded, the named friction carries it.
    pub demanded: bool,
}

/// The knee of a named saturation (module `saturation` of [`mod@crate::diagnose`]): the
/// limiter x/(1 + |x/L|ⁿ)^{1/n} with n free beside the limit L.
#[derive(Clone, Debug, Serialize)]
pub struct SaturationKnee {
    /// n (`current_knee`, `voltage_knee`): 8 is the catalog's limiter, large n the clamp, 2 a
    /// soft limit.
    pub knee: EffectParameter,
    /// The limit, refitted beside the knee.
    pub limit: EffectParameter,
    /// In-sample gain of the knee over the catalog's limiter, both refitted to convergence
    /// (nats).
    pub gain: f64,
    /// Whether the knee came out at 50 or more: a clamp (within 1.4 % of one at the limit, closer
    /// elsewhere), sharper ones barely told apart.
    pub clamp: bool,
    /// Whether the data demand it: it gains at least the held-out threshold, the limit is
    /// determined inside its range, and the knee is too or is a clamp. Demanded, the named
    /// saturation carries it.
    pub demanded: bool,
}
