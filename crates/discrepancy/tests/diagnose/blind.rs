//! The blind development set made by a simulator that shares no code with memid (ignored: it
//! lives outside the repository), and what the workflow refuses.

use super::*;

/// A strong Stribeck friction of the blind development set (case A3_stribeck_strong_s2, outside
/// the repository) read at 128 Hz instead of decimated: the friction gains about 13,000 nats,
/// and a servo stiffness that falls with time beside it takes up under 2 nats of what its form
/// leaves — at z 5.8, so the Wald rule alone would call the friction a torque fade. A fade must
/// also gain a tenth of what the friction explains: the friction is named. Run with
/// `cargo test --release -p discrepancy --test diagnose -- --ignored`.
#[test]
#[ignore = "needs ../shared/blind-dev"]
fn a_strong_stribeck_friction_read_at_128_hz_is_not_called_a_fade() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/blind-dev");
    let case = "A3_stribeck_strong_s2";
    let text =
        std::fs::read_to_string(root.join(format!("models/{case}.ron"))).expect("the blind set is there");
    let model = SlewingModel::from_ron(&text, "case.ron").unwrap();
    let data = mem::Measurement::read_csv(&root.join(format!("data/{case}.csv"))).unwrap();
    let d = diagnose(&model.into(), &data, &DiagnoseOptions::new(&["cv", "kp"])).unwrap();
    assert_eq!(d.effect(), "coulomb_friction", "{:?}", d.answer());
    let fade = d.fading.as_ref().expect("the fade was tried");
    assert!(!fade.demanded && fade.gain < d.threshold, "{fade:?}");
}

/// The blind development set (`../shared/blind-dev`, outside the repository; its README): the
/// rules its scorer checks, through the library. Run with
/// `cargo test --release -p discrepancy --test diagnose -- --ignored`.
#[test]
#[ignore = "needs ../shared/blind-dev and about three minutes in release mode"]
fn blind_development_set_meets_its_rules() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/blind-dev");
    let truth: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("truth.json")).expect("../shared/blind-dev/truth.json is there"),
    )
    .unwrap();
    let cases = truth["cases"].as_array().expect("a list of cases");
    let (mut right, mut total) = (std::collections::BTreeMap::new(), std::collections::BTreeMap::new());
    for case in cases {
        let family = case["family"].as_str().unwrap().to_string();
        let model_path = root.join(case["model"].as_str().unwrap());
        let model =
            SlewingModel::from_ron(&std::fs::read_to_string(&model_path).unwrap(), "case.ron").unwrap();
        let data = mem::Measurement::read_csv(&root.join(case["data"].as_str().unwrap())).unwrap();
        let free: Vec<&str> = case["free"].as_str().unwrap().split(',').collect();
        let mut options = DiagnoseOptions::new(&free);
        let args: Vec<&str> =
            case["args"].as_array().map_or(Vec::new(), |a| a.iter().filter_map(|v| v.as_str()).collect());
        if let Some(i) = args.iter().position(|a| *a == "--decimate") {
            options.decimate = Some(args[i + 1].parse().unwrap());
        }
        let d = diagnose(&model.clone().into(), &data, &options).unwrap();
        let accept: Vec<&str> =
            case["accept"].as_array().unwrap().iter().filter_map(|v| v.as_str()).collect();
        // As the set's scorer: a sensor effect of catalog physics must name the right sensor.
        let sensors: Vec<&str> = case["truth"]["effects"]
            .as_array()
            .map_or(Vec::new(), |e| e.iter().filter_map(|e| e["sensor"].as_str()).collect());
        let label = d.named().map_or("", |c| c.label.as_str());
        let sensor_ok = !(family == "A" && ["sensor_quantization", "output_offset"].contains(&d.effect()))
            || sensors.is_empty()
            || sensors.iter().any(|s| label.contains(&format!("({s})")));
        let ok = accept.contains(&d.effect()) && sensor_ok;
        *right.entry(family.clone()).or_insert(0) += usize::from(ok);
        *total.entry(family).or_insert(0) += 1;
    }
    let share =
        |f: &str| right.get(f).copied().unwrap_or(0) as f64 / total.get(f).copied().unwrap_or(1) as f64;
    let wrong = |f: &str| total.get(f).copied().unwrap_or(0) - right.get(f).copied().unwrap_or(0);
    assert!(share("A") >= 0.8, "A {right:?} of {total:?}");
    assert!(wrong("B") <= 1, "B {right:?} of {total:?}");
    assert!(wrong("C") <= 2, "C {right:?} of {total:?}");
}

#[test]
fn a_driven_slewing_model_is_refused_in_one_sentence() {
    let driven = edited(|t| t.replace("    bounds: {", "    inputs: [ReferenceAngle],\n    bounds: {"));
    let data = record(&SlewingModel::paper(), 1);
    let err = diagnose(&driven.into(), &data, &options()).unwrap_err();
    assert!(matches!(err, discrepancy::WorkflowError::Driven { .. }), "{err}");
    assert!(err.to_string().contains("theta_ref"));
}

/// A tolerance on the model file's values that is not a positive number is refused by name,
/// before anything is fitted (it divides what each account asks of the file).
#[test]
fn a_file_tolerance_that_is_not_positive_is_refused() {
    let data = record(&SlewingModel::paper(), 1);
    for bad in [0.0, -0.05, f64::NAN, f64::INFINITY] {
        let options = DiagnoseOptions { file_tolerance: bad, ..options() };
        let err = diagnose(&SlewingModel::paper().into(), &data, &options).unwrap_err();
        assert!(
            matches!(err, discrepancy::WorkflowError::Setting { field: "file_tolerance", .. }),
            "{bad}: {err}"
        );
        assert!(err.to_string().contains("file_tolerance") && !err.to_string().contains('\n'), "{err}");
    }
}
