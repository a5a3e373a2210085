//! The structure's matrices, inputs, initial state and outputs.

use super::{Compiler, Ctx, Named};
use crate::StructureError;
use crate::assemble::{Coef, CompiledDamping, CompiledOutput, Dynamics, OutputRow, Quantity};
use crate::scan::Path;
use crate::schema::{Damping, Entry, Initial, Input, Measure, Output, Structure, Term};

/// Checks a list of names (coordinates, states, inputs): not empty, distinct.
fn distinct_names(ctx: &Ctx, names: &[String], path: &Path, what: &str) -> Result<(), StructureError> {
    for (i, name) in names.iter().enumerate() {
        if name.trim().is_empty() {
            return Err(ctx.invalid(&path.index(i), format!("a {what} needs a name")));
        }
        if names[..i].contains(name) {
            return Err(ctx.invalid_name(
                &path.index(i),
                format!("{what} `{name}` is named twice; names must be distinct"),
            ));
        }
    }
    Ok(())
}

/// Checks a CSV column's name (an input's or an output's): not empty, not the time column's, and
/// without spaces at its ends or control characters, which a CSV reader trims or cannot hold in
/// a header, so that no record could match it.
fn csv_column(ctx: &Ctx, name: &str, path: &Path, what: &str) -> Result<(), StructureError> {
    if name.trim().is_empty() {
        return Err(ctx.invalid(path, format!("{what} needs a name (its CSV column)")));
    }
    if name != name.trim() || name.contains(char::is_control) {
        return Err(ctx.invalid_name(
            path,
            format!(
                "column {name:?} has spaces at its ends or a control character, which a CSV header cannot keep; write it as {:?}",
                name.trim().replace(char::is_control, "_")
            ),
        ));
    }
    if matches!(name, "t" | "time") {
        return Err(ctx.invalid_name(
            path,
            format!("`{name}` names the time column of a CSV record; choose another name"),
        ));
    }
    Ok(())
}

/// Reads the inputs' names and units; `force` must be present exactly for second-order files.
fn inputs(
    c: &Compiler,
    inputs: &[Input],
    path: &Path,
    n: Option<usize>,
) -> Result<(Vec<Named>, Vec<Vec<Coef>>), StructureError> {
    let names: Vec<String> = inputs.iter().map(|i| i.name.clone()).collect();
    let each = |i: usize| path.index(i);
    for (i, name) in names.iter().enumerate() {
        csv_column(c.ctx, name, &each(i).field("name"), "an input")?;
        if names[..i].contains(name) {
            return Err(c.ctx.invalid_name(
                &each(i).field("name"),
                format!("input `{name}` is declared twice; names must be distinct"),
            ));
        }
    }
    let mut forces = Vec::with_capacity(inputs.len());
    for (i, input) in inputs.iter().enumerate() {
        match (n, &input.force) {
            (Some(n), Some(force)) => {
                forces.push(c.vector(force, n, &each(i).field("force"), "one per coordinate")?)
            }
            (Some(_), None) => {
                return Err(c.ctx.invalid(
                    &each(i),
                    format!(
                        "input `{}` needs `force: [...]`, how it loads each coordinate (a column of F)",
                        input.name
                    ),
                ));
            }
            (None, Some(_)) => {
                return Err(c.ctx.invalid(
                    &each(i).field("force"),
                    "`force` is for second-order files; a first-order file gives the inputs' columns in `b`",
                ));
            }
            (None, None) => {}
        }
    }
    let named = inputs.iter().map(|i| Named { name: i.name.clone(), unit: i.unit.clone() }).collect();
    Ok((named, forces))
}

/// A vector that may be omitted (zeros).
fn optional_vector(
    c: &Compiler,
    entries: &Option<Vec<Entry>>,
    n: usize,
    path: &Path,
    what: &str,
) -> Result<Vec<Coef>, StructureError> {
    match entries {
        Some(entries) => c.vector(entries, n, path, what),
        None => Ok(vec![Coef::Num(0.0); n]),
    }
}

