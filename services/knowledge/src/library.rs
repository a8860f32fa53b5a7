//! The knowledge base's libraries as records: list, read, add, change, remove,
//! each write validated field by field.
//!
//! A record is a JSON object (field name → value). Every flat library is
//! described by a table of [`Field`]s (name, type, required or default,
//! allowed range); the same description drives the SQL, the validation, the
//! CSV columns and the CLI's value parsing, so a new field is added in one
//! place. Machines are nested profiles ([`gearcam_proto::MachineProfile`])
//! stored as JSON and validated by deserialising them.
//!
//! Every error is a [`JobError`] (stage `knowledge`) naming the field, what
//! was expected and what was given.

use gearcam_proto::{JobError, MachineProfile, Stage};
use rusqlite::types::Value as SqlValue;
use rusqlite::{params_from_iter, Connection, OptionalExtension};
use serde_json::{Map, Value};

use crate::KnowledgeError;

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

const fn f(name: &'static str, kind: Kind, need: Need, check: Check, doc: &'static str) -> Field {
    Field {
        name,
        kind,
        need,
        check,
        doc,
    }
}

use Check::{Any, Id, OneOf, Positive, Range};
use Kind::{Bool, Int, Real, Text};
use Need::{Optional, Required};

const HANDS: &[&str] = &["right", "left"];
const CLASSES: &[&str] = &[
    "cylindrical",
    "conical",
    "worm_wheel",
    "crowned",
    "curved_tooth",
    "multi_gear",
];
const ACCURACY: &[&str] = &["AA", "A", "B", "C"];
const OPERATIONS: &[&str] = &["rough", "finish"];
const OUTCOMES: &[&str] = &["ok", "rework", "scrap", "unknown"];
const CUT_MODES: &[&str] = &["conventional", "climb"];
const JOB_STATES: &[&str] = &["planned", "delivered", "confirmed"];

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

/// The group-technology class tree (docs/knowledge.md#group-technology-classes).
pub const CLASSES_LIB: Library = Library {
    name: "classes",
    table: "gt_classes",
    key: "id",
    doc: "group-technology class tree (docs/knowledge.md#group-technology-classes)",
    csv: false,
    fields: &[
        f("id", Text, Required, Id, "class id, e.g. cylindrical"),
        f(
            "parent",
            Text,
            Optional,
            Id,
            "parent class id (absent for the root)",
        ),
        f("name", Text, Required, Any, "human name"),
        f(
            "tooth_trace",
            Text,
            Required,
            Any,
            "tooth trace / generating line",
        ),
        f(
            "deformation",
            Text,
            Required,
            Any,
            "deformation along the face width",
        ),
        f("hobbing_method", Text, Required, Any, "how it is hobbed"),
        f(
            "programmable",
            Bool,
            Need::Default(Def::Bool(false)),
            Any,
            "whether gearcam programs it in this release",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the entry comes from",
        ),
    ],
};

