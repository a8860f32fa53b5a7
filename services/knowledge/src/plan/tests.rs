use super::*;
use crate::{db, library};
use approx::assert_abs_diff_eq;
use gearcam_proto::{JobSpec, MachineId, ProcessOverrides};
use serde_json::json;

/// A left-hand helical gear, module 3, 16MnCr5, grade 7 (built from JSON so
/// the test does not depend on every optional field of the job file).
pub(crate) fn request(hob: serde_json::Value, process: serde_json::Value) -> JobRequest {
    let spec: JobSpec = serde_json::from_value(json!({
        "job": {"machine": "H01", "quantity": 20, "part_number": "P-1"},
        "gear": {"module_mm": 3.0, "teeth": 25, "helix_angle_deg": 15.0,
                 "helix_hand": "left", "face_width_mm": 30.0, "material": "16MnCr5",
                 "quality_grade": 7, "fixture_height_mm": 100.0},
        "hob": hob,
        "process": process,
    }))
    .unwrap();
    JobRequest {
        job_id: gearcam_proto::JobId::new("J1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "test".into(),
        spec,
    }
}

#[test]
fn proposes_cutting_data_from_the_most_similar_cases_with_provenance() {
    let conn = db::open_in_memory().unwrap();
    let plan = plan(&conn, &request(json!({}), json!({}))).unwrap();
    // Module 3 case-hardening steel first; then module 4 (ln(4/3) < ln(3/2)), then 2.
    let ids: Vec<&str> = plan.cases.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["SEED-CASE-M3", "SEED-CASE-M4", "SEED-CASE-M2"]);
    let s0 = plan.cases[0].similarity;
    assert!(s0 > 0.7 && s0 < 1.0, "{s0}");
    assert!(plan.cases[0].provenance.contains("engineering estimate"));
    let vc = plan.values["cutting_speed_m_min"];
    assert_eq!(vc.source, Source::Case);
    assert_abs_diff_eq!(vc.value, 90.0, epsilon = 1e-9);
    assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Case);
    assert_abs_diff_eq!(plan.values["feed_mm_per_rev"].value, 2.0, epsilon = 0.01);
    assert_eq!(plan.values["cuts"].source, Source::Case);
    assert_eq!(plan.values["safety_mm"].source, Source::Machine);
    // Confidence = best similarity × mean confidence of the seed cases (0.5).
    assert_abs_diff_eq!(plan.confidence, s0 * 0.5, epsilon = 1e-9);
    assert_eq!(plan.process.cut_mode, CutMode::Conventional);
    // Hob matching: module 3 at 20°, the left-hand AA hob for a left-hand grade-7 gear.
    assert_eq!(plan.hob.id, "HOB-M3-80L");
    let why = plan.proposal.hob.as_ref().unwrap();
    assert!(
        why.reason.contains("class AA fits grade 7"),
        "{}",
        why.reason
    );
    let m2 = why.rejected.iter().find(|r| r.id == "HOB-M2-70").unwrap();
    assert!(m2.reasons[0].contains("normal base pitch"), "{m2:?}");
    let a = why
        .rejected
        .iter()
        .find(|r| r.id == "HOB-M3-100-2")
        .unwrap();
    assert!(a.reasons[0].contains("class A too coarse"), "{a:?}");
    assert!(plan.proposal.overridden.is_empty());
    assert_eq!(plan.proposal.weights["module"], 3.0);
    // Every decided value has one of the documented sources.
    for (name, v) in &plan.values {
        assert!(
            matches!(
                v.source,
                Source::Job | Source::Case | Source::Machine | Source::Default
            ),
            "{name}: {:?}",
            v.source
        );
    }
}

