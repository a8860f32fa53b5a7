//! ISO wire G-code (FANUC-like wire controls, docs/wire.md): the part
//! outline with the control's wire compensation, written and replayed.
//!
//! The program, in mm, absolute, 4 decimals:
//!
//! ```text
//! %
//! O1000                      program number
//! (…)                        the caller's header lines as comments
//! G90 G17 G21                absolute, XY plane, mm
//! G92 X… Y…                  the wire is at the start hole
//! G10 L12 P1 R…              offset register 1 = wire radius + spark gap
//! G41 D1 G01 X… Y…           lead-in, compensation on (G41 punch, G42 die)
//! G01 X… Y…                  a line to its end
//! G02 X… Y… I… J…            a clockwise arc (G03 counter-clockwise) to its
//!                            end, I J its centre from its start
//! G40 G01 X… Y…              lead-out to the start hole, compensation off
//! M02
//! %
//! ```
//!
//! The contour runs clockwise about the gear (material on the right): a
//! punch is cut with the wire on the left of the travel (`G41`), a die with
//! it on the right (`G42`). A program of a section repeated by turns (a
//! quarter of the teeth) keeps the section in subprogram `O{number + 1}`,
//! ending `M99` after the main's `M02`, and calls it once per turn with the
//! wire compensated throughout:
//!
//! ```text
//! G68 X0 Y0 R{k·deg}    (k = 0 … n − 1)
//! M98 P{number + 1}
//! G69
//! ```
//!
//! [`replay`] interprets exactly this subset (G00 G01 G02 G03 with I J,
//! G10 L12 P R, G17, G21, G40 G41 G42 with D, G68 X Y R and G69, G90, G92,
//! M02 M30, M98 P and M99 within the same text, O numbers, comments, `%`)
//! and refuses any other word, naming its line.

use gearcam_geom::plane::rotate_about;
use std::collections::HashMap;
use std::fmt::Write as _;

use crate::Segment;

/// The side of the travel the wire is kept on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// On the left of the travel, `G41`: a punch, the wire outside the gear.
    Left,
    /// On the right of the travel, `G42`: a die, the wire inside the gear.
    Right,
}

/// What an ISO program is made of.
#[derive(Debug, Clone, PartialEq)]
pub struct IsoProgram {
    /// The program number, `O` (the subprogram takes the next one).
    pub number: u32,
    /// Header lines, written as comments (parentheses in them become
    /// brackets).
    pub header: Vec<String>,
    /// The start hole: where the wire is threaded, and the lead-in's start.
    pub start_hole: (f64, f64),
    /// The part outline, closed, clockwise about the gear; with `repeat`,
    /// one section of it.
    pub contour: Vec<Segment>,
    /// The compensation side.
    pub side: Side,
    /// Wire radius + spark gap, mm: register `D1`.
    pub offset_mm: f64,
    /// The section run `n` times, turned by `k·deg` degrees (counter-
    /// clockwise positive) the k-th time; the section's end must be its
    /// start turned by `deg`.
    pub repeat: Option<(u32, f64)>,
}

/// A number with 4 decimals, without a minus on zero.
fn n(v: f64) -> String {
    let s = format!("{v:.4}");
    if s == "-0.0000" {
        "0.0000".into()
    } else {
        s
    }
}

