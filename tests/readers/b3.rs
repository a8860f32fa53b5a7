//! A clean-room reader and runner of the 3B and 4B wire-EDM program formats, written from
//! `docs/wire.md` ("The 3B format", "The 4B format", "Programs", "Verification and the
//! certificate") and the 3B table of `docs/reference.md` ("Spur-gear dies by wire EDM"), to
//! check gearcam's own writer and reader without sharing their code. Both formats live in this
//! one file (there is no separate `b4.rs`).
//!
//! The rules implemented:
//!
//! - A program is a sequence of text lines. A line whose first non-blank character is `;` is a
//!   comment (the W01 loader skips the header, "Programs"); blank lines are skipped. The program
//!   ends with the line `DD`; a block after `DD`, or a program without `DD`, is refused.
//! - 3B block `B X B Y B J G Z` (blanks between the words are allowed, "The 3B format"); X, Y, J
//!   unsigned integers in µm (leading zeros allowed, as in the seed's `B079483`); G is `GX` or
//!   `GY`; Z is `L1`–`L4` (a line) or `SR1`–`SR4` / `NR1`–`NR4` (a clockwise / counter-clockwise
//!   arc).
//! - Line: X, Y = the end relative to the start, with the signs of the quadrant L1 (+X included:
//!   x > 0, y ≥ 0), L2 (+Y: x ≤ 0, y > 0), L3 (−X: x < 0, y ≤ 0), L4 (−Y: x ≥ 0, y < 0). G is the
//!   axis of the larger component (GX on a tie) and J that component. A line that breaks one of
//!   these rules is refused with its line.
//! - Arc: X, Y = the start relative to the centre, signed by the quadrant code as for lines (on
//!   an axis the code must name the quadrant the arc moves into); the arc runs from its start
//!   until its count J, the travel along the counting axis G summed over every quadrant it
//!   passes, is used up. The control moves in µm steps, so the end is the point where the count
//!   runs out rounded to the nearest µm grid point (the start is on the grid, hence so is the
//!   centre). At that end G must follow the rule |x| > |y| → GY, else GX (within 2 µm, the
//!   rounding). An arc of no radius, or a count beyond a whole turn (J > 4·r + 1 µm), is
//!   refused.
//! - The sections header `; ROTATE: BLOCK 1, THEN BLOCKS 2-N 4 TIMES TURNED 90 DEG CLOCKWISE
//!   EACH, THEN BLOCK N+1` ("Programs"): the first part runs once, the middle range runs the
//!   given number of times, run k (k = 0, 1, …) turned by k times the angle clockwise, then the
//!   last part runs once, unturned. Turning a block turns its displacement (a line) or its
//!   start-from-centre vector (an arc), keeps its sense, and makes the count run along the
//!   turned axis (GX ↔ GY for an odd number of quarter turns). Only multiples of 90° are
//!   accepted: they map the µm grid onto itself.
//! - 4B ("The 4B format"): 3B with, before each arc, `L3` (convex) or `L4` (concave) and the
//!   radius R in µm: `L{3|4}{R}B{X}B{Y}B{J}{G}{Z}`; lines stay plain 3B. An arc without a kind,
//!   a line with one, an R more than 2 µm from √(X² + Y²), or a kind that disagrees with the
//!   contour's sense (clockwise: SR is L3, NR is L4; counter-clockwise the other way round) is
//!   refused with its line. The 4B program is the part's outline; this runner returns that
//!   outline as programmed and does not apply the control's wire offset.
//!
//! All positions are whole µm internally and are returned in mm relative to the start hole.

/// One motion the control makes, in mm, relative to the program's start point (the start hole
/// = (0,0)).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WireMove {
    /// 1-based line of the block in the text.
    pub(crate) line: usize,
    pub(crate) from: (f64, f64),
    pub(crate) to: (f64, f64),
    /// The arc's centre and whether it runs counter-clockwise; `None` for a line.
    pub(crate) arc: Option<((f64, f64), bool)>,
}

/// The counting axis G of a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Axis {
    X,
    Y,
}

/// What a block's Z code says it is: a line `L1`–`L4`, or an arc `SR1`–`SR4` / `NR1`–`NR4`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Motion {
    Line { quadrant: u8 },
    Arc { ccw: bool, quadrant: u8 },
}

/// The 4B prefix of an arc ("The 4B format"): `L3` convex or `L4` concave, and the radius in µm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Convexity {
    pub(crate) convex: bool,
    pub(crate) radius_um: i64,
}

/// The sense of a 4B contour, which decides which of L3/L4 goes with SR and NR.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Sense {
    Clockwise,
    CounterClockwise,
}

/// One parsed block, its numbers as written (unsigned µm).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Block {
    pub(crate) line: usize,
    pub(crate) x: i64,
    pub(crate) y: i64,
    pub(crate) j: i64,
    pub(crate) g: Axis,
    pub(crate) motion: Motion,
    /// 4B only: the `L3`/`L4` kind and radius written before the block.
    pub(crate) convexity: Option<Convexity>,
}

/// The `; ROTATE:` header: blocks are numbered from 1 in the order they are written, `DD` not
/// counted. Ranges are inclusive.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Rotation {
    pub(crate) line: usize,
    pub(crate) first: (usize, usize),
    pub(crate) repeated: (usize, usize),
    pub(crate) times: usize,
    /// The turn of each run over the one before, clockwise, in quarter turns.
    pub(crate) quarter_turns: i64,
    pub(crate) last: (usize, usize),
}