#[test]
fn a_job_on_the_fanuc_machine_h02_gets_the_general_cases_as_on_h01() {
    let conn = db::open_in_memory().unwrap();
    let h01 = plan(&conn, &request(json!({}), json!({}))).unwrap();
    let mut req = request(json!({}), json!({}));
    req.spec.job.machine = MachineId::new("H02").unwrap();
    let h02 = plan(&conn, &req).unwrap();
    assert_eq!(h02.machine, crate::seed::seed_machine_h02());
    assert_eq!(h02.machine.dialect, gearcam_proto::Dialect::Fanuc);
    // The seed cases name no machine, so they fit both machines alike.
    assert_eq!(h02.cases, h01.cases);
    assert_eq!(h02.values["cutting_speed_m_min"].source, Source::Case);
    assert_eq!(
        h02.values["safety_mm"],
        Sourced {
            value: 3.0,
            source: Source::Machine
        }
    );
}

#[test]
fn a_case_cut_on_h02_ranks_first_for_h02_jobs_only() {
    let conn = db::open_in_memory().unwrap();
    let rec = record(json!({
        "id": "SHOP-H02-1",
        "machine": "H02",
        "material": "20CrMnTi",
        "material_group": "case_hardening_steel",
        "hardness_hb": 180.0,
        "module_mm": 3.0,
        "teeth": 30,
        "face_width_mm": 30.0,
        "quality_grade": 8,
        "hob_material": "HSS",
        "hob_coating": "TiN",
        "cutting_speed_m_min": 70.0,
        "feed_mm_per_rev": 1.6,
        "confidence": 0.9,
        "provenance": "shop history, H02",
    }));
    library::add(&conn, &library::CASES, &rec).unwrap();
    // The same problem as SEED-CASE-M3 but for the machine.
    let h01 = plan(&conn, &request(json!({}), json!({}))).unwrap();
    assert_eq!(h01.cases[0].id, "SEED-CASE-M3");
    assert_eq!(h01.cases[1].id, "SHOP-H02-1");
    assert_abs_diff_eq!(
        h01.cases[0].similarity,
        h01.cases[1].similarity,
        epsilon = 1e-6
    );
    let mut req = request(json!({}), json!({}));
    req.spec.job.machine = MachineId::new("H02").unwrap();
    let h02 = plan(&conn, &req).unwrap();
    assert_eq!(h02.cases[0].id, "SHOP-H02-1");
    assert!(h02.cases[0].similarity > h02.cases[1].similarity);
}

/// A library record from a JSON object.
fn record(v: serde_json::Value) -> library::Record {
    v.as_object().cloned().expect("a JSON object")
}

/// A request from a job that names part `part` and gives no `[gear]`.
fn by_part(part: &str) -> JobRequest {
    let mut req = request(json!({}), json!({}));
    req.spec.job.part_number = part.into();
    req.spec.hobbing_mut().unwrap().gear = None;
    req
}

#[test]
fn a_job_naming_a_library_part_gets_its_drawing_data_from_the_library() {
    let conn = db::open_in_memory().unwrap();
    let plan = plan(&conn, &by_part("SP-1001")).unwrap();
    // The request stays as it was asked; the plan carries the library's gear.
    assert!(!plan.request.spec.has_gear());
    let g = &plan.gear;
    assert_eq!((g.module_mm, g.teeth), (3.0, 25));
    assert_eq!((g.face_width_mm, g.blank_od_mm), (30.0, Some(81.0)));
    assert_eq!((g.material.as_str(), g.quality_grade), ("20CrMnTi", 7));
    assert_eq!(g.fixture_height_mm, 100.0);
    assert_eq!(plan.class, GearClass::Cylindrical);
    for name in ["gear.module_mm", "gear.teeth", "gear.blank_od_mm"] {
        assert_eq!(plan.values[name].source, Source::Library, "{name}");
    }
    assert_eq!(plan.values["gear.teeth"].value, 25.0);
    let w = plan.proposal.workpiece.as_ref().unwrap();
    assert!(w.supplied_gear);
    assert_eq!(w.part_number, "SP-1001");
    assert!(w.provenance.contains("examples"), "{}", w.provenance);
    assert!(plan.proposal.overridden.is_empty());
    // The hob is matched to the library's gear (module 3, spur, grade 7).
    assert_eq!(plan.hob.id, "HOB-M3-80");
}

