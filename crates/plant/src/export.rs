//! JSON export of the assembled matrices, to carry the model to other tools.

use crate::{PlantError, SlewingModel};
use faer::Mat;
use serde_json::{Value, json};

fn rows(m: &Mat<f64>) -> Value {
    Value::Array(
        (0..m.nrows()).map(|i| json!((0..m.ncols()).map(|j| m[(i, j)]).collect::<Vec<_>>())).collect(),
    )
}

impl SlewingModel {
    /// `{"name", "states", "outputs", "M", "D", "K", "B", "A", "C", "x0"}` with matrices as
    /// arrays of rows; states are [θ, q_1..q_n, θ̇, q̇_1..q̇_n], then the effects' states
    /// (`eta`, `theta_m` among the coordinates; `delay_w`, `lag_w_<output>` after the rates).
    ///
    /// # Errors
    /// As [`SlewingModel::state_space`].
    pub fn matrices_json(&self) -> Result<Value, PlantError> {
        let ss = self.state_space()?;
        let layout = self.layout();
        let n = self.n_modes();
        let mut coordinates = vec!["theta".to_string()];
        coordinates.extend((1..=n).map(|i| format!("q{i}")));
        if layout.extra_mode.is_some() {
            coordinates.push("eta".into());
        }
        if layout.motor.is_some() {
            coordinates.push("theta_m".into());
        }
        let mut states = coordinates.clone();
        states.extend(coordinates.iter().map(|c| format!("{c}_dot")));
        if layout.delay.is_some() {
            states.push("delay_w".into());
        }
        // The lag states follow, in the order the layout numbered them.
        let mut lags: Vec<(usize, crate::Sensor)> =
            crate::Sensor::ALL.into_iter().filter_map(|s| Some((layout.lags[s.index()]?, s))).collect();
        lags.sort_unstable_by_key(|(w, _)| *w);
        states.extend(lags.into_iter().map(|(_, s)| format!("lag_w_{}", s.output_name())));
        Ok(json!({
            "name": self.file().name,
            "states": states,
            "outputs": self.output_names(),
            "M": rows(&ss.m),
            "D": rows(&ss.d),
            "K": rows(&ss.k),
            "B": rows(&ss.b),
            "A": rows(&ss.a),
            "C": rows(&ss.c),
            "x0": ss.x0,
        }))
    }
}
