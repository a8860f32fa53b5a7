//! The path check (`gearcam_nc`) against real programs: every valid
//! example's 840D program (machine H01) and FANUC program (machine H02) from
//! the shipped templates, hand-written FANUC programs per `DIALECTS.md`, one
//! broken program per rule naming its line, the round trip model → program →
//! trace, and property tests that no text makes the check panic.
//!
//! Models are computed as `gearcam check` computes them: the seeded in-memory
//! knowledge base plans the job, `gearcam_model::compute` models it.

use std::sync::OnceLock;

use gearcam_nc::{self as nc, Trace};
use gearcam_proto::Code;
use gearcam_proto::{Dialect, Kinematics, MachiningModel, MoveKind, PathCheck};
use gearcam_template::format_fixed;
use gearcam_template::Templates;
use proptest::prelude::*;

/// Print rounding of lengths, feeds and speeds (3 decimals) plus 1e-6 mm.
const MM: f64 = 0.0005 + 1e-6;
/// Print rounding of gearbox factors (6 decimals).
const FACTOR: f64 = 0.000_000_5 + 1e-9;

use gearcam_testkit::examples::{example, on_machine, valid_hobbing as valid_examples};

/// The model of a job file, planned for `machine` (H01: 840D, H02: FANUC).
fn model(name: &str, text: &str, machine: &str) -> MachiningModel {
    gearcam_testkit::pipeline::model_of(&on_machine(text, machine))
        .unwrap_or_else(|e| panic!("{name} on {machine}: {e:#?}"))
}

/// The program the shipped templates write for a model.
fn program(name: &str, model: &MachiningModel) -> String {
    Templates::builtin()
        .instantiate(model)
        .unwrap_or_else(|e| panic!("{name}: {e:#?}"))
        .text
}

fn f3(v: f64) -> String {
    format_fixed(v, 3).unwrap()
}

fn f4(v: f64) -> String {
    format_fixed(v, 4).unwrap()
}

fn assert_clean(what: &str, text: &str, check: &PathCheck) {
    assert!(
        check.ok && check.findings.is_empty(),
        "{what}: {:#?}\n{text}",
        check.findings
    );
}

/// The rules and lines of a check's findings.
fn found(check: &PathCheck) -> Vec<(Code, u32)> {
    check.findings.iter().map(|f| (f.rule, f.line)).collect()
}

/// The 1-based line of the first line containing `needle`.
fn line_of(text: &str, needle: &str) -> u32 {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no line with {needle:?} in\n{text}")) as u32
        + 1
}

