//! Verification of a spiral program before delivery (blocking): the program
//! text is replayed by an interpreter that knows nothing of spirals
//! ([`crate::macrob`]: Macro B for the FANUC forms, the LinuxCNC subset for
//! LinuxCNC) and its moves are compared with the model: the depth passes,
//! the start and end points, the block count, no rapid below the face, a
//! retract at the end, and the largest distance of the model's spiral from
//! the replayed path, sampled densely along the spiral.

use gearcam_proto::Code;
use gearcam_proto::{PathCheck, PathFinding, SpiralModel, SpiralProgram};

use crate::arcs::Arc;
use crate::macrob::{replay, replay_linuxcnc, Move};
use crate::Spiral;

/// What the replay measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Replayed {
    /// Largest distance of the spiral from the replayed path, mm (over every pass).
    pub max_deviation_mm: f64,
    /// Cutting blocks along the spiral, per pass.
    pub blocks: usize,
    /// Depth passes found.
    pub passes: usize,
}

/// Samples of the spiral per pass for the deviation.
const SAMPLES: usize = 20_000;

/// Rounding of printed coordinates the comparison allows, mm (0.1 µm
/// numbers; the polar forms print angles to 10⁻⁶ degrees).
const PRINT_SLACK_MM: f64 = 2e-4;

enum Piece {
    Line((f64, f64), (f64, f64)),
    Arc(Arc),
}

