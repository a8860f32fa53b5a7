use super::*;
use crate::fixtures;
use crate::hobbing::{hob_reference_diameter_mm, kinematics};
use gearcam_proto::Hand;

fn codes_of(plan: &ProcessPlan) -> Vec<Code> {
    validate(plan).errors.into_iter().map(|e| e.code).collect()
}

#[test]
fn fixture_plan_passes_without_warnings() {
    let report = validate(&fixtures::plan());
    assert!(report.is_ok(), "{:?}", report.errors);
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    let report = validate(&fixtures::helical_plan(15.0, Hand::Left));
    assert!(report.is_ok(), "{:?}", report.errors);
}

#[test]
fn hob_module_2_5_for_module_3_gear_is_a_base_pitch_mismatch() {
    let mut plan = fixtures::plan();
    plan.hob.module_mm = 2.5;
    let report = validate(&plan);
    let e = report
        .errors
        .iter()
        .find(|e| e.code == Code::BASE_PITCH_MISMATCH)
        .expect("BASE_PITCH_MISMATCH reported");
    assert_eq!(e.stage, Stage::Model);
    assert_eq!(e.field, "hob.module_mm");
    // 3·cos 20° = 2.819078 mm, 2.5·cos 20° = 2.349232 mm.
    assert_eq!(
        e.expected,
        "mn0·cos α0 = 2.819078 mm ± 0.0001 mm (hob module 3 mm at α0 20°)"
    );
    assert_eq!(
        e.got,
        "mn0·cos α0 = 2.349232 mm (hob module 2.5 mm, α0 20°)"
    );
    assert!(e.message.contains("choose a matching hob"), "{}", e.message);
    // d0 = 2.5/sin 2.3716° = 60.4151 mm, so the default depth
    // (80 + 81)/2 − (d0/2 + 37.5) = 12.7925 mm is too deep as well.
    assert_eq!(report.codes(), vec!["BASE_PITCH_MISMATCH", "CUT_DEPTH"]);
}

#[test]
fn a_ball_below_the_base_circle_is_refused_with_the_smallest_that_rests() {
    let mut plan = fixtures::plan();
    let g = &mut plan.gear;
    g.ball_diameter_mm = Some(0.5);
    let min = crate::geometry::min_ball_mm(g);
    let e = validate(&plan)
        .errors
        .into_iter()
        .find(|e| e.code == "BALL_DIAMETER_RANGE")
        .expect("a ball of 0.5 mm on module 3 falls through the space");
    assert_eq!(e.field, "gear.ball_diameter_mm");
    assert_eq!(
        e.expected,
        format!(
            "> {} mm (smaller balls drop below the base circle)",
            num(min)
        )
    );
    assert_eq!(e.got, "0.5 mm");
    plan.gear.ball_diameter_mm = Some(min * 1.01);
    assert!(validate(&plan)
        .errors
        .iter()
        .all(|e| e.code != "BALL_DIAMETER_RANGE"));
}

#[test]
fn reports_several_failures_together() {
    let mut plan = fixtures::plan();
    plan.hob.module_mm = 2.5;
    plan.process.cuts = 7;
    plan.process.feed_mm_per_rev = 0.0;
    plan.process.cutting_speed_m_min = f64::NAN;
    plan.request.spec.job.quantity = 0;
    plan.gear.blank_od_mm = Some(70.0);
    plan.hob.lead_angle_deg = 50.0;
    assert_eq!(
        codes_of(&plan),
        vec![
            "HOB_LEAD_ANGLE_RANGE",
            "QUANTITY_RANGE",
            "CUTS_RANGE",
            "CUTTING_SPEED_RANGE",
            "FEED_RANGE",
            "BLANK_OD_WINDOW",
        ]
    );
    // With a valid lead angle the hob checks run too.
    plan.hob.lead_angle_deg = 2.3716;
    assert_eq!(
        codes_of(&plan),
        vec![
            "QUANTITY_RANGE",
            "CUTS_RANGE",
            "CUTTING_SPEED_RANGE",
            "FEED_RANGE",
            "BLANK_OD_WINDOW",
            "BASE_PITCH_MISMATCH",
            "CUT_DEPTH",
        ]
    );
}

#[test]
fn blank_od_exactly_at_the_window_edges_passes_with_a_warning() {
    // da = 81 mm; window 79 to 81.5 mm.
    for blank in [79.0, 81.5] {
        let mut g = fixtures::gear();
        g.blank_od_mm = Some(blank);
        let report = validate(&fixtures::plan_with(g));
        assert!(report.is_ok(), "{blank}: {:?}", report.errors);
        assert_eq!(report.warnings.len(), 1);
        assert_eq!(report.warnings[0].code, "BLANK_OD_EDGE");
        assert_eq!(report.warnings[0].field, "gear.blank_od_mm");
    }
    // 1.7 mm under uses 85 % of the 2 mm allowance: no warning.
    let mut g = fixtures::gear();
    g.blank_od_mm = Some(79.3);
    let report = validate(&fixtures::plan_with(g));
    assert!(report.is_ok() && report.warnings.is_empty(), "{report:?}");
}