/// `text` with the first line containing `needle` replaced by `with`.
fn replace_line(text: &str, needle: &str, with: &str) -> String {
    let n = line_of(text, needle) as usize;
    text.lines()
        .enumerate()
        .map(|(i, l)| if i + 1 == n { with } else { l })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `text` without the first line containing `needle`.
fn remove_line(text: &str, needle: &str) -> String {
    let n = line_of(text, needle) as usize;
    text.lines()
        .enumerate()
        .filter(|(i, _)| i + 1 != n)
        .map(|(_, l)| l)
        .collect::<Vec<_>>()
        .join("\n")
}

/// The units' kinematics of a model, in machining order.
fn unit_kins(model: &MachiningModel) -> Vec<&Kinematics> {
    if model.model.units.is_empty() {
        vec![&model.model]
    } else {
        model.model.units.iter().map(|u| &u.model).collect()
    }
}

/// The round trip: the trace gives back the model's cut moves (every target
/// coordinate the model gives, the feeds and dwells), its coupling ratios and
/// factors, hob speeds and swivel angles, within print rounding; the program
/// starts towards the first B and ends at A.
fn assert_round_trip(what: &str, model: &MachiningModel, trace: &Trace) {
    let kins = unit_kins(model);
    let mut next = 0;
    for (u, k) in kins.iter().enumerate() {
        for cut in &k.cuts {
            for (i, m) in cut.moves.iter().enumerate() {
                let matches = |t: &nc::TraceMove| {
                    t.kind == m.kind
                        && m.x_mm.is_none_or(|x| (t.x_mm - x).abs() <= MM)
                        && m.z_mm.is_none_or(|z| (t.z_mm - z).abs() <= MM)
                        && m.y_mm.is_none_or(|y| (t.y_mm - y).abs() <= 2.0 * MM)
                        && match m.kind {
                            MoveKind::Rapid => true,
                            MoveKind::Dwell => {
                                t.dwell_s.is_some_and(|d| (d - m.dwell_s).abs() <= MM)
                            }
                            _ => t
                                .feed_mm_min
                                .is_some_and(|f| (f - m.feed_mm_min).abs() <= MM),
                        }
                };
                let Some(found) = trace.moves[next..].iter().position(matches) else {
                    panic!(
                        "{what}: unit {} cut {} move {i} ({m:?}) is not in the trace after line {}:\n{:#?}",
                        u + 1,
                        cut.number,
                        trace.moves.get(next.max(1) - 1).map_or(0, |t| t.line),
                        &trace.moves[next..]
                    )
                };
                let t = &trace.moves[next + found];
                if m.kind != MoveKind::Rapid {
                    assert!(
                        t.coupled,
                        "{what}: cutting move at line {} uncoupled",
                        t.line
                    );
                }
                next += found + 1;
            }
        }
    }
    // The approach: from wherever the hob stands it retracts radially, rises,
    // swivels, then reaches the first B before the gearbox couples.
    let b = kins[0].cuts[0].positions.B;
    let approach: Vec<_> = trace.moves.iter().take_while(|t| !t.coupled).collect();
    assert!(
        approach
            .iter()
            .any(|t| (t.x_mm - b.x_mm).abs() <= MM && (t.z_mm - b.z_mm).abs() <= MM),
        "{what}: no move before the coupling ends at B {b:?}: {approach:#?}"
    );
    let last = trace
        .moves
        .iter()
        .rev()
        .find(|m| m.kind != MoveKind::Dwell)
        .unwrap();
    let a = model.model.positions.A;
    assert!(
        (last.x_mm - a.x_mm).abs() <= MM && (last.z_mm - a.z_mm).abs() <= MM,
        "{what}: the program ends at X={} Z={}, not at A",
        last.x_mm,
        last.z_mm
    );

    // Couplings in order: each belongs to the current unit or the next.
    assert!(
        trace.couplings.len() >= kins.len(),
        "{what}: {:?}",
        trace.couplings
    );
    let mut u = 0;
    for c in &trace.couplings {
        let fits = |k: &Kinematics| {
            let f = &k.factors;
            // The ratio with its sign: the hob's hand in the machine's
            // directions (FANUC L and T are the unreduced starts and teeth).
            i128::from(c.num) * i128::from(f.c_per_b.den)
                == i128::from(c.den) * i128::from(f.c_per_b.num)
                && c.c_per_y_deg_per_mm
                    .is_none_or(|y| (y - f.c_per_y_deg_per_mm).abs() <= FACTOR)
                && match c.c_per_z_deg_per_mm {
                    // FANUC: 360·sin P/(π·Q·T) from the rounded Q and P.
                    Some(z) => (z - f.c_per_z_deg_per_mm).abs() <= 1e-4 * z.abs().max(1e-3),
                    None => f.c_per_z_deg_per_mm == 0.0,
                }
        };
        if !fits(kins[u]) {
            u += 1;
            assert!(
                u < kins.len() && fits(kins[u]),
                "{what}: coupling {c:?} does not fit the model's units"
            );
        }
    }
    assert_eq!(u + 1, kins.len(), "{what}: not every unit coupled");

    // Hob speeds: each S is a unit's speed (FANUC prints whole rpm).
    let rpm_tol = if model.plan.machine.dialect == Dialect::Fanuc {
        0.5 + 1e-9
    } else {
        MM
    };
    for (line, s) in &trace.spindle_rpm {
        assert!(
            kins.iter().any(|k| (k.hob_rpm - s).abs() <= rpm_tol),
            "{what}: S={s} at line {line} is no unit's hob speed"
        );
    }
    assert!(!trace.spindle_rpm.is_empty(), "{what}: no speed");
    for (line, a) in &trace.swivel_deg {
        assert!(
            kins.iter()
                .any(|k| (k.swivel_axis_deg - a).abs() <= 0.00005 + 1e-9),
            "{what}: swivel {a} at line {line} is no unit's"
        );
    }
}

#[test]
fn every_valid_example_passes_on_840d_and_fanuc_and_traces_back_to_its_model() {
    let examples = valid_examples();
    assert!(examples.len() >= 10, "{} examples", examples.len());
    for (name, text) in &examples {
        for (machine, dialect) in [("H01", Dialect::Sinumerik840d), ("H02", Dialect::Fanuc)] {
            let what = format!("{name} on {machine}");
            let m = model(name, text, machine);
            assert_eq!(m.plan.machine.dialect, dialect);
            let program = program(&what, &m);
            let (check, trace) = nc::check(&program, &m);
            assert_clean(&what, &program, &check);
            assert_round_trip(&what, &m, &trace);
        }
    }
}

// ----- hand-written FANUC programs (DIALECTS.md) -----

/// A FANUC program for a one-cut spur or helical job on H02, written by hand
/// after DIALECTS.md with the model's numbers: coupling before the hob starts,
/// radial retract before the axial return to A.
fn fanuc_program(m: &MachiningModel) -> String {
    let k = &m.model;
    let gear = &m.plan.gear;
    let cut = &k.cuts[0];
    let (b, e) = (cut.positions.B, cut.positions.E);
    let a = k.positions.A;
    let mut g81 = format!("G81 T{} L{}", k.factors.c_per_b.den, k.factors.c_per_b.num);
    if k.factors.c_per_z_deg_per_mm != 0.0 {
        let p = gear
            .helix_angle_deg
            .abs()
            .copysign(k.factors.c_per_z_deg_per_mm);
        g81.push_str(&format!(" Q{} P{}", f3(gear.module_mm), f4(p)));
    }
    let mut s = String::new();
    s.push_str("%\nO1001 (SP-1001 HOBBING)\n(GEARCAM HOBBING PROGRAM O1001)\n");
    s.push_str(&format!("(JOB {})\n", m.job_id));
    s.push_str("N5 G21 (METRIC)\nN6 G90 G94 G54 (ABSOLUTE, FEED PER MINUTE, WORK OFFSET)\n");
    s.push_str(&format!(
        "N10 G00 G90 X{} Z{} A{}\n",
        f3(b.x_mm),
        f3(b.z_mm),
        f4(k.swivel_axis_deg)
    ));
    s.push_str("N20 M10 (FIXTURE CLAMP)\nN30 M08 (COOLANT ON)\nN40 M24 (CHIP CONVEYOR ON)\n");
    s.push_str(&format!(
        "#501={} (NORMAL MODULE MN, MM)\n#502={} (NUMBER OF TEETH Z)\n",
        f3(gear.module_mm),
        gear.teeth
    ));
    s.push_str(&format!("N50 {g81} (EGB ON)\n"));
    s.push_str(&format!("N60 M03 S{} (HOB ON, RPM)\n", k.hob_rpm.round()));
    let mut n = 70;
    for mv in &cut.moves {
        let mut words = String::new();
        if let Some(x) = mv.x_mm {
            words.push_str(&format!(" X{}", f3(x)));
        }
        if let Some(z) = mv.z_mm {
            words.push_str(&format!(" Z{}", f3(z)));
        }
        let block = match mv.kind {
            MoveKind::Rapid => format!("G00 G90{words}"),
            MoveKind::Feed => format!("G01 G90 G94{words} F{}", f3(mv.feed_mm_min)),
            other => panic!("the fixture writes rapid and feed moves, not {other:?}"),
        };
        s.push_str(&format!(
            "N{n} {block} ({})\n",
            mv.note.replace(['(', ')'], "")
        ));
        n += 10;
    }
    assert!((e.x_mm - cut.moves.last().unwrap().x_mm.unwrap()).abs() < 1e-9);
    s.push_str(&format!("N{n} M05 (HOB OFF)\n"));
    s.push_str(&format!(
        "N{} G00 G90 X{} (RADIAL RETRACT FIRST)\nN{} G00 G90 Z{}\n",
        n + 10,
        f3(a.x_mm),
        n + 20,
        f3(a.z_mm)
    ));
    s.push_str(&format!(
        "N{} G80 (EGB OFF)\nN{} M09 (COOLANT OFF)\nN{} M25 (CHIP CONVEYOR OFF)\nN{} M11 (FIXTURE UNCLAMP)\nN{} M30 (END OF PROGRAM)\n%\n",
        n + 30,
        n + 40,
        n + 50,
        n + 60,
        n + 70
    ));
    s
}

fn fanuc_model(example_name: &str) -> MachiningModel {
    model(example_name, &example(example_name), "H02")
}

#[test]
fn hand_written_fanuc_spur_and_helical_programs_pass_and_trace_back() {
    for name in ["spur_840d.toml", "helical_840d.toml"] {
        let m = fanuc_model(name);
        assert_eq!(m.plan.machine.mcodes.program_end, 30);
        let text = fanuc_program(&m);
        let (check, trace) = nc::check(&text, &m);
        assert_clean(name, &text, &check);
        assert_round_trip(name, &m, &trace);
        let g81 = &trace.couplings[0];
        assert_eq!((g81.num, g81.den), (1, 25));
        if name.starts_with("helical") {
            // 360·sin 15°/(π·3·25) = 0.395446 °/mm (docs/reference.md#worked-self-check).
            let z = g81.c_per_z_deg_per_mm.expect("helical compensation");
            assert!((z - 0.395446).abs() < 1e-6, "{z}");
            assert!(text.contains("G81 T25 L1 Q3.0 P15.0"), "{text}");
        } else {
            assert_eq!(g81.c_per_z_deg_per_mm, None);
        }
        assert_eq!(
            trace.spindle_rpm,
            vec![(line_of(&text, "M03 S"), m.model.hob_rpm.round())]
        );
    }
}

/// The tangential worm wheel on H02, by hand: the hob shifted to the start
/// before coupling, the tangential feed as the incremental shift move with its
/// C correction.
fn fanuc_tangential(m: &MachiningModel) -> String {
    let k = &m.model;
    let w = k.worm.as_ref().expect("worm wheel");
    let cut = &k.cuts[0];
    let (b, c, e) = (cut.positions.B, cut.positions.C, cut.positions.E);
    let a = k.positions.A;
    let dy: f64 = f3(w.end_y_mm - w.start_y_mm).parse().unwrap();
    let correction = k.factors.c_per_y_deg_per_mm * dy;
    format!(
        "%\nO4002 (WW-4002 HOBBING)\n\
         N5 G21\n\
         N6 G90 G94 G54\n\
         N10 G00 G90 X{} Z{} A{}\n\
         N20 G00 G90 Y{} (HOB SHIFTED TO THE TANGENTIAL START)\n\
         N30 G81 T{} L{} (EGB ON)\n\
         N40 M03 S{} (HOB ON, RPM)\n\
         N50 G00 G90 X{} (TO THE FINAL CENTRE DISTANCE)\n\
         N60 G01 G91 Y{} C{} F{} (TANGENTIAL FEED)\n\
         N70 G00 G90 X{} (RETRACT)\n\
         N80 M05 (HOB OFF)\n\
         N90 G00 G90 X{}\n\
         N100 G00 G90 Z{}\n\
         N110 G80 (EGB OFF)\n\
         N120 M30 (END OF PROGRAM)\n%\n",
        f3(b.x_mm),
        f3(b.z_mm),
        f4(k.swivel_axis_deg),
        f3(w.start_y_mm),
        k.factors.c_per_b.den,
        k.factors.c_per_b.num,
        k.hob_rpm.round(),
        f3(c.x_mm),
        f3(dy),
        f4(correction),
        f3(w.tangential_feed_mm_min),
        f3(e.x_mm),
        f3(a.x_mm),
        f3(a.z_mm),
    )
}

#[test]
fn fanuc_shift_move_carries_its_c_correction() {
    let m = fanuc_model("worm_wheel_tangential_840d.toml");
    let text = fanuc_tangential(&m);
    let (check, trace) = nc::check(&text, &m);
    assert_clean("tangential", &text, &check);
    assert_round_trip("tangential", &m, &trace);
    let shift = trace
        .moves
        .iter()
        .find(|t| t.c_correction_deg.is_some())
        .expect("the shift move");
    assert!(shift.coupled);
    assert_eq!(shift.line, line_of(&text, "G91"));

    // A C correction 1° off.
    let line = text.lines().find(|l| l.contains("G91")).unwrap();
    let c = line.split(' ').find(|w| w.starts_with('C')).unwrap();
    let wrong: f64 = c[1..].parse::<f64>().unwrap() + 1.0;
    let bad = replace_line(&text, "G91", &line.replace(c, &format!("C{}", f4(wrong))));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::COUPLING_RATIO, line_of(&bad, "G91"))]
    );

    // The shift move before the coupling.
    let bad = remove_line(&text, "G81");
    let (check, _) = nc::check(&bad, &m);
    assert!(
        found(&check).contains(&(Code::COUPLING_RATIO, line_of(&bad, "G91"))),
        "{:#?}",
        check.findings
    );

    // G90 forgotten after the incremental move: the retract would be incremental.
    let bad = replace_line(
        &text,
        "(RETRACT)",
        &format!("N70 G00 X{}", f3(m.model.cuts[0].positions.E.x_mm)),
    );
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(check.findings[0].rule, Code::PARSE);
    assert_eq!(check.findings[0].line, line_of(&bad, "N70 G00"));
    assert!(
        check.findings[0].message.contains("G91 of line"),
        "{}",
        check.findings[0].message
    );
}

