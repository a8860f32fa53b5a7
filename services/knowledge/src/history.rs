//! Reads the libraries into the plain types of retrieval and hob matching.

use std::collections::BTreeMap;

use gearcam_proto::{ConeSpec, CutMode, GearSpec, Hand, HobData, LargeEnd, Source};
use rusqlite::{Connection, OptionalExtension};
use serde_json::Value;

use crate::cbr::{Case, CaseBase, Operation, Problem, Solution, Weights};
use crate::hobmatch::Hob;
use crate::library::{self, Record};
use crate::KnowledgeError;

fn f(r: &Record, k: &str) -> Option<f64> {
    r.get(k).and_then(Value::as_f64)
}

fn s(r: &Record, k: &str) -> Option<String> {
    r.get(k).and_then(Value::as_str).map(str::to_string)
}

/// A case from its library record (a record that passed validation).
pub fn case_from_record(r: &Record) -> Case {
    Case {
        id: s(r, "id").unwrap_or_default(),
        problem: Problem {
            class: s(r, "class").unwrap_or_default(),
            material: s(r, "material").unwrap_or_default(),
            material_group: s(r, "material_group").unwrap_or_default(),
            hardness_hb: f(r, "hardness_hb"),
            module_mm: f(r, "module_mm").unwrap_or(1.0),
            teeth: f(r, "teeth").unwrap_or(1.0) as u32,
            helix_angle_deg: f(r, "helix_angle_deg").unwrap_or(0.0),
            face_width_mm: f(r, "face_width_mm"),
            quality_grade: f(r, "quality_grade").unwrap_or(8.0) as u8,
            hob_material: s(r, "hob_material"),
            hob_coating: s(r, "hob_coating"),
            hob_starts: f(r, "hob_starts").unwrap_or(1.0) as u32,
            operation: Operation::parse(&s(r, "operation").unwrap_or_default()),
            machine: s(r, "machine"),
        },
        solution: Solution {
            cutting_speed_m_min: f(r, "cutting_speed_m_min").unwrap_or(0.0),
            feed_mm_per_rev: f(r, "feed_mm_per_rev").unwrap_or(0.0),
            hob_od_mm: f(r, "hob_od_mm"),
            radial_feed_mm_min: f(r, "radial_feed_mm_min"),
            cuts: f(r, "cuts").unwrap_or(1.0) as u32,
            allowance_mm: f(r, "allowance_mm"),
            cut_mode: match s(r, "cut_mode").as_deref() {
                Some("climb") => Some(CutMode::Climb),
                Some("conventional") => Some(CutMode::Conventional),
                _ => None,
            },
        },
        confidence: f(r, "confidence").unwrap_or(0.0)
            * match s(r, "outcome").as_deref() {
                // A case that needed rework is trusted half as much.
                Some("rework") => 0.5,
                _ => 1.0,
            },
        provenance: s(r, "provenance").unwrap_or_default(),
    }
}

/// Every usable case (scrapped outcomes are history, not advice).
pub fn load_cases(conn: &Connection) -> Result<Vec<Case>, KnowledgeError> {
    Ok(library::list(conn, &library::CASES)?
        .iter()
        .filter(|r| s(r, "outcome").as_deref() != Some("scrap"))
        .map(case_from_record)
        .collect())
}

/// The case base in memory.
pub fn load_case_base(conn: &Connection) -> Result<CaseBase, KnowledgeError> {
    Ok(CaseBase::new(load_cases(conn)?))
}

/// The retrieval weights (defaults for features without a row).
pub fn load_weights(conn: &Connection) -> Result<Weights, KnowledgeError> {
    let map: BTreeMap<String, f64> = library::list(conn, &library::WEIGHTS)?
        .iter()
        .filter_map(|r| Some((s(r, "feature")?, f(r, "weight")?)))
        .collect();
    Ok(Weights::from_map(&map))
}

