//! Every job file in `examples/` through knowledge (seeded in-memory base),
//! model and template, as `gearcam check` runs them: a valid example yields a
//! model of its class and an 840D program; an invalid one (marked
//! `# expect: CODE`) is refused with that named error.

use gearcam_proto::{classify, GearClass, MachiningModel, MoveKind};
use gearcam_testkit::examples::{all, expected_code, is_spiral, is_wire};
use gearcam_testkit::pipeline::{model_of, program_of};

/// The hobbing examples (the spiral and wire families' run through
/// `gearcam check`'s tests, `services/gearcam/src/check.rs` and
/// `check_wire.rs`).
fn examples() -> Vec<(String, String)> {
    all()
        .into_iter()
        .filter(|(_, t)| !is_spiral(t) && !is_wire(t))
        .collect()
}

/// Plan, model and program of one job file, or the errors of the first
/// stage that refuses it.
fn run(
    _name: &str,
    text: &str,
) -> Result<(MachiningModel, gearcam_proto::NcProgram), Vec<gearcam_proto::JobError>> {
    let model = model_of(text)?;
    let program = program_of(&model)?;
    Ok((model, program))
}

#[test]
fn every_example_runs_or_fails_with_its_named_error() {
    let all = examples();
    assert!(all.len() >= 12, "{} examples", all.len());
    let mut classes = std::collections::BTreeSet::new();
    for (name, text) in &all {
        match (expected_code(text), run(name, text)) {
            (None, Ok((model, program))) => {
                // The plan's gear: a job that names its part only gets the
                // gear from the workpiece library; the plan's class is the
                // class of that gear, and the model's is the plan's.
                let class = classify(&model.plan.gear, &model.plan.sections().units);
                assert_eq!(model.plan.class, class, "{name}");
                assert_eq!(model.model.class, class, "{name}");
                // The machine names the dialect: H01 840D, H02 FANUC EGB.
                match model.plan.machine.dialect {
                    gearcam_proto::Dialect::Fanuc => {
                        assert!(program.text.contains(" G81 T"), "{name}")
                    }
                    _ => assert!(program.text.contains("EGONSYNE("), "{name}"),
                }
                assert!(!model.model.cuts.is_empty(), "{name}");
                assert!(model.model.part_time_min > 0.0, "{name}");
                classes.insert(model.model.class);
            }
            (Some(code), Err(errors)) => {
                assert!(
                    errors.iter().any(|e| e.code == code),
                    "{name}: expected {code}, got {errors:#?}"
                );
            }
            (None, Err(errors)) => panic!("{name} fails: {errors:#?}"),
            (Some(code), Ok(_)) => panic!("{name} should fail with {code}"),
        }
    }
    for class in GearClass::ALL.into_iter().filter(|c| c.programmable()) {
        assert!(classes.contains(&class), "no example of class {class}");
    }
}

fn example(name: &str) -> (MachiningModel, String) {
    let text = examples()
        .into_iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("{name} missing"))
        .1;
    let (m, p) = run(name, &text).unwrap_or_else(|e| panic!("{name}: {e:#?}"));
    (m, p.text)
}

#[test]
fn multi_cut_example_re_synchronises_and_shifts_per_part() {
    let (m, text) = example("multi_cut_shift_840d.toml");
    let k = &m.model;
    assert_eq!(k.cuts.len(), 2);
    let (rough, finish) = (&k.cuts[0], &k.cuts[1]);
    assert!(!rough.finish && finish.finish && finish.resync && !rough.resync);
    // The rough cut stops 0.3 mm short of the depth.
    assert!(
        (rough.allowance_mm - 0.3).abs() < 1e-9,
        "{}",
        rough.allowance_mm
    );
    assert!((rough.centre_distance_mm - finish.centre_distance_mm - 0.3).abs() < 1e-9);
    assert!(
        text.contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25"),
        "{text}"
    );
    let shift = k.shift.as_ref().expect("shift plan");
    assert_eq!(shift.parts_per_step, 4);
    assert!(shift.start_mm >= shift.usable_mm[0] && shift.end_mm <= shift.usable_mm[1]);
    assert!(text.contains("Y=R20+R22*(R26 MOD R24)"), "{text}");
    assert!(text.contains("R25=R25+1"), "{text}");
    // Radial-axial: each cut plunges radially at the radial feed before feeding axially.
    assert_eq!(rough.moves[1].kind, MoveKind::Feed);
    assert!(rough.moves[1].z_mm.is_none() && rough.radial_feed_mm_min > 0.0);
}

#[test]
fn crowned_example_is_one_arc_and_conical_follows_the_cone() {
    let (m, text) = example("crowned_840d.toml");
    let arc = m.model.cuts[0]
        .moves
        .iter()
        .find(|mv| mv.kind == MoveKind::Arc)
        .expect("an arc");
    assert!(arc.via.is_some());
    assert!(text.contains("CIP X="), "{text}");
    let (m, _) = example("conical_840d.toml");
    let cone = m.model.cone.expect("cone model");
    // Along the cone (the face and beyond its small end) X follows Z;
    // beyond, it holds.
    let moves = &m.model.cuts[0].moves;
    let (to_face, across) = (&moves[1], &moves[2]);
    let p = m.model.positions;
    assert_eq!(to_face.x_mm, None);
    let slope = (across.x_mm.unwrap() - p.C.x_mm) / (across.z_mm.unwrap() - to_face.z_mm.unwrap());
    assert!((slope - cone.x_per_z).abs() < 1e-12);
    assert!((p.D.x_mm - across.x_mm.unwrap()).abs() < 1e-12);
    assert!((cone.x_per_z + 6.5f64.to_radians().tan()).abs() < 1e-12);
}

