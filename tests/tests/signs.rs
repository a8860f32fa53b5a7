//! Hobbing programs that are right on a real machine: the signs read back
//! from the emitted program text of both dialects (mirror and invariance
//! properties over random jobs), the independent clearance check against the
//! patent's ΔH′, and one regression test per defect found, named after it.
//!
//! Nothing here recomputes the model's formulas to judge the program: the
//! signs come from the parsed program (the profile's axis mapping turns the
//! swivel value back into η), and the clearance from the path check's swept
//! hob solid.

use gearcam_nc as nc;
use gearcam_proto::{MachiningModel, MoveKind};
use gearcam_template::Templates;
use gearcam_testkit::examples::{example, on_machine};
use gearcam_testkit::pipeline::model_of;
use proptest::prelude::*;

/// What a program says, parsed back: η of every swivel value (through the
/// machine profile's mapping), every coupling's signed ratio and C-per-Z
/// factor, and every move.
#[derive(Debug, Clone, PartialEq)]
struct Said {
    eta: Vec<f64>,
    ratios: Vec<(i64, i64)>,
    c_per_z: Vec<Option<f64>>,
    moves: Vec<(MoveKind, f64, f64, Option<f64>)>,
}

fn said(model: &MachiningModel) -> Said {
    let program = Templates::builtin()
        .render(model)
        .unwrap_or_else(|e| panic!("{e:#?}"));
    let (check, trace) = nc::check(&program.text, model);
    assert!(check.ok, "{:#?}\n{}", check.findings, program.text);
    let s = &model.plan.machine.settings;
    Said {
        eta: trace
            .swivel_deg
            .iter()
            .map(|(_, a)| (a - s.swivel_offset_deg) * s.swivel_sign)
            .collect(),
        ratios: trace.couplings.iter().map(|c| (c.num, c.den)).collect(),
        c_per_z: trace
            .couplings
            .iter()
            .map(|c| c.c_per_z_deg_per_mm)
            .collect(),
        moves: trace
            .moves
            .iter()
            .map(|m| (m.kind, m.x_mm, m.z_mm, m.feed_mm_min))
            .collect(),
    }
}

/// A cylindrical job with an inline module-3 hob, hands and cut mode given.
fn job(
    machine: &str,
    teeth: u32,
    helix: f64,
    gear_right: bool,
    hob_right: bool,
    climb: bool,
) -> String {
    let hand = |right: bool| if right { "right" } else { "left" };
    let gear_hand = if helix > 0.0 {
        format!("helix_hand = \"{}\"\n", hand(gear_right))
    } else {
        String::new()
    };
    format!(
        "[job]\nmachine = \"{machine}\"\npart_number = \"SG-{teeth}\"\nquantity = 4\n\n\
         [gear]\nmodule_mm = 3.0\nteeth = {teeth}\nhelix_angle_deg = {helix:.3}\n{gear_hand}\
         face_width_mm = 30.0\nmaterial = \"42CrMo4\"\nfixture_height_mm = 110.0\nfixture_diameter_mm = 30.0\n\n\
         [hob]\nstarts = 1\nod_mm = 80.0\nmodule_mm = 3.0\nlead_angle_deg = 2.3716\nhand = \"{}\"\nlength_mm = 100.0\n\n\
         [process]\ncut_mode = \"{}\"\ncuts = 1\n",
        hand(hob_right),
        if climb { "climb" } else { "conventional" },
    )
}

