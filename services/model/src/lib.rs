//! The gearcam model service: validates a [`ProcessPlan`] and computes its
//! [`MachiningModel`] — gear geometry and hobbing kinematics (docs/reference.md#what-the-model-service-computes,
//! the "zero programming" patent's steps 2 and 3).
//!
//! The computation is pure: plain functions on plain data, no I/O, no async,
//! no clock. The Zenoh wrapper in [`service`] subscribes to plans and
//! publishes models or typed error events.
//!
//! # Layout
//!
//! - [`geometry`]: ISO 21771 cylindrical gear geometry from a [`GearSpec`].
//! - [`validate`]: the parameter checks and the patent's five physical checks
//!   (all failures together, stable codes), and the machine-limit checks of
//!   the computed kinematics.
//! - [`hobbing`]: hob swivel, approach clearance ΔH′, cuts with positions
//!   A–E, speeds, feed, differential, coupling factors and machining time.
//! - [`path`]: the X–Z(–Y) moves of a cut for each class (axial, radial-axial,
//!   conical, crowned, worm wheel).
//! - [`shift`]: hob shifting per part and per cut inside the usable length.
//! - [`units`]: multi-gear parts, unit by unit, with hob changes.
//! - [`explain`]: where each value came from.
//! - [`spiral`]: the spiral face milling family's model ([`spiral::compute_spiral`]).
//! - [`wire`]: the wire EDM family's model ([`wire::compute_wire`]).
//! - [`service`]: the Zenoh service around [`compute`], [`spiral::compute_spiral`] and [`wire::compute_wire`].
//!
//! The entry point is [`compute`].
#![forbid(unsafe_code)]

pub mod explain;
pub mod frame;
pub mod geometry;
pub mod hobbing;
pub mod path;
#[cfg(test)]
mod properties;
pub mod service;
pub mod shift;
pub mod spiral;
pub mod units;
pub mod validate;
pub mod wire;

use gearcam_proto::Code;
use gearcam_proto::{GearClass, GearSpec, Geometry, JobError, MachiningModel, ProcessPlan};

/// Version of the model code, written into every [`MachiningModel`].
/// `PROGRAM_FORM`: the job's program form is not one the machine's
/// control runs (the milling and the wire families' models).
pub fn program_form_error(
    field: &str,
    machine: &gearcam_proto::MachineId,
    controller: &str,
    forms: &[&str],
    got: &str,
) -> gearcam_proto::JobError {
    gearcam_proto::Stage::Model.error(
        Code::PROGRAM_FORM,
        field,
        format!("a form {machine} runs: {}", forms.join(", ")),
        got,
        format!("{machine} is a {controller} control"),
    )
}

pub const MODEL_VERSION: &str = concat!("gearcam-model ", env!("CARGO_PKG_VERSION"));

/// The ISO 21771 geometry of a gear (see [`geometry::geometry`]).
pub fn geometry_of(gear: &GearSpec) -> Geometry {
    geometry::geometry(gear)
}

/// Validates a plan and computes its machining model.
///
/// Runs [`validate::validate`]; if it finds any error, returns all of them
/// without computing. Otherwise computes the geometry and the kinematics
/// ([`hobbing::kinematics`]), checks them against the machine
/// ([`validate::check_limits`]) and returns every limit error, or the model
/// with the plan, the validation warnings and [`MODEL_VERSION`].
pub fn compute(plan: &ProcessPlan) -> Result<MachiningModel, Vec<JobError>> {
    let report = validate::validate(plan);
    if !report.errors.is_empty() {
        return Err(report.errors);
    }
    let geometry = geometry_of(&plan.gear);
    let mut model = hobbing::kinematics(plan, &geometry);
    if plan.class == GearClass::MultiGear {
        model = units::kinematics(plan, model);
    }
    model.explain = explain::explain(plan, &geometry, &model);
    let limit_errors = validate::check_limits(plan, &model);
    if !limit_errors.is_empty() {
        return Err(limit_errors);
    }
    Ok(MachiningModel {
        job_id: plan.job_id.clone(),
        plan: plan.clone(),
        geometry,
        model,
        warnings: report.warnings,
        model_version: MODEL_VERSION.to_string(),
    })
}

/// Test fixtures: a realistic plan for machine H01 (840D) and hob HOB-M3-80.
#[cfg(test)]
pub(crate) mod fixtures {
    use std::collections::BTreeMap;

    use gearcam_proto::{
        CaseRef, CutMode, FamilySpec, GearSpec, Hand, HobData, HobId, HobSpec, HobbingSpec,
        JobHeader, JobId, JobRequest, JobSpec, MachineProfile, Options, ProcessData,
        ProcessOverrides, ProcessPlan, Source, Sourced,
    };

    /// Spur gear mn 3, z 25, αn 20°, b 30, x 0, ha* 1, c* 0.25, H 50, blank at da.
    pub(crate) fn gear() -> GearSpec {
        crate::geometry::tests::gear(3.0, 25, 0.0)
    }

    /// Machine H01 as the knowledge base seeds it (840D, axes X Z A B C Y).
    pub(crate) fn machine() -> MachineProfile {
        gearcam_knowledge::seed::seed_machine_h01()
    }

