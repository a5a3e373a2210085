//! Parameter uncertainty that says what the data support.
//!
//! * **Covariance** of the least-squares estimate, as a sandwich over the free parameters:
//!   Cov = G ᵀ Ω G with G = S(SᵀS)⁺ from the SVD of S ((SᵀS)⁻¹ is never formed) and Ω
//!   block-diagonal over the output series (one output of one experiment): σ_s² I for
//!   independent errors, σ_s² ρ_s^{|k−l|} for an AR(1) process. With equal σ_s and ρ = 0 this
//!   is σ̂²(SᵀS)⁺. σ_s² = ‖r_s‖²/n_s·m/(m − rank) (the degrees of freedom shared out), ρ_s the
//!   series' lag-one autocorrelation. Ω g is applied in O(n) by a forward and a backward pass.
//! * **Intervals**: P ± t_{0.975, m−rank}·σ for a determined parameter; **none** for a
//!   parameter in an undetermined combination (its standard error is infinite: `None`), also
//!   when it rests on a bound; for a determined parameter held on a bound, a **one-sided** 95 %
//!   profile-likelihood interval from the bound into the box, from the linearised profile
//!   Δ(d) = −2g d + e d² (g = s_iᵀr, e = ‖(I − H)s_i‖², H the projection on the other free
//!   columns) against σ̂²·χ²₁(0.90) = σ̂²·2.706 (the boundary case's ½χ²₀ + ½χ²₁ law); **none**
//!   for a parameter with finite bounds whose interval, symmetric or one-sided, would hold all
//!   of its box ([`spans_bounds`]: the data do not narrow it beyond its bounds).
//! * **Conditional standard errors**: σ²_i|H = Σ_ii − Σ_iH Σ_HH⁻¹ Σ_Hi, parameter i's variance
//!   with the parameters H fixed at their estimates (a Schur complement; for independent errors,
//!   to first order the variance a fit without H free would report; under the AR(1) sandwich
//!   the conditional variance of the same estimate). A parameter held on a bound is conditioned on
//!   through its local row, which the reported covariance blanks and
//!   [`Statistics::local_covariance`] keeps.

use super::Side;
use crate::evaluate::{Evaluation, RowLayout};
use crate::fit::settings::{Covariance, Fit, columns};
use crate::solve::StepSolver;
use crate::stats::{lag_one, ljung_box, t_quantile_975};
use crate::{MemError, Problem};
use faer::Mat;
use faer::linalg::solvers::Solve;
use serde::Serialize;

/// Ljung–Box p-value below which a residual series counts as correlated.
pub(crate) const WHITENESS_LEVEL: f64 = 0.01;
/// χ²₁ at 0.90: the 95 % one-sided profile-likelihood threshold at a boundary.
const ONE_SIDED_95: f64 = 2.705_543_454_095_404;

/// A parameter's 95 % interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Interval {
    /// P ± t·σ.
    Symmetric {
        /// Lower end.
        lower: f64,
        /// Upper end.
        upper: f64,
    },
    /// From a bound the parameter is held on into the box.
    OneSided {
        /// Lower end.
        lower: f64,
        /// Upper end.
        upper: f64,
    },
    /// The data do not determine the parameter: no interval.
    Undetermined,
}

impl Interval {
    /// Whether `value` lies in the interval (never, when undetermined).
    pub fn contains(&self, value: f64) -> bool {
        match self {
            Interval::Symmetric { lower, upper } | Interval::OneSided { lower, upper } => {
                *lower <= value && value <= *upper
            }
            Interval::Undetermined => false,
        }
    }
}

/// Whether the interval [`lower`, `upper`] holds all of the parameter's box, both of whose bounds
/// are finite: then the data narrow it no further than its bounds do, and no interval is told.
///
/// The rank test ([`super::identifiability`]) is scale-free: it finds a combination the data
/// cannot tell from the others, not one they cannot resolve against the noise. Where every
/// column of S is small beside the noise — a record far too short or too coarse for the
/// model's dynamics — each parameter is resolved as well as the others, and its interval is
/// the noise over a tiny sensitivity: ±10⁵⁰ on a stiffness bounded to [0, 10¹⁰].
pub(crate) fn spans_bounds(parameter: &crate::Parameter, lower: f64, upper: f64) -> bool {
    parameter.lower.is_finite()
        && parameter.upper.is_finite()
        && lower <= parameter.lower
        && upper >= parameter.upper
}

