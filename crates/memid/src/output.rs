//! Tables for the terminal and JSON documents (fields documented in docs/json.md).

use mem::FitReport;
use models::FitOutcome;
use models::ModeRow;
use serde_json::{Value, json};

/// A fit as JSON: the report's own fields (docs/json.md), with a per-parameter summary and the
/// warnings in words.
pub fn fit_json(outcome: &FitOutcome) -> Value {
    let r = &outcome.report;
    let s = &r.statistics;
    let parameters: Vec<Value> = (0..r.parameters.len())
        .map(|i| {
            let ci95 = match s.intervals[i] {
                mem::Interval::Symmetric { lower, upper } => json!([lower, upper]),
                _ => Value::Null,
            };
            json!({
                "name": r.names[i],
                "initial": r.initial[i],
                "final": r.parameters[i],
                "change": r.parameters[i] - r.initial[i],
                "std_error": s.std_errors[i],
                "ci95": ci95,
                "interval": s.intervals[i],
                "on_bound": r.on_bound[i],
            })
        })
        .collect();
    let mut document = serde_json::to_value(r).unwrap_or(Value::Null);
    if let Value::Object(map) = &mut document {
        // `parameters` is the per-parameter table (docs/json.md); the bare vectors are in it.
        for redundant in ["names", "initial", "parameters", "on_bound"] {
            map.remove(redundant);
        }
        map.insert("parameters".into(), json!(parameters));

        map.insert(
            "singular_values".into(),
            json!(r.records.last().map(|rec| rec.singular_values.clone()).unwrap_or_default()),
        );
        map.insert(
            "warnings".into(),
            json!(
                r.warnings
                    .iter()
                    .map(|w| {
                        let mut v = serde_json::to_value(w).unwrap_or(Value::Null);
                        if let Value::Object(m) = &mut v {
                            m.insert("message".into(), json!(w.to_string()));
                        }
                        v
                    })
                    .collect::<Vec<_>>()
            ),
        );
        // The records are in the report; the per-iteration parameters are rarely wanted in JSON.
        map.remove("records");
    }
    document
}

/// Modal rows as JSON.
pub fn modal_json(rows: &[ModeRow]) -> Value {
    json!({ "modes": rows.iter().map(|r| {
        let mut v = json!({
            "kind": r.kind,
            "frequency_hz": r.frequency_hz,
            "damping_ratio": r.damping_ratio,
            "eigenvalue": [r.eigenvalue.0, r.eigenvalue.1],
        });
        if let Some(shape) = &r.shape {
            v["shape"] = json!(shape);
        }
        v
    }).collect::<Vec<_>>() })
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

/// The fit table in the spirit of the paper's Table 1 (the report's own summary).
pub fn fit_table(r: &FitReport) -> String {
    r.to_string()
}

/// Modes as a table (Table 2's columns; the mode shape over the coordinates for a structure).
pub fn modal_table(rows: &[ModeRow], coordinates: &[String]) -> String {
    let shapes = rows.iter().any(|r| r.shape.is_some());
    let mut out = format!("{:<12} {:>14} {:>14}", "mode", "frequency Hz", "damping %");
    if shapes {
        out += &format!("   shape ({})", coordinates.join(", "));
    }
    out += "\n";
    for r in rows {
        out += &format!("{:<12} {:>14.4} {:>14.2}", r.kind, r.frequency_hz, 100.0 * r.damping_ratio);
        if let Some(shape) = &r.shape {
            out +=
                &format!("   [{}]", shape.iter().map(|v| format!("{v:+.4}")).collect::<Vec<_>>().join(", "));
        }
        out += "\n";
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

/// Fails if JSON text holds a `null` where a number was written (serde_json writes NaN and
/// infinities as null): a non-finite result must be an error, never an output.
pub fn ensure_finite_json(text: &str, what: &str) -> anyhow::Result<()> {
    if text.contains("null") {
        anyhow::bail!("{what} hold non-finite values (an overflow); check the model's values");
    }
    Ok(())
}
