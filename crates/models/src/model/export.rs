//! What a model shows of itself: its modes (Table 2's columns, or a structure's modes with
//! their shapes) and its assembled matrices as JSON (`memid modal`, `memid model`).

use super::{ModeRow, Model};
use crate::ModelError;

impl Model {
    /// The closed-loop modes (slewing: servo and flexible modes, Table 2's columns) or the
    /// structure's modes with their shapes.
    ///
    /// # Errors
    /// Assembly failures; [`ModelError::NonFinite`] if a mode is not finite.
    pub fn modes(&self) -> Result<Vec<ModeRow>, ModelError> {
        let rows: Vec<ModeRow> = match self {
            Model::Slewing(m) => m
                .modal()?
                .into_iter()
                .map(|r| ModeRow {
                    kind: r.kind.name(),
                    frequency_hz: r.frequency_hz,
                    damping_ratio: r.damping_ratio,
                    eigenvalue: r.eigenvalue,
                    shape: None,
                })
                .collect(),
            Model::Structure(m) => m
                .modes()?
                .into_iter()
                .enumerate()
                .map(|(i, r)| ModeRow {
                    kind: format!("mode_{}", i + 1),
                    frequency_hz: r.frequency_hz,
                    damping_ratio: r.damping_ratio,
                    eigenvalue: r.eigenvalue,
                    shape: r.shape,
                })
                .collect(),
        };
        if let Some(r) = rows.iter().find(|r| !(r.frequency_hz.is_finite() && r.damping_ratio.is_finite())) {
            return Err(ModelError::NonFinite {
                what: format!("the {} mode ({} Hz)", r.kind, r.frequency_hz),
            });
        }
        Ok(rows)
    }

    /// The assembled matrices as JSON (`memid model`).
    ///
    /// # Errors
    /// Assembly failures; [`ModelError::NonFinite`] for a non-finite entry.
    pub fn matrices_json(&self) -> Result<serde_json::Value, ModelError> {
        let value = match self {
            Model::Slewing(m) => m.matrices_json()?,
            Model::Structure(m) => {
                let ss = m.state_space::<f64>(&m.values())?;
                let rows = |x: &mem::nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
                    (0..x.nrows()).map(|i| (0..x.ncols()).map(|j| x[(i, j)]).collect()).collect()
                };
                let mut doc = serde_json::json!({
                    "name": m.name(),
                    "kind": "structure",
                    "coordinates": m.coordinates(),
                    "outputs": m.output_names(),
                    "inputs": m.input_names(),
                    "A": rows(&ss.a),
                    "C": rows(&ss.c),
                    "x0": ss.x0.iter().copied().collect::<Vec<_>>(),
                });
                if let Some(b) = &ss.b {
                    doc["B"] = serde_json::json!(rows(b));
                }
                if let Some(d) = &ss.d {
                    doc["D"] = serde_json::json!(rows(d));
                }
                if let Some(so) = m.second_order::<f64>(&m.values())? {
                    doc["M"] = serde_json::json!(rows(&so.m));
                    doc["damping"] = serde_json::json!(rows(&so.d));
                    doc["K"] = serde_json::json!(rows(&so.k));
                }
                doc
            }
        };
        if serde_json::to_string(&value).is_ok_and(|t| t.contains("null")) {
            return Err(ModelError::NonFinite { what: "the assembled matrices".into() });
        }
        Ok(value)
    }
}