/// The noise of one output series as the residuals show it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SeriesNoise {
    /// Experiment index.
    pub experiment: usize,
    /// Output name.
    pub output: String,
    /// σ_s of the weighted residual.
    pub sigma: f64,
    /// Lag-one autocorrelation.
    pub rho: f64,
    /// Ljung–Box p-value (lags 1–20).
    pub p_value: f64,
}

/// Parameter uncertainty from the final S and the residuals.
#[derive(Clone, Debug, Serialize)]
pub struct Statistics {
    /// The covariance that was used (White or Ar1; Auto is resolved).
    pub covariance_kind: Covariance,
    /// σ̂² = ‖E‖²/(m − rank).
    pub residual_variance: f64,
    /// Degrees of freedom m − rank.
    pub degrees_of_freedom: usize,
    /// The covariance (j × j; rows and columns of undetermined or bound parameters are NaN).
    #[serde(serialize_with = "matrix")]
    pub covariance: Mat<f64>,
    /// The same covariance with the rows and columns of parameters held on a bound, or whose
    /// interval would hold all of their box, kept: their local, linearised
    /// uncertainty as if they were free and unbounded (NaN only where a combination is
    /// undetermined). Not an interval for them (a bound parameter's is one-sided); it is what a
    /// test that holds such a parameter at its estimate conditions on
    /// ([`Statistics::conditional_std_error`]), and what a caller that weighs a parameter inside a
    /// range it chose itself reads ([`Statistics::local_std_error`]).
    #[serde(skip)]
    pub local_covariance: Mat<f64>,
    /// √diag(covariance); None where the data do not determine the parameter or it is held on
    /// a bound.
    pub std_errors: Vec<Option<f64>>,
    /// 95 % intervals.
    pub intervals: Vec<Interval>,
    /// Correlation matrix (NaN where undefined).
    #[serde(serialize_with = "matrix")]
    pub correlation: Mat<f64>,
    /// The noise of each output series.
    pub series: Vec<SeriesNoise>,
}

fn matrix<S: serde::Serializer>(m: &Mat<f64>, serializer: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeSeq;
    let mut seq = serializer.serialize_seq(Some(m.nrows()))?;
    for i in 0..m.nrows() {
        let row: Vec<Option<f64>> =
            (0..m.ncols()).map(|j| Some(m[(i, j)]).filter(|v| v.is_finite())).collect();
        seq.serialize_element(&row)?;
    }
    seq.end()
}

/// y = R(ρ) g for R_kl = ρ^{|k−l|}: forward and backward exponential sums, O(n).
fn ar1_apply(g: &[f64], rho: f64) -> Vec<f64> {
    let n = g.len();
    let mut forward = vec![0.0; n];
    let mut backward = vec![0.0; n];
    for k in 0..n {
        forward[k] = g[k] + if k > 0 { rho * forward[k - 1] } else { 0.0 };
    }
    for k in (0..n).rev() {
        backward[k] = g[k] + if k + 1 < n { rho * backward[k + 1] } else { 0.0 };
    }
    (0..n).map(|k| forward[k] + backward[k] - g[k]).collect()
}

/// What [`analyse`] finds at the final point.
pub(crate) struct Analysed {
    /// The parameters' uncertainty.
    pub statistics: Statistics,
    /// The noise of each output series.
    pub series: Vec<SeriesNoise>,
    /// The parameters whose interval would hold all of their bounds ([`spans_bounds`]), with
    /// that interval's half width (a one-sided interval's whole width).
    pub spanning: Vec<(usize, f64)>,
}

