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
    let mut m = Machine {
        vars: HashMap::new(),
        motion: 0,
        polar: false,
        absolute: true,
        feed_mode: false,
        pos: (0.0, 0.0, 0.0),
        polar_words: (0.0, 0.0),
        moves: Vec::new(),
    };
    // Where each program `O####` starts, for `G65 P####`.
    let programs: HashMap<u32, usize> = lines
        .iter()
        .enumerate()
        .filter_map(|(i, l)| {
            let rest = l.trim().strip_prefix('O')?;
            let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
            digits.parse().ok().map(|n| (n, i))
        })
        .collect();
    let mut loops: Vec<(u32, usize)> = Vec::new();
    // The macro call stack: where to return, the caller's locals and loops.
    let mut frames: Vec<Frame> = Vec::new();
    let mut pc = 0;
    let mut steps = 0;
    let err = |line: usize, message: String| ReplayError {
        line: line + 1,
        message,
    };
    while pc < lines.len() {
        steps += 1;
        if steps > budget {
            return Err(err(
                pc,
                format!("more than {budget} blocks: a runaway loop?"),
            ));
        }
        let line = lines[pc].trim();
        let line = strip_sequence(line);
        if line.is_empty() || line == "%" || line.starts_with('O') {
            if line.starts_with('O') && pc > 0 && frames.is_empty() && !m.moves.is_empty() {
                // The main program ran into the next program without M30.
                return Err(err(
                    pc,
                    "the main program ran into another program: M30 missing".into(),
                ));
            }
            pc += 1;
            continue;
        }
        if line == "M30" || line == "M02" || line == "M2" {
            break;
        }
        if line == "M99" {
            let Some(frame) = frames.pop() else {
                return Err(err(pc, "M99 outside a called macro".into()));
            };
            if let Some((id, _)) = loops.last() {
                return Err(err(pc, format!("M99 inside WHILE … DO{id}")));
            }
            for n in LOCALS {
                m.vars.remove(&n);
            }
            m.vars.extend(frame.locals);
            loops = frame.loops;
            pc = frame.back;
            continue;
        }
        if let Some(rest) = line.strip_prefix("G65") {
            let args = call_arguments(&m, rest).map_err(|e| err(pc, e))?;
            let target = args
                .iter()
                .find(|(l, _)| *l == 'P')
                .map(|(_, p)| p.round() as u32)
                .ok_or_else(|| err(pc, "G65 without P (the program number)".into()))?;
            let start = *programs
                .get(&target)
                .ok_or_else(|| err(pc, format!("G65 P{target}: no program O{target:04}")))?;
            if frames.len() >= 4 {
                return Err(err(pc, "more than 4 nested macro calls".into()));
            }
            let locals = LOCALS
                .filter_map(|n| m.vars.remove(&n).map(|v| (n, v)))
                .collect();
            frames.push(Frame {
                back: pc + 1,
                locals,
                loops: std::mem::take(&mut loops),
            });
            for (letter, v) in args {
                if let Some(n) = argument_variable(letter) {
                    m.vars.insert(n, v);
                } else if letter != 'P' && letter != 'L' {
                    return Err(err(
                        pc,
                        format!("G65 argument {letter} is not an argument letter"),
                    ));
                }
            }
            pc = start + 1;
            continue;
        }
        if let Some(rest) = line.strip_prefix("WHILE") {
            let (cond, after) = bracketed(rest).map_err(|e| err(pc, e))?;
            let id: u32 = after
                .trim()
                .strip_prefix("DO")
                .and_then(|d| d.trim().parse().ok())
                .ok_or_else(|| err(pc, format!("WHILE without DOm: {line}")))?;
            if eval(&m, &cond).map_err(|e| err(pc, e))? != 0.0 {
                loops.push((id, pc));
                pc += 1;
            } else {
                // Skip to the matching ENDm.
                let end = format!("END{id}");
                pc = (pc + 1..lines.len())
                    .find(|&j| strip_sequence(lines[j].trim()) == end)
                    .ok_or_else(|| err(pc, format!("no {end} for DO{id}")))?
                    + 1;
            }
            continue;
        }
        if let Some(id) = line.strip_prefix("END") {
            let id: u32 = id
                .trim()
                .parse()
                .map_err(|_| err(pc, format!("bad END: {line}")))?;
            match loops.pop() {
                Some((open, start)) if open == id => pc = start,
                _ => return Err(err(pc, format!("END{id} without its WHILE … DO{id}"))),
            }
            continue;
        }
        if let Some(rest) = line.strip_prefix("IF") {
            let (cond, after) = bracketed(rest).map_err(|e| err(pc, e))?;
            let target: u32 = after
                .trim()
                .strip_prefix("GOTO")
                .and_then(|d| d.trim().parse().ok())
                .ok_or_else(|| err(pc, format!("IF without GOTOn: {line}")))?;
            if eval(&m, &cond).map_err(|e| err(pc, e))? != 0.0 {
                pc = *labels
                    .get(&target)
                    .ok_or_else(|| err(pc, format!("no N{target}")))?;
            } else {
                pc += 1;
            }
            continue;
        }
        if let Some(target) = line.strip_prefix("GOTO") {
            let target: u32 = target
                .trim()
                .parse()
                .map_err(|_| err(pc, format!("bad GOTO: {line}")))?;
            pc = *labels
                .get(&target)
                .ok_or_else(|| err(pc, format!("no N{target}")))?;
            continue;
        }
        if let Some(rest) = line.strip_prefix('#') {
            let (var, expr) = rest
                .split_once('=')
                .ok_or_else(|| err(pc, format!("not an assignment: {line}")))?;
            let n: u32 = var
                .trim()
                .parse()
                .map_err(|_| err(pc, format!("bad variable: {line}")))?;
            let v = eval(&m, expr).map_err(|e| err(pc, e))?;
            m.vars.insert(n, v);
            pc += 1;
            continue;
        }
        block(&mut m, line).map_err(|e| err(pc, e))?;
        pc += 1;
    }
    if let Some((id, _)) = loops.pop() {
        return Err(err(lines.len() - 1, format!("DO{id} never ended")));
    }
    Ok(m.moves)
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
        return Ok((eval(m, &expr)?, after));
    }
    if let Some(rest) = s.strip_prefix('#') {
        let end = rest
            .find(|c: char| !c.is_ascii_digit())
            .unwrap_or(rest.len());
        let n: u32 = rest[..end]
            .parse()
            .map_err(|_| format!("bad variable in {s}"))?;
        return Ok((var(m, n)?, &rest[end..]));
    }
    let end = s
        .char_indices()
        .find(|&(i, c)| !(c.is_ascii_digit() || c == '.' || (i == 0 && (c == '-' || c == '+'))))
        .map_or(s.len(), |(i, _)| i);
    let v: f64 = s[..end].parse().map_err(|_| format!("bad number in {s}"))?;
    Ok((v, &s[end..]))
}