/// Workpieces: drawing data by part number.
pub const WORKPIECES: Library = Library {
    name: "workpieces",
    table: "workpieces",
    key: "part_number",
    doc: "workpieces: drawing data by part number",
    csv: true,
    fields: &[
        f("part_number", Text, Required, Id, "drawing number"),
        f(
            "description",
            Text,
            Need::Default(Def::Text("")),
            Any,
            "what the part is",
        ),
        f(
            "class",
            Text,
            Need::Default(Def::Text("cylindrical")),
            OneOf(CLASSES),
            "group-technology class",
        ),
        f(
            "module_mm",
            Real,
            Required,
            Positive,
            "normal module mn, mm",
        ),
        f(
            "teeth",
            Int,
            Required,
            Range(1.0, 10000.0),
            "number of teeth z",
        ),
        f(
            "pressure_angle_deg",
            Real,
            Need::Default(Def::Real(20.0)),
            Range(5.0, 45.0),
            "normal pressure angle αn, degrees",
        ),
        f(
            "helix_angle_deg",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 89.0),
            "helix angle β magnitude, degrees",
        ),
        f(
            "helix_hand",
            Text,
            Optional,
            OneOf(HANDS),
            "hand of the helix (required when β ≠ 0)",
        ),
        f(
            "face_width_mm",
            Real,
            Required,
            Positive,
            "face width b, mm",
        ),
        f(
            "profile_shift",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(-3.0, 3.0),
            "profile shift coefficient x",
        ),
        f(
            "addendum_coef",
            Real,
            Need::Default(Def::Real(1.0)),
            Range(0.0, 3.0),
            "addendum coefficient ha*",
        ),
        f(
            "clearance_coef",
            Real,
            Need::Default(Def::Real(0.25)),
            Range(0.0, 1.0),
            "tip clearance coefficient c*",
        ),
        f(
            "blank_od_mm",
            Real,
            Optional,
            Positive,
            "blank outside diameter Da1, mm",
        ),
        f(
            "od_correction_mm",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(-50.0, 50.0),
            "X correction Δx, mm",
        ),
        f(
            "material",
            Text,
            Need::Default(Def::Text("unspecified")),
            Any,
            "material, e.g. 20CrMnTi",
        ),
        f(
            "hardness_hb",
            Real,
            Optional,
            Range(50.0, 700.0),
            "hardness when hobbed, HB",
        ),
        f(
            "quality_grade",
            Int,
            Need::Default(Def::Int(8)),
            Range(1.0, 12.0),
            "accuracy grade (ISO 1328)",
        ),
        f(
            "fixture_height_mm",
            Real,
            Required,
            Range(0.0, 2000.0),
            "H: lower tooth face above the table, mm",
        ),
        f(
            "cone_angle_deg",
            Real,
            Optional,
            Range(0.0, 45.0),
            "cone angle δ of a conical gear, degrees",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the data comes from",
        ),
    ],
};

/// Hobs: the tool library.
pub const HOBS: Library = Library {
    name: "hobs",
    table: "hobs",
    key: "id",
    doc: "hobs: geometry, accuracy class, material, coating, shift position, remaining life",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "hob id"),
        f(
            "module_mm",
            Real,
            Required,
            Positive,
            "normal module mn0, mm",
        ),
        f(
            "pressure_angle_deg",
            Real,
            Need::Default(Def::Real(20.0)),
            Range(5.0, 45.0),
            "normal pressure angle α0, degrees",
        ),
        f(
            "starts",
            Int,
            Required,
            Range(1.0, 12.0),
            "number of starts z0",
        ),
        f("hand", Text, Required, OneOf(HANDS), "hand of the thread"),
        f(
            "lead_angle_deg",
            Real,
            Required,
            Range(0.0, 45.0),
            "lead angle γ0, degrees",
        ),
        f(
            "od_mm",
            Real,
            Required,
            Positive,
            "outside diameter da0, mm",
        ),
        f("length_mm", Real, Required, Positive, "overall length, mm"),
        f(
            "usable_length_mm",
            Real,
            Required,
            Positive,
            "usable (cutting) length, mm",
        ),
        f(
            "accuracy_class",
            Text,
            Need::Default(Def::Text("A")),
            OneOf(ACCURACY),
            "accuracy class (DIN 3968)",
        ),
        f(
            "material",
            Text,
            Need::Default(Def::Text("HSS")),
            Any,
            "cutting material, e.g. HSS, PM-HSS, carbide",
        ),
        f(
            "coating",
            Text,
            Need::Default(Def::Text("none")),
            Any,
            "coating, e.g. none, TiN, TiAlN, AlCrN",
        ),
        f(
            "shift_position_mm",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 1000.0),
            "current shift position from the start of the usable length, mm",
        ),
        f(
            "shift_step_mm",
            Real,
            Need::Default(Def::Real(0.5)),
            Positive,
            "shift per step, mm",
        ),
        f(
            "parts_per_shift",
            Int,
            Need::Default(Def::Int(1)),
            Range(1.0, 10000.0),
            "parts cut per shift step",
        ),
        f(
            "remaining_life_parts",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e9),
            "parts the hob can still cut before regrinding",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the data comes from",
        ),
    ],
};

/// Machines: whole profiles (see [`MachineProfile`]) plus `source`.
pub const MACHINES: Library = Library {
    name: "machines",
    table: "machines",
    key: "id",
    doc: "machines: dialect, axis names and sign conventions, M-codes, travels and limits",
    csv: false,
    fields: &[],
};