/// The value a number is written as.
fn grid(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

/// The moves of a contour from the written position `at`.
fn moves(p: &mut String, contour: &[Segment], mut at: (f64, f64)) {
    for s in contour {
        let to = (grid(s.to().0), grid(s.to().1));
        let _ = match *s {
            Segment::Line { .. } => writeln!(p, "G01 X{} Y{}", n(to.0), n(to.1)),
            Segment::Arc { centre, ccw, .. } => writeln!(
                p,
                "{} X{} Y{} I{} J{}",
                if ccw { "G03" } else { "G02" },
                n(to.0),
                n(to.1),
                n(centre.0 - at.0),
                n(centre.1 - at.1)
            ),
        };
        at = to;
    }
}

/// The program text.
pub fn program(prog: &IsoProgram) -> String {
    let mut p = String::from("%\n");
    let _ = writeln!(p, "O{:04}", prog.number);
    for h in &prog.header {
        let h: String = h
            .chars()
            .map(|c| match c {
                '(' => '[',
                ')' => ']',
                '\n' | '\r' => ' ',
                c => c,
            })
            .collect();
        let _ = writeln!(p, "({h})");
    }
    let hole = prog.start_hole;
    let first = prog.contour.first().map_or(hole, Segment::from);
    let first = (grid(first.0), grid(first.1));
    let g = match prog.side {
        Side::Left => "G41",
        Side::Right => "G42",
    };
    let _ = writeln!(p, "G90 G17 G21");
    let _ = writeln!(p, "G92 X{} Y{}", n(hole.0), n(hole.1));
    let _ = writeln!(p, "G10 L12 P1 R{}", n(prog.offset_mm));
    let _ = writeln!(p, "{g} D1 G01 X{} Y{}", n(first.0), n(first.1));
    match prog.repeat {
        None => moves(&mut p, &prog.contour, first),
        Some((times, deg)) => {
            for k in 0..times {
                let _ = writeln!(p, "G68 X0 Y0 R{}", n(f64::from(k) * deg));
                let _ = writeln!(p, "M98 P{}", prog.number + 1);
                let _ = writeln!(p, "G69");
            }
        }
    }
    let _ = writeln!(p, "G40 G01 X{} Y{}", n(hole.0), n(hole.1));
    p.push_str("M02\n");
    if prog.repeat.is_some() {
        let _ = writeln!(p, "O{:04}", prog.number + 1);
        moves(&mut p, &prog.contour, first);
        p.push_str("M99\n");
    }
    p.push_str("%\n");
    p
}

/// One programmed move, in the machine frame (turns applied).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Move {
    /// The programmed path (the outline, before compensation).
    pub segment: Segment,
    /// The compensation side in force.
    pub side: Option<Side>,
    /// The offset in force (the D register's value), mm; `None` without
    /// compensation.
    pub offset_mm: Option<f64>,
    /// A rapid move (`G00`).
    pub rapid: bool,
    /// The 1-based line that made it.
    pub line: usize,
}

/// A program followed as the control does.
#[derive(Debug, Clone, PartialEq)]
pub struct Replay {
    /// Where the program starts: the last `G92` before the first move.
    pub start: (f64, f64),
    /// Every move, in order.
    pub moves: Vec<Move>,
}

impl Replay {
    /// The programmed path.
    pub fn path(&self) -> Vec<Segment> {
        self.moves.iter().map(|m| m.segment).collect()
    }
}

/// A program that cannot be replayed, with its line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong, naming the word.
    pub message: String,
}

/// A line's words, its comments gone.
#[derive(Debug)]
struct Statement {
    line: usize,
    words: Vec<(char, f64)>,
}

/// Splits a line into words (a letter and a number); comments in
/// parentheses are dropped.
fn words(raw: &str, line: usize) -> Result<Vec<(char, f64)>, ReadError> {
    let err = |message: String| ReadError { line, message };
    let mut out = Vec::new();
    let mut chars = raw.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            c if c.is_whitespace() => {}
            '(' => {
                if !chars.by_ref().any(|c| c == ')') {
                    return Err(err("a comment without its )".into()));
                }
            }
            c if c.is_ascii_alphabetic() => {
                let mut num = String::new();
                while let Some(&d) = chars.peek() {
                    if d.is_ascii_digit() || d == '.' || d == '-' || d == '+' {
                        num.push(d);
                        chars.next();
                    } else {
                        break;
                    }
                }
                let v: f64 = num
                    .parse()
                    .map_err(|_| err(format!("word {c} without a number: {raw}")))?;
                out.push((c.to_ascii_uppercase(), v));
            }
            c => return Err(err(format!("unexpected {c:?}: {raw}"))),
        }
    }
    Ok(out)
}

/// Follows a program as the control does and returns the programmed path.
pub fn replay(text: &str) -> Result<Replay, ReadError> {
    // Statements, and where each O number's program starts.
    let mut stmts: Vec<Statement> = Vec::new();
    let mut programs: HashMap<u32, usize> = HashMap::new();
    let mut main = None;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        if raw.trim() == "%" {
            continue;
        }
        let w = words(raw, line)?;
        if w.is_empty() {
            continue;
        }
        if w[0].0 == 'O' {
            if w.len() > 1 || w[0].1 < 0.0 || w[0].1.fract() != 0.0 {
                return Err(ReadError {
                    line,
                    message: format!("an O line holds its number only: {raw}"),
                });
            }
            programs.insert(w[0].1 as u32, stmts.len());
            main.get_or_insert(stmts.len());
            continue;
        }
        stmts.push(Statement { line, words: w });
    }
    run(&stmts, &programs, main.unwrap_or(0))
}