/// A program read from text.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Program {
    pub(crate) blocks: Vec<Block>,
    pub(crate) rotation: Option<Rotation>,
}

/// The motion of one block relative to where it starts, in µm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Step {
    pub(crate) end: (i64, i64),
    /// The arc's centre relative to the start, and counter-clockwise?
    pub(crate) centre: Option<((i64, i64), bool)>,
}

const MAX_NUMBER: i64 = 1_000_000_000;

/// Reads a 3B program: its blocks and its rotation header.
pub(crate) fn parse_3b(text: &str) -> Result<Program, String> {
    parse_program(text, false)
}

/// Reads a 4B program: its blocks (arcs with their `L3`/`L4` prefix) and its rotation header.
/// Only the syntax; [`check_4b`] applies the format's rules on kind and radius.
pub(crate) fn parse_4b(text: &str) -> Result<Program, String> {
    parse_program(text, true)
}

fn parse_program(text: &str, four_b: bool) -> Result<Program, String> {
    let mut blocks = Vec::new();
    let mut rotation = None;
    let mut ended = false;
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() {
            continue;
        }
        if let Some(comment) = trimmed.strip_prefix(';') {
            let comment = comment.trim();
            if comment.to_ascii_uppercase().starts_with("ROTATE") {
                if rotation.is_some() {
                    return Err(format!("line {line}: a second ROTATE header"));
                }
                rotation = Some(parse_rotation(comment, line)?);
            }
            continue;
        }
        if ended {
            return Err(format!("line {line}: a block after DD: {trimmed:?}"));
        }
        if trimmed.eq_ignore_ascii_case("DD") {
            ended = true;
            continue;
        }
        blocks.push(if four_b {
            parse_block_4b(trimmed, line)?
        } else {
            parse_block_3b(trimmed, line)?
        });
    }
    if !ended {
        return Err("the program does not end with DD".to_string());
    }
    if let Some(r) = &rotation {
        let n = blocks.len();
        if r.first.0 != 1
            || r.repeated.0 != r.first.1 + 1
            || r.last.0 != r.repeated.1 + 1
            || r.last.1 != n
        {
            return Err(format!(
                "line {}: the ROTATE header's blocks {}-{}, {}-{}, {}-{} do not cover the program's {} blocks in order",
                r.line, r.first.0, r.first.1, r.repeated.0, r.repeated.1, r.last.0, r.last.1, n
            ));
        }
    }
    Ok(Program { blocks, rotation })
}

/// Parses `BLOCK n` or `BLOCKS a-b` from the words given; returns the range and the words left.
fn parse_range<'a>(
    words: &'a [&'a str],
    line: usize,
) -> Result<((usize, usize), &'a [&'a str]), String> {
    let bad = || format!("line {line}: bad block range in the ROTATE header: {words:?}");
    match words {
        ["BLOCK", n, rest @ ..] => {
            let n: usize = n.parse().map_err(|_| bad())?;
            Ok(((n, n), rest))
        }
        ["BLOCKS", range, rest @ ..] => {
            let (a, b) = range.split_once('-').ok_or_else(bad)?;
            let a: usize = a.parse().map_err(|_| bad())?;
            let b: usize = b.parse().map_err(|_| bad())?;
            if a > b {
                return Err(bad());
            }
            Ok(((a, b), rest))
        }
        _ => Err(bad()),
    }
}

/// Parses `ROTATE: BLOCK 1, THEN BLOCKS 2-N K TIMES TURNED D DEG CLOCKWISE EACH, THEN BLOCK
/// N+1` ("Programs"); D must be a positive multiple of 90.
fn parse_rotation(comment: &str, line: usize) -> Result<Rotation, String> {
    let upper = comment.to_ascii_uppercase();
    let body = upper
        .strip_prefix("ROTATE:")
        .ok_or_else(|| format!("line {line}: a ROTATE header without ':'"))?;
    let parts: Vec<&str> = body.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!(
            "line {line}: the ROTATE header needs three parts: {comment:?}"
        ));
    }
    let words0: Vec<&str> = parts[0].split_whitespace().collect();
    let (first, rest) = parse_range(&words0, line)?;
    if !rest.is_empty() {
        return Err(format!(
            "line {line}: unexpected words {rest:?} in the ROTATE header"
        ));
    }
    let words1: Vec<&str> = parts[1].split_whitespace().collect();
    let words1 = match words1.as_slice() {
        ["THEN", rest @ ..] => rest,
        _ => {
            return Err(format!(
                "line {line}: the ROTATE header's second part must start with THEN"
            ))
        }
    };
    let (repeated, rest) = parse_range(words1, line)?;
    let (times, degrees) = match rest {
        [times, "TIMES", "TURNED", deg, "DEG", "CLOCKWISE", "EACH"] => (*times, *deg),
        _ => {
            return Err(format!(
                "line {line}: expected 'K TIMES TURNED D DEG CLOCKWISE EACH', found {rest:?}"
            ))
        }
    };
    let times: usize = times
        .parse()
        .map_err(|_| format!("line {line}: bad repeat count {times:?} in the ROTATE header"))?;
    let degrees: i64 = degrees.parse().map_err(|_| {
        format!("line {line}: the turn {degrees:?} is not a whole number of degrees")
    })?;
    if degrees <= 0 || degrees % 90 != 0 {
        return Err(format!(
            "line {line}: a turn of {degrees} deg is not a positive multiple of 90"
        ));
    }
    let words2: Vec<&str> = parts[2].split_whitespace().collect();
    let words2 = match words2.as_slice() {
        ["THEN", rest @ ..] => rest,
        _ => {
            return Err(format!(
                "line {line}: the ROTATE header's third part must start with THEN"
            ))
        }
    };
    let (last, rest) = parse_range(words2, line)?;
    if !rest.is_empty() {
        return Err(format!(
            "line {line}: unexpected words {rest:?} in the ROTATE header"
        ));
    }
    Ok(Rotation {
        line,
        first,
        repeated,
        times,
        quarter_turns: degrees / 90,
        last,
    })
}

