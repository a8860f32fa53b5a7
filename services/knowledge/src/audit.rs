//! Every change to the knowledge base recorded, so that any change can be
//! traced: who, when, which record, the old and the new values.
//!
//! SQLite triggers on the library tables write each insert, update and
//! delete into `kb_changes`, whatever made it (the CLI, a CSV import, a
//! confirmed job, a change over the bus), so no path can forget. Who acted
//! is read from the one-row table `kb_actor`, which every writer sets first
//! ([`acting_as`]); a change nobody claimed is recorded as `unknown`.

use rusqlite::{params, Connection};

use crate::KnowledgeError;

/// The tables audited: every library a person or the learning loop changes.
pub const AUDITED: &[&str] = &[
    "machines",
    "hobs",
    "materials",
    "gt_classes",
    "workpieces",
    "cases",
    "cbr_weights",
    "mill_machines",
    "mills",
    "milling_data",
    "milling_cases",
    "wire_machines",
    "wires",
    "wire_data",
];

/// Creates the audit tables and the triggers of [`AUDITED`] (schema 6).
pub fn install(conn: &Connection) -> Result<(), KnowledgeError> {
    conn.execute_batch(
        "CREATE TABLE IF NOT EXISTS kb_changes (
             seq        INTEGER PRIMARY KEY AUTOINCREMENT,
             at_ms      INTEGER NOT NULL,
             by_user    TEXT NOT NULL,
             library    TEXT NOT NULL,
             record_id  TEXT NOT NULL,
             op         TEXT NOT NULL CHECK (op IN ('add', 'edit', 'remove')),
             old_json   TEXT,
             new_json   TEXT
         );
         CREATE TABLE IF NOT EXISTS kb_actor (id INTEGER PRIMARY KEY CHECK (id = 1), by_user TEXT NOT NULL);
         INSERT OR IGNORE INTO kb_actor (id, by_user) VALUES (1, 'unknown');",
    )?;
    for table in AUDITED {
        let columns: Vec<(String, bool)> = conn
            .prepare(&format!(
                "SELECT name, pk FROM pragma_table_info('{table}')"
            ))?
            .query_map([], |r| {
                Ok((r.get::<_, String>(0)?, r.get::<_, i64>(1)? > 0))
            })?
            .collect::<Result<_, _>>()?;
        if columns.is_empty() {
            // Created by a later migration, which installs its triggers.
            continue;
        }
        let key = columns
            .iter()
            .find(|(_, pk)| *pk)
            .map(|(c, _)| c.clone())
            .unwrap_or_else(|| "rowid".to_string());
        let object = |row: &str| {
            let pairs: Vec<String> = columns
                .iter()
                .map(|(c, _)| format!("'{c}', {row}.\"{c}\""))
                .collect();
            format!("json_object({})", pairs.join(", "))
        };
        let now = "CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER)";
        let actor = "(SELECT by_user FROM kb_actor WHERE id = 1)";
        let insert =
            "INSERT INTO kb_changes (at_ms, by_user, library, record_id, op, old_json, new_json)";
        let (old, new) = (object("o"), object("NEW"));
        // The libraries write with INSERT OR REPLACE: before the insert, the
        // record either exists (an edit: old and new) or not (an add).
        conn.execute_batch(&format!(
            "CREATE TRIGGER IF NOT EXISTS kb_audit_{table}_edit BEFORE INSERT ON {table} BEGIN
               {insert} SELECT {now}, {actor}, '{table}', NEW.\"{key}\", 'edit', {old}, {new}
                 FROM {table} AS o WHERE o.\"{key}\" = NEW.\"{key}\";
             END;
             CREATE TRIGGER IF NOT EXISTS kb_audit_{table}_add BEFORE INSERT ON {table}
               WHEN NOT EXISTS (SELECT 1 FROM {table} WHERE \"{key}\" = NEW.\"{key}\") BEGIN
               {insert} VALUES ({now}, {actor}, '{table}', NEW.\"{key}\", 'add', NULL, {new});
             END;
             CREATE TRIGGER IF NOT EXISTS kb_audit_{table}_update AFTER UPDATE ON {table} BEGIN
               {insert} VALUES ({now}, {actor}, '{table}', NEW.\"{key}\", 'edit', {old_u}, {new});
             END;
             CREATE TRIGGER IF NOT EXISTS kb_audit_{table}_remove AFTER DELETE ON {table} BEGIN
               {insert} VALUES ({now}, {actor}, '{table}', OLD.\"{key}\", 'remove', {old_d}, NULL);
             END;",
            old_u = object("OLD"),
            old_d = object("OLD"),
        ))?;
    }
    Ok(())
}

/// Says who makes the next changes on `conn` (a login name, a bus user,
/// `seed`, `confirm by …`).
pub fn acting_as(conn: &Connection, who: &str) -> Result<(), rusqlite::Error> {
    conn.execute(
        "UPDATE kb_actor SET by_user = ?1 WHERE id = 1",
        params![if who.trim().is_empty() {
            "unknown"
        } else {
            who
        }],
    )?;
    Ok(())
}

/// One recorded change.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Change {
    /// Order of the change.
    pub seq: i64,
    /// When, ms since the epoch.
    pub at_ms: i64,
    /// Who.
    pub by: String,
    /// The library's table.
    pub library: String,
    /// The record's key.
    pub record_id: String,
    /// `add`, `edit` or `remove`.
    pub op: String,
    /// The record before (edit, remove), as JSON.
    pub old: Option<String>,
    /// The record after (add, edit), as JSON.
    pub new: Option<String>,
}

/// The recorded changes, newest first, at most `limit`.
pub fn changes(conn: &Connection, limit: usize) -> Result<Vec<Change>, KnowledgeError> {
    changes_of(conn, None, None, limit)
}

/// The recorded changes of one table (`table`, e.g. `gt_classes`) or of
/// every table, of one record (`record_id`) or of every record, newest
/// first, at most `limit`.
pub fn changes_of(
    conn: &Connection,
    table: Option<&str>,
    record_id: Option<&str>,
    limit: usize,
) -> Result<Vec<Change>, KnowledgeError> {
    let mut stmt = conn.prepare(
        "SELECT seq, at_ms, by_user, library, record_id, op, old_json, new_json
         FROM kb_changes
         WHERE (?1 IS NULL OR library = ?1) AND (?2 IS NULL OR record_id = ?2)
         ORDER BY seq DESC LIMIT ?3",
    )?;
    let limit = i64::try_from(limit).unwrap_or(i64::MAX);
    let rows = stmt.query_map(params![table, record_id, limit], |r| {
        Ok(Change {
            seq: r.get(0)?,
            at_ms: r.get(1)?,
            by: r.get(2)?,
            library: r.get(3)?,
            record_id: r.get(4)?,
            op: r.get(5)?,
            old: r.get(6)?,
            new: r.get(7)?,
        })
    })?;
    Ok(rows.collect::<Result<_, _>>()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_change_is_recorded_with_who_old_and_new() {
        let conn = crate::db::open_in_memory().unwrap();
        let before = changes(&conn, 1000).unwrap().len();
        acting_as(&conn, "admin Zhang").unwrap();
        conn.execute(
            "UPDATE hobs SET coating = 'TiAlN' WHERE id = 'HOB-M3-80'",
            [],
        )
        .unwrap();
        let c = &changes(&conn, 1).unwrap()[0];
        assert_eq!(
            (
                c.by.as_str(),
                c.library.as_str(),
                c.record_id.as_str(),
                c.op.as_str()
            ),
            ("admin Zhang", "hobs", "HOB-M3-80", "edit")
        );
        let (old, new): (serde_json::Value, serde_json::Value) = (
            serde_json::from_str(c.old.as_deref().unwrap()).unwrap(),
            serde_json::from_str(c.new.as_deref().unwrap()).unwrap(),
        );
        assert_eq!(new["coating"], "TiAlN");
        assert_ne!(old["coating"], "TiAlN");
        // The libraries' INSERT OR REPLACE: one edit, with old and new.
        let n = changes(&conn, 1000).unwrap().len();
        conn.execute(
            "INSERT OR REPLACE INTO materials (name, material_group) VALUES ('40Cr', 'other')",
            [],
        )
        .unwrap();
        let all = changes(&conn, 1000).unwrap();
        assert_eq!(all.len(), n + 1);
        assert_eq!(all[0].op, "edit");
        assert!(all[0].old.as_deref().unwrap().contains("40Cr"));
        assert!(all[0].new.as_deref().unwrap().contains("other"));
        conn.execute(
            "INSERT OR REPLACE INTO materials (name, material_group) VALUES ('NEW-STEEL', 'other')",
            [],
        )
        .unwrap();
        assert_eq!(changes(&conn, 1).unwrap()[0].op, "add");
        conn.execute("DELETE FROM materials WHERE name = '40Cr'", [])
            .unwrap();
        let c = &changes(&conn, 1).unwrap()[0];
        assert_eq!((c.op.as_str(), c.new.as_deref()), ("remove", None));
        assert_eq!(changes(&conn, 1000).unwrap().len(), before + 4);
        // One table's, one record's.
        let hobs = changes_of(&conn, Some("hobs"), None, 1000).unwrap();
        assert!(!hobs.is_empty() && hobs.iter().all(|c| c.library == "hobs"));
        let one = changes_of(&conn, Some("materials"), Some("40Cr"), 1000).unwrap();
        let ops: Vec<&str> = one.iter().map(|c| c.op.as_str()).collect();
        assert_eq!(&ops[..2], ["remove", "edit"], "newest first");
        assert!(one.iter().all(|c| c.record_id == "40Cr"));
        assert_eq!(changes_of(&conn, None, None, 2).unwrap().len(), 2);
    }
}
