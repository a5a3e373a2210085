//! Model-file errors name the field and its line and column.

use plant::{PlantError, SlewingModel};

const GOOD: &str = plant::PAPER_MODEL_RON;

fn load(text: &str) -> Result<SlewingModel, PlantError> {
    SlewingModel::from_ron(text, "test.ron")
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn fixture_loads_and_round_trips() {
    let m = load(GOOD).unwrap();
    let again = load(&m.to_ron()).unwrap();
    assert_eq!(m.file(), again.file());
    assert_eq!(m.output_names(), vec!["theta", "theta_dot", "strain"]);
}

#[test]
fn negative_inertia_names_field_and_line() {
    let text = GOOD.replace("inertia: 6.02e-2", "inertia: -6.02e-2");
    let err = load(&text).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("motor.inertia"), "{msg}");
    assert!(msg.starts_with(&format!("test.ron:{}:", line_of(&text, "inertia: -6.02e-2"))), "{msg}");
}

#[test]
fn zero_length_is_rejected() {
    let text = GOOD.replace("length: 1.19", "length: 0.0");
    let msg = load(&text).unwrap_err().to_string();
    assert!(msg.contains("beam.length") && msg.contains("> 0"), "{msg}");
    assert!(msg.starts_with(&format!("test.ron:{}:", line_of(&text, "length: 0.0"))), "{msg}");
}

#[test]
fn negative_modal_damping_points_at_the_entry() {
    let text = GOOD.replace("[0.5, 1.0, 1.0]", "[0.5, -1.0, 1.0]");
    let msg = load(&text).unwrap_err().to_string();
    assert!(msg.contains("modal_damping[1]"), "{msg}");
}

#[test]
fn malformed_ron_reports_line_and_column() {
    let text = GOOD.replace("length: 1.19,", "length: 1.19 oops,");
    match load(&text).unwrap_err() {
        PlantError::Syntax { line, column, .. } => {
            assert_eq!(line, line_of(&text, "oops"));
            assert!(column > 1);
        }
        other => panic!("{other}"),
    }
}

#[test]
fn unknown_and_missing_fields_are_syntax_errors() {
    let unknown = GOOD.replace("hub_radius: 0.06,", "hub_radius: 0.06,\n        colour: 1.0,");
    let msg = load(&unknown).unwrap_err().to_string();
    assert!(msg.contains("colour"), "{msg}");
    let missing =
        GOOD.replace("        thickness: 0.00079375,   // 1/32 in [m], for the root strain gauge\n", "");
    let msg = load(&missing).unwrap_err().to_string();
    assert!(msg.contains("thickness"), "{msg}");
}

#[test]
fn unknown_free_parameter_lists_valid_names() {
    let text = GOOD.replace("free: [\"cv\"]", "free: [\"cvv\"]");
    let msg = load(&text).unwrap_err().to_string();
    assert!(msg.contains("cvv") && msg.contains("cv, kp, modal_damping_1"), "{msg}");
}

#[test]
fn setting_an_impossible_value_is_an_error() {
    let mut m = load(GOOD).unwrap();
    let id = m.parameter("ra").unwrap();
    assert!(m.set(id, 0.0).is_err());
    assert!(m.set(id, f64::NAN).is_err());
    assert!(m.set(id, 3.0).is_ok());
}