// ----- one broken program per rule -----

fn spur_840d() -> (MachiningModel, String) {
    let m = model("spur_840d.toml", &example("spur_840d.toml"), "H01");
    let text = program("spur_840d.toml", &m);
    (m, text)
}

/// The 840D spur program's first block with `needle`, as written.
fn block_with<'a>(text: &'a str, needle: &str) -> &'a str {
    text.lines()
        .find(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("no {needle:?} in\n{text}"))
}

#[test]
fn a_cut_before_the_gearbox_is_coupled_is_depth_uncoupled() {
    let (m, text) = spur_840d();
    // Move EGDEF and EGONSYNE after the axial feed C → D.
    let egdef = block_with(&text, "EGDEF(").to_string();
    let egon = block_with(&text, "EGONSYNE(").to_string();
    let feed = block_with(&text, "G1 G90 G94").to_string();
    let bad = remove_line(&remove_line(&text, "EGDEF("), "EGONSYNE(");
    let bad = replace_line(&bad, &feed, &format!("{feed}\n{egdef}\n{egon}"));
    let (check, _) = nc::check(&bad, &m);
    let line = line_of(&bad, &feed);
    assert_eq!(found(&check), vec![(Code::DEPTH_UNCOUPLED, line)], "{bad}");
    let msg = &check.findings[0].message;
    assert!(
        msg.starts_with(&format!("line {line}: feed move from X=73.75 Z=154.278 to X=73.75 Z=75.722 enters the contact zone (X < 80.5, 75.722 < Z < 154.278) while the gearbox is not coupled")),
        "{msg}"
    );

    // The hob stopped instead: M3 removed.
    let bad = remove_line(&text, "M3 S=");
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::DEPTH_UNCOUPLED, line_of(&bad, &feed))]
    );
    assert!(check.findings[0]
        .message
        .ends_with("while the hob is not turning"));
}

