//! Extreme values end in one-line errors, and a property test over mutated RON, CSV and arguments
//! (`fuzz_short` in the default run, `fuzz_long` with ≥ 1,000 cases behind `--ignored`).

use super::*;

#[test]
fn extreme_values_end_in_one_line_errors() {
    let dir = scratch("extreme");
    let (model, _) = inputs(&dir);
    let with_effect = |name: &str, effect: &str| {
        let path = dir.join(name);
        let text = std::fs::read_to_string(&model)
            .unwrap()
            .replace("    bounds: {", &format!("    effects: [{effect}],\n    bounds: {{"));
        std::fs::write(&path, text).unwrap();
        name.to_string()
    };
    let drag = with_effect("drag.ron", "QuadraticDrag(hub: 1e308)");
    let friction = with_effect("friction.ron", "CoulombFriction(torque: 1e308)");
    let smooth = with_effect("smooth.ron", "CoulombFriction(torque: 0.01, smoothing_velocity: 5e-324)");
    let delay = with_effect("delay.ron", "TimeDelay(delay: 5e-324)");
    let offset = with_effect("offset.ron", "OutputOffset(sensor: Potentiometer, offset: 1e308)");
    // One reading of 1e308 in an otherwise ordinary record.
    let text = std::fs::read_to_string(dir.join("d.csv")).unwrap();
    let spiked: Vec<String> = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i == 5 {
                l.splitn(3, ',')
                    .take(1)
                    .chain(["1e308"])
                    .chain(l.splitn(3, ',').skip(2))
                    .collect::<Vec<_>>()
                    .join(",")
            } else {
                l.to_string()
            }
        })
        .collect();
    std::fs::write(dir.join("spike.csv"), spiked.join("\n") + "\n").unwrap();
    let cases: Vec<Vec<&str>> = vec![
        vec!["modal", "--model", "m.ron", "--set", "cv=1e308"],
        vec!["modal", "--model", "m.ron", "--set", "kb=1e308"],
        vec!["model", "--model", "m.ron", "--set", "length=5e-324"],
        vec!["modal", "--model", "m.ron", "--set", "cv=nan"],
        vec!["simulate", "--model", "m.ron", "--duration", "1e9", "--rate", "128", "-o", "x.csv"],
        vec!["simulate", "--model", &drag, "--duration", "5", "--rate", "10", "-o", "x.csv"],
        vec!["simulate", "--model", &friction, "--duration", "5", "--rate", "10", "-o", "x.csv"],
        vec!["simulate", "--model", &smooth, "--duration", "5", "--rate", "10", "-o", "x.csv"],
        vec!["modal", "--model", &delay],
        vec!["fit", "--model", &drag, "--data", "d.csv", "--free", "cv"],
        vec![
            "fit",
            "--model",
            "m.ron",
            "--data",
            "d.csv",
            "--free",
            "cv",
            "--decimate",
            "18446744073709551615",
        ],
        vec!["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "--decimate", "1000000000000"],
        vec!["era", "--data", "d.csv", "--order", "100000"],
        vec!["fit", "--model", &offset, "--data", "d.csv", "--free", "cv"],
        vec!["fit", "--model", "m.ron", "--data", "spike.csv", "--free", "cv"],
        vec!["diagnose", "--model", "m.ron", "--data", "spike.csv", "--free", "cv"],
        vec!["era", "--data", "spike.csv", "--order", "4"],
        vec!["diagnose", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "--only", "nope"],
        vec!["diagnose", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "--threshold", "-5"],
    ];
    for args in cases {
        let _ = std::fs::remove_file(dir.join("x.csv"));
        let out = memid_in(&dir, &args);
        let what = args.join(" ");
        match out.status.code() {
            Some(2) => assert_one_line_error(&out, &what),
            // A value memid can honestly handle must give finite output.
            Some(0) => {
                let text = String::from_utf8_lossy(&out.stdout).to_lowercase();
                assert!(
                    !text.contains("nan") && !text.contains("inf") && !text.contains("null"),
                    "{what}: {text}"
                );
            }
            other => panic!("{what}: status {other:?}: {}", String::from_utf8_lossy(&out.stderr)),
        }
        assert!(!dir.join("x.csv").exists() || out.status.success(), "{what}: a partial output was left");
    }
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

fn extreme() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("1e308".to_string()),
        Just("-1e308".to_string()),
        Just("5e-324".to_string()),
        Just("0".to_string()),
        Just("-1".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("".to_string()),
        Just("x".to_string()),
        Just("1e-300".to_string()),
        (-1e6f64..1e6).prop_map(|v| format!("{v}")),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (0usize..60, extreme()).prop_map(|(index, value)| Mutation::RonNumber { index, value }),
        (0usize..200, extreme()).prop_map(|(index, value)| Mutation::CsvNumber { index, value }),
        (any::<bool>(), 0.0f64..1.0).prop_map(|(csv, at)| Mutation::Truncate { csv, at }),
        (0usize..8, extreme()).prop_map(|(index, value)| Mutation::Argument { index, value }),
    ]
}

/// Replaces the `index`-th (mod count) number token of `text`.
fn replace_number(text: &str, index: usize, value: &str) -> String {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if starts {
            let s = if i > 0 && bytes[i - 1] == b'-' { i - 1 } else { i };
            let mut e = i;
            while e < bytes.len() && (bytes[e].is_ascii_digit() || b".eE-+".contains(&bytes[e])) {
                e += 1;
            }
            spans.push((s, e));
            i = e;
        } else {
            i += 1;
        }
    }
    if spans.is_empty() {
        return text.to_string();
    }
    let (s, e) = spans[index % spans.len()];
    format!("{}{}{}", &text[..s], value, &text[e..])
}

