//! The 3B program format of Chinese fast-wire EDM controls (docs/wire.md): one
//! block `B X B Y B J G Z` per line or arc, X, Y, J unsigned integers in µm.
//!
//! - **Line**: X, Y = the end point relative to the start (unsigned); the
//!   counting direction G is the axis of the larger component (GX on a
//!   tie), J that component; Z = L1–L4 by the quadrant of the move, L1
//!   including +X, L2 +Y, L3 −X, L4 −Y.
//! - **Arc**: X, Y = the start point relative to the centre (unsigned); Z =
//!   SR1–SR4 (clockwise) or NR1–NR4 (counter-clockwise) by the quadrant of
//!   the start point (on an axis, the quadrant the arc moves into); G by
//!   the end point relative to the centre: |x| > |y| → GY, else GX; J = the
//!   travel along the counting axis summed over every quadrant the arc
//!   passes. Published example: the R 9.9 mm circle from (9.9, 0)
//!   counter-clockwise is `B9900 B0 B39600 GY NR1`.
//!
//! [`read`] parses a program back and [`replay`] follows it as a control
//! does — an arc runs until its count J is used up — so a program can be
//! compared with the outline it was made from.

use std::f64::consts::{FRAC_PI_2, TAU};
use std::fmt::Write as _;

use crate::Segment;

/// Micrometres per millimetre.
const UM: f64 = 1000.0;

fn um(v: f64) -> i64 {
    (v * UM).round() as i64
}

/// The quadrant 1–4 of a direction, each including the axis it starts at
/// (1: +X, 2: +Y, 3: −X, 4: −Y).
fn quadrant(x: i64, y: i64) -> u8 {
    match (x, y) {
        (x, y) if x > 0 && y >= 0 => 1,
        (x, y) if x <= 0 && y > 0 => 2,
        (x, y) if x < 0 && y <= 0 => 3,
        _ => 4,
    }
}

/// The quadrant of an arc's start point relative to its centre: where it
/// is, or, on an axis, where it moves.
fn arc_quadrant(x: f64, y: f64, ccw: bool) -> u8 {
    let a = y.atan2(x).rem_euclid(TAU);
    // Nudge along the motion, then take the quadrant of the open interval.
    let a = a + if ccw { 1e-9 } else { -1e-9 };
    (a.rem_euclid(TAU) / FRAC_PI_2).floor() as u8 % 4 + 1
}

/// The travel along the x (or y) axis of the arc from angle `a0` through
/// the signed sweep `sweep` on radius `r`.
fn axis_travel(r: f64, a0: f64, sweep: f64, along_x: bool) -> f64 {
    let coord = |a: f64| if along_x { r * a.cos() } else { r * a.sin() };
    // Split at every multiple of 90° the arc crosses: between them the
    // coordinate is monotonic.
    let mut total = 0.0;
    let mut a = a0;
    let end = a0 + sweep;
    let dir = sweep.signum();
    loop {
        let next = if dir > 0.0 {
            ((a / FRAC_PI_2).floor() + 1.0) * FRAC_PI_2
        } else {
            ((a / FRAC_PI_2).ceil() - 1.0) * FRAC_PI_2
        };
        let stop = if (dir > 0.0 && next >= end) || (dir < 0.0 && next <= end) {
            end
        } else {
            next
        };
        total += (coord(stop) - coord(a)).abs();
        if stop == end {
            return total;
        }
        a = stop;
    }
}

/// The 3B block of one segment.
pub fn block(s: &Segment) -> String {
    match *s {
        Segment::Line { from, to } => {
            let (dx, dy) = (um(to.0) - um(from.0), um(to.1) - um(from.1));
            let (x, y) = (dx.abs(), dy.abs());
            let (g, j) = if x >= y { ("GX", x) } else { ("GY", y) };
            format!("B{x}B{y}B{j}{g}L{}", quadrant(dx, dy))
        }
        Segment::Arc {
            from,
            to,
            centre,
            ccw,
        } => {
            let (sx, sy) = (from.0 - centre.0, from.1 - centre.1);
            let (ex, ey) = (to.0 - centre.0, to.1 - centre.1);
            let r = (sx * sx + sy * sy).sqrt();
            let a0 = sy.atan2(sx);
            let a1 = ey.atan2(ex);
            let mut sweep = if ccw { a1 - a0 } else { a0 - a1 }.rem_euclid(TAU);
            if sweep < 1e-12 {
                sweep = TAU; // a whole circle
            }
            let signed = if ccw { sweep } else { -sweep };
            let along_x = ex.abs() <= ey.abs();
            let j = um(axis_travel(r, a0, signed, along_x));
            let g = if along_x { "GX" } else { "GY" };
            let z = if ccw { "NR" } else { "SR" };
            format!(
                "B{}B{}B{j}{g}{z}{}",
                um(sx).abs(),
                um(sy).abs(),
                arc_quadrant(sx, sy, ccw)
            )
        }
    }
}

/// A 3B program: one block per segment, then `DD` (end of program).
pub fn program(segments: &[Segment]) -> String {
    let mut p = String::new();
    for s in segments {
        let _ = writeln!(p, "{}", block(s));
    }
    p.push_str("DD\n");
    p
}

/// A block read back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block {
    /// X, µm.
    pub x: i64,
    /// Y, µm.
    pub y: i64,
    /// J, µm.
    pub j: i64,
    /// Counting along X (else Y).
    pub gx: bool,
    /// `L`, `SR` or `NR`.
    pub kind: Kind,
    /// Quadrant 1–4.
    pub quadrant: u8,
}