#[test]
fn a_gear_section_wins_over_the_library_part_and_the_plan_says_where_they_differ() {
    let conn = db::open_in_memory().unwrap();
    let mut req = request(json!({}), json!({}));
    req.spec.job.part_number = "SP-1001".into();
    let plan = plan(&conn, &req).unwrap();
    assert_eq!(plan.sections().gear, req.spec.hobbing().unwrap().gear);
    assert_eq!(plan.values["gear.teeth"].source, Source::Job);
    assert_eq!(
        plan.proposal.values["gear.face_width_mm"],
        Sourced {
            value: 30.0,
            source: Source::Library
        }
    );
    assert!(plan
        .proposal
        .overridden
        .contains(&"gear.helix_angle_deg".to_string()));
    let w = plan.proposal.workpiece.as_ref().unwrap();
    assert!(!w.supplied_gear);
    // The fixture gear is a left-hand 15° helical gear of 16MnCr5 with no
    // blank OD; the record a spur gear of 20CrMnTi with a blank of 81 mm.
    assert_eq!(
        w.differs,
        [
            "gear.blank_od_mm",
            "gear.helix_angle_deg",
            "gear.material",
            "gear.helix_hand"
        ]
    );
}

#[test]
fn a_job_with_neither_gear_nor_library_part_is_refused_naming_the_gear() {
    let conn = db::open_in_memory().unwrap();
    let errors = plan(&conn, &by_part("NO-SUCH-PART")).unwrap_err();
    assert_eq!(errors.len(), 1, "{errors:#?}");
    let e = &errors[0];
    assert_eq!(
        (e.code.as_str(), e.field.as_str()),
        ("GEAR_MISSING", "gear")
    );
    assert!(
        e.expected
            .starts_with("a [gear] section or a part number in the workpiece library"),
        "{}",
        e.expected
    );
    assert!(e.expected.contains("SP-1001"), "{}", e.expected);
    assert!(e.got.contains("\"NO-SUCH-PART\""), "{}", e.got);
    // With an unknown machine as well, both are reported.
    let mut req = by_part("NO-SUCH-PART");
    req.spec.job.machine = MachineId::new("H99").unwrap();
    let codes: Vec<Code> = plan(&conn, &req)
        .unwrap_err()
        .into_iter()
        .map(|e| e.code)
        .collect();
    assert_eq!(codes, ["GEAR_MISSING", "UNKNOWN_MACHINE"]);
}

#[test]
fn a_library_part_without_its_class_data_needs_the_gear_section() {
    let conn = db::open_in_memory().unwrap();
    let mut rec = record(json!({
        "part_number": "CR-1",
        "class": "crowned",
        "module_mm": 3.0,
        "teeth": 25,
        "face_width_mm": 30.0,
        "fixture_height_mm": 100.0,
    }));
    library::add(&conn, &library::WORKPIECES, &rec).unwrap();
    let errors = plan(&conn, &by_part("CR-1")).unwrap_err();
    assert_eq!(errors[0].code, "WORKPIECE_INCOMPLETE");
    assert!(errors[0].expected.contains("[gear.crowning]"), "{errors:?}");
    // A conical part with its cone angle is complete.
    rec.insert("part_number".into(), json!("CO-1"));
    rec.insert("class".into(), json!("conical"));
    rec.insert("cone_angle_deg".into(), json!(6.5));
    library::add(&conn, &library::WORKPIECES, &rec).unwrap();
    let p = plan(&conn, &by_part("CO-1")).unwrap();
    assert_eq!(p.class, GearClass::Conical);
    assert_eq!(p.values["gear.cone.angle_deg"].value, 6.5);
}

