//! A FANUC Macro B interpreter for the subset gearcam emits, to replay a
//! macro program and compare its path with the model. It knows nothing of
//! spirals: it reads the program as a control would.
//!
//! Subset: `#n=expr` (local and common variables), arithmetic `+ - * /`
//! with `[ ]`, functions `SIN COS TAN ATAN SQRT ABS ROUND FIX FUP`
//! (degrees, as on the control), comparisons `EQ NE GT GE LT LE` with
//! `AND OR`, `WHILE [cond] DOm` … `ENDm`, arcs with `I J` (centre from the start), `IF [cond] GOTOn`, `GOTOn`, `Nn`
//! sequence numbers, `G00 G01 G02 G03 G15 G16 G17 G21 G90 G91 G94` (other G codes
//! are accepted and ignored), axis words `X Y Z` and `F S M` with a number,
//! `#n` or `[expr]`, comments in parentheses, `%` and `O` lines. Under
//! `G16` X is the radius and Y the angle about the origin. Macro calls:
//! `G65 P#### <arguments>` runs program `O####` with the argument letters
//! in its local variables (#1–#33, the caller's kept and restored, FANUC
//! argument specification I) until `M99`; `M30` ends the main program.

use std::collections::HashMap;

use crate::macrob_expr::{eval, var};

/// A move the program commands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Move {
    /// `true` for `G01`/`G02`/`G03`, `false` for `G00`.
    pub feed: bool,
    /// For `G02`/`G03`: the centre (absolute) and whether counter-clockwise.
    pub arc: Option<((f64, f64), bool)>,
    /// End point, mm.
    pub x: f64,
    /// End point, mm.
    pub y: f64,
    /// End point, mm.
    pub z: f64,
}

/// A replay error: the line (1-based) and what is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayError {
    /// Program line, 1-based.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

struct Machine {
    vars: HashMap<u32, f64>,
    /// 0, 1, 2 or 3: the modal motion.
    motion: u8,
    polar: bool,
    absolute: bool,
    feed_mode: bool,
    /// Cartesian position.
    pos: (f64, f64, f64),
    /// The polar words last given (radius, angle), as the control keeps them.
    polar_words: (f64, f64),
    moves: Vec<Move>,
}

/// Replays `program`; the moves, or the first error. `budget` bounds the
/// blocks executed (a runaway loop stops there).
pub fn replay(program: &str, budget: usize) -> Result<Vec<Move>, ReplayError> {
    let listing = Listing::read(program);
    let mut control = Control::new();
    let err = |line: usize, message: String| ReplayError {
        line: line + 1,
        message,
    };
    let mut steps = 0;
    while control.pc < listing.lines.len() {
        steps += 1;
        if steps > budget {
            return Err(err(
                control.pc,
                format!("more than {budget} blocks: a runaway loop?"),
            ));
        }
        let at = control.pc;
        if !control.step(&listing).map_err(|e| err(at, e))? {
            break;
        }
    }
    if let Some((id, _)) = control.loops.pop() {
        return Err(err(listing.lines.len() - 1, format!("DO{id} never ended")));
    }
    Ok(control.m.moves)
}

/// A program read for replay: its lines without comments, and where each
/// sequence number `Nn` (for `GOTOn`) and each program `O####` (for
/// `G65 P####`) stands.
struct Listing {
    lines: Vec<String>,
    labels: HashMap<u32, usize>,
    programs: HashMap<u32, usize>,
}

impl Listing {
    /// The program's lines, comments stripped, and its labels and programs.
    fn read(program: &str) -> Listing {
        let lines: Vec<String> = program.lines().map(strip_comments).collect();
        let labels: HashMap<u32, usize> = lines
            .iter()
            .enumerate()
            .filter_map(|(i, l)| {
                let t = l.trim();
                let rest = t.strip_prefix('N')?;
                let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
                digits.parse().ok().map(|n| (n, i))
            })
            .collect();
        let programs: HashMap<u32, usize> = lines
            .iter()
            .enumerate()
            .filter_map(|(i, l)| {
                let rest = l.trim().strip_prefix('O')?;
                let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
                digits.parse().ok().map(|n| (n, i))
            })
            .collect();
        Listing {
            lines,
            labels,
            programs,
        }
    }

    /// The line that sequence number `N{target}` starts.
    fn label(&self, target: u32) -> Result<usize, String> {
        self.labels
            .get(&target)
            .copied()
            .ok_or_else(|| format!("no N{target}"))
    }
}