/// What a block does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// A line.
    Line,
    /// A clockwise arc.
    Clockwise,
    /// A counter-clockwise arc.
    CounterClockwise,
}

/// A program that cannot be read, with its line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Reads a 3B program (blocks until `DD`).
pub fn read(text: &str) -> Result<Vec<Block>, ReadError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let err = |message: String| ReadError {
            line: i + 1,
            message,
        };
        let line: String = raw.chars().filter(|c| !c.is_whitespace()).collect();
        if line.is_empty() {
            continue;
        }
        if line == "DD" {
            return Ok(out);
        }
        let rest = line
            .strip_prefix('B')
            .ok_or_else(|| err(format!("a block starts with B: {raw}")))?;
        let mut parts = rest.splitn(3, 'B');
        let num = |s: Option<&str>| -> Result<i64, ReadError> {
            s.and_then(|s| s.parse().ok())
                .ok_or_else(|| err(format!("three numbers B X B Y B J: {raw}")))
        };
        let x = num(parts.next())?;
        let y = num(parts.next())?;
        let tail = parts.next().unwrap_or("");
        let digits: String = tail.chars().take_while(char::is_ascii_digit).collect();
        let j = num(Some(&digits))?;
        let code = &tail[digits.len()..];
        let (gx, code) = if let Some(c) = code.strip_prefix("GX") {
            (true, c)
        } else if let Some(c) = code.strip_prefix("GY") {
            (false, c)
        } else {
            return Err(err(format!("GX or GY after J: {raw}")));
        };
        let (kind, q) = if let Some(q) = code.strip_prefix("NR") {
            (Kind::CounterClockwise, q)
        } else if let Some(q) = code.strip_prefix("SR") {
            (Kind::Clockwise, q)
        } else if let Some(q) = code.strip_prefix('L') {
            (Kind::Line, q)
        } else {
            return Err(err(format!("L, SR or NR: {raw}")));
        };
        let quadrant = match q {
            "1" => 1,
            "2" => 2,
            "3" => 3,
            "4" => 4,
            _ => return Err(err(format!("a quadrant 1-4: {raw}"))),
        };
        out.push(Block {
            x,
            y,
            j,
            gx,
            kind,
            quadrant,
        });
    }
    Err(ReadError {
        line: text.lines().count(),
        message: "no DD at the end".into(),
    })
}

/// The signs of a quadrant's x and y.
fn signs(q: u8) -> (f64, f64) {
    match q {
        1 => (1.0, 1.0),
        2 => (-1.0, 1.0),
        3 => (-1.0, -1.0),
        _ => (1.0, -1.0),
    }
}

/// Follows the blocks from `start` as a control does: a line to its end,
/// an arc until the travel along its counting axis reaches J.
pub fn replay(blocks: &[Block], start: (f64, f64)) -> Vec<Segment> {
    let mut p = start;
    let mut out = Vec::with_capacity(blocks.len());
    for b in blocks {
        let (x, y) = (b.x as f64 / UM, b.y as f64 / UM);
        match b.kind {
            Kind::Line => {
                let (sx, sy) = signs(b.quadrant);
                let to = (p.0 + sx * x, p.1 + sy * y);
                out.push(Segment::Line { from: p, to });
                p = to;
            }
            Kind::Clockwise | Kind::CounterClockwise => {
                let ccw = b.kind == Kind::CounterClockwise;
                // The start relative to the centre: its quadrant gives the
                // signs (an axis point belongs to the quadrant it moves into).
                let (sx, sy) = signs(b.quadrant);
                let (rx, ry) = (sx * x, sy * y);
                let centre = (p.0 - rx, p.1 - ry);
                let r = (rx * rx + ry * ry).sqrt();
                let a0 = ry.atan2(rx);
                let dir = if ccw { 1.0 } else { -1.0 };
                let goal = b.j as f64 / UM;
                // Walk quadrant by quadrant, then solve within the last.
                let coord = |a: f64| if b.gx { r * a.cos() } else { r * a.sin() };
                let mut a = a0;
                let mut used = 0.0;
                let end_angle = loop {
                    let next = if ccw {
                        ((a / FRAC_PI_2).floor() + 1.0) * FRAC_PI_2
                    } else {
                        ((a / FRAC_PI_2).ceil() - 1.0) * FRAC_PI_2
                    };
                    let piece = (coord(next) - coord(a)).abs();
                    if used + piece >= goal - 1e-12 || piece == 0.0 && used >= goal {
                        // Within this quadrant the coordinate is monotonic:
                        // bisect for the angle that uses the rest.
                        let left = goal - used;
                        let (mut lo, mut hi) = (0.0, (next - a).abs());
                        for _ in 0..80 {
                            let mid = 0.5 * (lo + hi);
                            if (coord(a + dir * mid) - coord(a)).abs() < left {
                                lo = mid;
                            } else {
                                hi = mid;
                            }
                        }
                        break a + dir * 0.5 * (lo + hi);
                    }
                    used += piece;
                    a = next;
                };
                let to = (
                    centre.0 + r * end_angle.cos(),
                    centre.1 + r * end_angle.sin(),
                );
                out.push(Segment::Arc {
                    from: p,
                    to,
                    centre,
                    ccw,
                });
                p = to;
            }
        }
    }
    out
}
