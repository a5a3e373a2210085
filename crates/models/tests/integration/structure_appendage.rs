//! An appendage on a structure (`structure::Effect::Appendage`): a mass on a spring and damper
//! at a coordinate, appended to the linear model as two states of its own. Checked against the
//! same building written out here as a four-coordinate file (the appendage a coordinate of the
//! file's own M, K and D, assembled by the file's path, not the effect's), read by displacements
//! and by accelerations, with a drag beside it on the nonlinear path; its sensitivities against
//! central differences; and its file errors.

use crate::common::{assert_central_differences, respond, with_effects_in as with_effects};
use expm::Response;
use models::Model;

const FILE: &str = include_str!("../../../../fixtures/shear_building.ron");
const ACCELERATIONS: &str = include_str!("../../../../fixtures/shear_building_acc2.ron");

/// The nominal building's values (fixtures/shear_building.ron).
const M: f64 = 1000.0;
const K: [f64; 3] = [2.5e6, 2.25e6, 1.875e6];
const ALPHA: f64 = 0.375;
const BETA: f64 = 1.25e-3;
/// The appendage: at q2, 30 kg, 18 Hz on a fixed base, ζ 1 %, released with 500 N in its spring.
const AT: usize = 1;
const MASS: f64 = 30.0;
const FREQUENCY: f64 = 18.0;
const DAMPING: f64 = 0.01;
const RELEASE: f64 = 500.0;

fn appendage() -> String {
    format!(
        "Appendage(coordinate: \"q2\", mass: {MASS}, frequency_hz: {FREQUENCY}, damping_ratio: {DAMPING}, \
         release_force: Some({RELEASE}))"
    )
}

