//! Backlash against an independent simulator: `fixtures/independent/slewing_backlash.py` (the
//! diagnosis study's truth plant, numpy only) with a sharp dead band and gear damping only in
//! contact, where memid smooths the band's corners and damps the gear throughout.

use models::Model;
use plant::SlewingModel;
use std::path::Path;

fn fixtures() -> String {
    format!("{}/../../fixtures", env!("CARGO_MANIFEST_DIR"))
}

/// The fixture's truth: C_v 0.15, K_p 8.5, a gear at 7 Hz (ζ 0.05), tachometer on the hub.
fn truth(band: f64) -> SlewingModel {
    let text = std::fs::read_to_string(format!("{}/slewing.ron", fixtures()))
        .unwrap()
        .replace("viscous_damping: 0.0528", "viscous_damping: 0.15")
        .replace("position_gain: 8.0", "position_gain: 8.5")
        .replace(
            "    free:",
            &format!(
                "    effects: [Backlash(dead_band: {band:e}, gear_frequency_hz: 7.0, tachometer_on_motor: false)],\n    free:"
            ),
        );
    let m = SlewingModel::from_ron(&text, "backlash.ron").unwrap();
    assert_eq!(m.constants().viscous_damping, 0.15, "the edit took");
    m
}

#[test]
fn backlash_agrees_with_an_independent_simulator() {
    let clean = mem::Measurement::read_csv(Path::new(&format!(
        "{}/independent/clean/slewing_backlash.csv",
        fixtures()
    )))
    .unwrap();
    let simulate = |m: SlewingModel| {
        let response = Model::Slewing(m).response(&[]).unwrap();
        mem::sampled_response(response.as_ref(), &clean, &[]).unwrap().outputs
    };
    let (band, closed) = (simulate(truth(0.008)), simulate(truth(1e-9)));
    let k = clean.n_samples();
    for o in 0..3 {
        let rms = |f: &dyn Fn(usize) -> f64| ((0..k).map(|t| f(t).powi(2)).sum::<f64>() / k as f64).sqrt();
        let size = rms(&|t| clean.values()[(t, o)]);
        let with_band = rms(&|t| band[(t, o)] - clean.values()[(t, o)]) / size;
        let without = rms(&|t| closed[(t, o)] - clean.values()[(t, o)]) / size;
        println!("output {o}: {with_band:.4} with the band, {without:.4} with it closed");
        assert!(with_band < 0.02, "output {o}: {with_band:.4}");
        assert!(
            with_band < 0.4 * without,
            "output {o}: the band explains the gap ({with_band:.4} vs {without:.4})"
        );
    }
}

/// `memid fit` of a backlash model to the independent record: the start's derivative check
/// passes (the response is strongly curved in K_p and the band, which a plain central difference
/// at the check's step mistook for a wrong derivative), and C_v, K_p, the band and the gear's
/// frequency come back near the truth from a band of 5 mrad and a gear at 10 Hz.
#[test]
fn a_backlash_model_fits_with_its_derivatives_checked() {
    let text = std::fs::read_to_string(format!("{}/slewing.ron", fixtures())).unwrap().replace(
        "    free:",
        "    effects: [Backlash(dead_band: 0.005, gear_frequency_hz: 10.0, tachometer_on_motor: false)],\n    free:",
    );
    let model = Model::Slewing(SlewingModel::from_ron(&text, "backlash.ron").unwrap());
    let data = mem::Measurement::read_csv(Path::new(&format!(
        "{}/independent/effects/slewing_backlash.csv",
        fixtures()
    )))
    .unwrap()
    .decimate(10)
    .unwrap();
    let request = models::FitRequest::new(&["cv", "kp", "backlash", "gear_frequency"]);
    assert_eq!(request.derivative_check, mem::DerivativeCheck::Error);
    let outcome = models::fit(&model, &data, &request).unwrap();
    let p = &outcome.report.parameters;
    println!("{p:?}");
    for (value, truth, within) in
        [(p[0], 0.15, 0.02), (p[1], 8.5, 0.02), (p[2], 0.008, 0.15), (p[3], 7.0, 0.1)]
    {
        assert!((value / truth - 1.0).abs() < within, "{p:?}");
    }
}
