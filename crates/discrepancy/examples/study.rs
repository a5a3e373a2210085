//! The long hidden-effect study: every case × seeds 1..=N, printed as the confusion matrix and
//! the shrink/recovery figures of docs/diagnose.md.
//!
//! `cargo run --release -p discrepancy --example study -- 10`

use discrepancy::study::CASES;
use discrepancy::study_run::{StudyResult, run_case};
use rayon::prelude::*;

fn main() {
    let seeds: u64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(10);
    let start = std::time::Instant::now();
    let jobs: Vec<(&str, u64)> = CASES.iter().flat_map(|c| (1..=seeds).map(move |s| (*c, s))).collect();
    let results: Vec<StudyResult> = jobs.par_iter().map(|(c, s)| run_case(c, *s)).collect();
    println!("{} diagnoses in {:.0?}\n", results.len(), start.elapsed());
    let mut named: Vec<&str> = CASES.to_vec();
    for r in &results {
        if !named.contains(&r.named.as_str()) {
            named.push(Box::leak(r.named.clone().into_boxed_str()));
        }
    }
    print!("| true \\ named |");
    for n in &named {
        print!(" {n} |");
    }
    println!("\n|---|{}", "---|".repeat(named.len()));
    for case in CASES {
        print!("| {case} |");
        for n in &named {
            let count = results.iter().filter(|r| r.case == case && r.named == *n).count();
            print!(" {} |", if count > 0 { count.to_string() } else { "·".into() });
        }
        println!();
    }
    println!(
        "\n| hidden effect | named correctly | median shrink | worst shrink | median parameter error | worst parameter error |"
    );
    println!("|---|---|---|---|---|---|");
    for case in CASES {
        let rs: Vec<&StudyResult> = results.iter().filter(|r| r.case == case).collect();
        let correct = rs.iter().filter(|r| r.named == case).count();
        let mut shrink: Vec<f64> = rs.iter().filter(|r| r.named == case).map(|r| r.shrink).collect();
        let mut perr: Vec<f64> = rs.iter().filter_map(|r| r.parameter_error).collect();
        shrink.sort_by(f64::total_cmp);
        perr.sort_by(f64::total_cmp);
        let med = |v: &[f64]| {
            if v.is_empty() { "–".to_string() } else { format!("{:.1} %", 100.0 * v[v.len() / 2]) }
        };
        let worst_shrink = shrink.first().map_or("–".into(), |v| format!("{:.1} %", 100.0 * v));
        let worst_perr = perr.last().map_or("–".into(), |v| format!("{:.2} %", 100.0 * v));
        println!(
            "| {case} | {correct}/{} | {} | {worst_shrink} | {} | {worst_perr} |",
            rs.len(),
            med(&shrink),
            med(&perr)
        );
    }
}
