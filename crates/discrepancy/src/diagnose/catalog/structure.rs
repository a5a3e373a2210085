//! A structure's candidates: sensor offset, scale and drift on every output; dry friction,
//! drag and a cubic spring at every coordinate of a second-order model; an unmodeled mode
//! where the residual or the data hold one, ringing in the outputs and, on a second-order
//! model, as an appendage at every coordinate ([`appendages`]; in free decay also one held
//! relaxed above the modelled modes, [`STIFF_BODY`]). Starting values and bounds come
//! from the model's own stiffness, damping and response (its peak displacement and velocity per
//! coordinate, in its free decay or, on a forced record, in its response to the record's inputs;
//! there the mode is driven by an input, from rest).

use super::{Clear, LIGHTLY_DAMPED, Located, Pole, Seed, Strength, Trial, mode_seeds, seed_at};
use crate::localise::Localisation;
use faer::Mat;
use mem::Measurement;
use plant::EffectKind;
use structure::{Effect, StructureModel};

/// The catalog kind of a structure effect.
pub(super) fn kind(effect: &Effect) -> EffectKind {
    match effect {
        Effect::OutputOffset { .. } => EffectKind::OutputOffset,
        Effect::SensorScale { .. } => EffectKind::SensorScale,
        Effect::SensorDrift { .. } => EffectKind::SensorDrift,
        Effect::SensorQuantization { .. } => EffectKind::SensorQuantization,
        Effect::SensorCrosstalk { .. } => EffectKind::SensorCrosstalk,
        Effect::DryFriction { .. } => EffectKind::CoulombFriction,
        Effect::Drag { .. } => EffectKind::QuadraticDrag,
        Effect::CubicStiffness { .. } => EffectKind::CubicStiffness,
        Effect::UnmodeledMode { .. } | Effect::Appendage { .. } => EffectKind::UnmodeledMode,
    }
}

/// Peak |q_j| and |q̇_j| of the model's response: to the measured inputs of `record` over its
/// whole length where it has them (held between samples as the record says, from the model's
/// initial state: x_{k+1} = Φx_k + Γ_now u_k + Γ_next u_{k+1}, the gains of
/// [`expm::step_gains`], Γ_now + Γ_next applied to u_k for a zero-order hold), else of its free
/// decay over two periods of its lowest mode (Φ = e^{Ah} over a short step). One exponential per
/// call; the state is stepped in two buffers.
fn peaks(model: &StructureModel, record: Option<&Measurement>) -> Option<Vec<(f64, f64)>> {
    if !model.is_second_order() {
        return None;
    }
    let n = model.coordinates().len();
    let space = model.state_space::<f64>(&model.values()).ok()?;
    let big = space.a.nrows();
    let a = Mat::from_fn(big, big, |r, c| space.a[(r, c)]);
    let forced = record.and_then(|r| Some((r.inputs()?, r.model_grid().1))).zip(space.b.as_ref());
    // Φ, and for a forced record the input gains applied to u_k and to u_{k+1}.
    let (phi, gains, steps) = match forced {
        Some(((inputs, h), b)) => {
            let b = Mat::from_fn(big, b.ncols(), |r, c| b[(r, c)]);
            let g = expm::step_gains(a.as_ref(), &[], b.as_ref(), &[], h).ok()?;
            let (now, next) = match inputs.hold() {
                mem::Hold::Zero => (&g.now + &g.next, None),
                mem::Hold::FirstOrder => (g.now, Some(g.next)),
            };
            (g.phi, Some((inputs.values(), now, next)), inputs.values().nrows())
        }
        None => {
            let modes = model.modes().ok()?;
            let (low, high) = (modes.first()?.frequency_hz, modes.last()?.frequency_hz);
            if !(low > 0.0 && high.is_finite()) {
                return None;
            }
            let h = 1.0 / (20.0 * high);
            (expm::expm((&a * h).as_ref()).ok()?, None, ((2.0 / low) / h).ceil().min(1e5) as usize)
        }
    };
    let mut x: Vec<f64> = space.x0.iter().copied().collect();
    let mut following = vec![0.0; big];
    let mut peak = vec![(0.0f64, 0.0f64); n];
    for k in 0..steps {
        for (j, p) in peak.iter_mut().enumerate() {
            p.0 = p.0.max(x[j].abs());
            p.1 = p.1.max(x[n + j].abs());
        }
        for (r, out) in following.iter_mut().enumerate() {
            *out = (0..big).map(|c| phi[(r, c)] * x[c]).sum();
            if let Some((u, now, next)) = &gains {
                let later = (k + 1).min(u.nrows() - 1);
                for i in 0..u.ncols() {
                    *out +=
                        now[(r, i)] * u[(k, i)] + next.as_ref().map_or(0.0, |g| g[(r, i)] * u[(later, i)]);
                }
            }
        }
        std::mem::swap(&mut x, &mut following);
    }
    peak.iter().all(|(q, v)| q.is_finite() && v.is_finite()).then_some(peak)
}