/// A job of another class with the hands given: conical (spur), crowned,
/// worm wheel (the wheel's helix is the hob's lead, of the hob's hand) or
/// multi-gear (a helical second unit cut with the job's hob).
fn class_job(
    class: u8,
    machine: &str,
    teeth: u32,
    helix: f64,
    gear_right: bool,
    hob_right: bool,
) -> String {
    let hand = |right: bool| if right { "right" } else { "left" };
    let hob = format!(
        "[hob]\nstarts = 1\nod_mm = 80.0\nmodule_mm = 3.0\nlead_angle_deg = 2.3716\nhand = \"{}\"\nlength_mm = 100.0\n",
        hand(hob_right)
    );
    let head =
        format!("[job]\nmachine = \"{machine}\"\npart_number = \"MC-{teeth}\"\nquantity = 4\n\n");
    let gear = |helix: f64, right: bool| {
        let h = if helix > 0.0 {
            format!(
                "helix_angle_deg = {helix:.4}\nhelix_hand = \"{}\"\n",
                hand(right)
            )
        } else {
            String::new()
        };
        format!(
            "module_mm = 3.0\nteeth = {teeth}\n{h}face_width_mm = 30.0\nmaterial = \"42CrMo4\"\n\
             fixture_height_mm = 110.0\nfixture_diameter_mm = 30.0\n"
        )
    };
    match class {
        0 => format!(
            "{head}[gear]\n{}\n[gear.cone]\nangle_deg = 6.5\nlarge_end = \"bottom\"\n\n{hob}",
            gear(0.0, true)
        ),
        1 => format!(
            "{head}[gear]\n{}\n[gear.crowning]\namount_mm = 0.02\nshape = \"circular\"\n\n{hob}",
            gear(helix, gear_right)
        ),
        2 => format!(
            "{head}[gear]\n{}\n[gear.worm_wheel]\ninfeed = \"radial\"\n\n{hob}",
            gear(2.3716, hob_right)
        ),
        _ => format!(
            "{head}[gear]\n{}\n{hob}\n[[units]]\nname = \"upper gear\"\nz_offset_mm = 90.0\n\n[units.gear]\n{}",
            gear(0.0, true),
            gear(helix.max(5.0), gear_right)
        ),
    }
}

/// A random cylindrical set-up: machine (FANUC or 840D), teeth, helix (0 =
/// spur), gear hand, hob hand, climb.
fn setup() -> impl Strategy<Value = (bool, u32, f64, bool, bool, bool)> {
    (
        any::<bool>(),
        18u32..70,
        prop_oneof![Just(0.0), 5.0f64..30.0],
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
    )
}

fn said_of(text: &str) -> Said {
    said(&model_of(text).unwrap_or_else(|e| panic!("{e:#?}\n{text}")))
}

fn negated(v: &[Option<f64>]) -> Vec<Option<f64>> {
    v.iter().map(|z| z.map(|z| -z)).collect()
}

/// The ratios with the direction turned.
fn flipped(v: &[(i64, i64)]) -> Vec<(i64, i64)> {
    v.iter().map(|(n, d)| (-n, *d)).collect()
}