#[test]
fn blank_od_outside_the_window_fails() {
    let mut g = fixtures::gear();
    g.blank_od_mm = Some(78.99);
    let report = validate(&fixtures::plan_with(g));
    assert_eq!(report.codes(), vec!["BLANK_OD_WINDOW"]);
    let e = &report.errors[0];
    assert_eq!(e.field, "gear.blank_od_mm");
    assert_eq!(e.expected, "79 to 81.5 mm (tip diameter da 81 mm)");
    assert_eq!(e.got, "78.99 mm");
}

#[test]
fn default_depth_sits_exactly_at_the_theoretical_centre_distance() {
    let plan = fixtures::plan();
    let geo = geometry(&plan.gear);
    let set = setup(&plan, &geo);
    assert!(!set.depth_given);
    assert_eq!(set.centre_distance_mm, set.theoretical_centre_distance_mm);
    // Giving that depth explicitly passes too.
    let mut given = fixtures::plan();
    given.process.depth_mm = Some(set.depth_mm);
    assert!(validate(&given).is_ok());
}

#[test]
fn deeper_depth_cuts_thin_teeth_and_too_deep_depth_cuts_the_root() {
    // Whole depth 6.75 + allowance 0.5 = 7.25 mm passes check 2 exactly,
    // but any depth beyond 6.750963 mm makes L smaller than the theory.
    let mut plan = fixtures::plan();
    plan.process.depth_mm = Some(7.25);
    assert_eq!(codes_of(&plan), vec!["CENTRE_DISTANCE_TOO_SMALL"]);
    plan.process.depth_mm = Some(7.26);
    assert_eq!(
        codes_of(&plan),
        vec!["CUT_DEPTH", "CENTRE_DISTANCE_TOO_SMALL"]
    );
    let report = validate(&plan);
    assert_eq!(report.errors[0].field, "process.depth_mm");
    assert_eq!(
        report.errors[0].expected,
        "> 0 and ≤ 7.25 mm (whole depth 6.75 mm for the blank, + allowance 0.5 mm)"
    );
    plan.process.depth_mm = Some(0.0);
    assert_eq!(codes_of(&plan), vec!["CUT_DEPTH"]);
}

#[test]
fn hob_od_exactly_at_its_minimum_passes() {
    let mut plan = fixtures::plan();
    let min = hob_reference_diameter_mm(&plan.hob) + 2.0 * 1.25 * 3.0;
    plan.hob.od_mm = min;
    assert!(validate(&plan).is_ok(), "{:?}", validate(&plan).errors);
    plan.hob.od_mm = min - 0.01;
    let report = validate(&plan);
    assert_eq!(report.codes(), vec!["HOB_OD_TOO_SMALL"]);
    assert_eq!(report.errors[0].field, "hob.od_mm");
}

#[test]
fn helical_gear_needs_a_hand_and_a_sane_angle() {
    let mut g = fixtures::gear();
    g.helix_angle_deg = 15.0;
    assert_eq!(
        codes_of(&fixtures::plan_with(g.clone())),
        vec!["HELIX_HAND_MISSING"]
    );
    g.helix_angle_deg = 90.0;
    assert_eq!(codes_of(&fixtures::plan_with(g)), vec!["HELIX_RANGE"]);
}

#[test]
fn broken_gear_parameters_skip_the_physical_checks() {
    let mut g = fixtures::gear();
    g.teeth = 0;
    g.module_mm = -3.0;
    g.face_width_mm = 0.0;
    assert_eq!(
        codes_of(&fixtures::plan_with(g)),
        vec!["TEETH_RANGE", "MODULE_RANGE", "FACE_WIDTH_RANGE"]
    );
}

#[test]
fn machine_limits_before_computation() {
    let mut plan = fixtures::plan();
    plan.machine.limits.module_mm = [0.5, 2.0];
    plan.machine.limits.max_workpiece_od_mm = 80.0;
    plan.machine.limits.max_hob_od_mm = 70.0;
    let report = validate(&plan);
    assert_eq!(
        report.codes(),
        vec!["MACHINE_MODULE_LIMIT", "WORKPIECE_OD_LIMIT", "HOB_OD_LIMIT"]
    );
    assert_eq!(report.errors[0].expected, "0.5 to 2 mm");
    assert_eq!(report.errors[0].got, "3 mm");
}

#[test]
fn limits_after_computation() {
    let mut plan = fixtures::plan();
    plan.machine.home_x_mm = 500.0;
    plan.gear.fixture_height_mm = 380.0;
    let k = kinematics(&plan, &geometry(&plan.gear));
    let errors = check_limits(&plan, &k);
    let fields: Vec<_> = errors.iter().map(|e| e.field.as_str()).collect();
    // Top = 380 + 30 + 22.2035 + 2 = 434.2 mm > 400 at B and C.
    assert_eq!(
        fields,
        vec![
            "model.positions.A.x_mm",
            "model.positions.B.z_mm",
            "model.positions.C.z_mm"
        ]
    );
    assert!(errors.iter().all(|e| e.code == "POSITION_TRAVEL_LIMIT"));
    assert_eq!(errors[0].expected, "0 to 400 mm");
    assert_eq!(errors[0].got, "500 mm");
}