/// A coordinate's scales, from the model and what drives it: its peak displacement q̂ and rate
/// v̂ in the model's response ([`peaks`]: to the record's measured inputs, or its own free
/// decay), its diagonal stiffness k_jj, and the viscous force at the peak rate (at least that of
/// 1 % critical damping).
pub(in crate::diagnose) struct Scales {
    /// The coordinate's name.
    pub coordinate: String,
    /// q̂.
    pub q: f64,
    /// v̂.
    pub v: f64,
    /// k_jj.
    pub k: f64,
    /// The viscous force at v̂.
    pub viscous: f64,
}

/// [`Scales`] of every coordinate of a second-order model where they are all positive (none for
/// a first-order model), in its response to `record`'s inputs (its free decay without them).
pub(in crate::diagnose) fn scales(model: &StructureModel, record: Option<&Measurement>) -> Vec<Scales> {
    let matrices = model.second_order::<f64>(&model.values()).ok().flatten();
    let Some((so, peaks)) = matrices.zip(peaks(model, record)) else { return Vec::new() };
    model
        .coordinates()
        .iter()
        .enumerate()
        .filter_map(|(j, c)| {
            let (q, v) = peaks[j];
            let (m, k) = (so.m[(j, j)], so.k[(j, j)]);
            (q > 0.0 && v > 0.0 && m > 0.0 && k > 0.0).then(|| Scales {
                coordinate: c.clone(),
                q,
                v,
                k,
                viscous: so.d[(j, j)].max(0.02 * (k * m).sqrt()) * v,
            })
        })
        .collect()
}

/// On a forced record, the clearance a lightly damped seed keeps from a modelled mode, in that
/// mode's damping ratios ζ_j (1.5 ζ_j: its half-power band is ±ζ_j).
const FORCED_CLEARANCE: f64 = 1.5;

/// The least of that clearance (relative).
const FORCED_MIN_CLEARANCE: f64 = 0.05;

fn trial(
    effect: Effect,
    label: String,
    bounds: Vec<(String, (f64, f64))>,
    strength: Vec<Strength>,
    outputs: &[String],
) -> Trial {
    let kind = kind(&effect);
    let freed = effect.parameters(outputs).into_iter().map(|(n, _)| n).collect();
    Trial::new(effect.into(), kind, label, bounds, strength, freed)
}