/// Reads the unsigned decimal number at the start of `s`; returns it and the rest.
fn number(s: &str, what: &str, line: usize) -> Result<(i64, String), String> {
    let digits: String = s.chars().take_while(char::is_ascii_digit).collect();
    if digits.is_empty() {
        return Err(format!("line {line}: {what} is missing its number"));
    }
    if digits.len() > 10 {
        return Err(format!("line {line}: {what} {digits} is too long"));
    }
    let value: i64 = digits
        .parse()
        .map_err(|_| format!("line {line}: {what} {digits} is not a number"))?;
    if value > MAX_NUMBER {
        return Err(format!("line {line}: {what} {value} µm is out of range"));
    }
    Ok((value, s[digits.len()..].to_string()))
}

/// Parses one 3B block `B X B Y B J G Z` (blanks allowed between the words, letters of any
/// case), naming `line` in any error. Only the syntax: the rules are applied by [`replay`].
pub(crate) fn parse_block_3b(text: &str, line: usize) -> Result<Block, String> {
    let s: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_uppercase();
    let rest = s
        .strip_prefix('B')
        .ok_or_else(|| format!("line {line}: a block must start with B: {text:?}"))?;
    let (x, rest) = number(rest, "X", line)?;
    let rest = rest
        .strip_prefix('B')
        .ok_or_else(|| format!("line {line}: expected B before Y: {text:?}"))?;
    let (y, rest) = number(rest, "Y", line)?;
    let rest = rest
        .strip_prefix('B')
        .ok_or_else(|| format!("line {line}: expected B before J: {text:?}"))?;
    let (j, rest) = number(rest, "J", line)?;
    let (g, rest) = if let Some(r) = rest.strip_prefix("GX") {
        (Axis::X, r)
    } else if let Some(r) = rest.strip_prefix("GY") {
        (Axis::Y, r)
    } else {
        return Err(format!("line {line}: expected GX or GY after J: {text:?}"));
    };
    let (kind, digit) = if let Some(r) = rest.strip_prefix("SR") {
        ("SR", r)
    } else if let Some(r) = rest.strip_prefix("NR") {
        ("NR", r)
    } else if let Some(r) = rest.strip_prefix('L') {
        ("L", r)
    } else {
        return Err(format!(
            "line {line}: expected L1-L4, SR1-SR4 or NR1-NR4: {text:?}"
        ));
    };
    let quadrant = match digit {
        "1" => 1,
        "2" => 2,
        "3" => 3,
        "4" => 4,
        _ => {
            return Err(format!(
                "line {line}: bad quadrant {digit:?} after {kind}: {text:?}"
            ))
        }
    };
    let motion = match kind {
        "L" => Motion::Line { quadrant },
        "SR" => Motion::Arc {
            ccw: false,
            quadrant,
        },
        _ => Motion::Arc {
            ccw: true,
            quadrant,
        },
    };
    Ok(Block {
        line,
        x,
        y,
        j,
        g,
        motion,
        convexity: None,
    })
}

/// Parses one 4B block: a plain 3B block (a line), or `L{3|4}{R}` followed by a 3B block (an
/// arc, "The 4B format"). Only the syntax: [`check_4b`] applies the format's rules.
pub(crate) fn parse_block_4b(text: &str, line: usize) -> Result<Block, String> {
    let s: String = text
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_uppercase();
    let Some(prefixed) = s.strip_prefix('L') else {
        return parse_block_3b(&s, line);
    };
    let convex = match prefixed.chars().next() {
        Some('3') => true,
        Some('4') => false,
        _ => {
            return Err(format!(
                "line {line}: a 4B prefix must be L3 or L4: {text:?}"
            ))
        }
    };
    let (radius_um, rest) = number(&prefixed[1..], "R", line)?;
    let mut block = parse_block_3b(&rest, line)?;
    block.convexity = Some(Convexity { convex, radius_um });
    Ok(block)
}

/// The signs (sx, sy) of quadrant n: 1 (+,+), 2 (−,+), 3 (−,−), 4 (+,−).
fn quadrant_signs(q: u8) -> (i64, i64) {
    match q {
        1 => (1, 1),
        2 => (-1, 1),
        3 => (-1, -1),
        _ => (1, -1),
    }
}

/// The quadrant of a nonzero vector with the axes assigned as "The 3B format" assigns them
/// (L1 includes +X, L2 +Y, L3 −X, L4 −Y).
fn quadrant_of(v: (i64, i64)) -> u8 {
    match v {
        (x, y) if x > 0 && y >= 0 => 1,
        (x, y) if x <= 0 && y > 0 => 2,
        (x, y) if x < 0 && y <= 0 => 3,
        _ => 4,
    }
}

/// Turns an integer vector by k quarter turns clockwise: (x, y) → (y, −x) per quarter.
fn turn_cw(v: (i64, i64), k: i64) -> (i64, i64) {
    let mut v = v;
    for _ in 0..k.rem_euclid(4) {
        v = (v.1, -v.0);
    }
    v
}