/// The control running a listing: the machine, the open `WHILE` loops (id
/// and line), the macro call stack and the line it is at (`pc`).
struct Control {
    m: Machine,
    loops: Vec<(u32, usize)>,
    frames: Vec<Frame>,
    pc: usize,
}

impl Control {
    /// The control at the first line: no variable set, G00, absolute,
    /// Cartesian, at the origin.
    fn new() -> Control {
        Control {
            m: Machine {
                vars: HashMap::new(),
                motion: 0,
                polar: false,
                absolute: true,
                feed_mode: false,
                pos: (0.0, 0.0, 0.0),
                polar_words: (0.0, 0.0),
                moves: Vec::new(),
            },
            loops: Vec::new(),
            frames: Vec::new(),
            pc: 0,
        }
    }

    /// Runs the line at `pc` as the control would and moves `pc` to the
    /// next line to run; `false` when the main program ends (M30, M02).
    /// An error is the message for this line.
    fn step(&mut self, p: &Listing) -> Result<bool, String> {
        let line = strip_sequence(p.lines[self.pc].trim());
        if line.is_empty() || line == "%" || line.starts_with('O') {
            if line.starts_with('O')
                && self.pc > 0
                && self.frames.is_empty()
                && !self.m.moves.is_empty()
            {
                // The main program ran into the next program without M30.
                return Err("the main program ran into another program: M30 missing".into());
            }
            self.pc += 1;
        } else if line == "M30" || line == "M02" || line == "M2" {
            return Ok(false);
        } else if line == "M99" {
            self.macro_return()?;
        } else if let Some(rest) = line.strip_prefix("G65") {
            self.macro_call(p, rest)?;
        } else if let Some(rest) = line.strip_prefix("WHILE") {
            self.while_do(p, line, rest)?;
        } else if let Some(id) = line.strip_prefix("END") {
            self.end(line, id)?;
        } else if let Some(rest) = line.strip_prefix("IF") {
            self.if_goto(p, line, rest)?;
        } else if let Some(target) = line.strip_prefix("GOTO") {
            let target: u32 = target
                .trim()
                .parse()
                .map_err(|_| format!("bad GOTO: {line}"))?;
            self.pc = p.label(target)?;
        } else if let Some(rest) = line.strip_prefix('#') {
            let (var, expr) = rest
                .split_once('=')
                .ok_or_else(|| format!("not an assignment: {line}"))?;
            let n: u32 = var
                .trim()
                .parse()
                .map_err(|_| format!("bad variable: {line}"))?;
            let v = eval(&self.m.vars, expr)?;
            self.m.vars.insert(n, v);
            self.pc += 1;
        } else {
            block(&mut self.m, line)?;
            self.pc += 1;
        }
        Ok(true)
    }

    /// `M99`: back to the caller of the macro, with its local variables
    /// and loops restored (a loop still open in the macro is an error).
    fn macro_return(&mut self) -> Result<(), String> {
        let Some(frame) = self.frames.pop() else {
            return Err("M99 outside a called macro".into());
        };
        if let Some((id, _)) = self.loops.last() {
            return Err(format!("M99 inside WHILE … DO{id}"));
        }
        for n in LOCALS {
            self.m.vars.remove(&n);
        }
        self.m.vars.extend(frame.locals);
        self.loops = frame.loops;
        self.pc = frame.back;
        Ok(())
    }

    /// `G65 P#### <arguments>`: the arguments evaluated in the caller, the
    /// caller's locals and loops kept on the call stack (at most 4 deep),
    /// the argument letters set in the macro's locals, and on to the line
    /// after `O####`.
    fn macro_call(&mut self, p: &Listing, rest: &str) -> Result<(), String> {
        let args = call_arguments(&self.m, rest)?;
        let target = args
            .iter()
            .find(|(l, _)| *l == 'P')
            .map(|(_, p)| p.round() as u32)
            .ok_or_else(|| "G65 without P (the program number)".to_string())?;
        let start = *p
            .programs
            .get(&target)
            .ok_or_else(|| format!("G65 P{target}: no program O{target:04}"))?;
        if self.frames.len() >= 4 {
            return Err("more than 4 nested macro calls".into());
        }
        let locals = LOCALS
            .filter_map(|n| self.m.vars.remove(&n).map(|v| (n, v)))
            .collect();
        self.frames.push(Frame {
            back: self.pc + 1,
            locals,
            loops: std::mem::take(&mut self.loops),
        });
        for (letter, v) in args {
            if let Some(n) = argument_variable(letter) {
                self.m.vars.insert(n, v);
            } else if letter != 'P' && letter != 'L' {
                return Err(format!("G65 argument {letter} is not an argument letter"));
            }
        }
        self.pc = start + 1;
        Ok(())
    }

