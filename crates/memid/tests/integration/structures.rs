//! Structure model files end to end: the shear building fixtures fitted to records made by an
//! independent program (`fixtures/independent/shear_building.py`: modal superposition checked
//! against DOP853), its modes against that program's values, forced experiments fitted jointly,
//! and located errors.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn fixture(name: &str) -> String {
    root().join("fixtures").join(name).display().to_string()
}

fn memid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_memid")).args(args).output().expect("the binary runs")
}

/// The truth of the independent records (fixtures/independent/README.md).
const TRUTH: [(&str, f64); 5] =
    [("k1", 2.62e6), ("k2", 2.16e6), ("k3", 1.96e6), ("alpha", 0.42), ("beta", 1.18e-3)];

/// Fits and checks every parameter within 2 % and 3 standard errors of the truth.
fn fit_recovers_truth(model: &str, data: &[&str]) {
    let mut args = vec!["fit", "--model", model, "--free", "k1,k2,k3,alpha,beta", "--json", "-"];
    let data: Vec<String> = data.iter().map(|d| fixture(d)).collect();
    for d in &data {
        args.extend(["--data", d.as_str()]);
    }
    let run = memid(&args);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["termination"], "converged");
    for (i, (name, truth)) in TRUTH.iter().enumerate() {
        let row = &v["parameters"][i];
        assert_eq!(row["name"], *name);
        let (value, se) = (row["final"].as_f64().unwrap(), row["std_error"].as_f64().unwrap());
        assert!((value / truth - 1.0).abs() < 0.02, "{name}: {value} vs {truth}");
        assert!((value - truth).abs() < 3.0 * se, "{name}: {value} ± {se} vs {truth}");
    }
}

#[test]
fn displacements_recover_the_independent_truth() {
    fit_recovers_truth(&fixture("shear_building.ron"), &["shear_building_measured.csv"]);
}

#[test]
fn accelerations_recover_the_independent_truth() {
    fit_recovers_truth(&fixture("shear_building_acc.ron"), &["shear_building_acc_measured.csv"]);
}

#[test]
fn two_forced_experiments_fit_jointly() {
    fit_recovers_truth(
        &fixture("shear_building_forced.ron"),
        &["shear_building_forced_chirp.csv", "shear_building_forced_random.csv"],
    );
}

