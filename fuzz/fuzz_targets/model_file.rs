//! A model file (RON) of either kind: parsing and validation must answer Ok or a located error,
//! never panic; a file that parses must export its modes (finite) and matrices, write itself back as a
//! file that parses to the same parameters, and simulate a short free decay without a panic.
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
});
