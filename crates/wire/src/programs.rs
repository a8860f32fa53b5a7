//! A die job's programs (docs/wire.md#programs): the wire's path written as
//! 3B, or the part's outline as 4B or ISO wire G-code for the control to
//! set off; a quarter or half of the teeth with the control's rotation when
//! the teeth divide by 4 or 2; and the certificate: the program read back,
//! replayed as the control runs it (rotations, the control's own offset for
//! 4B and ISO) and measured against the theoretical outline.
//!
//! The start hole is the opening's centre for a die and a point 5 mm
//! outside the tip circle on +Y for a punch; the lead-in runs from it to the
//! middle of the tooth on +Y, where the contour starts, and the lead-out
//! back.

use gearcam_proto::{DiePart, WireProgram};

use crate::die::{Cut, Problem};
use crate::fourb;
use crate::iso::{self, IsoProgram};
use crate::offset::{offset, Side};
use crate::verify::{measure, Measure, SAMPLES};
use crate::{threeb, Segment};

/// How far outside the tip circle a punch's start hole lies, mm.
pub const PUNCH_START_MM: f64 = 5.0;

/// How the teeth are written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// Sections the control repeats, turning each by 360°/sections
    /// clockwise: 4, 2 or 1.
    pub sections: u32,
    /// Teeth per section.
    pub teeth_per_section: u32,
    /// The start hole, mm.
    pub start_hole: (f64, f64),
}

/// The layout of a cut: a quarter when the teeth divide by 4, a half when
/// by 2, else whole (or whole when asked).
pub fn layout(cut: &Cut, part: DiePart, whole: bool) -> Layout {
    let z = cut.outline.teeth;
    let sections = if whole {
        1
    } else if z % 4 == 0 {
        4
    } else if z % 2 == 0 {
        2
    } else {
        1
    };
    let start_hole = match part {
        DiePart::Die => (0.0, 0.0),
        DiePart::Punch => (0.0, cut.outline.figures.tip_radius_mm + PUNCH_START_MM),
    };
    Layout {
        sections,
        teeth_per_section: z / sections,
        start_hole,
    }
}

/// The first section's share of a closed path of z equal periods.
fn section(path: &[Segment], teeth: u32, layout: &Layout) -> Vec<Segment> {
    let per_tooth = path.len() / teeth as usize;
    path[..per_tooth * layout.teeth_per_section as usize].to_vec()
}

/// A program written.
#[derive(Debug, Clone, PartialEq)]
pub struct Written {
    /// The text.
    pub text: String,
    /// Motion blocks in the text (lead-in and lead-out included).
    pub blocks: u32,
}

/// Writes the program of `cut` in `form` with `header` lines (comments).
/// `number` is an ISO program's `O` number (unused by 3B and 4B).
pub fn write(
    cut: &Cut,
    form: WireProgram,
    layout: &Layout,
    header: &[String],
    number: u32,
) -> Written {
    let teeth = cut.outline.teeth;
    // 3B runs the wire's path; 4B and ISO the outline, set off by the control.
    let contour = match form {
        WireProgram::ThreeB => &cut.path,
        _ => &cut.contour,
    };
    let part = section(contour, teeth, layout);
    let start = contour[0].from();
    if form == WireProgram::IsoWire {
        let blocks = part.len() as u32 + 2;
        let text = iso::program(&IsoProgram {
            number,
            header: header.to_vec(),
            start_hole: layout.start_hole,
            contour: part,
            side: match cut.side {
                Side::Left => iso::Side::Left,
                Side::Right => iso::Side::Right,
            },
            offset_mm: cut.offset_mm,
            repeat: (layout.sections > 1)
                .then(|| (layout.sections, -360.0 / f64::from(layout.sections))),
        });
        return Written { text, blocks };
    }
    let mut segments = vec![Segment::Line {
        from: layout.start_hole,
        to: start,
    }];
    segments.extend(part);
    // The lead-out leaves from where the last section ends: the start.
    segments.push(Segment::Line {
        from: start,
        to: layout.start_hole,
    });
    let mut text = String::new();
    for h in header {
        text.push_str("; ");
        text.push_str(h);
        text.push('\n');
    }
    if layout.sections > 1 {
        text.push_str(&format!(
            "; ROTATE: BLOCK 1, THEN BLOCKS 2-{} {} TIMES TURNED {} DEG CLOCKWISE EACH, THEN BLOCK {}\n",
            segments.len() - 1,
            layout.sections,
            360 / layout.sections,
            segments.len()
        ));
    }
    let start_hole = layout.start_hole;
    text.push_str(&match form {
        WireProgram::FourB => fourb::program_from(start_hole, &segments),
        _ => threeb::program_from(start_hole, &segments),
    });
    Written {
        text,
        blocks: segments.len() as u32,
    }
}