/// The dynamics, the coordinate (or state) names and the inputs.
pub(super) fn structure(
    c: &Compiler,
    structure: &Structure,
    initial: &Initial,
) -> Result<(Dynamics, Vec<String>, Vec<Named>), StructureError> {
    let path = Path::default().field("structure");
    let start = Path::default().field("initial");
    match structure {
        Structure::SecondOrder { coordinates, mass, stiffness, damping, inputs: declared } => {
            let n = coordinates.len();
            if n == 0 {
                return Err(c.ctx.invalid(&path.field("coordinates"), "list at least one coordinate"));
            }
            distinct_names(c.ctx, coordinates, &path.field("coordinates"), "coordinate")?;
            let what = format!("one row and column per coordinate ({})", coordinates.join(", "));
            let mass = c.matrix(mass, n, n, &path.field("mass"), &what)?;
            let stiffness = c.matrix(stiffness, n, n, &path.field("stiffness"), &what)?;
            let at = path.field("damping");
            let damping = match damping {
                Damping::Matrix(rows) => CompiledDamping::Matrix(c.matrix(rows, n, n, &at.inner(), &what)?),
                Damping::Rayleigh { alpha, beta } => CompiledDamping::Rayleigh(
                    c.entry(alpha, &at.field("alpha"))?,
                    c.entry(beta, &at.field("beta"))?,
                ),
                Damping::Modal(ratios) => CompiledDamping::Modal(c.vector(
                    ratios,
                    n,
                    &at.inner(),
                    "one damping ratio per mode, lowest frequency first",
                )?),
            };
            let (named, forces) = inputs(c, declared, &path.field("inputs"), Some(n))?;
            let m = named.len();
            // F is n × m row-major: F[i][j] = force of input j on coordinate i.
            let forces = (0..n).flat_map(|i| forces.iter().map(move |f| f[i].clone())).collect();
            if initial.state.is_some() {
                return Err(c.ctx.invalid(
                    &start.field("state"),
                    "`state` is for first-order files; a second-order file gives `displacement` and `velocity`",
                ));
            }
            let q0 = optional_vector(
                c,
                &initial.displacement,
                n,
                &start.field("displacement"),
                "one per coordinate",
            )?;
            let v0 =
                optional_vector(c, &initial.velocity, n, &start.field("velocity"), "one per coordinate")?;
            let dynamics = Dynamics::Second { n, mass, stiffness, damping, forces, m, q0, v0 };
            Ok((dynamics, coordinates.clone(), named))
        }
        Structure::FirstOrder { states, a, b, inputs: declared } => {
            let n = states.len();
            if n == 0 {
                return Err(c.ctx.invalid(&path.field("states"), "list at least one state"));
            }
            distinct_names(c.ctx, states, &path.field("states"), "state")?;
            let what = format!("one row and column per state ({})", states.join(", "));
            let a = c.matrix(a, n, n, &path.field("a"), &what)?;
            let (named, _) = inputs(c, declared, &path.field("inputs"), None)?;
            let m = named.len();
            let b = match (b, m) {
                (None, 0) => Vec::new(),
                (Some(b), m) if m > 0 => c.matrix(
                    b,
                    n,
                    m,
                    &path.field("b"),
                    &format!("one row per state and one column per input ({})", join(&named)),
                )?,
                (Some(_), _) => {
                    return Err(c.ctx.invalid(
                        &path.field("b"),
                        "the model declares no inputs; add `inputs: [(name: …)]` or remove `b`",
                    ));
                }
                (None, _) => {
                    return Err(c.ctx.invalid(
                        &path.field("inputs"),
                        "inputs need `b: [[…]]`, one row per state and one column per input",
                    ));
                }
            };
            for (field, given) in [("displacement", &initial.displacement), ("velocity", &initial.velocity)] {
                if given.is_some() {
                    return Err(c.ctx.invalid(
                        &start.field(field),
                        format!("`{field}` is for second-order files; a first-order file gives `state`"),
                    ));
                }
            }
            let x0 = optional_vector(c, &initial.state, n, &start.field("state"), "one per state")?;
            Ok((Dynamics::First { n, a, b, m, x0 }, states.clone(), named))
        }
    }
}

fn join(named: &[Named]) -> String {
    named.iter().map(|n| n.name.as_str()).collect::<Vec<_>>().join(", ")
}

/// The kinds of quantity an output (or a term of a combination) measures.
#[derive(Clone, Copy)]
enum Kind {
    Displacement,
    Velocity,
    Acceleration,
    State,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Displacement => "Displacement",
            Kind::Velocity => "Velocity",
            Kind::Acceleration => "Acceleration",
            Kind::State => "State",
        }
    }
}

fn term_kind(term: &Term) -> (Kind, &str) {
    match term {
        Term::Displacement(name) => (Kind::Displacement, name),
        Term::Velocity(name) => (Kind::Velocity, name),
        Term::Acceleration(name) => (Kind::Acceleration, name),
        Term::State(name) => (Kind::State, name),
    }
}