/// The building with the appendage as its fourth coordinate `z`, by hand: M = diag(1000 ×3,
/// m_a), K and D = αM + βK of the building in the upper block, the appendage's spring
/// k_a = m_a ω² and damper c_a = 2ζ m_a ω between q2 and z, z(0) = q2(0) + F_r/k_a; `outputs`
/// the file's outputs' lines, `effects` its effects.
fn four_coordinates(outputs: &str, effects: &str) -> Model {
    let omega = 2.0 * std::f64::consts::PI * FREQUENCY;
    let (ka, ca) = (MASS * omega * omega, 2.0 * DAMPING * MASS * omega);
    let mut k = [[0.0; 4]; 4];
    let building = [[K[0] + K[1], -K[1], 0.0], [-K[1], K[1] + K[2], -K[2]], [0.0, -K[2], K[2]]];
    let mut d = [[0.0; 4]; 4];
    for i in 0..3 {
        for j in 0..3 {
            k[i][j] = building[i][j];
            d[i][j] = BETA * building[i][j] + if i == j { ALPHA * M } else { 0.0 };
        }
    }
    for (matrix, c) in [(&mut k, ka), (&mut d, ca)] {
        matrix[AT][AT] += c;
        matrix[3][3] += c;
        matrix[AT][3] -= c;
        matrix[3][AT] -= c;
    }
    let rows = |m: &[[f64; 4]; 4]| {
        m.iter()
            .map(|r| format!("[{}]", r.iter().map(|v| format!("{v:e}")).collect::<Vec<_>>().join(", ")))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let z0 = 0.02 + RELEASE / ka;
    let text = format!(
        "(
    name: \"Building with its appendage as a coordinate\",
    parameters: {{ \"m\": (value: {M}) }},
    structure: SecondOrder(
        coordinates: [\"q1\", \"q2\", \"q3\", \"z\"],
        mass: [[\"m\", 0, 0, 0], [0, \"m\", 0, 0], [0, 0, \"m\", 0], [0, 0, 0, {MASS}]],
        stiffness: [{}],
        damping: Matrix([{}]),
    ),
    outputs: [{outputs}],
    initial: (displacement: [0.01, 0.02, 0.03, {z0:e}], velocity: [0, 0, 0, 0]),
    effects: [{effects}],
)
",
        rows(&k),
        rows(&d)
    );
    Model::from_ron(&text, "four.ron").expect("the four-coordinate file reads")
}

/// The largest difference of two responses' outputs relative to the second's peak, per output.
fn relative_difference(a: &Response, b: &Response) -> Vec<f64> {
    (0..b.outputs.ncols())
        .map(|o| {
            let peak = (0..b.outputs.nrows()).map(|s| b.outputs[(s, o)].abs()).fold(0.0, f64::max);
            let worst = (0..b.outputs.nrows())
                .map(|s| (a.outputs[(s, o)] - b.outputs[(s, o)]).abs())
                .fold(0.0, f64::max);
            worst / peak
        })
        .collect()
}

#[test]
fn an_appendage_is_a_fourth_coordinate_on_its_spring_and_damper() {
    let (k, h) = (1000, 0.005);
    let displacements = "(column: \"q1\", measures: Displacement(\"q1\")), \
                         (column: \"q3\", measures: Displacement(\"q3\"))";
    let accelerations = "(column: \"a1\", measures: Acceleration(\"q1\")), \
                         (column: \"a3\", measures: Acceleration(\"q3\"))";
    for (file, outputs) in [(FILE, displacements), (ACCELERATIONS, accelerations)] {
        let model = with_effects(file, &appendage());
        assert!(model.is_linear(), "an appendage is linear: the exact path applies");
        let with = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
        let four = four_coordinates(outputs, "");
        let reference = respond(four.response(&[]).unwrap().as_ref(), &[], k, h);
        for (o, d) in relative_difference(&with, &reference).into_iter().enumerate() {
            assert!(d < 1e-9, "{outputs}: output {o} differs by {d:e} of its peak");
        }
        // The appendage shows: the bare building differs from it by more than a percent.
        let bare = Model::from_ron(file, "building.ron").unwrap();
        let without = respond(bare.response(&[]).unwrap().as_ref(), &[], k, h);
        assert!(relative_difference(&without, &reference).iter().all(|&d| d > 0.01));
    }
}

#[test]
fn an_appendage_beside_a_force_takes_the_nonlinear_path_alike() {
    let drag = "Drag(coordinate: \"q3\", coefficient: 3e4, exponent: 1.8)";
    let model = with_effects(FILE, &format!("{}, {drag}", appendage()));
    assert!(!model.is_linear());
    let (k, h) = (600, 0.005);
    let with = respond(model.response(&[]).unwrap().as_ref(), &[], k, h);
    let four = four_coordinates(
        "(column: \"q1\", measures: Displacement(\"q1\")), (column: \"q3\", measures: Displacement(\"q3\"))",
        drag,
    );
    let reference = respond(four.response(&[]).unwrap().as_ref(), &[], k, h);
    for (o, d) in relative_difference(&with, &reference).into_iter().enumerate() {
        assert!(d < 1e-6, "output {o} differs by {d:e} of its peak");
    }
}

#[test]
fn appendage_sensitivities_are_central_differences() {
    let model = with_effects(ACCELERATIONS, &appendage());
    let free = [
        "k2",
        "alpha",
        "appendage_mass_q2",
        "appendage_frequency_q2",
        "appendage_damping_q2",
        "appendage_release_q2",
    ];
    let response = model.response(&free).unwrap();
    let p: Vec<f64> = free.iter().map(|n| model.value(n).unwrap()).collect();
    let (k, h) = (400, 0.005);
    let out = respond(response.as_ref(), &p, k, h);
    for i in 0..free.len() {
        assert_central_differences(response.as_ref(), &p, &out, i, h, 1e-5);
    }
}

#[test]
fn an_impossible_appendage_is_refused_at_its_line() {
    for (effect, says) in [
        ("Appendage(coordinate: \"q2\", mass: 0, frequency_hz: 18, damping_ratio: 0.01)", "positive mass"),
        (
            "Appendage(coordinate: \"q2\", mass: 30, frequency_hz: -1, damping_ratio: 0.01)",
            "positive frequency",
        ),
        ("Appendage(coordinate: \"q2\", mass: 30, frequency_hz: 18, damping_ratio: -0.1)", "ratio ≥ 0"),
        (
            "Appendage(coordinate: \"q7\", mass: 30, frequency_hz: 18, damping_ratio: 0.01)",
            "no coordinate `q7`",
        ),
        (
            "Appendage(coordinate: \"q2\", mass: 30, frequency_hz: 18, damping_ratio: 0.01, release_force: Some(inf))",
            "not finite",
        ),
        ("Appendage(coordinate: \"q2\", mass: 30, frequency_hz: 1e200, damping_ratio: 0.01)", "overflows"),
        ("Appendage(coordinate: \"q2\", mass: 1e305, frequency_hz: 100, damping_ratio: 0.01)", "overflows"),
    ] {
        let text = FILE.trim_end().trim_end_matches(')').to_string()
            + &format!("    effects: [\n        {effect},\n    ],\n)\n");
        let error = Model::from_ron(&text, "building.ron").unwrap_err().to_string();
        let line = text.lines().position(|l| l.contains("Appendage")).unwrap() + 1;
        assert!(
            error.contains(says) && error.contains(&format!("building.ron:{line}:")),
            "{effect}: {error}"
        );
        assert_eq!(error.lines().count(), 1, "{error}");
    }
}
