//! A clean-room reader of gearcam's ISO wire-EDM G-code (W02, FANUC-type control).
//!
//! Written from `docs/wire.md` only (sections "ISO wire G-code", "Programs",
//! "Verification and the certificate"), without gearcam's own reader, to check it.
//!
//! # The subset (docs/wire.md, "ISO wire G-code")
//!
//! "The replay interprets exactly that subset (G00–G03, G10 L12, G17, G21, G40–G42 with D,
//! G68/G69, G90, G92, M02/M30, M98/M99 in the same text, O numbers, comments, `%`) [...] any
//! other word (F, G91, M08, a D without a register, an arc whose end is more than 5 µm off its
//! circle) is refused with its line."
//!
//! * One block per line; words are an upper-case letter and a number, written with or
//!   without spaces between words. `( ... )` are comments (not nested), `%` stands alone on
//!   the first or the last line of the tape, `O####` alone on its line starts a program.
//! * Words: `G` 00 01 02 03 10 17 21 40 41 42 68 69 90 92; `M` 02 30 98 99; `X Y I J` (mm),
//!   `D` (offset register), `L` (only `L12` with `G10`), `P` (register with `G10`, program
//!   number with `M98`), `R` (offset with `G10`, angle in degrees with `G68`). Anything else —
//!   `F`, `N`, `G91`, `M08`, `R` on an arc, a `;` — is refused naming the line.
//! * Lengths and angles must carry a decimal point unless they are zero: on a FANUC control
//!   `X5` means 5 least input increments (0.005 mm), so a bare integer is refused rather than
//!   guessed.
//! * `G90 G17 G21` are the only distance mode, plane and unit the subset has, so they are the
//!   state whether written or not; `G91`, `G18`, `G20` are refused.
//! * `G92 X Y` sets the current position (the start hole). The first `G92` defines the frame
//!   the moves are reported in (the "machine frame" of [`IsoMove`]); a later one shifts the
//!   program's coordinates against it.
//! * `G10 L12 P{n} R{d}` sets offset register n to d mm (docs: "wire radius + spark gap").
//! * `G41`/`G42` with `D{n}` switch the control's offset on, the wire left or right of the
//!   travel (docs: "`G41 D1 G01` (punch, wire left of the travel) or `G42 D1 G01` (die)");
//!   `G40` switches it off. The programmed path is the part's outline, NOT offset: the moves
//!   carry the side and the register's value in force ([`IsoMove::comp`],
//!   [`IsoMove::offset_mm`]).
//! * `G02`/`G03` run clockwise / counter-clockwise from the current position to absolute
//!   `X Y`, centre at `I J` from the arc's start ("I J from the arc's start"). An end more than
//!   5 µm further from the centre, or nearer, than the start is refused. Omitted `X`/`Y` keep
//!   the current programmed value, an omitted `I` or `J` is 0; an arc ending where it starts is
//!   a full circle (as on a FANUC control).
//! * `G68 X Y R{deg}` turns every following programmed point by R degrees (counter-clockwise
//!   positive) about (X, Y); `G69` cancels it. Sections are called as
//!   "`G68 X0 Y0 R{k·deg}` / `M98 P{n+1}` / `G69` for each k, compensated throughout".
//! * `M98 P{n}` runs program `O{n}` of the same text, `M99` returns; `M02`/`M30` end the run.
//!
//! # Structural rules a control enforces (refused with the line)
//!
//! * Compensation is switched (on, off or from side to side) only on a linear move
//!   (`G00`/`G01`) of non-zero length: the lead-in and the lead-out. An arc while it is switched,
//!   or a switch without a move, is refused (a FANUC control alarms on a circular start-up or
//!   cancel block).
//! * The main program's last block is `M02` or `M30`, and no other block of it ends or returns;
//!   each subprogram's last block is `M99` and it holds no other `M99` nor `M02`/`M30`.
//! * At `M02`/`M30` compensation is off and no `G68` is in force (the lead-out was run and
//!   every rotation cancelled).
//! * No move before `G92` (the position would be unknown); `G92` is refused while `G68` or
//!   compensation is in force; `G68` is not nested; subprograms nest at most 4 deep.

use std::collections::BTreeMap;

/// Side of the control's wire offset (docs/wire.md, "ISO wire G-code": G40/G41/G42).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Comp {
    Off,
    Left,
    Right,
}

/// One motion of the programmed path (the contour as written, NOT offset by the compensation), mm,
/// in the machine frame (after G92 and any G68 rotation are applied).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IsoMove {
    pub(crate) line: usize, // 1-based line of the block executed (in a subprogram: its line)
    pub(crate) from: (f64, f64),
    pub(crate) to: (f64, f64),
    pub(crate) rapid: bool,
    pub(crate) arc: Option<((f64, f64), bool)>, // centre, counter-clockwise?
    pub(crate) comp: Comp,                      // compensation in force during the move
    pub(crate) offset_mm: f64,                  // the D register's value in force (0 when Off)
}

/// A whole run of a program: its moves in execution order, the `G92` start and the end word.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IsoRun {
    pub(crate) moves: Vec<IsoMove>,
    pub(crate) start: (f64, f64), // position set by G92
    pub(crate) ended_by: String,  // "M02" or "M30"
}

/// Largest difference between an arc's start and end distance from its centre
/// (docs/wire.md, "ISO wire G-code": "an arc whose end is more than 5 µm off its circle").
pub(crate) const ARC_TOLERANCE_MM: f64 = 0.005;

/// Deepest subprogram nesting accepted (a classic FANUC control's limit).
pub(crate) const MAX_NESTING: usize = 4;

