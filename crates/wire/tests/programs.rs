//! Die jobs made end to end: the program written, read back, replayed as
//! the control runs it and measured against the theoretical outline.

mod common;

use common::molybdenum;
use gearcam_proto::{DiePart, DieSpec, WireProgram};
use gearcam_wire::programs::{certify, make, write};

fn die(part: DiePart, m: f64, z: u32, x: f64) -> DieSpec {
    let mut d = DieSpec::new(part, m, z, 20.0, "Cr12MoV");
    d.profile_shift = x;
    d
}

/// m2 z20 as punch and die in every form, whole and in quarters: each
/// program read back and replayed as the control runs it holds 1 µm on the
/// flanks and 5 µm on the fillets, closes and goes once round.
#[test]
fn every_form_replays_within_its_tolerances_whole_and_in_quarters() {
    for form in [
        WireProgram::ThreeB,
        WireProgram::FourB,
        WireProgram::IsoWire,
    ] {
        for part in [DiePart::Die, DiePart::Punch] {
            for whole in [true, false] {
                let d = die(part, 2.0, 20, 0.0);
                let made = make(&d, &molybdenum(form, whole), &["TEST".into()], 1234).unwrap();
                let c = &made.certificate;
                eprintln!(
                    "m2 z20 {part:?} {} whole {whole}: {} sections, {} blocks, {} bytes, flank {:.3} um, fillet {:.3} um, closure {:.3} um, share {}, {} arcs/flank",
                    form.as_str(), made.layout.sections, c.blocks, c.bytes, c.measure.flank_mm * 1e3, c.measure.fillet_mm * 1e3,
                    c.measure.closure_mm * 1e3, made.fit_share, made.cut.outline.arcs_per_flank
                );
                assert_eq!(made.layout.sections, if whole { 1 } else { 4 });
                assert!(c.measure.flank_mm <= 0.001 && c.measure.fillet_mm <= 0.005);
                assert!(c.measure.closure_mm <= 0.001 && (c.measure.turns + 1.0).abs() < 1e-4);
            }
        }
    }
}

/// The blocks of a 3B or 4B program (a 4B block's 3B part).
fn blocks_of(text: &str) -> Vec<gearcam_wire::threeb::Block> {
    let body: String = text
        .lines()
        .filter(|l| !l.starts_with(';'))
        .map(|l| format!("{l}\n"))
        .collect();
    gearcam_wire::fourb::read(&body)
        .unwrap()
        .into_iter()
        .map(|b| b.block)
        .collect()
}

/// The m2 z20 part in `form`, in quarters.
fn quarter(part: DiePart, form: WireProgram) -> gearcam_wire::programs::Made {
    make(
        &die(part, 2.0, 20, 0.0),
        &molybdenum(form, false),
        &[],
        1234,
    )
    .unwrap()
}

/// Where a turned program leaves the wire, followed block by block from the
/// text alone: every block after the rotation line's section is run from
/// where the fourth turned section ended. The check does not use the
/// crate's run of the blocks: it turns each replayed move itself.
fn end_of_3b(text: &str, start: (f64, f64)) -> (f64, f64) {
    let blocks = blocks_of(text);
    let n = blocks.len();
    // Block 1, blocks 2..n-1 four times turned 90° clockwise each, block n.
    let one = |i: usize, at: (f64, f64)| gearcam_wire::threeb::replay(&blocks[i..=i], at)[0];
    let mut at = one(0, start).to();
    for k in 0..4 {
        for i in 1..n - 1 {
            let s = one(i, (0.0, 0.0));
            let d = common::turn(s.to(), -90.0 * f64::from(k));
            at = (at.0 + d.0, at.1 + d.1);
        }
    }
    let last = one(n - 1, (0.0, 0.0)).to();
    (at.0 + last.0, at.1 + last.1)
}

/// The wire of a quarter program ends at its start hole: the lead-out
/// leaves from where the fourth turned section ends (the tooth on +Y),
/// not from where the written quarter ends (on +X). With the lead-out
/// written from the written quarter's end, the die's ended 30.97 mm from
/// its start hole, at (−21.9, 21.9), and the certificate said closure 0.
#[test]
fn a_turned_program_ends_at_its_start_hole() {
    for form in [WireProgram::ThreeB, WireProgram::FourB] {
        for part in [DiePart::Die, DiePart::Punch] {
            let made = quarter(part, form);
            assert_eq!(made.layout.sections, 4);
            let text = &made.written.text;
            let end = end_of_3b(text, made.layout.start_hole);
            let hole = made.layout.start_hole;
            assert!(
                (end.0 - hole.0).hypot(end.1 - hole.1) < 1e-9,
                "{form:?} {part:?}: ends at {end:?}, start hole {hole:?}"
            );
            // The lead-out is radial: straight back down (die) or up (punch).
            let last = text.lines().rev().nth(1).unwrap();
            let back = if part == DiePart::Die { "GYL4" } else { "GYL2" };
            assert!(last.ends_with(back), "{form:?} {part:?}: {last}");
        }
    }
}

/// The old lead-out put back — written from the written quarter's end —
/// is refused by the certificate, which runs the last block too.
#[test]
fn a_lead_out_from_the_written_sections_end_is_refused() {
    for form in [WireProgram::ThreeB, WireProgram::FourB] {
        for part in [DiePart::Die, DiePart::Punch] {
            let made = quarter(part, form);
            let text = &made.written.text;
            let blocks = blocks_of(text);
            let hole = made.layout.start_hole;
            let written_end = gearcam_wire::threeb::replay(&blocks[..blocks.len() - 1], hole)
                .last()
                .unwrap()
                .to();
            let old = gearcam_wire::threeb::line_to(written_end, hole).to_string();
            let mut lines: Vec<&str> = text.lines().collect();
            let n = lines.len();
            lines[n - 2] = &old;
            let bad = lines.join("\n") + "\n";
            // The control then ends a tooth's radius or more from the hole.
            let e = end_of_3b(&bad, hole);
            assert!((e.0 - hole.0).hypot(e.1 - hole.1) > 20.0, "{e:?}");
            let tol = (0.001, 0.005);
            let p = certify(&bad, form, &made.cut, &made.layout, tol).unwrap_err();
            assert_eq!(p.code, "WIRE_LEAD_OUT", "{form:?} {part:?}: {p:?}");
            assert!(p.got.contains("mm away"), "{}", p.got);
        }
    }
}