    /// `WHILE [cond] DOm`: into the loop while the condition holds, else on
    /// past its `ENDm`.
    fn while_do(&mut self, p: &Listing, line: &str, rest: &str) -> Result<(), String> {
        let (cond, after) = bracketed(rest)?;
        let id: u32 = after
            .trim()
            .strip_prefix("DO")
            .and_then(|d| d.trim().parse().ok())
            .ok_or_else(|| format!("WHILE without DOm: {line}"))?;
        if eval(&self.m.vars, &cond)? != 0.0 {
            self.loops.push((id, self.pc));
            self.pc += 1;
        } else {
            // Skip to the matching ENDm.
            let end = format!("END{id}");
            self.pc = (self.pc + 1..p.lines.len())
                .find(|&j| strip_sequence(p.lines[j].trim()) == end)
                .ok_or_else(|| format!("no {end} for DO{id}"))?
                + 1;
        }
        Ok(())
    }

    /// `ENDm`: back to the `WHILE` of the innermost loop, which must be
    /// `DOm`.
    fn end(&mut self, line: &str, id: &str) -> Result<(), String> {
        let id: u32 = id.trim().parse().map_err(|_| format!("bad END: {line}"))?;
        match self.loops.pop() {
            Some((open, start)) if open == id => self.pc = start,
            _ => return Err(format!("END{id} without its WHILE … DO{id}")),
        }
        Ok(())
    }

    /// `IF [cond] GOTOn`: to `Nn` if the condition holds, else on.
    fn if_goto(&mut self, p: &Listing, line: &str, rest: &str) -> Result<(), String> {
        let (cond, after) = bracketed(rest)?;
        let target: u32 = after
            .trim()
            .strip_prefix("GOTO")
            .and_then(|d| d.trim().parse().ok())
            .ok_or_else(|| format!("IF without GOTOn: {line}"))?;
        if eval(&self.m.vars, &cond)? != 0.0 {
            self.pc = p.label(target)?;
        } else {
            self.pc += 1;
        }
        Ok(())
    }
}

/// Replays a LinuxCNC program of the subset gearcam emits by reading it into
/// the Macro B subset line by line: named parameters `#<name>` become
/// numbered variables (#100 on, in order of appearance), `oN while [c]` …
/// `oN endwhile` become `WHILE [c] DOm` … `ENDm`, a block with the polar
/// words `@` (radius) and `^` (angle) becomes `G16` with X and Y and is
/// followed by `G15` (LinuxCNC's polar words hold for their block only),
/// `M2` ends the program. Errors name the LinuxCNC program's line. The tests
/// run the same programs through LinuxCNC's own `rs274`.
pub fn replay_linuxcnc(program: &str, budget: usize) -> Result<Vec<Move>, ReplayError> {
    let mut names: HashMap<String, u32> = HashMap::new();
    let mut out = String::new();
    let mut origin = Vec::new();
    let mut open: Vec<String> = Vec::new();
    for (i, raw) in program.lines().enumerate() {
        let err = |message: String| ReplayError {
            line: i + 1,
            message,
        };
        let mut line = String::new();
        let mut rest = strip_comments(raw);
        while let Some(at) = rest.find("#<") {
            let end = rest[at..]
                .find('>')
                .ok_or_else(|| err(format!("unclosed parameter name in {raw}")))?;
            let name = rest[at + 2..at + end].trim().to_lowercase();
            let next = 100 + names.len() as u32;
            let n = *names.entry(name).or_insert(next);
            line.push_str(&rest[..at]);
            line.push_str(&format!("#{n}"));
            rest = rest[at + end + 1..].to_string();
        }
        line.push_str(&rest);
        let line = line.trim().to_uppercase();
        let mut emit = |text: String| {
            out.push_str(&text);
            out.push('\n');
            origin.push(i);
        };
        if let Some(o) = line.strip_prefix('O') {
            let (label, body) = o
                .split_once(char::is_whitespace)
                .ok_or_else(|| err(format!("an o-word without a keyword: {raw}")))?;
            let body = body.trim();
            if let Some(cond) = body.strip_prefix("WHILE") {
                open.push(label.to_string());
                emit(format!("WHILE {} DO{}", cond.trim(), open.len()));
            } else if body == "ENDWHILE" {
                if open.last().map(String::as_str) != Some(label) {
                    return Err(err(format!("o{label} endwhile without its while")));
                }
                emit(format!("END{}", open.len()));
                open.pop();
            } else {
                return Err(err(format!("o-word {body} is outside the subset")));
            }
        } else if line.contains('@') || line.contains('^') {
            emit(format!("G16 {}", line.replace('@', "X").replace('^', "Y")));
            emit("G15".to_string());
        } else {
            emit(line);
        }
    }
    replay(&out, budget).map_err(|e| ReplayError {
        line: origin
            .get(e.line.saturating_sub(1))
            .map_or(e.line, |o| o + 1),
        message: e.message,
    })
}

