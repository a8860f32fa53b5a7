//! The typed records of the machining history and the workpiece library as
//! the types of retrieval ([`crate::cbr`]) and of a job's drawing data.

use std::collections::BTreeMap;

use gearcam_proto::{ConeSpec, GearClass, GearSpec, LargeEnd};
use rusqlite::Connection;

use crate::cbr::{Case, CaseBase, Problem, Solution, Weights};
use crate::records::{self, CaseOutcome, CaseRecord, WorkpieceRecord};
use crate::KnowledgeError;

/// A case for retrieval from its record. A case whose job needed rework is
/// trusted half as much as its recorded confidence.
pub fn case_from_record(r: &CaseRecord) -> Case {
    Case {
        id: r.id.clone(),
        problem: Problem {
            class: r.class.as_str().to_string(),
            material: r.material.clone(),
            material_group: r.material_group.clone(),
            hardness_hb: r.hardness_hb,
            module_mm: r.module_mm,
            teeth: r.teeth,
            helix_angle_deg: r.helix_angle_deg,
            face_width_mm: r.face_width_mm,
            quality_grade: r.quality_grade,
            hob_material: Some(r.hob_material.clone()),
            hob_coating: Some(r.hob_coating.clone()),
            hob_starts: r.hob_starts,
            operation: r.operation.into(),
            machine: r.machine.clone(),
        },
        solution: Solution {
            cutting_speed_m_min: r.cutting_speed_m_min,
            feed_mm_per_rev: r.feed_mm_per_rev,
            hob_od_mm: r.hob_od_mm,
            radial_feed_mm_min: r.radial_feed_mm_min,
            cuts: r.cuts,
            allowance_mm: r.allowance_mm,
            cut_mode: r.cut_mode,
        },
        confidence: r.confidence
            * match r.outcome {
                CaseOutcome::Rework => 0.5,
                CaseOutcome::Ok | CaseOutcome::Scrap | CaseOutcome::Unknown => 1.0,
            },
        provenance: r.provenance.clone(),
    }
}

/// Every usable case (scrapped outcomes are history, not advice).
pub fn load_cases(conn: &Connection) -> Result<Vec<Case>, KnowledgeError> {
    Ok(records::cases(conn)?
        .iter()
        .filter(|r| r.outcome != CaseOutcome::Scrap)
        .map(case_from_record)
        .collect())
}

/// The case base in memory.
pub fn load_case_base(conn: &Connection) -> Result<CaseBase, KnowledgeError> {
    Ok(CaseBase::new(load_cases(conn)?))
}

/// The retrieval weights (defaults for features without a row).
pub fn load_weights(conn: &Connection) -> Result<Weights, KnowledgeError> {
    let map: BTreeMap<String, f64> = records::weights(conn)?
        .into_iter()
        .map(|w| (w.feature, w.weight))
        .collect();
    Ok(Weights::from_map(&map))
}

/// The drawing data of a workpiece record as a job's gear. A conical
/// workpiece with a cone angle becomes a conical gear (cone angle δ, blank
/// OD taken at the bottom face); the library holds no crowning, worm-wheel,
/// curved-tooth or unit data, see [`workpiece_lacks_class_data`].
pub fn gear_from_workpiece(w: &WorkpieceRecord) -> GearSpec {
    let mut g = GearSpec {
        module_mm: w.module_mm,
        teeth: w.teeth,
        pressure_angle_deg: w.pressure_angle_deg,
        helix_angle_deg: w.helix_angle_deg,
        helix_hand: w.helix_hand,
        face_width_mm: w.face_width_mm,
        profile_shift: w.profile_shift,
        addendum_coef: w.addendum_coef,
        clearance_coef: w.clearance_coef,
        blank_od_mm: w.blank_od_mm,
        od_correction_mm: w.od_correction_mm,
        material: w.material.clone(),
        quality_grade: w.quality_grade,
        fixture_height_mm: w.fixture_height_mm,
        fixture_diameter_mm: None,
        ball_diameter_mm: None,
        mate: None,
        cone: None,
        crowning: None,
        worm_wheel: None,
        curved_tooth: None,
    };
    if w.class == GearClass::Conical {
        g.cone = w.cone_angle_deg.map(|angle_deg| ConeSpec {
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
pub fn workpiece_lacks_class_data(
    w: &WorkpieceRecord,
    job_has_units: bool,
) -> Option<&'static str> {
    match w.class {
        GearClass::Cylindrical => None,
        GearClass::MultiGear if job_has_units => None,
        GearClass::Conical if w.cone_angle_deg.is_some() => None,
        GearClass::Conical => Some("the cone angle (cone_angle_deg)"),
        GearClass::Crowned => Some("the crowning ([gear.crowning])"),
        GearClass::WormWheel => Some("the worm-wheel hobbing data ([gear.worm_wheel])"),
        GearClass::CurvedTooth => Some("the tooth trace ([gear.curved_tooth])"),
        GearClass::MultiGear => Some("the gear units ([[units]]) of a multi-gear part"),
    }
}