/// The mirror image's program: η, the ratio's sign and the differential
/// turned, every move the same.
fn assert_mirrored(base: &Said, mirror: &Said) -> Result<(), TestCaseError> {
    prop_assert_eq!(mirror.eta.len(), base.eta.len());
    for (m, b) in mirror.eta.iter().zip(&base.eta) {
        prop_assert!((m + b).abs() < 1e-9, "η {} mirrors to {}", b, m);
    }
    prop_assert_eq!(&mirror.ratios, &flipped(&base.ratios));
    prop_assert_eq!(&mirror.c_per_z, &negated(&base.c_per_z));
    prop_assert_eq!(&mirror.moves, &base.moves);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    /// Mirroring the whole set-up (both hands) mirrors the swivel, the
    /// indexing direction and the differential, and nothing else; the
    /// differential ignores the hob's hand and the cut mode; the indexing
    /// direction ignores the gear's hand and the cut mode. On both dialects.
    #[test]
    fn mirror_and_invariance_of_the_emitted_program(
        (fanuc, teeth, helix, gear_right, hob_right, climb) in setup(),
    ) {
        let machine = if fanuc { "H02" } else { "H01" };
        let base = said_of(&job(machine, teeth, helix, gear_right, hob_right, climb));
        prop_assert!(!base.eta.is_empty() && !base.ratios.is_empty());

        let mirror = said_of(&job(machine, teeth, helix, !gear_right, !hob_right, climb));
        assert_mirrored(&base, &mirror)?;
        for b in &base.eta {
            prop_assert!(b.abs() > 1.0, "a hob is always tilted by its lead angle at least: {}", b);
        }

        let other_hob = said_of(&job(machine, teeth, helix, gear_right, !hob_right, climb));
        prop_assert_eq!(&other_hob.c_per_z, &base.c_per_z);
        prop_assert_eq!(&other_hob.ratios, &flipped(&base.ratios));

        let other_mode = said_of(&job(machine, teeth, helix, gear_right, hob_right, !climb));
        prop_assert_eq!(&other_mode.c_per_z, &base.c_per_z);
        prop_assert_eq!(&other_mode.ratios, &base.ratios);

        if helix > 0.0 {
            let other_gear = said_of(&job(machine, teeth, helix, !gear_right, hob_right, climb));
            prop_assert_eq!(&other_gear.ratios, &base.ratios);
            prop_assert_eq!(&other_gear.c_per_z, &negated(&base.c_per_z));
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 16, .. ProptestConfig::default() })]

    /// The mirror of every other programmable class: both hands swapped
    /// mirror the swivel, the indexing direction and the differential of
    /// every unit, and leave every move as it was. On both dialects.
    #[test]
    fn mirror_of_every_class(
        class in 0u8..4,
        fanuc in any::<bool>(),
        teeth in 30u32..60,
        helix in prop_oneof![Just(0.0), 5.0f64..25.0],
        gear_right in any::<bool>(),
        hob_right in any::<bool>(),
    ) {
        let machine = if fanuc { "H02" } else { "H01" };
        let base = said_of(&class_job(class, machine, teeth, helix, gear_right, hob_right));
        let mirror = said_of(&class_job(class, machine, teeth, helix, !gear_right, !hob_right));
        assert_mirrored(&base, &mirror)?;
    }
}

