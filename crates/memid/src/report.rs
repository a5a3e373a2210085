//! Report directories: figures (SVG + PNG), report.md embedding them, and JSON — staged with
//! the command's other outputs, so that the report is written whole or not at all and never
//! over an input.

use crate::io::{Outputs, Target};
use crate::plot::{COLORS, Figure, Panel, Series};
use anyhow::Result;
use faer::Mat;
use mem::Measurement;
use models::FitOutcome;
use std::path::{Path, PathBuf};

/// One file the report will hold.
enum Pending {
    Bytes(String, Vec<u8>),
    Figure(String, Figure),
}

/// A report being assembled for a directory.
pub struct Report {
    dir: PathBuf,
    markdown: String,
    pending: Vec<Pending>,
}

fn unit(name: &str) -> String {
    match name {
        "theta" => "θ [rad]".into(),
        "theta_dot" => "θ̇ [rad/s]".into(),
        "strain" => "strain [µε]".into(),
        other => other.to_string(),
    }
}

fn series(label: &str, times: &[f64], values: &Mat<f64>, column: usize, color: usize) -> Series {
    Series {
        label: label.to_string(),
        points: times.iter().enumerate().map(|(k, t)| (*t, values[(k, column)])).collect(),
        color: COLORS[color],
    }
}

impl Report {
    /// Starts a report for `dir` (nothing is written until [`Report::stage`]).
    pub fn new(dir: &Path, title: &str) -> Self {
        Self { dir: dir.to_path_buf(), markdown: format!("# {title}\n\n"), pending: Vec::new() }
    }

    /// Appends markdown text.
    pub fn text(&mut self, text: &str) {
        self.markdown += text;
        self.markdown += "\n";
    }

    fn figure(&mut self, stem: &str, caption: &str, figure: Figure) {
        self.markdown += &format!("![{caption}]({stem}.png)\n\n*{caption}* ([SVG]({stem}.svg))\n\n");
        self.pending.push(Pending::Figure(stem.to_string(), figure));
    }

    /// The measured time histories (paper Fig. 3).
    pub fn measured(&mut self, stem: &str, caption: &str, data: &Measurement) {
        let times = data.times();
        let panels = (0..data.n_outputs())
            .map(|o| Panel {
                y_label: unit(&data.names()[o]),
                series: vec![series("measured", &times, data.values(), o, 0)],
            })
            .collect::<Vec<_>>();
        self.figure(stem, caption, Figure { title: caption.to_string(), x_label: "t [s]".into(), panels });
    }

    /// Measurement vs initial vs final model (Fig. 4), convergence (Fig. 5) and residuals, for
    /// experiment `index` of a fit.
    pub fn fit(&mut self, name: &str, caption: &str, outcome: &FitOutcome, index: usize) {
        let experiment = &outcome.experiments[index];
        let data = &experiment.data;
        let times = data.times();
        let panels = (0..data.n_outputs())
            .map(|o| Panel {
                y_label: unit(&data.names()[o]),
                series: vec![
                    series("measured", &times, data.values(), o, 0),
                    series("initial model", &times, &experiment.initial_outputs, o, 1),
                    series("final model", &times, &experiment.final_outputs, o, 2),
                ],
            })
            .collect::<Vec<_>>();
        let title = format!("{caption}: measurement, initial and final model");
        self.figure(
            &format!("{name}_fit"),
            &title,
            Figure { title: title.clone(), x_label: "t [s]".into(), panels },
        );
        let history = &outcome.report.error_history;
        let convergence = Panel {
            y_label: "log10 ‖Y_error‖".into(),
            series: vec![Series {
                label: "‖Y_error‖ (Eq. 22)".into(),
                points: history
                    .iter()
                    .enumerate()
                    .map(|(i, e)| (i as f64, e.max(f64::MIN_POSITIVE).log10()))
                    .collect(),
                color: COLORS[2],
            }],
        };
        self.figure(
            &format!("{name}_convergence"),
            &format!("{caption}: convergence of the error"),
            Figure {
                title: format!("{caption}: convergence"),
                x_label: "iteration".into(),
                panels: vec![convergence],
            },
        );
        let residual = experiment.residual();
        let panels = (0..data.n_outputs())
            .map(|o| Panel {
                y_label: unit(&data.names()[o]),
                series: vec![series("measured − final model", &times, &residual, o, 3)],
            })
            .collect::<Vec<_>>();
        self.figure(
            &format!("{name}_residuals"),
            &format!("{caption}: residuals of the final model"),
            Figure { title: format!("{caption}: residuals"), x_label: "t [s]".into(), panels },
        );
    }

    /// Adds a JSON document.
    pub fn json(&mut self, file: &str, value: &serde_json::Value) -> Result<()> {
        self.pending
            .push(Pending::Bytes(file.to_string(), serde_json::to_string_pretty(value)?.into_bytes()));
        Ok(())
    }

    /// Stages every file (report.md last) with the command's other outputs and returns the
    /// path of report.md.
    pub fn stage(self, outputs: &mut Outputs<'_>) -> Result<PathBuf> {
        outputs.check_directory(&self.dir)?;
        for item in self.pending {
            match item {
                Pending::Bytes(name, bytes) => outputs.stage(&Target::File(self.dir.join(name)), bytes)?,
                Pending::Figure(stem, figure) => {
                    outputs.stage(&Target::File(self.dir.join(format!("{stem}.svg"))), figure.svg()?)?;
                    outputs
                        .stage_file(&self.dir.join(format!("{stem}.png")), ".png", |tmp| figure.png(tmp))?;
                }
            }
        }
        let path = self.dir.join("report.md");
        outputs.stage(&Target::File(path.clone()), self.markdown.into_bytes())?;
        Ok(path)
    }
}
