//! The command line as a hostile user meets it (issue 13): inputs never overwritten, outputs
//! whole or absent, device nodes and FIFOs written in place, closed pipes ended quietly, extreme
//! values ending in one-line errors; and a property test over mutated RON, CSV and arguments
//! (`fuzz_short` in the default run, `fuzz_long` with ≥ 1,000 cases behind `--ignored`).

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

mod fuzz;

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures").join(name)
}

fn scratch(test: &str) -> test_problems::Scratch {
    test_problems::Scratch::new("memid-rel", test)
}

fn memid_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_memid")).current_dir(dir).args(args).output().expect("the binary runs")
}

fn hash(path: &Path) -> u64 {
    let mut h = DefaultHasher::new();
    std::fs::read(path).unwrap_or_default().hash(&mut h);
    h.finish()
}

/// A short record of the paper's model (2 s at 12.8 Hz) and the model file, in `dir`.
fn inputs(dir: &Path) -> (PathBuf, PathBuf) {
    let model = dir.join("m.ron");
    std::fs::copy(fixture("slewing.ron"), &model).unwrap();
    let data = dir.join("d.csv");
    let out =
        memid_in(dir, &["simulate", "--model", "m.ron", "--duration", "2", "--rate", "12.8", "-o", "d.csv"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    (model, data)
}

/// Exit status 2 with one line on stderr, no panic.
fn assert_one_line_error(out: &Output, what: &str) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{what}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{what}: one line expected: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
}

fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.') && n.contains(".tmp"))
        .collect()
}

