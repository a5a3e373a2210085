//! Report directories: figures (SVG + PNG), report.md embedding them, and JSON.

use crate::plot::{COLORS, Panel, Series, figure};
use anyhow::Result;
use discrepancy::FitOutcome;
use faer::Mat;
use mem::Measurement;
use std::path::{Path, PathBuf};

/// A report being assembled in a directory.
pub struct Report {
    dir: PathBuf,
    markdown: String,
}

fn unit(name: &str) -> &'static str {
    match name {
        "theta" => "θ [rad]",
        "theta_dot" => "θ̇ [rad/s]",
        "strain" => "strain [µε]",
        _ => "output",
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
    /// Starts a report in `dir` (created if needed).
    pub fn new(dir: &Path, title: &str) -> Result<Self> {
        std::fs::create_dir_all(dir)?;
        Ok(Self { dir: dir.to_path_buf(), markdown: format!("# {title}\n\n") })
    }

    /// Appends markdown text.
    pub fn text(&mut self, text: &str) {
        self.markdown += text;
        self.markdown += "\n";
    }

    fn embed(&mut self, stem: &str, caption: &str) {
        self.markdown += &format!("![{caption}]({stem}.png)\n\n*{caption}* ([SVG]({stem}.svg))\n\n");
    }

    /// The measured time histories (paper Fig. 3).
    pub fn measured(&mut self, stem: &str, caption: &str, data: &Measurement) -> Result<()> {
        let times = data.times();
        let panels = (0..data.n_outputs())
            .map(|o| Panel {
                y_label: unit(&data.names()[o]).into(),
                series: vec![series("measured", &times, data.values(), o, 0)],
            })
            .collect::<Vec<_>>();
        figure(&self.dir.join(stem), caption, "t [s]", &panels)?;
        self.embed(stem, caption);
        Ok(())
    }

    /// Measurement vs initial vs final model (Fig. 4), convergence (Fig. 5) and residuals.
    pub fn fit(&mut self, name: &str, caption: &str, data: &Measurement, outcome: &FitOutcome) -> Result<()> {
        let times = data.times();
        let panels = (0..data.n_outputs())
            .map(|o| Panel {
                y_label: unit(&data.names()[o]).into(),
                series: vec![
                    series("measured", &times, data.values(), o, 0),
                    series("initial model", &times, &outcome.initial_outputs, o, 1),
                    series("final model", &times, &outcome.final_outputs, o, 2),
                ],
            })
            .collect::<Vec<_>>();
        let stem = format!("{name}_fit");
        figure(
            &self.dir.join(&stem),
            &format!("{caption}: measurement, initial and final model"),
            "t [s]",
            &panels,
        )?;
        self.embed(&stem, &format!("{caption}: measurement, initial and final model"));
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
        let stem = format!("{name}_convergence");
        figure(&self.dir.join(&stem), &format!("{caption}: convergence"), "iteration", &[convergence])?;
        self.embed(&stem, &format!("{caption}: convergence of the error"));
        let residual = outcome.residual(data);
        let panels = (0..data.n_outputs())
            .map(|o| Panel {
                y_label: unit(&data.names()[o]).into(),
                series: vec![series("measured − final model", &times, &residual, o, 3)],
            })
            .collect::<Vec<_>>();
        let stem = format!("{name}_residuals");
        figure(&self.dir.join(&stem), &format!("{caption}: residuals"), "t [s]", &panels)?;
        self.embed(&stem, &format!("{caption}: residuals of the final model"));
        Ok(())
    }

    /// Writes a JSON document into the directory.
    pub fn json(&self, file: &str, value: &serde_json::Value) -> Result<()> {
        crate::io::write_atomic(&self.dir.join(file), serde_json::to_string_pretty(value)?.as_bytes())
    }

    /// Writes report.md and returns its path.
    pub fn finish(self) -> Result<PathBuf> {
        let path = self.dir.join("report.md");
        crate::io::write_atomic(&path, self.markdown.as_bytes())?;
        Ok(path)
    }
}
