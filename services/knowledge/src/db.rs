//! The knowledge base in SQLite: schema migrations, seed data, and reads.
//!
//! The database is created and seeded on first open. Every seeded row says
//! where its values come from (`source`) and how far to trust them
//! (`confidence`); a shop replaces them with its own history.

use std::path::Path;

use gearcam_proto::{
    AxisNames, Dialect, Envelope, GCodeSystem, Hand, HobData, MCodes, MachineId, MachineLimits,
    MachineProfile, MachineSettings, ParameterBlock, Source,
};
use rusqlite::{params, Connection, OptionalExtension};

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
            0 => seed(&tx)?,
            1 => crate::seed::seed_v2(&tx)?,
            2 => crate::seed::seed_v3(&tx)?,
            3 => crate::seed::seed_v4(&tx)?,
            _ => {}
        }
        tx.pragma_update(None, "user_version", (i + 1) as i64)?;
    }
    tx.commit()?;
    Ok(())
}

/// The schema version of an open knowledge base.
pub fn schema_version(conn: &Connection) -> Result<i64, KnowledgeError> {
    Ok(conn.pragma_query_value(None, "user_version", |r| r.get(0))?)
}

/// The seeded 840D hobbing machine `H01`.
pub fn seed_machine_h01() -> MachineProfile {
    MachineProfile {
        id: MachineId::new("H01").expect("valid id"),
        name: "six-axis CNC hobbing machine, SINUMERIK 840D sl".into(),
        dialect: Dialect::Sinumerik840d,
        axes: AxisNames {
            radial: "X".into(),
            axial: "Z".into(),
            swivel: "A".into(),
            hob: "B".into(),
            table: "C".into(),
            shift: "Y".into(),
        },
        // M-codes as in the patent's 840D program (M20/M21 outer support,
        // M10/M11 fixture, M7/M9 coolant, M2 end); conveyor and mist separator
        // codes are this machine's builder codes.
        mcodes: MCodes {
            spindle_on: 3,
            spindle_off: 5,
            coolant_on: 7,
            coolant_off: 9,
            outer_support_on: 20,
            outer_support_off: 21,
            fixture_clamp: 10,
            fixture_unclamp: 11,
            chip_conveyor_on: 24,
            chip_conveyor_off: 25,
            mist_on: 26,
            mist_off: 27,
            program_end: 2,
        },
        limits: MachineLimits {
            module_mm: [0.5, 8.0],
            max_workpiece_od_mm: 320.0,
            max_hob_od_mm: 130.0,
            x_mm: [0.0, 400.0],
            z_mm: [-50.0, 400.0],
            max_hob_rpm: 1500.0,
            max_table_rpm: 150.0,
            max_axial_feed_mm_min: 2000.0,
            max_swivel_deg: 45.0,
        },
        settings: MachineSettings {
            blank_od_below_mm: 2.0,
            blank_od_above_mm: 0.5,
            depth_allowance_mm: 0.5,
            safety_mm: 2.0,
            retract_mm: 100.0,
            exit_mm: 5.0,
            swivel_sign: -1.0,
            swivel_offset_deg: 0.0,
            table_sign: 1.0,
            hob_sign: 1.0,
            shift_sign: -1.0,
        },
        gcode_system: GCodeSystem::Sinumerik,
        envelope: Envelope {
            table_radius_mm: 130.0,
            fixture_radius_mm: 30.0,
            tailstock_radius_mm: 20.0,
            tailstock_gap_mm: 60.0,
        },
        work_offset: "G54".into(),
        parameters: ParameterBlock {
            r_first: 1,
            macro_first: 501,
        },
        home_x_mm: 300.0,
        home_z_mm: 350.0,
    }
}

