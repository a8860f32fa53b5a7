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

use gearcam_proto::{Code, Problem};
use gearcam_proto::{DiePart, WireProgram};

use crate::die::Cut;
use crate::fourb;
use crate::iso::{self, IsoProgram};
use crate::offset::{offset, Side};
use crate::verify::{measure, Measure, SAMPLES};
use crate::winding::{lead_crossing, winds};
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
    let lead_in = Segment::Line {
        from: layout.start_hole,
        to: start,
    };
    let mut segments = vec![lead_in];
    segments.extend(part);
    let mut blocks = threeb::blocks_from(layout.start_hole, &segments);
    let rotation = (layout.sections > 1).then(|| Rotation {
        last_turned: blocks.len(),
        times: layout.sections,
        quarters_clockwise: 4 / layout.sections,
    });
    // The lead-out leaves from where the control is after the last
    // section: the written section turned as often as the rotation turns
    // it, not the written section's own end.
    let at = run_blocks(&blocks, rotation.as_ref(), layout.start_hole)
        .last()
        .map_or(layout.start_hole, |s| s.segment.to());
    blocks.push(threeb::line_to(at, layout.start_hole));
    let mut text = String::new();
    for h in header {
        text.push_str("; ");
        text.push_str(h);
        text.push('\n');
    }
    if let Some(r) = &rotation {
        text.push_str(&r.header_line(blocks.len()));
        text.push('\n');
        // For a control whose rotate instruction asks for a centre.
        let (x, y) = (-layout.start_hole.0, -layout.start_hole.1);
        text.push_str(&format!(
            "; TURNS ABOUT THE GEAR'S CENTRE X{:.3} Y{:.3} FROM THE START HOLE\n",
            x + 0.0,
            y + 0.0
        ));
    }
    text.push_str(&match form {
        WireProgram::FourB => fourb::text(&blocks),
        _ => threeb::text(&blocks),
    });
    Written {
        text,
        blocks: blocks.len() as u32,
    }
}

/// How a 3B or 4B control runs a program with a rotation: block 1 once,
/// blocks 2 to `last_turned` `times` times, the k-th time (k from 0)
/// turned clockwise by k × `quarters_clockwise` × 90° about the start of
/// the section, then every block after `last_turned` once, unturned
/// (docs/wire.md#programs). The program's header states it in one line,
/// `; ROTATE: BLOCK 1, THEN BLOCKS 2-N k TIMES TURNED d DEG CLOCKWISE
/// EACH, THEN BLOCK N+1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rotation {
    /// The last block (1-based) of the turned section.
    pub last_turned: usize,
    /// How often the section runs.
    pub times: u32,
    /// Quarter turns clockwise from one run of the section to the next.
    pub quarters_clockwise: u32,
}

/// The header's words before and after the numbers of a rotation.
const ROTATE: &str = "; ROTATE: BLOCK 1, THEN BLOCKS 2-";

impl Rotation {
    /// The header line stating the rotation of a program of `blocks` blocks.
    fn header_line(&self, blocks: usize) -> String {
        format!(
            "{ROTATE}{} {} TIMES TURNED {} DEG CLOCKWISE EACH, THEN BLOCK {}",
            self.last_turned,
            self.times,
            90 * self.quarters_clockwise,
            blocks
        )
    }

    /// The rotation a program's text states, if any; an error names what
    /// does not read (a control that cannot read the line would not run
    /// the program as written).
    pub fn of_text(text: &str) -> Result<Option<Rotation>, String> {
        let Some(line) = text
            .lines()
            .find(|l| l.trim_start().starts_with("; ROTATE"))
        else {
            return Ok(None);
        };
        let bad = || {
            format!("a rotation line of the form {ROTATE}N k TIMES TURNED d DEG CLOCKWISE EACH, THEN BLOCK N+1: {line}")
        };
        let rest = line.trim().strip_prefix(ROTATE).ok_or_else(bad)?;
        let words: Vec<&str> = rest.split([' ', ',']).filter(|w| !w.is_empty()).collect();
        let num = |i: usize| -> Result<u32, String> {
            words.get(i).and_then(|w| w.parse().ok()).ok_or_else(bad)
        };
        let shape = [
            "",
            "",
            "TIMES",
            "TURNED",
            "",
            "DEG",
            "CLOCKWISE",
            "EACH",
            "THEN",
            "BLOCK",
            "",
        ];
        if words.len() != shape.len()
            || shape
                .iter()
                .zip(&words)
                .any(|(s, w)| !s.is_empty() && s != w)
        {
            return Err(bad());
        }
        let (last, times, deg, after) = (num(0)?, num(1)?, num(4)?, num(10)?);
        if last < 2 || after != last + 1 || times == 0 || deg % 90 != 0 || deg == 0 {
            return Err(bad());
        }
        Ok(Some(Rotation {
            last_turned: last as usize,
            times,
            quarters_clockwise: deg / 90,
        }))
    }
}

