//! A model file (RON) of either kind: parsing and validation must answer Ok or a located error,
//! never panic; a file that parses must export its modes (finite) and matrices, write itself back as a
//! file that parses to the same parameters, and simulate a short free decay without a panic —
//! also after one parameter is set to an extreme value, as `--set` would.
#![no_main]

use libfuzzer_sys::fuzz_target;
use models::Model;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(model) = Model::from_ron(text, "fuzz.ron") else { return };
    let names = model.parameter_names();
    if let Ok(modes) = model.modes() {
        for m in &modes {
            let numbers = [m.frequency_hz, m.damping_ratio, m.eigenvalue.0, m.eigenvalue.1];
            assert!(numbers.iter().all(|v| v.is_finite()), "mode {} of a valid model: {numbers:?}", m.kind);
        }
    }
    let _ = model.matrices_json();
    let written = model.to_ron();
    let again = Model::from_ron(&written, "written.ron")
        .unwrap_or_else(|e| panic!("a parsed model's own file does not parse: {e}\n{written}"));
    assert_eq!(names, again.parameter_names(), "the written file changed the parameters");
    for name in &names {
        let (a, b) = (model.value(name).unwrap(), again.value(name).unwrap());
        assert!(a == b || (a.is_nan() && b.is_nan()), "{name}: {a} written back as {b}");
    }
    if model.input_names().is_empty() {
        let _ = model.simulate(&mem::Grid::free(0.01), 16);
    }
    // `--set NAME=VALUE` with an extreme value: refused, or a model whose modes are finite and
    // whose free decay simulates or reports a non-finite response.
    if let (Some(&last), false) = (data.last(), names.is_empty()) {
        const EXTREMES: [f64; 8] = [0.0, -0.0, 1e-300, -1e-300, 1e300, -1e300, 1e15, -1.0];
        let mut changed = model.clone();
        let name = &names[usize::from(last) % names.len()];
        if changed.set(name, EXTREMES[usize::from(last / 32) % EXTREMES.len()]).is_ok() {
            if let Ok(modes) = changed.modes() {
                assert!(modes.iter().all(|m| m.frequency_hz.is_finite() && m.damping_ratio.is_finite()));
            }
            if changed.input_names().is_empty() {
                let _ = changed.simulate(&mem::Grid::free(0.01), 16);
            }
        }
    }
});