/// Seed 000's bevel gear (docs/knowledge.md#case-based-reasoning): conical, mn 2, z 19, OD 42.5, 40Cr,
/// grade 7, cone 6.5°, on the module-2 hob; `process` as given.
fn bevel(process: serde_json::Value) -> JobRequest {
    let spec: JobSpec = serde_json::from_value(json!({
        "job": {"machine": "H01", "quantity": 10, "part_number": "CB-1901"},
        "gear": {"module_mm": 2.0, "teeth": 19, "face_width_mm": 20.0,
                 "blank_od_mm": 42.5, "material": "40Cr", "quality_grade": 7,
                 "fixture_height_mm": 100.0, "cone": {"angle_deg": 6.5}},
        "hob": {"id": "HOB-M2-70"},
        "process": process,
    }))
    .unwrap();
    JobRequest {
        job_id: gearcam_proto::JobId::new("J2").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "test".into(),
        spec,
    }
}

#[test]
fn seed_conical_case_gives_a_roughing_feed_to_a_finish() {
    // Seed 000's bevel cut was a rough cut, 105 mm/min at
    // 246 rpm, 19 teeth, one start: 8.1 mm per table revolution as
    // published. A finishing job got 7.92 mm/rev from it; now the feed of
    // a finish comes only from finishing cases, else the default.
    let conn = db::open_in_memory().unwrap();
    let finish = plan(&conn, &bevel(json!({}))).unwrap();
    assert_eq!(finish.cases[0].id, "SEED000-BEVEL-CBR");
    assert_eq!(
        finish.values["feed_mm_per_rev"],
        Sourced {
            value: DEFAULT_FEED_MM_PER_REV,
            source: Source::Default
        }
    );
    // A rough job takes the published roughing feed (the mean of the two
    // seed cases, 8.11 and 7.73 mm/rev by similarity).
    let rough = plan(&conn, &bevel(json!({"operation": "rough"}))).unwrap();
    let fa = rough.values["feed_mm_per_rev"];
    assert_eq!(fa.source, Source::Case);
    assert!(fa.value > 7.7 && fa.value < 8.2, "{fa:?}");
}

#[test]
fn a_rough_job_retrieves_the_rough_cases_first_and_a_finish_job_the_finish_ones() {
    let conn = db::open_in_memory().unwrap();
    // A finish case of the same bevel gear beside seed 000's two rough ones.
    let rec = record(json!({
        "id": "SHOP-BEVEL-FINISH",
        "class": "conical",
        "material": "40Cr",
        "material_group": "quenched_tempered_steel",
        "module_mm": 2.0,
        "teeth": 19,
        "quality_grade": 7,
        "hob_coating": "unknown",
        "operation": "finish",
        "cutting_speed_m_min": 60.0,
        "feed_mm_per_rev": 1.0,
        "confidence": 0.6,
        "provenance": "test: a finishing cut",
    }));
    library::add(&conn, &library::CASES, &rec).unwrap();

    let rough = plan(&conn, &bevel(json!({"operation": "rough"}))).unwrap();
    let ids: Vec<&str> = rough.cases.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(
        ids,
        [
            "SEED000-BEVEL-CBR",
            "SEED000-BEVEL-HAND",
            "SHOP-BEVEL-FINISH"
        ]
    );
    assert_eq!(
        rough.values["operation_rough"],
        Sourced {
            value: 1.0,
            source: Source::Job
        }
    );
    assert_eq!(rough.proposal.overridden, ["operation_rough"]);
    // Seed 000's rough cut leaves 2.5 mm of stock.
    assert_eq!(rough.values["allowance_mm"].value, 2.5);

    // The same job, finish by default: the finish case first.
    let finish = plan(&conn, &bevel(json!({}))).unwrap();
    assert_eq!(finish.cases[0].id, "SHOP-BEVEL-FINISH");
    assert_eq!(
        finish.values["operation_rough"],
        Sourced {
            value: 0.0,
            source: Source::Default
        }
    );
    assert!(finish.proposal.overridden.is_empty());
    let seed_sim = |p: &ProcessPlan| {
        p.cases
            .iter()
            .find(|c| c.id == "SEED000-BEVEL-CBR")
            .unwrap()
            .similarity
    };
    assert!(seed_sim(&rough) > seed_sim(&finish));
    // Said explicitly, finish is the job's.
    let said = plan(&conn, &bevel(json!({"operation": "finish"}))).unwrap();
    assert_eq!(said.cases, finish.cases);
    assert_eq!(said.values["operation_rough"].source, Source::Job);
}