/// The statistics of the final point ([`Analysed`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn analyse(
    fit: &Fit,
    problem: &Problem<'_>,
    p: &[f64],
    last: &Evaluation,
    layout: &RowLayout,
    free: &[usize],
    solver: Option<&StepSolver>,
    on_bound: &[Option<Side>],
    undetermined: &[bool],
) -> Result<Analysed, MemError> {
    let j = p.len();
    let m = last.residual.len();
    let rank = solver.map_or(0, |s| s.rank);
    let dof = m.saturating_sub(rank);
    let variance = if dof > 0 { last.cost / dof as f64 } else { f64::NAN };
    let share = if dof > 0 { m as f64 / dof as f64 } else { f64::NAN };
    let series: Vec<(usize, usize, Vec<usize>)> = layout.series().collect();
    let mut noise: Vec<SeriesNoise> = series
        .iter()
        .map(|(e, o, rows)| {
            let r: Vec<f64> = rows.iter().map(|&k| last.residual[k]).collect();
            let power = r.iter().map(|v| v * v).sum::<f64>();
            SeriesNoise {
                experiment: *e,
                output: problem.experiments[*e].data.names()[*o].clone(),
                sigma: (power / r.len().max(1) as f64 * share).sqrt(),
                rho: lag_one(&r),
                p_value: ljung_box(&r, 20.min(r.len() / 5)).1,
            }
        })
        .collect();
    let kind = match fit.covariance {
        Covariance::Auto if noise.iter().any(|s| s.p_value < WHITENESS_LEVEL) => Covariance::Ar1,
        Covariance::Auto => Covariance::White,
        other => other,
    };
    if kind == Covariance::White {
        noise.iter_mut().for_each(|s| s.rho = s.rho.min(0.99));
    }
    let mut covariance = Mat::<f64>::from_fn(j, j, |_, _| f64::NAN);
    if let Some(solver) = solver {
        // (SᵀS)⁺ over the kept, determined directions: D⁻¹ V Σ⁻² Vᵀ D⁻¹.
        let cutoff = fit.identifiability_threshold.max(fit.rank_cutoff)
            * solver.singular_values.first().copied().unwrap_or(0.0);
        let kept: Vec<usize> = (0..solver.rank).filter(|&d| solver.singular_values[d] > cutoff).collect();
        let f = free.len();
        let pinv = Mat::from_fn(f, f, |a, b| {
            let sum: f64 = kept
                .iter()
                .map(|&d| solver.v[(a, d)] * solver.v[(b, d)] / solver.singular_values[d].powi(2))
                .sum();
            sum / (solver.scale[a] * solver.scale[b])
        });
        let s_free = columns(&last.sensitivity, free);
        let g = &s_free * &pinv; // m × f
        let mut inner = Mat::<f64>::zeros(f, f);
        for ((_, _, rows), s) in series.iter().zip(&noise) {
            let rho = if kind == Covariance::Ar1 { s.rho } else { 0.0 };
            let blocks: Vec<Vec<f64>> = (0..f).map(|a| rows.iter().map(|&k| g[(k, a)]).collect()).collect();
            let applied: Vec<Vec<f64>> =
                blocks.iter().map(|b| if rho == 0.0 { b.clone() } else { ar1_apply(b, rho) }).collect();
            for a in 0..f {
                for b in 0..f {
                    let v: f64 = blocks[a].iter().zip(&applied[b]).map(|(x, y)| x * y).sum();
                    inner[(a, b)] += s.sigma * s.sigma * v;
                }
            }
        }
        for (a, &ia) in free.iter().enumerate() {
            for (b, &ib) in free.iter().enumerate() {
                covariance[(ia, ib)] = inner[(a, b)];
            }
        }
    }
    let t = t_quantile_975(dof);
    let mut std_errors = Vec::with_capacity(j);
    let mut intervals = Vec::with_capacity(j);
    let mut spanning = Vec::new();
    for i in 0..j {
        if undetermined[i] {
            // Also on a bound: the profile is flat along the combination, so a one-sided
            // interval would run from the bound to wherever the box ends.
            std_errors.push(None);
            intervals.push(Interval::Undetermined);
        } else if let Some(side) = on_bound[i] {
            std_errors.push(None);
            let others: Vec<usize> = free.iter().copied().filter(|&l| l != i).collect();
            match one_sided(last, &others, i, side, p[i], variance, fit.rank_cutoff)? {
                Interval::OneSided { lower, upper } if spans_bounds(&problem.parameters[i], lower, upper) => {
                    spanning.push((i, upper - lower));
                    intervals.push(Interval::Undetermined);
                }
                interval => intervals.push(interval),
            }
        } else if !covariance[(i, i)].is_finite() {
            std_errors.push(None);
            intervals.push(Interval::Undetermined);
        } else {
            let se = covariance[(i, i)].max(0.0).sqrt();
            let (lower, upper) = (p[i] - t * se, p[i] + t * se);
            if spans_bounds(&problem.parameters[i], lower, upper) {
                spanning.push((i, t * se));
                std_errors.push(None);
                intervals.push(Interval::Undetermined);
            } else {
                std_errors.push(Some(se));
                intervals.push(Interval::Symmetric { lower, upper });
            }
        }
    }
    let blank = |m: &mut Mat<f64>, i: usize| {
        for l in 0..j {
            m[(i, l)] = f64::NAN;
            m[(l, i)] = f64::NAN;
        }
    };
    let mut local_covariance = covariance.clone();
    for i in 0..j {
        let local = covariance[(i, i)];
        // Held on a bound, or resolved no better than its box: a local uncertainty all the same.
        let kept_locally = (on_bound[i].is_some() || spanning.iter().any(|&(s, _)| s == i))
            && !undetermined[i]
            && local.is_finite()
            && local > 0.0;
        if std_errors[i].is_none() {
            blank(&mut covariance, i);
            if !kept_locally {
                blank(&mut local_covariance, i);
            }
        }
    }
    let correlation = Mat::from_fn(j, j, |a, b| match (std_errors[a], std_errors[b]) {
        (Some(x), Some(y)) if x > 0.0 && y > 0.0 => covariance[(a, b)] / (x * y),
        (Some(_), Some(_)) if a == b => 1.0,
        _ => f64::NAN,
    });
    let statistics = Statistics {
        covariance_kind: kind,
        residual_variance: variance,
        degrees_of_freedom: dof,
        covariance,
        local_covariance,
        std_errors,
        intervals,
        correlation,
        series: noise.clone(),
    };
    Ok(Analysed { statistics, series: noise, spanning })
}

