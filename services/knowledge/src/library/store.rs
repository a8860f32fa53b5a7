//! The SQL reads and writes of the libraries' records: list, get, add,
//! edit, remove.

use gearcam_proto::Code;
use gearcam_proto::{JobError, MachineProfile, Stage};
use rusqlite::types::Value as SqlValue;
use rusqlite::{params_from_iter, Connection, OptionalExtension};
use serde_json::Value;

use super::defs::MACHINES;
use super::fields::Kind::{Bool, Int, Real};
use super::fields::{Field, Library, Outcome, Record};
use super::validate::{show, validate};
use crate::KnowledgeError;

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
        lib.columns(),
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
        lib.columns(),
        lib.table,
        lib.key
    );
    Ok(conn
        .query_row(&sql, [id], |r| row_to_record(lib, r))
        .optional()?)
}

/// Every key of a library, ordered (the ids an error lists as the choices).
pub fn keys(conn: &Connection, lib: &Library) -> Result<Vec<String>, KnowledgeError> {
    let sql = format!(
        "SELECT {key} FROM {} WHERE {key} IS NOT NULL ORDER BY {key}",
        lib.table,
        key = lib.key
    );
    let mut stmt = conn.prepare(&sql)?;
    let rows = stmt.query_map([], |r| r.get::<_, String>(0))?;
    Ok(rows.collect::<Result<_, _>>()?)
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
    vec![Stage::Knowledge.error(
        Code::NOT_FOUND,
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
        lib.columns()
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
        return Err(vec![Stage::Knowledge.error(
            Code::DUPLICATE_ID,
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
                return Err(Stage::Knowledge.error(
                    Code::UNKNOWN_FIELD,
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
            errors.push(Stage::Knowledge.error(
                Code::KEY_IMMUTABLE,
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

/// The refusal of a job whose machine `machine` is not one of `family`'s
/// (`hobbing`, `spiral face milling` or `wire EDM`): `MACHINE_FAMILY` when
/// another family's library has it, else `UNKNOWN_MACHINE`; either way
/// naming the family's machines, and for an unknown one every family's, in
/// the words the station uses.
pub fn machine_error(
    conn: &Connection,
    machine: &str,
    family: &str,
) -> Result<gearcam_proto::JobError, KnowledgeError> {
    let hobbing = keys(conn, &super::MACHINES)?;
    let mills = keys(conn, &super::MILL_MACHINES)?;
    let wires = keys(conn, &super::WIRE_MACHINES)?;
    let families = [
        ("hobbing", &hobbing, "machines"),
        ("spiral face milling", &mills, "mill-machines"),
        ("wire EDM", &wires, "wire-machines"),
    ];
    let (own, library) = families
        .iter()
        .find(|(f, _, _)| *f == family)
        .map_or((&hobbing, "machines"), |(_, ids, lib)| (*ids, *lib));
    let other = families
        .iter()
        .find(|(f, ids, _)| *f != family && ids.iter().any(|m| m == machine))
        .map(|(f, _, _)| *f);
    let wanted = format!("a {family} machine: one of {}", own.join(", "));
    Ok(match other {
        Some(other) => gearcam_proto::Stage::Knowledge.error(
            Code::MACHINE_FAMILY,
            "job.machine",
            wanted,
            format!("{machine} (a {other} machine)"),
            format!("a {family} job runs on a {family} machine (gearcam kb list {library})"),
        ),
        None => gearcam_proto::Stage::Knowledge.error(
            Code::UNKNOWN_MACHINE,
            "job.machine",
            format!(
                "{wanted}; the knowledge base's machines: {}",
                gearcam_proto::job::machines_by_family(&hobbing, &mills, &wires)
            ),
            machine,
            "the knowledge base has no such machine; pick a configured machine or add it",
        ),
    })
}
