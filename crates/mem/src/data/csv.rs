//! Reading a measurement from CSV text: header `t,<column names>`, one row per sample.

use super::{Measurement, uniform_grid};
use crate::MemError;
use faer::Mat;

impl Measurement {
    /// Parses CSV text with the header `t,<names>` (or `time,…`): the first column holds
    /// uniform, increasing time stamps, the others one output each (move inputs out with
    /// [`Measurement::with_inputs`]). `origin` names the text in errors (a file name).
    ///
    /// # Errors
    /// [`MemError::Csv`] naming `origin`, the line and, where it is one field, its column: a
    /// bad header, a row with the wrong number of fields, a field that is not a finite number,
    /// non-uniform or non-increasing times.
    pub fn from_csv(text: &str, origin: &str) -> Result<Self, MemError> {
        let error = |line: usize, column: Option<usize>, message: String| MemError::Csv {
            origin: origin.to_string(),
            line,
            column,
            message,
        };
        let mut reader =
            csv::ReaderBuilder::new().trim(csv::Trim::All).flexible(true).from_reader(text.as_bytes());
        let headers =
            reader.headers().map_err(|e| error(1, None, format!("cannot read the CSV header: {e}")))?.clone();
        if headers.len() < 2 || !matches!(&headers[0], "t" | "time") {
            return Err(error(
                1,
                None,
                format!(
                    "the header must be `t,<column names>` (found `{}`)",
                    headers.iter().collect::<Vec<_>>().join(",")
                ),
            ));
        }
        let names: Vec<String> = headers.iter().skip(1).map(|s| s.to_string()).collect();
        for (c, name) in names.iter().enumerate() {
            if name.is_empty() {
                return Err(error(1, Some(c + 2), "an empty column name; name every column".into()));
            }
            if names[..c].contains(name) {
                return Err(error(1, Some(c + 2), format!("the column `{name}` appears twice")));
            }
        }
        let mut times = Vec::new();
        let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        for (index, record) in reader.records().enumerate() {
            let line = index + 2;
            let record = record.map_err(|e| error(line, None, format!("malformed CSV: {e}")))?;
            if record.len() != headers.len() {
                return Err(error(
                    line,
                    None,
                    format!("{} fields where the header has {}", record.len(), headers.len()),
                ));
            }
            for (column, field) in record.iter().enumerate() {
                let v: f64 = field
                    .parse()
                    .map_err(|_| error(line, Some(column + 1), format!("`{field}` is not a number")))?;
                if !v.is_finite() {
                    return Err(error(
                        line,
                        Some(column + 1),
                        format!("`{field}` is not a finite number; remove or repair the sample"),
                    ));
                }
                if column == 0 {
                    times.push(v);
                } else {
                    columns[column - 1].push(v);
                }
            }
        }
        let rows = times.len();
        let (start, h) = uniform_grid(&times, rows).map_err(|e| match e {
            MemError::Sample { sample, message } => error(sample + 2, Some(1), message),
            other => error(1, None, other.to_string()),
        })?;
        let values = Mat::from_fn(rows, names.len(), |k, o| columns[o][k]);
        Self::new(names, start, h, values).map_err(|e| error(1, None, e.to_string()))
    }

    /// Reads a CSV file (see [`Measurement::from_csv`]).
    ///
    /// # Errors
    /// [`MemError::Io`] if it cannot be read, else as [`Measurement::from_csv`].
    pub fn read_csv(path: &std::path::Path) -> Result<Self, MemError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| MemError::Io { path: path.display().to_string(), source })?;
        Self::from_csv(&text, &path.display().to_string())
    }

    /// The record as CSV text (`t,<outputs>,<inputs>`), numbers in shortest round-trip form.
    pub fn to_csv(&self) -> String {
        let names = self.names.iter().chain(self.inputs.iter().flat_map(|i| i.names.iter()));
        let mut out = csv_header(names.map(String::as_str));
        let inputs_here = self.inputs.as_ref().filter(|i| i.values.nrows() == self.n_samples());
        for k in 0..self.n_samples() {
            out.push_str(&format!("{}", self.start + k as f64 * self.interval));
            for o in 0..self.n_outputs() {
                out.push_str(&format!(",{:e}", self.values[(k, o)]));
            }
            if let Some(i) = inputs_here {
                for c in 0..i.values.ncols() {
                    out.push_str(&format!(",{:e}", i.values[(k, c)]));
                }
            }
            out.push('\n');
        }
        out
    }
}

/// The header line `t,<names>` (ending in a newline), each name quoted where CSV needs it (a
/// comma, a quote or a line break in it, RFC 4180), so that [`Measurement::from_csv`] reads the
/// names back.
pub fn csv_header<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    let mut out = String::from("t");
    for name in names {
        out.push(',');
        if name.contains([',', '"', '\n', '\r']) {
            out.push('"');
            out.push_str(&name.replace('"', "\"\""));
            out.push('"');
        } else {
            out.push_str(name);
        }
    }
    out.push('\n');
    out
}