impl Statistics {
    /// Parameter i's local standard error, √ of [`Statistics::local_covariance`]'s diagonal:
    /// also where it is held on a bound or its interval would hold all of its box (and then it
    /// is not an interval); `None` where a combination it is in is undetermined.
    pub fn local_std_error(&self, i: usize) -> Option<f64> {
        let variance = self.local_covariance[(i, i)];
        variance.is_finite().then(|| variance.max(0.0).sqrt())
    }

    /// The standard error of a quantity derived from the parameters, whose gradient over them is
    /// `gradient` (one entry per parameter): √(gᵀΣg), the delta method over [`Statistics::covariance`].
    /// None where a parameter it depends on (gᵢ ≠ 0) has no determined covariance (undetermined
    /// or held on a bound), where `gradient` has another length, or where the variance is not
    /// positive.
    pub fn std_error_of(&self, gradient: &[f64]) -> Option<f64> {
        let cov = &self.covariance;
        if gradient.len() != cov.nrows() || gradient.len() != cov.ncols() {
            return None;
        }
        let used: Vec<usize> = (0..gradient.len()).filter(|&j| gradient[j] != 0.0).collect();
        let mut variance = 0.0;
        for &a in &used {
            for &b in &used {
                let c = cov[(a, b)];
                if !c.is_finite() {
                    return None;
                }
                variance += gradient[a] * c * gradient[b];
            }
        }
        (variance > 0.0).then(|| variance.sqrt())
    }

    /// The standard error of parameter `i` with the parameters `held` fixed at their estimates:
    /// σ²_i|H = Σ_ii − Σ_iH Σ_HH⁻¹ Σ_Hi, a Schur complement of the covariance (for independent
    /// errors, to first order the variance of a fit in which H were not free). A held parameter on a bound is
    /// conditioned on through its local row ([`Statistics::local_covariance`]): holding it at
    /// the bound is what the fit did. Undetermined held parameters are left out (their rows carry
    /// no information). None where `i` itself has no standard error.
    pub fn conditional_std_error(&self, i: usize, held: &[usize]) -> Option<f64> {
        let se = self.std_errors.get(i).copied().flatten()?;
        let cov = &self.local_covariance;
        let usable = |h: usize| h != i && h < cov.nrows() && cov[(h, h)].is_finite() && cov[(h, h)] > 0.0;
        let held: Vec<usize> = held.iter().copied().filter(|&h| usable(h)).collect();
        if held.is_empty() {
            return Some(se);
        }
        let k = held.len();
        let hh = Mat::<f64>::from_fn(k, k, |a, b| cov[(held[a], held[b])]);
        let hi = Mat::<f64>::from_fn(k, 1, |a, _| cov[(held[a], i)]);
        if (0..k).any(|a| !hi[(a, 0)].is_finite() || (0..k).any(|b| !hh[(a, b)].is_finite())) {
            return Some(se);
        }
        let x = hh.partial_piv_lu().solve(&hi);
        let explained: f64 = (0..k).map(|a| hi[(a, 0)] * x[(a, 0)]).sum();
        let conditional = se * se - explained;
        if explained.is_finite() && conditional > 0.0 { Some(conditional.sqrt()) } else { Some(se) }
    }
}

