//! Safety findings from the run: each produced by a program with that
//! defect, none on the correct example programs.

mod common;

use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{self, MachineRates};
use gearcam_hobsim::safety::{self, BlankGeometry, Fixtures, SafetyFinding, SafetyKind};
use gearcam_proto::MachiningModel;

/// The safety findings of `text` against `model` (the path check's own
/// findings do not stop the run).
fn findings(text: &str, model: &MachiningModel) -> Vec<SafetyFinding> {
    let (_, trace) = gearcam_nc::check(text, model);
    let tl = kinematics::from_trace(&trace, model, MachineRates::default()).expect("timeline");
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let blank = BlankGeometry::of_model(model);
    safety::check(&tl, &hob, &blank, &Fixtures::of_model(model, &blank))
}

/// A FANUC program and its model from `crates/hobsim/tests/programs`.
fn fanuc(name: &str) -> (String, MachiningModel) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/programs/");
    let text = std::fs::read_to_string(format!("{dir}{name}.nc")).expect("program");
    let json = std::fs::read_to_string(format!("{dir}{name}.model.json")).expect("model");
    (text, serde_json::from_str(&json).expect("model reads"))
}

/// The 1-based line of the block starting `n`.
fn line_of(text: &str, n: &str) -> u32 {
    let i = text
        .lines()
        .position(|l| l.starts_with(n))
        .unwrap_or_else(|| panic!("no block {n}"));
    u32::try_from(i + 1).unwrap()
}

/// The spur program with `from` replaced by `to` (which must occur).
fn spur_with(from: &str, to: &str) -> (String, MachiningModel) {
    let (text, model) = common::program("spur_840d");
    assert!(text.contains(from), "{from}");
    (text.replacen(from, to, 1), model)
}

fn kinds(f: &[SafetyFinding]) -> Vec<(SafetyKind, u32)> {
    f.iter().map(|f| (f.kind, f.line)).collect()
}

#[test]
fn the_correct_programs_have_no_finding() {
    for name in ["spur_840d", "helical_climb_840d"] {
        let (text, model) = common::program(name);
        let f = findings(&text, &model);
        assert!(f.is_empty(), "{name}: {f:#?}");
    }
    for name in ["spur_fanuc", "helical_climb_fanuc"] {
        let (text, model) = fanuc(name);
        let f = findings(&text, &model);
        assert!(f.is_empty(), "{name}: {f:#?}");
    }
    let (text, model) = common::program("helical_shift_fanuc");
    let f = findings(&text, &model);
    assert!(f.is_empty(), "helical_shift_fanuc: {f:#?}");
}

/// A what-if run of a correct program on a worn machine (a hob with radial
/// and axial runout, an eccentric workpiece) changes the gear it cuts, not
/// what the program commands: no depth or face-width finding.
#[test]
fn runouts_do_not_make_a_correct_program_unsafe() {
    let errors = kinematics::MachineErrors {
        hob_radial_mm: 0.02,
        hob_axial_mm: 0.01,
        table_mm: 0.01,
        ..Default::default()
    };
    for name in ["spur_840d", "helical_climb_840d"] {
        let (text, model) = common::program(name);
        let (_, trace) = gearcam_nc::check(&text, &model);
        let tl = kinematics::from_trace_with(&trace, &model, MachineRates::default(), errors)
            .expect("timeline");
        let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
        let blank = BlankGeometry::of_model(&model);
        let f = safety::check(&tl, &hob, &blank, &Fixtures::of_model(&model, &blank));
        assert!(f.is_empty(), "{name}: {f:#?}");
    }
}

/// The tangential worm-wheel program feeds along Y while coupled with the
/// model's C per Y: the shift rule's −(C/B)·ΔY/p agrees with it.
#[test]
fn the_tangential_feed_is_compensated() {
    let (text, model) = common::program("worm_wheel_tangential_840d");
    let f = findings(&text, &model);
    let shifts: Vec<_> = f
        .iter()
        .filter(|f| f.kind == SafetyKind::UncompensatedShift)
        .collect();
    assert!(shifts.is_empty(), "{shifts:#?}");
    // Without the Y factor the same feed is flagged.
    let bare = text
        .replace(",Y,0,0.954112,1)", ")")
        .replace("EGDEF(C,B,1,Y,1)", "EGDEF(C,B,1)");
    let f = findings(&bare, &model);
    assert!(
        f.iter()
            .any(|f| f.kind == SafetyKind::UncompensatedShift && f.line == line_of(&bare, "N210")),
        "{f:#?}"
    );
}

