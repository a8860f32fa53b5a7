//! Die jobs made end to end: the program written, read back, replayed as
//! the control runs it and measured against the theoretical outline.

mod common;

use common::molybdenum;
use gearcam_proto::{DiePart, DieSpec, WireProgram};
use gearcam_wire::programs::make;

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