/// ‖(I − H)s_i‖², s_iᵀr for the column i against the free columns.
fn profile_terms(last: &Evaluation, free: &[usize], i: usize, cutoff: f64) -> Result<(f64, f64), MemError> {
    let s_i: Vec<f64> = (0..last.sensitivity.nrows()).map(|k| last.sensitivity[(k, i)]).collect();
    let power: f64 = s_i.iter().map(|v| v * v).sum();
    let g: f64 = s_i.iter().zip(&last.residual).map(|(a, b)| a * b).sum();
    if free.is_empty() {
        return Ok((power, g));
    }
    let explained = StepSolver::from_owned(columns(&last.sensitivity, free), &s_i, cutoff)?.step(0.0).1;
    Ok(((power - explained).max(0.0), g))
}

/// The one-sided interval of a parameter held on a bound (module docs).
fn one_sided(
    last: &Evaluation,
    free: &[usize],
    i: usize,
    side: Side,
    bound: f64,
    variance: f64,
    cutoff: f64,
) -> Result<Interval, MemError> {
    let (e, g) = profile_terms(last, free, i, cutoff)?;
    // Moving d into the box (d > 0): Δ = 2|g| d + e d² (the data pull outward, so the linear
    // term raises the cost inward).
    let a = 2.0 * g.abs();
    let threshold = ONE_SIDED_95 * variance;
    let d = one_sided_width(a, e, threshold);
    Ok(match side {
        Side::Lower => Interval::OneSided { lower: bound, upper: bound + d },
        Side::Upper => Interval::OneSided { lower: bound - d, upper: bound },
    })
}

/// The positive root d of e d² + a d = threshold (a, threshold ≥ 0), rationalised as
/// 2·threshold/(a + √(a² + 4 e threshold)): no cancellation for a small e, 0 (not NaN) when the
/// slope overflows or the threshold is 0 (a perfect fit), ∞ when neither term grows.
fn one_sided_width(a: f64, e: f64, threshold: f64) -> f64 {
    let denominator = a + (a * a + 4.0 * e.max(0.0) * threshold).sqrt();
    if denominator > 0.0 {
        2.0 * threshold / denominator
    } else if e > 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// The fraction of the error the linear model predicts would go if parameter i (held on a
/// bound) were freed along with the free ones.
pub(crate) fn release_gain(
    last: &Evaluation,
    free: &[usize],
    i: usize,
    cutoff: f64,
) -> Result<f64, MemError> {
    let mut with = free.to_vec();
    with.push(i);
    with.sort_unstable();
    let released =
        StepSolver::from_owned(columns(&last.sensitivity, &with), &last.residual, cutoff)?.step(0.0).1;
    let held = if free.is_empty() {
        0.0
    } else {
        StepSolver::from_owned(columns(&last.sensitivity, free), &last.residual, cutoff)?.step(0.0).1
    };
    Ok(if last.cost > 0.0 { ((released - held) / last.cost).clamp(0.0, 1.0) } else { 0.0 })
}

#[cfg(test)]
mod tests {
    use super::one_sided_width;

    /// Against the textbook root (−a + √(a² + 4et))/(2e) where it is well conditioned, and the
    /// limits where it is not.
    #[test]
    fn one_sided_width_is_the_positive_root_and_never_nan() {
        for (a, e, t) in [(1.0f64, 2.0, 3.0), (0.5, 1e-3, 2.7), (0.0, 4.0, 2.7)] {
            let textbook = (-a + (a * a + 4.0 * e * t).sqrt()) / (2.0 * e);
            assert!((one_sided_width(a, e, t) / textbook - 1.0).abs() < 1e-12, "{a} {e} {t}");
        }
        assert!((one_sided_width(2.0, 0.0, 3.0) - 1.5).abs() < 1e-15, "linear: t/a");
        assert_eq!(one_sided_width(f64::INFINITY, 1.0, 2.7), 0.0, "an overflowing slope");
        assert_eq!(one_sided_width(0.0, 1.0, 0.0), 0.0, "a perfect fit");
        assert_eq!(one_sided_width(0.0, 0.0, 2.7), f64::INFINITY, "nothing grows");
        assert_eq!(one_sided_width(0.0, 0.0, 0.0), f64::INFINITY, "nothing grows, perfect fit");
    }
}