#[test]
fn a_rapid_into_the_blank_breaks_the_clearance() {
    let (m, text) = spur_840d();
    let infeed = block_with(&text, "G0 G90 X=73.75");
    let number = infeed.split(' ').next().unwrap();
    let bad = replace_line(&text, infeed, &format!("{number} G0 G90 X=75.0 Z=120.0"));
    let (check, _) = nc::check(&bad, &m);
    let line = line_of(&bad, "X=75.0 Z=120.0");
    // The zone of the model's clearance and the swept hob solid both see it.
    assert_eq!(
        found(&check),
        vec![(Code::RAPID_CLEARANCE, line), (Code::HOB_CLEARANCE, line)],
        "{bad}"
    );
    assert_eq!(
        check.findings[0].message,
        format!("line {line}: rapid move from X=173.75 Z=154.278 to X=75.0 Z=120.0 passes through the blank zone (X < 80.5, 75.722 < Z < 154.278)")
    );

    // The diagonal return from E to A the first 840D template wrote: X is
    // below R + r while Z climbs into the band, with the hob stopped.
    let back = block_with(&text, "RADIAL RETRACT FIRST: THE HOB LEAVES");
    let number = back.split(' ').next().unwrap();
    let back_z = text
        .lines()
        .rev()
        .find(|l| l.contains("G0 G90 Z=350.0"))
        .unwrap();
    let bad = remove_line(
        &replace_line(&text, back, &format!("{number} G0 X=300.0 Z=350.0")),
        back_z,
    );
    let (check, _) = nc::check(&bad, &m);
    let line = line_of(&bad, "G0 X=300.0 Z=350.0");
    assert_eq!(
        found(&check),
        vec![(Code::RAPID_CLEARANCE, line), (Code::DEPTH_UNCOUPLED, line)],
        "{:#?}",
        check.findings
    );
}