#[test]
fn an_output_through_a_missing_directory_never_replaces_an_input() {
    let dir = scratch("nodir");
    let (model, data) = inputs(&dir);
    let before = (hash(&model), hash(&data));
    for args in [
        vec!["simulate", "--model", "m.ron", "--duration", "1", "--rate", "10", "-o", "nodir/../m.ron"],
        vec!["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "-o", "nodir/../d.csv"],
        vec!["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "--json", "./nodir/../m.ron"],
        vec!["model", "--model", "m.ron", "-o", "nodir/../m.ron"],
    ] {
        let out = memid_in(&dir, &args);
        assert_one_line_error(&out, &args.join(" "));
        assert!(String::from_utf8_lossy(&out.stderr).contains("refusing to overwrite"), "{:?}", out);
    }
    assert_eq!(before, (hash(&model), hash(&data)));
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

#[test]
fn a_report_directory_holding_an_input_is_refused_and_nothing_is_written() {
    let dir = scratch("report");
    let (_, _) = inputs(&dir);
    let report = dir.join("rep");
    std::fs::create_dir_all(&report).unwrap();
    // The data live where the report would write its fit.json.
    std::fs::copy(dir.join("d.csv"), report.join("fit.json")).unwrap();
    let before = hash(&report.join("fit.json"));
    let out = memid_in(
        &dir,
        &[
            "fit",
            "--model",
            "m.ron",
            "--data",
            "rep/fit.json",
            "--free",
            "cv",
            "-o",
            "fitted.ron",
            "--report",
            "rep",
        ],
    );
    assert_one_line_error(&out, "report collision");
    assert_eq!(before, hash(&report.join("fit.json")));
    // Outputs are whole or absent: the model output was not written either.
    assert!(!dir.join("fitted.ron").exists());
    // A --report path that is a file names it.
    let out =
        memid_in(&dir, &["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "--report", "m.ron"]);
    assert_one_line_error(&out, "report onto a file");
    assert!(String::from_utf8_lossy(&out.stderr).contains("m.ron"));
}

#[test]
fn a_fifo_and_a_device_node_are_written_in_place() {
    let dir = scratch("nodes");
    let (_, _) = inputs(&dir);
    // A FIFO: memid writes into it (a reader drains it) and leaves it a FIFO.
    let fifo = dir.join("pipe");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut text = String::new();
            std::fs::File::open(&fifo).unwrap().read_to_string(&mut text).unwrap();
            text
        })
    };
    let out = memid_in(&dir, &["model", "--model", "m.ron", "-o", "pipe"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(reader.join().unwrap().contains("\"A\""));
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // A character device made here (never the real /dev/null): only root may make one; as
    // another user mknod fails and the FIFO above stands for the non-regular case.
    let node = dir.join("null");
    if Command::new("mknod")
        .arg(&node)
        .args(["c", "1", "3"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
    {
        let out = memid_in(&dir, &["model", "--model", "m.ron", "-o", "null"]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        assert!(std::fs::metadata(&node).unwrap().file_type().is_char_device(), "the node was replaced");
    } else {
        eprintln!("mknod not permitted: the device-node case is covered by the FIFO only");
    }
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

#[test]
fn a_closed_pipe_ends_quietly() {
    let dir = scratch("pipe");
    let (_, _) = inputs(&dir);
    for args in [
        vec!["model", "--model", "m.ron"],
        vec!["modal", "--model", "m.ron"],
        vec!["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "--json", "-"],
        vec!["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv"],
        vec!["era", "--data", "d.csv", "--order", "4"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_memid"))
            .current_dir(&dir)
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the reading end before memid writes.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!stderr.contains("panicked"), "{}: {stderr}", args.join(" "));
        assert!(
            out.status.code() == Some(0) && stderr.is_empty(),
            "{}: {:?} {stderr}",
            args.join(" "),
            out.status
        );
    }
}

#[test]
fn a_dash_means_standard_output() {
    let dir = scratch("dash");
    let (_, _) = inputs(&dir);
    for args in [
        vec!["model", "--model", "m.ron", "-o", "-"],
        vec!["simulate", "--model", "m.ron", "--duration", "1", "--rate", "10", "-o", "-"],
        vec!["fit", "--model", "m.ron", "--data", "d.csv", "--free", "cv", "-o", "-", "--json", "out.json"],
    ] {
        let out = memid_in(&dir, &args);
        assert!(out.status.success(), "{}: {}", args.join(" "), String::from_utf8_lossy(&out.stderr));
        assert!(!out.stdout.is_empty(), "{}", args.join(" "));
    }
    assert!(!dir.join("-").exists(), "a file named `-` was written");
}

/// An output that reads zero throughout (a disconnected gauge) is warned about, and the residual
/// structure gives no ratio to its RMS (null, and said in words) — never an infinite percentage
/// (found by the mutation fuzz: "inf % of the output's RMS").
#[test]
fn an_output_that_reads_zero_gives_no_ratio_to_its_rms() {
    let dir = scratch("zero-output");
    std::fs::copy(fixture("slewing.ron"), dir.join("m.ron")).unwrap();
    let text = std::fs::read_to_string(fixture("slewing_measured.csv")).unwrap();
    let mut lines = text.lines();
    let mut zeroed = vec![lines.next().unwrap().to_string()];
    zeroed.extend(lines.map(|l| {
        let mut cells: Vec<&str> = l.split(',').collect();
        cells[3] = "0.0";
        cells.join(",")
    }));
    std::fs::write(dir.join("d.csv"), zeroed.join("\n") + "\n").unwrap();
    let out = memid_in(
        &dir,
        &[
            "diagnose",
            "--model",
            "m.ron",
            "--data",
            "d.csv",
            "--free",
            "cv,kp",
            "--decimate",
            "10",
            "--only",
            "output_offset",
            "--json",
            "-",
        ],
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(!stdout.contains("inf %") && !stdout.contains("NaN"), "{stdout}");
    let v: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let strain =
        v["residual"]["outputs"].as_array().unwrap().iter().find(|o| o["output"] == "strain").unwrap();
    assert!(strain["relative_rms"].is_null(), "{strain}");
}

/// One mutation of the inputs or the arguments.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the `index`-th number of the model file by `value`.
    RonNumber { index: usize, value: String },
    /// Replace the `index`-th number of the CSV by `value`.
    CsvNumber { index: usize, value: String },
    /// Cut the file at a fraction of its length.
    Truncate { csv: bool, at: f64 },
    /// Replace the value of an argument.
    Argument { index: usize, value: String },
}