/// A material's group and typical hardness.
pub fn material(
    conn: &Connection,
    name: &str,
) -> Result<Option<(String, Option<f64>)>, KnowledgeError> {
    Ok(conn
        .query_row(
            "SELECT material_group, hardness_hb FROM materials WHERE name = ?1",
            [name.trim()],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .optional()?)
}

/// A library hob for matching, its data for the plan, and its material and coating.
#[derive(Debug, Clone)]
pub struct LibraryHob {
    /// For matching.
    pub hob: Hob,
    /// For the plan.
    pub data: HobData,
    /// Cutting material.
    pub material: String,
    /// Coating.
    pub coating: String,
}

/// A hob from its library record.
pub fn hob_from_record(r: &Record) -> LibraryHob {
    let hand = if s(r, "hand").as_deref() == Some("left") {
        Hand::Left
    } else {
        Hand::Right
    };
    let id = s(r, "id").unwrap_or_default();
    LibraryHob {
        hob: Hob {
            id: id.clone(),
            module_mm: f(r, "module_mm").unwrap_or(0.0),
            pressure_angle_deg: f(r, "pressure_angle_deg").unwrap_or(20.0),
            starts: f(r, "starts").unwrap_or(1.0) as u32,
            hand,
            lead_angle_deg: f(r, "lead_angle_deg").unwrap_or(0.0),
            od_mm: f(r, "od_mm").unwrap_or(0.0),
            usable_length_mm: f(r, "usable_length_mm").unwrap_or(0.0),
            accuracy_class: s(r, "accuracy_class").unwrap_or_default(),
            shift_position_mm: f(r, "shift_position_mm").unwrap_or(0.0),
            shift_step_mm: f(r, "shift_step_mm").unwrap_or(0.5),
            parts_per_shift: f(r, "parts_per_shift").unwrap_or(1.0) as u32,
            remaining_life_parts: f(r, "remaining_life_parts").unwrap_or(0.0) as u64,
        },
        data: HobData {
            id,
            starts: f(r, "starts").unwrap_or(1.0) as u32,
            od_mm: f(r, "od_mm").unwrap_or(0.0),
            module_mm: f(r, "module_mm").unwrap_or(0.0),
            pressure_angle_deg: f(r, "pressure_angle_deg").unwrap_or(20.0),
            lead_angle_deg: f(r, "lead_angle_deg").unwrap_or(0.0),
            hand,
            length_mm: f(r, "length_mm").unwrap_or(0.0),
            source: Source::Library,
        },
        material: s(r, "material").unwrap_or_default(),
        coating: s(r, "coating").unwrap_or_default(),
    }
}

/// Every library hob.
pub fn library_hobs(conn: &Connection) -> Result<Vec<LibraryHob>, KnowledgeError> {
    Ok(library::list(conn, &library::HOBS)?
        .iter()
        .map(hob_from_record)
        .collect())
}

/// The drawing data of a workpiece record (a record that passed validation)
/// as a job's gear. A conical workpiece with a cone angle becomes a conical
/// gear (cone angle δ, blank OD taken at the bottom face); the library holds
/// no crowning, worm-wheel, curved-tooth or unit data, see
/// [`workpiece_lacks_class_data`].
pub fn gear_from_workpiece(r: &Record) -> GearSpec {
    let mut g = GearSpec::absent();
    g.module_mm = f(r, "module_mm").unwrap_or(0.0);
    g.teeth = f(r, "teeth").unwrap_or(0.0) as u32;
    g.pressure_angle_deg = f(r, "pressure_angle_deg").unwrap_or(20.0);
    g.helix_angle_deg = f(r, "helix_angle_deg").unwrap_or(0.0);
    g.helix_hand = match s(r, "helix_hand").as_deref() {
        Some("left") => Some(Hand::Left),
        Some("right") => Some(Hand::Right),
        _ => None,
    };
    g.face_width_mm = f(r, "face_width_mm").unwrap_or(0.0);
    g.profile_shift = f(r, "profile_shift").unwrap_or(0.0);
    g.addendum_coef = f(r, "addendum_coef").unwrap_or(1.0);
    g.clearance_coef = f(r, "clearance_coef").unwrap_or(0.25);
    g.blank_od_mm = f(r, "blank_od_mm");
    g.od_correction_mm = f(r, "od_correction_mm").unwrap_or(0.0);
    if let Some(m) = s(r, "material") {
        g.material = m;
    }
    g.quality_grade = f(r, "quality_grade").unwrap_or(8.0) as u8;
    g.fixture_height_mm = f(r, "fixture_height_mm").unwrap_or(0.0);
    if s(r, "class").as_deref() == Some("conical") {
        g.cone = f(r, "cone_angle_deg").map(|angle_deg| ConeSpec {
            angle_deg,
            large_end: LargeEnd::Bottom,
        });
    }
    g
}

/// What a workpiece record lacks to stand for a whole `[gear]` section:
/// `None` for a cylindrical part, a conical one with its cone angle, and a
/// multi-gear part whose job gives the further units (the record is the
/// first unit); otherwise the class data a job must give itself.
pub fn workpiece_lacks_class_data(r: &Record, job_has_units: bool) -> Option<&'static str> {
    match s(r, "class").as_deref().unwrap_or("cylindrical") {
        "cylindrical" => None,
        "multi_gear" if job_has_units => None,
        "conical" if f(r, "cone_angle_deg").is_some() => None,
        "conical" => Some("the cone angle (cone_angle_deg)"),
        "crowned" => Some("the crowning ([gear.crowning])"),
        "worm_wheel" => Some("the worm-wheel hobbing data ([gear.worm_wheel])"),
        "curved_tooth" => Some("the tooth trace ([gear.curved_tooth])"),
        _ => Some("the gear units ([[units]]) of a multi-gear part"),
    }
}
