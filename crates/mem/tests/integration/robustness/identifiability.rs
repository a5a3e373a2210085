//! What the data do not determine gets no interval and a sentence; what they do gets an honest
//! one (the delta method, an initial state near zero).

use super::*;

#[test]
fn product_of_two_parameters_gets_no_interval_and_a_sentence() {
    let model = LinearResponse(ProductOscillator);
    let truth = [2.0, 3.0, 0.2]; // stiffness 6
    let data = add_noise(&simulate_measurement(&model, &truth, 0.05, 300, 0.0, 0), 0.01, 3);
    let start = [1.5, 3.5, 0.3]; // product 5.25, ratio 0.43
    let problem =
        Problem::new(vec![Experiment::new(&model, &data)], parameters(&["a", "b", "c"], &start)).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    let p = &report.parameters;
    assert!((p[0] * p[1] / 6.0 - 1.0).abs() < 0.01, "product {}", p[0] * p[1]);
    // No wandering: the undetermined ratio stays near where it started.
    assert!((p[0] / p[1] / (1.5 / 3.5) - 1.0).abs() < 0.3, "ratio {}", p[0] / p[1]);
    assert_eq!(report.rank, 2, "the rank cutoff must drop the null direction");
    // a and b: no standard error, no interval; c: an ordinary one.
    assert_eq!(report.std_error(0), None);
    assert_eq!(report.std_error(1), None);
    assert_eq!(report.statistics.intervals[0], Interval::Undetermined);
    assert!(report.std_error(2).is_some_and(|s| s > 0.0 && s.is_finite()));
    let undetermined = &report.identifiability.undetermined;
    assert_eq!(undetermined.len(), 1, "{:?}", report.identifiability);
    let v = &undetermined[0].direction;
    // ln a − ln b (the ratio) is the undetermined direction.
    assert!((v[0] - 1.0).abs() < 1e-6 && (v[1] + 1.0).abs() < 1e-6 && v[2].abs() < 1e-6, "{v:?}");
    let warning = report.warnings().iter().find_map(|w| match w {
        Warning::RankDeficient { sentence, parameters, .. } => Some((sentence.clone(), parameters.clone())),
        _ => None,
    });
    let (sentence, involved) = warning.expect("a rank-deficiency warning");
    assert_eq!(involved, vec!["a".to_string(), "b".to_string()]);
    assert!(sentence.contains("only the product a·b is determined"), "{sentence}");
    let json = serde_json::to_value(&report).unwrap();
    assert!(json["statistics"]["std_errors"][0].is_null());
    assert_eq!(json["warnings"][0]["kind"], "rank_deficient");
}

#[test]
fn scaling_every_mass_and_stiffness_together_is_named_and_gets_no_interval() {
    let building = ShearBuilding { free_masses: true, ..ShearBuilding::displacements() };
    let model = LinearResponse(Exact(building));
    let truth = [1000.0, 1000.0, 1000.0, 2.5e6, 2.25e6, 1.875e6, 0.375, 1.25e-3];
    let data = add_noise(&simulate_measurement(&model, &truth, 0.005, 2001, 0.0, 0), 0.01, 5);
    let start = [900.0, 1100.0, 950.0, 2.3e6, 2.4e6, 1.7e6, 0.4, 1.1e-3];
    let names = ["m1", "m2", "m3", "k1", "k2", "k3", "alpha", "beta"];
    let problem =
        Problem::new(vec![Experiment::normalized(&model, &data)], parameters(&names, &start)).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    for i in 0..6 {
        assert_eq!(report.std_error(i), None, "{} must have no finite interval: {report}", names[i]);
    }
    for i in 6..8 {
        assert!(report.std_error(i).is_some(), "{} is determined: {report}", names[i]);
    }
    let sentence = report
        .warnings()
        .iter()
        .find_map(
            |w| if let Warning::RankDeficient { sentence, .. } = w { Some(sentence.clone()) } else { None },
        )
        .expect("a rank-deficiency warning");
    assert!(sentence.starts_with("scaling m1, m2, m3, k1, k2 and k3 together"), "{sentence}");
}