/// The conical example approaches its small (upper) end: C stands above it
/// by that end's ΔH′ (and the safety distance) at the depth the hob really
/// has there, found from C's own X and the small end's blank, whatever
/// formula placed it.
#[test]
fn the_conical_approach_clears_the_small_end_at_its_own_depth() {
    let (m, _) = example("conical_840d.toml");
    let (k, gear) = (&m.model, &m.plan.gear);
    let cone = k.cone.as_ref().expect("cone model");
    let c = k.cuts[0].positions.C;
    let small_od = k.blank_od_mm - 2.0 * gear.face_width_mm * cone.angle_deg.to_radians().tan();
    let depth = small_od / 2.0 + m.plan.hob.od_mm / 2.0 - c.x_mm;
    let clearance = gearcam_model::hobbing::Clearance {
        blank_od_mm: small_od,
        hob_od_mm: m.plan.hob.od_mm,
        depth_mm: depth,
        swivel_deg: k.swivel_deg,
        hob_length_mm: m.plan.hob.length_mm,
    }
    .solve()
    .clearance_mm;
    let top = gear.fixture_height_mm + gear.face_width_mm;
    assert!(
        (c.z_mm - (top + clearance + k.safety_mm)).abs() < 2e-3,
        "C at Z {} for ΔH′ {clearance} at depth {depth}",
        c.z_mm
    );
}

#[test]
fn worm_wheel_and_multi_gear_examples() {
    let (m, text) = example("worm_wheel_840d.toml");
    let w = m.model.worm.as_ref().expect("worm model");
    assert!((m.model.positions.D.x_mm - w.centre_distance_mm).abs() < 1e-9);
    assert!(text.contains("G4 F="), "{text}");
    // The wheel helix equals the hob lead angle to the 6 decimals of the job file.
    assert!(m.model.swivel_deg.abs() < 1e-6, "{}", m.model.swivel_deg);
    let (m, text) = example("worm_wheel_tangential_840d.toml");
    assert!(text.contains("EGDEF(C,B,1,Y,1)"), "{text}");
    assert!(m.model.worm.as_ref().unwrap().start_y_mm < 0.0);
    let (m, text) = example("multi_gear_840d.toml");
    assert_eq!(m.model.class, GearClass::MultiGear);
    assert_eq!(m.model.units.len(), 2);
    assert!(m.model.units[1].hob_change);
    assert!((m.model.units[1].gear.fixture_height_mm - 190.0).abs() < 1e-12);
    assert!(text.contains("M0 ; STOP FOR THE HOB CHANGE"), "{text}");
    let sum: f64 = m.model.units.iter().map(|u| u.model.part_time_min).sum();
    assert!((m.model.part_time_min - sum).abs() < 1e-12);
}

/// docs/reference.md#reference-values's MESYS gear (mn 1, αn 20°, z 20, x 0, ha* 1, 1.7 mm balls) with
/// a matching inline module-1 hob, on H01.
const MESYS_JOB: &str = r#"
[job]
machine = "H01"
part_number = "MESYS-1"
[gear]
module_mm = 1.0
teeth = 20
face_width_mm = 10.0
ball_diameter_mm = 1.7
fixture_height_mm = 100.0
fixture_diameter_mm = 12.0
[hob]
starts = 1
od_mm = 40.0
module_mm = 1.0
lead_angle_deg = 1.5281
hand = "right"
length_mm = 40.0
[process]
cutting_speed_m_min = 60.0
feed_mm_per_rev = 1.0
"#;

