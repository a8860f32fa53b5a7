//! The knowledge base in SQLite: opening it, its schema migrations, and the
//! reads other crates use (machines and hobs, over [`crate::records`]).
//!
//! The database is created and seeded ([`crate::seed`]) on first open. Every seeded row says
//! where its values come from (`source`) and how far to trust them
//! (`confidence`); a shop replaces them with its own history.

use std::path::Path;

use gearcam_proto::{HobData, MachineId, MachineProfile};
use rusqlite::Connection;

use crate::records::{self, HobRecord};
use crate::KnowledgeError;

/// Schema migrations, applied in order; the index + 1 is the schema version.
const MIGRATIONS: &[&str] = &[
    r#"
CREATE TABLE machines (
    id            TEXT PRIMARY KEY,
    name          TEXT NOT NULL,
    dialect       TEXT NOT NULL,
    profile_json  TEXT NOT NULL,
    source        TEXT NOT NULL
);
CREATE TABLE hobs (
    id                  TEXT PRIMARY KEY,
    module_mm           REAL NOT NULL CHECK (module_mm > 0),
    pressure_angle_deg  REAL NOT NULL,
    starts              INTEGER NOT NULL CHECK (starts >= 1),
    hand                TEXT NOT NULL CHECK (hand IN ('right', 'left')),
    lead_angle_deg      REAL NOT NULL,
    od_mm               REAL NOT NULL,
    length_mm           REAL NOT NULL,
    usable_length_mm    REAL NOT NULL,
    accuracy_class      TEXT NOT NULL,
    material            TEXT NOT NULL,
    coating             TEXT NOT NULL,
    source              TEXT NOT NULL
);
CREATE TABLE cutting_data (
    id                   TEXT PRIMARY KEY,
    material_group       TEXT NOT NULL,
    hob_material         TEXT NOT NULL,
    cutting_speed_m_min  REAL NOT NULL CHECK (cutting_speed_m_min > 0),
    feed_mm_per_rev      REAL NOT NULL CHECK (feed_mm_per_rev > 0),
    confidence           REAL NOT NULL CHECK (confidence BETWEEN 0 AND 1),
    source               TEXT NOT NULL
);
CREATE TABLE materials (
    name            TEXT PRIMARY KEY COLLATE NOCASE,
    material_group  TEXT NOT NULL
);
"#,
    r#"
CREATE TABLE gt_classes (
    id              TEXT PRIMARY KEY,
    parent          TEXT REFERENCES gt_classes(id),
    name            TEXT NOT NULL,
    tooth_trace     TEXT NOT NULL,
    deformation     TEXT NOT NULL,
    hobbing_method  TEXT NOT NULL,
    programmable    INTEGER NOT NULL,
    source          TEXT NOT NULL
);
CREATE TABLE workpieces (
    part_number         TEXT PRIMARY KEY,
    description         TEXT NOT NULL,
    class               TEXT NOT NULL,
    module_mm           REAL NOT NULL,
    teeth               INTEGER NOT NULL,
    pressure_angle_deg  REAL NOT NULL,
    helix_angle_deg     REAL NOT NULL,
    helix_hand          TEXT,
    face_width_mm       REAL NOT NULL,
    profile_shift       REAL NOT NULL,
    addendum_coef       REAL NOT NULL,
    clearance_coef      REAL NOT NULL,
    blank_od_mm         REAL,
    od_correction_mm    REAL NOT NULL,
    material            TEXT NOT NULL,
    hardness_hb         REAL,
    quality_grade       INTEGER NOT NULL,
    fixture_height_mm   REAL NOT NULL,
    cone_angle_deg      REAL,
    source              TEXT NOT NULL
);
ALTER TABLE hobs ADD COLUMN shift_position_mm REAL NOT NULL DEFAULT 0;
ALTER TABLE hobs ADD COLUMN shift_step_mm REAL NOT NULL DEFAULT 0.5;
ALTER TABLE hobs ADD COLUMN parts_per_shift INTEGER NOT NULL DEFAULT 1;
ALTER TABLE hobs ADD COLUMN remaining_life_parts INTEGER NOT NULL DEFAULT 0;
ALTER TABLE materials ADD COLUMN hardness_hb REAL;
ALTER TABLE materials ADD COLUMN source TEXT NOT NULL DEFAULT 'gearcam seed';
CREATE TABLE cases (
    id                   TEXT PRIMARY KEY,
    class                TEXT NOT NULL,
    machine              TEXT,
    material             TEXT NOT NULL,
    material_group       TEXT NOT NULL,
    hardness_hb          REAL,
    module_mm            REAL NOT NULL CHECK (module_mm > 0),
    teeth                INTEGER NOT NULL CHECK (teeth >= 1),
    helix_angle_deg      REAL NOT NULL,
    face_width_mm        REAL,
    quality_grade        INTEGER NOT NULL,
    hob_material         TEXT NOT NULL,
    hob_coating          TEXT NOT NULL,
    hob_starts           INTEGER NOT NULL,
    hob_od_mm            REAL,
    operation            TEXT NOT NULL CHECK (operation IN ('rough', 'finish')),
    cutting_speed_m_min  REAL NOT NULL CHECK (cutting_speed_m_min > 0),
    feed_mm_per_rev      REAL NOT NULL CHECK (feed_mm_per_rev > 0),
    hob_rpm              REAL,
    axial_feed_mm_min    REAL,
    radial_feed_mm_min   REAL,
    cuts                 INTEGER NOT NULL,
    allowance_mm         REAL,
    shifting             INTEGER NOT NULL,
    cut_mode             TEXT,
    outcome              TEXT NOT NULL,
    quality_achieved     INTEGER,
    notes                TEXT NOT NULL,
    confidence           REAL NOT NULL CHECK (confidence BETWEEN 0 AND 1),
    provenance           TEXT NOT NULL,
    job_id               TEXT,
    created_at_ms        INTEGER NOT NULL
);
CREATE INDEX cases_by_class_group ON cases (class, material_group);
CREATE TABLE jobs (
    job_id              TEXT PRIMARY KEY,
    part_number         TEXT NOT NULL,
    machine             TEXT NOT NULL,
    class               TEXT NOT NULL,
    quantity            INTEGER NOT NULL,
    hob_id              TEXT NOT NULL,
    state               TEXT NOT NULL CHECK (state IN ('planned', 'delivered', 'confirmed')),
    confidence          REAL NOT NULL,
    plan_json           TEXT NOT NULL,
    program_name        TEXT,
    planned_at_ms       INTEGER NOT NULL,
    delivered_at_ms     INTEGER,
    confirmed_at_ms     INTEGER,
    delivered_quantity  INTEGER,
    case_id             TEXT
);
CREATE TABLE cbr_weights (
    feature  TEXT PRIMARY KEY,
    weight   REAL NOT NULL CHECK (weight >= 0),
    source   TEXT NOT NULL
);
DROP TABLE cutting_data;
"#,
    // Version 3 changes no table: it seeds the FANUC machine H02 (and
    // repairs a version-2 workpiece record), into new databases and into
    // those created before it alike.
    "",
    // Version 4 changes no table: the seeded machines gain the neutral
    // frame's axis senses, the G-code system, the envelope, the work offset
    // and the parameter block (docs/hobbing.md), and the example workpieces
    // a fixture tall enough for the hob's run-out.
    "",
    // Version 5: a job a later stage refused is `refused`, never left
    // `planned`: the state's check gains the value; SQLite changes
    // a check by copying the table.
    r#"
CREATE TABLE jobs_v5 (
    job_id              TEXT PRIMARY KEY,
    part_number         TEXT NOT NULL,
    machine             TEXT NOT NULL,
    class               TEXT NOT NULL,
    quantity            INTEGER NOT NULL,
    hob_id              TEXT NOT NULL,
    state               TEXT NOT NULL CHECK (state IN ('planned', 'delivered', 'confirmed', 'refused')),
    confidence          REAL NOT NULL,
    plan_json           TEXT NOT NULL,
    program_name        TEXT,
    planned_at_ms       INTEGER NOT NULL,
    delivered_at_ms     INTEGER,
    confirmed_at_ms     INTEGER,
    delivered_quantity  INTEGER,
    case_id             TEXT
);
INSERT INTO jobs_v5 SELECT job_id, part_number, machine, class, quantity, hob_id, state, confidence,
    plan_json, program_name, planned_at_ms, delivered_at_ms, confirmed_at_ms, delivered_quantity,
    case_id FROM jobs;
DROP TABLE jobs;
ALTER TABLE jobs_v5 RENAME TO jobs;
"#,
    // Version 6: every change to the libraries recorded (who, when, old,
    // new) by triggers ([`crate::audit`]); created in Rust from the tables'
    // columns.
    "",
    // Version 7: the spiral face milling family: milling
    // machines, mills, starting cutting data and cases; audited like the rest.
    r#"
CREATE TABLE IF NOT EXISTS mill_machines (
    id               TEXT PRIMARY KEY,
    name             TEXT NOT NULL,
    controller       TEXT NOT NULL,
    dialect          TEXT NOT NULL CHECK (dialect IN ('fanuc', 'linuxcnc')),
    programs         TEXT NOT NULL,
    default_program  TEXT NOT NULL,
    max_rpm          REAL NOT NULL CHECK (max_rpm > 0),
    max_feed_mm_min  REAL NOT NULL CHECK (max_feed_mm_min > 0),
    max_radius_mm    REAL NOT NULL CHECK (max_radius_mm > 0),
    safe_z_mm        REAL NOT NULL CHECK (safe_z_mm > 0),
    work_offset      TEXT NOT NULL,
    source           TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS mills (
    id                TEXT PRIMARY KEY,
    kind              TEXT NOT NULL CHECK (kind IN ('face-mill', 'end-mill')),
    diameter_mm       REAL NOT NULL CHECK (diameter_mm > 0),
    corner_radius_mm  REAL NOT NULL CHECK (corner_radius_mm >= 0),
    flutes            INTEGER NOT NULL CHECK (flutes >= 1),
    material          TEXT NOT NULL,
    source            TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS milling_data (
    id                     TEXT PRIMARY KEY,
    material_group         TEXT NOT NULL,
    tool_material          TEXT NOT NULL,
    cutting_speed_m_min    REAL NOT NULL CHECK (cutting_speed_m_min > 0),
    feed_per_tooth_mm      REAL NOT NULL CHECK (feed_per_tooth_mm > 0),
    step_over_ratio        REAL NOT NULL CHECK (step_over_ratio > 0 AND step_over_ratio < 1),
    max_depth_per_pass_mm  REAL NOT NULL CHECK (max_depth_per_pass_mm > 0),
    confidence             REAL NOT NULL CHECK (confidence BETWEEN 0 AND 1),
    source                 TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS milling_cases (
    id                   TEXT PRIMARY KEY,
    kind                 TEXT NOT NULL CHECK (kind IN ('face', 'groove')),
    machine              TEXT,
    material             TEXT NOT NULL,
    material_group       TEXT NOT NULL,
    outer_radius_mm      REAL NOT NULL CHECK (outer_radius_mm > 0),
    inner_radius_mm      REAL NOT NULL CHECK (inner_radius_mm >= 0),
    tool_id              TEXT,
    tool_diameter_mm     REAL NOT NULL CHECK (tool_diameter_mm > 0),
    flutes               INTEGER NOT NULL CHECK (flutes >= 1),
    step_over_mm         REAL NOT NULL CHECK (step_over_mm > 0),
    passes               INTEGER NOT NULL CHECK (passes >= 1),
    depth_mm             REAL NOT NULL CHECK (depth_mm > 0),
    cutting_speed_m_min  REAL NOT NULL CHECK (cutting_speed_m_min > 0),
    feed_per_tooth_mm    REAL NOT NULL CHECK (feed_per_tooth_mm > 0),
    outcome              TEXT NOT NULL,
    notes                TEXT NOT NULL,
    confidence           REAL NOT NULL CHECK (confidence BETWEEN 0 AND 1),
    provenance           TEXT NOT NULL,
    job_id               TEXT,
    created_at_ms        INTEGER NOT NULL
);
CREATE INDEX IF NOT EXISTS milling_cases_by_group ON milling_cases (kind, material_group);
"#,
    // Version 8: the wire EDM family: machines, wires and
    // starting technology; audited like the rest.
    r#"
CREATE TABLE IF NOT EXISTS wire_machines (
    id                TEXT PRIMARY KEY,
    name              TEXT NOT NULL,
    controller        TEXT NOT NULL,
    dialect           TEXT NOT NULL CHECK (dialect IN ('wire3b', 'wireiso')),
    programs          TEXT NOT NULL,
    default_program   TEXT NOT NULL,
    wire              TEXT NOT NULL,
    max_thickness_mm  REAL NOT NULL CHECK (max_thickness_mm > 0),
    max_radius_mm     REAL NOT NULL CHECK (max_radius_mm > 0),
    source            TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS wires (
    id            TEXT PRIMARY KEY,
    material      TEXT NOT NULL,
    diameter_mm   REAL NOT NULL CHECK (diameter_mm > 0),
    spark_gap_mm  REAL NOT NULL CHECK (spark_gap_mm >= 0),
    source        TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS wire_data (
    id                    TEXT PRIMARY KEY,
    wire_material         TEXT NOT NULL,
    material_group        TEXT NOT NULL,
    pulse_on_us           REAL NOT NULL CHECK (pulse_on_us > 0),
    pulse_off_us          REAL NOT NULL CHECK (pulse_off_us > 0),
    current_a             REAL NOT NULL CHECK (current_a > 0),
    cutting_rate_mm2_min  REAL NOT NULL CHECK (cutting_rate_mm2_min > 0),
    confidence            REAL NOT NULL CHECK (confidence BETWEEN 0 AND 1),
    source                TEXT NOT NULL
);
"#,
    // Version 9: whether a wire EDM control turns a section of blocks (a
    // 3B/4B rotate instruction, ISO G68); one that does not is given whole
    // programs. The seeded W01 and W02 do. The column is added by
    // `add_rotates` (SQLite has no ADD COLUMN IF NOT EXISTS); the audit
    // triggers name every column, so they are dropped here and made again
    // with it by the migration's audit install.
    r#"
DROP TRIGGER IF EXISTS kb_audit_wire_machines_edit;
DROP TRIGGER IF EXISTS kb_audit_wire_machines_add;
DROP TRIGGER IF EXISTS kb_audit_wire_machines_update;
DROP TRIGGER IF EXISTS kb_audit_wire_machines_remove;
"#,
    // Version 10: a job's tool is a hob, a mill or a wire, so the jobs
    // library's column is `tool_id`, not `hob_id`; its rows keep their
    // values.
    "ALTER TABLE jobs RENAME COLUMN hob_id TO tool_id;",
];

/// Opens (creating and seeding if new) the knowledge base at `path`.
pub fn open(path: &Path) -> Result<Connection, KnowledgeError> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| KnowledgeError::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
    }
    let mut conn = Connection::open(path)?;
    conn.pragma_update(None, "journal_mode", "WAL")?;
    // WAL with synchronous NORMAL: every commit is atomic and survives a crash
    // of the process; only a power loss can drop the last commits. The
    // knowledge base is not the record of accepted jobs (the station's journal
    // is, with FULL), and a fsync per planned job would cap the pipeline.
    conn.pragma_update(None, "synchronous", "NORMAL")?;
    conn.busy_timeout(std::time::Duration::from_secs(5))?;
    // Every plan runs the same few lookups: their statements are kept
    // prepared rather than parsed again for each job.
    conn.set_prepared_statement_cache_capacity(64);
    migrate(&mut conn)?;
    Ok(conn)
}

/// Opens an in-memory knowledge base with the seed data (for tests).
pub fn open_in_memory() -> Result<Connection, KnowledgeError> {
    let mut conn = Connection::open_in_memory()?;
    migrate(&mut conn)?;
    Ok(conn)
}

/// Applies the missing migrations, each followed by its seed data, in one
/// transaction. A database created by an older gearcam keeps its rows and
/// gains the new tables and their seed.
fn migrate(conn: &mut Connection) -> Result<(), KnowledgeError> {
    let version: i64 = conn.pragma_query_value(None, "user_version", |r| r.get(0))?;
    let tx = conn.transaction()?;
    for (i, sql) in MIGRATIONS.iter().enumerate().skip(version as usize) {
        tx.execute_batch(sql)?;
        match i {
            0 => crate::seed::seed_v1(&tx)?,
            1 => crate::seed::seed_v2(&tx)?,
            2 => crate::seed::seed_v3(&tx)?,
            3 => crate::seed::seed_v4(&tx)?,
            5 => crate::audit::install(&tx)?,
            6 => {
                crate::audit::install(&tx)?;
                crate::spiral::seed_v7(&tx)?;
            }
            // The wire tables' seed goes in once they have every column of
            // the library (version 9 adds `rotates`), for a database that
            // did not have them yet.
            7 => crate::audit::install(&tx)?,
            8 => {
                add_rotates(&tx)?;
                crate::audit::install(&tx)?;
                if version < 8 {
                    crate::wire::seed_v8(&tx)?;
                }
            }
            _ => {}
        }
        tx.pragma_update(None, "user_version", (i + 1) as i64)?;
    }
    tx.commit()?;
    Ok(())
}

/// Adds `wire_machines.rotates` (true for every machine there) unless the
/// table has it.
fn add_rotates(conn: &Connection) -> Result<(), KnowledgeError> {
    let has: bool = conn.query_row(
        "SELECT COUNT(*) > 0 FROM pragma_table_info('wire_machines') WHERE name = 'rotates'",
        [],
        |r| r.get(0),
    )?;
    if !has {
        conn.execute_batch(
            "ALTER TABLE wire_machines ADD COLUMN rotates INTEGER NOT NULL DEFAULT 1 CHECK (rotates IN (0, 1));",
        )?;
    }
    Ok(())
}

/// The schema version of an open knowledge base.
pub fn schema_version(conn: &Connection) -> Result<i64, KnowledgeError> {
    Ok(conn.pragma_query_value(None, "user_version", |r| r.get(0))?)
}

/// A machine's profile by id (see [`records::machine`]).
pub fn machine(
    conn: &Connection,
    id: &MachineId,
) -> Result<Option<MachineProfile>, KnowledgeError> {
    records::machine(conn, id)
}

/// Every machine's profile, ordered by id (see [`records::machines`]).
pub fn machines(conn: &Connection) -> Result<Vec<MachineProfile>, KnowledgeError> {
    records::machines(conn)
}

/// A hob's data as the model needs it, with source `library` (see
/// [`records::hob`] for the whole record).
pub fn hob(conn: &Connection, id: &str) -> Result<Option<HobData>, KnowledgeError> {
    Ok(records::hob(conn, id)?.map(|h| h.data()))
}

/// Every hob's data, ordered by id (see [`records::hobs`] for the whole records).
pub fn hobs(conn: &Connection) -> Result<Vec<HobData>, KnowledgeError> {
    Ok(records::hobs(conn)?.iter().map(HobRecord::data).collect())
}

/// The material group of a material name, if the materials table knows it
/// (see [`records::material`] for the whole record).
pub fn material_group(conn: &Connection, material: &str) -> Result<Option<String>, KnowledgeError> {
    Ok(records::material(conn, material)?.map(|m| m.material_group))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::library;
    use crate::seed::{seed_machine_h01, seed_machine_h02};
    use gearcam_proto::Dialect;

    #[test]
    fn a_fresh_knowledge_base_has_the_840d_machine_h01_and_the_fanuc_machine_h02() {
        let conn = open_in_memory().unwrap();
        let machines = machines(&conn).unwrap();
        assert_eq!(machines, [seed_machine_h01(), seed_machine_h02()]);
        let h02 = &machines[1];
        assert_eq!(h02.dialect, Dialect::Fanuc);
        assert_eq!(
            (h02.mcodes.coolant_on, h02.mcodes.coolant_off),
            (8, 9),
            "FANUC coolant M8/M9"
        );
        assert_eq!(h02.mcodes.program_end, 30);
        assert_eq!(
            (h02.limits.max_hob_rpm, h02.limits.max_table_rpm),
            (1000.0, 100.0)
        );
        // The seed passes the library's own validation of machine profiles.
        let rec = library::get(&conn, &library::MACHINES, "H02")
            .unwrap()
            .unwrap();
        library::validate(&library::MACHINES, &rec).unwrap();
        assert!(rec["source"]
            .as_str()
            .unwrap()
            .contains("machine-builder specific"));
    }

    /// A version-8 database (wire machines without `rotates`, W01 edited
    /// by the shop) gains the column, every machine rotating, and keeps its
    /// rows: nothing is seeded again.
    /// A knowledge base of version 9 named a job's tool `hob_id`: opened,
    /// the column is `tool_id` with every row's value kept, and the jobs
    /// library reads and edits it.
    #[test]
    fn a_knowledge_base_of_version_9_renames_hob_id_to_tool_id() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("knowledge.db");
        let conn = open(&path).unwrap();
        // As version 9 left it: the column `hob_id`.
        conn.execute_batch("ALTER TABLE jobs RENAME COLUMN tool_id TO hob_id;")
            .unwrap();
        conn.execute(
            "INSERT INTO jobs (job_id, part_number, machine, class, quantity, hob_id, state,
                 confidence, plan_json, planned_at_ms)
             VALUES ('J-OLD', 'P-1', 'H01', 'cylindrical', 2, 'HOB-M3-80', 'planned', 0.7, '{}', 1)",
            [],
        )
        .unwrap();
        conn.pragma_update(None, "user_version", 9).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(schema_version(&conn).unwrap(), MIGRATIONS.len() as i64);
        let job = records::job(&conn, "J-OLD").unwrap().unwrap();
        assert_eq!(job.tool_id, "HOB-M3-80");
        let mut set = library::Record::new();
        set.insert("tool_id".into(), serde_json::json!("HOB-M3-80-B"));
        library::edit(&conn, &library::JOBS, "J-OLD", &set).unwrap();
        let job = records::job(&conn, "J-OLD").unwrap().unwrap();
        assert_eq!((job.tool_id.as_str(), job.quantity), ("HOB-M3-80-B", 2));
    }

    #[test]
    fn a_knowledge_base_of_version_8_gains_rotates_and_keeps_its_wire_machines() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("knowledge.db");
        let conn = open(&path).unwrap();
        // As version 8 left it: no column, audit triggers without it.
        conn.execute_batch(
            "DROP TRIGGER kb_audit_wire_machines_edit;
             DROP TRIGGER kb_audit_wire_machines_add;
             DROP TRIGGER kb_audit_wire_machines_update;
             DROP TRIGGER kb_audit_wire_machines_remove;
             ALTER TABLE wire_machines DROP COLUMN rotates;",
        )
        .unwrap();
        crate::audit::install(&conn).unwrap();
        conn.execute_batch(
            "UPDATE wire_machines SET max_radius_mm = 123 WHERE id = 'W01';
             DELETE FROM wire_machines WHERE id = 'W02';",
        )
        .unwrap();
        // Before version 10 the jobs' tool column was `hob_id`.
        conn.execute_batch("ALTER TABLE jobs RENAME COLUMN tool_id TO hob_id;")
            .unwrap();
        conn.pragma_update(None, "user_version", 8).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(schema_version(&conn).unwrap(), MIGRATIONS.len() as i64);
        let rows = library::list(&conn, &library::WIRE_MACHINES).unwrap();
        assert_eq!(rows.len(), 1, "{rows:?}");
        assert_eq!(rows[0]["id"], "W01");
        assert_eq!(rows[0]["max_radius_mm"], 123.0);
        assert_eq!(rows[0]["rotates"], true);
        // A change of the new column is in the audit trail.
        conn.execute("UPDATE wire_machines SET rotates = 0 WHERE id = 'W01'", [])
            .unwrap();
        let new: String = conn
            .query_row(
                "SELECT new_json FROM kb_changes WHERE library = 'wire_machines' ORDER BY rowid DESC LIMIT 1",
                [],
                |r| r.get(0),
            )
            .unwrap();
        assert!(new.contains("\"rotates\":0"), "{new}");
    }

    #[test]
    fn a_knowledge_base_of_version_2_gains_h02_and_keeps_a_shops_own_h02() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("knowledge.db");
        // A version-2 database: as a fresh one, without H02.
        let conn = open(&path).unwrap();
        conn.execute("DELETE FROM machines WHERE id = 'H02'", [])
            .unwrap();
        conn.execute(
            "UPDATE workpieces SET profile_shift = 0 WHERE part_number = 'HG-3003-L'",
            [],
        )
        .unwrap();
        // Before version 10 the jobs' tool column was `hob_id`.
        conn.execute_batch("ALTER TABLE jobs RENAME COLUMN tool_id TO hob_id;")
            .unwrap();
        conn.pragma_update(None, "user_version", 2).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(schema_version(&conn).unwrap(), MIGRATIONS.len() as i64);
        let id = MachineId::new("H02").unwrap();
        assert_eq!(machine(&conn, &id).unwrap(), Some(seed_machine_h02()));
        // The version-2 seed record of HG-3003-L gains its profile shift.
        let hg = library::get(&conn, &library::WORKPIECES, "HG-3003-L")
            .unwrap()
            .unwrap();
        assert_eq!(hg["profile_shift"], 0.2);

        // A shop that already had its own H02 keeps it.
        let mut set = library::Record::new();
        set.insert("name".into(), "our own H02".into());
        library::edit(&conn, &library::MACHINES, "H02", &set).unwrap();
        // Before version 10 the jobs' tool column was `hob_id`.
        conn.execute_batch("ALTER TABLE jobs RENAME COLUMN tool_id TO hob_id;")
            .unwrap();
        conn.pragma_update(None, "user_version", 2).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(machine(&conn, &id).unwrap().unwrap().name, "our own H02");
    }

    #[test]
    fn a_knowledge_base_of_version_3_gains_the_new_machine_profiles() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("knowledge.db");
        let conn = open(&path).unwrap();
        // A version-3 H01 as seeded then: no axis senses, envelope, G-code
        // system, work offset or parameter block, and A = +γ of the patent.
        let mut old = serde_json::to_value(seed_machine_h01()).unwrap();
        let obj = old.as_object_mut().unwrap();
        for key in ["gcode_system", "envelope", "work_offset", "parameters"] {
            obj.remove(key);
        }
        let settings = obj["settings"].as_object_mut().unwrap();
        for key in ["swivel_offset_deg", "table_sign", "hob_sign", "shift_sign"] {
            settings.remove(key);
        }
        settings.insert("swivel_sign".into(), 1.0.into());
        conn.execute(
            "UPDATE machines SET profile_json = ?1 WHERE id = 'H01'",
            [old.to_string()],
        )
        .unwrap();
        conn.execute(
            "UPDATE workpieces SET fixture_height_mm = 50.0 WHERE part_number = 'SP-1001'",
            [],
        )
        .unwrap();
        let id = MachineId::new("H01").unwrap();
        // Loading the old profile names what it lacks.
        let err = machine(&conn, &id).unwrap_err().to_string();
        assert!(err.contains("missing field"), "{err}");
        // Before version 10 the jobs' tool column was `hob_id`.
        conn.execute_batch("ALTER TABLE jobs RENAME COLUMN tool_id TO hob_id;")
            .unwrap();
        conn.pragma_update(None, "user_version", 3).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(schema_version(&conn).unwrap(), MIGRATIONS.len() as i64);
        assert_eq!(machine(&conn, &id).unwrap(), Some(seed_machine_h01()));
        let sp = library::get(&conn, &library::WORKPIECES, "SP-1001")
            .unwrap()
            .unwrap();
        assert_eq!(sp["fixture_height_mm"], 100.0);
    }
}