/// A macro call's return point and the caller's state.
struct Frame {
    back: usize,
    locals: Vec<(u32, f64)>,
    loops: Vec<(u32, usize)>,
}

/// The local variables of a macro level (#1–#33).
const LOCALS: std::ops::RangeInclusive<u32> = 1..=33;

/// The local variable a `G65` argument letter sets (argument specification
/// I of the FANUC 0i manual): A #1, B #2, C #3, I #4, J #5, K #6, D #7,
/// E #8, F #9, H #11, M #13, Q #17, R #18, S #19, T #20, U #21, V #22,
/// W #23, X #24, Y #25, Z #26 (G, L, N, O, P are not arguments).
fn argument_variable(letter: char) -> Option<u32> {
    Some(match letter {
        'A' => 1,
        'B' => 2,
        'C' => 3,
        'I' => 4,
        'J' => 5,
        'K' => 6,
        'D' => 7,
        'E' => 8,
        'F' => 9,
        'H' => 11,
        'M' => 13,
        'Q' => 17,
        'R' => 18,
        'S' => 19,
        'T' => 20,
        'U' => 21,
        'V' => 22,
        'W' => 23,
        'X' => 24,
        'Y' => 25,
        'Z' => 26,
        _ => return None,
    })
}

/// The words of a `G65` block after `G65`, evaluated in the caller.
fn call_arguments(m: &Machine, mut rest: &str) -> Result<Vec<(char, f64)>, String> {
    let mut args = Vec::new();
    while !rest.trim_start().is_empty() {
        rest = rest.trim_start();
        let letter = rest.chars().next().expect("not empty");
        if !letter.is_ascii_uppercase() {
            return Err(format!("bad G65 word at {rest}"));
        }
        let (v, after) = word_value(m, &rest[1..])?;
        if args.iter().any(|(l, _)| *l == letter) {
            return Err(format!("G65 argument {letter} given twice"));
        }
        args.push((letter, v));
        rest = after;
    }
    Ok(args)
}