#[test]
fn travel_and_swivel_beyond_the_machine_are_travel_limits() {
    let (m, text) = spur_840d();
    let first = block_with(&text, "G0 G90 X=173.75");
    let bad = replace_line(&text, first, &first.replace("X=173.75", "X=450.0"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::TRAVEL_LIMIT, line_of(&bad, "X=450.0"))]
    );
    assert!(check.findings[0]
        .message
        .contains("X=450.0 is outside the machine's travel 0.0 to 400.0 mm"));

    // A swivel beyond the head's range; tilted that far the hob also
    // reaches the blank on the approach, which the swept solid reports.
    let swivel = block_with(&text, "G0 G90 A=2.3715");
    let bad = replace_line(&text, swivel, &swivel.replace("A=2.3715", "A=-50.0"));
    let (check, _) = nc::check(&bad, &m);
    let line = line_of(&bad, "A=-50.0");
    assert!(
        found(&check).contains(&(Code::TRAVEL_LIMIT, line)),
        "{:#?}",
        check.findings
    );
    assert!(found(&check)
        .iter()
        .all(|(rule, l)| *rule != Code::TRAVEL_LIMIT || *l == line));
}

#[test]
fn hob_and_table_speeds_above_the_machine_are_speed_limits() {
    let (m, text) = spur_840d();
    let on = block_with(&text, "M3 S=");
    let bad = replace_line(&text, on, &on.replace("S=358.099", "S=1600.0"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::SPEED_LIMIT, line_of(&bad, "S=1600.0"))]
    );

    // The same program on a machine whose table turns at most 10 rpm:
    // 358.099·1/25 = 14.3 rpm.
    let mut slow = m.clone();
    slow.plan.machine.limits.max_table_rpm = 10.0;
    let (check, _) = nc::check(&text, &slow);
    assert_eq!(
        found(&check),
        vec![(Code::SPEED_LIMIT, line_of(&text, "M3 S="))]
    );
    assert!(
        check.findings[0].message.contains("S*1/25 = 14.324 rpm"),
        "{}",
        check.findings[0].message
    );

    // FANUC: the printed whole S is what the machine runs.
    let f = fanuc_model("spur_840d.toml");
    let ftext = fanuc_program(&f);
    let mut limit = f.clone();
    limit.plan.machine.limits.max_hob_rpm = f.model.hob_rpm.round() - 1.0;
    let (check, _) = nc::check(&ftext, &limit);
    assert_eq!(
        found(&check),
        vec![(Code::SPEED_LIMIT, line_of(&ftext, "M03 S"))]
    );
}

#[test]
fn feeds_above_the_machine_or_missing_are_feed_limits() {
    let (m, text) = spur_840d();
    let feed = block_with(&text, "G1 G90 G94");
    let f = feed.split(' ').find(|w| w.starts_with("F=")).unwrap();
    let bad = replace_line(&text, feed, &feed.replace(f, "F=2500.0"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::FEED_LIMIT, line_of(&bad, "F=2500.0"))]
    );
    let bad = replace_line(&text, feed, &feed.replace(f, "F=0.0"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::FEED_LIMIT, line_of(&bad, "F=0.0"))]
    );
    let bad = replace_line(&text, feed, &feed.replace(&format!(" {f}"), ""));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::FEED_LIMIT, line_of(&bad, "G1 G90 G94"))]
    );
}

#[test]
fn switched_functions_are_paired() {
    let (m, text) = spur_840d();
    // M7 without M9: still on at the end (the end code's line).
    let bad = remove_line(&text, "M9 ");
    let (check, _) = nc::check(&bad, &m);
    let end = line_of(&bad, "M2 ");
    assert_eq!(found(&check), vec![(Code::MCODE_PAIR, end)]);
    assert!(
        check.findings[0].message.contains(&format!(
            "the coolant is still on at the end of the program (switched on at line {})",
            line_of(&bad, "M7 ")
        )),
        "{}",
        check.findings[0].message
    );
    // Off twice, on twice.
    let m9 = block_with(&text, "M9 ");
    let bad = replace_line(&text, m9, &format!("{m9}\n{m9}"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::MCODE_PAIR, line_of(&bad, "M9 ") + 1)]
    );
    let m7 = block_with(&text, "M7 ");
    let bad = replace_line(&text, m7, &format!("{m7}\n{m7}"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::MCODE_PAIR, line_of(&bad, "M7 ") + 1)]
    );
}