#[test]
// MESYS prints sn = 1.5708 (π/2 for x = 0 to four decimals); the printed
// value is the oracle.
#[allow(clippy::approx_constant)]
fn check_json_fields_carry_the_published_geometry_and_the_cut_list() {
    // `gearcam check --json` writes `geometry` and `model` as these structs
    // serialise; the MESYS values (docs/reference.md#reference-values) to their printed precision.
    let (m, _) = run("MESYS", MESYS_JOB).unwrap_or_else(|e| panic!("{e:#?}"));
    let geometry = serde_json::to_value(&m.geometry).unwrap();
    let model = serde_json::to_value(&m.model).unwrap();
    let num = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k}"));
    assert!((num(&geometry, "sn_mm") - 1.5708).abs() < 5e-5);
    assert_eq!(geometry["span_teeth"], 2);
    assert!((num(&geometry, "span_mm") - 4.7083).abs() < 5e-5);
    assert!((num(&geometry, "over_balls_mm") - 22.2941).abs() < 5e-5);
    for key in ["d_mm", "db_mm", "da_mm", "df_mm"] {
        assert!(geometry[key].is_number(), "{key}");
    }
    assert_eq!(model["class"], "cylindrical");
    let cuts = model["cuts"].as_array().expect("model.cuts is a list");
    assert_eq!(cuts.len(), 1);
    assert_eq!(cuts[0]["positions"], model["positions"]);
    for key in [
        "swivel_deg",
        "clearance_mm",
        "centre_distance_mm",
        "hob_rpm",
        "table_rpm",
        "axial_feed_mm_min",
        "differential_deg_per_mm",
    ] {
        assert!(model[key].is_number(), "{key}");
    }
    for p in ["A", "B", "C", "D", "E"] {
        assert!(model["positions"][p]["x_mm"].is_number(), "{p}");
        assert!(model["positions"][p]["z_mm"].is_number(), "{p}");
    }
    // Every explained value names its origin.
    let explain = model["explain"].as_array().unwrap();
    assert!(explain
        .iter()
        .any(|e| e["name"] == "process.cutting_speed_m_min" && e["origin"] == "job"));
    assert!(explain
        .iter()
        .any(|e| e["name"] == "hob.od_mm" && e["origin"] == "job"));
    assert!(explain
        .iter()
        .any(|e| e["name"] == "machine.retract_mm" && e["origin"] == "machine"));
    assert!(explain
        .iter()
        .any(|e| e["name"] == "model.hob_rpm" && e["origin"] == "computed"));
}

#[test]
fn units_too_close_for_the_hob_run_out_collide() {
    // Unit 2 of the cluster example 45 mm above unit 1: cutting unit 2, its
    // hob (r 35 mm) at L 51.1 mm overlaps unit 1 (R 40.5 mm) by 24.4 mm
    // radially, so its centre must stay about 33 mm above unit 1's top face
    // (80 mm) and cannot reach unit 2's lower face (95 mm) less its run-out.
    let text = examples()
        .into_iter()
        .find(|(n, _)| n == "multi_gear_840d.toml")
        .unwrap()
        .1
        .replace("z_offset_mm = 90.0", "z_offset_mm = 45.0");
    let errors = run("close units", &text).unwrap_err();
    assert!(
        errors
            .iter()
            .any(|e| e.code == "UNIT_COLLISION" && e.field == "units[1].model.positions"),
        "{errors:#?}"
    );
}

/// The explained origin of the fixture height is its own value's: with the
/// drawing data from the workpiece library but no blank diameter among the
/// plan's values, it is `library`, not the job's (it once took the blank
/// diameter's origin).
#[test]
fn explain_names_the_fixture_heights_own_origin() {
    let (m, _) = example("spur_by_part_840d.toml");
    let mut plan = m.plan.clone();
    plan.values.remove("gear.blank_od_mm");
    let rows = gearcam_model::explain::explain(&plan, &m.geometry, &m.model);
    let origin = |name: &str| {
        rows.iter()
            .find(|e| e.name == name)
            .unwrap_or_else(|| panic!("no {name}"))
            .origin
    };
    assert_eq!(
        origin("gear.fixture_height_mm"),
        gearcam_proto::Origin::Library
    );
    assert_eq!(origin("gear.module_mm"), gearcam_proto::Origin::Library);
}

/// The hob shifts inside the usable length the tool
/// library gives (HOB-M3-80: 100 mm overall, 90 mm usable), not the overall
/// length: at the extreme positions the active length ends at the usable
/// length's ends, and the old range (on the overall length) was 5 mm wider
/// on each side.
#[test]
fn the_shift_travels_in_the_usable_length() {
    let (m, _) = example("multi_cut_shift_840d.toml");
    assert_eq!(m.plan.hob.length_mm, 100.0);
    assert_eq!(m.plan.hob.usable_length_mm, Some(90.0));
    let shift = m.model.shift.as_ref().expect("a shift plan");
    let half_active = shift.active_length_mm / 2.0;
    assert!(
        (shift.usable_mm[1] + half_active - 45.0).abs() < 1e-9,
        "{shift:?}"
    );
    assert!(
        (shift.usable_mm[0] - half_active + 45.0).abs() < 1e-9,
        "{shift:?}"
    );
    assert!(
        shift.start_mm.abs() + half_active <= 45.0 + 1e-9,
        "{shift:?}"
    );
    assert!(shift.end_mm.abs() + half_active <= 45.0 + 1e-9, "{shift:?}");
    // The explanation shows both lengths.
    let row = |name: &str| {
        m.model
            .explain
            .iter()
            .find(|e| e.name == name)
            .map(|e| e.value)
    };
    assert_eq!(row("hob.length_mm"), Some(100.0));
    assert_eq!(row("hob.usable_length_mm"), Some(90.0));
    // On the overall length (the defect) the range is 5 mm wider each side.
    let mut plan = m.plan.clone();
    plan.hob.usable_length_mm = None;
    let wide = gearcam_model::compute(&plan).expect("a model");
    let wide = wide.model.shift.expect("a shift plan");
    assert!((wide.usable_mm[1] - shift.usable_mm[1] - 5.0).abs() < 1e-9);
}
