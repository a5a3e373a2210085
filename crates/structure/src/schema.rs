//! The model file's schema: what serde reads from (and writes to) RON.
//!
//! These types hold the file as written; [`crate::compile`] validates them and turns every entry
//! into a compiled expression. Optional fields may be written bare (`unit: "kg"`) or as
//! `Some("kg")`: the file is read with RON's `implicit_some` extension.

use serde::de::{self, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;

/// The whole model file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ModelFile {
    pub name: String,
    pub parameters: Parameters,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub derived: Vec<(String, Entry)>,
    pub structure: Structure,
    #[serde(default, skip_serializing_if = "HoldKind::is_zero")]
    pub hold: HoldKind,
    pub outputs: Vec<Output>,
    #[serde(default)]
    pub initial: Initial,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effects: Vec<crate::effects::Effect>,
}

/// A matrix or vector entry: a number or an expression of the parameters and derived names.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Entry {
    Number(f64),
    Expression(String),
}

impl Serialize for Entry {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Entry::Number(value) => serializer.serialize_f64(*value),
            Entry::Expression(text) => serializer.serialize_str(text),
        }
    }
}

/// Reads a number or a string like an untagged enum, but without buffering the value, so that an
/// entry of the wrong type is reported where it stands, with a message that says what fits.
impl<'de> Deserialize<'de> for Entry {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct EntryVisitor;
        impl Visitor<'_> for EntryVisitor {
            type Value = Entry;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or a string holding an expression such as \"k1 + k2\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Entry, E> {
                Ok(Entry::Number(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Entry, E> {
                Ok(Entry::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Entry, E> {
                Ok(Entry::Number(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Entry, E> {
                Ok(Entry::Expression(v.to_string()))
            }
        }
        deserializer.deserialize_any(EntryVisitor)
    }
}

/// The parameters in the order the file declares them (a map that keeps its order and its
/// repeated keys, so that a repeated name can be reported where it stands).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Parameters(pub Vec<(String, Parameter)>);

impl Serialize for Parameters {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, parameter) in &self.0 {
            map.serialize_entry(name, parameter)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for Parameters {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct OrderedVisitor;
        impl<'de> Visitor<'de> for OrderedVisitor {
            type Value = Parameters;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a map from parameter names to (value: …, …)")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Parameters, A::Error> {
                let mut out = Vec::with_capacity(map.size_hint().unwrap_or(0));
                while let Some(entry) = map.next_entry::<String, Parameter>()? {
                    out.push(entry);
                }
                Ok(Parameters(out))
            }
        }
        deserializer.deserialize_map(OrderedVisitor)
    }
}

/// One parameter's declaration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Parameter {
    pub value: f64,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub unit: Option<String>,
    #[serde(default, skip_serializing_if = "is_false")]
    pub free: bool,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub bounds: Option<(f64, f64)>,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub typical: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub description: Option<String>,
}

/// The dynamics: second order in coordinates, or first order in states.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) enum Structure {
    SecondOrder {
        coordinates: Vec<String>,
        mass: Vec<Vec<Entry>>,
        stiffness: Vec<Vec<Entry>>,
        damping: Damping,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        inputs: Vec<Input>,
    },
    FirstOrder {
        states: Vec<String>,
        a: Vec<Vec<Entry>>,
        #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
        b: Option<Vec<Vec<Entry>>>,
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        inputs: Vec<Input>,
    },
}

/// How the damping matrix is given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) enum Damping {
    Matrix(Vec<Vec<Entry>>),
    Rayleigh { alpha: Entry, beta: Entry },
    Modal(Vec<Entry>),
}

/// A measured input.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Input {
    pub name: String,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub unit: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub force: Option<Vec<Entry>>,
}

/// How inputs are held between samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) enum HoldKind {
    #[default]
    Zero,
    FirstOrder,
}

impl HoldKind {
    fn is_zero(&self) -> bool {
        *self == HoldKind::Zero
    }
}

/// One output: a CSV column and what it measures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Output {
    pub column: String,
    pub measures: Measure,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub unit: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub feedthrough: Option<Vec<Entry>>,
}

/// What an output measures.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) enum Measure {
    Displacement(String),
    Velocity(String),
    Acceleration(String),
    State(String),
    Combination(Vec<(Term, Entry)>),
    Row(Vec<Entry>),
}

/// One term of a combination.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(crate) enum Term {
    Displacement(String),
    Velocity(String),
    Acceleration(String),
    State(String),
}

/// The initial state: displacement and velocity (second order) or state (first order); what is
/// not given is zero.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct Initial {
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub displacement: Option<Vec<Entry>>,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub velocity: Option<Vec<Entry>>,
    #[serde(default, skip_serializing_if = "Option::is_none", serialize_with = "bare")]
    pub state: Option<Vec<Entry>>,
}

fn is_false(value: &bool) -> bool {
    !*value
}

/// Writes an `Option` that is `Some` (the `None`s are skipped) as its bare value, which the
/// reader's `implicit_some` accepts.
fn bare<T: Serialize, S: Serializer>(value: &Option<T>, serializer: S) -> Result<S::Ok, S::Error> {
    match value {
        Some(value) => value.serialize(serializer),
        None => serializer.serialize_none(),
    }
}

/// Reads a model file (RON with `implicit_some`).
pub(crate) fn from_str(text: &str) -> Result<ModelFile, ron::error::SpannedError> {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME).from_str(text)
}

/// Writes a model file as pretty RON.
pub(crate) fn to_string(file: &ModelFile) -> String {
    let config = ron::ser::PrettyConfig::new().struct_names(false).depth_limit(4);
    ron::ser::to_string_pretty(file, config).unwrap_or_else(|e| format!("// cannot write the model: {e}\n"))
}
