use super::*;
use crate::db;
use gearcam_proto::{JobId, JobSpec};

fn request(v: Value) -> JobRequest {
    let spec: JobSpec = serde_json::from_value(v).unwrap();
    JobRequest {
        job_id: JobId::new("J-S1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "test".into(),
        spec,
    }
}

fn face(machine: &str, extra: Value) -> JobRequest {
    let mut v = json!({
        "job": {"family": "spiral-face", "machine": machine, "part_number": "FL-1"},
        "face": {"outer_radius_mm": 100.0, "inner_radius_mm": 20.0, "depth_mm": 1.0,
                 "material": "C45"},
    });
    if let (Value::Object(m), Value::Object(e)) = (&mut v, extra) {
        m.extend(e);
    }
    request(v)
}

/// A job without process data gets its values from the most similar
/// case, each with its source, and the case with its similarity and
/// provenance; the step-over scales with the tool's diameter.
#[test]
fn a_face_without_process_data_gets_a_proposal_from_similar_cases() {
    let conn = db::open_in_memory().unwrap();
    let plan = plan_spiral(&conn, &face("M01", json!({}))).unwrap();
    assert_eq!(plan.tool.id, "FM-063", "the largest mill no wider than Ro");
    assert_eq!(plan.cases[0].id, "MC-FACE-C45-100");
    assert!(plan.cases[0].similarity > 0.9, "{:?}", plan.cases);
    assert!(plan.cases[0].provenance.contains("engineering estimate"));
    let p = &plan.process;
    assert_eq!(
        (p.cutting_speed_m_min.value, p.cutting_speed_m_min.source),
        (170.0, Source::Case)
    );
    assert_eq!(p.feed_per_tooth_mm.source, Source::Case);
    assert_eq!(p.step_over_mm.value, 38.0);
    assert_eq!(p.tolerance_mm.source, Source::Default);
    assert_eq!(p.program, SpiralProgram::FanucMacro, "M01's default form");
    assert!((plan.confidence - plan.cases[0].similarity * 0.5).abs() < 1e-12);

    // The planner's own values win and say so.
    let plan = plan_spiral(
        &conn,
        &face(
            "M01",
            json!({"mill": {"id": "EM-16"}, "milling": {"step_over_mm": 9.0, "cutting_speed_m_min": 150.0}}),
        ),
    )
    .unwrap();
    assert_eq!(plan.tool.id, "EM-16");
    assert_eq!(plan.process.step_over_mm.source, Source::Job);
    assert_eq!(plan.process.cutting_speed_m_min.value, 150.0);
    assert_eq!(plan.process.cutting_speed_m_min.source, Source::Job);
}

/// With no similar case the milling data of the material's group
/// proposes; a proposal above the machine's spindle is lowered to it
/// (source `machine`), a job's value never is.
#[test]
fn proposals_come_from_the_milling_data_and_respect_the_machine() {
    let conn = db::open_in_memory().unwrap();
    let req = request(json!({
        "job": {"family": "spiral-face", "machine": "M02", "part_number": "FL-2"},
        "face": {"outer_radius_mm": 70.0, "depth_mm": 4.5, "material": "AlMg3"},
        "mill": {"id": "EM-16"},
    }));
    let plan = plan_spiral(&conn, &req).unwrap();
    assert!(plan.cases.is_empty(), "{:?}", plan.cases);
    assert_eq!(plan.process.passes, 2, "4.5 mm at 3 mm per pass");
    assert_eq!(plan.process.step_over_mm.value, 0.6 * 16.0);
    let vc = plan.process.cutting_speed_m_min;
    // 500 m/min from the data would be 9,947 rpm; M02 turns 4,000.
    assert_eq!(vc.source, Source::Machine);
    let rpm = 1000.0 * vc.value / (std::f64::consts::PI * 16.0);
    assert!(rpm <= 4000.0 && rpm > 3990.0, "{rpm}");
    assert_eq!(plan.process.program, SpiralProgram::Linuxcnc);
    let req = request(json!({
        "job": {"family": "spiral-face", "machine": "M02", "part_number": "FL-2"},
        "face": {"outer_radius_mm": 70.0, "depth_mm": 1.0, "material": "AlMg3"},
        "mill": {"id": "EM-16"},
        "milling": {"cutting_speed_m_min": 500.0},
    }));
    let plan = plan_spiral(&conn, &req).unwrap();
    assert_eq!(plan.process.cutting_speed_m_min.value, 500.0);
}

/// A groove gets the end mill of its width; none of that width is an
/// error naming the widths there are.
#[test]
fn a_groove_gets_the_end_mill_of_its_width() {
    let conn = db::open_in_memory().unwrap();
    let groove = |width: f64| {
        request(json!({
            "job": {"family": "spiral-face", "machine": "M01", "part_number": "PT-1"},
            "groove": {"outer_radius_mm": 60.0, "pitch_mm": 16.0, "turns": 3,
                       "depth_mm": 4.0, "width_mm": width, "material": "C45"},
        }))
    };
    let plan = plan_spiral(&conn, &groove(10.0)).unwrap();
    assert_eq!(plan.tool.id, "EM-10");
    assert_eq!(
        (
            plan.process.step_over_mm.value,
            plan.process.step_over_mm.source
        ),
        (16.0, Source::Job),
        "a groove's step-over is its pitch"
    );
    assert_eq!(plan.cases[0].id, "MC-GROOVE-C45-60");
    let e = plan_spiral(&conn, &groove(12.0)).unwrap_err();
    assert_eq!(
        (e[0].code.as_str(), e[0].field.as_str()),
        ("NO_TOOL", "groove.width_mm")
    );
    assert!(e[0].expected.contains("10 mm"), "{}", e[0].expected);
}

/// Sections of the other family, a hobbing machine, an unknown tool and
/// an incomplete inline tool are refused naming the field.
#[test]
fn wrong_sections_machines_and_tools_are_refused_on_their_fields() {
    let conn = db::open_in_memory().unwrap();
    let e = plan_spiral(&conn, &face("H01", json!({}))).unwrap_err();
    assert_eq!(
        (e[0].code.as_str(), e[0].field.as_str()),
        ("MACHINE_FAMILY", "job.machine")
    );
    assert!(e[0].expected.contains("M01, M02"), "{}", e[0].expected);
    // A hobbing section in a spiral job does not decode: the job is typed by
    // its family.
    let foreign = serde_json::from_value::<gearcam_proto::JobSpec>(json!({
        "job": {"family": "spiral-face", "machine": "M01", "part_number": "FL-1"},
        "face": {"outer_radius_mm": 100.0, "depth_mm": 1.0, "material": "C45"},
        "gear": {"module_mm": 3.0, "teeth": 20, "face_width_mm": 20.0,
                 "fixture_height_mm": 50.0},
    }))
    .unwrap_err();
    assert!(
        foreign
            .to_string()
            .contains("[gear] belongs to the hobbing family"),
        "{foreign}"
    );
    let e = plan_spiral(&conn, &face("M01", json!({"mill": {"id": "FM-999"}}))).unwrap_err();
    assert_eq!(
        (e[0].code.as_str(), e[0].field.as_str()),
        ("UNKNOWN_TOOL", "mill.id")
    );
    let e = plan_spiral(&conn, &face("M01", json!({"mill": {"radius_mm": 8.0}}))).unwrap_err();
    assert_eq!(
        (e[0].code.as_str(), e[0].field.as_str()),
        ("MISSING_FIELD", "mill.kind")
    );
    // The spiral planner plans spiral jobs only.
    let mut req = face("H01", json!({}));
    req.spec.part = gearcam_proto::FamilySpec::Hobbing(Default::default());
    let e = plan_spiral(&conn, &req).unwrap_err();
    assert_eq!(
        (e[0].code.as_str(), e[0].field.as_str()),
        ("SECTION_FAMILY", "job.family")
    );
}

/// The learning loop: a delivered spiral job, confirmed with the feed
/// that really ran, becomes a milling case; the next similar job is
/// proposed from it first.
#[test]
fn a_confirmed_spiral_job_becomes_the_case_the_next_job_is_proposed_from() {
    let conn = db::open_in_memory().unwrap();
    let req = face("M01", json!({}));
    let plan = plan_spiral(&conn, &req).unwrap();
    record_planned(&conn, &plan, 1).unwrap();
    conn.execute(
        "UPDATE jobs SET state = 'delivered' WHERE job_id = 'J-S1'",
        [],
    )
    .unwrap();
    let c = crate::learn::Confirmation {
        job_id: "J-S1".into(),
        quantity: None,
        cutting_speed_m_min: None,
        feed_mm_per_rev: Some(0.09),
        cuts: None,
        outcome: "ok".into(),
        quality_achieved: None,
        notes: "flat within 0.01".into(),
        confidence: 0.9,
        by: "planner Wang".into(),
        at_ms: 2,
        allow_undelivered: false,
    };
    let done = crate::learn::confirm(&conn, &c).unwrap();
    assert_eq!(done.case["id"], "JOB-J-S1");
    assert_eq!(done.case["feed_per_tooth_mm"], 0.09);
    assert!(done.case["provenance"]
        .as_str()
        .unwrap()
        .contains("fz 0.09 mm"));
    assert_eq!(done.job["state"], "confirmed");
    let next = plan_spiral(&conn, &face("M01", json!({}))).unwrap();
    assert_eq!(next.cases[0].id, "JOB-J-S1");
    assert_eq!(next.process.feed_per_tooth_mm.value, 0.09);
    // Confirmed once.
    let e = crate::learn::confirm(&conn, &c).unwrap_err();
    assert_eq!(e[0].code, "JOB_STATE");
}

/// The seeded machines and tools are in their libraries, with provenance.
#[test]
fn the_seed_has_the_mills_and_their_tools() {
    let conn = db::open_in_memory().unwrap();
    let m = mill_machines(&conn).unwrap();
    let ids: Vec<&str> = m.iter().map(|m| m.id.as_str()).collect();
    assert_eq!(ids, ["M01", "M02"]);
    assert_eq!(
        (m[0].dialect, m[1].dialect),
        (Dialect::Fanuc, Dialect::Linuxcnc)
    );
    assert!(m[0].programs.contains(&SpiralProgram::FanucArcs));
    assert_eq!(m[1].programs, [SpiralProgram::Linuxcnc]);
    assert!(m
        .iter()
        .all(|m| m.controller.contains("FANUC") || m.controller.contains("LinuxCNC")));
    let tools = library::list(&conn, &library::MILLS).unwrap();
    assert_eq!(tools.len(), 5);
    assert!(tools.iter().all(|t| text(t, "source") == TOOLS_SEED));
}