/// A replayed block: the segment the control moved along and the 1-based
/// block it ran.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ran {
    /// The block, 1-based, as written.
    pub block: usize,
    /// Its motion.
    pub segment: Segment,
}

/// Every block of a 3B or 4B program in the order the control runs it,
/// from `start`: each block from where the one before really ended, the
/// turned section's blocks turned as `rotation` says.
pub fn run_blocks(
    blocks: &[threeb::Block],
    rotation: Option<&Rotation>,
    start: (f64, f64),
) -> Vec<Ran> {
    let mut order: Vec<(usize, u8)> = Vec::new();
    match rotation {
        None => order.extend((0..blocks.len()).map(|i| (i, 0))),
        Some(r) => {
            order.push((0, 0));
            let last = r.last_turned.min(blocks.len());
            for k in 0..r.times {
                // Clockwise by k quarters: counter-clockwise by 4 − k.
                let ccw = ((4 - (k * r.quarters_clockwise) % 4) % 4) as u8;
                order.extend((1..last).map(|i| (i, ccw)));
            }
            order.extend((last..blocks.len()).map(|i| (i, 0)));
        }
    }
    let mut at = start;
    order
        .into_iter()
        .map(|(i, quarters)| {
            let turned = threeb::rotate_block(blocks[i], quarters);
            let segment = threeb::replay_block(&turned, at);
            at = segment.to();
            Ran {
                block: i + 1,
                segment,
            }
        })
        .collect()
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

fn replay_problem(code: Code, expected: String, got: String, message: String) -> Problem {
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

/// Reads `text` back, replays every block in the order the control runs
/// it — the lead-in, the sections turned as the program's rotation says
/// (3B, 4B) or its subprogram calls under `G68` (ISO), the lead-out — and
/// checks the whole of it: the wire ends at its start hole
/// (`WIRE_LEAD_OUT`), the lead-in and lead-out run through the scrap only
/// (`WIRE_LEAD_CROSSES_PART`), ISO's compensation is switched on by the
/// lead-in and off by the lead-out, and the contour between them, set off
/// as the control sets it off (4B, ISO), is measured against the
/// theoretical outline: over its tolerances, not closed, or not once round
/// the part fails.
pub fn certify(
    text: &str,
    form: WireProgram,
    cut: &Cut,
    layout: &Layout,
    tolerances: (f64, f64),
) -> Result<Certificate, Problem> {
    let Replayed {
        start,
        lead_in,
        contour,
        lead_out,
        blocks,
        compensation,
    } = read_back(text, form, layout)?;
    let path = wire_path(form, cut, &contour, compensation)?;
    // The measure below is a distance from the outline: blind to the side.
    // The wire runs in the scrap — inside a die's opening, outside a punch —
    // or the part comes out a wire's width too large or too small.
    let scrap_inside = cut.side == Side::Right;
    check_scrap_side(cut, &path, scrap_inside)?;
    check_lead_out_end(start, &lead_out)?;
    check_leads(&lead_in, &lead_out, &contour, scrap_inside)?;
    let m = measure(&cut.outline, &path, cut.offset_mm, SAMPLES);
    check_measure(&m, tolerances)?;
    Ok(Certificate {
        measure: m,
        blocks,
        bytes: text.len() as u32,
    })
}

/// A program the certificate cannot read back or replay: `WIRE_REPLAY_FAILED`.
fn unreadable(e: String) -> Problem {
    replay_problem(
        Code::WIRE_REPLAY_FAILED,
        "a program the reader follows".into(),
        e,
        "the program cannot be read back".into(),
    )
}

/// The program read back and replayed as its form is run, which must
/// start at the job's start hole.
fn read_back(text: &str, form: WireProgram, layout: &Layout) -> Result<Replayed, Problem> {
    let replayed = match form {
        WireProgram::ThreeB | WireProgram::FourB => replay_b(text, form, layout.start_hole),
        WireProgram::IsoWire => replay_iso(text),
    }
    .map_err(unreadable)?;
    if distance(replayed.start, layout.start_hole) > END_MM {
        return Err(unreadable(format!(
            "the program starts at ({:.4}, {:.4}), the job's start hole is ({:.4}, {:.4})",
            replayed.start.0, replayed.start.1, layout.start_hole.0, layout.start_hole.1
        )));
    }
    Ok(replayed)
}

/// The wire's path of the replayed contour. 3B is the wire's path; 4B is
/// set off by the control for the job's wire (each arc's R and L3/L4 as
/// written); ISO by the side and D value the program itself sets.
fn wire_path(
    form: WireProgram,
    cut: &Cut,
    contour: &[Segment],
    compensation: Option<(Side, f64)>,
) -> Result<Vec<Segment>, Problem> {
    let (side, d) = compensation.unwrap_or((cut.side, cut.offset_mm));
    match form {
        WireProgram::ThreeB => Ok(contour.to_vec()),
        _ => offset(contour, side, d).map_err(|e| {
            unreadable(format!(
                "the control's offset fails at contour move {}: {e}",
                e.index + 1
            ))
        }),
    }
}

/// The wire on the scrap side of the outline (inside a die's opening,
/// outside a punch), tried at the middle of some sixteen moves spread
/// along the path: `WIRE_DEVIATION` if not.
fn check_scrap_side(cut: &Cut, path: &[Segment], scrap_inside: bool) -> Result<(), Problem> {
    if let Some(p) = path
        .iter()
        .step_by((path.len() / 16).max(1))
        .map(|s| s.arc().point_at(s.arc().length / 2.0))
        .find(|&p| (winds(p, &cut.contour) != 0) != scrap_inside)
    {
        let (part, want) = if scrap_inside {
            ("a die", "inside the opening")
        } else {
            ("a punch", "outside the punch")
        };
        return Err(replay_problem(
            Code::WIRE_DEVIATION,
            format!("the wire of {part} {want}, on the scrap side of the outline"),
            format!("the wire at ({:.3}, {:.3}), on the part's side", p.0, p.1),
            "the replayed program sets the wire off to the wrong side of the outline (G41/G42, or the path itself)".into(),
        ));
    }
    Ok(())
}

/// The lead-out back at the start hole, where the program began:
/// `WIRE_LEAD_OUT` if not.
fn check_lead_out_end(start: (f64, f64), lead_out: &Ran) -> Result<(), Problem> {
    let end = lead_out.segment.to();
    if distance(end, start) > END_MM {
        return Err(replay_problem(
            Code::WIRE_LEAD_OUT,
            format!(
                "the wire back at its start hole ({:.3}, {:.3}) after the last block",
                start.0, start.1
            ),
            format!(
                "the lead-out (block {}) ends at ({:.3}, {:.3}), {:.3} mm away",
                lead_out.block,
                end.0,
                end.1,
                distance(end, start)
            ),
            "the program does not end where it began: the lead-out would cut elsewhere".into(),
        ));
    }
    Ok(())
}

/// The lead-in and lead-out through the scrap only, clear of the kept
/// part: `WIRE_LEAD_CROSSES_PART` if not. 3B is the wire's path; 4B and ISO
/// the outline the control sets off.
fn check_leads(
    lead_in: &Ran,
    lead_out: &Ran,
    contour: &[Segment],
    scrap_inside: bool,
) -> Result<(), Problem> {
    for (name, lead, join) in [
        ("lead-in", lead_in, contour[0].from()),
        ("lead-out", lead_out, contour[contour.len() - 1].to()),
    ] {
        if let Some(place) = lead_crossing(&lead.segment, join, contour, scrap_inside) {
            let kept = if scrap_inside {
                "the die plate"
            } else {
                "the punch"
            };
            return Err(replay_problem(
                Code::WIRE_LEAD_CROSSES_PART,
                format!("the {name} through the scrap only, clear of {kept}"),
                format!(
                    "the {name} (block {}) enters {kept} at ({:.3}, {:.3})",
                    lead.block, place.0, place.1
                ),
                format!("the {name} would cut into {kept}"),
            ));
        }
    }
    Ok(())
}

/// The measure against the tolerances (flank, fillet): within them on the
/// flanks and fillets (`WIRE_DEVIATION`), closed within the flank's and
/// once round the part (`WIRE_CLOSURE`).
fn check_measure(m: &Measure, (flank_tol, fillet_tol): (f64, f64)) -> Result<(), Problem> {
    if m.flank_mm > flank_tol || m.fillet_mm > fillet_tol {
        return Err(replay_problem(
            Code::WIRE_DEVIATION,
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
            Code::WIRE_CLOSURE,
            format!(
                "a closed path once round the part (within {:.1} µm)",
                flank_tol * 1e3
            ),
            format!("{:.3} µm apart, {:.4} turns", m.closure_mm * 1e3, -m.turns),
            "the replayed program does not close on itself".into(),
        ));
    }
    Ok(())
}

/// How far the replayed end may lie from the start hole, mm: the 3B/4B
/// replay runs on the control's µm grid, ISO writes 0.1 µm.
const END_MM: f64 = 0.0005;

fn distance(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// A program replayed block by block, cut into its three parts.
#[derive(Debug)]
struct Replayed {
    /// Where the wire starts (and must end).
    start: (f64, f64),
    /// The first motion.
    lead_in: Ran,
    /// Every motion between, in order.
    contour: Vec<Segment>,
    /// The last motion.
    lead_out: Ran,
    /// Blocks of the text (a section's or subprogram's once, however often
    /// it runs).
    blocks: u32,
    /// The compensation the program itself sets (ISO: `G41`/`G42` and its
    /// `D` register's value); the control sets the outline off by it.
    compensation: Option<(Side, f64)>,
}

impl Replayed {
    fn of(start: (f64, f64), mut ran: Vec<Ran>, blocks: u32) -> Result<Replayed, String> {
        if ran.len() < 3 {
            return Err(format!(
                "{} motions: a program is a lead-in, a contour and a lead-out",
                ran.len()
            ));
        }
        // The control runs each move from where the one before ended: a
        // gap is a block the replay cannot account for.
        for pair in ran.windows(2) {
            let gap = distance(pair[0].segment.to(), pair[1].segment.from());
            if gap > END_MM {
                return Err(format!(
                    "block {} starts {gap:.4} mm from where block {} ended",
                    pair[1].block, pair[0].block
                ));
            }
        }
        let lead_out = ran.pop().expect("three motions");
        let lead_in = ran.remove(0);
        for (name, lead) in [("lead-in", &lead_in), ("lead-out", &lead_out)] {
            if !matches!(lead.segment, Segment::Line { .. }) {
                return Err(format!("block {}: the {name} is a line", lead.block));
            }
        }
        Ok(Replayed {
            start,
            lead_in,
            contour: ran.into_iter().map(|r| r.segment).collect(),
            lead_out,
            blocks,
            compensation: None,
        })
    }
}

/// A 3B or 4B program replayed from `start`: its comment lines skipped,
/// its rotation line followed, every block run.
fn replay_b(text: &str, form: WireProgram, start: (f64, f64)) -> Result<Replayed, String> {
    let rotation = Rotation::of_text(text)?;
    let body = body(text);
    let blocks: Vec<threeb::Block> = if form == WireProgram::FourB {
        let b4 = fourb::read(&body).map_err(|e| format!("line {}: {}", e.line, e.message))?;
        fourb::check(&b4, fourb::Sense::Clockwise)
            .map_err(|e| format!("block {}: {}", e.line, e.message))?;
        b4.iter().map(|b| b.block).collect()
    } else {
        threeb::read(&body).map_err(|e| format!("line {}: {}", e.line, e.message))?
    };
    if let Some(r) = rotation {
        if r.last_turned >= blocks.len() {
            return Err(format!(
                "the rotation turns blocks 2-{} of {}: no lead-out after it",
                r.last_turned,
                blocks.len()
            ));
        }
    }
    let ran = run_blocks(&blocks, rotation.as_ref(), start);
    Replayed::of(start, ran, blocks.len() as u32)
}

/// An ISO program replayed: every move from the `G92` start to `M02`/`M30`
/// through its subprogram calls. No rapid (a wire cuts wherever it moves);
/// the lead-in switches the compensation on, every contour move keeps it,
/// the lead-out switches it off.
fn replay_iso(text: &str) -> Result<Replayed, String> {
    let r = iso::replay(text).map_err(|e| format!("line {}: {}", e.line, e.message))?;
    if let Some(m) = r.moves.iter().find(|m| m.rapid) {
        return Err(format!(
            "line {}: a rapid move (G00); a wire cuts wherever it moves",
            m.line
        ));
    }
    let ran: Vec<Ran> = r
        .moves
        .iter()
        .map(|m| Ran {
            block: m.line,
            segment: m.segment,
        })
        .collect();
    let (Some(first), Some(last)) = (r.moves.first(), r.moves.last()) else {
        return Err("no motion".into());
    };
    let (Some(side), Some(offset_mm)) = (first.side, first.offset_mm) else {
        return Err(format!(
            "line {}: the lead-in switches the compensation on (G41/G42 with D)",
            first.line
        ));
    };
    let side = match side {
        iso::Side::Left => Side::Left,
        iso::Side::Right => Side::Right,
    };
    if last.side.is_some() {
        return Err(format!(
            "line {}: the lead-out switches the compensation off (G40)",
            last.line
        ));
    }
    let inner = &r.moves[1..r.moves.len() - 1];
    if let Some(m) = inner
        .iter()
        .find(|m| m.side != first.side || m.offset_mm != first.offset_mm)
    {
        return Err(format!(
            "line {}: the compensation changes along the contour",
            m.line
        ));
    }
    let blocks: std::collections::BTreeSet<usize> = r.moves.iter().map(|m| m.line).collect();
    let mut replayed = Replayed::of(r.start, ran, blocks.len() as u32)?;
    replayed.compensation = Some((side, offset_mm));
    Ok(replayed)
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
                Err(p) if p.code == Code::WIRE_DEVIATION => last = Some(p),
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