/// The catalog's candidates for a structure (see the module docs).
pub(super) fn trials(
    model: &StructureModel,
    record: &Measurement,
    localisation: &Localisation,
) -> Vec<Trial> {
    let outputs = model.output_names();
    let mut out = Vec::new();
    for (o, name) in outputs.iter().enumerate() {
        out.push(
            trial(
                Effect::OutputOffset { output: name.clone(), offset: 0.0 },
                format!("output_offset({name})"),
                vec![],
                vec![Strength::Nonzero(format!("offset_{name}"))],
                &outputs,
            )
            .on_output(o),
        );
        out.push(
            trial(
                Effect::SensorScale { output: name.clone(), scale: 0.0 },
                format!("sensor_scale({name})"),
                vec![(format!("scale_{name}"), (-0.9, 9.0))],
                vec![Strength::Nonzero(format!("scale_{name}"))],
                &outputs,
            )
            .on_output(o),
        );
        out.push(
            trial(
                Effect::SensorDrift { output: name.clone(), rate: 0.0, time_constant: None },
                format!("sensor_drift({name})"),
                vec![],
                vec![Strength::Nonzero(format!("drift_{name}"))],
                &outputs,
            )
            .on_output(o),
        );
        if let Some((range, [first, second])) = super::drift_time_range(super::record_length(localisation)) {
            let levelling =
                |tau: f64| Effect::SensorDrift { output: name.clone(), rate: 0.0, time_constant: Some(tau) };
            out.push(
                trial(
                    levelling(first),
                    format!("sensor_drift({name}), levelling off"),
                    vec![(format!("drift_time_{name}"), range)],
                    vec![Strength::Nonzero(format!("drift_{name}"))],
                    &outputs,
                )
                .on_output(o)
                .or_from(levelling(second))
                .located_inside(format!("drift_time_{name}")),
            );
        }
    }
    for Scales { coordinate: c, q, v, k, viscous } in scales(model, Some(record)) {
        out.push(
            trial(
                // Smoothed over 1 % of the peak rate: sharp for the motion, smooth enough
                // for the integrator's substep at the bounds' largest force.
                Effect::DryFriction {
                    coordinate: c.clone(),
                    force: 0.02 * k * q,
                    smoothing_velocity: 0.01 * v,
                    static_peak: None,
                    stribeck_velocity: None,
                },
                format!("coulomb_friction({c})"),
                vec![(format!("friction_{c}"), (0.0, 0.3 * k * q))],
                vec![Strength::Nonzero(format!("friction_{c}"))],
                &outputs,
            )
            .or_from(Effect::DryFriction {
                coordinate: c.clone(),
                force: 0.1 * k * q,
                smoothing_velocity: 0.01 * v,
                static_peak: None,
                stribeck_velocity: None,
            }),
        );
        out.push(
            trial(
                // Drag equal to a fifth of the viscous force at the peak rate.
                Effect::Drag { coordinate: c.clone(), coefficient: 0.2 * viscous / (v * v), exponent: 2.0 },
                format!("quadratic_drag({c})"),
                vec![
                    (format!("drag_{c}"), (0.0, 200.0 * viscous / (v * v))),
                    (format!("drag_exponent_{c}"), (1.2, 3.5)),
                ],
                vec![Strength::Nonzero(format!("drag_{c}"))],
                &outputs,
            )
            .or_from(Effect::Drag {
                coordinate: c.clone(),
                coefficient: viscous / (v * v),
                exponent: 2.0,
            }),
        );
        out.push(
            trial(
                // Hardening and softening starts (the stiffnesses can take up part of a
                // cubic from either side).
                Effect::CubicStiffness {
                    coordinate: c.clone(),
                    coefficient: 0.05 * k / (q * q),
                    quadratic: None,
                    quintic: None,
                    sided: None,
                    rate: None,
                    change: None,
                },
                format!("cubic_stiffness({c})"),
                vec![(format!("cubic_{c}"), (-10.0 * k / (q * q), 10.0 * k / (q * q)))],
                vec![Strength::Nonzero(format!("cubic_{c}"))],
                &outputs,
            )
            .or_from(Effect::CubicStiffness {
                coordinate: c.clone(),
                coefficient: -0.05 * k / (q * q),
                quadratic: None,
                quintic: None,
                sided: None,
                rate: None,
                change: None,
            }),
        );
    }
    // On a forced record the mode is the response to a measured input, from rest (one trial
    // per input, the input named in the label when there are several); in free decay, a
    // ringing from the start.
    let drives: Vec<Option<(String, f64)>> = match record.inputs() {
        Some(inputs) if !model.input_names().is_empty() => inputs
            .names()
            .iter()
            .enumerate()
            .filter_map(|(i, name)| {
                let column = inputs.values().col(i);
                let rms = (column.iter().map(|u| u * u).sum::<f64>() / column.nrows().max(1) as f64).sqrt();
                (rms > 0.0 && rms.is_finite()).then(|| Some((name.clone(), rms)))
            })
            .collect(),
        _ => vec![None],
    };
    // A mode within 15 % of a modelled one is not told from a change of that mode (its
    // frequency or damping, or their dependence on amplitude): seeds there are not tried, and
    // a seed's range stops 15 % short of the modelled modes around it.
    //
    // On a forced record the measured input shows each resonance's width: there a seed damped
    // less than half a modelled mode's ratio ζ_j is a sharp peak on that mode's flank, which no
    // change of the broader mode makes, and it need only be clear of it by
    // [`FORCED_CLEARANCE`]·ζ_j (at least [`FORCED_MIN_CLEARANCE`]). A 25 kg appendage at
    // 15.1 Hz on floor 2 (ζ 0.9 %, 1,895 nats of resonance in its record) lay 10 % above the
    // building's third mode (13.7 Hz, ζ ≈ 5.6 %) on the forced draw 20261306, and was answered
    // a sensor scale.
    let forced = drives.iter().any(Option::is_some);
    let modelled: Vec<Clear> = model
        .modes()
        .map(|m| {
            m.iter()
                .map(|r| Clear {
                    frequency: r.frequency_hz,
                    margin: 0.15,
                    sharp: forced.then(|| {
                        (
                            (FORCED_CLEARANCE * r.damping_ratio).max(FORCED_MIN_CLEARANCE),
                            0.5 * r.damping_ratio,
                        )
                    }),
                })
                .collect()
        })
        .unwrap_or_default();
    let several = drives.len() > 1;
    let seeds = mode_seeds(&modelled, LIGHTLY_DAMPED, localisation, &[]);
    // The bodies the residual shows at a coordinate, under the same clearances.
    let bodies: Vec<Body> = localisation
        .appendages
        .iter()
        .filter_map(|a| {
            let seed = seed_at(a.frequency_hz, a.damping_ratio, &modelled, localisation)?;
            Some(Body { coordinate: a.coordinate.clone(), seed, mass: a.mass })
        })
        .collect();
    // In free decay, an appendage stiffer than the modelled modes is looked for above them too
    // ([`STIFF_BODY`]): released relaxed it follows its floor and shows no resonance of its own.
    let top = modelled.iter().map(|c| c.frequency).fold(0.0, f64::max);
    let stiff = (!forced)
        .then(|| seed_at(STIFF_BODY * top, STIFF_BODY_DAMPING, &modelled, localisation))
        .flatten()
        .filter(|s| seeds.iter().all(|o| (o.frequency / s.frequency - 1.0).abs() >= 0.1));
    out.extend(appendages(model, record, &seeds, &bodies, stiff, &outputs, forced));
    for seed in seeds {
        for drive in &drives {
            let (f, zeta, (low, high)) = (seed.frequency, seed.damping, seed.range);
            // A ringing's amplitude is the residual's RMS; a driven mode's, per unit input.
            let per = drive.as_ref().map_or(1.0, |(_, rms)| *rms);
            let amplitudes: Vec<(f64, f64)> =
                localisation.outputs.iter().map(|o| (o.rms / per, 0.0)).collect();
            let prefix = match drive {
                Some((input, _)) if several => format!("unmodeled_mode({input}, "),
                _ => "unmodeled_mode(".into(),
            };
            let located = Located {
                name: "mode_frequency".into(),
                limits: seed.limits,
                prefix,
                damping: "mode_damping".into(),
                pole: Pole::Ringing,
            };
            let at = |f: f64| Effect::UnmodeledMode {
                frequency_hz: f,
                damping_ratio: zeta.clamp(0.005, 0.15),
                amplitudes: amplitudes.clone(),
                driven_by: drive.as_ref().map(|(input, _)| input.clone()),
            };
            let mut t = trial(
                at(f),
                located.label(f),
                vec![("mode_frequency".into(), (low, high)), ("mode_damping".into(), (0.0, 0.2))],
                vec![Strength::Largest(
                    outputs
                        .iter()
                        .map(|o| format!("mode_cos_{o}"))
                        .chain(outputs.iter().map(|o| format!("mode_sin_{o}")))
                        .collect(),
                )],
                &outputs,
            )
            .or_from_other_starts(&seed, at);
            t.located = Some(located);
            out.push(t);
        }
    }
    // Effects the model has are not tried again (a second mode is not offered either).
    out.retain(|t| match &t.effect {
        models::ModelEffect::Structure(e) => !has_effect(model, e),
        models::ModelEffect::Slewing(_) => false,
    });
    out
}