/// Machining history: cases (problem features → solution → outcome).
pub const CASES: Library = Library {
    name: "cases",
    table: "cases",
    key: "id",
    doc: "machining history: cases (features → solution → outcome) with provenance and confidence",
    csv: true,
    fields: &[
        f("id", Text, Required, Id, "case id"),
        // Problem features.
        f(
            "class",
            Text,
            Need::Default(Def::Text("cylindrical")),
            OneOf(CLASSES),
            "group-technology class",
        ),
        f("machine", Text, Optional, Id, "machine the case was cut on"),
        f("material", Text, Required, Any, "workpiece material"),
        f(
            "material_group",
            Text,
            Required,
            Any,
            "material group (hard constraint)",
        ),
        f(
            "hardness_hb",
            Real,
            Optional,
            Range(50.0, 700.0),
            "hardness when hobbed, HB",
        ),
        f("module_mm", Real, Required, Positive, "normal module, mm"),
        f("teeth", Int, Required, Range(1.0, 10000.0), "teeth"),
        f(
            "helix_angle_deg",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 89.0),
            "helix angle magnitude, degrees",
        ),
        f("face_width_mm", Real, Optional, Positive, "face width, mm"),
        f(
            "quality_grade",
            Int,
            Need::Default(Def::Int(8)),
            Range(1.0, 12.0),
            "accuracy grade",
        ),
        f(
            "hob_material",
            Text,
            Need::Default(Def::Text("HSS")),
            Any,
            "hob cutting material",
        ),
        f(
            "hob_coating",
            Text,
            Need::Default(Def::Text("none")),
            Any,
            "hob coating",
        ),
        f(
            "hob_starts",
            Int,
            Need::Default(Def::Int(1)),
            Range(1.0, 12.0),
            "hob starts",
        ),
        f(
            "hob_od_mm",
            Real,
            Optional,
            Positive,
            "hob outside diameter used, mm",
        ),
        f(
            "operation",
            Text,
            Need::Default(Def::Text("finish")),
            OneOf(OPERATIONS),
            "rough or finish hobbing",
        ),
        // Solution.
        f(
            "cutting_speed_m_min",
            Real,
            Required,
            Positive,
            "cutting speed vc, m/min",
        ),
        f(
            "feed_mm_per_rev",
            Real,
            Required,
            Positive,
            "axial feed per workpiece revolution, mm/rev",
        ),
        f("hob_rpm", Real, Optional, Positive, "hob speed used, rpm"),
        f(
            "axial_feed_mm_min",
            Real,
            Optional,
            Positive,
            "axial feed rate used, mm/min",
        ),
        f(
            "radial_feed_mm_min",
            Real,
            Optional,
            Positive,
            "radial (infeed) feed rate, mm/min",
        ),
        f(
            "cuts",
            Int,
            Need::Default(Def::Int(1)),
            Range(1.0, 10.0),
            "number of cuts",
        ),
        f(
            "allowance_mm",
            Real,
            Optional,
            Range(0.0, 20.0),
            "stock / finish allowance, mm",
        ),
        f(
            "shifting",
            Bool,
            Need::Default(Def::Bool(false)),
            Any,
            "hob shifted during the job",
        ),
        f(
            "cut_mode",
            Text,
            Optional,
            OneOf(CUT_MODES),
            "conventional or climb",
        ),
        // Outcome and trust.
        f(
            "outcome",
            Text,
            Need::Default(Def::Text("unknown")),
            OneOf(OUTCOMES),
            "ok, rework, scrap or unknown",
        ),
        f(
            "quality_achieved",
            Int,
            Optional,
            Range(1.0, 12.0),
            "grade measured",
        ),
        f("notes", Text, Need::Default(Def::Text("")), Any, "remarks"),
        f(
            "confidence",
            Real,
            Required,
            Range(0.0, 1.0),
            "how far to trust the case, 0–1",
        ),
        f(
            "provenance",
            Text,
            Required,
            Any,
            "where the values come from",
        ),
        f(
            "job_id",
            Text,
            Optional,
            Id,
            "the confirmed job it came from",
        ),
        f(
            "created_at_ms",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e15),
            "when recorded, ms since the epoch",
        ),
    ],
};