/// The control's state while it runs.
#[derive(Debug, Default)]
struct State {
    at: (f64, f64),
    motion: Option<u8>,
    side: Option<Side>,
    d: Option<u32>,
    registers: HashMap<u32, f64>,
    turn: Option<((f64, f64), f64)>,
}

fn run(
    stmts: &[Statement],
    programs: &HashMap<u32, usize>,
    start: usize,
) -> Result<Replay, ReadError> {
    let mut st = State::default();
    let mut moves = Vec::new();
    let mut calls: Vec<usize> = Vec::new();
    let mut pc = start;
    let mut steps = 0usize;
    loop {
        let Some(s) = stmts.get(pc) else {
            let line = stmts.last().map_or(0, |s| s.line);
            return Err(ReadError {
                line,
                message: "the program ends without M02 or M30".into(),
            });
        };
        steps += 1;
        if steps > 1_000_000 || calls.len() > 16 {
            return Err(ReadError {
                line: s.line,
                message: "subprogram calls nest or loop too deep".into(),
            });
        }
        pc += 1;
        match statement(s, &mut st, &mut moves)? {
            Flow::Next => {}
            Flow::End => {
                if st.turn.is_some() {
                    return Err(ReadError {
                        line: s.line,
                        message:
                            "the program ends with G68 in force (no G69 after the turned section)"
                                .into(),
                    });
                }
                if !calls.is_empty() {
                    return Err(ReadError {
                        line: s.line,
                        message: "M02/M30 in a subprogram (it returns with M99)".into(),
                    });
                }
                // Before its first move only G92 sets where the wire is.
                let start = moves.first().map_or(st.at, |m: &Move| m.segment.from());
                return Ok(Replay { start, moves });
            }
            Flow::Call(p) => {
                let Some(&at) = programs.get(&p) else {
                    return Err(ReadError {
                        line: s.line,
                        message: format!("M98 P{p}: no program O{p} in the text"),
                    });
                };
                calls.push(pc);
                pc = at;
            }
            Flow::Return => {
                pc = calls.pop().ok_or_else(|| ReadError {
                    line: s.line,
                    message: "M99 outside a subprogram".into(),
                })?;
            }
        }
    }
}

/// Where the control goes after a statement.
#[derive(Debug)]
enum Flow {
    Next,
    End,
    Call(u32),
    Return,
}

