//! CSV import and export of the flat libraries (workpieces, hobs, cases,
//! materials), so a shop can bring its own history and take it out again.
//!
//! The header row names the fields (those of [`crate::library`]); an empty
//! cell is "no value" (the field's default, or NULL when optional). Import is
//! all or nothing: every row is validated, every error is reported with its
//! row number, and nothing is written unless every row is valid. A row whose
//! key exists replaces that record.

use gearcam_proto::Code;
use std::io::{Read, Write};

use gearcam_proto::{JobError, Stage};
use rusqlite::Connection;
use serde_json::Value;

use crate::library::{self, Library, Outcome, Record};
use crate::KnowledgeError;

/// What an import did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ImportReport {
    /// New records.
    pub added: usize,
    /// Existing records replaced.
    pub replaced: usize,
}

fn csv_lib(lib: &Library) -> Result<(), JobError> {
    if lib.csv {
        return Ok(());
    }
    let with: Vec<&str> = library::LIBRARIES
        .iter()
        .filter(|l| l.csv)
        .map(|l| l.name)
        .collect();
    Err(Stage::Knowledge.error(
        Code::NO_CSV,
        "library",
        format!("one of {}", with.join(", ")),
        lib.name,
        format!("{} cannot be imported or exported as CSV", lib.name),
    ))
}

/// Writes every record of the library as CSV; returns the number of rows.
pub fn export(conn: &Connection, lib: &Library, out: impl Write) -> Outcome<usize> {
    csv_lib(lib).map_err(|e| vec![e])?;
    let mut w = csv::Writer::from_writer(out);
    let names: Vec<&str> = lib.fields.iter().map(|f| f.name).collect();
    w.write_record(&names).map_err(KnowledgeError::from)?;
    let records = library::list(conn, lib)?;
    for r in &records {
        let row: Vec<String> = names
            .iter()
            .map(|n| library::cell(r.get(*n).unwrap_or(&Value::Null)))
            .collect();
        w.write_record(&row).map_err(KnowledgeError::from)?;
    }
    w.flush()
        .map_err(|e| KnowledgeError::Csv(csv::Error::from(e)))?;
    Ok(records.len())
}

/// Reads CSV rows into the library (see the module docs).
pub fn import(conn: &Connection, lib: &Library, input: impl Read) -> Outcome<ImportReport> {
    csv_lib(lib).map_err(|e| vec![e])?;
    let mut rd = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(input);
    let headers = rd.headers().map_err(KnowledgeError::from)?.clone();
    let mut errors = Vec::new();
    for h in headers.iter() {
        if !lib.fields.iter().any(|f| f.name == h) {
            errors.push(Stage::Knowledge.error(
                Code::UNKNOWN_FIELD,
                h,
                format!(
                    "a column of {}: {}",
                    lib.name,
                    lib.fields
                        .iter()
                        .map(|f| f.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                h,
                "the CSV header names a column this library does not have",
            ));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut records = Vec::new();
    for (i, row) in rd.records().enumerate() {
        let line = i + 2; // the header is line 1
        let row = match row {
            Ok(r) => r,
            Err(e) => {
                errors.push(Stage::Knowledge.error(
                    Code::CSV_ROW,
                    &format!("row {line}"),
                    format!("{} cells", headers.len()),
                    e.to_string(),
                    "the row cannot be read",
                ));
                continue;
            }
        };
        let mut rec = Record::new();
        for (name, text) in headers.iter().zip(row.iter()) {
            match library::parse_value(lib, name, text) {
                Ok(Value::Null) => {}
                Ok(v) => {
                    rec.insert(name.to_string(), v);
                }
                // Validation reports it with the field's expectation.
                Err(_) => {
                    rec.insert(name.to_string(), Value::from(text));
                }
            }
        }
        match library::validate(lib, &rec) {
            Ok(r) => records.push(r),
            Err(es) => errors.extend(es.into_iter().map(|mut e| {
                e.field = format!("row {line}: {}", e.field);
                e
            })),
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let tx = conn.unchecked_transaction().map_err(KnowledgeError::from)?;
    let mut report = ImportReport::default();
    for r in &records {
        let id = r.get(lib.key).and_then(Value::as_str).unwrap_or_default();
        if library::get(&tx, lib, id)?.is_some() {
            library::remove(&tx, lib, id)?;
            report.replaced += 1;
        } else {
            report.added += 1;
        }
        library::add(&tx, lib, r)?;
    }
    tx.commit().map_err(KnowledgeError::from)?;
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db;

    #[test]
    fn cases_export_and_import_round_trip_and_bad_rows_name_row_and_field() {
        let conn = db::open_in_memory().unwrap();
        let mut out = Vec::new();
        let n = export(&conn, &library::CASES, &mut out).unwrap();
        assert_eq!(n, 14);
        let text = String::from_utf8(out).unwrap();
        assert!(text.starts_with("id,class,machine,material,"));
        // Into a fresh database with the cases removed: the same records come back.
        let other = db::open_in_memory().unwrap();
        other.execute("DELETE FROM cases", []).unwrap();
        let r = import(&other, &library::CASES, text.as_bytes()).unwrap();
        assert_eq!(
            r,
            ImportReport {
                added: 14,
                replaced: 0
            }
        );
        assert_eq!(
            library::list(&conn, &library::CASES).unwrap(),
            library::list(&other, &library::CASES).unwrap()
        );
        let r = import(&other, &library::CASES, text.as_bytes()).unwrap();
        assert_eq!(
            r,
            ImportReport {
                added: 0,
                replaced: 14
            }
        );

        let bad = "id,material,material_group,module_mm,teeth,cutting_speed_m_min,feed_mm_per_rev,confidence,provenance\n\
                   OK-1,C45,quenched_tempered_steel,3,20,80,1.8,0.9,shop\n\
                   BAD-1,C45,quenched_tempered_steel,-3,twenty,80,1.8,1.5,shop\n";
        let errors = import(&other, &library::CASES, bad.as_bytes()).unwrap_err();
        let fields: Vec<&str> = errors.iter().map(|e| e.field.as_str()).collect();
        assert_eq!(
            fields,
            ["row 3: module_mm", "row 3: teeth", "row 3: confidence"]
        );
        assert_eq!(errors[0].expected, "a number > 0");
        assert_eq!(errors[1].got, "\"twenty\"");
        assert_eq!(errors[2].expected, "a number in [0, 1]");
        // All or nothing: the valid row was not written either.
        assert!(library::get(&other, &library::CASES, "OK-1")
            .unwrap()
            .is_none());
    }

    #[test]
    fn machines_have_no_csv_and_unknown_columns_are_refused() {
        let conn = db::open_in_memory().unwrap();
        let e = export(&conn, &library::MACHINES, Vec::new()).unwrap_err();
        assert_eq!(e[0].code, "NO_CSV");
        let e = import(&conn, &library::HOBS, "id,colour\nH,red\n".as_bytes()).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str()),
            ("UNKNOWN_FIELD", "colour")
        );
    }
}
