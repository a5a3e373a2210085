//! Measurement validation and decimation.

use faer::Mat;
use mem::Measurement;

fn column(values: &[f64]) -> Mat<f64> {
    Mat::from_fn(values.len(), 1, |i, _| values[i])
}

#[test]
fn non_uniform_and_non_increasing_times_are_rejected_with_the_sample() {
    let v = column(&[1.0, 2.0, 3.0, 4.0]);
    let err =
        Measurement::from_times(&[0.0, 0.1, 0.25, 0.3], vec!["y".into()], v.clone()).unwrap_err().to_string();
    assert!(err.contains("sample 2") && err.contains("not uniformly sampled"), "{err}");
    let err =
        Measurement::from_times(&[0.0, 0.1, 0.1, 0.3], vec!["y".into()], v.clone()).unwrap_err().to_string();
    assert!(err.contains("sample 2") && err.contains("not increasing"), "{err}");
    let ok = Measurement::from_times(&[0.0, 0.1, 0.2, 0.3000001], vec!["y".into()], v).unwrap();
    assert!((ok.interval() - 0.1).abs() < 1e-6);
}

#[test]
fn nan_is_rejected_naming_sample_and_output() {
    let err = Measurement::new(vec!["theta".into()], 0.0, 0.1, column(&[1.0, f64::NAN, 3.0]))
        .unwrap_err()
        .to_string();
    assert!(err.contains("theta") && err.contains("sample 1"), "{err}");
}

#[test]
fn other_values_keep_the_record_and_are_validated_as_new_ones() {
    let record = Measurement::new(vec!["y".into()], 0.5, 0.1, column(&[1.0, 2.0, 3.0, 4.0])).unwrap();
    let changed = record.with_values(column(&[1.0, 2.5, 3.0, 4.0])).unwrap();
    assert_eq!((changed.start(), changed.interval(), changed.names()), (0.5, 0.1, record.names()));
    assert_eq!(changed.values()[(1, 0)], 2.5);
    let err = record.with_values(column(&[1.0, 2.0, 3.0])).unwrap_err().to_string();
    assert!(err.contains("3 × 1 values for a record of 4 samples"), "{err}");
    let err = record.with_values(column(&[1.0, f64::INFINITY, 3.0, 4.0])).unwrap_err().to_string();
    assert!(err.contains("sample 1") && err.contains('y'), "{err}");
}

#[test]
fn decimation_keeps_slow_content_and_removes_aliases() {
    // 128 Hz → 12.8 Hz (the paper's factor 10). New Nyquist 6.4 Hz; pass band up to 5.1 Hz.
    let fs = 128.0;
    let n = 1281;
    let slow = |t: f64| (2.0 * std::f64::consts::PI * 0.5 * t).cos() * (-0.1 * t).exp();
    let fast = |t: f64| 0.3 * (2.0 * std::f64::consts::PI * 30.0 * t).sin(); // would alias to 4.4 Hz
    let values = Mat::from_fn(n, 1, |k, _| slow(k as f64 / fs) + fast(k as f64 / fs));
    let data = Measurement::new(vec!["y".into()], 0.0, 1.0 / fs, values).unwrap();
    let d = data.decimate(10).unwrap();
    assert_eq!(d.n_samples(), 129);
    assert!((d.interval() - 0.078125).abs() < 1e-15);
    // The fast component must be attenuated by ≥ 40 dB (0.3 → < 3e-3: the root-raised-cosine
    // filter's stop band; the model goes through the same filter, so what leaks leaks on both
    // sides) and the slow content kept within 3e-3 everywhere, including the first sample (odd
    // reflection keeps the edge).
    let worst = (0..d.n_samples())
        .map(|k| (d.values()[(k, 0)] - slow(k as f64 * 0.078125)).abs())
        .fold(0.0, f64::max);
    assert!(worst < 3e-3, "worst deviation {worst}");
    // The operator is recorded: the model is simulated on the raw grid and filtered alike.
    assert_eq!(d.model_grid(), (0.0, 1.0 / fs, n));
    // The 30 Hz component holds 0.045 of the record's ≈ 0.26 mean power (17 %): all of it is removed.
    assert!((d.discarded()[0] - 0.17).abs() < 0.02, "{}", d.discarded()[0]);
    assert!(data.decimate(0).is_err());
}

