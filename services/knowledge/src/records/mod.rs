//! One typed record per library, read by one reader per table.
//!
//! Planning, case retrieval, hob matching and the learning loop read these
//! types; the generic JSON records of [`crate::library`] serve the libraries'
//! own machinery (validation on add and edit, CSV, the `kb` queryable and
//! CLI), which writes every record these types read.
//!
//! A flat library's reader selects exactly its table's columns (the
//! library's field table, [`crate::library::Library::fields`]), and its type reads each of
//! them by name. A value the type cannot hold (NULL in a required field, a
//! value of another type or outside the type's range, a text that is not
//! one of the field's choices) is a [`KnowledgeError::Record`] naming the
//! library, the record and the field: no value is replaced by a default on
//! the way. Fields a record may lack (a case's machine, a workpiece's blank
//! diameter) are `Option`s, as the libraries define them.
//!
//! Machines are whole profiles: their typed record is
//! [`MachineProfile`], read from the profile's JSON column.
//!
//! # Layout
//!
//! - this module: the readers, one per table;
//! - `row`: reading one row of a table field by field, every error naming
//!   the library, the record and the field;
//! - `types`: the record types ([`CaseRecord`], [`HobRecord`],
//!   [`WorkpieceRecord`], [`MaterialRecord`], [`WeightRecord`],
//!   [`JobRecord`], [`ClassRecord`]) and their text choices ([`CaseOutcome`],
//!   [`JobState`]).

mod row;
mod types;

use gearcam_proto::{MachineId, MachineProfile};
use rusqlite::{Connection, Row};
use serde_json::Value;

use crate::library;
use crate::KnowledgeError;
use row::{describe, read_all, read_one, record_error, RecordRow};

pub use types::{
    hand_name, CaseOutcome, CaseRecord, ClassRecord, HobRecord, JobClass, JobRecord, JobState,
    MaterialRecord, WeightRecord, WorkpieceRecord,
};

/// Every case of the machining history, ordered by id.
pub fn cases(conn: &Connection) -> Result<Vec<CaseRecord>, KnowledgeError> {
    read_all(conn)
}

/// Every hob of the tool library, ordered by id.
pub fn hobs(conn: &Connection) -> Result<Vec<HobRecord>, KnowledgeError> {
    read_all(conn)
}

/// A hob of the tool library by id.
pub fn hob(conn: &Connection, id: &str) -> Result<Option<HobRecord>, KnowledgeError> {
    read_one(conn, id)
}

/// Every workpiece, ordered by part number.
pub fn workpieces(conn: &Connection) -> Result<Vec<WorkpieceRecord>, KnowledgeError> {
    read_all(conn)
}

/// A workpiece by part number.
pub fn workpiece(
    conn: &Connection,
    part_number: &str,
) -> Result<Option<WorkpieceRecord>, KnowledgeError> {
    read_one(conn, part_number)
}

/// Every material, ordered by name.
pub fn materials(conn: &Connection) -> Result<Vec<MaterialRecord>, KnowledgeError> {
    read_all(conn)
}

/// A material by name (surrounding blanks ignored, case ignored).
pub fn material(conn: &Connection, name: &str) -> Result<Option<MaterialRecord>, KnowledgeError> {
    read_one(conn, name.trim())
}

/// Every retrieval weight, ordered by feature.
pub fn weights(conn: &Connection) -> Result<Vec<WeightRecord>, KnowledgeError> {
    read_all(conn)
}

/// Every job the knowledge service planned, ordered by id.
pub fn jobs(conn: &Connection) -> Result<Vec<JobRecord>, KnowledgeError> {
    read_all(conn)
}

/// A planned job by id.
pub fn job(conn: &Connection, job_id: &str) -> Result<Option<JobRecord>, KnowledgeError> {
    read_one(conn, job_id)
}

/// The group-technology class tree, ordered by id.
pub fn classes(conn: &Connection) -> Result<Vec<ClassRecord>, KnowledgeError> {
    read_all(conn)
}

/// A machine's profile from its row (`id`, `profile_json`); a profile that
/// is not a whole [`MachineProfile`] names the path of the field at fault.
fn machine_from_row(row: &Row<'_>) -> Result<MachineProfile, KnowledgeError> {
    let lib = &library::MACHINES;
    let id = RecordRow::new(lib, row).id().to_string();
    let json: String = row
        .get("profile_json")
        .map_err(|e| record_error(lib, &id, "profile_json", describe(&e)))?;
    let value: Value = serde_json::from_str(&json)
        .map_err(|e| record_error(lib, &id, "profile_json", format!("unreadable JSON: {e}")))?;
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let field = if path == "." {
            "profile_json".to_string()
        } else {
            format!("profile_json.{path}")
        };
        record_error(lib, &id, &field, e.inner().to_string())
    })
}

/// A machine's profile by id.
pub fn machine(
    conn: &Connection,
    id: &MachineId,
) -> Result<Option<MachineProfile>, KnowledgeError> {
    let mut stmt = conn.prepare_cached("SELECT id, profile_json FROM machines WHERE id = ?1")?;
    let mut rows = stmt.query([id.as_str()])?;
    match rows.next()? {
        Some(row) => Ok(Some(machine_from_row(row)?)),
        None => Ok(None),
    }
}

/// Every machine's profile, ordered by id.
pub fn machines(conn: &Connection) -> Result<Vec<MachineProfile>, KnowledgeError> {
    let mut stmt = conn.prepare_cached("SELECT id, profile_json FROM machines ORDER BY id")?;
    let mut rows = stmt.query([])?;
    let mut out = Vec::new();
    while let Some(row) = rows.next()? {
        out.push(machine_from_row(row)?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests;