/// One block of the subset, as read (before it is run).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum IsoBlock {
    /// `G00`–`G03`, `G17`, `G21`, `G90`, `G40`–`G42`, `D`, `X Y I J`; motion 0–3 when given.
    Motion {
        motion: Option<u8>,
        comp: Option<Comp>,
        d: Option<u32>,
        x: Option<f64>,
        y: Option<f64>,
        i: Option<f64>,
        j: Option<f64>,
    },
    /// `G10 L12 P{register} R{mm}`.
    Offset { register: u32, value: f64 },
    /// `G92 X Y`.
    SetPosition { x: f64, y: f64 },
    /// `G68 X Y R{deg}`.
    Rotate { centre: (f64, f64), deg: f64 },
    /// `G69`.
    RotateOff,
    /// `M98 P{program}`.
    Call(u32),
    /// `M99`.
    Return,
    /// `M02` or `M30`.
    End(String),
}

/// A line of the text, as read.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum IsoLine {
    /// Nothing but blanks and comments.
    Empty,
    /// `%`: start or end of the tape.
    Percent,
    /// `O####`: a program starts.
    Number(u32),
    /// A block.
    Block(IsoBlock),
}

/// One word as written: its letter, its text and value, whether it has a decimal point.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IsoWord {
    pub(crate) letter: char,
    pub(crate) text: String,
    pub(crate) value: f64,
    pub(crate) point: bool,
    pub(crate) sign: bool,
}

/// A program of the text (`O` number, or the unnumbered start) with its blocks and their lines.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IsoSection {
    pub(crate) number: Option<u32>,
    pub(crate) line: usize,
    pub(crate) blocks: Vec<(usize, IsoBlock)>,
}

/// An error message naming the 1-based line: `line N: what`.
pub(crate) fn err(line: usize, msg: impl std::fmt::Display) -> String {
    format!("line {line}: {msg}")
}

/// Removes `( ... )` comments; refuses nested or unbalanced parentheses.
pub(crate) fn strip_comments(line: usize, raw: &str) -> Result<String, String> {
    let mut out = String::new();
    let mut inside = false;
    for c in raw.chars() {
        match (inside, c) {
            (false, '(') => inside = true,
            (false, ')') => return Err(err(line, "')' without '('")),
            (false, _) => out.push(c),
            (true, '(') => return Err(err(line, "nested '(' in a comment")),
            (true, ')') => inside = false,
            (true, _) => {}
        }
    }
    if inside {
        return Err(err(line, "comment not closed by ')'"));
    }
    Ok(out)
}

/// Splits a block (comments removed) into words: an upper-case letter, then a number
/// `[+|-]digits[.digits]` (at least one digit). Whitespace may separate words only.
pub(crate) fn split_words(line: usize, text: &str) -> Result<Vec<IsoWord>, String> {
    let chars: Vec<char> = text.chars().collect();
    let mut words = Vec::new();
    let mut k = 0;
    while k < chars.len() {
        let c = chars[k];
        if c.is_whitespace() {
            k += 1;
            continue;
        }
        if !c.is_ascii_uppercase() {
            return Err(err(
                line,
                format!("'{c}' is not a word of the ISO wire subset"),
            ));
        }
        let start = k + 1;
        let mut end = start;
        while end < chars.len()
            && (chars[end].is_ascii_digit()
                || chars[end] == '.'
                || chars[end] == '-'
                || chars[end] == '+')
        {
            end += 1;
        }
        let number: String = chars[start..end].iter().collect();
        let word_text = format!("{c}{number}");
        if !"GMXYIJDLPRO".contains(c) {
            return Err(err(
                line,
                format!("word {word_text} is not in the ISO wire subset"),
            ));
        }
        let body = number.strip_prefix(['-', '+']).unwrap_or(&number);
        let digits = body.chars().filter(char::is_ascii_digit).count();
        let points = body.chars().filter(|&ch| ch == '.').count();
        let well_formed =
            digits > 0 && points <= 1 && body.chars().all(|ch| ch.is_ascii_digit() || ch == '.');
        let value = if well_formed {
            number.parse::<f64>().ok()
        } else {
            None
        };
        let Some(value) = value else {
            return Err(err(line, format!("word {word_text} has no valid number")));
        };
        words.push(IsoWord {
            letter: c,
            text: word_text,
            value,
            point: points == 1,
            sign: number.len() != body.len(),
        });
        k = end;
    }
    Ok(words)
}

/// An integer word (G, M, D, L, P, O): no sign, no decimal point.
pub(crate) fn int_word(line: usize, w: &IsoWord) -> Result<u32, String> {
    if w.point || w.sign || w.value > f64::from(u32::MAX) {
        return Err(err(line, format!("{} must be an unsigned integer", w.text)));
    }
    // value is a non-negative whole number below u32::MAX here
    Ok(w.value as u32)
}

/// A length or angle (X, Y, I, J, R): a decimal point unless zero (see the module docs).
pub(crate) fn real_word(line: usize, w: &IsoWord) -> Result<f64, String> {
    if !w.point && w.value != 0.0 {
        return Err(err(
            line,
            format!(
                "{} has no decimal point (a FANUC control would read least input increments)",
                w.text
            ),
        ));
    }
    Ok(w.value)
}

