//! The machinery every flat library is described with: a record, the types
//! of its fields, what a field accepts, the library's table, the typed
//! error of a library operation, and a field's value as text and back.

use gearcam_proto::Code;
use gearcam_proto::{JobError, Stage};
use serde_json::{Map, Value};

use crate::KnowledgeError;

use Check::{Any, Id, OneOf, Positive, Range};
use Kind::{Bool, Int, Real, Text};

/// A record: field name → value.
pub type Record = Map<String, Value>;

/// The type of a field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A floating-point number.
    Real,
    /// An integer.
    Int,
    /// A string.
    Text,
    /// A boolean (stored as 0/1).
    Bool,
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Kind::Real => "number",
            Kind::Int => "integer",
            Kind::Text => "text",
            Kind::Bool => "true/false",
        })
    }
}

/// What values a field accepts beyond its type.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Check {
    /// Any value of the type.
    Any,
    /// A number in `[min, max]`.
    Range(f64, f64),
    /// A number greater than zero (and finite).
    Positive,
    /// One of these strings.
    OneOf(&'static [&'static str]),
    /// An id: 1–64 characters from `A–Z a–z 0–9 _ - .`, starting with a letter or digit
    /// (safe inside a key expression and a file name).
    Id,
}

/// Whether a field must be given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Need {
    /// Must be given.
    Required,
    /// May be absent (stored as NULL).
    Optional,
    /// Takes this value when absent.
    Default(Def),
}

impl std::fmt::Display for Need {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Need::Required => f.write_str("required"),
            Need::Optional => f.write_str("optional"),
            Need::Default(Def::Real(v)) => write!(f, "default {v}"),
            Need::Default(Def::Int(v)) => write!(f, "default {v}"),
            Need::Default(Def::Text(v)) => write!(f, "default {v:?}"),
            Need::Default(Def::Bool(v)) => write!(f, "default {v}"),
        }
    }
}

/// A default value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Def {
    /// A number.
    Real(f64),
    /// An integer.
    Int(i64),
    /// A string.
    Text(&'static str),
    /// A boolean.
    Bool(bool),
}

/// One field of a library.
#[derive(Debug, Clone, Copy)]
pub struct Field {
    /// Name (also the SQL column and CSV header).
    pub name: &'static str,
    /// Type.
    pub kind: Kind,
    /// Required, optional or defaulted.
    pub need: Need,
    /// Allowed values.
    pub check: Check,
    /// What it means, with its unit.
    pub doc: &'static str,
}

/// A library: its name on the CLI and the bus, its table and key field.
#[derive(Debug, Clone, Copy)]
pub struct Library {
    /// Name, e.g. `hobs` (`gearcam kb hobs`, `gearcam/v1/kb/hobs`).
    pub name: &'static str,
    /// SQLite table.
    pub table: &'static str,
    /// The key field.
    pub key: &'static str,
    /// What it holds.
    pub doc: &'static str,
    /// Fields (empty for machines, whose record is a whole profile).
    pub fields: &'static [Field],
    /// Whether the library can be imported from and exported to CSV.
    pub csv: bool,
}

impl Library {
    /// The columns of a flat library's table, in field order, as an SQL
    /// column list (`id, module_mm, ...`); empty for machines.
    pub fn columns(&self) -> String {
        self.fields
            .iter()
            .map(|f| f.name)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The outcome of a library operation: the records, or every error.
pub type Outcome<T> = Result<T, Vec<JobError>>;

fn internal(e: KnowledgeError) -> Vec<JobError> {
    // A file that is not CSV is the file's fault, not the database's.
    if let KnowledgeError::Csv(csv) = &e {
        return vec![Stage::Knowledge.error(
            Code::CSV_UNREADABLE,
            "file",
            "a UTF-8 CSV file with a header of the library's columns (gearcam kb export LIBRARY shows one)",
            csv.to_string(),
            "the file given is not CSV text the library can import; nothing was imported",
        )];
    }
    vec![Stage::Knowledge.error(
        Code::KNOWLEDGE_BASE_ERROR,
        "-",
        "a readable, writable knowledge base",
        e.to_string(),
        "the knowledge base could not be read or written; check the database file",
    )]
}

impl From<KnowledgeError> for Vec<JobError> {
    fn from(e: KnowledgeError) -> Self {
        internal(e)
    }
}

pub(super) fn expected_of(field: &Field) -> String {
    let t = match field.kind {
        Real => "a number",
        Int => "an integer",
        Text => "a string",
        Bool => "true or false",
    };
    match field.check {
        Any => t.to_string(),
        Range(lo, hi) => format!("{t} in [{lo}, {hi}]"),
        Positive => format!("{t} > 0"),
        OneOf(v) => format!("one of {}", v.join(", ")),
        Id => "an id: 1–64 characters A–Z a–z 0–9 _ - . starting with a letter or digit".into(),
    }
}

/// Parses a value given as text (CLI `--set name=value`, CSV cell) by the
/// field's type. Nested machine fields and unknown names are read as JSON
/// when they parse, else as a string. An empty text is NULL.
pub fn parse_value(lib: &Library, name: &str, text: &str) -> Result<Value, JobError> {
    let t = text.trim();
    if t.is_empty() {
        return Ok(Value::Null);
    }
    let Some(field) = lib.fields.iter().find(|f| f.name == name) else {
        return Ok(serde_json::from_str(t).unwrap_or_else(|_| Value::from(t)));
    };
    let bad = || {
        Stage::Knowledge.error(
            Code::FIELD_INVALID,
            name,
            expected_of(field),
            format!("{t:?}"),
            format!("{name}: {}", field.doc),
        )
    };
    Ok(match field.kind {
        Real => Value::from(t.parse::<f64>().map_err(|_| bad())?),
        Int => Value::from(t.parse::<i64>().map_err(|_| bad())?),
        Bool => match t.to_ascii_lowercase().as_str() {
            "true" | "yes" | "1" => Value::from(true),
            "false" | "no" | "0" => Value::from(false),
            _ => return Err(bad()),
        },
        Text => Value::from(t),
    })
}

/// A record as text for a CSV cell / a table cell.
pub fn cell(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}
