//! `memid demo`: the paper's two runs on the embedded slewing experiment.

use crate::commands::fit::prepare;
use crate::io::{Inputs, Outputs, print};
use crate::output::{era_json, era_table, fit_json, fit_table, modal_json};
use crate::progress::spinner;
use crate::report::Report;
use anyhow::Result;
use models::{FitOutcome, FitRequest, Model, fit};
use plant::{ModalRow, ModeKind, SlewingModel};
use serde_json::json;
use std::path::PathBuf;

/// The "measured" free decay (synthetic, from the truth model; see fixtures/README.md).
const MEASURED_CSV: &str = include_str!("../../../../fixtures/slewing_measured.csv");

/// Run the paper's Run 1 (C_v) and Run 2 (C_v, K_p) on the embedded experiment and write a report.
#[derive(clap::Args)]
#[command(allow_negative_numbers = true)]
pub struct Args {
    /// Report directory.
    #[arg(long, value_name = "DIR", default_value = "reports/demo")]
    report: PathBuf,
    /// Print the report's JSON instead of the tables.
    #[arg(long)]
    json: bool,
}

/// The paper's Table 1 and 2 numbers.
mod paper {
    pub const RUN1: (f64, f64, f64, f64) = (0.0528, 0.2048, 40.2109, 8.7819); // C_v initial, final; error initial, final
    pub const RUN2: (f64, f64, f64, f64, f64, f64) = (0.2048, 0.1299, 8.0, 6.5753, 8.7819, 3.6512);
    /// (row, servo Hz, servo ζ, flexible-1 Hz, flexible-1 ζ)
    pub const TABLE2: [(&str, f64, f64, f64, f64); 4] = [
        ("Measurements", 0.1421, 0.0992, 1.5648, 0.0310),
        ("Run 1 initial", 0.1520, 0.0632, 1.72, 0.0231),
        ("Run 1 final", 0.1519, 0.2448, 1.724, 0.0246),
        ("Run 2 final", 0.1377, 0.1773, 1.7249, 0.0242),
    ];
}

/// (servo Hz, servo ζ, flexible-1 Hz, flexible-1 ζ): one row of Table 2.
type Table2Row = (f64, f64, f64, f64);

fn servo_and_flexible(rows: &[ModalRow]) -> Table2Row {
    let find = |k: ModeKind| {
        rows.iter().find(|r| r.kind == k).map_or((f64::NAN, f64::NAN), |r| (r.frequency_hz, r.damping_ratio))
    };
    let (fs, zs) = find(ModeKind::Servo);
    let (ff, zf) = find(ModeKind::Flexible(1));
    (fs, zs, ff, zf)
}

/// The measured mode that pairs with a model mode at `target_hz`: among ERA's physical modes
/// within a factor 1.5 in frequency and with ζ < 50 % (a more damped component of a nonlinear
/// decay is not an oscillation mode), the one carrying the largest share of the response.
fn pair(result: &era::EraResult, target_hz: f64) -> Option<&era::EraMode> {
    result
        .modes
        .iter()
        .filter(|m| m.physical && m.damping_ratio < 0.5)
        .filter(|m| m.frequency_hz > target_hz / 1.5 && m.frequency_hz < target_hz * 1.5)
        .max_by(|a, b| a.contribution.total_cmp(&b.contribution))
}

/// One parameter row of Table 1: (paper initial, paper final) beside ours, and both ΔP.
fn parameter_row(name: &str, paper: (f64, f64), ours: (f64, f64)) -> String {
    format!(
        "{:<16} {:>8.4} | {:<8.4} {:>8.4} | {:<8.4} {:>8.4} | {:<+8.4}\n",
        name,
        paper.0,
        ours.0,
        paper.1,
        ours.1,
        paper.1 - paper.0,
        ours.1 - ours.0
    )
}