/// Replays one block as the control runs it, relative to its start (µm). The rules are those of
/// "The 3B format"; see the module documentation.
pub(crate) fn replay(b: &Block) -> Result<Step, String> {
    let line = b.line;
    match b.motion {
        Motion::Line { quadrant } => {
            let (sx, sy) = quadrant_signs(quadrant);
            let d = (sx * b.x, sy * b.y);
            if d != (0, 0) && quadrant_of(d) != quadrant {
                return Err(format!(
                    "line {line}: the line ({}, {}) µm lies in quadrant {}, written L{quadrant}",
                    d.0,
                    d.1,
                    quadrant_of(d)
                ));
            }
            let (axis, count) = if b.x >= b.y {
                (Axis::X, b.x)
            } else {
                (Axis::Y, b.y)
            };
            if b.g != axis {
                return Err(format!(
                    "line {line}: a line of X {} Y {} must count along G{:?}, written G{:?}",
                    b.x, b.y, axis, b.g
                ));
            }
            if b.j != count {
                return Err(format!(
                    "line {line}: a line's J {} is not its larger component {count}",
                    b.j
                ));
            }
            Ok(Step {
                end: d,
                centre: None,
            })
        }
        Motion::Arc { ccw, quadrant } => {
            if b.x == 0 && b.y == 0 {
                return Err(format!("line {line}: an arc of no radius"));
            }
            let (sx, sy) = quadrant_signs(quadrant);
            let s = (sx * b.x, sy * b.y);
            // On an axis the code names the quadrant the arc moves into.
            let expected = if b.x == 0 || b.y == 0 {
                let nudge = if ccw { turn_cw(s, 3) } else { turn_cw(s, 1) };
                quadrant_of((s.0 * 1000 + nudge.0, s.1 * 1000 + nudge.1))
            } else {
                quadrant_of(s)
            };
            if expected != quadrant {
                return Err(format!(
                    "line {line}: an arc starting at ({}, {}) µm from its centre {} moves in quadrant {expected}, written {}{quadrant}",
                    s.0,
                    s.1,
                    if ccw { "counter-clockwise" } else { "clockwise" },
                    if ccw { "NR" } else { "SR" }
                ));
            }
            let (ex, ey) = arc_end(s, ccw, b.g, b.j, line)?;
            let (ax, ay) = (ex.abs(), ey.abs());
            let wrong = match b.g {
                Axis::Y => ax + 2 < ay,
                Axis::X => ax > ay + 2,
            };
            if wrong {
                return Err(format!(
                    "line {line}: the arc ends at ({ex}, {ey}) µm from its centre, which asks for G{}, written G{:?}",
                    if ax > ay { "Y" } else { "X" },
                    b.g
                ));
            }
            Ok(Step {
                end: (ex - s.0, ey - s.1),
                centre: Some(((-s.0, -s.1), ccw)),
            })
        }
    }
}