/// The quantity `kind(name)` written at `path` (the variant; its name is at `path.inner()`).
fn quantity(
    ctx: &Ctx,
    kind: Kind,
    name: &str,
    path: &Path,
    names: &[String],
    second: bool,
) -> Result<Quantity, StructureError> {
    match (kind, second) {
        (Kind::State, true) => {
            return Err(ctx.invalid(
                path,
                "`State` is for first-order files; a second-order output measures Displacement, Velocity or Acceleration of a coordinate",
            ));
        }
        (Kind::State, false) => {}
        (kind, false) => {
            return Err(ctx.invalid(
                path,
                format!(
                    "`{}` is for second-order files; a first-order output measures State(\"…\") or Row([…])",
                    kind.name()
                ),
            ));
        }
        _ => {}
    }
    let what = if second { "coordinate" } else { "state" };
    let i = names.iter().position(|n| n == name).ok_or_else(|| {
        ctx.invalid_name(
            &path.inner(),
            format!("unknown {what} `{name}`; the {what}s are {}", names.join(", ")),
        )
    })?;
    Ok(match kind {
        Kind::Displacement => Quantity::Displacement(i),
        Kind::Velocity => Quantity::Velocity(i),
        Kind::Acceleration => Quantity::Acceleration(i),
        Kind::State => Quantity::State(i),
    })
}

/// The outputs: their columns and compiled rows.
pub(super) fn outputs(
    c: &Compiler,
    outputs: &[Output],
    dynamics: &Dynamics,
    names: &[String],
    inputs: &[Named],
) -> Result<Vec<(Named, CompiledOutput)>, StructureError> {
    let root = Path::default().field("outputs");
    if outputs.is_empty() {
        return Err(c.ctx.invalid(&root, "list at least one output: `(column: \"…\", measures: …)`"));
    }
    let (second, n, m) = match dynamics {
        Dynamics::Second { n, m, .. } => (true, 2 * n, *m),
        Dynamics::First { n, m, .. } => (false, *n, *m),
    };
    let mut out: Vec<(Named, CompiledOutput)> = Vec::with_capacity(outputs.len());
    for (o, output) in outputs.iter().enumerate() {
        let path = root.index(o);
        let column = &output.column;
        let column_path = path.field("column");
        csv_column(c.ctx, column, &column_path, "an output")?;
        if out.iter().any(|(named, _)| &named.name == column) {
            return Err(c.ctx.invalid_name(
                &column_path,
                format!("column `{column}` is listed twice; columns must be distinct"),
            ));
        }
        if inputs.iter().any(|i| &i.name == column) {
            return Err(c.ctx.invalid_name(
                &column_path,
                format!("column `{column}` is also an input's name; inputs and outputs are CSV columns with distinct names"),
            ));
        }
        let at = path.field("measures");
        let row = match &output.measures {
            Measure::Displacement(name) => single(c.ctx, Kind::Displacement, name, &at, names, second)?,
            Measure::Velocity(name) => single(c.ctx, Kind::Velocity, name, &at, names, second)?,
            Measure::Acceleration(name) => single(c.ctx, Kind::Acceleration, name, &at, names, second)?,
            Measure::State(name) => single(c.ctx, Kind::State, name, &at, names, second)?,
            Measure::Combination(terms) => {
                if terms.is_empty() {
                    return Err(c
                        .ctx
                        .invalid(&at, "a combination needs at least one term: `(Displacement(\"q1\"), 1)`"));
                }
                let mut compiled = Vec::with_capacity(terms.len());
                for (t, (term, weight)) in terms.iter().enumerate() {
                    let term_path = at.inner().index(t);
                    let (kind, name) = term_kind(term);
                    let q = quantity(c.ctx, kind, name, &term_path.index(0), names, second)?;
                    compiled.push((q, c.entry(weight, &term_path.index(1))?));
                }
                OutputRow::Terms(compiled)
            }
            Measure::Row(entries) => {
                if second {
                    return Err(c.ctx.invalid(
                        &at,
                        "`Row` is for first-order files; a second-order output measures Displacement, Velocity, Acceleration or a Combination of them",
                    ));
                }
                OutputRow::Row(c.vector(entries, n, &at.inner(), "one per state")?)
            }
        };
        let feedthrough = match &output.feedthrough {
            None => None,
            Some(_) if second => {
                return Err(c.ctx.invalid(
                    &path.field("feedthrough"),
                    "`feedthrough` is for first-order files; a second-order acceleration includes M⁻¹F u by itself",
                ));
            }
            Some(_) if m == 0 => {
                return Err(c.ctx.invalid(
                    &path.field("feedthrough"),
                    "the model has no inputs; remove `feedthrough` or declare inputs",
                ));
            }
            Some(entries) => Some(c.vector(entries, m, &path.field("feedthrough"), "one per input")?),
        };
        out.push((
            Named { name: column.clone(), unit: output.unit.clone() },
            CompiledOutput { row, feedthrough },
        ));
    }
    Ok(out)
}

fn single(
    ctx: &Ctx,
    kind: Kind,
    name: &str,
    path: &Path,
    names: &[String],
    second: bool,
) -> Result<OutputRow, StructureError> {
    Ok(OutputRow::Terms(vec![(quantity(ctx, kind, name, path, names, second)?, Coef::Num(1.0))]))
}