#[test]
fn the_program_ends_at_a_with_the_end_code() {
    let (m, text) = spur_840d();
    // The axial return to A dropped: the last move ends above E.
    let ret = text
        .lines()
        .rev()
        .find(|l| l.contains("G0 G90 Z=350.0"))
        .unwrap();
    let bad = remove_line(&text, ret);
    let (check, _) = nc::check(&bad, &m);
    let last = line_of(&bad, "RADIAL RETRACT FIRST: THE HOB LEAVES");
    assert_eq!(found(&check), vec![(Code::END_AT_A, last)]);
    assert!(check.findings[0]
        .message
        .contains("not at the start point A (X=300.0 Z=350.0)"));
    // No M2.
    let bad = remove_line(&text, "M2 ");
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::END_AT_A, bad.lines().count() as u32)]
    );
    // A block after M2 is never run.
    let bad = format!("{}\nN999 M9\n", text.trim_end());
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(found(&check), vec![(Code::END_AT_A, line_of(&bad, "N999"))]);
}

#[test]
fn couplings_other_than_the_models_are_coupling_ratios() {
    let (m, text) = spur_840d();
    let egon = block_with(&text, "EGONSYNE(");
    let bad = replace_line(&text, egon, &egon.replace("B,0,1,25", "B,0,1,24"));
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::COUPLING_RATIO, line_of(&bad, "B,0,1,24"))]
    );
    assert!(
        check.findings[0]
            .message
            .contains("by 1/24; the model's ratio is 1/25"),
        "{}",
        check.findings[0].message
    );
    // 2/50 is z0/z as a fraction.
    let bad = replace_line(&text, egon, &egon.replace("B,0,1,25", "B,0,2,50"));
    assert!(nc::check(&bad, &m).0.ok);
    // The sign is the hob's hand: −1/25 turns the table the wrong way.
    let bad = replace_line(&text, egon, &egon.replace("B,0,1,25", "B,0,-1,25"));
    assert_eq!(
        found(&nc::check(&bad, &m).0),
        vec![(Code::COUPLING_RATIO, line_of(&bad, "B,0,-1,25"))]
    );

    // Helical: the differential factor of the EGON.
    let h = model("helical_840d.toml", &example("helical_840d.toml"), "H01");
    let htext = program("helical_840d.toml", &h);
    let egon = block_with(&htext, "EGONSYNE(");
    let bad = replace_line(
        &htext,
        egon,
        &egon.replace("Z,0,0.395446,1", "Z,0,0.395456,1"),
    );
    let (check, _) = nc::check(&bad, &h);
    assert_eq!(
        found(&check),
        vec![(Code::COUPLING_RATIO, line_of(&bad, "EGONSYNE("))]
    );

    // FANUC: G81 T24 for a 25-tooth gear; L, Q and P likewise.
    let f = fanuc_model("helical_840d.toml");
    let ftext = fanuc_program(&f);
    for (from, to) in [
        ("T25", "T24"),
        ("L1 ", "L2 "),
        ("L1 ", "L-1 "),
        ("Q3.0", "Q3.5"),
        ("P15.0", "P-15.0"),
        (" Q3.0 P15.0", ""),
        (" P15.0", ""),
    ] {
        let g81 = block_with(&ftext, "G81");
        let bad = replace_line(&ftext, g81, &g81.replace(from, to));
        let (check, _) = nc::check(&bad, &f);
        assert_eq!(
            found(&check),
            vec![(Code::COUPLING_RATIO, line_of(&bad, "G81"))],
            "{from} -> {to}: {:#?}",
            check.findings
        );
    }
}

#[test]
fn garbage_is_a_parse_finding_naming_its_line() {
    let (m, text) = spur_840d();
    let egon = block_with(&text, "EGONSYNE(");
    let bad = replace_line(
        &text,
        egon,
        &format!("{egon}\nN115 GOTOF LABEL1\nWHATEVER 12"),
    );
    let (check, trace) = nc::check(&bad, &m);
    let line = line_of(&bad, "GOTOF");
    assert_eq!(
        found(&check),
        vec![(Code::PARSE, line), (Code::PARSE, line + 1)]
    );
    assert_eq!(trace, Trace::default());
    assert!(nc::parse(Dialect::Sinumerik840d, &bad).is_err());
    // A block continuing a modal CIP without its intermediate point.
    let infeed = block_with(&text, "G0 G90 X=73.75");
    let bad = replace_line(
        &text,
        infeed,
        &format!(
            "{infeed}\nN131 CIP X=73.75 Z=100.0 I1=73.0 K1=102.0 F=28.634\nN132 X=73.75 Z=98.0"
        ),
    );
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(found(&check), vec![(Code::PARSE, line_of(&bad, "N132"))]);
    // The 840D program is not a FANUC program.
    let errors = nc::parse(Dialect::Fanuc, &text).unwrap_err();
    assert_eq!(errors[0].line, 1);
    // A parameter expression dividing by zero.
    let f = fanuc_model("spur_840d.toml");
    let ftext = fanuc_program(&f);
    let bad = replace_line(&ftext, "#502=", "#502=#501/#509 (NUMBER OF TEETH Z)");
    let (check, _) = nc::check(&bad, &f);
    assert_eq!(found(&check), vec![(Code::PARSE, line_of(&bad, "#502="))]);
}

// ----- IF: the shift counter's wrap -----

/// `text` with `line` inserted before the first line containing `needle`.
fn insert_before(text: &str, needle: &str, line: &str) -> String {
    let n = line_of(text, needle) as usize;
    let mut out: Vec<&str> = text.lines().collect();
    out.insert(n - 1, line);
    out.join("\n")
}

