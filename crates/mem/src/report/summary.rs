//! The report as a printable table (in the spirit of the paper's Table 1).

use super::{FitReport, Interval};
use crate::fit::settings::Termination;

fn termination(t: Termination) -> &'static str {
    match t {
        Termination::Converged => "converged",
        Termination::Stagnated => "stagnated",
        Termination::MaxIterations => "max_iterations",
        Termination::Diverged => "diverged",
    }
}

impl std::fmt::Display for FitReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{:<22} {:>13} {:>13} {:>13} {:>12}   95 % interval",
            "parameter", "initial", "final", "ΔP", "std. error"
        )?;
        for i in 0..self.parameters.len() {
            let se = self.statistics.std_errors[i].map_or("—".to_string(), |s| format!("{s:.3e}"));
            let interval = match self.statistics.intervals[i] {
                Interval::Symmetric { lower, upper } => format!("[{lower:.6}, {upper:.6}]"),
                Interval::OneSided { lower, upper } => {
                    format!("[{lower:.6}, {upper:.6}] one-sided (on a bound)")
                }
                Interval::Undetermined => "none: not determined by the data".to_string(),
            };
            writeln!(
                f,
                "{:<22} {:>13.6} {:>13.6} {:>+13.6} {:>12}   {interval}",
                self.names[i],
                self.initial[i],
                self.parameters[i],
                self.parameters[i] - self.initial[i],
                se
            )?;
        }
        let (e0, e1) = self.error_change();
        writeln!(f, "{:<22} {:>13.6e} {:>13.6e}", "‖Y_error‖ (Eq. 22)", e0, e1)?;
        writeln!(
            f,
            "iterations {}, termination {}, rank {}/{} (cutoff {:.0e} of σ_max), covariance {}",
            self.iterations,
            termination(self.termination),
            self.rank,
            self.parameters.len(),
            self.rank_cutoff,
            match self.statistics.covariance_kind {
                crate::Covariance::Ar1 => "AR(1) sandwich",
                _ => "white noise",
            }
        )?;
        if let Some(last) = self.records.last() {
            writeln!(
                f,
                "singular values of the column-scaled S: {}",
                last.singular_values.iter().map(|s| format!("{s:.3e}")).collect::<Vec<_>>().join(", ")
            )?;
        }
        if let Some(d) = &self.derivative_check {
            writeln!(
                f,
                "derivative check at the start: worst relative mismatch of S vs central differences {:.2e} (tolerance {:.0e})",
                d.worst_relative_mismatch, d.tolerance
            )?;
        }
        for w in &self.warnings {
            writeln!(f, "warning: {w}")?;
        }
        Ok(())
    }
}