fn var(m: &Machine, n: u32) -> Result<f64, String> {
    m.vars
        .get(&n)
        .copied()
        .ok_or_else(|| format!("#{n} is used before it is set"))
}

/// Evaluates an expression (the subset's grammar, with precedence
/// OR < AND < comparison < + - < * / < unary < primary).
fn eval(m: &Machine, s: &str) -> Result<f64, String> {
    let tokens = tokenize(s)?;
    let mut p = Parser { m, tokens, i: 0 };
    let v = p.or()?;
    if p.i != p.tokens.len() {
        return Err(format!("unexpected {:?} in {s}", p.tokens[p.i]));
    }
    Ok(v)
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Var(u32),
    Word(String),
    Op(char),
    Open,
    Close,
}

fn tokenize(s: &str) -> Result<Vec<Tok>, String> {
    let mut out = Vec::new();
    let cs: Vec<char> = s.chars().collect();
    let mut i = 0;
    while i < cs.len() {
        let c = cs[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < cs.len() && (cs[i].is_ascii_digit() || cs[i] == '.') {
                i += 1;
            }
            let t: String = cs[start..i].iter().collect();
            out.push(Tok::Num(t.parse().map_err(|_| format!("bad number {t}"))?));
        } else if c == '#' {
            let start = i + 1;
            i += 1;
            while i < cs.len() && cs[i].is_ascii_digit() {
                i += 1;
            }
            let t: String = cs[start..i].iter().collect();
            out.push(Tok::Var(
                t.parse().map_err(|_| format!("bad variable #{t}"))?,
            ));
        } else if c.is_ascii_alphabetic() {
            let start = i;
            while i < cs.len() && cs[i].is_ascii_alphabetic() {
                i += 1;
            }
            out.push(Tok::Word(cs[start..i].iter().collect()));
        } else if "+-*/".contains(c) {
            out.push(Tok::Op(c));
            i += 1;
        } else if c == '[' {
            out.push(Tok::Open);
            i += 1;
        } else if c == ']' {
            out.push(Tok::Close);
            i += 1;
        } else {
            return Err(format!("character {c:?} outside the subset"));
        }
    }
    Ok(out)
}