#[test]
fn swivel_beyond_the_machine_is_reported_after_computation() {
    // β 44° left-hand, right-hand hob: η = −44 − 2.3716 = −46.3716°,
    // |η| > 45°; H01 programs A = −η.
    let plan = fixtures::helical_plan(44.0, Hand::Left);
    assert!(validate(&plan).is_ok());
    let errors: Vec<_> = crate::compute(&plan)
        .unwrap_err()
        .into_iter()
        .filter(|e| e.code != "ENVELOPE_COLLISION")
        .collect();
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert_eq!(errors[0].code, "SWIVEL_LIMIT");
    assert_eq!(errors[0].got, "-46.3716 °");
}

#[test]
fn the_machine_profile_new_fields_are_checked_with_their_names() {
    let mut plan = fixtures::plan();
    plan.machine.settings.table_sign = 0.5;
    plan.machine.envelope.table_radius_mm = -1.0;
    plan.machine.parameters.r_first = 980;
    plan.gear.fixture_diameter_mm = Some(f64::NAN);
    let fields: Vec<String> = validate(&plan)
        .errors
        .into_iter()
        .map(|e| e.field)
        .collect();
    for want in [
        "machine.settings.table_sign",
        "machine.envelope.table_radius_mm",
        "machine.parameters.r_first",
        "gear.fixture_diameter_mm",
    ] {
        assert!(fields.iter().any(|f| f == want), "{want} in {fields:?}");
    }
}

#[test]
fn numbers_print_plainly() {
    assert_eq!(num(80.0), "80");
    assert_eq!(num(2.5), "2.5");
    assert_eq!(num(-0.0000001), "0");
    assert_eq!(num(1.0 / 3.0), "0.333333");
    assert_eq!(num(f64::NAN), "NaN");
}

#[test]
fn tolerances_and_windows_come_from_the_config() {
    // A blank 1 mm over da fails H01's +0.5 mm window but passes a
    // machine configured for +1.5 mm; the defaults are documented.
    let mut plan = fixtures::plan();
    plan.gear.blank_od_mm = Some(82.0);
    assert_eq!(codes_of(&plan), vec![Code::BLANK_OD_WINDOW]);
    let cfg = Config {
        blank_od_above_mm: 1.5,
        ..Config::for_machine(&plan.machine)
    };
    let report = validate_with(&plan, &cfg);
    assert!(report.is_ok(), "{:?}", report.errors);
    let d = Config::default();
    assert_eq!(
        (d.length_tolerance_mm, d.base_pitch_tolerance_mm),
        (1e-6, 1e-4)
    );
    assert_eq!(
        (
            d.blank_od_below_mm,
            d.blank_od_above_mm,
            d.depth_allowance_mm
        ),
        (2.0, 0.5, 0.5)
    );
    // A base-pitch tolerance is a per-machine choice too.
    let mut off = fixtures::plan();
    off.hob.module_mm = 2.9995;
    assert_eq!(codes_of(&off), vec![Code::BASE_PITCH_MISMATCH]);
    let loose = Config {
        base_pitch_tolerance_mm: 1e-3,
        ..Config::default()
    };
    assert!(validate_with(&off, &loose).is_ok());
}

#[test]
fn class_options_and_cut_settings_are_checked() {
    let mut plan = fixtures::plan();
    plan.gear.cone = Some(gearcam_proto::ConeSpec {
        angle_deg: 6.5,
        large_end: gearcam_proto::LargeEnd::Bottom,
    });
    plan.sections_mut().process.infeed = Some(Infeed::RadialAxial);
    plan.process.cuts = 2;
    plan.sections_mut().process.finish_allowance_mm = Some(9.0);
    plan.sections_mut().process.radial_feed_mm_per_rev = Some(0.0);
    assert_eq!(
        codes_of(&plan),
        vec![
            Code::CLASS_OPTION_UNSUPPORTED,
            Code::FEED_RATE_RANGE,
            Code::FINISH_ALLOWANCE_RANGE
        ]
    );
}

#[test]
fn unit_errors_name_the_unit() {
    let mut plan = fixtures::plan();
    let mut g = fixtures::gear();
    g.module_mm = 2.0;
    plan.sections_mut().units.push(gearcam_proto::UnitSpec {
        name: None,
        z_offset_mm: 10.0,
        gear: g,
        hob: Default::default(),
    });
    plan.class = gearcam_proto::GearClass::MultiGear;
    let report = validate(&plan);
    // The unit overlaps unit 1 (30 mm face) and a module-2 gear does not fit
    // the job's module-3 hob.
    let fields: Vec<(Code, &str)> = report
        .errors
        .iter()
        .map(|e| (e.code, e.field.as_str()))
        .collect();
    assert!(
        fields.contains(&(Code::UNIT_RANGE, "units[0].z_offset_mm")),
        "{fields:?}"
    );
    assert!(
        fields.contains(&(Code::BASE_PITCH_MISMATCH, "units[0].hob.module_mm")),
        "{fields:?}"
    );
}