/// Runs one mutated command and checks the contract.
fn check(dir: &Path, command: usize, m: &Mutation) -> Result<(), TestCaseError> {
    let ron = std::fs::read_to_string(fixture("slewing.ron")).unwrap();
    let csv = std::fs::read_to_string(dir.join("clean.csv")).unwrap();
    // Bytes: a cut may split a character, and memid must say so, not panic.
    let (mut ron_m, mut csv_m) = (ron.clone().into_bytes(), csv.clone().into_bytes());
    let mut args: Vec<String> = match command {
        0 => "modal --model m.ron",
        1 => "simulate --model m.ron --duration 2 --rate 12.8 -o out.csv",
        2 => "fit --model m.ron --data d.csv --free cv,kp -o out.ron --json out.json",
        3 => "era --data d.csv --order 6",
        _ => "model --model m.ron -o out.json",
    }
    .split(' ')
    .map(String::from)
    .collect();
    match m {
        Mutation::RonNumber { index, value } => ron_m = replace_number(&ron, *index, value).into_bytes(),
        Mutation::CsvNumber { index, value } => csv_m = replace_number(&csv, *index, value).into_bytes(),
        Mutation::Truncate { csv: true, at } => csv_m.truncate((csv.len() as f64 * at) as usize),
        Mutation::Truncate { csv: false, at } => ron_m.truncate((ron.len() as f64 * at) as usize),
        Mutation::Argument { index, value } => {
            let i = 1 + index % (args.len() - 1);
            args[i] = value.clone();
        }
    }
    for out in ["out.csv", "out.ron", "out.json"] {
        let _ = std::fs::remove_file(dir.join(out));
    }
    std::fs::write(dir.join("m.ron"), &ron_m).unwrap();
    std::fs::write(dir.join("d.csv"), &csv_m).unwrap();
    let before = (hash(&dir.join("m.ron")), hash(&dir.join("d.csv")));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = memid_in(dir, &refs);
    let what = format!("{m:?} on `{}`", args.join(" "));
    let stderr = String::from_utf8_lossy(&out.stderr);
    prop_assert!(!stderr.contains("panicked"), "{}: {}", what, stderr);
    prop_assert!(matches!(out.status.code(), Some(0) | Some(2)), "{}: {:?} {}", what, out.status, stderr);
    if out.status.code() == Some(2) {
        prop_assert_eq!(stderr.trim_end().lines().count(), 1, "{}: {}", what, stderr);
    }
    prop_assert_eq!(
        before,
        (hash(&dir.join("m.ron")), hash(&dir.join("d.csv"))),
        "{}: an input changed",
        what
    );
    prop_assert!(leftovers(dir).is_empty(), "{}: temporaries left", what);
    for name in ["out.csv", "out.json"] {
        if let Ok(text) = std::fs::read_to_string(dir.join(name)) {
            prop_assert!(out.status.success(), "{}: {} written by a failed run", what, name);
            let lower = text.to_lowercase();
            prop_assert!(
                !lower.contains("nan") && !lower.contains("inf"),
                "{}: non-finite in {}",
                what,
                name
            );
        }
    }
    if out.status.success() {
        let lower = String::from_utf8_lossy(&out.stdout).to_lowercase();
        prop_assert!(!lower.contains(" nan") && !lower.contains(" inf"), "{}: non-finite on stdout", what);
    }
    Ok(())
}

fn fuzz(cases: u32, seed: u8) {
    let dir = scratch(&format!("fuzz{cases}"));
    inputs(&dir);
    std::fs::rename(dir.join("d.csv"), dir.join("clean.csv")).unwrap();
    let config = Config { cases, failure_persistence: None, ..Config::default() };
    let mut runner = TestRunner::new_with_rng(
        config,
        proptest::test_runner::TestRng::from_seed(proptest::test_runner::RngAlgorithm::ChaCha, &[seed; 32]),
    );
    runner.run(&(0usize..5, mutation()), |(command, m)| check(&dir, command, &m)).unwrap();
}

#[test]
fn fuzz_short() {
    fuzz(40, 7);
}

#[test]
#[ignore = "the long fuzz run (1,000 cases, several minutes): cargo test -p memid --test integration -- --ignored reliability::"]
fn fuzz_long() {
    fuzz(1000, 11);
}

#[test]
fn an_argument_error_names_what_is_missing_or_allowed_on_its_one_line() {
    // clap lists the missing arguments and the allowed values on lines of their own; the
    // one-line error keeps them (it once kept only the first line, which names neither).
    let dir = scratch("clap");
    let (_, _) = inputs(&dir);
    for (args, needs) in [
        (vec!["diagnose", "--model", "m.ron", "--data", "d.csv"], vec!["--free"]),
        (vec!["simulate"], vec!["--model", "--output"]),
        (
            vec!["fit", "--model", "m.ron", "--data", "d.csv", "--covariance", "x"],
            vec!["auto", "white", "ar1"],
        ),
    ] {
        let out = memid_in(&dir, &args);
        assert_one_line_error(&out, &args.join(" "));
        let stderr = String::from_utf8_lossy(&out.stderr);
        for word in needs {
            assert!(stderr.contains(word), "{}: {word} not named in {stderr}", args.join(" "));
        }
    }
}
