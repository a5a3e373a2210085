//! A [`StructureModel`] as text: written back with its current values, its RON errors located,
//! and whether a text is a structure file at all.

use super::StructureModel;
use crate::scan::{self, Tree};
use crate::{StructureError, schema, write};

impl StructureModel {
    /// The model file with the current parameter values written in.
    ///
    /// The file's own text is kept — comments, layout, expressions — and only the `value:` of
    /// each parameter whose value changed is rewritten (in Rust's shortest round-trip form).
    /// Should the text not allow that, the file is written anew from its parsed content (same
    /// model, without comments). Reading the result back gives the same model with the current
    /// values, provided the model can be assembled at them (a file whose masses were set to zero,
    /// say, is written but rejected when read).
    pub fn to_ron(&self) -> String {
        let file_values: Vec<f64> = self.checked.params.iter().map(|p| p.value).collect();
        if self.effects != self.file.effects {
            return self.rewritten();
        }
        if let Some(text) =
            write::patch_values(&self.text, &Tree::parse(&self.text), &file_values, &self.values)
            && self.reads_back(&text)
        {
            return text;
        }
        self.rewritten()
    }

    /// The file written anew from its parsed content with the current values (no comments).
    pub(super) fn rewritten(&self) -> String {
        let mut file = self.file.clone();
        for ((_, parameter), value) in file.parameters.0.iter_mut().zip(&self.values) {
            parameter.value = *value;
        }
        file.effects = self.effects.clone();
        schema::to_string(&file)
    }

    /// Whether `text` reads back as a model with the current values.
    fn reads_back(&self, text: &str) -> bool {
        StructureModel::from_ron(text, &self.origin)
            .is_ok_and(|m| m.values().iter().zip(&self.values()).all(|(a, b)| a.to_bits() == b.to_bits()))
    }

    /// The file's text as read.
    pub fn source(&self) -> &str {
        &self.text
    }
}

/// A RON error, located at the offending identifier for an unknown field or variant (RON
/// reports the position after it).
pub(super) fn syntax_error(text: &str, origin: &str, e: &ron::error::SpannedError) -> StructureError {
    let (mut line, mut column) = (e.position.line, e.position.col);
    let ident = match &e.code {
        ron::Error::NoSuchStructField { found, .. } | ron::Error::NoSuchEnumVariant { found, .. } => {
            Some(found.as_str())
        }
        ron::Error::DuplicateStructField { field, .. } => Some(*field),
        _ => None,
    };
    if let Some(at) =
        ident.and_then(|ident| scan::ident_before(text, scan::offset_of(text, line, column), ident))
    {
        (line, column) = scan::line_column(text, at);
    }
    StructureError::Syntax { origin: origin.to_string(), line, column, message: e.code.to_string() }
}

/// Whether RON text is a structure model file (its top-level value has a `structure:` field)
/// rather than a slewing-rig file. Comments and string contents are not mistaken for the field;
/// the text need not be valid.
pub fn is_structure_file(text: &str) -> bool {
    crate::scan::has_top_level_field(text, "structure")
}