/// A lead-in that starts where its line runs through the kept part is
/// refused with the place: a die's start hole off centre at (19, 0), whose
/// line to the tooth on +Y crosses the plate between two teeth, and a
/// punch's start hole inside the punch.
#[test]
fn a_lead_through_the_kept_part_is_refused_with_the_place() {
    let tol = (0.001, 0.005);
    for form in [
        WireProgram::ThreeB,
        WireProgram::FourB,
        WireProgram::IsoWire,
    ] {
        for (part, hole) in [(DiePart::Die, (19.0, 0.0)), (DiePart::Punch, (0.0, 0.0))] {
            let made = quarter(part, form);
            let mut lay = made.layout;
            lay.start_hole = hole;
            let w = write(&made.cut, form, &lay, &[], 1234);
            let p = certify(&w.text, form, &made.cut, &lay, tol).unwrap_err();
            assert_eq!(p.code, "WIRE_LEAD_CROSSES_PART", "{form:?} {part:?}: {p:?}");
            assert!(p.got.contains("lead-in"), "{}", p.got);
            // The place: the start hole for the punch; a point of the plate
            // between the root and tip circles for the die.
            if part == DiePart::Punch {
                assert!(p.got.contains("(0.000, 0.000)"), "{}", p.got);
            } else {
                assert!(p.got.contains("die plate"), "{}", p.got);
            }
            // Where the start hole is, the same program is certified.
            assert!(certify(&made.written.text, form, &made.cut, &made.layout, tol).is_ok());
        }
    }
}

/// An ISO program ends on its lead-out with the compensation off: one
/// whose lead-out keeps G42 on, or stops short of the start hole, is
/// refused.
#[test]
fn an_iso_lead_out_switches_compensation_off_and_returns_to_the_hole() {
    let tol = (0.001, 0.005);
    let made = quarter(DiePart::Die, WireProgram::IsoWire);
    let text = &made.written.text;
    assert!(text.contains("G40 G01 X0.0000 Y0.0000\nM02"));
    let kept_on = text.replace("G40 G01 X0.0000 Y0.0000", "G01 X0.0000 Y0.0000");
    let p = certify(&kept_on, WireProgram::IsoWire, &made.cut, &made.layout, tol).unwrap_err();
    assert_eq!(p.code, "WIRE_REPLAY_FAILED");
    assert!(p.got.contains("G40"), "{}", p.got);
    let short = text.replace("G40 G01 X0.0000 Y0.0000", "G40 G01 X0.0000 Y5.0000");
    let p = certify(&short, WireProgram::IsoWire, &made.cut, &made.layout, tol).unwrap_err();
    assert_eq!(p.code, "WIRE_LEAD_OUT");
    // The last turned call left without its G69.
    let last_g69 = text.rfind("G69\n").unwrap();
    let turned = format!("{}{}", &text[..last_g69], &text[last_g69 + 4..]);
    let p = certify(&turned, WireProgram::IsoWire, &made.cut, &made.layout, tol).unwrap_err();
    assert_eq!(p.code, "WIRE_REPLAY_FAILED");
    assert!(p.got.contains("G68"), "{}", p.got);
    let rapid = text.replace("G40 G01 X0.0000 Y0.0000", "G40 G00 X0.0000 Y0.0000");
    let p = certify(&rapid, WireProgram::IsoWire, &made.cut, &made.layout, tol).unwrap_err();
    assert!(p.got.contains("rapid"), "{}", p.got);
}

/// The ISO certificate sets the outline off as the program tells the
/// control to — its G41/G42 and its D register's value — not as the job
/// would: a program with the wrong register value, or the wrong side, is
/// refused. A G92 after the first move (a control would shift its frame)
/// and a second G68 without its G69 are refused too.
#[test]
fn an_iso_program_is_certified_with_its_own_compensation() {
    let tol = (0.001, 0.005);
    let made = quarter(DiePart::Die, WireProgram::IsoWire);
    let text = &made.written.text;
    let check = |t: &str| certify(t, WireProgram::IsoWire, &made.cut, &made.layout, tol);
    assert!(check(text).is_ok());
    let register = text
        .lines()
        .find(|l| l.starts_with("G10 L12 P1 R"))
        .unwrap();
    let wrong = text.replace(register, "G10 L12 P1 R0.2000");
    assert_eq!(check(&wrong).unwrap_err().code, "WIRE_DEVIATION");
    let side = text.replace("G42 D1 G01", "G41 D1 G01");
    assert!(check(&side).is_err());
    let shifted = text.replacen(
        "G68 X0 Y0 R-90.0000",
        "G92 X1.0000 Y0.0000\nG68 X0 Y0 R-90.0000",
        1,
    );
    let p = check(&shifted).unwrap_err();
    assert!(p.got.contains("G92 after the first move"), "{}", p.got);
    let nested = text.replacen("G69\nG68 X0 Y0 R-90.0000", "G68 X0 Y0 R-90.0000", 1);
    let p = check(&nested).unwrap_err();
    assert!(p.got.contains("G68 while a G68"), "{}", p.got);
}