/// Provenance of the seeded FANUC machine `H02`.
pub const H02_SOURCE: &str =
    "gearcam seed: example FANUC hobbing machine, an M-series control (Series 0i-MF Plus / 30i-B, \
G-code system M: G90 absolute, G94 feed per minute; the EGB G81 T L Q P is an M-series command) \
with the EGB electronic gear box option: the hob spindle leads, the table C follows, coupled by \
G81 T_ L_ Q_ P_ ... G80); X is programmed as a radius, i.e. the centre distance (parameter 1006#3 \
DIAx = 0). M3/M5 spindle, M8/M9 coolant and M30 end are ISO/FANUC conventions; M10/M11 fixture, \
M24/M25 chip conveyor, M26/M27 mist separator and M68/M69 outer support are this shop's \
assignments (M-codes beyond M3/M5/M8/M9/M30 are machine-builder specific): check them against \
your machine builder's M-code list. Travels and limits: a larger machine than H01 (engineering \
estimate); set them to your machine's";

/// The seeded FANUC hobbing machine `H02`: a larger machine than `H01`
/// (slower hob and table spindles, longer travels), programmed in the FANUC
/// dialect with the EGB hobbing cycle (see [`H02_SOURCE`]).
pub fn seed_machine_h02() -> MachineProfile {
    MachineProfile {
        id: MachineId::new("H02").expect("valid id"),
        name: "six-axis CNC hobbing machine, FANUC 0i-MF Plus (M series) with EGB".into(),
        dialect: Dialect::Fanuc,
        axes: AxisNames {
            // X radial (radius programming), Z axial, A hob head swivel,
            // C table, Y hob shift. The hob spindle is the EGB master
            // spindle, commanded by S and coupled by G81, never as an axis
            // word; `B` only names it in messages.
            radial: "X".into(),
            axial: "Z".into(),
            swivel: "A".into(),
            hob: "B".into(),
            table: "C".into(),
            shift: "Y".into(),
        },
        // M3/M5, M8/M9 and M30 as on every FANUC control; the others are
        // this shop's assignments on H02 (see H02_SOURCE).
        mcodes: MCodes {
            spindle_on: 3,
            spindle_off: 5,
            coolant_on: 8,
            coolant_off: 9,
            outer_support_on: 68,
            outer_support_off: 69,
            fixture_clamp: 10,
            fixture_unclamp: 11,
            chip_conveyor_on: 24,
            chip_conveyor_off: 25,
            mist_on: 26,
            mist_off: 27,
            program_end: 30,
        },
        limits: MachineLimits {
            module_mm: [1.0, 8.0],
            max_workpiece_od_mm: 500.0,
            max_hob_od_mm: 180.0,
            x_mm: [0.0, 500.0],
            z_mm: [-50.0, 600.0],
            max_hob_rpm: 1000.0,
            max_table_rpm: 100.0,
            max_axial_feed_mm_min: 1500.0,
            max_swivel_deg: 45.0,
        },
        settings: MachineSettings {
            blank_od_below_mm: 2.0,
            blank_od_above_mm: 0.5,
            depth_allowance_mm: 0.5,
            safety_mm: 3.0,
            retract_mm: 120.0,
            exit_mm: 5.0,
            swivel_sign: -1.0,
            swivel_offset_deg: 0.0,
            table_sign: 1.0,
            hob_sign: 1.0,
            shift_sign: -1.0,
        },
        gcode_system: GCodeSystem::FanucM,
        envelope: Envelope {
            table_radius_mm: 200.0,
            fixture_radius_mm: 30.0,
            tailstock_radius_mm: 25.0,
            tailstock_gap_mm: 80.0,
        },
        work_offset: "G54".into(),
        parameters: ParameterBlock {
            r_first: 1,
            macro_first: 501,
        },
        home_x_mm: 450.0,
        home_z_mm: 550.0,
    }
}

/// Inserts a seed machine unless the database already has a machine with
/// its id (a shop that added its own `H02` keeps it).
pub(crate) fn seed_machine(
    tx: &rusqlite::Transaction<'_>,
    m: &MachineProfile,
    source: &str,
) -> Result<(), KnowledgeError> {
    tx.execute(
        "INSERT OR IGNORE INTO machines (id, name, dialect, profile_json, source) VALUES (?1, ?2, ?3, ?4, ?5)",
        params![
            m.id.as_str(),
            m.name,
            m.dialect.as_str(),
            serde_json::to_string(m)?,
            source,
        ],
    )?;
    Ok(())
}