/// The certificate of a program: its replay measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Certificate {
    /// The measure of the replayed wire path.
    pub measure: Measure,
    /// Motion blocks.
    pub blocks: u32,
    /// Bytes.
    pub bytes: u32,
}

fn replay_problem(code: &'static str, expected: String, got: String, message: String) -> Problem {
    Problem {
        code,
        field: "program".into(),
        expected,
        got,
        message,
    }
}

/// The program's text without its comment lines.
fn body(text: &str) -> String {
    text.lines()
        .filter(|l| !l.trim_start().starts_with(';'))
        .map(|l| format!("{l}\n"))
        .collect()
}

/// Reads `text` back, replays it as the control would (sections turned,
/// the outline set off for 4B and ISO) and measures the wire's path against
/// the theoretical outline: a program over its tolerances, not closed, or
/// not once round the part fails.
pub fn certify(
    text: &str,
    form: WireProgram,
    cut: &Cut,
    layout: &Layout,
    tolerances: (f64, f64),
) -> Result<Certificate, Problem> {
    let unreadable = |e: String| {
        replay_problem(
            "WIRE_REPLAY_FAILED",
            "a program the reader follows".into(),
            e,
            "the program cannot be read back".into(),
        )
    };
    let (path, blocks) = match form {
        WireProgram::ThreeB | WireProgram::FourB => {
            let body = body(text);
            let blocks: Vec<threeb::Block> = if form == WireProgram::FourB {
                let b4 = fourb::read(&body)
                    .map_err(|e| unreadable(format!("line {}: {}", e.line, e.message)))?;
                fourb::check(&b4, fourb::Sense::Clockwise)
                    .map_err(|e| unreadable(format!("block {}: {}", e.line, e.message)))?;
                b4.iter().map(|b| b.block).collect()
            } else {
                threeb::read(&body)
                    .map_err(|e| unreadable(format!("line {}: {}", e.line, e.message)))?
            };
            if blocks.len() < 3 {
                return Err(unreadable(format!("{} blocks", blocks.len())));
            }
            let inner = &blocks[1..blocks.len() - 1];
            let lead_in = threeb::replay(&blocks[..1], layout.start_hole);
            let mut at = lead_in[0].to();
            let mut contour = Vec::new();
            for k in 0..layout.sections {
                // Clockwise by 360°/n: counter-clockwise by 4 − 4k/n quarters.
                let quarters = ((4 - 4 * k / layout.sections) % 4) as u8;
                let turned = threeb::rotate_quarter(inner, quarters);
                let part = threeb::replay(&turned, at);
                at = part.last().map_or(at, Segment::to);
                contour.extend(part);
            }
            let path = match form {
                WireProgram::ThreeB => contour,
                _ => offset(&contour, cut.side, cut.offset_mm).map_err(|e| {
                    unreadable(format!(
                        "the control's offset fails at block {}: {e}",
                        e.index + 2
                    ))
                })?,
            };
            (path, blocks.len() as u32)
        }
        WireProgram::IsoWire => {
            let r = iso::replay(text)
                .map_err(|e| unreadable(format!("line {}: {}", e.line, e.message)))?;
            let moves: Vec<&iso::Move> = r.moves.iter().filter(|m| !m.rapid).collect();
            if moves.len() < 3 {
                return Err(unreadable(format!("{} moves", moves.len())));
            }
            // Between the lead-in and the lead-out: the contour, set off as
            // the control's compensation in force says.
            let inner = &moves[1..moves.len() - 1];
            let contour: Vec<Segment> = inner.iter().map(|m| m.segment).collect();
            let (Some(side), Some(d)) = (inner[0].side, inner[0].offset_mm) else {
                return Err(unreadable("the contour runs without compensation".into()));
            };
            let side = match side {
                iso::Side::Left => Side::Left,
                iso::Side::Right => Side::Right,
            };
            let path = offset(&contour, side, d).map_err(|e| {
                unreadable(format!(
                    "the control's offset fails at move {}: {e}",
                    e.index + 2
                ))
            })?;
            // Blocks of the text (a subprogram's once, however often it runs).
            let lines: std::collections::BTreeSet<usize> = r.moves.iter().map(|m| m.line).collect();
            (path, lines.len() as u32)
        }
    };
    let m = measure(&cut.outline, &path, cut.offset_mm, SAMPLES);
    let (flank_tol, fillet_tol) = tolerances;
    if m.flank_mm > flank_tol || m.fillet_mm > fillet_tol {
        return Err(replay_problem(
            "WIRE_DEVIATION",
            format!(
                "the wire within {:.1} µm on the flanks and {:.1} µm on the fillets",
                flank_tol * 1e3,
                fillet_tol * 1e3
            ),
            format!(
                "{:.3} µm on the flanks, {:.3} µm on the fillets",
                m.flank_mm * 1e3,
                m.fillet_mm * 1e3
            ),
            "the replayed program strays from the outline set off by the wire".into(),
        ));
    }
    if m.closure_mm > flank_tol || (m.turns + 1.0).abs() > 0.01 {
        return Err(replay_problem(
            "WIRE_CLOSURE",
            format!(
                "a closed path once round the part (within {:.1} µm)",
                flank_tol * 1e3
            ),
            format!("{:.3} µm apart, {:.4} turns", m.closure_mm * 1e3, -m.turns),
            "the replayed program does not close on itself".into(),
        ));
    }
    Ok(Certificate {
        measure: m,
        blocks,
        bytes: text.len() as u32,
    })
}