#[test]
fn the_shift_counter_starts_again_in_its_if_after_every_position_has_cut() {
    let job = example("multi_cut_shift_840d.toml");
    for (machine, if_line, preset, steps) in [
        ("H01", "IF R25>=", "N1 R25=", "R26=TRUNC"),
        ("H02", "IF [#525 GE", "#525=", "#526=FIX"),
    ] {
        let m = model("multi_cut_shift_840d.toml", &job, machine);
        let text = program("multi_cut_shift_840d.toml", &m);
        let shift = m.model.shift.clone().expect("the example shifts per part");
        assert!(shift.positions >= 2, "{shift:?}");
        // The part counter is kept by the machine between runs; the check
        // starts it at 0. Preset it to see where the hob shifts at part n.
        let y_at_part = |n: u32| {
            let t = insert_before(&text, if_line, &format!("{preset}{n}"));
            let (check, trace) = nc::check(&t, &m);
            assert_clean(machine, &t, &check);
            trace.moves.last().unwrap().y_mm
        };
        let (p, n) = (shift.parts_per_step, shift.positions);
        let start = shift.start_mm;
        assert!((y_at_part(0) - start).abs() < MM, "{machine}");
        assert!((y_at_part(p - 1) - start).abs() < MM, "{machine}");
        assert!(
            (y_at_part(p) - (start + shift.step_mm)).abs() < MM,
            "{machine}"
        );
        // The last position lies within the range (the end is reached when
        // the range is a whole number of steps).
        let last = start + shift.step_mm * f64::from(n - 1);
        assert!(last <= shift.end_mm + MM, "{machine}");
        // (R20 + R22·k from printed values: k print roundings of the step)
        let tol = MM * f64::from(n);
        assert!((y_at_part(p * (n - 1)) - last).abs() < tol, "{machine}");
        // After every position has cut p parts the IF sets the counter back
        // to 0: one more step past the full pass is the start again, where
        // the counter alone (MOD) would be one step on.
        assert!((y_at_part(p * n + p) - start).abs() < MM, "{machine}");
        let without_if = text
            .lines()
            .filter(|l| !l.contains(if_line) && !l.contains("R25=0") && !l.contains("ENDIF"))
            .collect::<Vec<_>>()
            .join("\n");
        let t = insert_before(&without_if, steps, &format!("{preset}{}", p * n + p));
        let (check, trace) = nc::check(&t, &m);
        assert_clean(machine, &t, &check);
        assert!(
            (trace.moves.last().unwrap().y_mm - (start + shift.step_mm)).abs() < MM,
            "{machine}"
        );
    }
}

#[test]
fn an_if_holds_assignments_only_and_is_closed() {
    let m = model(
        "multi_cut_shift_840d.toml",
        &example("multi_cut_shift_840d.toml"),
        "H01",
    );
    let text = program("multi_cut_shift_840d.toml", &m);
    let endif = line_of(&text, "ENDIF");
    // A move inside the IF: the checked path would depend on the counter.
    let bad = insert_before(&text, "ENDIF", "N2 G0 G90 X=300.0");
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::PARSE, endif)],
        "{:#?}",
        check.findings
    );
    assert!(check.findings[0]
        .message
        .contains("only R-parameter assignments"));
    // The ENDIF forgotten.
    let bad = remove_line(&text, "ENDIF");
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(
        found(&check),
        vec![(Code::PARSE, line_of(&bad, "IF R25>="))]
    );
    assert!(check.findings[0].message.contains("not closed by an ENDIF"));
    // An ENDIF too many, and a second ELSE.
    let bad = insert_before(&text, "ENDIF", "ENDIF");
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(found(&check), vec![(Code::PARSE, endif + 1)]);
    let bad = insert_before(&text, "ENDIF", "ELSE\nR25=1\nELSE");
    let (check, _) = nc::check(&bad, &m);
    assert_eq!(found(&check), vec![(Code::PARSE, endif + 2)]);
    // ELSE runs when the condition fails: R25 = 1 here, so part 0 cuts one step on.
    let bad = insert_before(&text, "ENDIF", "ELSE\nR25=R23");
    let (check, trace) = nc::check(&bad, &m);
    assert_clean("else", &bad, &check);
    let shift = m.model.shift.clone().unwrap();
    assert!((trace.moves.last().unwrap().y_mm - (shift.start_mm + shift.step_mm)).abs() < MM);
    // FANUC: IF [..] THEN one assignment; GOTO is outside the subset.
    let f = model(
        "multi_cut_shift_840d.toml",
        &example("multi_cut_shift_840d.toml"),
        "H02",
    );
    let ftext = program("multi_cut_shift_840d.toml", &f);
    let bad = replace_line(&ftext, "IF [#525 GE", "IF [#525 GE #523*#524] GOTO 10");
    let (check, _) = nc::check(&bad, &f);
    assert_eq!(found(&check), vec![(Code::PARSE, line_of(&bad, "GOTO"))]);
    let bad = replace_line(&ftext, "IF [#525 GE", "IF [#525 >= #523] THEN #525=0");
    let (check, _) = nc::check(&bad, &f);
    assert_eq!(
        found(&check),
        vec![(Code::PARSE, line_of(&bad, "IF [#525"))]
    );
}