/// One statement's effect on the state and the path.
fn statement(s: &Statement, st: &mut State, moves: &mut Vec<Move>) -> Result<Flow, ReadError> {
    let line = s.line;
    let err = |message: String| ReadError { line, message };
    let mut gs: Vec<u32> = Vec::new();
    let mut val: HashMap<char, f64> = HashMap::new();
    let mut m = None;
    for &(c, v) in &s.words {
        let int = || -> Result<u32, ReadError> {
            if v >= 0.0 && v.fract() == 0.0 && v < 1e6 {
                Ok(v as u32)
            } else {
                Err(err(format!("{c}{v}: a whole number")))
            }
        };
        match c {
            'G' => {
                let g = int()?;
                if !matches!(g, 0..=3 | 10 | 17 | 21 | 40..=42 | 68 | 69 | 90 | 92) {
                    return Err(err(format!("G{g} is not in the subset")));
                }
                gs.push(g);
            }
            'M' => {
                let code = int()?;
                if !matches!(code, 2 | 30 | 98 | 99) || m.replace(code).is_some() {
                    return Err(err(format!("M{code} is not in the subset or not alone")));
                }
            }
            'X' | 'Y' | 'I' | 'J' | 'R' | 'L' | 'P' | 'D' => {
                if val.insert(c, v).is_some() {
                    return Err(err(format!("word {c} twice")));
                }
            }
            c => return Err(err(format!("word {c}{v} is not in the subset"))),
        }
    }
    let has = |g: u32| gs.contains(&g);
    let take = |val: &mut HashMap<char, f64>, c: char| val.remove(&c);
    if has(10) {
        let (l, p, r) = (
            take(&mut val, 'L'),
            take(&mut val, 'P'),
            take(&mut val, 'R'),
        );
        match (l, p, r) {
            (Some(l), Some(p), Some(r)) if l == 12.0 && p >= 0.0 && p.fract() == 0.0 => {
                st.registers.insert(p as u32, r);
            }
            _ => return Err(err("G10 takes L12 P{register} R{value}".into())),
        }
    }
    for &g in &gs {
        match g {
            0..=3 => st.motion = Some(g as u8),
            40 => st.side = None,
            41 => st.side = Some(Side::Left),
            42 => st.side = Some(Side::Right),
            69 => st.turn = None,
            _ => {}
        }
    }
    if let Some(d) = take(&mut val, 'D') {
        if d < 0.0 || d.fract() != 0.0 {
            return Err(err(format!("D{d}: a register number")));
        }
        st.d = Some(d as u32);
    }
    if has(92) {
        if st.turn.is_some() {
            return Err(err("G92 under G68".into()));
        }
        // A control shifts its coordinates by a later G92; the programs in
        // this subset set the start once, before any move.
        if !moves.is_empty() {
            return Err(err("G92 after the first move".into()));
        }
        st.at = (
            take(&mut val, 'X').unwrap_or(st.at.0),
            take(&mut val, 'Y').unwrap_or(st.at.1),
        );
    }
    if has(68) {
        if st.turn.is_some() {
            return Err(err("G68 while a G68 is in force (no G69 before it)".into()));
        }
        let c = (
            take(&mut val, 'X').unwrap_or(st.at.0),
            take(&mut val, 'Y').unwrap_or(st.at.1),
        );
        let r = take(&mut val, 'R').ok_or_else(|| err("G68 takes R{degrees}".into()))?;
        st.turn = Some((c, r.to_radians()));
    }
    let p = if m == Some(98) {
        take(&mut val, 'P')
    } else {
        None
    };
    let (x, y) = (take(&mut val, 'X'), take(&mut val, 'Y'));
    let (i, j) = (take(&mut val, 'I'), take(&mut val, 'J'));
    if let Some((&c, v)) = val.iter().next() {
        return Err(err(format!("word {c}{v} has no meaning here")));
    }
    if x.is_some() || y.is_some() {
        motion(st, moves, line, (x, y), (i, j))?;
    } else if i.is_some() || j.is_some() {
        return Err(err("I or J without X or Y".into()));
    }
    Ok(match m {
        Some(2 | 30) => Flow::End,
        Some(98) => {
            let p = p.ok_or_else(|| err("M98 takes P{program}".into()))?;
            if p < 0.0 || p.fract() != 0.0 {
                return Err(err(format!("M98 P{p}: a program number")));
            }
            Flow::Call(p as u32)
        }
        Some(_) => Flow::Return,
        None => Flow::Next,
    })
}

/// A move to X Y (absolute, in the turned frame), with I J for an arc.
fn motion(
    st: &mut State,
    moves: &mut Vec<Move>,
    line: usize,
    (x, y): (Option<f64>, Option<f64>),
    (i, j): (Option<f64>, Option<f64>),
) -> Result<(), ReadError> {
    let err = |message: String| ReadError { line, message };
    let (c, a) = st.turn.unwrap_or(((0.0, 0.0), 0.0));
    let here = rotate_about(st.at, c, -a);
    let end = (x.unwrap_or(here.0), y.unwrap_or(here.1));
    let to = rotate_about(end, c, a);
    let offset_mm = match (st.side, st.d) {
        (None, _) => None,
        (Some(_), None) => return Err(err("compensation without a D register".into())),
        (Some(_), Some(d)) => Some(
            *st.registers
                .get(&d)
                .ok_or_else(|| err(format!("D{d} has no value (G10 L12 P{d} R…)")))?,
        ),
    };
    let segment = match st.motion {
        None => return Err(err("a move before G00, G01, G02 or G03".into())),
        Some(g @ (0 | 1)) => {
            if i.is_some() || j.is_some() {
                return Err(err(format!("I or J on G0{g}")));
            }
            Segment::Line { from: st.at, to }
        }
        Some(g) => {
            let centre = (here.0 + i.unwrap_or(0.0), here.1 + j.unwrap_or(0.0));
            let centre = rotate_about(centre, c, a);
            let (r0, r1) = (
                (st.at.0 - centre.0).hypot(st.at.1 - centre.1),
                (to.0 - centre.0).hypot(to.1 - centre.1),
            );
            // A control alarms when the end is off the circle; 5 µm is a
            // usual limit.
            if (r0 - r1).abs() > 0.005 {
                return Err(err(format!(
                    "G0{g}: the start is {r0:.4} mm from the centre, the end {r1:.4} mm"
                )));
            }
            Segment::Arc {
                from: st.at,
                to,
                centre,
                ccw: g == 3,
            }
        }
    };
    moves.push(Move {
        segment,
        side: st.side,
        offset_mm,
        rapid: st.motion == Some(0),
        line,
    });
    st.at = to;
    Ok(())
}
