//! The knowledge base in SQLite: schema migrations, seed data, and reads.
//!
//! The database is created and seeded on first open. Every seeded row says
//! where its values come from (`source`) and how far to trust them
//! (`confidence`); a shop replaces them with its own history.

use std::path::Path;

use gearcam_proto::{
    AxisNames, Dialect, Hand, HobData, MCodes, MachineId, MachineLimits, MachineProfile,
    MachineSettings, Source,
};
use rusqlite::{params, Connection, OptionalExtension};

use crate::KnowledgeError;

/// Schema migrations, applied in order; the index + 1 is the schema version.
const MIGRATIONS: &[&str] = &[r#"
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
"#];

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
    conn.pragma_update(None, "synchronous", "FULL")?;
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

fn migrate(conn: &mut Connection) -> Result<(), KnowledgeError> {
    let version: i64 = conn.pragma_query_value(None, "user_version", |r| r.get(0))?;
    let tx = conn.transaction()?;
    for (i, sql) in MIGRATIONS.iter().enumerate().skip(version as usize) {
        tx.execute_batch(sql)?;
        tx.pragma_update(None, "user_version", (i + 1) as i64)?;
    }
    if version == 0 {
        seed(&tx)?;
    }
    tx.commit()?;
    Ok(())
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
            swivel_sign: 1.0,
        },
        home_x_mm: 300.0,
        home_z_mm: 350.0,
    }
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

fn seed(tx: &rusqlite::Transaction<'_>) -> Result<(), KnowledgeError> {
    let h01 = seed_machine_h01();
    tx.execute(
        "INSERT INTO machines (id, name, dialect, profile_json, source) VALUES (?1, ?2, ?3, ?4, ?5)",
        params![
            h01.id.as_str(),
            h01.name,
            h01.dialect.as_str(),
            serde_json::to_string(&h01)?,
            "gearcam seed: example 840D hobbing machine; M-codes of the patent CN1838008 program; set travels and limits to your machine's",
        ],
    )?;
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

/// A cutting-data record.
#[derive(Debug, Clone, PartialEq)]
pub struct CuttingData {
    /// Record id.
    pub id: String,
    /// Material group it applies to.
    pub material_group: String,
    /// Cutting speed, m/min.
    pub cutting_speed_m_min: f64,
    /// Axial feed per workpiece revolution, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Confidence, 0–1.
    pub confidence: f64,
    /// Provenance.
    pub source: String,
}

/// The material group of a material name (`steel` when unknown).
pub fn material_group(conn: &Connection, material: &str) -> Result<Option<String>, KnowledgeError> {
    Ok(conn
        .query_row(
            "SELECT material_group FROM materials WHERE name = ?1",
            [material.trim()],
            |r| r.get(0),
        )
        .optional()?)
}

/// Cutting data for a material group and hob material.
pub fn cutting_data(
    conn: &Connection,
    group: &str,
    hob_material: &str,
) -> Result<Option<CuttingData>, KnowledgeError> {
    Ok(conn
        .query_row(
            "SELECT id, material_group, cutting_speed_m_min, feed_mm_per_rev, confidence, source
             FROM cutting_data WHERE material_group = ?1 AND hob_material = ?2
             ORDER BY confidence DESC, id LIMIT 1",
            params![group, hob_material],
            |r| {
                Ok(CuttingData {
                    id: r.get(0)?,
                    material_group: r.get(1)?,
                    cutting_speed_m_min: r.get(2)?,
                    feed_mm_per_rev: r.get(3)?,
                    confidence: r.get(4)?,
                    source: r.get(5)?,
                })
            },
        )
        .optional()?)
}
