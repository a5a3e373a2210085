//! Validation of a model file and compilation of its entries, with located errors.
//!
//! The order follows the file's dependencies: parameters (names, values, bounds), derived names
//! (each an expression of the parameters and the derived names above it, evaluated at the
//! file's values), the structure's matrices and inputs, the outputs and the initial state
//! (every entry compiled and evaluated at the file's values), and finally the assembled model
//! at the file's values (a singular mass matrix, a modal damping that cannot be formed, a
//! non-finite matrix). Each error names the origin, line and column of what is wrong.

mod dynamics;

use crate::assemble::{Coef, Compiled, MASS, MODAL};
use crate::scan::{AtomKind, Node, Path, Tree, line_column};
use crate::schema::{Entry, ModelFile, Parameters};
use crate::{Expr, ExprError, StructureError};

/// One parameter as declared.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ParamInfo {
    pub name: String,
    pub value: f64,
    pub free: bool,
    pub bounds: Option<(f64, f64)>,
    pub typical: Option<f64>,
    pub unit: Option<String>,
    pub description: Option<String>,
}

/// A named input or output column with its unit.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Named {
    pub name: String,
    pub unit: Option<String>,
}

/// A validated, compiled file.
#[derive(Clone, Debug)]
pub(crate) struct Checked {
    pub compiled: Compiled,
    pub params: Vec<ParamInfo>,
    pub coordinates: Vec<String>,
    pub inputs: Vec<Named>,
    pub outputs: Vec<Named>,
    pub hold: mem::Hold,
}

/// The text and origin of a file, for locating errors.
pub(crate) struct Ctx<'a> {
    text: &'a str,
    origin: &'a str,
    tree: Tree,
}

impl<'a> Ctx<'a> {
    pub fn new(text: &'a str, origin: &'a str) -> Self {
        Ctx { text, origin, tree: Tree::parse(text) }
    }

    /// Line and column of the value at `path` (or of as much of the path as exists).
    fn at(&self, path: &Path) -> (usize, usize) {
        line_column(self.text, self.tree.find(path).0)
    }

    /// Line and column of byte `offset` of the decoded string at `path`; for a name (a string
    /// or a map key), offset 0 is its first character.
    fn in_string(&self, path: &Path, offset: usize) -> (usize, usize) {
        let (start, node) = self.tree.find(path);
        let raw = match node {
            Some(Node::Atom { kind: AtomKind::Str(literal), .. }) => {
                literal.raw.get(offset).or(literal.raw.last()).copied().unwrap_or(start)
            }
            _ if self.text[start..].starts_with('"') => start + 1,
            _ => start,
        };
        line_column(self.text, raw)
    }

    /// A problem with the value at `path`.
    pub fn invalid(&self, path: &Path, message: impl Into<String>) -> StructureError {
        let (line, column) = self.at(path);
        self.invalid_at(path, line, column, message.into())
    }

    /// A problem with the name (string or map key) at `path`, located at its first character.
    pub fn invalid_name(&self, path: &Path, message: impl Into<String>) -> StructureError {
        let (line, column) = self.in_string(path, 0);
        self.invalid_at(path, line, column, message.into())
    }

    fn invalid_at(&self, path: &Path, line: usize, column: usize, message: String) -> StructureError {
        StructureError::Invalid {
            origin: self.origin.to_string(),
            line,
            column,
            field: path.to_string(),
            message,
        }
    }

    /// An impossible number at `path`.
    pub fn invalid_value(&self, path: &Path, value: f64, requirement: impl Into<String>) -> StructureError {
        let (line, column) = self.at(path);
        StructureError::InvalidValue {
            origin: self.origin.to_string(),
            line,
            column,
            field: path.to_string(),
            value,
            requirement: requirement.into(),
        }
    }

    /// An expression error at `path`, located at the offending character.
    pub fn expression(&self, path: &Path, source: ExprError) -> StructureError {
        let (line, column) = self.in_string(path, source.offset().unwrap_or(0));
        StructureError::Expression {
            origin: self.origin.to_string(),
            line,
            column,
            field: path.to_string(),
            source,
        }
    }

    /// A problem at byte `offset` of the expression at `path`.
    fn invalid_in_string(&self, path: &Path, offset: usize, message: String) -> StructureError {
        let (line, column) = self.in_string(path, offset);
        self.invalid_at(path, line, column, message)
    }
}

/// Compiles entries against all names (parameters, then derived) and checks them at the file's
/// values.
pub(crate) struct Compiler<'a> {
    pub ctx: &'a Ctx<'a>,
    names: Vec<&'a str>,
    values: &'a [f64],
}