/// Reads one line of the text into an [`IsoLine`], refusing anything outside the subset.
pub(crate) fn parse_line(line: usize, raw: &str) -> Result<IsoLine, String> {
    let text = strip_comments(line, raw.trim_end_matches('\r'))?;
    let text = text.trim();
    if text.is_empty() {
        return Ok(IsoLine::Empty);
    }
    if text == "%" {
        return Ok(IsoLine::Percent);
    }
    if text.contains('%') {
        return Err(err(line, "'%' must stand alone on its line"));
    }
    let words = split_words(line, text)?;
    if words.iter().any(|w| w.letter == 'O') {
        if words.len() != 1 {
            return Err(err(line, "an O number must stand alone in its block"));
        }
        let n = int_word(line, &words[0])?;
        if !(1..=9999).contains(&n) {
            return Err(err(
                line,
                format!("program number {} out of 1..9999", words[0].text),
            ));
        }
        return Ok(IsoLine::Number(n));
    }

    // Letters other than G appear at most once.
    let mut seen: BTreeMap<char, &IsoWord> = BTreeMap::new();
    let mut gs: Vec<(u32, &IsoWord)> = Vec::new();
    for w in &words {
        if w.letter == 'G' {
            gs.push((int_word(line, w)?, w));
        } else if seen.insert(w.letter, w).is_some() {
            return Err(err(line, format!("{} given twice in one block", w.letter)));
        }
    }

    let mut motion: Option<u8> = None;
    let mut comp: Option<Comp> = None;
    let mut special: Option<u32> = None;
    let mut modal_other = false;
    for (code, w) in &gs {
        match code {
            0..=3 => {
                if motion.is_some() {
                    return Err(err(line, "two motion G codes in one block"));
                }
                // 0..=3 fits a u8
                motion = Some(*code as u8);
            }
            17 | 21 | 90 => modal_other = true,
            40..=42 => {
                if comp.is_some() {
                    return Err(err(line, "two of G40/G41/G42 in one block"));
                }
                comp = Some(match code {
                    40 => Comp::Off,
                    41 => Comp::Left,
                    _ => Comp::Right,
                });
            }
            10 | 68 | 69 | 92 => {
                if special.is_some() {
                    return Err(err(line, "two of G10/G68/G69/G92 in one block"));
                }
                special = Some(*code);
            }
            _ => {
                return Err(err(
                    line,
                    format!("word {} is not in the ISO wire subset", w.text),
                ))
            }
        }
    }
    let get = |c: char| seen.get(&c).copied();
    let only = |allowed: &str, what: &str| -> Result<(), String> {
        for w in &words {
            if w.letter != 'G' && !allowed.contains(w.letter) {
                return Err(err(
                    line,
                    format!("word {} not allowed in a {what} block", w.text),
                ));
            }
        }
        Ok(())
    };

    if let Some(mw) = get('M') {
        if !gs.is_empty() {
            return Err(err(
                line,
                format!("{} must not share its block with G words", mw.text),
            ));
        }
        let m = int_word(line, mw)?;
        return match m {
            98 => {
                only("MP", "M98")?;
                let Some(pw) = get('P') else {
                    return Err(err(line, "M98 without P (program number)"));
                };
                let p = int_word(line, pw)?;
                if !(1..=9999).contains(&p) {
                    return Err(err(line, format!("M98 {}: program number out of 1..9999 (repeat counts are not in the subset)", pw.text)));
                }
                Ok(IsoLine::Block(IsoBlock::Call(p)))
            }
            99 => {
                only("M", "M99")?;
                Ok(IsoLine::Block(IsoBlock::Return))
            }
            2 | 30 => {
                only("M", "M02/M30")?;
                Ok(IsoLine::Block(IsoBlock::End(if m == 2 {
                    "M02".into()
                } else {
                    "M30".into()
                })))
            }
            _ => Err(err(
                line,
                format!("word {} is not in the ISO wire subset", mw.text),
            )),
        };
    }

    if let Some(code) = special {
        if motion.is_some() || comp.is_some() || modal_other {
            return Err(err(
                line,
                format!("G{code:02} must not share its block with other G codes"),
            ));
        }
        let need = |c: char| -> Result<&IsoWord, String> {
            get(c).ok_or_else(|| err(line, format!("G{code:02} without {c}")))
        };
        return match code {
            10 => {
                only("LPR", "G10")?;
                let l = int_word(line, need('L')?)?;
                if l != 12 {
                    return Err(err(
                        line,
                        format!("G10 L{l}: only L12 (offset register) is in the subset"),
                    ));
                }
                let register = int_word(line, need('P')?)?;
                if register == 0 {
                    return Err(err(line, "G10 L12 P0: registers start at 1"));
                }
                let value = real_word(line, need('R')?)?;
                if value < 0.0 {
                    return Err(err(
                        line,
                        "G10 L12 with a negative offset (it would swap the sides)",
                    ));
                }
                Ok(IsoLine::Block(IsoBlock::Offset { register, value }))
            }
            92 => {
                only("XY", "G92")?;
                let x = real_word(line, need('X')?)?;
                let y = real_word(line, need('Y')?)?;
                Ok(IsoLine::Block(IsoBlock::SetPosition { x, y }))
            }
            68 => {
                only("XYR", "G68")?;
                let x = real_word(line, need('X')?)?;
                let y = real_word(line, need('Y')?)?;
                let deg = real_word(line, need('R')?)?;
                Ok(IsoLine::Block(IsoBlock::Rotate {
                    centre: (x, y),
                    deg,
                }))
            }
            _ => {
                only("", "G69")?;
                Ok(IsoLine::Block(IsoBlock::RotateOff))
            }
        };
    }

    if let Some(r) = get('R') {
        return Err(err(
            line,
            format!(
                "word {} not in the subset outside G10/G68 (arcs are given by I J)",
                r.text
            ),
        ));
    }
    only("XYIJD", "motion")?;
    let real =
        |c: char| -> Result<Option<f64>, String> { get(c).map(|w| real_word(line, w)).transpose() };
    let d = match get('D') {
        Some(w) => {
            let d = int_word(line, w)?;
            if d == 0 {
                return Err(err(line, "D0: registers start at 1"));
            }
            Some(d)
        }
        None => None,
    };
    Ok(IsoLine::Block(IsoBlock::Motion {
        motion,
        comp,
        d,
        x: real('X')?,
        y: real('Y')?,
        i: real('I')?,
        j: real('J')?,
    }))
}

