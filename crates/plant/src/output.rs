//! The output matrix C: each sensor's reading, or a lagged sensor's Padé reading.

use crate::Constants;
use crate::assemble::{Layout, Scalar, SecondOrder, reading};
use crate::sensors::Sensor;
use nalgebra::DMatrix;

/// C (p × n_states): each sensor's [`reading`], or for a sensor read late
/// ([`crate::Effect::SensorLag`]) −y + w_s, the Padé(1,1) of its delayed reading. The strain
/// row depends on the mode shapes, hence on the parameters, so C is generic like A.
pub fn output_matrix<D: Scalar>(c: &Constants<D>, so: &SecondOrder<D>, sensors: &[Sensor]) -> DMatrix<D> {
    let layout = Layout::of(c);
    let mut out = DMatrix::from_element(sensors.len(), layout.n_states, D::from(0.0));
    for (row, sensor) in sensors.iter().enumerate() {
        let y = reading(c, so, &layout, *sensor);
        let lag = layout.lags[sensor.index()];
        for (j, value) in y.into_iter().enumerate() {
            out[(row, j)] = if lag.is_some() { -value } else { value };
        }
        if let Some(w) = lag {
            out[(row, w)] = D::from(1.0);
        }
    }
    out
}