/// The delta method's standard error of a derived quantity, the ratio k/c, against its spread
/// over 200 seeded noise realisations of the same record (independent of the covariance); the
/// gradient e_i gives the parameter's own standard error, and a quantity that depends on a
/// parameter held on its bound has none.
#[test]
fn a_derived_quantity_gets_the_delta_method_standard_error() {
    let model = LinearResponse(Oscillator);
    let clean = simulate_measurement(&model, &[0.2, 4.0], 0.05, 400, 0.0, 0);
    let fit = Fit::new().with_covariance(mem::Covariance::White);
    let run = |seed: u64| {
        let data = add_noise(&clean, 0.01, seed);
        let params = vec![
            Parameter::new("c", 0.25).with_bounds(0.01, 1.0),
            Parameter::new("k", 3.8).with_bounds(0.1, 100.0),
        ];
        fit.run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap()
    };
    let report = run(1000);
    let (c, k) = (report.parameters[0], report.parameters[1]);
    let predicted = report.statistics.std_error_of(&[-k / (c * c), 1.0 / c]).unwrap();
    let ratios: Vec<f64> = (0..200).map(run).map(|r| r.parameters[1] / r.parameters[0]).collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let spread = (ratios.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (ratios.len() - 1) as f64).sqrt();
    assert!((predicted / spread - 1.0).abs() < 0.2, "delta method {predicted} vs spread {spread}");
    assert_eq!(report.statistics.std_error_of(&[0.0, 1.0]), report.std_error(1));
    assert_eq!(report.statistics.std_error_of(&[1.0]), None, "one entry per parameter");
    // c held on its lower bound: k/c has no standard error, k alone still has one.
    let data = add_noise(&clean, 0.01, 9);
    let bound = vec![
        Parameter::new("c", 0.5).with_bounds(0.3, 1.0),
        Parameter::new("k", 3.5).with_bounds(0.1, 100.0),
    ];
    let held = fit.run(&Problem::new(vec![Experiment::new(&model, &data)], bound).unwrap()).unwrap();
    assert_eq!(held.on_bound[0], Some(Side::Lower));
    assert_eq!(held.statistics.std_error_of(&[1.0, 1.0]), None);
    assert!(held.statistics.std_error_of(&[0.0, 1.0]).is_some());
}

#[test]
fn an_initial_state_near_zero_is_estimated_without_a_false_alarm() {
    let model = LinearResponse(OscillatorWithUnknownStart);
    let truth = [0.2, 4.0, 0.8, 1e-9];
    let data = add_noise(&simulate_measurement(&model, &truth, 0.05, 300, 0.0, 0), 0.01, 2);
    let problem = Problem::new(
        vec![Experiment::new(&model, &data)],
        vec![
            Parameter::new("c", 0.3),
            Parameter::new("k", 3.5),
            Parameter::new("x0", 1.0),
            Parameter::new("v0", 0.0),
        ],
    )
    .unwrap();
    let report = Fit::new().run(&problem).unwrap();
    assert!(report.identifiability.undetermined.is_empty(), "{:?}", report.identifiability);
    assert!(report.statistics.std_errors.iter().all(|s| s.is_some_and(f64::is_finite)), "{report}");
}

/// A parameter resting on its bound that the data do not determine gets no interval, as the
/// rank-deficiency warning says, not a one-sided one from the bound to infinity, and no warning
/// that the data pull it beyond the bound. (Its finite differences, one-sided at the bound, are
/// pure rounding: the derivative check must not call that a mismatch.)
#[test]
fn a_parameter_on_its_bound_that_the_data_do_not_determine_gets_no_interval() {
    let model = LinearResponse(OscillatorWithInert);
    let data = add_noise(&simulate_measurement(&model, &[0.2, 4.0, 1.0], 0.05, 400, 0.0, 0), 0.01, 9);
    let params = vec![
        Parameter::new("c", 0.25).with_bounds(0.01, 1.0),
        Parameter::new("k", 3.5).with_bounds(0.1, 100.0),
        Parameter::new("inert", 1.0).with_bounds(1.0, 2.0),
    ];
    let report =
        Fit::new().run(&Problem::new(vec![Experiment::new(&model, &data)], params).unwrap()).unwrap();
    assert_eq!(report.parameters[2], 1.0, "{report}");
    assert!(
        report.warnings().iter().any(
            |w| matches!(w, Warning::RankDeficient { parameters, .. } if parameters == &["inert".to_string()])
        ),
        "inert must be named undetermined: {report}"
    );
    assert_eq!(report.on_bound[2], Some(Side::Lower), "it does rest on its bound");
    assert!(
        !report.warnings().iter().any(|w| matches!(w, Warning::ActiveBound { .. })),
        "no data pull it beyond its bound: {report}"
    );
    assert_eq!(report.std_error(2), None);
    assert_eq!(report.statistics.intervals[2], Interval::Undetermined, "{report}");
    assert!(report.to_string().contains("none: not determined by the data"), "{report}");
    for i in 0..2 {
        assert!(matches!(report.statistics.intervals[i], Interval::Symmetric { .. }), "{report}");
    }
}