/// Reads the whole text into programs: the unnumbered start (when it holds blocks) or the first
/// `O` program is the main program, the `O` programs after it are subprograms. Checks the
/// structural rules of the module docs on how each program ends.
pub(crate) fn parse_sections(text: &str) -> Result<Vec<IsoSection>, String> {
    let mut sections = vec![IsoSection {
        number: None,
        line: 1,
        blocks: Vec::new(),
    }];
    let mut content = false;
    let mut closed_at: Option<usize> = None;
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let parsed = parse_line(line, raw)?;
        if !matches!(parsed, IsoLine::Empty | IsoLine::Percent) {
            if let Some(c) = closed_at {
                return Err(err(
                    line,
                    format!("block after the closing '%' of line {c}"),
                ));
            }
            content = true;
        }
        match parsed {
            IsoLine::Empty => {}
            IsoLine::Percent => {
                if content {
                    closed_at = Some(line);
                }
            }
            IsoLine::Number(n) => {
                if sections.iter().any(|s| s.number == Some(n)) {
                    return Err(err(line, format!("O{n:04} defined twice")));
                }
                sections.push(IsoSection {
                    number: Some(n),
                    line,
                    blocks: Vec::new(),
                });
            }
            IsoLine::Block(b) => {
                if let Some(s) = sections.last_mut() {
                    s.blocks.push((line, b));
                }
            }
        }
    }
    if sections[0].blocks.is_empty() {
        sections.remove(0);
    }
    if sections.is_empty() {
        return Err(err(1, "no program in the text"));
    }
    for (k, s) in sections.iter().enumerate() {
        let name = s
            .number
            .map_or_else(|| "the main program".to_string(), |n| format!("O{n:04}"));
        let Some(((last_line, last), body)) = s.blocks.split_last() else {
            return Err(err(s.line, format!("{name} has no blocks")));
        };
        if k == 0 {
            if !matches!(last, IsoBlock::End(_)) {
                return Err(err(*last_line, format!("{name} does not end with M02/M30")));
            }
            for (l, b) in body {
                match b {
                    IsoBlock::End(m) => {
                        return Err(err(
                            *l,
                            format!("{m} before the end of {name}: the blocks after it never run"),
                        ))
                    }
                    IsoBlock::Return => return Err(err(*l, format!("M99 in {name}"))),
                    _ => {}
                }
            }
        } else {
            if !matches!(last, IsoBlock::Return) {
                return Err(err(
                    *last_line,
                    format!("subprogram {name} does not end with M99"),
                ));
            }
            for (l, b) in body {
                match b {
                    IsoBlock::End(m) => {
                        return Err(err(
                            *l,
                            format!(
                                "{m} in subprogram {name}: the program ends in the main program"
                            ),
                        ))
                    }
                    IsoBlock::Return => {
                        return Err(err(
                            *l,
                            format!("M99 before the end of {name}: the blocks after it never run"),
                        ))
                    }
                    _ => {}
                }
            }
        }
    }
    Ok(sections)
}

/// cos and sin of an angle in degrees, exact for whole quarter turns.
pub(crate) fn cos_sin_deg(deg: f64) -> (f64, f64) {
    let q = deg / 90.0;
    if q == q.round() && q.abs() < 1e9 {
        // q is a whole number of quarter turns
        match (q.round() as i64).rem_euclid(4) {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        }
    } else {
        let a = deg.to_radians();
        (a.cos(), a.sin())
    }
}

/// The frame programmed points are given in: machine = shift + c + Rot(p − c).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IsoFrame {
    pub(crate) shift: (f64, f64),
    pub(crate) rotation: Option<((f64, f64), f64, f64)>, // centre, cos, sin
}

impl IsoFrame {
    pub(crate) fn to_machine(&self, p: (f64, f64)) -> (f64, f64) {
        let q = match self.rotation {
            Some((c, cs, sn)) => {
                let (dx, dy) = (p.0 - c.0, p.1 - c.1);
                (c.0 + cs * dx - sn * dy, c.1 + sn * dx + cs * dy)
            }
            None => p,
        };
        (q.0 + self.shift.0, q.1 + self.shift.1)
    }
    pub(crate) fn to_program(&self, m: (f64, f64)) -> (f64, f64) {
        let q = (m.0 - self.shift.0, m.1 - self.shift.1);
        match self.rotation {
            Some((c, cs, sn)) => {
                let (dx, dy) = (q.0 - c.0, q.1 - c.1);
                (c.0 + cs * dx + sn * dy, c.1 - sn * dx + cs * dy)
            }
            None => q,
        }
    }
}