#[test]
fn modal_gives_the_independent_frequencies_and_shapes() {
    let run = memid(&["modal", "--model", &fixture("shear_building.ron"), "--json"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    // Nominal undamped frequencies and Rayleigh damping ratios from the independent program.
    let expected =
        [(3.4139699088, 0.0221476404), (9.0887311061, 0.0389747209), (13.3431801825, 0.0546350108)];
    for (i, (f, z)) in expected.iter().enumerate() {
        let mode = &v["modes"][i];
        assert!((mode["frequency_hz"].as_f64().unwrap() / f - 1.0).abs() < 1e-8, "{mode}");
        assert!((mode["damping_ratio"].as_f64().unwrap() / z - 1.0).abs() < 1e-7, "{mode}");
        assert_eq!(mode["shape"].as_array().unwrap().len(), 3);
    }
    let table = memid(&["modal", "--model", &fixture("shear_building.ron")]);
    assert!(String::from_utf8_lossy(&table.stdout).contains("shape (q1, q2, q3)"));
}

#[test]
fn a_wrong_expression_is_one_line_with_line_and_column() {
    let dir = test_problems::Scratch::new("memid-structures", "expression");
    let text = std::fs::read_to_string(fixture("shear_building.ron")).unwrap();
    let bad = text.replacen("\"k2 + k3\"", "\"k2 + k4\"", 1);
    assert_ne!(bad, text, "the fixture holds the expression");
    let path = dir.join("bad.ron");
    std::fs::write(&path, &bad).unwrap();
    let (line, column) = bad
        .lines()
        .enumerate()
        .find_map(|(i, l)| l.find("k4").map(|c| (i + 1, l[..c].chars().count() + 1)))
        .unwrap();
    let run = memid(&["modal", "--model", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains(&format!("bad.ron:{line}:{column}")), "expected {line}:{column}: {stderr}");
    assert!(stderr.contains("k4"), "{stderr}");
}

/// Fits k2 alone to `data`, simulated by `model` with k2 = 2.0e6, from the file's value: the
/// noise-free record gives it back to 1e-8.
fn fits_k2_back(model: &str, data: &Path) {
    let data = data.to_str().unwrap();
    let run = memid(&["fit", "--model", model, "--data", data, "--free", "k2", "--json", "-"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    let k2 = v["parameters"][0]["final"].as_f64().unwrap();
    assert!((k2 / 2.0e6 - 1.0).abs() < 1e-8, "{}", v["parameters"][0]);
}

#[test]
fn simulate_drives_a_forced_structure_and_its_output_fits_back() {
    let dir = test_problems::Scratch::new("memid-structures", "simulate");
    let out = dir.join("sim.csv");
    let run = memid(&[
        "simulate",
        "--model",
        &fixture("shear_building_forced.ron"),
        "--inputs",
        &fixture("shear_building_forced_random.csv"),
        "--set",
        "k2=2.0e6",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("t,u,a1,a2,a3\n"), "{}", &text[..40]);
    // Noise-free and simulated by the same model: fitting k2 back from the nominal value.
    fits_k2_back(&fixture("shear_building_forced.ron"), &out);
}

#[test]
fn diagnose_names_a_sensor_bias_and_the_augmented_file_fits() {
    let dir = test_problems::Scratch::new("memid-structures", "diagnose");
    let augmented = dir.join("augmented.ron");
    let data = fixture("independent/effects/offset_q3.csv");
    let run = memid(&[
        "diagnose",
        "--model",
        &fixture("shear_building.ron"),
        "--data",
        &data,
        "--free",
        "k1,k2,k3,alpha,beta",
        "--json",
        "-",
        "-o",
        augmented.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["effect"], "output_offset");
    assert_eq!(v["label"], "output_offset(q3)");
    // The augmented file carries the effect; fitted again with its offset free, the offset
    // stays (truth 4e-4 m) and the storey stiffnesses are the independent truth's.
    let text = std::fs::read_to_string(&augmented).unwrap();
    assert!(text.contains("OutputOffset"), "{text}");
    let fit = memid(&[
        "fit",
        "--model",
        augmented.to_str().unwrap(),
        "--data",
        &data,
        "--free",
        "k1,k2,k3,alpha,beta,offset_q3",
        "--json",
        "-",
    ]);
    assert!(fit.status.success(), "{}", String::from_utf8_lossy(&fit.stderr));
    let v: serde_json::Value = serde_json::from_slice(&fit.stdout).unwrap();
    let row =
        |name: &str| v["parameters"].as_array().unwrap().iter().find(|r| r["name"] == name).unwrap().clone();
    let offset = row("offset_q3");
    let (value, se) = (offset["final"].as_f64().unwrap(), offset["std_error"].as_f64().unwrap());
    assert!((value - 4e-4).abs() < 3.0 * se + 1e-5, "offset {value} ± {se}");
    let k1 = row("k1")["final"].as_f64().unwrap();
    assert!((k1 / 2.62e6 - 1.0).abs() < 0.02, "k1 {k1}");
}

/// Column names a CSV header must quote (found with `fuzz/`): `simulate` wrote them bare, so its
/// own output did not read back. Quoted, the record it writes fits back with the same model.
#[test]
fn simulate_quotes_column_names_so_its_record_fits_back() {
    let dir = test_problems::Scratch::new("memid-structures", "quoted-columns");
    let text = std::fs::read_to_string(fixture("shear_building.ron")).unwrap();
    assert!(text.contains(r#"(column: "q1""#) && text.contains(r#"(column: "q3""#));
    let text = text.replacen(r#"(column: "q1""#, r#"(column: "floor 1, x""#, 1).replacen(
        r#"(column: "q3""#,
        r#"(column: "roof \"x\"""#,
        1,
    );
    let model = dir.join("quoted.ron");
    std::fs::write(&model, text).unwrap();
    let out = dir.join("sim.csv");
    let model = model.to_str().unwrap();
    let run = memid(&[
        "simulate",
        "--model",
        model,
        "--set",
        "k2=2.0e6",
        "--duration",
        "2",
        "--rate",
        "100",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let written = std::fs::read_to_string(&out).unwrap();
    assert!(written.starts_with("t,\"floor 1, x\",\"roof \"\"x\"\"\"\n"), "{}", &written[..40]);
    fits_k2_back(model, &out);
}
