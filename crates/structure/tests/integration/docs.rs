//! The model file shown in the crate documentation reads as a valid model.

use structure::StructureModel;

#[test]
fn the_documented_model_file_is_valid() {
    let lib = include_str!("../../src/lib.rs");
    let start = lib.find("//! ```ron\n").expect("a ron example") + "//! ```ron\n".len();
    let end = start + lib[start..].find("//! ```\n").expect("its end");
    let text: String = lib[start..end]
        .lines()
        .map(|l| l.strip_prefix("//!").unwrap_or(l).trim_start_matches(' '))
        .map(|l| format!("{l}\n"))
        .collect();
    let model = StructureModel::from_ron(&text, "lib.rs").unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(model.output_names(), ["a2", "drift"]);
    assert_eq!(model.input_names(), ["u"]);
    assert_eq!(model.free(), ["k1", "k2", "zeta"]);
    let modes = model.modes().unwrap();
    assert!(modes.iter().all(|m| (m.damping_ratio - 0.02).abs() < 1e-12));
    let first = r#"(
        name: "first order", parameters: {"k": (value: 4), "c": (value: 0.2), "g": (value: 2), "d": (value: 0.1)},
        structure: FirstOrder(states: ["x1", "x2"], a: [[0, 1], ["-k", "-c"]], b: [[0], [1]], inputs: [(name: "u", unit: "V")]),
        outputs: [(column: "y", measures: Row([1, "g"]), feedthrough: ["d"])],
        initial: (state: [1, 0]),
    )"#;
    StructureModel::from_ron(first, "lib.rs").unwrap();
}
