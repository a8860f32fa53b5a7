//! Multi-gear parts (docs/reference.md#class-models): an ordered list of units, each of its own
//! class and hob, at its Z offset on the part; the hob is changed between
//! units when it differs.
//!
//! The job's `[gear]` and `[hob]` are the first unit at Z offset 0; each
//! `[[units]]` entry adds one. A unit's Z position is the job's fixture height
//! plus its offset (its own `fixture_height_mm` is replaced). A unit's hob is
//! given inline, or is the job's hob when its `[units.hob]` is empty or names
//! the job's hob id; library hobs for further units are not resolved yet.

use gearcam_proto::class::unit_class;
use gearcam_proto::Code;
use gearcam_proto::{
    GearClass, GearSpec, HobData, JobError, Kinematics, ProcessPlan, Source, Stage, UnitModel,
    UnitSpec,
};

use crate::geometry::geometry;
use crate::hobbing::{unit_kinematics, Unit};

/// The unit's gear with its Z position: fixture height H + offset.
pub fn unit_gear(plan: &ProcessPlan, unit: &UnitSpec) -> GearSpec {
    let mut g = unit.gear.clone();
    g.fixture_height_mm = plan.gear.fixture_height_mm + unit.z_offset_mm;
    g
}

/// The hob of unit `index` (0-based among `[[units]]`): inline data, or the
/// job's hob. Errors name the unit's fields.
pub fn unit_hob(
    plan: &ProcessPlan,
    index: usize,
    unit: &UnitSpec,
) -> Result<HobData, Vec<JobError>> {
    let h = &unit.hob;
    let field = |f: &str| format!("units[{index}].hob.{f}");
    let err = |code: Code, f: &str, expected: &str, got: String, message: String| {
        JobError::new(Stage::Model, code, &field(f), expected, got, message)
    };
    if let Some(id) = &h.id {
        if id.as_str() == plan.hob.id && !h.has_inline_data() {
            return Ok(plan.hob.clone());
        }
        return Err(vec![err(
            Code::UNIT_HOB_UNRESOLVED,
            "id",
            &format!("{} (the job's hob) or inline hob data", plan.hob.id),
            id.to_string(),
            format!(
                "unit {} names library hob {id}; only the job's hob is resolved from the library so far, so give this unit's hob inline",
                index + 2
            ),
        )]);
    }
    if !h.has_inline_data() {
        return Ok(plan.hob.clone());
    }
    let mut errors = Vec::new();
    let mut need = |name: &str, present: bool| {
        if !present {
            errors.push(err(
                Code::UNIT_HOB_INCOMPLETE,
                name,
                "a value (inline hob data needs starts, od_mm, module_mm, lead_angle_deg, hand, length_mm)",
                "nothing".into(),
                format!("unit {}'s inline hob lacks {name}; add it or leave [units.hob] empty to use the job's hob", index + 2),
            ));
        }
    };
    need("starts", h.starts.is_some());
    need("od_mm", h.od_mm.is_some());
    need("module_mm", h.module_mm.is_some());
    need("lead_angle_deg", h.lead_angle_deg.is_some());
    need("hand", h.hand.is_some());
    need("length_mm", h.length_mm.is_some());
    match (
        h.starts,
        h.od_mm,
        h.module_mm,
        h.lead_angle_deg,
        h.hand,
        h.length_mm,
    ) {
        (Some(starts), Some(od_mm), Some(module_mm), Some(lead), Some(hand), Some(length_mm)) => {
            Ok(HobData {
                id: format!("inline-unit-{}", index + 2),
                starts,
                od_mm,
                module_mm,
                pressure_angle_deg: h.pressure_angle_deg.unwrap_or(20.0),
                lead_angle_deg: lead,
                hand,
                length_mm,
                usable_length_mm: None,
                source: Source::Job,
            })
        }
        _ => Err(errors),
    }
}

/// True when two hobs differ in anything that matters to cutting.
pub fn hob_differs(a: &HobData, b: &HobData) -> bool {
    a.starts != b.starts
        || a.od_mm != b.od_mm
        || a.module_mm != b.module_mm
        || a.pressure_angle_deg != b.pressure_angle_deg
        || a.lead_angle_deg != b.lead_angle_deg
        || a.hand != b.hand
        || a.length_mm != b.length_mm
}

/// A plan for unit `index` alone: its gear and hob in place of the job's, no
/// further units (used to validate and limit-check each unit like a job).
pub fn unit_plan(plan: &ProcessPlan, index: usize, unit: &UnitSpec, hob: HobData) -> ProcessPlan {
    let mut p = plan.clone();
    p.gear = unit_gear(plan, unit);
    if let Some(h) = p.request.spec.hobbing_mut() {
        h.units.clear();
    }
    p.hob = hob;
    p.class = unit_class(&p.gear);
    let _ = index;
    p
}

/// The multi-gear kinematics of a validated plan: the first unit's kinematics
/// (positions, speeds, cuts at the top level) with the class multi-gear, every
/// unit in `units`, and part and job times summed over the units.
pub fn kinematics(plan: &ProcessPlan, first: Kinematics) -> Kinematics {
    let spec = &plan.request.spec;
    let mut units = vec![UnitModel {
        name: "unit 1".into(),
        class: first.class,
        z_offset_mm: 0.0,
        hob_id: plan.hob.id.clone(),
        hob_change: false,
        hob: plan.hob.clone(),
        gear: plan.gear.clone(),
        geometry: geometry(&plan.gear),
        model: first.clone(),
    }];
    let mut previous = plan.hob.clone();
    for (i, u) in plan.sections().units.iter().enumerate() {
        let hob = unit_hob(plan, i, u).expect("validated unit hob");
        let gear = unit_gear(plan, u);
        let geo = geometry(&gear);
        let unit = Unit {
            gear: &gear,
            hob: &hob,
            process: &plan.process,
            overrides: &plan.sections().process,
            machine: &plan.machine,
            quantity: spec.job.quantity,
            class: unit_class(&gear),
            proposed_allowance_mm: plan.values.get("allowance_mm").map(|v| v.value),
            proposed_finish_feed_mm_per_rev: crate::hobbing::proposed_finish_feed(plan),
        };
        let model = unit_kinematics(&unit, &geo);
        units.push(UnitModel {
            name: u.name.clone().unwrap_or_else(|| format!("unit {}", i + 2)),
            class: unit.class,
            z_offset_mm: u.z_offset_mm,
            hob_id: hob.id.clone(),
            hob_change: hob_differs(&hob, &previous),
            hob: hob.clone(),
            gear: gear.clone(),
            geometry: geo,
            model,
        });
        previous = hob;
    }
    let part: f64 = units.iter().map(|u| u.model.part_time_min).sum();
    Kinematics {
        class: GearClass::MultiGear,
        part_time_min: part,
        job_time_min: part * f64::from(spec.job.quantity),
        units,
        ..first
    }
}