/// The error row of Table 1: ‖Y_error‖ initial and final, paper beside ours.
fn error_row(paper: (f64, f64), ours: (f64, f64)) -> String {
    format!("{:<16} {:>8.4} | {:<8.4} {:>8.4} | {:<8.4}\n", "  ‖Y_error‖", paper.0, ours.0, paper.1, ours.1)
}

fn table1(run1: &FitOutcome, run2: &FitOutcome) -> String {
    let (r1, r2) = (&run1.report, &run2.report);
    let ours = |r: &mem::FitReport, i: usize| (r.initial[i], r.parameters[i]);
    let mut t = String::from("Table 1 — parameter values (paper | memid)\n");
    t += &format!("{:<16} {:>19} {:>19} {:>19}\n", "", "initial", "final", "ΔP");
    t += "Run 1:\n";
    t += &parameter_row("  C_v", (paper::RUN1.0, paper::RUN1.1), ours(r1, 0));
    t += &error_row((paper::RUN1.2, paper::RUN1.3), r1.error_change());
    t += "Run 2:\n";
    t += &parameter_row("  C_v", (paper::RUN2.0, paper::RUN2.1), ours(r2, 0));
    t += &parameter_row("  K_p", (paper::RUN2.2, paper::RUN2.3), ours(r2, 1));
    t += &error_row((paper::RUN2.4, paper::RUN2.5), r2.error_change());
    t += "(‖Y_error‖ is Eq. 22 on the potentiometer signal in rad at 12.8 Hz; the paper's recordings and\n units differ, so compare reductions, not magnitudes.)\n";
    t
}

