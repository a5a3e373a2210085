//! Sensor effects' parameters may stand anywhere in the free list: the response and every
//! sensitivity column follow the caller's order (a regression: they were once assumed last).

use expm::Response;
use mem::Grid;
use models::Model;
use plant::SlewingModel;

fn model() -> Model {
    let text = plant::PAPER_MODEL_RON.replace(
        "    bounds: {",
        "    effects: [OutputOffset(sensor: Potentiometer, offset: 0.01), \
         SensorScale(sensor: StrainGauge, scale: 0.05)],\n    bounds: {",
    );
    Model::Slewing(SlewingModel::from_ron(&text, "sensors.ron").unwrap())
}

fn respond(names: &[&str], p: &[f64]) -> Response {
    let response = model().response(names).unwrap();
    let mut out = Response::zeros(120, 3, names.len());
    response.respond(p, &Grid::free(1.0 / 12.8), &mut out).unwrap();
    out
}

#[test]
fn sensor_parameters_in_any_position_follow_the_callers_order() {
    let first = ["offset_theta", "cv", "scale_strain", "kp"];
    let p_first = [0.01, 0.06, 0.05, 8.0];
    let last = ["cv", "kp", "offset_theta", "scale_strain"];
    let p_last = [0.06, 8.0, 0.01, 0.05];
    let a = respond(&first, &p_first);
    let b = respond(&last, &p_last);
    assert_eq!(a.outputs, b.outputs);
    // Column i of `first` is column map[i] of `last`.
    let map = [2, 0, 3, 1];
    for (i, &j) in map.iter().enumerate() {
        for r in 0..a.sensitivities.nrows() {
            assert_eq!(a.sensitivities[(r, i)], b.sensitivities[(r, j)], "{} row {r}", first[i]);
        }
    }
    // And each column is the derivative of the outputs (central differences, the model is
    // linear so the exact path's sensitivities are exact to rounding).
    for i in 0..4 {
        let h = 1e-6 * p_first[i].abs().max(1e-3);
        let shifted = |sign: f64| {
            let mut q = p_first;
            q[i] += sign * h;
            respond(&first, &q)
        };
        let (plus, minus) = (shifted(1.0), shifted(-1.0));
        for k in 0..120 {
            for o in 0..3 {
                let fd = (plus.outputs[(k, o)] - minus.outputs[(k, o)]) / (2.0 * h);
                let exact = a.sensitivities[(k * 3 + o, i)];
                let scale =
                    (0..a.sensitivities.nrows()).map(|r| a.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
                assert!(
                    (fd - exact).abs() <= 1e-6 * scale,
                    "{} sample {k} output {o}: {fd} vs {exact}",
                    first[i]
                );
            }
        }
    }
}
