//! Seed data of every schema version: 1 (the 840D machine `H01`, the seed
//! hobs, materials and their groups), 2 (the class tree, hob accuracy/life
//! data, material hardness, starting cases, retrieval weights and example
//! workpieces), 3 (the FANUC machine `H02`) and 4 (older machine profiles
//! gain the new fields). Every row says where its values come from; where a
//! value is our own estimate it says "engineering estimate", and a shop
//! replaces it by importing its history (`gearcam kb import cases FILE.csv`).

use gearcam_proto::{
    AxisNames, Dialect, Envelope, GCodeSystem, Hand, MCodes, MachineId, MachineLimits,
    MachineProfile, MachineSettings, ParameterBlock,
};
use rusqlite::{params, Transaction};
use serde_json::{json, Value};

use crate::library::{self, Record};
use crate::records::{hand_name, HobRecord};
use crate::KnowledgeError;

/// Provenance of the starting cutting data.
pub const ESTIMATE: &str = "gearcam seed: engineering estimate for TiN-coated HSS hobs, one cut, \
from general hobbing practice (not shop history); feeds for modules 2 and 4 scaled from \
module 3 by sqrt(m/3), the same rule retrieval adapts with; replace by importing your cases";

/// Provenance of seed 000's bevel-gear example.
pub const SEED000: &str = "seed 000 (Cao, Yan, Guo 2015, CIMS 21(1), §4.2): straight bevel \
(conical involute) gear, cone 6.5°, hobbed rough with an AA hob on a 5-axis hobbing machine \
(840D); hob_rpm, axial and radial feed as published. Not published, derived here: \
cutting_speed_m_min = π·70·rpm/1000 assuming a 70 mm hob (the paper gives no hob diameter); \
feed_mm_per_rev = axial feed / (z0·rpm/z). Hob material not stated (HSS assumed), coating unknown";

/// Provenance of the example workpieces.
pub const EXAMPLES: &str = "gearcam example job files (examples/*.toml)";