/// Jobs the knowledge service planned, and their state.
pub const JOBS: Library = Library {
    name: "jobs",
    table: "jobs",
    key: "job_id",
    doc: "jobs planned by the knowledge service, delivered and confirmed",
    csv: false,
    fields: &[
        f("job_id", Text, Required, Id, "job id"),
        f("part_number", Text, Required, Any, "part number"),
        f("machine", Text, Required, Id, "machine"),
        f("class", Text, Required, OneOf(CLASSES), "class"),
        f(
            "quantity",
            Int,
            Need::Default(Def::Int(1)),
            Range(0.0, 1e9),
            "parts ordered",
        ),
        f("hob_id", Text, Required, Any, "hob used"),
        f(
            "state",
            Text,
            Need::Default(Def::Text("planned")),
            OneOf(JOB_STATES),
            "planned, delivered or confirmed",
        ),
        f(
            "confidence",
            Real,
            Need::Default(Def::Real(0.0)),
            Range(0.0, 1.0),
            "confidence of the proposal",
        ),
        f("plan_json", Text, Required, Any, "the process plan (JSON)"),
        f("program_name", Text, Optional, Any, "delivered program"),
        f(
            "planned_at_ms",
            Int,
            Need::Default(Def::Int(0)),
            Range(0.0, 1e15),
            "when planned",
        ),
        f(
            "delivered_at_ms",
            Int,
            Optional,
            Range(0.0, 1e15),
            "when delivered",
        ),
        f(
            "confirmed_at_ms",
            Int,
            Optional,
            Range(0.0, 1e15),
            "when confirmed",
        ),
        f(
            "delivered_quantity",
            Int,
            Optional,
            Range(0.0, 1e9),
            "parts actually cut (confirm)",
        ),
        f(
            "case_id",
            Text,
            Optional,
            Id,
            "the case the confirmation made",
        ),
    ],
};

/// Materials and their groups (the case retrieval's hard constraint).
pub const MATERIALS: Library = Library {
    name: "materials",
    table: "materials",
    key: "name",
    doc: "materials: group (hard constraint of retrieval) and typical hardness",
    csv: true,
    fields: &[
        f("name", Text, Required, Any, "material name, e.g. 20CrMnTi"),
        f(
            "material_group",
            Text,
            Required,
            Any,
            "group, e.g. case_hardening_steel",
        ),
        f(
            "hardness_hb",
            Real,
            Optional,
            Range(50.0, 700.0),
            "typical hardness when hobbed, HB",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "where the data comes from",
        ),
    ],
};

/// Similarity weights of case retrieval, by feature.
pub const WEIGHTS: Library = Library {
    name: "weights",
    table: "cbr_weights",
    key: "feature",
    doc: "similarity weights of case retrieval, by feature",
    csv: false,
    fields: &[
        f(
            "feature",
            Text,
            Required,
            OneOf(crate::cbr::FEATURES),
            "feature",
        ),
        f(
            "weight",
            Real,
            Required,
            Range(0.0, 100.0),
            "weight (0 ignores the feature)",
        ),
        f(
            "source",
            Text,
            Need::Default(Def::Text("user")),
            Any,
            "who set it and why",
        ),
    ],
};

/// Every library, in the order `gearcam kb` lists them.
pub const LIBRARIES: &[Library] = &[
    CLASSES_LIB,
    WORKPIECES,
    HOBS,
    MACHINES,
    CASES,
    JOBS,
    MATERIALS,
    WEIGHTS,
];

/// A library by name.
pub fn library(name: &str) -> Result<Library, JobError> {
    LIBRARIES
        .iter()
        .find(|l| l.name == name)
        .copied()
        .ok_or_else(|| {
            kb_err(
                "UNKNOWN_LIBRARY",
                "library",
                format!("one of {}", names().join(", ")),
                name,
                "there is no such library in the knowledge base",
            )
        })
}

fn names() -> Vec<&'static str> {
    LIBRARIES.iter().map(|l| l.name).collect()
}

/// A typed knowledge-base error.
pub fn kb_err(
    code: &str,
    field: &str,
    expected: impl Into<String>,
    got: impl Into<String>,
    message: impl Into<String>,
) -> JobError {
    JobError::new(Stage::Knowledge, code, field, expected, got, message)
}