impl Compiler<'_> {
    /// One entry: a finite number, or an expression that parses and is finite at the file's
    /// values.
    pub fn entry(&self, entry: &Entry, path: &Path) -> Result<Coef, StructureError> {
        match entry {
            Entry::Number(value) if value.is_finite() => Ok(Coef::Num(*value)),
            Entry::Number(value) => Err(self.ctx.invalid_value(path, *value, "must be a finite number")),
            Entry::Expression(text) => {
                let expr = Expr::parse(text, &self.names).map_err(|e| self.ctx.expression(path, e))?;
                expr.eval_checked(self.values).map_err(|e| {
                    self.ctx.invalid(
                        path,
                        format!("{e} at the file's parameter values; check the expression and the values"),
                    )
                })?;
                Ok(match expr.as_constant() {
                    Some(value) => Coef::Num(value),
                    None => Coef::Expr(expr),
                })
            }
        }
    }

    /// A vector of `n` entries (`what` says what they are, for the message).
    pub fn vector(
        &self,
        entries: &[Entry],
        n: usize,
        path: &Path,
        what: &str,
    ) -> Result<Vec<Coef>, StructureError> {
        if entries.len() != n {
            return Err(self
                .ctx
                .invalid(path, format!("has {} entries; it needs {n}, {what}", entries.len())));
        }
        entries.iter().enumerate().map(|(i, e)| self.entry(e, &path.index(i))).collect()
    }

    /// An `n_rows` × `n_cols` matrix, row-major.
    pub fn matrix(
        &self,
        rows: &[Vec<Entry>],
        n_rows: usize,
        n_cols: usize,
        path: &Path,
        what: &str,
    ) -> Result<Vec<Coef>, StructureError> {
        if rows.len() != n_rows {
            return Err(self
                .ctx
                .invalid(path, format!("has {} rows; it must be {n_rows} × {n_cols}, {what}", rows.len())));
        }
        let mut out = Vec::with_capacity(n_rows * n_cols);
        for (i, row) in rows.iter().enumerate() {
            let row_path = path.index(i);
            if row.len() != n_cols {
                return Err(self.ctx.invalid(
                    &row_path,
                    format!(
                        "row {i} has {} entries; the matrix must be {n_rows} × {n_cols}, {what}",
                        row.len()
                    ),
                ));
            }
            for (j, entry) in row.iter().enumerate() {
                out.push(self.entry(entry, &row_path.index(j))?);
            }
        }
        Ok(out)
    }
}

/// Validates and compiles a parsed file.
pub(crate) fn compile(file: &ModelFile, ctx: &Ctx) -> Result<Checked, StructureError> {
    let params = parameters(ctx, &file.parameters)?;
    let mut names: Vec<String> = params.iter().map(|p| p.name.clone()).collect();
    let mut values: Vec<f64> = params.iter().map(|p| p.value).collect();
    let derived = derived(ctx, &file.derived, &mut names, &mut values)?;
    let compiler = Compiler { ctx, names: names.iter().map(String::as_str).collect(), values: &values };
    let (dynamics, coordinates, inputs) = dynamics::structure(&compiler, &file.structure, &file.initial)?;
    let outputs = dynamics::outputs(&compiler, &file.outputs, &dynamics, &coordinates, &inputs)?;
    let compiled = Compiled {
        n_params: params.len(),
        derived,
        dynamics,
        outputs: outputs.iter().map(|(_, o)| o.clone()).collect(),
    };
    let structure = Path::default().field("structure");
    let p: Vec<f64> = params.iter().map(|p| p.value).collect();
    compiled.state_space::<f64>(&p).map_err(|e| match &e {
        StructureError::Assembly { part, reason } if part == MASS => {
            ctx.invalid(&structure.field("mass"), format!("{reason} (at the file's values)"))
        }
        StructureError::Assembly { part, reason } if part == MODAL => {
            ctx.invalid(&structure.field("damping"), format!("{reason} (at the file's values)"))
        }
        _ => ctx.invalid(&structure, format!("{e}")),
    })?;
    // Kinetic energy ½ q̇ᵀ M q̇ is positive for every motion: a negative mass is caught here, a
    // singular one above.
    if !compiled.positive_mass(&p).unwrap_or(true) {
        return Err(ctx.invalid(
            &structure.field("mass"),
            format!("{} (at the file's values)", crate::assemble::NOT_POSITIVE_MASS),
        ));
    }
    let hold = match file.hold {
        crate::schema::HoldKind::Zero => mem::Hold::Zero,
        crate::schema::HoldKind::FirstOrder => mem::Hold::FirstOrder,
    };
    Ok(Checked {
        compiled,
        params,
        coordinates,
        inputs,
        outputs: outputs.into_iter().map(|(named, _)| named).collect(),
        hold,
    })
}