#[test]
fn overrides_win_and_the_plan_records_what_was_proposed() {
    let conn = db::open_in_memory().unwrap();
    let plan = plan(
        &conn,
        &request(
            json!({}),
            json!({"cutting_speed_m_min": 70.0, "feed_mm_per_rev": 1.2, "cut_mode": "climb"}),
        ),
    )
    .unwrap();
    assert_eq!(
        plan.values["cutting_speed_m_min"],
        Sourced {
            value: 70.0,
            source: Source::Job
        }
    );
    assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Job);
    assert_eq!(plan.process.cutting_speed_m_min, 70.0);
    assert_eq!(plan.process.feed_mm_per_rev, 1.2);
    assert_eq!(plan.process.cut_mode, CutMode::Climb);
    assert_eq!(
        plan.proposal.values["cutting_speed_m_min"].source,
        Source::Case
    );
    assert_abs_diff_eq!(
        plan.proposal.values["cutting_speed_m_min"].value,
        90.0,
        epsilon = 1e-9
    );
    assert_eq!(
        plan.proposal.overridden,
        ["cutting_speed_m_min", "feed_mm_per_rev", "cut_mode_climb"]
    );
    // The number of cuts still comes from the cases, so they are listed.
    assert_eq!(plan.values["cuts"].source, Source::Case);
    assert!(!plan.cases.is_empty());
}

#[test]
fn a_job_that_overrides_every_case_value_lists_no_cases() {
    let conn = db::open_in_memory().unwrap();
    let plan = plan(
        &conn,
        &request(
            json!({"id": "HOB-M3-80L"}),
            json!({"cutting_speed_m_min": 70.0, "feed_mm_per_rev": 1.2,
                   "cut_mode": "climb", "cuts": 1}),
        ),
    )
    .unwrap();
    assert!(plan.cases.is_empty());
    assert_eq!(plan.confidence, 1.0);
    assert!(plan.proposal.hob.is_none(), "a named hob is not matched");
    assert_eq!(plan.proposal.overridden.len(), 4);
}

#[test]
fn a_proposal_above_the_machines_hob_speed_is_clamped_to_the_machine() {
    let conn = db::open_in_memory().unwrap();
    let mut set = library::Record::new();
    set.insert("limits.max_hob_rpm".into(), json!(300.0));
    library::edit(&conn, &library::MACHINES, "H01", &set).unwrap();
    let plan = plan(&conn, &request(json!({}), json!({}))).unwrap();
    // 300 rpm on an 80 mm hob: vc ≤ 300·π·80/1000 = 75.398 m/min; the
    // 90 m/min cases fail that hard constraint, the default is clamped.
    let vc = plan.values["cutting_speed_m_min"];
    assert_eq!(vc.source, Source::Machine);
    assert_abs_diff_eq!(
        vc.value,
        300.0 * std::f64::consts::PI * 80.0 / 1000.0,
        epsilon = 1e-9
    );
    assert!(plan.cases.is_empty());
    assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Default);
    assert_eq!(plan.confidence, DEFAULT_CONFIDENCE);
}

#[test]
fn an_unknown_material_gets_defaults_and_low_confidence() {
    let conn = db::open_in_memory().unwrap();
    let mut req = request(json!({}), json!({}));
    req.spec
        .hobbing_mut()
        .unwrap()
        .gear
        .as_mut()
        .unwrap()
        .material = "unobtainium".into();
    let plan = plan(&conn, &req).unwrap();
    assert_eq!(plan.values["cutting_speed_m_min"].source, Source::Default);
    assert_eq!(
        plan.values["cutting_speed_m_min"].value,
        DEFAULT_CUTTING_SPEED_M_MIN
    );
    assert_eq!(plan.confidence, DEFAULT_CONFIDENCE);
}