    /// Hob HOB-M3-80: one start, OD 80, mn 3, α 20°, lead angle 2.3716°, right hand, length 100.
    pub(crate) fn hob() -> HobData {
        HobData {
            id: "HOB-M3-80".into(),
            starts: 1,
            od_mm: 80.0,
            module_mm: 3.0,
            pressure_angle_deg: 20.0,
            lead_angle_deg: 2.3716,
            hand: Hand::Right,
            length_mm: 100.0,
            usable_length_mm: None,
            source: Source::Library,
        }
    }

    /// The whole plan: conventional, one cut, vc 100 m/min, fa 2 mm/rev, default depth, safety 2.
    pub(crate) fn plan() -> ProcessPlan {
        plan_with(gear())
    }

    /// The plan for another gear.
    pub(crate) fn plan_with(gear: GearSpec) -> ProcessPlan {
        let job_id = JobId::new("J-TEST-0001").unwrap();
        let machine = machine();
        let request = JobRequest {
            job_id: job_id.clone(),
            submitted_at_ms: 1_700_000_000_000,
            submitted_by: "test".into(),
            spec: JobSpec::new(
                JobHeader {
                    family: Default::default(),
                    id: Some(job_id.clone()),
                    machine: machine.id.clone(),
                    quantity: 10,
                    part_number: "SP-1001".into(),
                    program_name: None,
                },
                FamilySpec::Hobbing(HobbingSpec {
                    gear: Some(gear.clone()),
                    hob: HobSpec {
                        id: Some(HobId::new("HOB-M3-80").unwrap()),
                        ..HobSpec::default()
                    },
                    process: ProcessOverrides::default(),
                    options: Options::default(),
                    units: Vec::new(),
                }),
            ),
        };
        let mut values = BTreeMap::new();
        values.insert(
            "cutting_speed_m_min".to_string(),
            Sourced {
                value: 100.0,
                source: Source::Case,
            },
        );
        ProcessPlan {
            job_id,
            request,
            class: gearcam_proto::classify(&gear, &[]),
            gear,
            machine,
            hob: hob(),
            process: ProcessData {
                cut_mode: CutMode::Conventional,
                cuts: 1,
                cutting_speed_m_min: 100.0,
                feed_mm_per_rev: 2.0,
                depth_mm: None,
                safety_mm: 2.0,
            },
            values,
            cases: vec![CaseRef {
                id: "CD-STEEL-HSS-1".into(),
                similarity: 1.0,
                provenance: "test fixture".into(),
            }],
            confidence: 0.8,
            proposal: Default::default(),
        }
    }

    /// The plan with a right-hand helical gear of the given helix angle.
    pub(crate) fn helical_plan(helix_angle_deg: f64, hand: Hand) -> ProcessPlan {
        let mut g = gear();
        g.helix_angle_deg = helix_angle_deg;
        g.helix_hand = Some(hand);
        plan_with(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use gearcam_proto::Ratio;

    #[test]
    fn computes_the_fixture_plan() {
        let plan = fixtures::plan();
        let m = compute(&plan).expect("the fixture plan is valid");
        assert_eq!(m.job_id, plan.job_id);
        assert_eq!(m.plan, plan);
        assert_eq!(m.model_version, MODEL_VERSION);
        assert!(m.model_version.starts_with("gearcam-model "));
        assert!(m.warnings.is_empty(), "{:?}", m.warnings);
        // Reference values from an independent brute-force Python computation
        // (ΔH′: a sweep of the hob's tip cylinder, not the ΔH formula).
        assert_relative_eq!(m.geometry.da_mm, 81.0, epsilon = 1e-12);
        assert_relative_eq!(m.model.depth_mm, 6.750_963_219_629, epsilon = 1e-9);
        assert_relative_eq!(
            m.model.centre_distance_mm,
            73.749_036_780_371,
            epsilon = 1e-9
        );
        assert_relative_eq!(m.model.clearance_mm, 22.279_643_304, epsilon = 1e-6);
        assert_relative_eq!(m.model.hob_rpm, 397.887_357_729_738, epsilon = 1e-9);
        assert_relative_eq!(
            m.model.axial_feed_mm_min,
            31.830_988_618_379,
            epsilon = 1e-9
        );
        assert_eq!(m.model.coupling, Ratio { num: 1, den: 25 });
        assert_relative_eq!(m.model.cut_time_min, 2.342_349_070_646, epsilon = 1e-6);
    }

    #[test]
    fn returns_all_validation_errors_without_computing() {
        let mut plan = fixtures::plan();
        plan.hob.module_mm = 2.5;
        plan.process.cuts = 0;
        let errors = compute(&plan).unwrap_err();
        let codes: Vec<_> = errors.iter().map(|e| e.code.as_str()).collect();
        assert!(codes.contains(&"BASE_PITCH_MISMATCH"), "{codes:?}");
        assert!(codes.contains(&"CUTS_RANGE"), "{codes:?}");
    }

    #[test]
    fn returns_limit_errors_after_computing() {
        let mut plan = fixtures::plan();
        // Nt = 1000·500/(π·80) = 1989.4 rpm > 1500.
        plan.process.cutting_speed_m_min = 500.0;
        let errors = compute(&plan).unwrap_err();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!(errors[0].code, "HOB_RPM_LIMIT");
        assert_eq!(errors[0].field, "model.hob_rpm");
        assert_eq!(errors[0].expected, "≤ 1500 rpm");
        assert_eq!(errors[0].got, "1989.436789 rpm");
    }

    #[test]
    fn geometry_of_is_the_geometry_module() {
        let g = fixtures::gear();
        assert_eq!(geometry_of(&g), geometry::geometry(&g));
    }
}