// ----- no input makes it panic -----

fn spur_models() -> &'static (MachiningModel, String, MachiningModel, String) {
    static MODELS: OnceLock<(MachiningModel, String, MachiningModel, String)> = OnceLock::new();
    MODELS.get_or_init(|| {
        let (m, text) = spur_840d();
        let f = fanuc_model("helical_840d.toml");
        let ftext = fanuc_program(&f);
        (m, text, f, ftext)
    })
}

/// One edit of a program: insert, delete or replace a character, or
/// duplicate, drop or swap lines.
#[derive(Debug, Clone)]
enum Edit {
    Insert(usize, char),
    Delete(usize),
    Replace(usize, char),
    DuplicateLine(usize),
    DropLine(usize),
    SwapLines(usize, usize),
}

fn apply(text: &str, edits: &[Edit]) -> String {
    let mut chars: Vec<char> = text.chars().collect();
    for e in edits {
        let n = chars.len().max(1);
        match *e {
            Edit::Insert(i, c) => chars.insert(i % (chars.len() + 1), c),
            Edit::Delete(i) if !chars.is_empty() => {
                chars.remove(i % n);
            }
            Edit::Replace(i, c) if !chars.is_empty() => chars[i % n] = c,
            Edit::DuplicateLine(i) | Edit::DropLine(i) | Edit::SwapLines(i, _) => {
                let s: String = chars.iter().collect();
                let mut lines: Vec<&str> = s.lines().collect();
                if lines.is_empty() {
                    continue;
                }
                let k = i % lines.len();
                match *e {
                    Edit::DuplicateLine(_) => lines.insert(k, lines[k]),
                    Edit::DropLine(_) => {
                        lines.remove(k);
                    }
                    Edit::SwapLines(_, j) => {
                        let j = j % lines.len();
                        lines.swap(k, j);
                    }
                    _ => {}
                }
                chars = lines.join("\n").chars().collect();
            }
            _ => {}
        }
    }
    chars.into_iter().collect()
}

fn edit() -> impl Strategy<Value = Edit> {
    let ch = prop_oneof![
        any::<char>(),
        prop::sample::select(vec![
            '0', '9', '.', '-', '=', '(', ')', '[', ']', '#', ';', ' ', '\n', 'X', 'Z', 'Y', 'R',
            'G', 'M', 'N', '"', ','
        ])
    ];
    prop_oneof![
        (any::<usize>(), ch.clone()).prop_map(|(i, c)| Edit::Insert(i, c)),
        any::<usize>().prop_map(Edit::Delete),
        (any::<usize>(), ch).prop_map(|(i, c)| Edit::Replace(i, c)),
        any::<usize>().prop_map(Edit::DuplicateLine),
        any::<usize>().prop_map(Edit::DropLine),
        (any::<usize>(), any::<usize>()).prop_map(|(i, j)| Edit::SwapLines(i, j)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn random_text_never_panics(text in "\\PC{0,400}", lines in prop::collection::vec("[ -~]{0,40}", 0..30)) {
        let (m, _, f, _) = spur_models();
        let joined = lines.join("\n");
        for t in [text.as_str(), joined.as_str()] {
            let (check, _) = nc::check(t, m);
            prop_assert_eq!(check.ok, check.findings.is_empty());
            let (check, _) = nc::check(t, f);
            prop_assert_eq!(check.ok, check.findings.is_empty());
            let with_header = format!("%_N_SP_1_MPF\n;$PATH=/_N_MPF_DIR\n{t}");
            let _ = nc::check(&with_header, m);
            let with_header = format!("%\nO0001\n{t}\n%");
            let _ = nc::check(&with_header, f);
        }
    }

    #[test]
    fn mutated_programs_never_panic(edits in prop::collection::vec(edit(), 1..6)) {
        let (m, text, f, ftext) = spur_models();
        for (model, program) in [(m, text), (f, ftext)] {
            let bad = apply(program, &edits);
            let (check, _) = nc::check(&bad, model);
            // Findings come sorted by line.
            prop_assert!(check.findings.windows(2).all(|w| w[0].line <= w[1].line));
            prop_assert_eq!(check.ok, check.findings.is_empty());
        }
    }
}

/// A FANUC crowning arc (`G03 X… Z… R…`) is an arc in X and Z only in the
/// Z–X plane: the program selects it with `G18` in its set-up, and without
/// it the control, which starts in `G17`, would not cut the crown. The
/// check refuses the arc then, naming its line.
#[test]
fn a_fanuc_arc_before_g18_is_a_setup_finding() {
    let m = model("crowned_840d", &example("crowned_840d.toml"), "H02");
    let text = program("crowned_840d", &m);
    let (check, _) = nc::check(&text, &m);
    assert_clean("crowned on H02", &text, &check);
    assert!(text.contains(" G90 G94 G18 "), "{text}");
    let bad = text.replacen(" G90 G94 G18 ", " G90 G94 ", 1);
    let (check, _) = nc::check(&bad, &m);
    let arc = bad
        .lines()
        .position(|l| l.contains(" G03 ") || l.contains(" G02 "))
        .unwrap() as u32
        + 1;
    assert_eq!(found(&check), vec![(Code::SETUP, arc)]);
    assert!(check.findings[0].message.contains("G18"));
}