/// The outcome of a library operation: the records, or every error.
pub type Outcome<T> = Result<T, Vec<JobError>>;

fn internal(e: KnowledgeError) -> Vec<JobError> {
    vec![kb_err(
        "KNOWLEDGE_BASE_ERROR",
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

fn expected_of(field: &Field) -> String {
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

fn is_id(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars().next().is_some_and(|c| c.is_ascii_alphanumeric())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

fn show(v: &Value) -> String {
    match v {
        Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}

/// Checks one field's value; returns the normalised value (NULL for an absent optional).
fn check_field(field: &Field, v: Option<&Value>, errors: &mut Vec<JobError>) -> Value {
    let v = match v {
        None | Some(Value::Null) => match field.need {
            Need::Required => {
                errors.push(kb_err(
                    "FIELD_MISSING",
                    field.name,
                    expected_of(field),
                    "nothing",
                    format!("{} is required ({})", field.name, field.doc),
                ));
                return Value::Null;
            }
            Need::Optional => return Value::Null,
            Need::Default(d) => match d {
                Def::Real(x) => Value::from(x),
                Def::Int(x) => Value::from(x),
                Def::Text(s) => Value::from(s),
                Def::Bool(b) => Value::from(b),
            },
        },
        Some(v) => v.clone(),
    };
    let bad = |errors: &mut Vec<JobError>| {
        errors.push(kb_err(
            "FIELD_INVALID",
            field.name,
            expected_of(field),
            show(&v),
            format!("{}: {}", field.name, field.doc),
        ));
        Value::Null
    };
    let num = match (field.kind, &v) {
        (Real, Value::Number(n)) => n.as_f64(),
        (Int, Value::Number(n)) => n
            .as_i64()
            .map(|i| i as f64)
            .or_else(|| n.as_f64().filter(|x| x.fract() == 0.0)),
        (Bool, Value::Bool(_)) | (Text, Value::String(_)) => None,
        _ => return bad(errors),
    };
    if let Some(x) = num {
        let ok = x.is_finite()
            && match field.check {
                Range(lo, hi) => (lo..=hi).contains(&x),
                Positive => x > 0.0,
                _ => true,
            };
        if !ok {
            return bad(errors);
        }
        return if field.kind == Int {
            Value::from(x as i64)
        } else {
            Value::from(x)
        };
    }
    if let Value::String(s) = &v {
        let ok = match field.check {
            OneOf(allowed) => allowed.contains(&s.as_str()),
            Id => is_id(s),
            _ => true,
        };
        if !ok {
            return bad(errors);
        }
    }
    v
}

/// Validates a whole record of a flat library: unknown fields, missing
/// required fields, types and ranges, and the library's cross-field rules.
/// Returns the normalised record with every field present (NULL for absent
/// optional ones).
pub fn validate(lib: &Library, rec: &Record) -> Outcome<Record> {
    if lib.name == MACHINES.name {
        return validate_machine(rec).map(|(_, r)| r);
    }
    let mut errors = Vec::new();
    for k in rec.keys() {
        if !lib.fields.iter().any(|f| f.name == k) {
            errors.push(kb_err(
                "UNKNOWN_FIELD",
                k,
                format!(
                    "one of {}",
                    lib.fields
                        .iter()
                        .map(|f| f.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                k.as_str(),
                format!("{} records have no field {k:?}", lib.name),
            ));
        }
    }
    let mut out = Record::new();
    for field in lib.fields {
        let v = check_field(field, rec.get(field.name), &mut errors);
        out.insert(field.name.to_string(), v);
    }
    cross_checks(lib, &out, &mut errors);
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}

fn num(r: &Record, k: &str) -> Option<f64> {
    r.get(k).and_then(Value::as_f64)
}

fn cross_checks(lib: &Library, r: &Record, errors: &mut Vec<JobError>) {
    match lib.name {
        "hobs" => {
            if let (Some(u), Some(l)) = (num(r, "usable_length_mm"), num(r, "length_mm")) {
                if u > l {
                    errors.push(kb_err(
                        "FIELD_INVALID",
                        "usable_length_mm",
                        format!("≤ length_mm = {l}"),
                        u.to_string(),
                        "the usable length cannot exceed the hob's length",
                    ));
                }
                if let Some(s) = num(r, "shift_position_mm") {
                    if s > u {
                        errors.push(kb_err(
                            "FIELD_INVALID",
                            "shift_position_mm",
                            format!("≤ usable_length_mm = {u}"),
                            s.to_string(),
                            "the shift position lies inside the usable length",
                        ));
                    }
                }
            }
        }
        "workpieces" => {
            let beta = num(r, "helix_angle_deg").unwrap_or(0.0);
            if beta != 0.0 && r.get("helix_hand").is_none_or(Value::is_null) {
                errors.push(kb_err(
                    "FIELD_MISSING",
                    "helix_hand",
                    "right or left (the helix angle is not zero)",
                    "nothing",
                    "a helical gear needs the hand of its helix",
                ));
            }
        }
        _ => {}
    }
}

fn validate_machine(rec: &Record) -> Outcome<(MachineProfile, Record)> {
    let mut rec = rec.clone();
    let source = match rec.remove("source") {
        None | Some(Value::Null) => "user".to_string(),
        Some(Value::String(s)) => s,
        Some(other) => {
            return Err(vec![kb_err(
                "FIELD_INVALID",
                "source",
                "a string",
                show(&other),
                "source says where the machine data comes from",
            )])
        }
    };
    let value = Value::Object(rec);
    let profile: MachineProfile = serde_path_to_error::deserialize(&value).map_err(|e| {
        vec![kb_err(
            "FIELD_INVALID",
            &e.path().to_string(),
            "a complete machine profile (see `gearcam kb show machines H01` for one)",
            e.inner().to_string(),
            format!("machine profile field {}: {}", e.path(), e.inner()),
        )]
    })?;
    let mut errors = Vec::new();
    let l = &profile.limits;
    for (name, [lo, hi]) in [
        ("limits.module_mm", l.module_mm),
        ("limits.x_mm", l.x_mm),
        ("limits.z_mm", l.z_mm),
    ] {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            errors.push(kb_err(
                "FIELD_INVALID",
                name,
                "[min, max] with min < max",
                format!("[{lo}, {hi}]"),
                "a range's lower end must lie below its upper end",
            ));
        }
    }
    for (name, v) in [
        ("limits.max_workpiece_od_mm", l.max_workpiece_od_mm),
        ("limits.max_hob_od_mm", l.max_hob_od_mm),
        ("limits.max_hob_rpm", l.max_hob_rpm),
        ("limits.max_table_rpm", l.max_table_rpm),
        ("limits.max_axial_feed_mm_min", l.max_axial_feed_mm_min),
        ("limits.max_swivel_deg", l.max_swivel_deg),
    ] {
        if !(v.is_finite() && v > 0.0) {
            errors.push(kb_err(
                "FIELD_INVALID",
                name,
                "a number > 0",
                v.to_string(),
                "machine limits are positive",
            ));
        }
    }
    let s = profile.settings.swivel_sign;
    if s != 1.0 && s != -1.0 {
        errors.push(kb_err(
            "FIELD_INVALID",
            "settings.swivel_sign",
            "1 or -1",
            s.to_string(),
            "the swivel axis sign: A = swivel_sign·η + swivel_offset_deg (docs/hobbing.md)",
        ));
    }
    for (name, axis) in [
        ("axes.radial", &profile.axes.radial),
        ("axes.axial", &profile.axes.axial),
        ("axes.swivel", &profile.axes.swivel),
        ("axes.hob", &profile.axes.hob),
        ("axes.table", &profile.axes.table),
        ("axes.shift", &profile.axes.shift),
    ] {
        if axis.is_empty()
            || axis.len() > 8
            || !axis.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            errors.push(kb_err(
                "FIELD_INVALID",
                name,
                "an axis name of 1–8 letters, digits or _",
                format!("{axis:?}"),
                "axis names are written into NC programs",
            ));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut out = match serde_json::to_value(&profile) {
        Ok(Value::Object(m)) => m,
        _ => Record::new(),
    };
    out.insert("source".into(), Value::from(source));
    Ok((profile, out))
}

fn sql_of(v: &Value) -> SqlValue {
    match v {
        Value::Null => SqlValue::Null,
        Value::Bool(b) => SqlValue::Integer(i64::from(*b)),
        Value::Number(n) => n
            .as_i64()
            .map(SqlValue::Integer)
            .unwrap_or_else(|| SqlValue::Real(n.as_f64().unwrap_or(f64::NAN))),
        Value::String(s) => SqlValue::Text(s.clone()),
        other => SqlValue::Text(other.to_string()),
    }
}

fn value_of(field: &Field, v: SqlValue) -> Value {
    match (field.kind, v) {
        (_, SqlValue::Null) => Value::Null,
        (Real, SqlValue::Real(x)) => Value::from(x),
        (Real, SqlValue::Integer(i)) => Value::from(i as f64),
        (Int, SqlValue::Integer(i)) => Value::from(i),
        (Int, SqlValue::Real(x)) => Value::from(x as i64),
        (Bool, SqlValue::Integer(i)) => Value::from(i != 0),
        (_, SqlValue::Text(s)) => Value::from(s),
        (_, SqlValue::Integer(i)) => Value::from(i),
        (_, SqlValue::Real(x)) => Value::from(x),
        (_, SqlValue::Blob(_)) => Value::Null,
    }
}

fn columns(lib: &Library) -> String {
    lib.fields
        .iter()
        .map(|f| f.name)
        .collect::<Vec<_>>()
        .join(", ")
}

fn row_to_record(lib: &Library, row: &rusqlite::Row<'_>) -> rusqlite::Result<Record> {
    let mut rec = Record::new();
    for (i, field) in lib.fields.iter().enumerate() {
        let v: SqlValue = row.get(i)?;
        rec.insert(field.name.to_string(), value_of(field, v));
    }
    Ok(rec)
}

fn machine_record(json: &str, source: String) -> Result<Record, KnowledgeError> {
    let mut rec: Record = serde_json::from_str(json)?;
    rec.insert("source".into(), Value::from(source));
    Ok(rec)
}

/// Every record of a library, ordered by key.
pub fn list(conn: &Connection, lib: &Library) -> Result<Vec<Record>, KnowledgeError> {
    if lib.name == MACHINES.name {
        let mut stmt = conn.prepare("SELECT profile_json, source FROM machines ORDER BY id")?;
        let rows = stmt.query_map([], |r| Ok((r.get::<_, String>(0)?, r.get::<_, String>(1)?)))?;
        let mut out = Vec::new();
        for row in rows {
            let (json, source) = row?;
            out.push(machine_record(&json, source)?);
        }
        return Ok(out);
    }
    let sql = format!(
        "SELECT {} FROM {} ORDER BY {}",
        columns(lib),
        lib.table,
        lib.key
    );
    let mut stmt = conn.prepare(&sql)?;
    let rows = stmt.query_map([], |r| row_to_record(lib, r))?;
    Ok(rows.collect::<Result<_, _>>()?)
}

/// One record by key.
pub fn get(conn: &Connection, lib: &Library, id: &str) -> Result<Option<Record>, KnowledgeError> {
    if lib.name == MACHINES.name {
        let row: Option<(String, String)> = conn
            .query_row(
                "SELECT profile_json, source FROM machines WHERE id = ?1",
                [id],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .optional()?;
        return row.map(|(j, s)| machine_record(&j, s)).transpose();
    }
    let sql = format!(
        "SELECT {} FROM {} WHERE {} = ?1",
        columns(lib),
        lib.table,
        lib.key
    );
    Ok(conn
        .query_row(&sql, [id], |r| row_to_record(lib, r))
        .optional()?)
}

fn not_found(lib: &Library, id: &str, conn: &Connection) -> Vec<JobError> {
    let known: Vec<String> = list(conn, lib)
        .map(|rs| {
            rs.iter()
                .filter_map(|r| r.get(lib.key).and_then(Value::as_str).map(str::to_string))
                .take(20)
                .collect()
        })
        .unwrap_or_default();
    vec![kb_err(
        "NOT_FOUND",
        lib.key,
        if known.is_empty() {
            format!("an existing {} id (the library is empty)", lib.name)
        } else {
            format!("one of {}", known.join(", "))
        },
        id,
        format!("there is no record {id:?} in {}", lib.name),
    )]
}

fn key_of(lib: &Library, rec: &Record) -> String {
    rec.get(lib.key)
        .and_then(Value::as_str)
        .unwrap_or_default()
        .to_string()
}

/// Writes a validated record, inserting or replacing.
fn write(conn: &Connection, lib: &Library, rec: &Record) -> Result<(), KnowledgeError> {
    if lib.name == MACHINES.name {
        let mut profile = rec.clone();
        let source = profile
            .remove("source")
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_else(|| "user".into());
        let p: MachineProfile = serde_json::from_value(Value::Object(profile))?;
        conn.execute(
            "INSERT OR REPLACE INTO machines (id, name, dialect, profile_json, source) VALUES (?1, ?2, ?3, ?4, ?5)",
            rusqlite::params![p.id.as_str(), p.name, p.dialect.as_str(), serde_json::to_string(&p)?, source],
        )?;
        return Ok(());
    }
    let placeholders = (1..=lib.fields.len())
        .map(|i| format!("?{i}"))
        .collect::<Vec<_>>()
        .join(", ");
    let sql = format!(
        "INSERT OR REPLACE INTO {} ({}) VALUES ({placeholders})",
        lib.table,
        columns(lib)
    );
    let vals: Vec<SqlValue> = lib
        .fields
        .iter()
        .map(|f| sql_of(rec.get(f.name).unwrap_or(&Value::Null)))
        .collect();
    conn.execute(&sql, params_from_iter(vals))?;
    Ok(())
}

/// Adds a new record; its key must not exist yet.
pub fn add(conn: &Connection, lib: &Library, rec: &Record) -> Outcome<Record> {
    let rec = validate(lib, rec)?;
    let id = key_of(lib, &rec);
    if get(conn, lib, &id)?.is_some() {
        return Err(vec![kb_err(
            "DUPLICATE_ID",
            lib.key,
            format!("an id not yet in {}", lib.name),
            id.clone(),
            format!("{} already has {id:?}; use edit to change it", lib.name),
        )]);
    }
    write(conn, lib, &rec)?;
    Ok(rec)
}

/// Sets a field, or a nested field by dotted path (`limits.max_hob_rpm`).
fn set_path(rec: &mut Record, path: &str, v: Value) -> Result<(), JobError> {
    let mut parts = path.split('.').peekable();
    let mut cur = rec;
    while let Some(p) = parts.next() {
        if parts.peek().is_none() {
            cur.insert(p.to_string(), v);
            return Ok(());
        }
        cur = match cur.get_mut(p) {
            Some(Value::Object(m)) => m,
            _ => {
                return Err(kb_err(
                    "UNKNOWN_FIELD",
                    path,
                    "a path into the record's nested fields",
                    path,
                    format!("{p} is not a nested group of this record"),
                ))
            }
        };
    }
    Ok(())
}

/// Changes fields of an existing record (by name or dotted path), validates
/// the whole record again and stores it. The key cannot change.
pub fn edit(conn: &Connection, lib: &Library, id: &str, set: &Record) -> Outcome<Record> {
    let Some(mut rec) = get(conn, lib, id)? else {
        return Err(not_found(lib, id, conn));
    };
    let mut errors = Vec::new();
    for (path, v) in set {
        if path == lib.key {
            errors.push(kb_err(
                "KEY_IMMUTABLE",
                lib.key,
                id,
                show(v),
                "a record's key cannot be changed; add a new record and remove the old one",
            ));
            continue;
        }
        if let Err(e) = set_path(&mut rec, path, v.clone()) {
            errors.push(e);
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let rec = validate(lib, &rec)?;
    write(conn, lib, &rec)?;
    Ok(rec)
}

/// Removes a record; returns it.
pub fn remove(conn: &Connection, lib: &Library, id: &str) -> Outcome<Record> {
    let Some(rec) = get(conn, lib, id)? else {
        return Err(not_found(lib, id, conn));
    };
    conn.execute(
        &format!("DELETE FROM {} WHERE {} = ?1", lib.table, lib.key),
        [id],
    )
    .map_err(KnowledgeError::from)?;
    Ok(rec)
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
        kb_err(
            "FIELD_INVALID",
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