#[test]
fn a_rapid_infeed_into_the_blank_is_a_rapid_contact() {
    // The approach height lowered into the face width: the rapid infeed to
    // depth runs into the blank.
    let (text, model) = spur_with("N60 G0 G90 Z=154.278", "N60 G0 G90 Z=125.0");
    let f = findings(&text, &model);
    assert!(
        kinds(&f).contains(&(SafetyKind::RapidContact, line_of(&text, "N190"))),
        "{f:#?}"
    );
}

#[test]
fn a_feed_without_the_gearbox_is_cutting_decoupled() {
    let (text, model) = spur_with("N170 EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25)", "N170 M0");
    let f = findings(&text, &model);
    let line = line_of(&text, "N200");
    assert!(
        kinds(&f).contains(&(SafetyKind::CutDecoupled, line)),
        "{f:#?}"
    );
    let (text, model) = spur_with(",B,0,1,25)", ",B,0,1,24)");
    let f = findings(&text, &model);
    assert!(
        kinds(&f).contains(&(SafetyKind::CutWrongRatio, line)),
        "{f:#?}"
    );
}

#[test]
fn a_feed_down_to_the_table_meets_the_fixtures() {
    let (text, model) = spur_with("Z=75.722 F=28.634", "Z=20.0 F=28.634");
    let f = findings(&text, &model);
    assert!(
        kinds(&f).contains(&(SafetyKind::FixtureContact, line_of(&text, "N200"))),
        "{f:#?}"
    );
}

#[test]
fn a_shallow_or_short_cut_is_flagged() {
    let (text, model) = spur_with("N190 G0 G90 X=73.75", "N190 G0 G90 X=74.25");
    let f = findings(&text, &model);
    assert_eq!(
        kinds(&f),
        vec![(SafetyKind::DepthNotReached, line_of(&text, "N200"))],
        "{f:#?}"
    );
    // The feed stops inside the face width: the gaps' lower part is not
    // cut, and the retracts from there (rapids) run through the blank left.
    let (text, model) = spur_with("Z=75.722 F=28.634", "Z=110.0 F=28.634");
    let f = findings(&text, &model);
    let k = kinds(&f);
    assert_eq!(
        k[0],
        (SafetyKind::FaceWidthNotCovered, line_of(&text, "N200")),
        "{f:#?}"
    );
    assert!(
        k[1..]
            .iter()
            .all(|(kind, _)| *kind == SafetyKind::RapidContact),
        "{f:#?}"
    );
}

#[test]
fn a_shift_during_the_cut_without_compensation_is_flagged() {
    let (text, model) = spur_with("N200 G1 G90 G94 Z=75.722", "N200 G1 G90 G94 Z=75.722 Y=5.0");
    let f = findings(&text, &model);
    assert!(
        kinds(&f).contains(&(SafetyKind::UncompensatedShift, line_of(&text, "N200"))),
        "{f:#?}"
    );
}

/// The spur program cut twice, coupled again by `couple` before the second
/// cut (as in `kinematics_sync.rs`).
fn recut(couple: &str) -> (String, MachiningModel) {
    let (text, model) = common::program("spur_840d");
    let second = format!(
        "N211 EGOFS(C)\nN212 G0 G90 X=173.75\nN213 G0 G90 Z=154.278\nN214 {couple}\n\
         N215 G0 G90 X=73.75\nN216 G1 G90 G94 Z=75.722 F=28.634\nN217 G0 G90 X=78.75\n"
    );
    let at = text.find("N220 M5").expect("M5");
    let mut out = text.clone();
    out.insert_str(at, &second);
    (out, model)
}

#[test]
fn coupling_again_without_synchronisation_is_flagged() {
    let (text, model) = recut("EGON(C,\"FINE\",B,1,25)");
    let f = findings(&text, &model);
    assert_eq!(
        kinds(&f),
        vec![(SafetyKind::UnsynchronisedCoupling, line_of(&text, "N214"))],
        "{f:#?}"
    );
    let (text, model) = recut("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25)");
    let f = findings(&text, &model);
    assert!(f.is_empty(), "{f:#?}");
}