/// Whether the model already has an effect of `effect`'s kind where it acts (for a mode, an
/// unmodeled one or an appendage, any mode anywhere: a second mode is not offered).
pub(in crate::diagnose) fn has_effect(model: &StructureModel, effect: &Effect) -> bool {
    let mode = |e: &Effect| kind(e) == EffectKind::UnmodeledMode;
    model.effects().iter().any(|have| {
        (have.kind() == effect.kind() && have.target() == effect.target()) || (mode(have) && mode(effect))
    })
}

/// The share of a coordinate's mass an appendage starts with.
const APPENDAGE_START_MASS: f64 = 0.02;

/// Where an appendage stiffer than the structure's modelled modes is first looked for in free
/// decay, as a multiple of the highest modelled frequency (its range a factor 2 about it, from
/// 15 % above that mode, with starts also at √2 times it). A body on a spring released relaxed
/// on its displaced floor is moved only through the floor's acceleration. Where its own frequency
/// f_a lies above the modes that move the floor, it follows the floor nearly rigidly and barely
/// rings: its resonance is not in the residual, and no residual mode seeds it. What it does
/// show is an inertia that rises toward the upper modes, m_a/(1 − (f/f_a)²) at mode f, which
/// no constant mass holds. A body below the modes is shaken by them and rings at its own
/// frequency, which the residual shows. This start is a relaxed body (its release is held at 0,
/// not refitted): one released stretched rings, and is seeded from the residual; refitted here,
/// a light body's release stands in for a kick to its floor at the start (a 0.1 kg body at
/// 38 Hz released with 9 kN, 5.6 σ, answered a −0.5 % gauge scale on the free-decay draw
/// 20261374). Without this start, on the free-decay draw 20261373, 50 kg at 17 Hz on floor 1
/// was `none` and 50 kg at 19 Hz on the roof was answered `sensor_scale(q3)`, the building's
/// top mode near 13–14 Hz.
const STIFF_BODY: f64 = 1.5;