#[test]
fn rms_weights_normalise_outputs() {
    let values = Mat::from_fn(4, 2, |k, o| if o == 0 { 2.0 * (k as f64 - 1.5) } else { 0.0 });
    let w = Measurement::new(vec!["a".into(), "b".into()], 0.0, 1.0, values).unwrap().rms_weights();
    // Output a is −3, −1, 1, 3: mean square 5.
    assert!((w[0] - 1.0 / 5.0f64.sqrt()).abs() < 1e-15, "{}", w[0]);
    assert_eq!(w[1], 1.0);
}

#[test]
fn csv_errors_name_the_line_and_column() {
    let ok = Measurement::from_csv("t,y,u\n0,1,5\n0.1,2,6\n0.2,3,7\n", "a.csv").unwrap();
    assert_eq!(ok.names(), ["y", "u"]);
    let forced = ok.with_inputs(&["u"], mem::Hold::Zero).unwrap();
    assert_eq!(forced.names(), ["y"]);
    assert_eq!(forced.inputs().unwrap().names(), ["u"]);
    assert_eq!(forced.inputs().unwrap().values()[(2, 0)], 7.0);
    let cases = [
        ("x,y\n0,1\n1,2\n", "a.csv:1: the header"),
        ("t,y\n0,1\n0.1,abc\n", "a.csv:3:2: `abc` is not a number"),
        ("t,y\n0,1\n0.1,inf\n", "a.csv:3:2: `inf` is not a finite number"),
        ("t,y\n0,1\n0.1,2,3\n", "a.csv:3: 3 fields"),
        ("t,y\n0,1\n0.1,2\n0.25,3\n", "a.csv:4:1: time is not uniformly sampled: 0.25 after 0.1 is a gap"),
        (
            "t,y\n0,1\n0.1,2\n0.2,3\n0.5,4\n0.6,5\n",
            "a.csv:5:1: time is not uniformly sampled: 0.5 after 0.2 is a gap of",
        ),
        (
            "t,y\n0,1\n0.1,2\n0.15,3\n0.25,4\n0.35,5\n",
            "a.csv:4:1: time is not uniformly sampled: 0.15 after 0.1 is a step of",
        ),
        ("t,y,y\n0,1,1\n0.1,2,2\n", "a.csv:1:3: the column `y` appears twice"),
        ("t,y\n0,1\n", "need at least 2 samples"),
    ];
    for (text, expected) in cases {
        let error = Measurement::from_csv(text, "a.csv").unwrap_err().to_string();
        assert!(error.contains(expected), "{text:?}: {error}");
    }
}

/// Names a CSV header must quote (a comma, a quote, a line break) are written quoted and read
/// back as they were (found with `fuzz/`: to_csv wrote them bare, and its own text did not read).
#[test]
fn names_with_commas_and_quotes_survive_a_round_trip() {
    let names = ["a,1", "b\"2", "c\n3", "d"];
    let values = faer::Mat::from_fn(3, names.len(), |k, o| (k * 10 + o) as f64 * 0.5);
    let record = Measurement::new(names.iter().map(|n| n.to_string()).collect(), 0.0, 0.1, values).unwrap();
    let text = record.to_csv();
    assert!(text.starts_with("t,\"a,1\",\"b\"\"2\",\"c\n3\",d\n"), "{text}");
    let again = Measurement::from_csv(&text, "written.csv").unwrap();
    assert_eq!(again.names(), names.map(String::from).as_slice());
    assert_eq!(again.values(), record.values());
    assert_eq!(mem::csv_header(["x"]), "t,x\n");
}