/// ẋ₁ = −a x₁, ẋ₂ = −b x₂ from x(0) = (1, 1), each state measured: two decays that the data
/// tell apart whatever the record (their sensitivities −t e^{−at} lie on different outputs).
struct TwoDecays;
impl LinearModel for TwoDecays {
    type Error = std::convert::Infallible;
    fn n_states(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn output_names(&self) -> Vec<String> {
        vec!["y1".into(), "y2".into()]
    }
    fn linearize(&self, p: &[f64]) -> Result<Linearized, Self::Error> {
        Ok(Linearized::new(
            mat![[-p[0], 0.0], [0.0, -p[1]]],
            vec![mat![[-1.0, 0.0], [0.0, 0.0]], mat![[0.0, 0.0], [0.0, -1.0]]],
            mat![[1.0, 0.0], [0.0, 1.0]],
            vec![1.0, 1.0],
        ))
    }
}

/// A record of 50 samples 10⁻⁹ s apart of two decays at rates 0.5 and 1 s⁻¹: each output moves
/// by about a·t ≈ 2.5·10⁻⁸ of its size, so neither rate is resolved against 1 % noise (a
/// standard error of about 0.01/(3·10⁻⁸·√50) ≈ 5·10⁴ s⁻¹) — yet each is resolved as well as the
/// other, and the scale-free rank test finds no combination. An interval that would hold all of
/// a bounded parameter's box, [0, 100] s⁻¹, is not told.
#[test]
fn a_record_too_short_for_the_dynamics_gets_no_interval_where_it_would_hold_all_the_bounds() {
    let model = LinearResponse(TwoDecays);
    let bounded = || {
        vec![
            Parameter::new("a", 0.6).with_bounds(0.0, 100.0),
            Parameter::new("b", 0.9).with_bounds(0.0, 100.0),
        ]
    };
    let blink = add_noise(&simulate_measurement(&model, &[0.5, 1.0], 1e-9, 50, 0.0, 0), 0.01, 11);
    let problem = Problem::new(vec![Experiment::new(&model, &blink)], bounded()).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    assert!(report.identifiability.undetermined.is_empty(), "{:?}", report.identifiability);
    for (i, name) in ["a", "b"].iter().enumerate() {
        assert_eq!(report.std_error(i), None, "{name}: {report}");
        assert_eq!(report.statistics.intervals[i], Interval::Undetermined, "{name}");
        let half_width = report.warnings().iter().find_map(|w| match w {
            Warning::SpansBounds { parameter, half_width, .. } if parameter == name => Some(*half_width),
            _ => None,
        });
        assert!(half_width.is_some_and(|h| h > 1e3), "{name}: {:?}", report.warnings());
        // Its local uncertainty is kept for a caller weighing it in a range of its own.
        let local = report.statistics.local_std_error(i);
        assert!(local.is_some_and(|s| s > 1e3 && s.is_finite()), "{name}: {local:?}");
    }
    // The same bounds on a record that resolves the decays: ordinary intervals inside them.
    let decay = add_noise(&simulate_measurement(&model, &[0.5, 1.0], 0.05, 400, 0.0, 0), 0.01, 11);
    let problem = Problem::new(vec![Experiment::new(&model, &decay)], bounded()).unwrap();
    let report = Fit::new().run(&problem).unwrap();
    for i in 0..2 {
        assert!(matches!(report.statistics.intervals[i], Interval::Symmetric { .. }), "{report}");
    }
    assert!(!report.warnings().iter().any(|w| matches!(w, Warning::SpansBounds { .. })));
}