/// The damping ratio the stiff appendage ([`STIFF_BODY`]) starts from.
const STIFF_BODY_DAMPING: f64 = 0.02;

/// A body the residual shows hanging on a coordinate ([`crate::frf::AppendageScan`]): its seed
/// and its first-order mass.
struct Body {
    coordinate: String,
    seed: Seed,
    mass: f64,
}

/// A mode the model lacks as a mass on a spring and damper at a coordinate
/// ([`Effect::Appendage`]): first at the coordinate's own body where the appendage scan found
/// one (`bodies`), then at every mode seed not within 10 % of it (in free decay also above the
/// modelled modes, [`STIFF_BODY`]). Where the missing mode is a body hanging on the structure,
/// it pushes back on it, and a ringing added to the outputs (the
/// free [`Effect::UnmodeledMode`]) cannot follow what its release or its reaction does to the
/// structure's own modes. Its mass starts at the body's first-order mass (within its bounds),
/// else at [`APPENDAGE_START_MASS`] of the coordinate's (bounds 10⁻⁴–1 of it); in free decay
/// it is released with its spring's force F_r (`appendage_release_<c>`, bounds ± the
/// coordinate's stiffness force at its peak displacement, k_jj q̂, from 0: relaxed; the stiff
/// start's held relaxed), on a forced record it starts at rest with the structure. Its strength
/// is the larger of the mass's and the release's resolution from zero.
fn appendages(
    model: &StructureModel,
    record: &Measurement,
    seeds: &[Seed],
    bodies: &[Body],
    stiff: Option<Seed>,
    outputs: &[String],
    forced: bool,
) -> Vec<Trial> {
    let Some(so) = model.second_order::<f64>(&model.values()).ok().flatten() else { return Vec::new() };
    let mut out = Vec::new();
    for Scales { coordinate: c, q, k, .. } in scales(model, Some(record)) {
        let Some(j) = model.coordinates().iter().position(|n| *n == c) else { continue };
        let m = so.m[(j, j)];
        let own: Vec<(Seed, f64)> = bodies
            .iter()
            .filter(|b| b.coordinate == c)
            .map(|b| (b.seed, b.mass.clamp(1e-4 * m, m)))
            .collect();
        let near_own = |s: &Seed| own.iter().any(|(o, _)| (o.frequency / s.frequency - 1.0).abs() < 0.1);
        // (seed, mass, whether its release is refitted)
        let starts: Vec<(Seed, f64, bool)> = own
            .iter()
            .map(|&(seed, mass)| (seed, mass, !forced))
            .chain(seeds.iter().filter(|s| !near_own(s)).map(|s| (*s, APPENDAGE_START_MASS * m, !forced)))
            // (The scan's bodies are a forced record's, the stiff start free decay's.)
            .chain(stiff.map(|s| (s, APPENDAGE_START_MASS * m, false)))
            .collect();
        let release = format!("appendage_release_{c}");
        for &(ref seed, mass, released) in &starts {
            let (zeta, (low, high)) = (seed.damping, seed.range);
            let located = Located {
                name: format!("appendage_frequency_{c}"),
                limits: seed.limits,
                prefix: format!("unmodeled_mode({c}, "),
                damping: format!("appendage_damping_{c}"),
                pole: Pole::Body,
            };
            let at = |f: f64| Effect::Appendage {
                coordinate: c.clone(),
                mass,
                frequency_hz: f,
                damping_ratio: zeta.clamp(0.005, 0.15),
                release_force: (!forced).then_some(0.0),
            };
            let mut bounds = vec![
                (format!("appendage_mass_{c}"), (1e-4 * m, m)),
                (located.name.clone(), (low, high)),
                (located.damping.clone(), (0.0, 0.2)),
            ];
            let mut strength = vec![format!("appendage_mass_{c}")];
            if released {
                bounds.push((release.clone(), (-k * q, k * q)));
                strength.push(release.clone());
            }
            let mut t = trial(
                at(seed.frequency),
                located.label(seed.frequency),
                bounds,
                vec![Strength::Largest(strength)],
                outputs,
            )
            .or_from_other_starts(seed, at);
            // A relaxed start holds its release at 0.
            t.freed.retain(|n| released || *n != release);
            t.located = Some(located);
            out.push(t);
        }
    }
    out
}
