//! Tables for the terminal and JSON documents (fields documented in docs/json.md).

use discrepancy::FitOutcome;
use mem::{FitReport, Termination};
use plant::{ModalRow, ModeKind};
use serde_json::{Value, json};

/// The termination reason as a stable word.
pub fn termination(t: Termination) -> &'static str {
    match t {
        Termination::Converged => "converged",
        Termination::Stagnated => "stagnated",
        Termination::MaxIterations => "max_iterations",
        Termination::Diverged => "diverged",
    }
}

/// A fit as JSON.
pub fn fit_json(outcome: &FitOutcome, output_names: &[&str]) -> Value {
    let r = &outcome.report;
    let s = &r.statistics;
    let parameters: Vec<Value> = (0..r.parameters.len())
        .map(|i| {
            json!({
                "name": r.names[i],
                "initial": r.initial[i],
                "final": r.parameters[i],
                "change": r.parameters[i] - r.initial[i],
                "std_error": s.std_errors[i],
                "ci95": [s.ci95[i].0, s.ci95[i].1],
            })
        })
        .collect();
    let j = r.parameters.len();
    json!({
        "parameters": parameters,
        "error_history": r.error_history,
        "iterations": r.iterations,
        "termination": termination(r.termination),
        "n_residuals": r.n_residuals,
        "rank": r.rank,
        "rank_cutoff": r.rank_cutoff,
        "singular_values": r.records.last().map(|rec| rec.singular_values.clone()).unwrap_or_default(),
        "residual_variance": s.residual_variance,
        "degrees_of_freedom": s.degrees_of_freedom,
        "correlation": (0..j).map(|a| (0..j).map(|b| s.correlation[(a, b)]).collect::<Vec<_>>()).collect::<Vec<_>>(),
        "weights": output_names.iter().zip(&outcome.weights).map(|(n, w)| json!({"output": n, "weight": w})).collect::<Vec<_>>(),
        "identifiability": {
            "relative_singular_values": r.identifiability.relative_singular_values,
            "condition_number": finite_or_null(r.identifiability.condition_number),
            "undetermined": r.identifiability.undetermined.iter().map(|c| json!({
                "ratio": c.ratio, "direction": c.direction, "description": c.description,
            })).collect::<Vec<_>>(),
        },
        "derivative_check": r.derivative_check.as_ref().map(|d| json!({
            "worst_relative_mismatch": d.worst_relative_mismatch,
            "per_parameter": d.per_parameter,
        })),
    })
}

fn finite_or_null(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

/// Modal rows as JSON.
pub fn modal_json(rows: &[ModalRow]) -> Value {
    json!({ "modes": rows.iter().map(|r| json!({
        "kind": kind(r.kind),
        "frequency_hz": r.frequency_hz,
        "damping_ratio": r.damping_ratio,
        "eigenvalue": [r.eigenvalue.0, r.eigenvalue.1],
    })).collect::<Vec<_>>() })
}

/// ERA modes as JSON.
pub fn era_json(result: &era::EraResult) -> Value {
    json!({
        "order": result.order,
        "singular_values": result.singular_values.iter().take(2 * result.order + 4).collect::<Vec<_>>(),
        "modes": result.modes.iter().map(|m| json!({
            "frequency_hz": m.frequency_hz,
            "damping_ratio": m.damping_ratio,
            "consistency": m.consistency,
            "mpc": m.mpc,
            "contribution": m.contribution,
            "physical": m.physical,
        })).collect::<Vec<_>>(),
    })
}

/// "servo" or "flexible_<i>".
pub fn kind(k: ModeKind) -> String {
    match k {
        ModeKind::Servo => "servo".into(),
        ModeKind::Flexible(i) => format!("flexible_{i}"),
    }
}

/// The fit table in the spirit of the paper's Table 1.
pub fn fit_table(r: &FitReport) -> String {
    let mut out = format!(
        "{:<22} {:>13} {:>13} {:>13} {:>12}   {}\n",
        "parameter", "initial", "final", "ΔP", "std. error", "95 % interval"
    );
    for i in 0..r.parameters.len() {
        let (lo, hi) = r.statistics.ci95[i];
        out += &format!(
            "{:<22} {:>13.6} {:>13.6} {:>+13.6} {:>12.3e}   [{lo:.6}, {hi:.6}]\n",
            r.names[i],
            r.initial[i],
            r.parameters[i],
            r.parameters[i] - r.initial[i],
            r.statistics.std_errors[i]
        );
    }
    let (e0, e1) = r.error_change();
    out += &format!("{:<22} {:>13.6} {:>13.6}\n", "‖Y_error‖ (Eq. 22)", e0, e1);
    out += &format!(
        "iterations {}, termination {}, rank {}/{} (cutoff {:.0e} of σ_max)\n",
        r.iterations,
        termination(r.termination),
        r.rank,
        r.parameters.len(),
        r.rank_cutoff
    );
    if let Some(last) = r.records.last() {
        out += &format!(
            "singular values of the column-scaled S: {}\n",
            last.singular_values.iter().map(|s| format!("{s:.3e}")).collect::<Vec<_>>().join(", ")
        );
    }
    for c in &r.identifiability.undetermined {
        out += &format!(
            "not determined by the data: {} (relative singular value {:.1e})\n",
            c.description, c.ratio
        );
    }
    if let Some(d) = &r.derivative_check {
        out += &format!(
            "derivative check: worst relative mismatch of S vs central differences {:.2e}\n",
            d.worst_relative_mismatch
        );
    }
    out
}

/// Closed-loop modes as a table (Table 2's columns).
pub fn modal_table(rows: &[ModalRow]) -> String {
    let mut out = format!("{:<12} {:>14} {:>14}\n", "mode", "frequency Hz", "damping %");
    for r in rows {
        out += &format!("{:<12} {:>14.4} {:>14.2}\n", kind(r.kind), r.frequency_hz, 100.0 * r.damping_ratio);
    }
    out
}

/// ERA modes as a table.
pub fn era_table(result: &era::EraResult) -> String {
    let mut out = format!(
        "{:>12} {:>10} {:>12} {:>8} {:>13}  {}\n",
        "frequency Hz", "damping %", "consistency", "MPC", "contribution", "verdict"
    );
    for m in &result.modes {
        out += &format!(
            "{:>12.4} {:>10.2} {:>12.3} {:>8} {:>12.1}%  {}\n",
            m.frequency_hz,
            100.0 * m.damping_ratio,
            m.consistency,
            m.mpc.map_or("-".to_string(), |v| format!("{v:.3}")),
            100.0 * m.contribution,
            if m.physical { "physical" } else { "spurious" }
        );
    }
    out
}