fn strip_comments(line: &str) -> String {
    let mut out = String::new();
    let mut depth = 0;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            _ if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

fn strip_sequence(line: &str) -> &str {
    match line.strip_prefix('N') {
        Some(rest) if rest.starts_with(|c: char| c.is_ascii_digit()) => {
            rest.trim_start_matches(|c: char| c.is_ascii_digit()).trim()
        }
        _ => line,
    }
}

/// The text inside the leading `[ … ]` of `s`, and what follows.
fn bracketed(s: &str) -> Result<(String, &str), String> {
    let s = s.trim_start();
    if !s.starts_with('[') {
        return Err(format!("expected [ … ], got {s}"));
    }
    let mut depth = 0;
    for (i, c) in s.char_indices() {
        match c {
            '[' => depth += 1,
            ']' => {
                depth -= 1;
                if depth == 0 {
                    return Ok((s[1..i].to_string(), &s[i + 1..]));
                }
            }
            _ => {}
        }
    }
    Err(format!("unbalanced [ in {s}"))
}

/// One motion block: G codes, axis words, F, S, M.
fn block(m: &mut Machine, line: &str) -> Result<(), String> {
    let mut rest = line;
    let mut axes: [Option<f64>; 3] = [None; 3];
    let mut centre: [Option<f64>; 2] = [None; 2];
    while !rest.trim_start().is_empty() {
        rest = rest.trim_start();
        let letter = rest.chars().next().expect("not empty");
        rest = &rest[1..];
        let (value, after) = word_value(m, rest)?;
        rest = after;
        match letter {
            'G' => match value.round() as i64 {
                0 => {
                    m.feed_mode = false;
                    m.motion = 0;
                }
                1 => {
                    m.feed_mode = true;
                    m.motion = 1;
                }
                2 | 3 => {
                    m.feed_mode = true;
                    m.motion = value.round() as u8;
                }
                15 => m.polar = false,
                16 => {
                    m.polar = true;
                    let (x, y) = (m.pos.0, m.pos.1);
                    m.polar_words = ((x * x + y * y).sqrt(), y.atan2(x).to_degrees());
                }
                90 => m.absolute = true,
                91 => m.absolute = false,
                _ => {}
            },
            'X' => axes[0] = Some(value),
            'Y' => axes[1] = Some(value),
            'Z' => axes[2] = Some(value),
            'I' => centre[0] = Some(value),
            'J' => centre[1] = Some(value),
            'F' | 'S' | 'M' | 'T' | 'H' | 'D' => {}
            other => return Err(format!("word {other} is outside the subset")),
        }
    }
    if axes.iter().all(Option::is_none) {
        return Ok(());
    }
    let (mut x, mut y, mut z) = m.pos;
    let start = m.pos;
    if m.motion >= 2 && m.polar {
        return Err("G02/G03 under G16 is outside the subset".into());
    }
    if m.polar {
        let (mut r, mut a) = m.polar_words;
        if let Some(v) = axes[0] {
            r = if m.absolute { v } else { r + v };
        }
        if let Some(v) = axes[1] {
            a = if m.absolute { v } else { a + v };
        }
        m.polar_words = (r, a);
        if axes[0].is_some() || axes[1].is_some() {
            x = r * a.to_radians().cos();
            y = r * a.to_radians().sin();
        }
    } else {
        if let Some(v) = axes[0] {
            x = if m.absolute { v } else { x + v };
        }
        if let Some(v) = axes[1] {
            y = if m.absolute { v } else { y + v };
        }
    }
    if let Some(v) = axes[2] {
        z = if m.absolute { v } else { z + v };
    }
    m.pos = (x, y, z);
    let arc = if m.motion >= 2 {
        let (Some(i), Some(j)) = (centre[0], centre[1]) else {
            return Err("G02/G03 needs I and J (the centre from the start)".into());
        };
        Some(((start.0 + i, start.1 + j), m.motion == 3))
    } else {
        None
    };
    m.moves.push(Move {
        feed: m.feed_mode,
        arc,
        x,
        y,
        z,
    });
    Ok(())
}

/// The value of a word after its letter: a number, `#n` or `[expr]`.
fn word_value<'a>(m: &Machine, s: &'a str) -> Result<(f64, &'a str), String> {
    if s.starts_with('[') {
        let (expr, after) = bracketed(s)?;
        return Ok((eval(&m.vars, &expr)?, after));
    }
    if let Some(rest) = s.strip_prefix('#') {
        let end = rest
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(rest.len());
        let n: u32 = rest[..end]
            .parse()
            .map_err(|_| format!("bad variable in {s}"))?;
        return Ok((var(&m.vars, n)?, &rest[end..]));
    }
    let end = s
        .char_indices()
        .find(|&(i, c)| !(c.is_ascii_digit() || c == '.' || (i == 0 && (c == '-' || c == '+'))))
        .map_or(s.len(), |(i, _)| i);
    let v: f64 = s[..end].parse().map_err(|_| format!("bad number in {s}"))?;
    Ok((v, &s[end..]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_loops_and_polar_words() {
        let moves = replay(
            "%\nO0001 (T)\n#1=2\n#2=[#1+3]*2-SQRT[16] (6)\n#3=0\nWHILE [#3 LT 3] DO1\n#3=#3+1\nG01 X#3 Y[#2/2]\nEND1\nG16\nG01 X10 Y90\nG15\nIF [#3 EQ 3] GOTO10\nG01 X99\nN10 G00 Z5\nM30\n%\n",
            1000,
        )
        .unwrap();
        let xy: Vec<(f64, f64)> = moves.iter().map(|m| (m.x, m.y)).collect();
        assert_eq!(&xy[..3], &[(1.0, 3.0), (2.0, 3.0), (3.0, 3.0)]);
        assert!(
            xy[3].0.abs() < 1e-12 && (xy[3].1 - 10.0).abs() < 1e-12,
            "{xy:?}"
        );
        assert_eq!(moves.len(), 5, "the GOTO skipped X99");
        assert_eq!(moves[4].z, 5.0);
    }

    #[test]
    fn errors_name_the_line() {
        let e = replay("#1=#9+1\n", 10).unwrap_err();
        assert_eq!(e.line, 1);
        assert!(e.message.contains("#9"), "{e:?}");
        let e = replay("#1=0\nWHILE [#1 LT 1] DO1\nG01 X1\n", 100).unwrap_err();
        assert!(e.message.contains("DO1"), "{e:?}");
        let e = replay("#1=0\nWHILE [1 EQ 1] DO1\nEND1\n", 50).unwrap_err();
        assert!(e.message.contains("runaway"), "{e:?}");
    }
}
