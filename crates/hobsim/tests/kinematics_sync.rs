//! Synchronised and unsynchronised couplings: a unit coupled again after it
//! cut keeps its phase with `EGONSYNE` at the same positions, and with a
//! plain `EGON` is taken half a pitch off (the worst case of an unknown
//! phase), which cuts double teeth.

mod common;

use gearcam_hobsim::cut::{self, Blank, Resolution};
use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{self, MachineRates, Timeline};
use gearcam_proto::{Code, MachiningModel};

const COARSE: Resolution = Resolution {
    axial_step_mm: 1.0,
    tolerance_mm: 1e-3,
};

/// The spur program cut twice: after the first cut's retract the gearbox is
/// switched off, the hob (still turning) goes back up, and `couple` couples
/// it again before the same cut once more.
fn recut(couple: &str) -> String {
    let (text, _) = common::program("spur_840d");
    let second = format!(
        "N211 EGOFS(C)\nN212 G0 G90 X=173.75\nN213 G0 G90 Z=154.278\nN214 {couple}\n\
         N215 G0 G90 X=73.75\nN216 G1 G90 G94 Z=75.722 F=28.634\nN217 G0 G90 X=78.75\n"
    );
    let at = text.find("N220 M5").expect("spur program's M5");
    let mut out = text.clone();
    out.insert_str(at, &second);
    out
}

/// The timeline of `text` (findings allowed) and the check's findings.
fn timeline(text: &str, model: &MachiningModel) -> (Timeline, Vec<gearcam_proto::PathFinding>) {
    let (check, trace) = gearcam_nc::check(text, model);
    let tl = kinematics::from_trace(&trace, model, MachineRates::default()).expect("timeline");
    (tl, check.findings)
}

/// The fraction of the reference circle still material in each of 3
/// sections, and the gaps of each.
fn cut_fraction(tl: &Timeline, model: &MachiningModel) -> Vec<(f64, usize)> {
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let g = &model.plan.gear;
    let h = g.fixture_height_mm;
    let z = Blank::planes(h + 2.0, h + g.face_width_mm - 2.0, 3);
    let mut blank =
        Blank::new(z, model.model.blank_od_mm / 2.0, g.teeth as usize * 16).expect("blank");
    cut::cut(tl, &hob, &mut blank, COARSE).expect("cut");
    let r = model.geometry.d_mm / 2.0;
    blank
        .r_mm
        .iter()
        .map(|o| {
            let solid = o.iter().filter(|&&x| x >= r).count() as f64 / o.len() as f64;
            (solid, common::gaps(o, r).len())
        })
        .collect()
}

#[test]
fn the_spur_programs_coupling_is_synchronised_in_the_trace() {
    let (text, model) = common::program("spur_840d");
    let (_, trace) = gearcam_nc::check(&text, &model);
    assert_eq!(trace.couplings.len(), 1);
    assert!(trace.couplings[0].synchronised, "EGONSYNE");
    let plain = text.replace(
        "EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25)",
        "EGON(C,\"FINE\",B,1,25)",
    );
    let (_, trace) = gearcam_nc::check(&plain, &model);
    assert!(!trace.couplings[0].synchronised, "EGON");
}

#[test]
fn a_unit_coupled_again_with_egonsyne_keeps_its_teeth() {
    let (_, model) = common::program("spur_840d");
    let text = recut("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25)");
    let (tl, findings) = timeline(&text, &model);
    assert!(findings.is_empty(), "{findings:?}");
    let phases = tl.couplings();
    assert_eq!(phases.len(), 2, "{phases:?}");
    assert!(phases[1].synchronised && !phases[1].phase_unknown);
    assert_eq!(phases[1].reference_line, phases[0].line);
    // The hob turned on while decoupled: the table had to move back.
    assert!(phases[1].jump_rad.abs() > 1e-6, "{phases:?}");
    let (single, _) = common::program("spur_840d");
    let once = cut_fraction(&common::timeline(&single, &model), &model);
    let twice = cut_fraction(&tl, &model);
    for (j, ((f1, n1), (f2, n2))) in once.iter().zip(&twice).enumerate() {
        assert_eq!((*n1, *n2), (25, 25), "section {j}");
        assert!(
            (f1 - f2).abs() < 0.01,
            "section {j}: solid {f1} once, {f2} twice"
        );
    }
}

#[test]
fn a_unit_coupled_again_with_a_plain_egon_cuts_double_teeth() {
    let (_, model) = common::program("spur_840d");
    let text = recut("EGON(C,\"FINE\",B,1,25)");
    let (tl, findings) = timeline(&text, &model);
    let line = text
        .lines()
        .position(|l| l.starts_with("N214"))
        .map(|i| i as u32 + 1)
        .unwrap();
    assert!(
        findings
            .iter()
            .any(|f| f.line == line && f.rule == Code::COUPLING_RATIO),
        "{findings:?}"
    );
    let phases = tl.couplings();
    assert!(!phases[1].synchronised && phases[1].phase_unknown);
    assert!((phases[1].offset_rad - std::f64::consts::PI / 25.0).abs() < 1e-12);
    let (single, _) = common::program("spur_840d");
    let once = cut_fraction(&common::timeline(&single, &model), &model);
    let twice = cut_fraction(&tl, &model);
    for (j, ((f1, _), (f2, _))) in once.iter().zip(&twice).enumerate() {
        // Each cut leaves about half the reference circle; the second,
        // half a pitch off, takes most of what the first left.
        assert!(
            *f1 > 0.35 && *f2 < 0.5 * f1,
            "section {j}: solid {f1} once, {f2} twice"
        );
    }
}

/// Two gear units, each coupled once with `EGONSYNE` after its own `EGDEF`:
/// each coupling starts its unit, none takes an unknown phase.
#[test]
fn two_units_each_set_their_own_reference() {
    let (text, model) = common::program("two_units_five_cuts_840d");
    let (tl, findings) = timeline(&text, &model);
    assert!(findings.is_empty(), "{findings:?}");
    let phases = tl.couplings();
    let units: Vec<usize> = phases.iter().map(|p| p.unit).collect();
    assert_eq!(units, vec![0, 1], "{phases:?}");
    assert!(phases.iter().all(|p| !p.phase_unknown && p.jump_rad == 0.0));
}