impl Piece {
    fn distance(&self, p: (f64, f64)) -> f64 {
        match self {
            Piece::Line(a, b) => {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len2 = dx * dx + dy * dy;
                let t = if len2 > 0.0 {
                    (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                ((a.0 + t * dx - p.0).powi(2) + (a.1 + t * dy - p.1).powi(2)).sqrt()
            }
            Piece::Arc(a) => a.distance(p),
        }
    }
}

fn finding(line: u32, rule: Code, message: String) -> PathFinding {
    PathFinding {
        line,
        rule,
        message,
    }
}

/// The model's spiral.
pub fn spiral_of(model: &SpiralModel) -> Spiral {
    Spiral {
        start_radius_mm: model.spiral.start_radius_mm,
        end_radius_mm: model.spiral.end_radius_mm,
        start_angle_deg: model.spiral.start_angle_deg,
        turns: model.spiral.turns,
        sense: model.spiral.sense,
    }
}

/// Replays `text` as `form` and compares it with `model`: the path check
/// (ok with no findings) and what was measured (when the replay ran).
pub fn verify(
    text: &str,
    form: SpiralProgram,
    model: &SpiralModel,
) -> (PathCheck, Option<Replayed>) {
    let budget =
        20 * (model.spiral.blocks as usize + 50) * model.cut.passes.max(1) as usize + 10_000;
    let replayed = match form {
        SpiralProgram::Linuxcnc => replay_linuxcnc(text, budget),
        _ => replay(text, budget),
    };
    let moves = match replayed {
        Ok(m) => m,
        Err(e) => {
            return (
                PathCheck {
                    ok: false,
                    findings: vec![finding(e.line as u32, Code::REPLAY_FAILED, e.message)],
                },
                None,
            )
        }
    };
    let (findings, replayed) = compare(&moves, model);
    (
        PathCheck {
            ok: findings.is_empty(),
            findings,
        },
        Some(replayed),
    )
}

/// The rules every move of the program keeps, from the first block to
/// `M30`, as the control runs them (the replay's start, the machine's
/// unknown position, counts as below the safe height):
///
/// - **approach**: no X/Y move before a move has taken the tool up to the
///   safe height;
/// - **rapids**: none ends below the face, and none moves in X/Y while the
///   tool is below it (a rapid straight up out of the cut is a retract);
/// - **plunges**: a feed down below the face (a plunge, or a ramp) ends
///   where the tool's disc is clear of the face's material (outside Ro +
///   rt or inside Ri − rt), so every pass starts clear of it; a groove is
///   cut into the face, so its plunge is its own first cut, at the plunge
///   feed, and is not held to this;
/// - **retracts** between passes follow from the rapid and plunge rules;
///   the final retract is `NO_RETRACT`.
fn every_move(moves: &[Move], model: &SpiralModel) -> Vec<PathFinding> {
    let mut findings = Vec::new();
    let f = &model.spiral;
    let (ri, ro, rt) = (f.inner_radius_mm, f.outer_radius_mm, f.tool_radius_mm);
    let safe = model.cut.safe_z_mm - 1e-9;
    let clear = |x: f64, y: f64| {
        let r = x.hypot(y);
        r - rt >= ro - 1e-6 || r + rt <= ri + 1e-6
    };
    let mut at = (0.0, 0.0, 0.0);
    let mut up = false;
    for (i, m) in moves.iter().enumerate() {
        let n = i + 1;
        let xy = (m.x - at.0).abs() + (m.y - at.1).abs() > 1e-12;
        if xy && !up {
            findings.push(finding(
                0,
                Code::UNSAFE_APPROACH,
                format!(
                    "move {n} moves in X/Y before the tool is at the safe height Z{}",
                    model.cut.safe_z_mm
                ),
            ));
        }
        if !m.feed && m.z < 0.0 {
            findings.push(finding(
                0,
                Code::RAPID_IN_MATERIAL,
                format!("move {n} is a rapid to Z{:.4}, below the face", m.z),
            ));
        } else if !m.feed && xy && at.2 < 0.0 {
            findings.push(finding(
                0,
                Code::RAPID_IN_MATERIAL,
                format!(
                    "move {n} is a rapid across X/Y at Z{:.4}, below the face: no retract before it",
                    at.2
                ),
            ));
        }
        if m.feed && m.z < at.2 - 1e-9 && m.z < 0.0 && model.groove.is_none() && !clear(m.x, m.y) {
            findings.push(finding(
                0,
                Code::PLUNGE_IN_MATERIAL,
                format!(
                    "move {n} feeds down to Z{:.4} at X{:.4} Y{:.4}, where the tool (radius {rt} mm, {:.4} mm from the centre) is in the face's material between R{ri} and R{ro}",
                    m.z,
                    m.x,
                    m.y,
                    m.x.hypot(m.y)
                ),
            ));
        }
        up |= m.z >= safe;
        at = (m.x, m.y, m.z);
    }
    findings
}

/// The replayed moves against the model: the rules of every move, the
/// depth passes, each pass's blocks, ends and distance from the spiral, and
/// the retract at the end.
fn compare(moves: &[Move], model: &SpiralModel) -> (Vec<PathFinding>, Replayed) {
    let mut findings = Vec::new();
    let spiral = spiral_of(model);
    let tol = model.cut.tolerance_mm;
    let total = std::f64::consts::TAU * f64::from(spiral.turns);
    findings.extend(every_move(moves, model));
    let passes = passes(moves);
    findings.extend(depth_finding(&passes, model));
    let mut worst: f64 = 0.0;
    let mut blocks = 0;
    let ends = (spiral.point_at(0.0), spiral.point_at(total));
    for pass in &passes {
        blocks = pass.pieces.len();
        findings.extend(pass_findings(pass, model, ends));
        worst = deviation(&spiral, total, &pass.pieces, worst);
    }
    if worst > tol * 1.01 + PRINT_SLACK_MM {
        findings.push(finding(
            0,
            Code::SPIRAL_DEVIATION,
            format!(
                "the path strays {worst:.5} mm from the model's spiral; the tolerance is {tol} mm"
            ),
        ));
    }
    match moves.last() {
        Some(m) if m.z >= model.cut.safe_z_mm - 1e-9 => {}
        other => findings.push(finding(
            0,
            Code::NO_RETRACT,
            format!(
                "the program ends at Z{:.4}, not at the safe height Z{}",
                other.map_or(0.0, |m| m.z),
                model.cut.safe_z_mm
            ),
        )),
    }
    (
        findings,
        Replayed {
            max_deviation_mm: worst,
            blocks,
            passes: passes.len(),
        },
    )
}

/// A depth pass of the replay: its depth, its pieces along the spiral and
/// where it starts.
struct Pass {
    z: f64,
    pieces: Vec<Piece>,
    start: (f64, f64),
}

/// The passes: runs of feed moves at one depth below the face, each a line
/// or an arc in X/Y.
fn passes(moves: &[Move]) -> Vec<Pass> {
    let mut passes: Vec<Pass> = Vec::new();
    let mut from = (0.0, 0.0, 0.0);
    for m in moves {
        let xy_moved = (m.x - from.0).abs() + (m.y - from.1).abs() > 1e-12;
        if m.feed && m.z < 0.0 && xy_moved {
            let start = (from.0, from.1);
            let piece = match m.arc {
                Some((centre, ccw)) => Piece::Arc(Arc {
                    start,
                    end: (m.x, m.y),
                    centre,
                    radius: ((start.0 - centre.0).powi(2) + (start.1 - centre.1).powi(2)).sqrt(),
                    ccw,
                    end_phi: 0.0,
                }),
                None => Piece::Line(start, (m.x, m.y)),
            };
            match passes.last_mut() {
                Some(p) if (p.z - m.z).abs() < 1e-9 && (from.2 - m.z).abs() < 1e-9 => {
                    p.pieces.push(piece)
                }
                _ => passes.push(Pass {
                    z: m.z,
                    pieces: vec![piece],
                    start,
                }),
            }
        }
        from = (m.x, m.y, m.z);
    }
    passes
}

/// The passes' depths against the model's: the cut's depth in equal steps.
fn depth_finding(passes: &[Pass], model: &SpiralModel) -> Option<PathFinding> {
    let expected: Vec<f64> = (1..=model.cut.passes)
        .map(|k| -model.cut.depth_mm * f64::from(k) / f64::from(model.cut.passes))
        .collect();
    let depths: Vec<f64> = passes.iter().map(|p| p.z).collect();
    if depths.len() != expected.len()
        || depths
            .iter()
            .zip(&expected)
            .any(|(a, b)| (a - b).abs() > 1e-4)
    {
        return Some(finding(
            0,
            Code::PASS_DEPTHS,
            format!(
                "the program cuts at Z {:?}; the model's passes are at Z {:?}",
                depths, expected
            ),
        ));
    }
    None
}

/// One pass against the model: its block count, and its start and end
/// against the spiral's (`ends`), within the printed rounding.
fn pass_findings(
    pass: &Pass,
    model: &SpiralModel,
    (begin, end): ((f64, f64), (f64, f64)),
) -> Vec<PathFinding> {
    let mut findings = Vec::new();
    let (z, pieces, start) = (pass.z, &pass.pieces, &pass.start);
    let blocks = pieces.len();
    if blocks != model.spiral.blocks as usize {
        findings.push(finding(
            0,
            Code::BLOCK_COUNT,
            format!(
                "the pass at Z{z:.4} has {blocks} blocks along the spiral; the model has {}",
                model.spiral.blocks
            ),
        ));
    }
    let last = match pieces.last() {
        Some(Piece::Line(_, b)) => *b,
        Some(Piece::Arc(a)) => a.end,
        None => *start,
    };
    for (what, got, want) in [("starts", *start, begin), ("ends", last, end)] {
        let d = ((got.0 - want.0).powi(2) + (got.1 - want.1).powi(2)).sqrt();
        if d > PRINT_SLACK_MM {
            findings.push(finding(
                0,
                Code::SPIRAL_ENDS,
                format!(
                    "the pass at Z{z:.4} {what} at X{:.4} Y{:.4}, {d:.4} mm from the model's X{:.4} Y{:.4}",
                    got.0, got.1, want.0, want.1
                ),
            ));
        }
    }
    findings
}

/// The largest of `worst` and the distances of the spiral's sample points
/// (over its whole sweep `total`, radians) from a pass's pieces. The pieces
/// run in order, so a window moving with the nearest piece suffices.
fn deviation(spiral: &Spiral, total: f64, pieces: &[Piece], mut worst: f64) -> f64 {
    let mut i = 0usize;
    for k in 0..=SAMPLES {
        let p = spiral.point_at(total * k as f64 / SAMPLES as f64);
        let (best, d) = (i.saturating_sub(2)..(i + 3).min(pieces.len()))
            .map(|j| (j, pieces[j].distance(p)))
            .fold((i, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        i = best;
        worst = worst.max(d);
    }
    worst
}