struct Parser<'a> {
    m: &'a Machine,
    tokens: Vec<Tok>,
    i: usize,
}

impl Parser<'_> {
    fn peek_word(&self, w: &str) -> bool {
        matches!(self.tokens.get(self.i), Some(Tok::Word(x)) if x == w)
    }

    fn or(&mut self) -> Result<f64, String> {
        let mut v = self.and()?;
        while self.peek_word("OR") {
            self.i += 1;
            let r = self.and()?;
            v = f64::from(u8::from(v != 0.0 || r != 0.0));
        }
        Ok(v)
    }

    fn and(&mut self) -> Result<f64, String> {
        let mut v = self.cmp()?;
        while self.peek_word("AND") {
            self.i += 1;
            let r = self.cmp()?;
            v = f64::from(u8::from(v != 0.0 && r != 0.0));
        }
        Ok(v)
    }

    fn cmp(&mut self) -> Result<f64, String> {
        let a = self.sum()?;
        for op in ["EQ", "NE", "GT", "GE", "LT", "LE"] {
            if self.peek_word(op) {
                self.i += 1;
                let b = self.sum()?;
                let t = match op {
                    "EQ" => a == b,
                    "NE" => a != b,
                    "GT" => a > b,
                    "GE" => a >= b,
                    "LT" => a < b,
                    _ => a <= b,
                };
                return Ok(f64::from(u8::from(t)));
            }
        }
        Ok(a)
    }

    fn sum(&mut self) -> Result<f64, String> {
        let mut v = self.product()?;
        while let Some(Tok::Op(c @ ('+' | '-'))) = self.tokens.get(self.i).cloned() {
            self.i += 1;
            let r = self.product()?;
            v = if c == '+' { v + r } else { v - r };
        }
        Ok(v)
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut v = self.unary()?;
        while let Some(Tok::Op(c @ ('*' | '/'))) = self.tokens.get(self.i).cloned() {
            self.i += 1;
            let r = self.unary()?;
            if c == '/' && r == 0.0 {
                return Err("division by zero".into());
            }
            v = if c == '*' { v * r } else { v / r };
        }
        Ok(v)
    }

    fn unary(&mut self) -> Result<f64, String> {
        match self.tokens.get(self.i) {
            Some(Tok::Op('-')) => {
                self.i += 1;
                Ok(-self.unary()?)
            }
            Some(Tok::Op('+')) => {
                self.i += 1;
                self.unary()
            }
            _ => self.primary(),
        }
    }

    fn primary(&mut self) -> Result<f64, String> {
        let t = self
            .tokens
            .get(self.i)
            .cloned()
            .ok_or("an expression ends too soon")?;
        self.i += 1;
        match t {
            Tok::Num(v) => Ok(v),
            Tok::Var(n) => var(self.m, n),
            Tok::Open => {
                let v = self.or()?;
                match self.tokens.get(self.i) {
                    Some(Tok::Close) => {
                        self.i += 1;
                        Ok(v)
                    }
                    _ => Err("a [ is not closed".into()),
                }
            }
            Tok::Word(f) => {
                if self.tokens.get(self.i) != Some(&Tok::Open) {
                    return Err(format!("{f} needs [ … ]"));
                }
                let x = self.primary()?;
                Ok(match f.as_str() {
                    "SIN" => x.to_radians().sin(),
                    "COS" => x.to_radians().cos(),
                    "TAN" => x.to_radians().tan(),
                    "ATAN" => x.atan().to_degrees(),
                    "SQRT" => x.sqrt(),
                    "ABS" => x.abs(),
                    "ROUND" => x.round(),
                    "FIX" => x.trunc(),
                    "FUP" => x.signum() * x.abs().ceil(),
                    other => return Err(format!("function {other} outside the subset")),
                })
            }
            other => Err(format!("unexpected {other:?}")),
        }
    }
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