/// The end (relative to the centre, whole µm) of the arc starting at `s` from its centre that
/// runs until its count `j` along `g` is used up.
fn arc_end(s: (i64, i64), ccw: bool, g: Axis, j: i64, line: usize) -> Result<(i64, i64), String> {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    if j == 0 {
        return Ok(s);
    }
    let (sx, sy) = (s.0 as f64, s.1 as f64);
    let r = sx.hypot(sy);
    let full = 4.0 * r;
    if j as f64 > full + 1.0 {
        return Err(format!(
            "line {line}: the count J {j} is beyond a whole turn ({full:.1} µm along the axis for R {r:.1})"
        ));
    }
    let coord = |t: f64| match g {
        Axis::X => r * t.cos(),
        Axis::Y => r * t.sin(),
    };
    // The counting coordinate turns round where the circle is tangent to it: at 0 and π for X,
    // at ±π/2 for Y.
    let offset = match g {
        Axis::X => 0.0,
        Axis::Y => FRAC_PI_2,
    };
    let dir = if ccw { 1.0 } else { -1.0 };
    let t0 = sy.atan2(sx);
    let t_stop = t0 + dir * TAU;
    // The turning points ahead, counted by an integer so that the walk always advances.
    let k0 = (t0 - offset) / PI;
    let mut k = if ccw {
        k0.floor() + 1.0
    } else {
        k0.ceil() - 1.0
    };
    let mut t = t0;
    let mut remaining = j as f64;
    let angle = loop {
        let mut next = k * PI + offset;
        if (next - t0) * dir >= TAU {
            next = t_stop;
        }
        let travel = (coord(next) - coord(t)).abs();
        if remaining <= travel {
            // Bisection on the monotone piece [t, next] for the travel `remaining`.
            let start = coord(t);
            let (mut lo, mut hi) = (t, next);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if (coord(mid) - start).abs() < remaining {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            break 0.5 * (lo + hi);
        }
        remaining -= travel;
        t = next;
        k += dir;
        if (t - t0) * dir >= TAU {
            // The count is at most 1 µm beyond a whole turn (checked above): the arc closes.
            break t_stop;
        }
    };
    Ok((
        (r * angle.cos()).round() as i64,
        (r * angle.sin()).round() as i64,
    ))
}

/// Checks a 4B program's prefixes ("The 4B format"): every arc has one, no line has one, R is
/// within 2 µm of √(X² + Y²), and L3 (convex) / L4 (concave) agree with the contour's sense:
/// clockwise, SR is L3 and NR is L4; counter-clockwise the other way round.
pub(crate) fn check_4b(program: &Program, sense: Sense) -> Result<(), String> {
    for b in &program.blocks {
        let line = b.line;
        match (b.motion, b.convexity) {
            (Motion::Line { .. }, Some(_)) => {
                return Err(format!("line {line}: a line with an L3/L4 prefix"));
            }
            (Motion::Line { .. }, None) => {}
            (Motion::Arc { .. }, None) => {
                return Err(format!(
                    "line {line}: an arc without its L3/L4 prefix and radius"
                ));
            }
            (Motion::Arc { ccw, .. }, Some(c)) => {
                let radius = (b.x as f64).hypot(b.y as f64);
                if (c.radius_um as f64 - radius).abs() > 2.0 {
                    return Err(format!(
                        "line {line}: R {} µm is not the radius {radius:.1} µm of its X {} and Y {}",
                        c.radius_um, b.x, b.y
                    ));
                }
                let convex_expected = match sense {
                    Sense::Clockwise => !ccw,
                    Sense::CounterClockwise => ccw,
                };
                if c.convex != convex_expected {
                    return Err(format!(
                        "line {line}: {} on a {} arc disagrees with a {} contour",
                        if c.convex { "L3" } else { "L4" },
                        if ccw { "NR" } else { "SR" },
                        match sense {
                            Sense::Clockwise => "clockwise",
                            Sense::CounterClockwise => "counter-clockwise",
                        }
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The order the control runs the blocks in: (index into `blocks`, quarter turns clockwise).
fn schedule(program: &Program) -> Vec<(usize, i64)> {
    match &program.rotation {
        None => (0..program.blocks.len()).map(|i| (i, 0)).collect(),
        Some(r) => {
            let mut order: Vec<(usize, i64)> =
                (r.first.0..=r.first.1).map(|n| (n - 1, 0)).collect();
            for k in 0..r.times {
                let turn = (k as i64) * r.quarter_turns;
                order.extend((r.repeated.0..=r.repeated.1).map(|n| (n - 1, turn)));
            }
            order.extend((r.last.0..=r.last.1).map(|n| (n - 1, 0)));
            order
        }
    }
}

/// Runs a parsed program: every block in the order of the rotation header (if any), each from
/// where the one before really ended, turned blocks turned as a whole (geometry, not codes).
pub(crate) fn run_program(program: &Program) -> Result<Vec<WireMove>, String> {
    let steps = program
        .blocks
        .iter()
        .map(replay)
        .collect::<Result<Vec<Step>, String>>()?;
    let mm = |p: (i64, i64)| (p.0 as f64 / 1000.0, p.1 as f64 / 1000.0);
    let mut at = (0_i64, 0_i64);
    let mut moves = Vec::new();
    for (index, turn) in schedule(program) {
        let step = steps[index];
        let end = turn_cw(step.end, turn);
        let to = (at.0 + end.0, at.1 + end.1);
        let arc = step.centre.map(|(c, ccw)| {
            let c = turn_cw(c, turn);
            (mm((at.0 + c.0, at.1 + c.1)), ccw)
        });
        moves.push(WireMove {
            line: program.blocks[index].line,
            from: mm(at),
            to: mm(to),
            arc,
        });
        at = to;
    }
    Ok(moves)
}

/// Runs a whole 3B program as the control runs it: every block from the first to DD, the
/// `; ROTATE: ...` header (if present) applied as "Programs" describes: block 1, then the given
/// range repeated N times, run k turned by k times the given angle clockwise, then the last
/// block(s).
pub(crate) fn run_3b(text: &str) -> Result<Vec<WireMove>, String> {
    run_program(&parse_3b(text)?)
}

/// The same for 4B, with gearcam's clockwise contours: each arc's L3/L4 and R are checked
/// ([`check_4b`]) and the outline is returned as programmed (the control's offset not applied).
pub(crate) fn run_4b(text: &str) -> Result<Vec<WireMove>, String> {
    run_4b_with_sense(text, Sense::Clockwise)
}

/// [`run_4b`] for a contour of the given sense.
pub(crate) fn run_4b_with_sense(text: &str, sense: Sense) -> Result<Vec<WireMove>, String> {
    let program = parse_4b(text)?;
    check_4b(&program, sense)?;
    run_program(&program)
}

#[cfg(test)]
mod tests {
    use super::*;

    const DIE_3B: &str = include_str!("../golden/die_m2z20_3b.3b");
    const PUNCH_3B: &str = include_str!("../golden/punch_m15z23_3b.3b");
    const PUNCH_4B: &str = include_str!("../golden/punch_m2z20_4b.4b");

    fn close(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9
    }

    fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
        (a.0 - b.0).hypot(a.1 - b.1)
    }

    /// Every move starts where the one before ended, and every arc's end is as far from its
    /// centre as its start, within the µm rounding.
    fn assert_chained(moves: &[WireMove]) {
        assert!(close(moves[0].from, (0.0, 0.0)));
        for w in moves.windows(2) {
            assert!(
                close(w[0].to, w[1].from),
                "line {} does not start where line {} ended",
                w[1].line,
                w[0].line
            );
        }
        for m in moves {
            if let Some((c, _)) = m.arc {
                let (r0, r1) = (dist(m.from, c), dist(m.to, c));
                assert!(
                    (r0 - r1).abs() < 0.001,
                    "line {}: radius {r0} -> {r1}",
                    m.line
                );
            }
        }
    }

    #[test]
    fn published_circle_is_a_full_circle() {
        // "The 3B format": the R 9.9 mm circle from (9.9, 0) counter-clockwise.
        let moves = run_3b("B9900 B0 B39600 GY NR1\nDD\n").expect("the published example reads");
        assert_eq!(
            moves,
            vec![WireMove {
                line: 1,
                from: (0.0, 0.0),
                to: (0.0, 0.0),
                arc: Some(((-9.9, 0.0), true))
            }]
        );
        let block = parse_block_3b("B9900 B0 B39600 GY NR1", 1).expect("parses");
        assert_eq!(
            (block.x, block.y, block.j, block.g),
            (9900, 0, 39600, Axis::Y)
        );
        assert_eq!(
            block.motion,
            Motion::Arc {
                ccw: true,
                quadrant: 1
            }
        );
        // With the G rule swapped the end (9.9, 0) from the centre asks for GY: refused.
        let err = run_3b("B9900 B0 B39600 GX NR1\nDD\n").expect_err("GX is the wrong axis");
        assert!(err.starts_with("line 1:") && err.contains("GY"), "{err}");
        // A count beyond a whole turn is refused.
        let err = run_3b("B9900B0B39602GYNR1\nDD").expect_err("beyond a whole turn");
        assert!(err.contains("whole turn"), "{err}");
    }

    #[test]
    fn partial_arcs_stop_where_their_count_runs_out() {
        // A quarter from (9.9, 0) counter-clockwise: ends at (0, 9.9) from the centre, which
        // asks for GX; X travels 9900.
        let moves = run_3b("B9900B0B9900GXNR1\nDD").expect("reads");
        assert!(close(moves[0].to, (-9.9, 9.9)), "{:?}", moves[0]);
        // Three quarters clockwise from (0, 5) (on +Y, moving into quadrant 1: SR1), counting
        // X: 5000 to +X, 5000 back to 0 at -Y, 5000 to -X: ends at (-5, 0) from the centre,
        // |x| > |y| so GY, whose travel is 5000 + 5000 + 5000 = 15000 as well.
        let moves = run_3b("B0B5000B15000GYSR1\nDD").expect("reads");
        assert!(close(moves[0].to, (-5.0, -5.0)), "{:?}", moves[0]);
        assert_eq!(moves[0].arc, Some(((0.0, -5.0), false)));
        // Half way along a piece: from (3, 4) mm counter-clockwise counting 3000 along X ends on
        // x = 0, y = 5 from the centre (GX since |x| < |y|).
        let moves = run_3b("B3000B4000B3000GXNR1\nDD").expect("reads");
        assert!(close(moves[0].to, (-3.0, 1.0)), "{:?}", moves[0]);
        // Wrong quadrant on an axis: (0, 5) clockwise moves into quadrant 1, not 2.
        let err = run_3b("; x\nB0B5000B5000GYSR2\nDD").expect_err("wrong quadrant");
        assert!(err.starts_with("line 2:"), "{err}");
        let err = run_3b("B0B0B0GXSR1\nDD").expect_err("no radius");
        assert!(err.contains("no radius"), "{err}");
    }

    #[test]
    fn hand_made_square() {
        let text = "; a 10 mm square\nB10000B0B10000GXL1\nB0 B10000 B10000 GY L2\n\nB10000B0B10000GXL3\nB0B10000B10000GYL4\nDD\n";
        let moves = run_3b(text).expect("the square reads");
        let expected = [
            (2, (0.0, 0.0), (10.0, 0.0)),
            (3, (10.0, 0.0), (10.0, 10.0)),
            (5, (10.0, 10.0), (0.0, 10.0)),
            (6, (0.0, 10.0), (0.0, 0.0)),
        ];
        assert_eq!(moves.len(), 4);
        for (m, (line, from, to)) in moves.iter().zip(expected) {
            assert_eq!(
                *m,
                WireMove {
                    line,
                    from,
                    to,
                    arc: None
                }
            );
        }
        // The format's rules on lines are enforced, naming the line.
        for (bad, what) in [
            ("B10000B0B10000GYL1\nDD", "G"), // counts along the smaller component
            ("B10000B0B9999GXL1\nDD", "J"),  // J is not the larger component
            ("B0B10000B10000GYL1\nDD", "quadrant"), // +Y belongs to L2
            ("B10000B0B10000GXL1\n", "DD"),  // no end
            ("B10000B0B10000GXL1\nDD\nB1B1B1GXL1", "after DD"),
            ("B10000B0GXL1\nDD", "B"),
        ] {
            let err = run_3b(bad).expect_err(bad);
            assert!(err.contains(what), "{bad:?}: {err}");
        }
        let err = run_3b("B1B1B1GXL1\nB1B1B1GXL5\nDD").expect_err("L5");
        assert!(err.starts_with("line 2:"), "{err}");
    }

    #[test]
    fn rotation_turns_lines_and_arcs_clockwise() {
        // Lead-in to (0, 5), a line to (5, 0) repeated 4 times turned 90° clockwise each: a
        // diamond (5,0), (0,-5), (-5,0), (0,5); then back to the start hole.
        let text = "; ROTATE: BLOCK 1, THEN BLOCKS 2-2 4 TIMES TURNED 90 DEG CLOCKWISE EACH, THEN BLOCK 3\n\
                    B0B5000B5000GYL2\nB5000B5000B5000GXL4\nB0B5000B5000GYL4\nDD\n";
        let moves = run_3b(text).expect("reads");
        let ends: Vec<(f64, f64)> = moves.iter().map(|m| m.to).collect();
        assert_eq!(
            ends,
            vec![
                (0.0, 5.0),
                (5.0, 0.0),
                (0.0, -5.0),
                (-5.0, 0.0),
                (0.0, 5.0),
                (0.0, 0.0)
            ]
        );
        assert_eq!(
            moves.iter().map(|m| m.line).collect::<Vec<_>>(),
            vec![2, 3, 3, 3, 3, 4]
        );
        // The same with a clockwise quarter arc about the start hole: a whole circle, each turned
        // copy with the same centre.
        let text = "; ROTATE: BLOCK 1, THEN BLOCKS 2-2 4 TIMES TURNED 90 DEG CLOCKWISE EACH, THEN BLOCK 3\n\
                    B0B5000B5000GYL2\nB0B5000B5000GYSR1\nB0B5000B5000GYL4\nDD\n";
        let moves = run_3b(text).expect("reads");
        let ends: Vec<(f64, f64)> = moves.iter().map(|m| m.to).collect();
        assert_eq!(
            ends,
            vec![
                (0.0, 5.0),
                (5.0, 0.0),
                (0.0, -5.0),
                (-5.0, 0.0),
                (0.0, 5.0),
                (0.0, 0.0)
            ]
        );
        for m in &moves[1..5] {
            assert_eq!(m.arc, Some(((0.0, 0.0), false)));
        }
        // Half turns: a line (5, -5) run twice, the second turned 180°.
        let text = "; ROTATE: BLOCKS 1-1, THEN BLOCK 2 2 TIMES TURNED 180 DEG CLOCKWISE EACH, THEN BLOCK 3\n\
                    B0B5000B5000GYL2\nB5000B5000B5000GXL4\nB0B5000B5000GYL4\nDD\n";
        let ends: Vec<(f64, f64)> = run_3b(text).expect("reads").iter().map(|m| m.to).collect();
        assert_eq!(ends, vec![(0.0, 5.0), (5.0, 0.0), (0.0, 5.0), (0.0, 0.0)]);
        // Headers that do not fit are refused with their line.
        for bad in [
            "; ROTATE: BLOCK 1, THEN BLOCKS 2-2 4 TIMES TURNED 45 DEG CLOCKWISE EACH, THEN BLOCK 3\nB1B1B1GXL1\nB1B1B1GXL1\nB1B1B1GXL1\nDD",
            "; ROTATE: BLOCK 1, THEN BLOCKS 2-3 4 TIMES TURNED 90 DEG CLOCKWISE EACH, THEN BLOCK 4\nB1B1B1GXL1\nB1B1B1GXL1\nB1B1B1GXL1\nDD",
            "; ROTATE: BLOCK 1, THEN BLOCKS 2-2 4 TIMES, THEN BLOCK 3\nB1B1B1GXL1\nB1B1B1GXL1\nB1B1B1GXL1\nDD",
        ] {
            let err = run_3b(bad).expect_err(bad);
            assert!(err.starts_with("line 1:"), "{err}");
        }
    }

    #[test]
    fn seed_4b_examples() {
        // "The 4B format": the first reads as L3, R 38750, X 7718, Y 37973, J 79483, GX, NR1.
        let first = "L338750B7718B37973B079483GXNR1";
        let b = parse_block_4b(first, 1).expect("the first example reads");
        assert_eq!(
            b.convexity,
            Some(Convexity {
                convex: true,
                radius_um: 38750
            })
        );
        assert_eq!((b.x, b.y, b.j, b.g), (7718, 37973, 79483, Axis::X));
        assert_eq!(
            b.motion,
            Motion::Arc {
                ccw: true,
                quadrant: 1
            }
        );
        // L3 on NR is a counter-clockwise contour's block: refused on gearcam's clockwise ones,
        // run on a counter-clockwise one. R = √(7718² + 37973²) = 38749.4: X runs 7718 + r to
        // -r, then 33015.6 back: x = -5733.9, y = -38322.8 from the centre.
        let program = format!("{first}\nDD\n");
        let err = run_4b(&program).expect_err("L3 on NR on a clockwise contour");
        assert!(err.starts_with("line 1:") && err.contains("L3"), "{err}");
        let moves =
            run_4b_with_sense(&program, Sense::CounterClockwise).expect("counter-clockwise");
        assert_eq!(moves.len(), 1);
        assert!(close(moves[0].to, (-13.452, -76.296)), "{:?}", moves[0]);
        assert_eq!(moves[0].arc, Some(((-7.718, -37.973), true)));
        // The second reads, but its R 808 is not the 38,750 µm of its X and Y: refused either way.
        let second = "L4808B5735B38323B000385GXSR1";
        let b = parse_block_4b(second, 3).expect("the second example reads");
        assert_eq!(
            b.convexity,
            Some(Convexity {
                convex: false,
                radius_um: 808
            })
        );
        assert_eq!((b.x, b.y, b.j, b.g), (5735, 38323, 385, Axis::X));
        assert_eq!(
            b.motion,
            Motion::Arc {
                ccw: false,
                quadrant: 1
            }
        );
        for sense in [Sense::Clockwise, Sense::CounterClockwise] {
            let err =
                run_4b_with_sense(&format!("; seed\n{second}\nDD"), sense).expect_err("R 808");
            assert!(err.starts_with("line 2:") && err.contains("R 808"), "{err}");
        }
        // An arc without a kind, a line with one.
        let err = run_4b("B0B5000B5000GYSR1\nDD").expect_err("no kind");
        assert!(err.contains("without"), "{err}");
        let err = run_4b("L35000B5000B0B5000GXL1\nDD").expect_err("a line with a kind");
        assert!(err.contains("a line with"), "{err}");
        // A clockwise circle of R 5 as 4B: convex, L3 on SR.
        let moves = run_4b("L35000B0B5000B20000GXSR1\nDD").expect("a clockwise circle");
        assert_eq!(moves[0].to, (0.0, 0.0));
        assert_eq!(moves[0].arc, Some(((0.0, -5.0), false)));
    }

    /// Distance of every block end (after the lead-in, before the lead-out) from the gear's
    /// centre lies within [lo, hi] mm.
    fn assert_between(moves: &[WireMove], centre: (f64, f64), lo: f64, hi: f64) {
        for m in &moves[1..moves.len() - 1] {
            let r = dist(m.to, centre);
            assert!(r > lo && r < hi, "line {}: radius {r}", m.line);
        }
    }

    #[test]
    fn golden_die_m2z20_3b() {
        let program = parse_3b(DIE_3B).expect("parses");
        assert_eq!(program.blocks.len(), 87);
        assert_eq!(
            program.rotation,
            Some(Rotation {
                line: 13,
                first: (1, 1),
                repeated: (2, 86),
                times: 4,
                quarter_turns: 1,
                last: (87, 87)
            })
        );
        let moves = run_3b(DIE_3B).expect("runs");
        assert_eq!(moves.len(), 1 + 4 * 85 + 1);
        assert_chained(&moves);
        // Lead-in from the opening's centre to the tooth's middle on +Y at the tip radius 22
        // less the offset 0.1.
        assert_eq!(moves[0].to, (0.0, 21.9));
        // The quarter ends on +X, each section a quarter turn further, the fourth back on +Y.
        assert_eq!(moves[85].to, (21.9, 0.0));
        assert_eq!(moves[170].to, (0.0, -21.9));
        assert_eq!(moves[255].to, (-21.9, 0.0));
        assert_eq!(moves[340].to, (0.0, 21.9));
        // The wire runs inside the opening: every block end between the root circle 17.5 and
        // the tip circle 22, each less the offset 0.1 (the gear's centre is the start hole).
        assert_between(&moves, (0.0, 0.0), 17.4 - 0.001, 21.9 + 0.001);
        // The last block, the lead-out, runs from where the fourth section ended straight back
        // to the start hole.
        assert_eq!(moves[341].line, 101);
        assert_eq!(moves[341].to, (0.0, 0.0));
        // Written from where the *first* quarter ended, (21.9, 0), as it once was, the same
        // block leaves the wire at (-21.9, 21.9), 30.97 mm from the start hole.
        let old = DIE_3B.replace("B0B21900B21900GYL4", "B21900B0B21900GXL3");
        let moves = run_3b(&old).expect("runs");
        assert_eq!(moves[341].to, (-21.9, 21.9));
    }

    #[test]
    fn golden_punch_m2z20_4b() {
        let program = parse_4b(PUNCH_4B).expect("parses");
        assert_eq!(program.blocks.len(), 87);
        assert_eq!(
            program.rotation,
            Some(Rotation {
                line: 13,
                first: (1, 1),
                repeated: (2, 86),
                times: 4,
                quarter_turns: 1,
                last: (87, 87)
            })
        );
        let arcs = program
            .blocks
            .iter()
            .filter(|b| b.convexity.is_some())
            .count();
        assert_eq!(arcs, 85);
        let moves = run_4b(PUNCH_4B).expect("runs");
        assert_eq!(moves.len(), 342);
        assert_chained(&moves);
        // The start hole is 5 mm outside the tip circle (22) on +Y: the gear's centre is
        // (0, -27); the lead-in reaches the outline's tip on +Y.
        let centre = (0.0, -27.0);
        assert_eq!(moves[0].to, (0.0, -5.0));
        assert_eq!(moves[85].to, (22.0, -27.0));
        assert_eq!(moves[170].to, (0.0, -49.0));
        assert_eq!(moves[255].to, (-22.0, -27.0));
        assert_eq!(moves[340].to, (0.0, -5.0));
        // The outline (no offset) lies between the root circle 17.5 and the tip circle 22.
        assert_between(&moves, centre, 17.5 - 0.001, 22.0 + 0.001);
        // The lead-out runs from where the fourth section ended, (0, -5), back up to the start
        // hole.
        assert_eq!(moves[341].line, 101);
        assert_eq!(moves[341].to, (0.0, 0.0));
        // Written from the first quarter's end (22, -27), as it once was, the lead-out
        // B22000B27000B27000GYL2 ends at (-22, 22) instead.
        let old = PUNCH_4B.replace("B0B5000B5000GYL2", "B22000B27000B27000GYL2");
        let moves = run_4b(&old).expect("runs");
        assert_eq!(moves[341].to, (-22.0, 22.0));
    }

    #[test]
    fn golden_punch_m15z23_3b() {
        let program = parse_3b(PUNCH_3B).expect("parses");
        assert_eq!(program.rotation, None);
        assert_eq!(program.blocks.len(), 347);
        let moves = run_3b(PUNCH_3B).expect("runs");
        assert_eq!(moves.len(), 347);
        assert_chained(&moves);
        // Start hole 5 mm outside the tip circle 18.75 on +Y: the gear's centre is (0, -23.75);
        // the lead-in reaches the wire's path at 18.75 + 0.1.
        let centre = (0.0, -23.75);
        assert_eq!(moves[0].to, (0.0, -4.899));
        assert!((dist(moves[0].to, centre) - 18.851).abs() < 1e-9);
        assert_between(&moves, centre, 15.375 + 0.1 - 0.001, 18.85 + 0.002);
        // The whole outline closes where the lead-in ended and the lead-out returns to the hole.
        assert_eq!(moves[345].to, (0.0, -4.899));
        assert_eq!(moves[346].to, (0.0, 0.0));
    }
}