#[test]
fn no_fitting_hob_names_every_rejection() {
    let conn = db::open_in_memory().unwrap();
    let mut req = request(json!({}), json!({}));
    req.spec
        .hobbing_mut()
        .unwrap()
        .gear
        .as_mut()
        .unwrap()
        .module_mm = 5.0;
    let errors = plan(&conn, &req).unwrap_err();
    assert_eq!(errors[0].code, "NO_MATCHING_HOB");
    assert!(
        errors[0].got.contains("HOB-M4-90: normal base pitch"),
        "{}",
        errors[0].got
    );
}

#[test]
fn unknown_machine_and_hob_errors_name_the_field_and_the_choices() {
    let conn = db::open_in_memory().unwrap();
    let mut req = request(json!({"id": "NOPE"}), json!({}));
    let errors = plan(&conn, &req).unwrap_err();
    assert_eq!(
        (errors[0].code.as_str(), errors[0].field.as_str()),
        ("UNKNOWN_HOB", "hob.id")
    );
    assert!(
        errors[0].expected.contains("HOB-M3-80"),
        "{}",
        errors[0].expected
    );
    req.spec.job.machine = MachineId::new("H99").unwrap();
    let errors = plan(&conn, &req).unwrap_err();
    // The family's machines, then every family's, in the station's words.
    assert_eq!(
        (errors[0].code.as_str(), errors[0].expected.as_str()),
        (
            "UNKNOWN_MACHINE",
            "a hobbing machine: one of H01, H02; the knowledge base's machines: H01, H02 (hobbing); M01, M02 (spiral face milling); W01, W02 (wire EDM)"
        )
    );
    // A mill for a hobbing job: the family is wrong, not the machine.
    req.spec.job.machine = MachineId::new("M01").unwrap();
    let errors = plan(&conn, &req).unwrap_err();
    assert_eq!(
        (errors[0].code.as_str(), errors[0].got.as_str()),
        ("MACHINE_FAMILY", "M01 (a spiral face milling machine)")
    );
}

#[test]
fn incomplete_inline_hob_lists_every_missing_field() {
    let conn = db::open_in_memory().unwrap();
    let req = request(json!({"starts": 1, "od_mm": 80.0}), json!({}));
    let errors = plan(&conn, &req).unwrap_err();
    let fields: Vec<&str> = errors.iter().map(|e| e.field.as_str()).collect();
    assert_eq!(
        fields,
        [
            "hob.module_mm",
            "hob.lead_angle_deg",
            "hob.hand",
            "hob.length_mm"
        ]
    );
    assert!(errors.iter().all(|e| e.code == "HOB_FIELD_MISSING"));
}

#[test]
fn a_hob_id_with_inline_data_is_ambiguous() {
    let conn = db::open_in_memory().unwrap();
    let req = request(json!({"id": "HOB-M3-80", "od_mm": 80.0}), json!({}));
    let errors = plan(&conn, &req).unwrap_err();
    assert_eq!(errors[0].code, "HOB_AMBIGUOUS");
    let _ = ProcessOverrides::default();
}

#[test]
fn the_database_file_is_created_once_and_reopened_without_reseeding() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("kb/knowledge.db");
    let conn = db::open(&path).unwrap();
    assert_eq!(db::hobs(&conn).unwrap().len(), 5);
    assert_eq!(db::schema_version(&conn).unwrap(), 10);
    let n = library::list(&conn, &library::CASES).unwrap().len();
    assert_eq!(n, 14);
    drop(conn);
    let conn = db::open(&path).unwrap();
    assert_eq!(db::hobs(&conn).unwrap().len(), 5);
    assert_eq!(library::list(&conn, &library::CASES).unwrap().len(), n);
    assert_eq!(
        db::machines(&conn).unwrap()[0],
        crate::seed::seed_machine_h01()
    );
}