/// Why `name` cannot be a parameter or derived name (invalid or reserved), if it cannot.
fn bad_name(name: &str) -> Option<String> {
    Expr::parse("0", &[name]).err().map(|e| e.to_string())
}

fn parameters(ctx: &Ctx, parameters: &Parameters) -> Result<Vec<ParamInfo>, StructureError> {
    let root = Path::default().field("parameters");
    let mut out: Vec<ParamInfo> = Vec::with_capacity(parameters.0.len());
    for (i, (name, p)) in parameters.0.iter().enumerate() {
        let key = root.key(i, name);
        let path = root.entry(i, name);
        if let Some(reason) = bad_name(name) {
            return Err(ctx.invalid_name(&key, reason));
        }
        if out.iter().any(|q| &q.name == name) {
            return Err(ctx.invalid_name(
                &key,
                format!("parameter `{name}` is declared twice; names must be distinct"),
            ));
        }
        if !p.value.is_finite() {
            return Err(ctx.invalid_value(&path.field("value"), p.value, "must be a finite number"));
        }
        if let Some((lower, upper)) = p.bounds {
            if lower.is_nan() || upper.is_nan() || lower >= upper {
                return Err(ctx.invalid(
                    &path.field("bounds"),
                    format!("bounds ({lower}, {upper}): the lower bound must be below the upper bound"),
                ));
            }
            if !(lower..=upper).contains(&p.value) {
                return Err(ctx.invalid_value(
                    &path.field("value"),
                    p.value,
                    format!("must lie within its bounds [{lower}, {upper}]; change the value or the bounds"),
                ));
            }
        }
        if let Some(typical) = p.typical
            && !(typical.is_finite() && typical > 0.0)
        {
            return Err(ctx.invalid_value(
                &path.field("typical"),
                typical,
                "must be a finite positive size (the parameter's usual magnitude)",
            ));
        }
        out.push(ParamInfo {
            name: name.clone(),
            value: p.value,
            free: p.free,
            bounds: p.bounds,
            typical: p.typical,
            unit: p.unit.clone(),
            description: p.description.clone(),
        });
    }
    Ok(out)
}

/// Compiles the derived names in order, appending each name and its value at the file's
/// parameter values to `names` and `values`.
fn derived(
    ctx: &Ctx,
    derived: &[(String, Entry)],
    names: &mut Vec<String>,
    values: &mut Vec<f64>,
) -> Result<Vec<Coef>, StructureError> {
    let root = Path::default().field("derived");
    let n_params = names.len();
    let mut out = Vec::with_capacity(derived.len());
    for (i, (name, entry)) in derived.iter().enumerate() {
        let path = root.index(i);
        let name_path = path.index(0);
        let expr_path = path.index(1);
        if let Some(reason) = bad_name(name) {
            return Err(ctx.invalid_name(&name_path, reason));
        }
        if let Some(at) = names.iter().position(|n| n == name) {
            let what = if at < n_params { "a parameter" } else { "a derived name above" };
            return Err(
                ctx.invalid_name(&name_path, format!("`{name}` is already {what}; names must be distinct"))
            );
        }
        let coef = match entry {
            Entry::Number(value) if value.is_finite() => Coef::Num(*value),
            Entry::Number(value) => {
                return Err(ctx.invalid_value(&expr_path, *value, "must be a finite number"));
            }
            Entry::Expression(text) => {
                let known: Vec<&str> = names.iter().map(String::as_str).collect();
                let expr = Expr::parse(text, &known).map_err(|e| match &e {
                    ExprError::UnknownName { name: used, offset, .. }
                        if derived[i..].iter().any(|(later, _)| later == used) =>
                    {
                        let which = if used == name { "itself" } else { "a derived name defined further down" };
                        ctx.invalid_in_string(
                            &expr_path,
                            *offset,
                            format!(
                                "derived `{name}` uses `{used}`, which is {which}; a derived name may use only \
                                 the parameters and the derived names above it (reorder the list; no cycles)"
                            ),
                        )
                    }
                    _ => ctx.expression(&expr_path, e),
                })?;
                Coef::Expr(expr)
            }
        };
        let value = match &coef {
            Coef::Num(value) => *value,
            Coef::Expr(expr) => expr.eval_checked(values).map_err(|e| {
                ctx.invalid(
                    &expr_path,
                    format!("{e} at the file's parameter values; check the expression and the values"),
                )
            })?,
        };
        names.push(name.clone());
        values.push(value);
        out.push(coef);
    }
    Ok(out)
}
