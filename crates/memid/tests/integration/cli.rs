//! The `memid` binary end to end on the fixtures, including bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn fixture(name: &str) -> PathBuf {
    root().join("fixtures").join(name)
}

fn scratch(test: &str) -> test_problems::Scratch {
    test_problems::Scratch::new("memid-cli", test)
}

fn memid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_memid")).args(args).output().expect("the binary runs")
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// A bad-input run: exit status 2 and a single line on stderr that contains `needle`.
fn assert_bad(out: &Output, needle: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line expected: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains(needle), "`{needle}` not in: {stderr}");
}

#[test]
fn simulate_writes_the_model_outputs_and_refuses_to_overwrite_inputs() {
    let dir = scratch("simulate");
    let out = dir.join("decay.csv");
    let run = memid(&[
        "simulate",
        "--model",
        p(&fixture("slewing.ron")),
        "--set",
        "cv=0.2",
        "--duration",
        "10",
        "--rate",
        "12.8",
        "--noise",
        "0.001",
        "--seed",
        "3",
        "-o",
        p(&out),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.starts_with("t,theta,theta_dot,strain\n"));
    assert_eq!(text.lines().count(), 1 + 129);
    let model = dir.join("model.ron");
    std::fs::copy(fixture("slewing.ron"), &model).unwrap();
    let before = std::fs::read(&model).unwrap();
    let clash =
        memid(&["simulate", "--model", p(&model), "--duration", "1", "--rate", "10", "-o", p(&model)]);
    assert_bad(&clash, "refusing to overwrite");
    assert_eq!(std::fs::read(&model).unwrap(), before);
}

#[test]
fn fit_prints_table_writes_json_model_and_report() {
    let dir = scratch("fit");
    let json = dir.join("fit.json");
    let fitted = dir.join("fitted.ron");
    let report = dir.join("report");
    let run = memid(&[
        "fit",
        "--model",
        p(&fixture("slewing.ron")),
        "--data",
        p(&fixture("slewing_measured.csv")),
        "--free",
        "cv,kp",
        "--outputs",
        "theta",
        "--decimate",
        "10",
        "--json",
        p(&json),
        "--report",
        p(&report),
        "-o",
        p(&fitted),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["parameters"][0]["name"], "cv");
    for field in ["initial", "final", "std_error"] {
        assert!(v["parameters"][1][field].is_number(), "{field}");
    }
    assert!(v["error_history"].as_array().unwrap().len() >= 2);
    assert!(v["iterations"].as_u64().unwrap() >= 1);
    assert_eq!(v["termination"], "converged");
    let history: Vec<f64> =
        v["error_history"].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(history.windows(2).all(|w| w[1] <= w[0]));
    let fitted_text = std::fs::read_to_string(&fitted).unwrap();
    let kp = v["parameters"][1]["final"].as_f64().unwrap();
    assert!(fitted_text.contains(&format!("position_gain: {kp}")), "fitted model must carry K_p = {kp}");
    for file in [
        "report.md",
        "fit.json",
        "fit_fit.svg",
        "fit_fit.png",
        "fit_convergence.png",
        "fit_residuals.svg",
        "measured.png",
    ] {
        assert!(report.join(file).exists(), "{file}");
    }
    // The table form.
    let table = memid(&[
        "fit",
        "--model",
        p(&fixture("slewing.ron")),
        "--data",
        p(&fixture("slewing_measured.csv")),
        "--outputs",
        "theta",
        "--decimate",
        "10",
    ]);
    let stdout = String::from_utf8_lossy(&table.stdout);
    assert!(table.status.success());
    assert!(
        stdout.contains("‖Y_error‖") && stdout.contains("cv") && stdout.contains("termination converged"),
        "{stdout}"
    );
}

#[test]
fn modal_era_and_model_export() {
    let modal = memid(&["modal", "--model", p(&fixture("slewing.ron")), "--json"]);
    assert!(modal.status.success());
    let v: serde_json::Value = serde_json::from_slice(&modal.stdout).unwrap();
    assert_eq!(v["modes"][0]["kind"], "servo");
    assert!((v["modes"][0]["frequency_hz"].as_f64().unwrap() - 0.152).abs() < 0.002);
    let table = memid(&["modal", "--model", p(&fixture("slewing.ron")), "--set", "kp=6.5753"]);
    assert!(String::from_utf8_lossy(&table.stdout).contains("servo"));
    let era = memid(&[
        "era",
        "--data",
        p(&fixture("slewing_measured.csv")),
        "--decimate",
        "10",
        "--order",
        "12",
        "--json",
    ]);
    assert!(era.status.success(), "{}", String::from_utf8_lossy(&era.stderr));
    let v: serde_json::Value = serde_json::from_slice(&era.stdout).unwrap();
    let modes = v["modes"].as_array().unwrap();
    assert!(
        modes
            .iter()
            .any(|m| m["physical"] == true && (m["frequency_hz"].as_f64().unwrap() - 1.66).abs() < 0.1)
    );
    let export = memid(&["model", "--model", p(&fixture("slewing.ron")), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&export.stdout).unwrap();
    assert_eq!(v["A"].as_array().unwrap().len(), 8);
}

#[test]
fn demo_runs_both_runs_and_writes_a_report() {
    let dir = scratch("demo");
    let report = dir.join("demo");
    let run = memid(&["demo", "--report", p(&report), "--json"]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let v: serde_json::Value = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(v["run1"]["parameters"][0]["name"], "cv");
    assert_eq!(v["run2"]["parameters"][1]["name"], "kp");
    // The paper's qualitative result: Run 1 raises C_v, Run 2 lowers C_v and K_p, errors fall.
    let c1 = v["run1"]["parameters"][0]["final"].as_f64().unwrap();
    assert!(c1 > 0.0528);
    assert!(v["run2"]["parameters"][0]["final"].as_f64().unwrap() < c1);
    assert!(v["run2"]["parameters"][1]["final"].as_f64().unwrap() < 8.0);
    for file in
        ["report.md", "demo.json", "fig3_measured.png", "fig4a_run1_fit.svg", "fig4b_run2_convergence.png"]
    {
        assert!(report.join(file).exists(), "{file}");
    }
}

#[test]
fn bad_inputs_give_one_line_and_status_2() {
    let dir = scratch("bad");
    let model = fixture("slewing.ron");
    let data = fixture("slewing_measured.csv");
    assert_bad(&memid(&["modal", "--model", p(&dir.join("missing.ron"))]), "missing.ron");
    let bad_ron = dir.join("bad.ron");
    std::fs::write(
        &bad_ron,
        std::fs::read_to_string(&model).unwrap().replace("length: 1.19,", "length: 1.19 oops,"),
    )
    .unwrap();
    assert_bad(&memid(&["modal", "--model", p(&bad_ron)]), "bad.ron:6:");
    let negative = dir.join("negative.ron");
    std::fs::write(
        &negative,
        std::fs::read_to_string(&model).unwrap().replace("inertia: 6.02e-2", "inertia: -6.02e-2"),
    )
    .unwrap();
    assert_bad(&memid(&["modal", "--model", p(&negative)]), "motor.inertia");
    let csv = |name: &str, body: &str| {
        let path = dir.join(name);
        std::fs::write(&path, body).unwrap();
        path
    };
    let fit = |data: &Path| {
        memid(&["fit", "--model", p(&model), "--data", p(data), "--free", "cv", "--outputs", "theta"])
    };
    let nan = csv("nan.csv", "t,theta,theta_dot,strain\n0,0.5,0,0\n0.1,NaN,0,0\n0.2,0.4,0,0\n");
    assert_bad(&fit(&nan), "nan.csv:3:2");
    let malformed = csv("malformed.csv", "t,theta,theta_dot,strain\n0,0.5,0,0\n0.1,0.4,0\n");
    assert_bad(&fit(&malformed), "malformed.csv:3");
    let uneven =
        csv("uneven.csv", "t,theta,theta_dot,strain\n0,0.5,0,0\n0.1,0.45,0,0\n0.25,0.4,0,0\n0.3,0.3,0,0\n");
    assert_bad(&fit(&uneven), "uneven.csv:4:1: time is not uniformly sampled");
    // A record read off a clock that did not start at the release is fitted on the model's clock,
    // and said so; one that starts at t = 0 is not.
    let late = csv(
        "late.csv",
        "t,theta,theta_dot,strain\n100,0.5,0,0\n100.1,0.45,0,0\n100.2,0.4,0,0\n100.3,0.3,0,0\n",
    );
    let on_time =
        csv("on_time.csv", "t,theta,theta_dot,strain\n0,0.5,0,0\n0.1,0.45,0,0\n0.2,0.4,0,0\n0.3,0.3,0,0\n");
    let note = |out: &Output| String::from_utf8_lossy(&out.stderr).contains("starts at t = 100 s");
    assert!(note(&fit(&late)), "{}", String::from_utf8_lossy(&fit(&late).stderr));
    assert!(!note(&fit(&on_time)));
    let backwards = csv("backwards.csv", "t,theta,theta_dot,strain\n0,0.5,0,0\n0.1,0.45,0,0\n0.05,0.4,0,0\n");
    assert_bad(&fit(&backwards), "not increasing");
    let columns = csv("columns.csv", "t,angle\n0,0.5\n0.1,0.4\n0.2,0.3\n");
    assert_bad(
        &memid(&["fit", "--model", p(&model), "--data", p(&columns), "--free", "cv"]),
        "do not match the model's outputs",
    );
    assert_bad(
        &memid(&["fit", "--model", p(&model), "--data", p(&data), "--free", "cv,bogus"]),
        "valid names are: cv, kp",
    );
    assert_bad(&memid(&["modal", "--model", p(&model), "--set", "kp=-1"]), "kp");
    assert_bad(
        &memid(&["fit", "--model", p(&model), "--data", p(&data), "-o", p(&data)]),
        "refusing to overwrite",
    );
    let usage = memid(&["fit", "--model"]);
    assert_eq!(usage.status.code(), Some(2));
    // A forced structure's record without its force column: the column is named as missing.
    let forced = fixture("shear_building_forced_q.ron");
    let unforced = csv("unforced.csv", "t,q1,q3\n0,0,0\n0.005,1e-6,2e-6\n0.01,2e-6,3e-6\n");
    assert_bad(
        &memid(&["fit", "--model", p(&forced), "--data", p(&unforced), "--free", "k1"]),
        "missing: u; name the header's columns as the model file does",
    );
    // A mass set by hand is checked as the file's are: no negative kinetic energy.
    assert_bad(
        &memid(&["modal", "--model", p(&forced), "--set", "m1=-1000"]),
        "--set m1=-1000: cannot assemble the mass matrix M at these parameter values: it is not positive definite",
    );
    // Too short a record for the parameters asked for: refused by count, not by a solver's shape.
    let two = csv("two.csv", "t,u,q1,q3\n0,1,0,0\n0.005,2,1e-6,2e-6\n");
    assert_bad(
        &memid(&["fit", "--model", p(&forced), "--data", p(&two), "--free", "k1,k2,k3,alpha,beta"]),
        "the records hold 4 readings (samples × outputs), fewer than the 5 parameters",
    );
    assert_bad(
        &memid(&["fit", "--model", p(&forced), "--data", p(&two), "--free", "k1", "--per-experiment", "k1"]),
        "parameter `k1` is given both as shared (--free) and per experiment (--per-experiment)",
    );
}

#[test]
fn diagnose_names_the_demo_data_effects_one_at_a_time() {
    // The demo's measurement hides a current limit, air drag and quantization (fixtures/README.md),
    // besides a mass-per-length and damping mismatch. Run after run, each named effect shrinks the
    // gap, nothing outside those is named, and the chain ends in `none` with all three in the model.
    // At the start of the decay a current and a voltage limit act alike: the chain may name either
    // first and swap it for its sibling once the rest of the model tells them apart.
    let dir = scratch("diagnose");
    let data = fixture("slewing_measured.csv");
    let mut model = fixture("slewing.ron");
    let mut previous_error = f64::INFINITY;
    let mut named = Vec::new();
    for step in 1..=6 {
        let augmented = dir.join(format!("step{step}.ron"));
        let json = dir.join(format!("step{step}.json"));
        let report = dir.join(format!("report{step}"));
        let run = memid(&[
            "diagnose",
            "--model",
            p(&model),
            "--data",
            p(&data),
            "--free",
            "cv,kp",
            "--decimate",
            "10",
            "-o",
            p(&augmented),
            "--json",
            p(&json),
            "--report",
            p(&report),
        ]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        let (base, aug) = (v["baseline_error"].as_f64().unwrap(), v["augmented_error"].as_f64().unwrap());
        assert!(base <= previous_error * (1.0 + 1e-6), "step {step} starts above the last step's error");
        let effect = v["effect"].as_str().unwrap().to_string();
        assert!(v["candidates"].as_array().unwrap().iter().all(|c| c["effect"].is_string()
            && c["verdict"].is_string()
            && c["evidence"]["delta_bic"].is_number()));
        assert!(report.join("report.md").exists());
        // Residuals "after" exist only when an effect was added.
        assert_eq!(report.join("augmented_residuals.png").exists(), effect != "none");
        named.push(effect.clone());
        if effect == "none" {
            assert_eq!(aug, base, "step {step}: nothing is left to name, the model stays");
            break;
        }
        assert!(aug <= base * (1.0 + 1e-9), "step {step}: the gap must not grow ({base} → {aug})");
        assert!(
            ["amplifier_saturation", "voltage_saturation", "sensor_quantization", "quadratic_drag"]
                .contains(&effect.as_str()),
            "step {step} named {effect}, which the data do not hide ({named:?})"
        );
        previous_error = aug;
        model = augmented;
    }
    assert_eq!(named.last().map(String::as_str), Some("none"), "the chain must end: {named:?}");
    let text = std::fs::read_to_string(&model).unwrap();
    assert!(
        (text.contains("AmplifierSaturation") || text.contains("VoltageSaturation"))
            && text.contains("SensorQuantization")
            && text.contains("QuadraticDrag"),
        "{named:?}"
    );
}

#[test]
fn diagnose_rejects_bad_arguments() {
    let model = fixture("slewing.ron");
    let data = fixture("slewing_measured.csv");
    assert_bad(
        &memid(&["diagnose", "--model", p(&model), "--data", p(&data), "--free", "nope"]),
        "valid names are",
    );
    assert_bad(
        &memid(&["diagnose", "--model", p(&model), "--data", p(&data), "--free", "cv", "-o", p(&model)]),
        "refusing to overwrite",
    );
    // Counts of zero are refused at parsing, naming the flag.
    assert_bad(
        &memid(&["diagnose", "--model", p(&model), "--data", p(&data), "--free", "cv", "--decimate", "0"]),
        "--decimate",
    );
    assert_bad(&memid(&["era", "--data", p(&data), "--order", "0"]), "--order");
    assert_bad(&memid(&["era", "--data", p(&data), "--decimate", "0"]), "--decimate");
}

/// The README's pipeline: simulate at 128 Hz with 0.001 noise, fit C_v and K_p with
/// `--decimate 10`. Decimation puts the model through the data's filter, so the 95 % intervals
/// cover the truth (issue: ≥ 8 of 10 seeds, |mean z| < 1.5 for both parameters; before, 0/10
/// with mean z −2.8 and −5.9). The JSON carries the warnings array and null-free errors.
#[test]
fn the_readme_pipeline_with_decimation_covers_its_truth() {
    let dir = scratch("readme");
    let truth = [("cv", 0.2), ("kp", 8.0)];
    let mut covered = [0; 2];
    let mut z_sum = [0.0; 2];
    for seed in 1..=10 {
        let data = dir.join(format!("decay{seed}.csv"));
        let json = dir.join(format!("fit{seed}.json"));
        let seed = seed.to_string();
        let run = memid(&[
            "simulate",
            "--model",
            p(&fixture("slewing.ron")),
            "--set",
            "cv=0.2",
            "--set",
            "kp=8",
            "--duration",
            "30",
            "--rate",
            "128",
            "--noise",
            "0.001",
            "--seed",
            &seed,
            "-o",
            p(&data),
        ]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let run = memid(&[
            "fit",
            "--model",
            p(&fixture("slewing.ron")),
            "--data",
            p(&data),
            "--free",
            "cv,kp",
            "--decimate",
            "10",
            "--json",
            p(&json),
        ]);
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        let v: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert!(v["warnings"].is_array());
        for (i, (name, value)) in truth.iter().enumerate() {
            let row = &v["parameters"][i];
            assert_eq!(row["name"], *name);
            let (estimate, se) = (row["final"].as_f64().unwrap(), row["std_error"].as_f64().unwrap());
            let z = (estimate - value) / se;
            z_sum[i] += z;
            if z.abs() < 1.96 {
                covered[i] += 1;
            }
        }
    }
    for i in 0..2 {
        assert!(covered[i] >= 8, "{}: covered in {}/10", truth[i].0, covered[i]);
        assert!((z_sum[i] / 10.0).abs() < 1.5, "{}: mean z {}", truth[i].0, z_sum[i] / 10.0);
    }
}