/// A die job made: the cut, the program and its certificate.
#[derive(Debug, Clone)]
pub struct Made {
    /// The outline and the wire's path.
    pub cut: Cut,
    /// The layout.
    pub layout: Layout,
    /// The program.
    pub written: Written,
    /// Its certificate.
    pub certificate: Certificate,
    /// The share of the tolerances the fit aimed at.
    pub fit_share: f64,
}

/// The shares of the flank's tolerance `flank_um` the arc fit aims at,
/// tightest last: a program rounds to the control's resolution (a 3B
/// control's µm steps cost up to about 0.45 µm of the path; ISO's 4
/// decimals 0.05 µm at most), so the fit first leaves room for that, and
/// tightens while the replay still strays.
fn shares(form: WireProgram, flank_um: f64) -> Vec<f64> {
    let grid_um = match form {
        WireProgram::IsoWire => 0.03,
        _ => 0.45,
    };
    let first = (1.0 - grid_um / flank_um).clamp(0.35, 0.97);
    [first, first - 0.1, first - 0.2]
        .into_iter()
        .filter(|s| *s >= 0.25)
        .collect()
}

/// Makes a die job: checks, fits, sets off, writes and certifies, fitting
/// tighter while the replayed program strays, and writing every tooth
/// when a rotated section strays even at the tightest fit.
pub fn make(
    die: &gearcam_proto::DieSpec,
    process: &gearcam_proto::WireProcess,
    header: &[String],
    number: u32,
) -> Result<Made, Problem> {
    let tol = (die.flank_tolerance_um / 1e3, die.fillet_tolerance_um / 1e3);
    let form = process.program;
    let mut last = None;
    // The fits, tightest last, made once each.
    let mut cuts: Vec<Cut> = Vec::new();
    // A quarter or half first; when even the tightest fit strays in its
    // rotated replay (each section carries its end's rounding into the
    // next), every tooth.
    for whole in [process.whole, true] {
        for (i, &share) in shares(form, die.flank_tolerance_um).iter().enumerate() {
            if cuts.len() <= i {
                let mut aimed = die.clone();
                aimed.flank_tolerance_um *= share;
                aimed.fillet_tolerance_um *= share;
                cuts.push(crate::die::cut(&aimed, process)?);
            }
            let cut = &cuts[i];
            let lay = layout(cut, die.part, whole);
            if whole && !process.whole && lay.sections == layout(cut, die.part, false).sections {
                // Nothing to fall back to: the first pass wrote every tooth.
                break;
            }
            let written = write(cut, form, &lay, header, number);
            match certify(&written.text, form, cut, &lay, tol) {
                Ok(certificate) => {
                    return Ok(Made {
                        cut: cut.clone(),
                        layout: lay,
                        written,
                        certificate,
                        fit_share: share,
                    })
                }
                Err(p) if p.code == "WIRE_DEVIATION" => last = Some(p),
                Err(p) => return Err(p),
            }
        }
        if process.whole {
            break;
        }
    }
    Err(last.expect("at least one share"))
}

/// Certifies a program text against its job's plan (the agent's check
/// before it stores a program): the die made again, the text replayed and
/// measured.
pub fn check_plan(text: &str, plan: &gearcam_proto::WirePlan) -> Result<Certificate, Problem> {
    let d = &plan.die;
    let tol = (d.flank_tolerance_um / 1e3, d.fillet_tolerance_um / 1e3);
    let made = make(d, &plan.process, &[], 1)?;
    certify(text, plan.process.program, &made.cut, &made.layout, tol)
}