struct SeedHob {
    id: &'static str,
    module_mm: f64,
    starts: u32,
    hand: &'static str,
    od_mm: f64,
    length_mm: f64,
}

/// Seed hobs. Outside diameters and lengths follow common single-piece hob
/// sizes; the lead angle is derived, not catalogued: the reference diameter is
/// taken as d0 = da0 − 2·1.25·mn0 (tip 1.25·mn0 over d0, so SPEC §4.2 check 4
/// holds with equality for ha* = 1, c* = 0.25) and γ0 = asin(z0·mn0 / d0).
const SEED_HOBS: &[SeedHob] = &[
    SeedHob {
        id: "HOB-M2-70",
        module_mm: 2.0,
        starts: 1,
        hand: "right",
        od_mm: 70.0,
        length_mm: 70.0,
    },
    SeedHob {
        id: "HOB-M3-80",
        module_mm: 3.0,
        starts: 1,
        hand: "right",
        od_mm: 80.0,
        length_mm: 100.0,
    },
    SeedHob {
        id: "HOB-M3-80L",
        module_mm: 3.0,
        starts: 1,
        hand: "left",
        od_mm: 80.0,
        length_mm: 100.0,
    },
    SeedHob {
        id: "HOB-M3-100-2",
        module_mm: 3.0,
        starts: 2,
        hand: "right",
        od_mm: 100.0,
        length_mm: 120.0,
    },
    SeedHob {
        id: "HOB-M4-90",
        module_mm: 4.0,
        starts: 1,
        hand: "right",
        od_mm: 90.0,
        length_mm: 110.0,
    },
];

/// Provenance of the seeded 840D machine `H01`.
pub const H01_SOURCE: &str = "gearcam seed: example 840D hobbing machine; M-codes of the patent CN1838008 program; set travels and limits to your machine's";

fn seed(tx: &rusqlite::Transaction<'_>) -> Result<(), KnowledgeError> {
    seed_machine(tx, &seed_machine_h01(), H01_SOURCE)?;
    for h in SEED_HOBS {
        let d0 = h.od_mm - 2.0 * 1.25 * h.module_mm;
        let lead = (h.starts as f64 * h.module_mm / d0).asin().to_degrees();
        tx.execute(
            "INSERT INTO hobs (id, module_mm, pressure_angle_deg, starts, hand, lead_angle_deg, od_mm, length_mm,
                               usable_length_mm, accuracy_class, material, coating, source)
             VALUES (?1, ?2, 20.0, ?3, ?4, ?5, ?6, ?7, ?8, 'A', 'HSS', 'TiN', ?9)",
            params![
                h.id,
                h.module_mm,
                h.starts,
                h.hand,
                lead,
                h.od_mm,
                h.length_mm,
                h.length_mm - 10.0,
                "gearcam seed: typical solid-hob size; lead angle derived from d0 = da0 - 2.5*mn0",
            ],
        )?;
    }
    const STOCK: &str = "gearcam seed: engineering estimate for TiN-coated HSS hobs, one cut, from general hobbing practice (not shop history); replace by importing your cases";
    for (id, group, vc, fa, conf) in [
        ("CD-CASE-HSS", "case_hardening_steel", 90.0, 2.0, 0.5),
        ("CD-QT-HSS", "quenched_tempered_steel", 80.0, 1.8, 0.5),
        ("CD-CI-HSS", "cast_iron", 100.0, 2.5, 0.4),
        ("CD-NF-HSS", "nonferrous", 150.0, 2.5, 0.3),
        ("CD-STEEL-HSS", "steel", 80.0, 1.8, 0.3),
    ] {
        tx.execute(
            "INSERT INTO cutting_data VALUES (?1, ?2, 'HSS', ?3, ?4, ?5, ?6)",
            params![id, group, vc, fa, conf, STOCK],
        )?;
    }
    for (name, group) in [
        ("20CrMnTi", "case_hardening_steel"),
        ("16MnCr5", "case_hardening_steel"),
        ("20MnCr5", "case_hardening_steel"),
        ("18CrNiMo7-6", "case_hardening_steel"),
        ("20CrMo", "case_hardening_steel"),
        ("42CrMo4", "quenched_tempered_steel"),
        ("42CrMo", "quenched_tempered_steel"),
        ("40Cr", "quenched_tempered_steel"),
        ("C45", "quenched_tempered_steel"),
        ("45", "quenched_tempered_steel"),
        ("GG25", "cast_iron"),
        ("HT250", "cast_iron"),
        ("EN-GJL-250", "cast_iron"),
        ("QT600", "cast_iron"),
        ("CuSn12", "nonferrous"),
        ("brass", "nonferrous"),
    ] {
        tx.execute(
            "INSERT INTO materials VALUES (?1, ?2)",
            params![name, group],
        )?;
    }
    Ok(())
}

