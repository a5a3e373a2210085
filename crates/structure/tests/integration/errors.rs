//! Located errors: each is one line, `origin:line:column: …`, pointing at the offending
//! character (inside a string literal for expressions and names).

use crate::common::{fixture, fixture_text, position};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;
use structure::{ExprError, StructureError, StructureModel};

const ORIGIN: &str = "building.ron";

/// The shear-building fixture with `from` replaced by `to` (which must occur).
fn edited(from: &str, to: &str) -> String {
    let text = fixture_text("shear_building.ron");
    assert!(text.contains(from), "`{from}` not in the fixture");
    text.replacen(from, to, 1)
}

/// Reads `text`, expects an error at `within` inside the first `needle`, and returns it.
fn error_at(text: &str, needle: &str, within: &str) -> StructureError {
    let error = match StructureModel::from_ron(text, ORIGIN) {
        Ok(_) => panic!("expected an error at `{within}` in `{needle}`"),
        Err(e) => e,
    };
    let message = error.to_string();
    let (line, column) = position(text, needle, within);
    assert!(
        message.starts_with(&format!("{ORIGIN}:{line}:{column}: ")),
        "expected {line}:{column}, got: {message}"
    );
    assert!(!message.contains('\n'), "one line: {message}");
    error
}

#[test]
fn unknown_parameter_in_an_expression_points_at_the_name() {
    let text = edited(r#""k1 + k2""#, r#""k1 + k4""#);
    match error_at(&text, r#""k1 + k4""#, "k4") {
        StructureError::Expression { field, source: ExprError::UnknownName { name, .. }, .. } => {
            assert_eq!(field, "structure.stiffness[0][0]");
            assert_eq!(name, "k4");
        }
        other => panic!("{other:?}"),
    }
    let message = StructureModel::from_ron(&text, ORIGIN).unwrap_err().to_string();
    assert!(message.contains("known parameters: m1, m2, m3, k1, k2, k3, alpha, beta"), "{message}");
}

#[test]
fn bad_expression_points_at_the_token() {
    let text = edited(r#""k1 + k2""#, r#""k1 +* k2""#);
    assert!(matches!(
        error_at(&text, r#""k1 +* k2""#, "*"),
        StructureError::Expression { source: ExprError::Unexpected { .. }, .. }
    ));
    let text = edited(r#""-k3", "k3"]"#, r#""-k3", "k3 + (k1"]"#);
    error_at(&text, r#""k3 + (k1""#, "(");
}

#[test]
fn escapes_raw_strings_and_comments_do_not_move_the_column() {
    // `\t` is two characters in the file but one in the expression.
    let text = edited(r#""k1 + k2""#, r#""k1 +\tk4""#);
    error_at(&text, r#""k1 +\tk4""#, "k4");
    let text = edited(r#""k1 + k2""#, r#""\u{6b}1 + k4""#);
    error_at(&text, r#""\u{6b}1 + k4""#, "k4");
    let text = edited(r#""k1 + k2""#, r##"r#"k1 + k4"#"##);
    error_at(&text, r##"r#"k1 + k4"#"##, "k4");
    // Comments holding quotes, brackets and the field's own name are skipped.
    let text = edited("stiffness: [", "/* stiffness: [\"( */ stiffness: [ // \"[[\n").replacen(
        r#""-k3", "k3"]"#,
        r#""-k3", "k3 ^ k4"]"#,
        1,
    );
    error_at(&text, r#""k3 ^ k4""#, "k4");
}

#[test]
fn unknown_field_points_at_its_name() {
    let text = edited("mass:", "masses:");
    match error_at(&text, "masses:", "masses") {
        StructureError::Syntax { message, .. } => assert!(message.contains("`mass`"), "{message}"),
        other => panic!("{other:?}"),
    }
    let text = edited("(value: 1000, unit: \"kg\"", "(value: 1000, units: \"kg\"");
    error_at(&text, "units:", "units");
    let text = edited("Rayleigh(", "Rayleig(");
    error_at(&text, "Rayleig(", "Rayleig");
}

#[test]
fn wrong_matrix_sizes_point_at_the_matrix_or_row() {
    let text = edited(r#"[0, 0, "m3"]]"#, r#"[0, 0, "m3"], [0, 0, 1]]"#);
    match error_at(&text, r#"mass: [["#, "[[") {
        StructureError::Invalid { field, message, .. } => {
            assert_eq!(field, "structure.mass");
            assert!(message.contains("4 rows") && message.contains("3 × 3"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let text = edited(r#"["-k2", "k2 + k3", "-k3"]"#, r#"["-k2", "k2 + k3"]"#);
    error_at(&text, r#"["-k2", "k2 + k3"]"#, "[");
    let text = edited("velocity: [0, 0, 0]", "velocity: [0, 0]");
    error_at(&text, "velocity: [0, 0]", "[");
}

#[test]
fn unknown_coordinate_in_an_output_points_at_the_name() {
    let text = edited(r#"Displacement("q3")"#, r#"Displacement("q4")"#);
    let message = error_at(&text, r#"Displacement("q4")"#, "q4").to_string();
    assert!(message.contains("the coordinates are q1, q2, q3"), "{message}");
    let text = edited(r#"Displacement("q3")"#, r#"State("q3")"#);
    error_at(&text, r#"State("q3")"#, "State");
}

#[test]
fn bounds_and_values_are_checked_where_they_stand() {
    let text = edited("bounds: (0, 100)", "bounds: (100, 100)");
    match error_at(&text, "bounds: (100, 100)", "(") {
        StructureError::Invalid { field, .. } => assert_eq!(field, "parameters.alpha.bounds"),
        other => panic!("{other:?}"),
    }
    let text = edited("value: 0.375", "value: 375");
    match error_at(&text, "value: 375", "375") {
        StructureError::InvalidValue { field, value, .. } => {
            assert_eq!(field, "parameters.alpha.value");
            assert_eq!(value, 375.0);
        }
        other => panic!("{other:?}"),
    }
    let text = edited("value: 0.375", "value: NaN");
    error_at(&text, "value: NaN", "NaN");
    let text = edited("value: 0.375, unit", "value: 0.375, typical: -1, unit");
    error_at(&text, "typical: -1", "-1");
    let text = edited(r#"[0, "m2", 0]"#, r#"[0, "m2", inf]"#);
    error_at(&text, r#""m2", inf"#, "inf");
}

#[test]
fn singular_mass_points_at_the_mass_matrix() {
    for text in [
        edited(r#"[["m1", 0, 0]"#, r#"[["m1 - m1", 0, 0]"#),
        edited(r#""m2": (value: 1000"#, r#""m2": (value: 0"#),
    ] {
        let message = error_at(&text, "mass: [[", "[[").to_string();
        assert!(message.contains("singular"), "{message}");
    }
}

#[test]
fn a_mass_matrix_without_positive_kinetic_energy_points_at_the_mass_matrix() {
    // A negative mass, and a coupling of floors 1 and 2 larger than their masses
    // (det [[1000, 1500], [1500, 1000]] < 0): ½ q̇ᵀ M q̇ < 0 for some motion, though M is regular.
    for text in [
        edited(r#""m2": (value: 1000"#, r#""m2": (value: -1000"#),
        edited(r#"[["m1", 0, 0], [0, "m2", 0]"#, r#"[["m1", 1500, 0], [1500, "m2", 0]"#),
    ] {
        let message = error_at(&text, "mass: [[", "[[").to_string();
        assert!(message.contains("not positive definite"), "{message}");
    }
}

#[test]
fn non_finite_entries_at_the_file_values_point_at_the_entry() {
    let text = edited(r#""-k3", "k3"]"#, r#""-k3", "k3/(k1 - k1)"]"#);
    let message = error_at(&text, r#""k3/(k1 - k1)""#, r#"""#).to_string();
    assert!(message.contains("inf"), "{message}");
}

#[test]
fn derived_names_must_be_defined_before_use() {
    let text =
        edited("    structure:", "    derived: [(\"a\", \"2*b\"), (\"b\", \"a + 1\")],\n    structure:");
    let message = error_at(&text, r#""2*b""#, "b").to_string();
    assert!(message.contains("derived `a` uses `b`"), "{message}");
    let text = edited("    structure:", "    derived: [(\"a\", \"k1 + a\")],\n    structure:");
    let message = error_at(&text, r#""k1 + a""#, "a\"").to_string();
    assert!(message.contains("itself"), "{message}");
    let text = edited("    structure:", "    derived: [(\"k1\", \"2*k2\")],\n    structure:");
    error_at(&text, r#"("k1""#, "k1");
    let text = edited("    structure:", "    derived: [(\"pi\", \"2\")],\n    structure:");
    error_at(&text, r#"("pi""#, "pi");
    // Derived names work in entries.
    let text = edited(r#""k1 + k2""#, r#""ksum""#).replacen(
        "    structure:",
        "    derived: [(\"ksum\", \"k1 + k2\")],\n    structure:",
        1,
    );
    StructureModel::from_ron(&text, ORIGIN).unwrap();
}

#[test]
fn repeated_and_invalid_names_point_at_the_second_one() {
    let text = edited(r#""m3": (value"#, r#""m2": (value"#);
    let message = error_at(&text, r#""m2": (value: 1000, unit: "kg", description: "mass of floor 3""#, "m2")
        .to_string();
    assert!(message.contains("twice"), "{message}");
    let text = edited(r#""m3": (value"#, r#""3m": (value"#);
    error_at(&text, r#""3m""#, "3m");
    let text = edited(r#"["q1", "q2", "q3"]"#, r#"["q1", "q2", "q2"]"#);
    error_at(&text, r#""q2", "q2"]"#, r#"q2"]"#);
    let text = edited(r#"(column: "q3""#, r#"(column: "q1""#);
    error_at(&text, r#"(column: "q1", measures: Displacement("q3")"#, r#"q1""#);
}

/// A column's name is a CSV header field: a name a reader would trim, or the time column's,
/// could never match a record, and is refused where it stands (found with `fuzz/`).
#[test]
fn column_names_a_csv_header_cannot_hold_point_at_the_name() {
    let text = edited(r#"(column: "q3""#, r#"(column: " q3""#);
    let message = error_at(&text, r#"(column: " q3""#, r#" q3""#).to_string();
    assert!(message.contains(r#"write it as "q3""#), "{message}");
    let text = edited(r#"(column: "q3""#, r#"(column: "q\t3""#);
    error_at(&text, r#"(column: "q\t3""#, r#"q\t3""#);
    let text = edited(r#"(column: "q3""#, r#"(column: "t""#);
    let message = error_at(&text, r#"(column: "t""#, r#"t""#).to_string();
    assert!(message.contains("time column"), "{message}");
    // A comma or a quote is kept: the writers quote it (mem::csv_header).
    assert!(StructureModel::from_ron(&edited(r#"(column: "q3""#, r#"(column: "q,\"3""#), ORIGIN).is_ok());
}

#[test]
fn second_and_first_order_fields_are_not_mixed() {
    let text = edited("initial: (displacement", "initial: (state: [0, 0, 0, 0, 0, 0], displacement");
    error_at(&text, "state: [", "[");
    let text = edited(
        "(column: \"q1\", measures: Displacement(\"q1\"), unit: \"m\")",
        "(column: \"q1\", measures: Row([1, 0, 0, 0, 0, 0]))",
    );
    error_at(&text, "Row([", "Row");
    let text = edited(
        "damping: Rayleigh(alpha: \"alpha\", beta: \"beta\"),",
        "damping: Rayleigh(alpha: \"alpha\", beta: \"beta\"), inputs: [(name: \"u\")],",
    );
    error_at(&text, "(name: \"u\")", "(");
    let text = edited(
        "(column: \"q1\", measures: Displacement(\"q1\"), unit: \"m\")",
        "(column: \"q1\", measures: Displacement(\"q1\"), feedthrough: [1])",
    );
    error_at(&text, "feedthrough: [1]", "[");
}

#[test]
fn syntax_errors_are_located() {
    let text = edited(r#""m2": (value: 1000, unit: "kg""#, r#""m2": (value: 1000 unit: "kg""#);
    let error = StructureModel::from_ron(&text, ORIGIN).unwrap_err();
    let (line, _) = position(&text, "value: 1000 unit", "unit");
    assert!(matches!(error, StructureError::Syntax { line: l, .. } if l == line), "{error}");
    let text = edited(r#""m1", 0, 0]"#, r#""m1", true, 0]"#);
    let message = StructureModel::from_ron(&text, ORIGIN).unwrap_err().to_string();
    assert!(message.contains("a number or a string"), "{message}");
}

#[test]
fn set_value_and_state_space_report_bad_use() {
    let mut model = fixture("shear_building.ron");
    let message = model.set("k4", 1.0).unwrap_err().to_string();
    assert!(message.contains("k4") && message.contains("m1, m2, m3, k1, k2, k3, alpha, beta"), "{message}");
    assert!(matches!(model.value("nope"), Err(StructureError::UnknownParameter { .. })));
    assert!(matches!(model.set("k1", f64::NAN), Err(StructureError::NotFinite { .. })));
    assert!(matches!(model.set("k1", -1.0), Err(StructureError::OutOfBounds { lower: 0.0, .. })));
    assert_eq!(model.value("k1").unwrap(), 2.5e6);
    model.set("m1", -5.0).unwrap(); // no bounds declared
    assert!(matches!(
        model.state_space::<f64>(&[1.0]),
        Err(StructureError::ParameterCount { expected: 8, got: 1 })
    ));
    let mut p = model.values();
    p[0] = 0.0;
    let message = model.state_space::<f64>(&p).unwrap_err().to_string();
    assert!(message.contains("mass matrix") && message.contains("singular"), "{message}");
    p[0] = f64::NAN;
    assert!(matches!(model.state_space::<f64>(&p), Err(StructureError::Assembly { .. })));
    let missing = StructureModel::load(std::path::Path::new("/nonexistent/model.ron")).unwrap_err();
    assert!(matches!(missing, StructureError::Io { .. }), "{missing}");
}

#[test]
fn modal_damping_needs_positive_definite_matrices() {
    let text = edited(r#"Rayleigh(alpha: "alpha", beta: "beta")"#, r#"Modal([0.02, 0.03, 0.05])"#);
    let model = StructureModel::from_ron(&text, ORIGIN).unwrap();
    assert_eq!(model.modes().unwrap().len(), 3);
    // A mechanism (k1 = 0): a rigid-body mode has no modal damping.
    let text = text.replacen(r#""k1": (value: 2.5e6"#, r#""k1": (value: 0"#, 1);
    let message = error_at(&text, "damping: Modal", "Modal").to_string();
    assert!(message.contains("positive definite stiffness"), "{message}");
    let mut p = model.values();
    p[3] = 0.0;
    assert!(matches!(model.state_space::<f64>(&p), Err(StructureError::Assembly { .. })));
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 200,
        rng_seed: RngSeed::Fixed(20261201),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Any edit of a valid file gives a model or an error, never a panic; a located error
    /// points inside the text.
    #[test]
    fn edited_files_never_panic(at in any::<prop::sample::Index>(), cut in 0usize..4, insert in "[\\[\\](){}\",:/*a-z0-9 .+-]{0,4}") {
        let text = fixture_text("shear_building_forced.ron");
        let mut at = at.index(text.len());
        while !text.is_char_boundary(at) {
            at -= 1;
        }
        let mut end = (at + cut).min(text.len());
        while !text.is_char_boundary(end) {
            end += 1;
        }
        let edited = format!("{}{}{}", &text[..at], insert, &text[end..]);
        let _ = structure::is_structure_file(&edited);
        if let Err(e) = StructureModel::from_ron(&edited, ORIGIN) {
            let message = e.to_string();
            prop_assert!(!message.contains('\n'), "{}", message);
            let lines = edited.lines().count().max(1);
            match e {
                StructureError::Syntax { line, .. } | StructureError::Expression { line, .. }
                | StructureError::Invalid { line, .. } | StructureError::InvalidValue { line, .. } => {
                    prop_assert!(line >= 1 && line <= lines + 1, "{}", message);
                }
                _ => {}
            }
        }
    }

    /// Random values within the bounds round-trip through `to_ron`.
    #[test]
    fn random_values_round_trip(k in prop::array::uniform3(1.0..1e9f64), alpha in 0.0..100.0f64, beta in 0.0..1.0f64, m in 1.0..1e5f64) {
        let mut model = fixture("shear_building.ron");
        for (name, value) in [("k1", k[0]), ("k2", k[1]), ("k3", k[2]), ("alpha", alpha), ("beta", beta), ("m2", m)] {
            model.set(name, value).unwrap();
        }
        let back = StructureModel::from_ron(&model.to_ron(), ORIGIN).unwrap();
        prop_assert_eq!(back.values(), model.values());
    }
}