pub(crate) fn insert(
    tx: &Transaction<'_>,
    lib: &library::Library,
    v: Value,
) -> Result<(), KnowledgeError> {
    let Value::Object(rec) = v else {
        unreachable!("seed records are objects")
    };
    let rec: Record = rec;
    match library::add(tx, lib, &rec) {
        Ok(_) => Ok(()),
        Err(errors) => Err(KnowledgeError::Seed(format!(
            "{} seed record invalid: {}",
            lib.name,
            errors
                .iter()
                .map(|e| e.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        ))),
    }
}

/// Seeds the tables of migration 2, one library at a time.
pub fn seed_v2(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    seed_classes(tx)?;
    seed_hob_life(tx)?;
    seed_hardness(tx)?;
    seed_weights(tx)?;
    seed_starting_cases(tx)?;
    seed_seed000_cases(tx)?;
    seed_example_workpieces(tx)
}

/// The group-technology class tree: the root `gear` and its classes, with
/// the tooth trace, deformation and hobbing method of each; only
/// `cylindrical` is programmed.
fn seed_classes(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    const GT: &str = "gearcam docs/knowledge.md#group-technology-classes / seed 000 §2.1 (group-technology classification tree)";
    for (id, parent, name, trace, deformation, method, programmable) in [
        ("gear", None, "hobbed gears", "-", "-", "hobbing", false),
        (
            "cylindrical",
            Some("gear"),
            "cylindrical (spur, helical)",
            "straight or helix",
            "none",
            "axial or radial-axial hobbing (patent model)",
            true,
        ),
        (
            "conical",
            Some("gear"),
            "conical involute (beveloid)",
            "straight",
            "linear taper",
            "X follows Z along the cone angle",
            false,
        ),
        (
            "worm_wheel",
            Some("gear"),
            "worm wheel",
            "helix",
            "throated",
            "radial or tangential infeed",
            false,
        ),
        (
            "crowned",
            Some("gear"),
            "crowned (drum)",
            "helix",
            "crowned (barrel)",
            "X follows Z on the crowning curve",
            false,
        ),
        (
            "curved_tooth",
            Some("gear"),
            "curved-tooth",
            "curved",
            "-",
            "classified; not programmed yet",
            false,
        ),
        (
            "multi_gear",
            Some("gear"),
            "multi-gear (cluster), derived",
            "per unit",
            "per unit",
            "each unit by its own class",
            false,
        ),
    ] {
        insert(
            tx,
            &library::CLASSES_LIB,
            json!({"id": id, "parent": parent, "name": name, "tooth_trace": trace,
                   "deformation": deformation, "hobbing_method": method,
                   "programmable": programmable, "source": GT}),
        )?;
    }
    Ok(())
}

/// The seed hobs of migration 1 gain their accuracy class, shift plan and
/// life (in a database of an older gearcam too).
fn seed_hob_life(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for h in seed_hobs() {
        tx.execute(
            "UPDATE hobs SET accuracy_class = ?2, shift_position_mm = ?3, shift_step_mm = ?4,
                             parts_per_shift = ?5, remaining_life_parts = ?6, source = source || ?7
             WHERE id = ?1",
            params![
                h.id,
                h.accuracy_class,
                h.shift_position_mm,
                h.shift_step_mm,
                h.parts_per_shift,
                h.remaining_life_parts,
                HOB_LIFE
            ],
        )?;
    }
    Ok(())
}

/// Typical hardness when hobbed (soft / normalised or quenched and
/// tempered as usually supplied): engineering estimates from common
/// material data, to be replaced by the shop's incoming-inspection values.
fn seed_hardness(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    const HB: &str = "gearcam seed: typical hardness as hobbed, engineering estimate";
    for (name, hb) in [
        ("20CrMnTi", 180.0),
        ("16MnCr5", 180.0),
        ("20MnCr5", 185.0),
        ("18CrNiMo7-6", 200.0),
        ("20CrMo", 180.0),
        ("42CrMo4", 280.0),
        ("42CrMo", 280.0),
        ("40Cr", 250.0),
        ("C45", 200.0),
        ("45", 200.0),
        ("GG25", 200.0),
        ("HT250", 200.0),
        ("EN-GJL-250", 200.0),
        ("QT600", 230.0),
        ("CuSn12", 95.0),
        ("brass", 100.0),
    ] {
        tx.execute(
            "UPDATE materials SET hardness_hb = ?2, source = ?3 WHERE name = ?1",
            params![name, hb, HB],
        )?;
    }
    Ok(())
}

/// The retrieval weights of the similarity features, gearcam's defaults.
fn seed_weights(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (feature, weight) in crate::cbr::DEFAULT_WEIGHTS {
        insert(
            tx,
            &library::WEIGHTS,
            json!({"feature": feature, "weight": weight,
                   "source": "gearcam default: engineering estimate (module, hob material, starts and rough/finish matter most)"}),
        )?;
    }
    Ok(())
}

/// Starting cases: per material group at modules 2, 3, 4 (finish hobbing,
/// spur, 30 teeth, 30 mm face, grade 8, TiN-coated HSS, one start).
fn seed_starting_cases(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (group, material, hb, vc, fa3, conf) in [
        ("case_hardening_steel", "20CrMnTi", 180.0, 90.0, 2.0, 0.5),
        ("quenched_tempered_steel", "42CrMo4", 280.0, 80.0, 1.8, 0.5),
        ("cast_iron", "GG25", 200.0, 100.0, 2.5, 0.4),
        ("nonferrous", "CuSn12", 95.0, 150.0, 2.5, 0.3),
    ] {
        for module in [2.0_f64, 3.0, 4.0] {
            let fa = (fa3 * (module / 3.0).sqrt() * 100.0).round() / 100.0;
            let id = format!("SEED-{}-M{}", group_code(group), module as u32);
            insert(
                tx,
                &library::CASES,
                json!({"id": id, "class": "cylindrical", "material": material,
                       "material_group": group, "hardness_hb": hb, "module_mm": module,
                       "teeth": 30, "helix_angle_deg": 0.0, "face_width_mm": 30.0,
                       "quality_grade": 8, "hob_material": "HSS", "hob_coating": "TiN",
                       "hob_starts": 1, "operation": "finish",
                       "cutting_speed_m_min": vc, "feed_mm_per_rev": fa, "cuts": 1,
                       "outcome": "unknown", "confidence": conf, "provenance": ESTIMATE}),
            )?;
        }
    }
    Ok(())
}

/// Seed 000 §4.2: the paper's system proposal and the hand-programmed values.
fn seed_seed000_cases(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (id, rpm, vf, vr, conf, what) in [
        (
            "SEED000-BEVEL-CBR",
            246.0,
            105.0,
            36.0,
            0.6,
            "the paper's proposed values",
        ),
        (
            "SEED000-BEVEL-HAND",
            236.0,
            96.0,
            32.0,
            0.5,
            "the hand-programmed values the paper compares with",
        ),
    ] {
        let vc = std::f64::consts::PI * 70.0 * rpm / 1000.0;
        let fa = vf / (rpm / 19.0);
        insert(
            tx,
            &library::CASES,
            json!({"id": id, "class": "conical", "material": "40Cr",
                   "material_group": "quenched_tempered_steel", "module_mm": 2.0,
                   "teeth": 19, "helix_angle_deg": 0.0, "quality_grade": 7,
                   "hob_material": "HSS", "hob_coating": "unknown", "hob_starts": 1,
                   "operation": "rough", "cutting_speed_m_min": (vc * 10.0).round() / 10.0,
                   "feed_mm_per_rev": (fa * 100.0).round() / 100.0, "hob_rpm": rpm,
                   "axial_feed_mm_min": vf, "radial_feed_mm_min": vr, "cuts": 1,
                   "allowance_mm": 2.5, "shifting": false, "outcome": "ok",
                   "notes": format!("{what}; blank OD 42.5 mm, coolant on, tailstock clamp, no shift"),
                   "confidence": conf, "provenance": SEED000}),
        )?;
    }
    Ok(())
}

/// Example workpieces: the parts of the bundled example jobs.
fn seed_example_workpieces(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    const EX: &str = EXAMPLES;
    for w in [
        json!({"part_number": "SP-1001", "description": "spur gear of the patent embodiment",
               "module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0, "blank_od_mm": 81.0,
               "material": "20CrMnTi", "quality_grade": 7, "fixture_height_mm": 100.0, "source": EX}),
        json!({"part_number": "HG-2002", "description": "right-hand helical gear",
               "module_mm": 3.0, "teeth": 25, "helix_angle_deg": 15.0, "helix_hand": "right",
               "face_width_mm": 40.0, "material": "42CrMo4", "quality_grade": 7,
               "fixture_height_mm": 100.0, "source": EX}),
        json!({"part_number": "HG-3003-L", "description": "left-hand helical gear, climb cut",
               "module_mm": 3.0, "teeth": 31, "helix_angle_deg": 20.0, "helix_hand": "left",
               "profile_shift": 0.2,
               "face_width_mm": 25.0, "material": "16MnCr5", "fixture_height_mm": 100.0, "source": EX}),
    ] {
        insert(tx, &library::WORKPIECES, w)?;
    }
    Ok(())
}

/// Seeds version 3: the FANUC hobbing machine `H02` beside the 840D machine
/// `H01`, so a job names its machine and so its dialect.
///
/// No cutting-data cases are seeded for H02. The starting cases are general
/// estimates, recorded without a machine, so they apply to every machine
/// alike (machine similarity 0.6 for H01 and H02 both): a job on H02 gets
/// the same proposal as the same job on H01, clamped to H02's slower spindle
/// and table. That is what a shop expects of data that was never cut on
/// either machine. Cases the shop confirms on H02 carry `machine = H02` and
/// then rank above the general ones for H02 jobs (similarity 1 on that
/// feature), while H01's history stays usable there at 0.6.
///
/// It also repairs a version-2 seed record: workpiece `HG-3003-L` lacked the
/// profile shift 0.2 of its example job (`helical_climb_840d.toml`); a record
/// the shop has changed since is left alone.
pub fn seed_v3(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    seed_machine(tx, &seed_machine_h02(), H02_SOURCE)?;
    tx.execute(
        "UPDATE workpieces SET profile_shift = 0.2
         WHERE part_number = 'HG-3003-L' AND profile_shift = 0 AND source = ?1",
        [EXAMPLES],
    )?;
    Ok(())
}

/// Seeds migration 4 into a database made by an older gearcam. Every
/// machine profile without the new fields gains them, converted so that its
/// programs of right-hand set-ups stay what they were: `swivel_sign` now maps
/// the signed setting angle η (the old one mapped the patent's γ = −η for
/// those), so it is negated; the table, hob and shift senses are those the
/// old programs implied (+1, +1, −1, docs/hobbing.md); the work offset `G54`
/// and the parameter block R1…/#501… are what the old programs used; the
/// G-code system is the dialect's (the FANUC templates write system M). The
/// envelope is the seed's for `H01` and `H02`; another machine's is estimated
/// (table radius = half the largest workpiece, fixture radius 0, no
/// tailstock), and its source says so: check it. A field the profile has is
/// kept. The example workpieces stood on fixtures too low for the hob's
/// run-out; unchanged, they take 100 mm.
pub fn seed_v4(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    let rows: Vec<(String, String, String)> = {
        let mut stmt = tx.prepare("SELECT id, profile_json, source FROM machines")?;
        let rows = stmt.query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?;
        rows.collect::<Result<_, _>>()?
    };
    for (id, json, source) in rows {
        let mut v: Value = serde_json::from_str(&json)?;
        let seed = match id.as_str() {
            "H01" => Some(seed_machine_h01()),
            "H02" => Some(seed_machine_h02()),
            _ => None,
        };
        let Some(obj) = v.as_object_mut() else {
            continue;
        };
        let mut notes = Vec::new();
        if let Some(settings) = obj.get_mut("settings").and_then(Value::as_object_mut) {
            if !settings.contains_key("table_sign") {
                let old = settings
                    .get("swivel_sign")
                    .and_then(Value::as_f64)
                    .unwrap_or(1.0);
                settings.insert("swivel_sign".into(), json!(-old));
                settings.insert("swivel_offset_deg".into(), json!(0.0));
                settings.insert("table_sign".into(), json!(1.0));
                settings.insert("hob_sign".into(), json!(1.0));
                settings.insert("shift_sign".into(), json!(-1.0));
                notes.push("axis senses of the old programs (swivel_sign negated to map η)");
            }
        }
        let fanuc = obj.get("dialect").and_then(Value::as_str) == Some("fanuc");
        let defaults = [
            (
                "gcode_system",
                json!(if fanuc { "fanuc_m" } else { "sinumerik" }),
            ),
            ("work_offset", json!("G54")),
            ("parameters", json!({"r_first": 1, "macro_first": 501})),
        ];
        for (key, value) in defaults {
            if !obj.contains_key(key) {
                obj.insert(key.into(), value);
                notes.push("G-code system, work offset and parameters of the old programs");
            }
        }
        if !obj.contains_key("envelope") {
            let envelope = match &seed {
                Some(m) => serde_json::to_value(&m.envelope)?,
                None => {
                    notes.push("envelope ESTIMATED: table radius half the largest workpiece, no fixture, no tailstock; set the machine's");
                    let od = obj
                        .get("limits")
                        .and_then(|l| l.get("max_workpiece_od_mm"))
                        .and_then(Value::as_f64)
                        .unwrap_or(0.0);
                    json!({"table_radius_mm": od / 2.0, "fixture_radius_mm": 0.0,
                           "tailstock_radius_mm": 0.0, "tailstock_gap_mm": 0.0})
                }
            };
            obj.insert("envelope".into(), envelope);
        }
        if notes.is_empty() {
            continue;
        }
        notes.dedup();
        tx.execute(
            "UPDATE machines SET profile_json = ?2, source = ?3 WHERE id = ?1",
            params![
                id,
                v.to_string(),
                format!("{source}; migrated to schema 4: {}", notes.join("; "))
            ],
        )?;
    }
    for (part, old) in [("SP-1001", 50.0), ("HG-2002", 60.0), ("HG-3003-L", 45.0)] {
        tx.execute(
            "UPDATE workpieces SET fixture_height_mm = 100.0
             WHERE part_number = ?1 AND fixture_height_mm = ?2 AND source = ?3",
            params![part, old, EXAMPLES],
        )?;
    }
    Ok(())
}

fn group_code(group: &str) -> &'static str {
    match group {
        "case_hardening_steel" => "CASE",
        "quenched_tempered_steel" => "QT",
        "cast_iron" => "CI",
        _ => "NF",
    }
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

/// Seed hobs: id, normal module mn0 (mm), starts z0, hand, outside diameter
/// da0 (mm), overall length (mm), accuracy class. Outside diameters and
/// lengths follow common single-piece hob sizes; the lead angle is derived,
/// not catalogued: the reference diameter is taken as d0 = da0 − 2·1.25·mn0
/// (tip 1.25·mn0 over d0, so docs/reference.md#check-4-hob-outside-diameter
/// holds with equality for ha* = 1, c* = 0.25) and γ0 = asin(z0·mn0 / d0).
/// Classes AA for the module-2/3 single-start hobs (grade 7 work, as in seed
/// 000's example), A for the others.
const SEED_HOBS: &[(&str, f64, u32, Hand, f64, f64, &str)] = &[
    ("HOB-M2-70", 2.0, 1, Hand::Right, 70.0, 70.0, "AA"),
    ("HOB-M3-80", 3.0, 1, Hand::Right, 80.0, 100.0, "AA"),
    ("HOB-M3-80L", 3.0, 1, Hand::Left, 80.0, 100.0, "AA"),
    ("HOB-M3-100-2", 3.0, 2, Hand::Right, 100.0, 120.0, "A"),
    ("HOB-M4-90", 4.0, 1, Hand::Right, 90.0, 110.0, "A"),
];

/// Provenance of the seed hobs' geometry (schema 1).
const HOB_SOURCE: &str =
    "gearcam seed: typical solid-hob size; lead angle derived from d0 = da0 - 2.5*mn0";

/// What schema 2 adds to the seed hobs' provenance.
const HOB_LIFE: &str = "; accuracy class, shift step 0.5 mm per 2 parts and remaining life 400 parts: engineering estimate, set them from your tool room";

/// The seed hobs as the tool library holds them from schema 2 on: TiN-coated
/// HSS, the usable length 10 mm short of the overall length, at the start of
/// their usable length, shifted 0.5 mm per 2 parts, with 400 parts of life
/// (engineering estimates; see `SEED_HOBS` for the geometry).
pub fn seed_hobs() -> Vec<HobRecord> {
    SEED_HOBS
        .iter()
        .map(|&(id, module_mm, starts, hand, od_mm, length_mm, class)| {
            let d0 = od_mm - 2.0 * 1.25 * module_mm;
            HobRecord {
                id: id.into(),
                module_mm,
                pressure_angle_deg: 20.0,
                starts,
                hand,
                lead_angle_deg: (f64::from(starts) * module_mm / d0).asin().to_degrees(),
                od_mm,
                length_mm,
                usable_length_mm: length_mm - 10.0,
                accuracy_class: class.into(),
                material: "HSS".into(),
                coating: "TiN".into(),
                shift_position_mm: 0.0,
                shift_step_mm: 0.5,
                parts_per_shift: 2,
                remaining_life_parts: 400,
                source: format!("{HOB_SOURCE}{HOB_LIFE}"),
            }
        })
        .collect()
}

/// Provenance of the seeded 840D machine `H01`.
pub const H01_SOURCE: &str = "gearcam seed: example 840D hobbing machine; M-codes of the patent CN1838008 program; set travels and limits to your machine's";

pub(crate) fn seed_v1(tx: &rusqlite::Transaction<'_>) -> Result<(), KnowledgeError> {
    seed_machine(tx, &seed_machine_h01(), H01_SOURCE)?;
    // The columns of schema 1; schema 2 adds the shift plan and life.
    for h in seed_hobs() {
        tx.execute(
            "INSERT INTO hobs (id, module_mm, pressure_angle_deg, starts, hand, lead_angle_deg, od_mm, length_mm,
                               usable_length_mm, accuracy_class, material, coating, source)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)",
            params![
                h.id,
                h.module_mm,
                h.pressure_angle_deg,
                h.starts,
                hand_name(h.hand),
                h.lead_angle_deg,
                h.od_mm,
                h.length_mm,
                h.usable_length_mm,
                h.accuracy_class,
                h.material,
                h.coating,
                HOB_SOURCE,
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