/// Distance of two points, mm.
pub(crate) fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// Runs the whole program as a control does: from the first block to M02/M30, main program and
/// subprograms (M98 P.. / M99), G68 rotation / G69, G41/G42/G40, G10 L12 offsets, G90/G92.
pub(crate) fn run_iso(text: &str) -> Result<IsoRun, String> {
    let sections = parse_sections(text)?;
    let mut moves = Vec::new();
    let mut start: Option<(f64, f64)> = None;
    let mut pos: Option<(f64, f64)> = None;
    let mut frame = IsoFrame {
        shift: (0.0, 0.0),
        rotation: None,
    };
    let mut motion: Option<u8> = None;
    let mut comp = Comp::Off;
    let mut d: Option<u32> = None;
    let mut registers: BTreeMap<u32, f64> = BTreeMap::new();
    // (section, next block) of the running program and of the callers
    let mut stack: Vec<(usize, usize)> = Vec::new();
    let (mut sec, mut idx) = (0usize, 0usize);
    loop {
        let Some((line, block)) = sections[sec].blocks.get(idx) else {
            // parse_sections makes every program end with M02/M30 or M99
            let l = sections[sec]
                .blocks
                .last()
                .map_or(sections[sec].line, |b| b.0);
            return Err(err(l, "the program runs past its last block"));
        };
        let line = *line;
        idx += 1;
        match block {
            IsoBlock::End(word) => {
                if comp != Comp::Off {
                    return Err(err(
                        line,
                        format!("{word} with compensation still on (no G40 lead-out)"),
                    ));
                }
                if frame.rotation.is_some() {
                    return Err(err(line, format!("{word} with G68 still in force")));
                }
                let Some(start) = start else {
                    return Err(err(line, "no G92: the start position is unknown"));
                };
                return Ok(IsoRun {
                    moves,
                    start,
                    ended_by: word.clone(),
                });
            }
            IsoBlock::Call(p) => {
                let Some(target) = sections.iter().position(|s| s.number == Some(*p)) else {
                    return Err(err(line, format!("M98 P{p}: no O{p:04} in the text")));
                };
                if target == 0 {
                    return Err(err(line, format!("M98 P{p} calls the main program")));
                }
                if stack.len() >= MAX_NESTING {
                    return Err(err(
                        line,
                        format!("subprograms nested deeper than {MAX_NESTING}"),
                    ));
                }
                stack.push((sec, idx));
                (sec, idx) = (target, 0);
            }
            IsoBlock::Return => {
                let Some(back) = stack.pop() else {
                    return Err(err(line, "M99 without a caller"));
                };
                (sec, idx) = back;
            }
            IsoBlock::Offset { register, value } => {
                registers.insert(*register, *value);
            }
            IsoBlock::SetPosition { x, y } => {
                if frame.rotation.is_some() {
                    return Err(err(line, "G92 while G68 is in force"));
                }
                if comp != Comp::Off {
                    return Err(err(line, "G92 while compensation is on"));
                }
                match pos {
                    None => {
                        pos = Some((*x, *y));
                        start = Some((*x, *y));
                    }
                    Some(p) => frame.shift = (p.0 - x, p.1 - y),
                }
            }
            IsoBlock::Rotate { centre, deg } => {
                if frame.rotation.is_some() {
                    return Err(err(line, "G68 while G68 is already in force (G69 first)"));
                }
                let (cs, sn) = cos_sin_deg(*deg);
                frame.rotation = Some((*centre, cs, sn));
            }
            IsoBlock::RotateOff => frame.rotation = None,
            IsoBlock::Motion {
                motion: m,
                comp: c,
                d: dw,
                x,
                y,
                i,
                j,
            } => {
                if dw.is_some() {
                    d = *dw;
                }
                if m.is_some() {
                    motion = *m;
                }
                let new_comp = c.clone().unwrap_or_else(|| comp.clone());
                let switching = new_comp != comp;
                let moves_here = x.is_some() || y.is_some() || i.is_some() || j.is_some();
                if switching && !moves_here {
                    return Err(err(
                        line,
                        "compensation switched in a block without a linear move",
                    ));
                }
                if moves_here {
                    let Some(from) = pos else {
                        return Err(err(line, "move before G92: the position is unknown"));
                    };
                    let Some(mode) = motion else {
                        return Err(err(line, "move without G00/G01/G02/G03 in force"));
                    };
                    let here = frame.to_program(from);
                    let target = (x.unwrap_or(here.0), y.unwrap_or(here.1));
                    let to = frame.to_machine(target);
                    let arc = if mode >= 2 {
                        if switching {
                            return Err(err(line, "arc while compensation is switched (lead-in/lead-out must be linear)"));
                        }
                        if i.is_none() && j.is_none() {
                            return Err(err(line, "arc without I or J"));
                        }
                        let centre = (here.0 + i.unwrap_or(0.0), here.1 + j.unwrap_or(0.0));
                        let r0 = dist(here, centre);
                        let r1 = dist(target, centre);
                        if r0 < 1e-7 {
                            return Err(err(line, "arc of no radius"));
                        }
                        if (r1 - r0).abs() > ARC_TOLERANCE_MM {
                            return Err(err(
                                line,
                                format!("arc end {:.4} mm off its circle (start radius {r0:.4}, end radius {r1:.4})", (r1 - r0).abs()),
                            ));
                        }
                        Some((frame.to_machine(centre), mode == 3))
                    } else {
                        if i.is_some() || j.is_some() {
                            return Err(err(line, "I/J on a linear move"));
                        }
                        if switching && dist(from, to) < 1e-7 {
                            return Err(err(line, "compensation switched on a move of no length"));
                        }
                        None
                    };
                    let offset_mm = if new_comp == Comp::Off {
                        0.0
                    } else {
                        let Some(reg) = d else {
                            return Err(err(line, "compensation without a D register"));
                        };
                        let Some(v) = registers.get(&reg) else {
                            return Err(err(
                                line,
                                format!("D{reg} without a register (no G10 L12 P{reg})"),
                            ));
                        };
                        *v
                    };
                    moves.push(IsoMove {
                        line,
                        from,
                        to,
                        rapid: mode == 0,
                        arc,
                        comp: new_comp.clone(),
                        offset_mm,
                    });
                    pos = Some(to);
                }
                comp = new_comp;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DIE: &str = include_str!("../golden/die_m1z40_iso.iso");
    const PUNCH: &str = include_str!("../golden/punch_pinion_undercut_iso.iso");

    fn close(a: (f64, f64), b: (f64, f64), tol: f64) -> bool {
        dist(a, b) <= tol
    }

    fn mv(line: usize, from: (f64, f64), to: (f64, f64), comp: Comp, offset_mm: f64) -> IsoMove {
        IsoMove {
            line,
            from,
            to,
            rapid: false,
            arc: None,
            comp,
            offset_mm,
        }
    }

    /// A die-style square: start hole at the centre, lead-in up to the middle of the top side,
    /// the square clockwise (one block modal, without G01), lead-out back.
    const SQUARE: &str = "%
O0001
(SQUARE 10 MM, DIE)
G90 G17 G21
G92 X0.0000 Y0.0000
G10 L12 P1 R0.1450
G42 D1 G01 X0.0000 Y5.0000
G01 X5.0000 Y5.0000
X5.0000 Y-5.0000
G01 X-5.0000 Y-5.0000
G01 Y5.0000
G01 X0.0000 Y5.0000
G40 G01 X0.0000 Y0.0000
M30
%
";

    #[test]
    fn square_with_lead_in_and_lead_out() {
        let run = run_iso(SQUARE).expect("square runs");
        assert_eq!(run.start, (0.0, 0.0));
        assert_eq!(run.ended_by, "M30");
        let r = Comp::Right;
        let expected = vec![
            mv(7, (0.0, 0.0), (0.0, 5.0), r.clone(), 0.145),
            mv(8, (0.0, 5.0), (5.0, 5.0), r.clone(), 0.145),
            mv(9, (5.0, 5.0), (5.0, -5.0), r.clone(), 0.145),
            mv(10, (5.0, -5.0), (-5.0, -5.0), r.clone(), 0.145),
            mv(11, (-5.0, -5.0), (-5.0, 5.0), r.clone(), 0.145),
            mv(12, (-5.0, 5.0), (0.0, 5.0), r, 0.145),
            mv(13, (0.0, 5.0), (0.0, 0.0), Comp::Off, 0.0),
        ];
        assert_eq!(run.moves, expected);
    }

    #[test]
    fn circle_of_two_arcs_punch() {
        let text = "O0002
G90 G17 G21
G92 X0.0000 Y15.0000
G10 L12 P3 R0.1000
G41 D3 G01 X0.0000 Y10.0000
G02 X0.0000 Y-10.0000 I0.0000 J-10.0000
G02 X0.0000 Y10.0000 I0 J10.0000
G00 G40 X0.0000 Y15.0000
M02
";
        let run = run_iso(text).expect("runs");
        assert_eq!(run.start, (0.0, 15.0));
        assert_eq!(run.ended_by, "M02");
        assert_eq!(run.moves.len(), 4);
        let a = &run.moves[1];
        assert_eq!(
            (a.line, a.from, a.to, a.arc),
            (6, (0.0, 10.0), (0.0, -10.0), Some(((0.0, 0.0), false)))
        );
        assert_eq!((a.comp.clone(), a.offset_mm), (Comp::Left, 0.1));
        let b = &run.moves[2];
        assert_eq!(
            (b.from, b.to, b.arc),
            ((0.0, -10.0), (0.0, 10.0), Some(((0.0, 0.0), false)))
        );
        let out = &run.moves[3];
        assert!(
            out.rapid && out.comp == Comp::Off && out.offset_mm == 0.0 && out.to == (0.0, 15.0)
        );
    }

    /// A quarter section run under G68 R0 and R−90 about the origin: the second call comes back
    /// turned a quarter clockwise, (x, y) → (y, −x), with the subprogram's own lines.
    #[test]
    fn g68_turns_a_subprogram_by_minus_90() {
        let text = "%
O0010
G90 G17 G21
G92 X0.0000 Y0.0000
G10 L12 P1 R0.1450
G41 D1 G01 X0.0000 Y10.0000
G68 X0 Y0 R0.0000
M98 P11
G69
G68 X0 Y0 R-90.0000
M98 P11
G69
G40 G01 X0.0000 Y0.0000
M02
O0011
G01 X2.0000 Y10.0000
G02 X10.0000 Y2.0000 I-2.0000 J-10.0000
G01 X10.0000 Y0.0000
M99
%
";
        let run = run_iso(text).expect("runs");
        let l = Comp::Left;
        let arc = |line, from, to| IsoMove {
            arc: Some(((0.0, 0.0), false)),
            ..mv(line, from, to, Comp::Left, 0.145)
        };
        let expected = vec![
            mv(6, (0.0, 0.0), (0.0, 10.0), l.clone(), 0.145),
            mv(16, (0.0, 10.0), (2.0, 10.0), l.clone(), 0.145),
            arc(17, (2.0, 10.0), (10.0, 2.0)),
            mv(18, (10.0, 2.0), (10.0, 0.0), l.clone(), 0.145),
            mv(16, (10.0, 0.0), (10.0, -2.0), l.clone(), 0.145),
            arc(17, (10.0, -2.0), (2.0, -10.0)),
            mv(18, (2.0, -10.0), (0.0, -10.0), l, 0.145),
            mv(13, (0.0, -10.0), (0.0, 0.0), Comp::Off, 0.0),
        ];
        assert_eq!(run.moves, expected);
    }

    #[test]
    fn g68_about_another_centre_and_by_30_degrees() {
        let text = "G92 X0.0000 Y0.0000
G68 X1.0000 Y1.0000 R30.0000
G00 X3.0000 Y1.0000
G69
M02
";
        let run = run_iso(text).expect("runs");
        let (s, c) = 30f64.to_radians().sin_cos();
        let want = (1.0 + 2.0 * c, 1.0 + 2.0 * s);
        assert!(close(run.moves[0].to, want, 1e-12));
        assert!(run.moves[0].rapid && run.moves[0].comp == Comp::Off);
    }

    #[test]
    fn full_circle_and_nesting() {
        let run = run_iso("G92 X10.0000 Y0.0000\nG02 I-10.0000\nM02\n").expect("runs");
        assert_eq!(run.moves.len(), 1);
        let m = &run.moves[0];
        assert_eq!(
            (m.from, m.to, m.arc),
            ((10.0, 0.0), (10.0, 0.0), Some(((0.0, 0.0), false)))
        );
        let err = run_iso("O0001\nG92 X0.0000 Y0.0000\nM98 P2\nM02\nO0002\nM98 P2\nM99\n");
        assert_eq!(
            err,
            Err("line 6: subprograms nested deeper than 4".to_string())
        );
    }

    fn refused(text: &str, line: usize, what: &str) {
        match run_iso(text) {
            Ok(_) => panic!("accepted, expected refusal at line {line} ({what})"),
            Err(e) => {
                assert!(
                    e.starts_with(&format!("line {line}:")),
                    "{e} (expected line {line})"
                );
                assert!(e.contains(what), "{e} (expected '{what}')");
            }
        }
    }

    #[test]
    fn refusals_name_the_line() {
        let head = "G90 G17 G21\nG92 X0.0000 Y0.0000\nG10 L12 P1 R0.1450\n";
        // unknown words
        refused(&format!("{head}G01 X1.0000 F200\nM02\n"), 4, "F200");
        refused(&format!("{head}M08\nM02\n"), 4, "M08");
        refused(&format!("G91\n{head}M02\n"), 1, "G91");
        refused(&format!("{head}N10 G01 X1.0000\nM02\n"), 4, "N10");
        refused(
            &format!("{head}G02 X1.0000 Y1.0000 R1.0000\nM02\n"),
            4,
            "R1.0000",
        );
        // an arc whose end is 10 µm off its circle; 4 µm passes
        refused(&format!("{head}G01 X10.0000 Y0.0000\nG02 X0.0000 Y-10.0100 I-10.0000 J0.0000\nG01 X0.0000 Y0.0000\nM02\n"), 5, "off its circle");
        assert!(run_iso(&format!("{head}G01 X10.0000 Y0.0000\nG02 X0.0000 Y-10.0040 I-10.0000 J0.0000\nG01 X0.0000 Y0.0000\nM02\n")).is_ok());
        // a D without a register
        refused(
            &format!("{head}G41 D2 G01 X1.0000 Y0.0000\nG40 G01 X0.0000 Y0.0000\nM02\n"),
            4,
            "D2 without a register",
        );
        // compensation switched on or off on an arc
        refused(
            &format!(
                "{head}G01 X10.0000 Y0.0000\nG41 D1 G02 X0.0000 Y-10.0000 I-10.0000 J0.0000\nM02\n"
            ),
            5,
            "arc while compensation",
        );
        refused(&format!("{head}G41 D1 G01 X10.0000 Y0.0000\nG40 G02 X0.0000 Y-10.0000 I-10.0000 J0.0000\nM02\n"), 5, "arc while compensation");
        refused(
            &format!("{head}G41 D1\nG01 X10.0000 Y0.0000\nM02\n"),
            4,
            "without a linear move",
        );
        // compensation left on, rotation left on
        refused(
            &format!("{head}G41 D1 G01 X10.0000 Y0.0000\nM02\n"),
            5,
            "compensation still on",
        );
        refused(&format!("{head}G68 X0 Y0 R90.0000\nM02\n"), 5, "G68 still");
        // endings
        refused(
            &format!("{head}G01 X1.0000 Y0.0000\n"),
            4,
            "does not end with M02/M30",
        );
        refused(
            &format!("{head}M02\nG01 X1.0000 Y0.0000\nM02\n"),
            4,
            "never run",
        );
        refused(
            &format!("O0001\n{head}M98 P2\nM02\nO0002\nG01 X1.0000 Y0.0000\n"),
            8,
            "does not end with M99",
        );
        refused(
            &format!("O0001\n{head}M98 P3\nM02\nO0002\nM99\n"),
            5,
            "no O0003",
        );
        refused(&format!("{head}M99\nM02\n"), 4, "M99 in");
        // no decimal point, no position, no mode
        refused(&format!("{head}G01 X5 Y0.0000\nM02\n"), 4, "decimal point");
        refused(
            "G01 X1.0000 Y0.0000\nG92 X0.0000 Y0.0000\nM02\n",
            1,
            "before G92",
        );
        refused("G92 X0.0000 Y0.0000\nX1.0000\nM02\n", 2, "without G00/G01");
        refused(
            "G92 X0.0000 Y0.0000\nG01 X1.0000 (OPEN\nM02\n",
            2,
            "not closed",
        );
        refused("G92 X0.0000 Y0.0000\nG01 X1.0000 ; END\nM02\n", 2, "';'");
    }

    /// The moves' total turning about the gear's centre, radians (negative: clockwise).
    fn winding(moves: &[IsoMove]) -> f64 {
        let mut total = 0.0;
        for m in moves {
            let pt = |t: f64| match &m.arc {
                None => (
                    m.from.0 + t * (m.to.0 - m.from.0),
                    m.from.1 + t * (m.to.1 - m.from.1),
                ),
                Some((c, ccw)) => {
                    let a0 = (m.from.1 - c.1).atan2(m.from.0 - c.0);
                    let mut a1 = (m.to.1 - c.1).atan2(m.to.0 - c.0);
                    if *ccw && a1 <= a0 {
                        a1 += std::f64::consts::TAU;
                    }
                    if !*ccw && a1 >= a0 {
                        a1 -= std::f64::consts::TAU;
                    }
                    // radius interpolated so that both ends are exact
                    let r = dist(m.from, *c) + t * (dist(m.to, *c) - dist(m.from, *c));
                    let a = a0 + t * (a1 - a0);
                    if t == 1.0 {
                        m.to
                    } else {
                        (c.0 + r * a.cos(), c.1 + r * a.sin())
                    }
                }
            };
            let mut prev = pt(0.0);
            for k in 1..=16 {
                let p = pt(f64::from(k) / 16.0);
                let mut da = p.1.atan2(p.0) - prev.1.atan2(prev.0);
                if da > std::f64::consts::PI {
                    da -= std::f64::consts::TAU;
                }
                if da < -std::f64::consts::PI {
                    da += std::f64::consts::TAU;
                }
                total += da;
                prev = p;
            }
        }
        total
    }

    fn max_radial_mismatch(moves: &[IsoMove]) -> f64 {
        moves
            .iter()
            .filter_map(|m| {
                m.arc
                    .as_ref()
                    .map(|(c, _)| (dist(m.from, *c) - dist(m.to, *c)).abs())
            })
            .fold(0.0, f64::max)
    }

    /// Checks common to both golden programs: a linear lead-in from the G92 start, radially to
    /// (0, r) on +Y, compensated on it; the outline all arcs, compensated, clockwise once round
    /// the gear's centre, closing on the lead-in's end; a linear lead-out back to the start, Off.
    /// The outline's corners (docs/wire.md, "The wire's path": "At a corner (the tooth's tip
    /// edges, an undercut's crossing)") are counted: `corner_count` joints turn by more than 1°.
    fn golden_shape(run: &IsoRun, side: &Comp, outline: usize, corner_count: usize) {
        let n = run.moves.len();
        assert_eq!(n, outline + 2);
        let (lead_in, lead_out) = (&run.moves[0], &run.moves[n - 1]);
        assert!(
            lead_in.arc.is_none()
                && !lead_in.rapid
                && lead_in.from == run.start
                && lead_in.to.0 == 0.0
        );
        assert_eq!((&lead_in.comp, lead_in.offset_mm), (side, 0.145));
        let contour = &run.moves[1..n - 1];
        for m in contour {
            assert!(m.arc.is_some(), "line {}: not an arc", m.line);
            assert_eq!((&m.comp, m.offset_mm), (side, 0.145));
        }
        assert!(close(contour[contour.len() - 1].to, lead_in.to, 1e-9));
        assert!(lead_out.arc.is_none() && lead_out.comp == Comp::Off && lead_out.offset_mm == 0.0);
        assert_eq!(lead_out.to, run.start);
        assert!(
            (winding(contour) + std::f64::consts::TAU).abs() < 1e-6,
            "winding {}",
            winding(contour)
        );
        // 4 decimals: start, end and I J each rounded by up to 0.05·√2 µm, so the two radii
        // of a written arc may differ by up to 3 · 0.0707 µm; far below the 5 µm refusal
        let mismatch = max_radial_mismatch(contour);
        assert!(
            mismatch < 3.0 * 0.05e-3 * std::f64::consts::SQRT_2,
            "{mismatch}"
        );
        assert_eq!(
            corners(contour, 1.0).len(),
            corner_count,
            "{:?}",
            corners(contour, 1.0)
        );
        // every other joint is tangent but for the 0.1 µm rounding (< 0.05° on the 0.4 mm arcs)
        assert_eq!(corners(contour, 0.05).len(), corner_count);
        assert_eq!(run.ended_by, "M02");
    }

    /// Joints between consecutive arcs whose tangents turn by more than `deg` degrees:
    /// (angle, line of the second arc).
    fn corners(moves: &[IsoMove], deg: f64) -> Vec<(f64, usize)> {
        let tangent = |c: (f64, f64), p: (f64, f64), ccw: bool| {
            let (vx, vy) = (p.0 - c.0, p.1 - c.1);
            let l = vx.hypot(vy);
            if ccw {
                (-vy / l, vx / l)
            } else {
                (vy / l, -vx / l)
            }
        };
        let mut out = Vec::new();
        for w in moves.windows(2) {
            if let (Some((c0, ccw0)), Some((c1, ccw1))) = (&w[0].arc, &w[1].arc) {
                let t0 = tangent(*c0, w[0].to, *ccw0);
                let t1 = tangent(*c1, w[1].from, *ccw1);
                let a = (t0.0 * t1.1 - t0.1 * t1.0)
                    .atan2(t0.0 * t1.0 + t0.1 * t1.1)
                    .abs()
                    .to_degrees();
                if a > deg {
                    out.push((a, w[1].line));
                }
            }
        }
        out
    }

    /// die_m1z40_iso: 40 teeth, a quarter (10 teeth, 110 arcs in O4002) called 4 times under
    /// G68 R0, −90, −180, −270; header: OUTLINE 440, BLOCKS 112 (110 + lead-in + lead-out),
    /// G42 (die, wire inside), OFFSET 0.1450.
    #[test]
    fn golden_die_m1z40() {
        let run = run_iso(DIE).expect("die runs");
        assert_eq!(run.start, (0.0, 0.0));
        golden_shape(&run, &Comp::Right, 440, 80);
        assert_eq!(run.moves[0].to, (0.0, 20.9997));
        assert_eq!((run.moves[0].line, run.moves[441].line), (18, 31));
        // each call runs O4002's lines 34..=143, the k-th turned by −90°·k
        for k in 0..4 {
            let first = &run.moves[1 + 110 * k];
            let last = &run.moves[110 * (k + 1)];
            assert_eq!((first.line, last.line), (34, 143));
            let (c, s) = cos_sin_deg(-90.0 * k as f64);
            let want = (20.9997 * -s, 20.9997 * c); // (0, 20.9997) turned
            assert!(close(first.from, want, 1e-12), "call {k}: {:?}", first.from);
        }
        // the first arc, turned by −90° in the second call: centre still the origin, clockwise
        assert_eq!(run.moves[111].arc, Some(((0.0, 0.0), false)));
        assert_eq!(run.moves[111].to, (20.9963, -0.3811));
    }

    /// punch_pinion_undercut_iso: 11 teeth (odd: whole), 165 arcs in the main program,
    /// G41 (punch, wire left: outside), start hole 5 mm outside the tip circle 9.6 on +Y.
    #[test]
    fn golden_punch_pinion_undercut() {
        let run = run_iso(PUNCH).expect("punch runs");
        assert_eq!(run.start, (0.0, 14.6));
        golden_shape(&run, &Comp::Left, 165, 44);
        assert_eq!(run.moves[0].to, (0.0, 9.6007));
        assert_eq!(
            (run.moves[0].line, run.moves[1].line, run.moves[166].line),
            (18, 19, 184)
        );
    }
}