fn table2(rows: &[(String, Table2Row)]) -> String {
    let mut t = String::from("Table 2 — closed-loop modes (paper | memid)\n");
    t += &format!(
        "{:<14} {:>17} {:>17} {:>17} {:>17}\n",
        "", "servo Hz", "servo ζ %", "flexible-1 Hz", "flexible-1 ζ %"
    );
    for ((name, ours), (_, pf, pz, qf, qz)) in rows.iter().zip(paper::TABLE2) {
        t += &format!(
            "{:<14} {:>7.4} | {:<7.4} {:>7.2} | {:<7.2} {:>7.4} | {:<7.4} {:>7.2} | {:<7.2}\n",
            name,
            pf,
            ours.0,
            100.0 * pz,
            100.0 * ours.1,
            qf,
            ours.2,
            100.0 * qz,
            100.0 * ours.3
        );
    }
    t
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let model = SlewingModel::paper();
    let inputs = Inputs::default();
    let mut outputs = Outputs::new(&inputs);
    outputs.check_directory(&args.report)?;
    let full = mem::Measurement::from_csv(MEASURED_CSV, "fixtures/slewing_measured.csv")?;
    // The paper recorded at 128 Hz and identified at 12.8 Hz from the position response.
    let (position_model, position_data) =
        prepare(Model::Slewing(model.clone()), vec![full.clone()], Some("theta"), Some(10))?;
    let position_data = position_data.into_iter().next().expect("one record");
    let mut request = FitRequest::new(&["cv"]);
    request.normalize = false; // one output: Eq. 22 exactly
    let bar = spinner("Run 1: fitting C_v", args.json);
    let run1 = fit(&position_model, &position_data, &request)?;
    bar.set_message("Run 2: fitting C_v and K_p");
    let mut request = FitRequest::new(&["cv", "kp"]);
    request.normalize = false;
    let run2 = fit(&run1.fitted, &position_data, &request)?;
    bar.finish_and_clear();
    // Table 2: ERA on the measured data (all sensors, 12.8 Hz), then the three models.
    let decimated = full.decimate(10)?;
    let era_result = era::identify(decimated.values().as_ref(), decimated.interval(), 12)?;
    let initial_modes = model.modal()?;
    let (model_servo, _, model_flexible, _) = servo_and_flexible(&initial_modes);
    let (servo, flexible) = (pair(&era_result, model_servo), pair(&era_result, model_flexible));
    let measured = (
        servo.map_or(f64::NAN, |m| m.frequency_hz),
        servo.map_or(f64::NAN, |m| m.damping_ratio),
        flexible.map_or(f64::NAN, |m| m.frequency_hz),
        flexible.map_or(f64::NAN, |m| m.damping_ratio),
    );
    let slewing = |m: &Model| m.as_slewing().cloned().expect("the demo fits the slewing model");
    let run1_modes = slewing(&run1.fitted).modal()?;
    let run2_modes = slewing(&run2.fitted).modal()?;
    let rows = vec![
        ("Measurements".to_string(), measured),
        ("Run 1 initial".to_string(), servo_and_flexible(&initial_modes)),
        ("Run 1 final".to_string(), servo_and_flexible(&run1_modes)),
        ("Run 2 final".to_string(), servo_and_flexible(&run2_modes)),
    ];
    let t1 = table1(&run1, &run2);
    let t2 = table2(&rows);
    let document = json!({
        "run1": fit_json(&run1),
        "run2": fit_json(&run2),
        "era": era_json(&era_result),
        "modal": {
            "initial": modal_json(&Model::Slewing(model.clone()).modes()?),
            "run1_final": modal_json(&run1.fitted.modes()?),
            "run2_final": modal_json(&run2.fitted.modes()?),
        },
        "table2": rows.iter().map(|(name, (fs, zs, ff, zf))| json!({
            "row": name, "servo_frequency_hz": fs, "servo_damping_ratio": zs,
            "flexible_frequency_hz": ff, "flexible_damping_ratio": zf,
        })).collect::<Vec<_>>(),
    });
    let mut report = Report::new(&args.report, "memid demo — the paper's two runs on the slewing experiment");
    report.text(
        "The \"measured\" data are synthetic (fixtures/README.md): a truth model with an amplifier current \
         limit, air drag, potentiometer quantization and sensor noise, sampled at 128 Hz. The fits below are \
         told none of that. As in the paper, they use the potentiometer signal decimated to 12.8 Hz.\n",
    );
    report.text(&format!("## Run 1 (C_v)\n\n```text\n{}```\n", fit_table(&run1.report)));
    report.text(&format!(
        "## Run 2 (C_v, K_p from Run 1's result)\n\n```text\n{}```\n",
        fit_table(&run2.report)
    ));
    report.text(&format!("## Tables\n\n```text\n{t1}\n{t2}```\n"));
    report.text(&format!(
        "## ERA on the measurement (12.8 Hz, all sensors, order 12)\n\nThe Measurements row pairs each model \
         mode with the strongest physical ERA mode within a factor 1.5 in frequency and below 50 % damping; \
         the heavily damped companion of the servo mode is the non-exponential, current-limited start of the \
         decay.\n\n```text\n{}```\n",
        era_table(&era_result)
    ));
    report.measured("fig3_measured", "Fig. 3 — measured time histories (128 Hz)", &full);
    report.fit("fig4a_run1", "Fig. 4a/5a — Run 1", &run1, 0);
    report.fit("fig4b_run2", "Fig. 4b/5b — Run 2", &run2, 0);
    report.json("demo.json", &document)?;
    let path = report.stage(&mut outputs)?;
    outputs.commit()?;
    if args.json {
        print(&(serde_json::to_string_pretty(&document)? + "\n"))
    } else {
        let mut text = format!("Run 1 — C_v from the paper's initial guess\n{}\n", fit_table(&run1.report));
        text += &format!("Run 2 — C_v and K_p from Run 1's result\n{}\n", fit_table(&run2.report));
        text += &format!("{t1}\n{t2}\n");
        text += &format!(
            "modes of the final model: {}\n",
            run2_modes
                .iter()
                .map(|r| format!(
                    "{} {:.4} Hz {:.2} %",
                    r.kind.name(),
                    r.frequency_hz,
                    100.0 * r.damping_ratio
                ))
                .collect::<Vec<_>>()
                .join("; ")
        );
        text += &format!("report written to {}\n", path.display());
        print(&text)
    }
}
