//! The 4B program format of fast-wire EDM controls (seed 002, docs/wire.md):
//! 3B with each arc's radius and its kind, so the control can offset the
//! part outline itself for the wire and spark gap.
//!
//! - **Arc**: `L c R B X B Y B J G Z`, without spaces: `c` is 3 for an arc
//!   convex on the part, 4 for a concave one; R the arc's radius in µm
//!   (the control's "equivalent radius" for its compensation); X, Y, J, G,
//!   Z exactly as 3B ([`crate::threeb`]). Seed 002's example:
//!   `L338750B7718B37973B079483GXNR1` (L3, R 38750, X 7718, Y 37973, J
//!   79483 written with a leading zero, GX, NR1).
//! - **Line**: a plain 3B block `B X B Y B J G L n`.
//! - The program ends with `DD`.
//!
//! The program is the part's outline, not the wire's path: the control
//! compensates. Convex means the arc's centre lies on the material side.
//! gearcam's contours run clockwise about the gear (material on the right),
//! so there a clockwise arc (SR) is convex (L3) and a counter-clockwise one
//! (NR) concave (L4); on a contour run counter-clockwise it is the other way
//! round, which is how seed 002's example (L3 on NR) reads. [`check`] takes
//! the sense and refuses a kind that disagrees with the arc's direction, or
//! an R more than 2 µm from √(X² + Y²).

use std::fmt::Write as _;

use crate::threeb::{self, Block, Kind, ReadError};
use crate::Segment;

/// A 4B block read back: a 3B block with, for an arc, its radius and kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block4 {
    /// The 1-based line of the program it was read from.
    pub line: usize,
    /// R, µm (an arc's `L3`/`L4` block; `None` for a plain 3B block).
    pub radius_um: Option<i64>,
    /// `Some(true)` for `L3` (convex), `Some(false)` for `L4` (concave).
    pub convex: Option<bool>,
    /// The 3B part: X, Y, J, G, Z.
    pub block: Block,
}

/// The direction a contour runs around the part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sense {
    /// Clockwise, material on the right (gearcam's contours).
    Clockwise,
    /// Counter-clockwise, material on the left.
    CounterClockwise,
}

/// A 4B program of the part outline from its first segment's start.
pub fn program(segments: &[Segment]) -> String {
    let start = segments.first().map_or((0.0, 0.0), Segment::from);
    program_from(start, segments)
}

/// A 4B program of the part outline from `start`, clockwise about the part
/// (clockwise arcs convex), written without drift as
/// [`threeb::program_from`]: the same X, Y, J, G, Z, with R the radius of
/// the arc as written, √(X² + Y²) rounded to the µm.
pub fn program_from(start: (f64, f64), segments: &[Segment]) -> String {
    text(&threeb::blocks_from(start, segments))
}

/// The 4B text of 3B `blocks` (a contour run clockwise about the part):
/// each arc with its kind, L3 for a clockwise arc (convex), L4 for a
/// counter-clockwise one, and R, its radius as written, √(X² + Y²)
/// rounded to the µm; lines as they are; then `DD`.
pub fn text(blocks: &[Block]) -> String {
    let mut p = String::new();
    for b in blocks {
        let _ = match b.kind {
            Kind::Line => writeln!(p, "{b}"),
            Kind::Clockwise | Kind::CounterClockwise => {
                let r = (b.x as f64).hypot(b.y as f64).round() as i64;
                let kind = if b.kind == Kind::CounterClockwise {
                    4
                } else {
                    3
                };
                writeln!(p, "L{kind}{r}{b}")
            }
        };
    }
    p.push_str("DD\n");
    p
}

/// Reads a 4B program (blocks until `DD`); spaces are ignored. The blocks
/// are not checked against each other: that is [`check`].
pub fn read(text: &str) -> Result<Vec<Block4>, ReadError> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let err = |message: &str| ReadError {
            line: i + 1,
            message: format!("{message}: {raw}"),
        };
        let line: String = raw.chars().filter(|c| !c.is_whitespace()).collect();
        if line.is_empty() {
            continue;
        }
        if line == "DD" {
            return Ok(out);
        }
        let (radius_um, convex, rest) = match line.strip_prefix('L') {
            None => (None, None, line.as_str()),
            Some(tail) => {
                let convex = match tail.as_bytes().first() {
                    Some(b'3') => true,
                    Some(b'4') => false,
                    _ => return Err(err("L3 (convex) or L4 (concave)")),
                };
                let digits = tail[1..].bytes().take_while(u8::is_ascii_digit).count();
                let r = tail[1..1 + digits]
                    .parse()
                    .map_err(|_| err("a radius in µm after L3 or L4"))?;
                (Some(r), Some(convex), &tail[1 + digits..])
            }
        };
        let block = threeb::parse_block(rest).map_err(|m| err(&m))?;
        out.push(Block4 {
            line: i + 1,
            radius_um,
            convex,
            block,
        });
    }
    Err(ReadError {
        line: text.lines().count(),
        message: "no DD at the end".into(),
    })
}

/// Checks blocks read from a contour run in `sense`: every arc carries
/// L3/L4 and its radius, the kind agrees with the arc's direction (convex
/// when the centre is on the material side), R is within 2 µm of
/// √(X² + Y²), and no line carries a kind. The error names the block's line.
pub fn check(blocks: &[Block4], sense: Sense) -> Result<(), ReadError> {
    for b in blocks {
        let err = |message: String| ReadError {
            line: b.line,
            message,
        };
        let ccw = match b.block.kind {
            Kind::Line => {
                if b.convex.is_some() || b.radius_um.is_some() {
                    return Err(err("a line is a plain 3B block, without L3/L4".into()));
                }
                continue;
            }
            Kind::Clockwise => false,
            Kind::CounterClockwise => true,
        };
        let (Some(convex), Some(r)) = (b.convex, b.radius_um) else {
            return Err(err("an arc carries L3/L4 and its radius".into()));
        };
        // Clockwise about the part, a clockwise arc turns about a centre on
        // the material side.
        let should = ccw == (sense == Sense::CounterClockwise);
        if convex != should {
            let has = if convex { "L3" } else { "L4" };
            let z = if ccw { "NR" } else { "SR" };
            return Err(err(format!(
                "{has} on an {z} arc of a {sense:?} contour: it should be {}",
                if should {
                    "L3 (convex)"
                } else {
                    "L4 (concave)"
                }
            )));
        }
        let (x, y) = (b.block.x as f64, b.block.y as f64);
        let radius = x.hypot(y);
        if (r as f64 - radius).abs() > 2.0 {
            return Err(err(format!(
                "R {r} µm but the start is {radius:.1} µm from the centre"
            )));
        }
    }
    Ok(())
}

/// Follows the blocks from `start` as a control does without compensation:
/// the 3B replay ([`threeb::replay`]) of their 3B part.
pub fn replay(blocks: &[Block4], start: (f64, f64)) -> Vec<Segment> {
    let inner: Vec<Block> = blocks.iter().map(|b| b.block).collect();
    threeb::replay(&inner, start)
}