/// A machine's profile by id.
pub fn machine(
    conn: &Connection,
    id: &MachineId,
) -> Result<Option<MachineProfile>, KnowledgeError> {
    let json: Option<String> = conn
        .query_row(
            "SELECT profile_json FROM machines WHERE id = ?1",
            [id.as_str()],
            |r| r.get(0),
        )
        .optional()?;
    json.map(|j| serde_json::from_str(&j).map_err(KnowledgeError::from))
        .transpose()
}

/// Every machine's profile, ordered by id.
pub fn machines(conn: &Connection) -> Result<Vec<MachineProfile>, KnowledgeError> {
    let mut stmt = conn.prepare("SELECT profile_json FROM machines ORDER BY id")?;
    let rows = stmt.query_map([], |r| r.get::<_, String>(0))?;
    let mut out = Vec::new();
    for j in rows {
        out.push(serde_json::from_str(&j?)?);
    }
    Ok(out)
}

/// A hob's data as the model needs it. Its source is `library`: the hob's
/// geometry comes from the tool library, not from a case or the machine.
fn hob_from_row(r: &rusqlite::Row<'_>) -> rusqlite::Result<HobData> {
    let hand: String = r.get("hand")?;
    Ok(HobData {
        id: r.get("id")?,
        starts: r.get("starts")?,
        od_mm: r.get("od_mm")?,
        module_mm: r.get("module_mm")?,
        pressure_angle_deg: r.get("pressure_angle_deg")?,
        lead_angle_deg: r.get("lead_angle_deg")?,
        hand: if hand == "left" {
            Hand::Left
        } else {
            Hand::Right
        },
        length_mm: r.get("length_mm")?,
        source: Source::Library,
    })
}

/// A hob by id.
pub fn hob(conn: &Connection, id: &str) -> Result<Option<HobData>, KnowledgeError> {
    Ok(conn
        .query_row("SELECT * FROM hobs WHERE id = ?1", [id], hob_from_row)
        .optional()?)
}

/// Every hob, ordered by id.
pub fn hobs(conn: &Connection) -> Result<Vec<HobData>, KnowledgeError> {
    let mut stmt = conn.prepare("SELECT * FROM hobs ORDER BY id")?;
    let rows = stmt.query_map([], hob_from_row)?;
    Ok(rows.collect::<Result<_, _>>()?)
}

/// The material group of a material name, if the materials table knows it.
pub fn material_group(conn: &Connection, material: &str) -> Result<Option<String>, KnowledgeError> {
    Ok(conn
        .query_row(
            "SELECT material_group FROM materials WHERE name = ?1",
            [material.trim()],
            |r| r.get(0),
        )
        .optional()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::library;

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
        conn.pragma_update(None, "user_version", 2).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(schema_version(&conn).unwrap(), 4);
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
        conn.pragma_update(None, "user_version", 3).unwrap();
        drop(conn);
        let conn = open(&path).unwrap();
        assert_eq!(schema_version(&conn).unwrap(), 4);
        assert_eq!(machine(&conn, &id).unwrap(), Some(seed_machine_h01()));
        let sp = library::get(&conn, &library::WORKPIECES, "SP-1001")
            .unwrap()
            .unwrap();
        assert_eq!(sp["fixture_height_mm"], 100.0);
    }
}
