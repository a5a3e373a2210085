//! Helpers shared by the structure-effect tests: a fixture file with effects added, a response
//! on a free grid, and a sensitivity column held to central differences.

use expm::Response;
use mem::{Grid, ResponseModel};
use models::Model;

/// The model file `file` with `effects` added to it.
pub fn with_effects_in(file: &str, effects: &str) -> Model {
    let text = file.trim_end().trim_end_matches(')').to_string() + &format!("    effects: [{effects}],\n)\n");
    Model::from_ron(&text, "building.ron").expect("the file reads")
}

/// The response with sensitivities at `p`, `k` samples at interval `h` from the release.
pub fn respond(model: &dyn ResponseModel, p: &[f64], k: usize, h: f64) -> Response {
    let mut out = Response::zeros(k, model.output_names().len(), model.n_params());
    model.respond(p, &Grid::free(h), &mut out).expect("it simulates");
    out
}

/// Holds sensitivity column `i` of `out` (the response at `p`, two outputs) to central
/// differences of the response with relative step 10⁻⁵, within `tolerance` of the column's scale.
pub fn assert_central_differences(
    response: &dyn ResponseModel,
    p: &[f64],
    out: &Response,
    i: usize,
    h: f64,
    tolerance: f64,
) {
    let k = out.outputs.nrows();
    let step = 1e-5 * p[i].abs();
    let shifted = |s: f64| {
        let mut q = p.to_vec();
        q[i] += s;
        respond(response, &q, k, h).outputs
    };
    let (plus, minus) = (shifted(step), shifted(-step));
    let scale = (0..k * 2).map(|r| out.sensitivities[(r, i)].abs()).fold(0.0, f64::max);
    assert!(scale > 0.0, "sensitivity {i} is zero");
    for s in 0..k {
        for o in 0..2 {
            let fd = (plus[(s, o)] - minus[(s, o)]) / (2.0 * step);
            let exact = out.sensitivities[(s * 2 + o, i)];
            assert!(
                (fd - exact).abs() < tolerance * scale,
                "sensitivity {i} at sample {s}, output {o}: {exact:e} vs {fd:e}"
            );
        }
    }
}