/// The patent's printed ΔH′ (factor cos γ − tan γ·sin γ, no hob length):
/// the bug put back.
fn patent_delta_h(blank_od: f64, hob_od: f64, depth: f64, gamma_deg: f64) -> f64 {
    let (big_r, r) = (blank_od / 2.0, hob_od / 2.0);
    let l = big_r + r - depth;
    let g = gamma_deg.abs().to_radians();
    (0..=20_000)
        .map(|i| (l - big_r) + (r - (l - big_r)) * f64::from(i) / 20_000.0)
        .map(|x| {
            let s = (r * r - x * x).max(0.0).sqrt();
            let w = (big_r * big_r - (l - x) * (l - x)).max(0.0).sqrt();
            s * (g.cos() - g.tan() * g.sin()) + w * g.tan()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The model with its first cut's approach moved to the height `over` beyond
/// the face it approaches (B and C, and X along a cone).
fn approach_at(model: &MachiningModel, over: f64) -> MachiningModel {
    let mut m = model.clone();
    let gear = &m.plan.gear;
    let (bottom, top) = (
        gear.fixture_height_mm,
        gear.fixture_height_mm + gear.face_width_mm,
    );
    let x_per_z = m.model.cone.as_ref().map_or(0.0, |c| c.x_per_z);
    let cut = &mut m.model.cuts[0];
    let down = cut.positions.C.z_mm > cut.positions.D.z_mm;
    let z = if down { top + over } else { bottom - over };
    let d = cut.positions.D;
    let x = d.x_mm + (z - d.z_mm) * x_per_z;
    let retract = cut.positions.B.x_mm - cut.positions.C.x_mm;
    cut.positions.C = gearcam_proto::Position { x_mm: x, z_mm: z };
    cut.positions.B = gearcam_proto::Position {
        x_mm: x + retract,
        z_mm: z,
    };
    cut.moves[0].x_mm = Some(x);
    m.model.positions = cut.positions;
    m
}

fn findings(model: &MachiningModel) -> Vec<(String, String)> {
    let program = Templates::builtin().instantiate(model).unwrap();
    program
        .path_check
        .findings
        .iter()
        .map(|f| (f.rule.to_string(), f.message.clone()))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]

    /// The swept hob solid catches the patent's ΔH′ whenever it would bring
    /// the hob into the blank (the old formula plus the safety distance below
    /// the hob's true reach), and passes the corrected program.
    #[test]
    fn the_independent_clearance_check_catches_the_patent_formula(
        (fanuc, teeth, helix, gear_right, hob_right, climb) in setup(),
    ) {
        let machine = if fanuc { "H02" } else { "H01" };
        let m = model_of(&job(machine, teeth, helix, gear_right, hob_right, climb)).unwrap();
        prop_assert!(findings(&m).is_empty());
        let k = &m.model;
        let old = patent_delta_h(k.blank_od_mm, m.plan.hob.od_mm, k.depth_mm, k.swivel_deg);
        let patched = approach_at(&m, old + k.safety_mm);
        let found = findings(&patched);
        if old + k.safety_mm < k.clearance_mm - 0.05 {
            prop_assert!(
                found.iter().any(|(rule, _)| rule == "HOB_CLEARANCE"),
                "old {old} + {} against {}: {found:?}", k.safety_mm, k.clearance_mm
            );
        }
    }
}

#[test]
fn delta_h_prime_too_small() {
    // The helical climb example (η 22.37°): the patent's ΔH′ lets the rapid
    // infeed enter the blank by several mm; the program the model writes now
    // is clean.
    let m = model_of(&example("helical_climb_840d.toml")).unwrap();
    assert!(findings(&m).is_empty());
    let k = &m.model;
    let old = patent_delta_h(k.blank_od_mm, m.plan.hob.od_mm, k.depth_mm, k.swivel_deg);
    let found = findings(&approach_at(&m, old + k.safety_mm));
    let clearance: Vec<_> = found
        .iter()
        .filter(|(rule, _)| rule == "HOB_CLEARANCE")
        .collect();
    assert_eq!(clearance.len(), 1, "{found:#?}");
    assert!(clearance[0].1.contains("into the blank"), "{found:#?}");
    eprintln!("patent ΔH′ {old:.3} mm: {}", clearance[0].1);
}

#[test]
fn conical_clearance_taken_at_the_large_end() {
    // The conical example approaches its small (upper) end. Before, the
    // clearance was the large end's and X followed the cone line beyond the
    // face, so at the approach height the hob stood deeper than the cut
    // against the small end: the rapid infeed overlapped the blank's edge
    // (about 1.4 mm). Now the clearance is the small end's, at the depth
    // the hob stands where its cone line ends beyond that face.
    let m = model_of(&example("conical_840d.toml")).unwrap();
    assert!(findings(&m).is_empty());
    let k = &m.model;
    let cone = k.cone.as_ref().unwrap();
    let large_end = gearcam_model::hobbing::Clearance {
        blank_od_mm: k.blank_od_mm,
        hob_od_mm: m.plan.hob.od_mm,
        depth_mm: k.depth_mm,
        swivel_deg: k.swivel_deg,
        hob_length_mm: m.plan.hob.length_mm,
    }
    .solve()
    .clearance_mm;
    let gear = &m.plan.gear;
    let (bottom, top) = (
        gear.fixture_height_mm,
        gear.fixture_height_mm + gear.face_width_mm,
    );
    // The old approach: large-end ΔH′ above the top face, X on the cone line.
    let z = top + large_end + k.safety_mm;
    let x = cone.x_large_mm + (z - bottom) * cone.x_per_z;
    let mut old = m.clone();
    let cut = &mut old.model.cuts[0];
    let retract = cut.positions.B.x_mm - cut.positions.C.x_mm;
    cut.positions.C = gearcam_proto::Position { x_mm: x, z_mm: z };
    cut.positions.B = gearcam_proto::Position {
        x_mm: x + retract,
        z_mm: z,
    };
    cut.moves[0].x_mm = Some(x);
    old.model.positions = cut.positions;
    let found = findings(&old);
    let hit = found
        .iter()
        .find(|(rule, _)| rule == "HOB_CLEARANCE")
        .unwrap_or_else(|| panic!("{found:#?}"));
    assert!(hit.1.contains("into the blank"), "{}", hit.1);
    eprintln!("old conical approach: {}", hit.1);
}

#[test]
fn multi_cut_840d_resynchronisation_without_one_reference() {
    // Before: cut 1 coupled with plain EGON, cut 2 re-synchronised to
    // position 0 after EGOFS: new gaps. Now: one EGONSYNE, stay coupled.
    let m = model_of(&example("multi_cut_shift_840d.toml")).unwrap();
    let text = Templates::builtin().render(&m).unwrap().text;
    assert_eq!(text.matches("EGONSYNE(").count(), 1, "{text}");
    assert!(!text.contains("EGON("), "{text}");
    assert!(!text.contains("EGOFS(C) ; GEARBOX OFF FOR"), "{text}");
    let sync = text.lines().find(|l| l.contains("EGONSYNE(")).unwrap();
    let (number, call) = sync.split_once(' ').unwrap();
    let call = call.split(" ;").next().unwrap();
    let plain = call
        .replace("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,", "EGON(C,\"FINE\",B,")
        .replace(",Y,0,", ",Y,");
    let second_cut = text
        .lines()
        .find(|l| l.contains("OUT OF THE GAPS"))
        .unwrap();
    let old = text
        .replace(sync, &format!("{number} {plain}"))
        .replace(second_cut, &format!("{second_cut}\nN1 EGOFS(C)\nN2 {call}"));
    let (check, _) = nc::check(&old, &m);
    let hits: Vec<_> = check
        .findings
        .iter()
        .filter(|f| f.rule == "COUPLING_RATIO" && f.message.contains("new gaps"))
        .collect();
    assert_eq!(hits.len(), 1, "{:#?}\n{old}", check.findings);
    assert!(
        hits[0].message.contains("plain EGON"),
        "{}",
        hits[0].message
    );
}

#[test]
fn fanuc_g_code_system() {
    // H02 is an M-series control: G90 absolute, G94 feed per minute. The old
    // programs wrote `G01 G90 G98`, which a system-A control reads as a
    // turning cycle and system B/C and M as a return level.
    let m = model_of(&on_machine(&example("spur_840d.toml"), "H02")).unwrap();
    assert_eq!(m.plan.machine.gcode_system.as_str(), "fanuc_m");
    let text = Templates::builtin().render(&m).unwrap().text;
    assert!(text.contains("G01 G90 G94 Z"), "{text}");
    assert!(!text.contains("G98"), "{text}");
    let old = text.replace("G01 G90 G94 Z", "G01 G90 G98 Z");
    let (check, _) = nc::check(&old, &m);
    assert!(
        check.findings.iter().any(
            |f| f.rule == "SETUP" && f.message.contains("G98 is the canned-cycle return level")
        ),
        "{:#?}",
        check.findings
    );
    // The same program on a system-A control: G90 and G94 mean other things.
    let mut system_a = m.clone();
    system_a.plan.machine.gcode_system = gearcam_proto::GCodeSystem::FanucTA;
    let (check, _) = nc::check(&text, &system_a);
    assert!(
        check.findings.iter().any(|f| f.rule == "SETUP"),
        "{:#?}",
        check.findings
    );
}

#[test]
fn nothing_keeps_the_hob_off_the_table_and_fixture() {
    // The old spur example stood on a 50 mm fixture: at D the hob reached
    // about 16 mm below the table plane. The model refuses it naming the field.
    let low =
        example("spur_840d.toml").replace("fixture_height_mm = 100.0", "fixture_height_mm = 50.0");
    let errors = model_of(&low).unwrap_err();
    let e = errors
        .iter()
        .find(|e| e.code == "ENVELOPE_COLLISION")
        .unwrap_or_else(|| panic!("{errors:#?}"));
    assert_eq!(e.field, "gear.fixture_height_mm");
    assert!(e.expected.starts_with("≥ 66.3"), "{}", e.expected);
    assert_eq!(e.got, "50 mm");
    // The path check sees it on its own: the good program lowered by 50 mm
    // (model and program alike) takes the hob into the table.
    let m = model_of(&example("spur_840d.toml")).unwrap();
    let mut lowered = m.clone();
    lowered.plan.gear.fixture_height_mm -= 50.0;
    for c in &mut lowered.model.cuts {
        for p in [
            &mut c.positions.B,
            &mut c.positions.C,
            &mut c.positions.D,
            &mut c.positions.E,
        ] {
            p.z_mm -= 50.0;
        }
        for mv in &mut c.moves {
            if let Some(z) = &mut mv.z_mm {
                *z -= 50.0;
            }
        }
    }
    lowered.model.positions = lowered.model.cuts[0].positions;
    let found = findings(&lowered);
    assert!(
        found
            .iter()
            .any(|(rule, msg)| rule == "ENVELOPE" && msg.contains("into the table")),
        "{found:#?}"
    );
    // A fixture as wide as the gear's root is cut by the hob's run-out.
    let mut wide = m.clone();
    wide.plan.gear.fixture_diameter_mm = Some(70.0);
    let found = findings(&wide);
    assert!(
        found
            .iter()
            .any(|(rule, msg)| rule == "ENVELOPE" && msg.contains("into the fixture")),
        "{found:#?}"
    );
}

#[test]
fn coolant_and_chip_conveyor_stay_on_during_the_hob_change() {
    let m = model_of(&example("multi_gear_840d.toml")).unwrap();
    let text = Templates::builtin().render(&m).unwrap().text;
    let lines: Vec<&str> = text.lines().collect();
    let stop = lines.iter().position(|l| l.contains(" M0 ")).unwrap();
    let before = &lines[..stop];
    let off = before.iter().rposition(|l| l.contains(" M9 ")).unwrap();
    let on = before.iter().rposition(|l| l.contains(" M7 ")).unwrap();
    assert!(off > on, "coolant off before the stop:\n{text}");
    // Put the old program back: the coolant-off block before M0 removed.
    let old = text.replace(lines[off], "");
    let (check, _) = nc::check(&old, &m);
    assert!(
        check
            .findings
            .iter()
            .any(|f| f.rule == "MCODE_PAIR" && f.message.contains("M0 stops")),
        "{:#?}",
        check.findings
    );
}

#[test]
fn no_work_offset_unit_or_radius_mode_is_programmed() {
    for machine in ["H01", "H02"] {
        let m = model_of(&on_machine(&example("spur_840d.toml"), machine)).unwrap();
        let text = Templates::builtin().render(&m).unwrap().text;
        let (metric, offset) = if machine == "H01" {
            ("G71 G90 G94 DIAMOF", " G54 ")
        } else {
            (" G21 ", " G54 ")
        };
        assert!(text.contains(metric) && text.contains(offset), "{text}");
        // The old programs had none of them.
        let old: String = text
            .lines()
            .filter(|l| !l.contains(metric) && !l.contains(offset))
            .map(|l| format!("{l}\n"))
            .collect();
        let (check, _) = nc::check(&old, &m);
        assert!(
            check.findings.iter().any(|f| f.rule == "SETUP"),
            "{machine}: {:#?}",
            check.findings
        );
    }
}

#[test]
fn the_first_block_moves_x_z_and_a_together() {
    // From an unknown position: retract radially, rise, swivel, then approach.
    for machine in ["H01", "H02"] {
        let m = model_of(&on_machine(&example("helical_840d.toml"), machine)).unwrap();
        let text = Templates::builtin().render(&m).unwrap().text;
        let moves: Vec<&str> = text
            .lines()
            .filter(|l| l.contains(" G0 ") || l.contains(" G00 "))
            .take(5)
            .collect();
        let axes = |l: &str| -> String {
            l.split(';')
                .next()
                .unwrap()
                .split('(')
                .next()
                .unwrap()
                .split_whitespace()
                .filter_map(|w| w.chars().next().filter(|c| "XZA".contains(*c)))
                .collect()
        };
        let order: Vec<String> = moves.iter().map(|l| axes(l)).collect();
        assert_eq!(order, ["X", "Z", "A", "Z", "X"], "{machine}: {moves:#?}");
    }
}

#[test]
fn a_shift_comment_names_a_position_never_reached() {
    let m = model_of(&example("multi_cut_shift_840d.toml")).unwrap();
    let shift = m.model.shift.clone().unwrap();
    let last = shift.start_mm
        + shift.step_mm.copysign(shift.end_mm - shift.start_mm) * f64::from(shift.positions - 1);
    let text = Templates::builtin().render(&m).unwrap().text;
    let comment = text.lines().find(|l| l.contains("POSITIONS FROM")).unwrap();
    let to: f64 = comment
        .split(" TO ")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((to - last).abs() < 5e-4, "{comment}: last position {last}");
}

#[test]
fn parameters_used_as_if_free() {
    // R1–R26 and #501–#528 were written whatever the machine used them for.
    // The profile names the block it leaves free; the programs use it, and
    // the path check refuses a parameter outside it.
    for (machine, letter) in [("H01", "R"), ("H02", "#")] {
        let m = model_of(&on_machine(&example("multi_cut_shift_840d.toml"), machine)).unwrap();
        let text = Templates::builtin().render(&m).unwrap().text;
        let (_, trace) = nc::check(&text, &m);
        let mut moved = m.clone();
        moved.plan.machine.parameters.r_first = 100;
        moved.plan.machine.parameters.macro_first = 700;
        let relocated = Templates::builtin()
            .render(&moved)
            .unwrap_or_else(|e| panic!("{machine}: {e:#?}"));
        let (first, counter) = if letter == "R" {
            ("R100=", "R124")
        } else {
            ("#700=", "#724")
        };
        assert!(relocated.text.contains(first), "{}", relocated.text);
        assert!(relocated.text.contains(counter), "{}", relocated.text);
        let old_counter = if letter == "R" { "R25" } else { "#525" };
        assert!(!relocated.text.contains(old_counter), "{}", relocated.text);
        // The same shift positions, computed in the other parameters.
        let (check, moved_trace) = nc::check(&relocated.text, &moved);
        assert!(check.ok, "{:#?}", check.findings);
        let ys = |t: &nc::Trace| t.moves.iter().map(|m| m.y_mm).collect::<Vec<_>>();
        assert_eq!(ys(&moved_trace), ys(&trace));
        // The original program on the moved machine writes outside the block.
        let (check, _) = nc::check(&text, &moved);
        assert!(
            check
                .findings
                .iter()
                .any(|f| f.rule == "SETUP" && f.message.contains("leaves free for gearcam")),
            "{machine}: {:#?}",
            check.findings
        );
    }
    // A block that does not fit is refused with the field.
    let m = model_of(&example("spur_840d.toml")).unwrap();
    let mut plan = m.plan.clone();
    plan.machine.parameters.r_first = 990;
    let errors = gearcam_model::compute(&plan).unwrap_err();
    assert!(
        errors
            .iter()
            .any(|e| e.field == "machine.parameters.r_first" && e.expected == "0 to 971"),
        "{errors:#?}"
    );
}

#[test]
fn the_swept_solid_sees_every_units_blank_at_its_own_height() {
    // A multi-gear part: the second unit's approach moved down to the middle
    // of its own face is a rapid into its blank. (The first version of the
    // check put the unit's blank at its offset twice, too high.)
    let m = model_of(&example("multi_gear_840d.toml")).unwrap();
    assert!(findings(&m).is_empty());
    let mut bad = m.clone();
    let unit = &mut bad.model.units[1];
    let middle = unit.gear.fixture_height_mm + unit.gear.face_width_mm / 2.0;
    let cut = &mut unit.model.cuts[0];
    cut.positions.B.z_mm = middle;
    cut.positions.C.z_mm = middle;
    let found = findings(&bad);
    assert!(
        found
            .iter()
            .any(|(rule, msg)| rule == "HOB_CLEARANCE" && msg.contains("the blank of unit 2")),
        "{found:#?}"
    );
}
