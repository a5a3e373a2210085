//! `diagnose` on a structure model file: the shear building of `fixtures/shear_building.ron`
//! against records made by `fixtures/independent/shear_building_effects.py` (numpy/scipy, no
//! code shared with memid; its effects in forms other than the candidates' — a quintic term in
//! the hardening spring, a tanh friction law, drag with exponent 1.8, a roof appendage as a fourth
//! degree of freedom). Each record hides one effect, or none; the building's own parameters are
//! refitted in every candidate. These records were used in development; the held-out study is
//! `studies/structure` (docs/diagnose.md).

use discrepancy::{DiagnoseOptions, diagnose};
use models::Model;

fn run(case: &str) -> discrepancy::Diagnosis {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures");
    let model = Model::load(std::path::Path::new(&format!("{root}/shear_building.ron"))).unwrap();
    let data =
        mem::Measurement::read_csv(std::path::Path::new(&format!("{root}/independent/effects/{case}.csv")))
            .unwrap();
    diagnose(&model, &data, &DiagnoseOptions::new(&["k1", "k2", "k3", "alpha", "beta"])).unwrap()
}

fn named(case: &str) -> String {
    let d = run(case);
    let label = d.named().map_or("none".to_string(), |c| c.label.clone());
    // The augmented model fits better than the baseline whenever something is named.
    if d.named().is_some() {
        assert!(d.augmented_error() < d.baseline_error(), "{case}: named {label} without a smaller error");
    }
    label
}

#[test]
fn nothing_hidden_is_none_in_white_and_coloured_noise() {
    assert_eq!(named("null"), "none");
    assert_eq!(named("null_coloured"), "none");
}

#[test]
fn a_hardening_storey_spring_is_a_cubic_spring_at_its_floor() {
    assert_eq!(named("cubic_q1"), "cubic_stiffness(q1)");
}

#[test]
fn dry_friction_is_named_at_its_floor() {
    assert_eq!(named("friction_q1"), "coulomb_friction(q1)");
}

#[test]
fn drag_on_the_roof_is_named_there() {
    assert_eq!(named("drag_q3"), "quadratic_drag(q3)");
}

#[test]
fn a_sensor_bias_is_named_on_its_sensor() {
    let d = run("offset_q3");
    let c = d.named().expect("named");
    assert_eq!(c.label, "output_offset(q3)");
    let offset = &c.parameters[0];
    let se = offset.std_error.expect("determined");
    // The truth's bias is 4e-4 m.
    assert!((offset.value - 4e-4).abs() < 3.0 * se + 2e-5, "{} ± {se}", offset.value);
}

#[test]
fn an_excited_roof_appendage_is_an_unmodeled_mode_at_its_frequency() {
    // 40 kg at 28 Hz on the roof, released 10 mm from its rest position.
    let d = run("appendage_excited_q3");
    let c = d.named().expect("named");
    assert_eq!(d.effect(), "unmodeled_mode", "{}", c.label);
    let f = c.parameters.iter().find(|p| p.name == "mode_frequency").unwrap().value;
    assert!((27.0..30.5).contains(&f), "{f} Hz");
    // The augmented model writes back as a structure file with the mode in it.
    let back = Model::from_ron(&d.augmented().to_ron(), "augmented.ron").unwrap();
    assert_eq!(back.value("mode_frequency").unwrap(), f);
}

#[test]
fn a_relaxed_appendage_is_not_given_another_name() {
    // 25 kg at 19 Hz released relaxed: below its frequency it moves with the roof (an added
    // mass the fixed masses' refit absorbs) and its own mode is barely excited.
    let d = run("appendage_q3");
    assert!(matches!(d.effect(), "none" | "unmodeled_mode"), "{:?}", d.named().map(|c| &c.label));
}
