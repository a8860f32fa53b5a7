//! NC programs read back: the dialect parsers and the machine simulation of
//! the path check (seed 000 §4). Every program is parsed back and simulated
//! before it leaves the template service; anything else that reads programs
//! back (a web page, a future verifier) uses the same crate.
//!
//! [`parse`] reads a program in exactly the subset of its dialect that
//! `crates/nc/DIALECTS.md` describes (SINUMERIK 840D, FANUC with the
//! EGB `G81`) and refuses every other line with a `PARSE` finding naming it.
//! [`check`] parses and simulates the program against the machining model it
//! was made from: the parameter arithmetic (840D `R` parameters, FANUC `#5nn`
//! macro variables, all starting at 0), the axis motion (absolute, and the
//! incremental FANUC shift move), the electronic gearbox, the hob spindle and
//! the switched machine functions, and reports every rule the program breaks
//! (codes of [`gearcam_proto::Code`]), sorted by line, with a [`Trace`] of what it saw so callers can
//! compare the program with the model.
//!
//! Pure and allocation-light (a block is parsed in place; literals are read
//! without compiling; evaluation never allocates): the 45–71-line example
//! programs are checked in about 4–7 µs (release build, criterion bench
//! `one_job/*/path_check_only` of `tests/benches/template.rs`). It never
//! panics, whatever the text (property tests in `tests/path_check.rs`).
//!
//! # Layout
//!
//! - [`expr`]: number literals and the parameter arithmetic, compiled once per
//!   line and evaluated without allocating.
//! - `siemens`: the 840D line parser.
//! - `fanuc`: the FANUC line parser.
//! - [`number`]: NC numbers as programs write them.
//! - `sim`: the contact zones and the simulation that applies the rules
//!   (motion, machine functions, the electronic gearbox).
//! - `collide`: the swept hob solid against blanks and the machine's envelope,
//!   in closed form (its pieces reachable for the crate's tests and benchmark
//!   through the hidden `collide_hook`).

#![forbid(unsafe_code)]

mod collide;
pub mod expr;
mod fanuc;
pub mod number;
mod siemens;
mod sim;

use gearcam_proto::{Code, Dialect, MachiningModel, MoveKind, PathCheck, PathFinding};

#[doc(hidden)]
pub use collide::hook as collide_hook;
pub use expr::{Cond, EvalError, NcExpr, NcValue, Num, Rel};
pub use number::{format_fixed, push_fixed};

/// Longest axis name (840D identifiers have at most 8 characters).
pub const MAX_AXIS_NAME: usize = 8;

/// Most axis words one motion block may hold.
pub const MAX_AXIS_WORDS: usize = 5;

/// An axis name as written in the program (`X`, `Z`, `X1`), stored inline,
/// zero-padded.
#[derive(Clone, Copy, PartialEq, Eq, Default)]
pub struct AxisName {
    bytes: [u8; MAX_AXIS_NAME],
}

impl AxisName {
    /// The name, if it is 1–8 ASCII letters, digits or `_` starting with a letter.
    pub fn new(name: &[u8]) -> Option<AxisName> {
        let first = *name.first()?;
        if name.len() > MAX_AXIS_NAME
            || !first.is_ascii_alphabetic()
            || !name.iter().all(|b| b.is_ascii_alphanumeric() || *b == b'_')
        {
            return None;
        }
        let mut bytes = [0u8; MAX_AXIS_NAME];
        bytes[..name.len()].copy_from_slice(name);
        Some(AxisName { bytes })
    }

    /// The name as text.
    pub fn as_str(&self) -> &str {
        let len = self
            .bytes
            .iter()
            .position(|b| *b == 0)
            .unwrap_or(MAX_AXIS_NAME);
        std::str::from_utf8(&self.bytes[..len]).unwrap_or("?")
    }

    /// True when this is `name`.
    pub fn is(&self, name: &str) -> bool {
        self.as_str() == name
    }
}

impl std::fmt::Debug for AxisName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.as_str())
    }
}

impl std::fmt::Display for AxisName {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One axis word: `X=74.05`, `Y=R20+R22*(R26 MOD R24)`, `Y[#520+#522]`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct AxisWord {
    /// The axis.
    pub axis: AxisName,
    /// Its value (absolute, or an increment under FANUC `G91`).
    pub value: NcValue,
}

/// Interpolation of a motion block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interp {
    /// `G0` / `G00`.
    Rapid,
    /// `G1` / `G01`.
    Linear,
    /// 840D `CIP`: a circle through an intermediate point.
    CircleVia,
    /// FANUC `G02`: clockwise arc in the Z–X plane (G18), radius form.
    ArcCw,
    /// FANUC `G03`: counter-clockwise arc in the Z–X plane, radius form.
    ArcCcw,
}

/// Absolute or incremental dimensions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Distance {
    /// `G90`.
    Absolute,
    /// `G91` (FANUC shift move only).
    Incremental,
}

/// Set-up codes a block states (modal; the simulation collects them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Setup {
    /// `G71` (840D) or `G21` (FANUC): metric input.
    pub metric: bool,
    /// `G54`–`G59`: the work offset's number.
    pub work_offset: Option<u8>,
    /// 840D `DIAMOF`: X is a radius (the centre distance).
    pub radius_x: bool,
    /// FANUC `G18`: arcs in the Z–X plane. A FANUC control starts in `G17`
    /// (the X–Y plane), where `G02 X… Z… R…` is not the arc in X and Z.
    pub plane_zx: bool,
}

impl Setup {
    /// Adds the codes of `other`.
    pub fn merge(&mut self, other: Setup) {
        self.metric |= other.metric;
        self.radius_x |= other.radius_x;
        self.plane_zx |= other.plane_zx;
        if other.work_offset.is_some() {
            self.work_offset = other.work_offset;
        }
    }
}

/// A motion block (or a block that only sets modal motion codes).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Motion {
    /// Interpolation given in this block.
    pub interp: Option<Interp>,
    /// Dimensions given in this block.
    pub distance: Option<Distance>,
    /// `G94` / `G98`: feed per minute given in this block.
    pub per_minute: bool,
    /// The G code that set feed per minute (94 or 98), for the G-code system check.
    pub feed_code: Option<u8>,
    /// Set-up codes stated in this block.
    pub setup: Setup,
    words: [AxisWord; MAX_AXIS_WORDS],
    n_words: u8,
    /// 840D `CIP` intermediate point (`I1`, `K1`): X and Z, absolute.
    pub via: Option<(Num, Num)>,
    /// FANUC arc radius `R`.
    pub radius: Option<Num>,
    /// Feed `F`, mm/min.
    pub feed: Option<Num>,
}

impl Motion {
    /// The axis words in the order written.
    pub fn words(&self) -> &[AxisWord] {
        &self.words[..usize::from(self.n_words).min(MAX_AXIS_WORDS)]
    }

    /// Adds an axis word; refuses a repeated axis or too many words.
    fn push(&mut self, word: AxisWord) -> Result<(), String> {
        if self.words().iter().any(|w| w.axis == word.axis) {
            return Err(format!("axis {} is written twice", word.axis));
        }
        let n = usize::from(self.n_words);
        if n >= MAX_AXIS_WORDS {
            return Err(format!("more than {MAX_AXIS_WORDS} axis words"));
        }
        self.words[n] = word;
        self.n_words += 1;
        Ok(())
    }
}

/// One leading axis of an 840D `EGON` / `EGONSYNE`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lead {
    /// The leading axis.
    pub axis: AxisName,
    /// `EGONSYNE` synchronised position of the leading axis.
    pub position: Option<Num>,
    /// Numerator of the coupling factor.
    pub num: Num,
    /// Denominator of the coupling factor.
    pub den: Num,
}

/// What a block does.
// A motion block is the common case; keeping it inline spares an allocation
// per block.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    /// `R<n>=expr` (840D) or `#n=expr` (FANUC); `param` is `n`.
    Assign {
        /// Parameter index: `R` number, or FANUC variable − 500.
        param: u16,
        /// The value.
        value: NcValue,
    },
    /// A motion block.
    Motion(Motion),
    /// `G4 F=s` (840D) or `G04 Xs` (FANUC).
    Dwell {
        /// Dwell time, seconds.
        seconds: Num,
    },
    /// An M function, with the spindle speed `S` when given.
    MCode {
        /// The M number.
        code: u16,
        /// `S`, rpm.
        speed: Option<Num>,
    },
    /// 840D `EGDEF(following, leading, type, ...)`.
    GearDefine {
        /// Following axis (the table).
        following: AxisName,
        /// Leading axes with their coupling type.
        leading: Vec<(AxisName, i64)>,
    },
    /// 840D `EGON` or (`sync`) `EGONSYNE`.
    GearOn {
        /// True for `EGONSYNE` (coupled at synchronised positions).
        sync: bool,
        /// `EGONSYNE`: the following axis's synchronised position.
        position: Option<Num>,
        /// Following axis.
        following: AxisName,
        /// Leading axes, the hob first.
        leading: Vec<Lead>,
    },
    /// FANUC `G81 T L [Q P]`.
    FanucGearOn {
        /// `T`: teeth.
        teeth: Num,
        /// `L`: hob starts, signed.
        starts: Num,
        /// `Q`: normal module, mm.
        module: Option<Num>,
        /// `P`: helix angle, degrees, signed.
        helix: Option<Num>,
    },
    /// 840D `EGOFS(following)` or FANUC `G80` (no axis).
    GearOff {
        /// The following axis named (840D).
        following: Option<AxisName>,
    },
    /// 840D `EGDEL(following)`.
    GearDelete {
        /// The following axis named.
        following: AxisName,
    },
    /// 840D `MSG(...)`: an operator message.
    Message,
    /// 840D `IF cond`: the blocks up to its `ELSE` or `ENDIF` run when the
    /// condition holds. Only parameter assignments may stand inside.
    If(Cond),
    /// 840D `ELSE`.
    Else,
    /// 840D `ENDIF`.
    EndIf,
    /// FANUC `IF [cond] THEN #5nn=expr`: an assignment made when the
    /// condition holds.
    AssignIf {
        /// The condition.
        cond: Cond,
        /// Parameter index: FANUC variable − 500.
        param: u16,
        /// The value.
        value: NcValue,
    },
}

/// One NC block with its place in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// 1-based line in the program text.
    pub line: u32,
    /// Block number `N`, when written.
    pub number: Option<u32>,
    /// What it does.
    pub op: Op,
}

/// What the simulation saw; used by callers to compare with the model
/// (round-trip tests).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    /// Every motion block in order.
    pub moves: Vec<TraceMove>,
    /// Every gearbox-on block (`EGON`, `EGONSYNE`, `G81`).
    pub couplings: Vec<TraceCoupling>,
    /// Every spindle speed `S` programmed: (line, rpm).
    pub spindle_rpm: Vec<(u32, f64)>,
    /// Every swivel angle programmed: (line, degrees).
    pub swivel_deg: Vec<(u32, f64)>,
    /// Every M function: (line, number).
    pub mcodes: Vec<(u32, u16)>,
}

/// One simulated move.
#[derive(Debug, Clone, PartialEq)]
pub struct TraceMove {
    /// Line of the block.
    pub line: u32,
    /// Rapid, feed, arc or dwell.
    pub kind: MoveKind,
    /// X after the move, absolute, mm.
    pub x_mm: f64,
    /// Z after the move, absolute, mm.
    pub z_mm: f64,
    /// Y (hob shift) after the move, absolute, mm.
    pub y_mm: f64,
    /// Feed in effect for feed and arc moves, mm/min.
    pub feed_mm_min: Option<f64>,
    /// Dwell time, s.
    pub dwell_s: Option<f64>,
    /// True when the gearbox was coupled during the move.
    pub coupled: bool,
    /// FANUC: the C correction superimposed on a shift move, degrees.
    pub c_correction_deg: Option<f64>,
    /// The circle an arc move follows (`None` for the other kinds).
    pub arc: Option<TraceArc>,
}

/// The circle of an arc move in the Z–X plane: the tool runs round `centre`
/// from the move's start point through `sweep_rad` (positive from +Z
/// towards +X) to its end point, Y moving linearly with the angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TraceArc {
    /// The centre's Z, mm.
    pub centre_z_mm: f64,
    /// The centre's X, mm.
    pub centre_x_mm: f64,
    /// The signed angle swept, radians.
    pub sweep_rad: f64,
}

/// One gearbox-on block.
#[derive(Debug, Clone, PartialEq)]
pub struct TraceCoupling {
    /// Line of the block.
    pub line: u32,
    /// Hob ratio numerator (840D num, FANUC `L`).
    pub num: i64,
    /// Hob ratio denominator (840D den, FANUC `T`).
    pub den: i64,
    /// Degrees of C per mm of Z: the 840D Z factor, or the FANUC helical
    /// compensation 360·sin P/(π·Q·T).
    pub c_per_z_deg_per_mm: Option<f64>,
    /// Degrees of C per mm of Y (840D Y factor).
    pub c_per_y_deg_per_mm: Option<f64>,
    /// True when this coupling starts a gear unit (the first of the program,
    /// one after a new `EGDEF`, or a `G81` after a `G80`).
    pub unit_start: bool,
    /// True for an 840D `EGONSYNE`: the table is moved to synchronised
    /// positions relative to the hob, so every coupling at the same positions
    /// has the same phase. False for a plain `EGON` and a FANUC `G81` (no
    /// phase synchronisation in the subset read): the phase is wherever the
    /// axes stand.
    pub synchronised: bool,
}

/// Parses and simulates `text` (the dialect is the model's machine's) against
/// the model it was made from. Findings are sorted by line; `ok` means none.
/// A program that does not parse gets only its `PARSE` findings and an empty
/// trace.
pub fn check(text: &str, model: &MachiningModel) -> (PathCheck, Trace) {
    let dialect = model.plan.machine.dialect;
    let mut parsed = parse_text(dialect, text);
    if parsed.findings.is_empty() {
        parsed.findings = structure(&parsed.blocks);
    }
    let (mut findings, trace) = if parsed.findings.is_empty() {
        let (mut findings, trace) = sim::run(dialect, &parsed.blocks, model, parsed.lines.max(1));
        findings.extend(collide::check(model, &trace));
        (findings, trace)
    } else {
        (parsed.findings, Trace::default())
    };
    findings.sort_by_key(|f| f.line);
    (
        PathCheck {
            ok: findings.is_empty(),
            findings,
        },
        trace,
    )
}

/// The 840D `IF` / `ELSE` / `ENDIF` pair up, and only parameter assignments
/// stand between them, so that every run of the program takes the path the
/// simulation follows whatever the parameters the machine keeps between runs
/// (the part counter). One `PARSE` finding per broken `IF`.
fn structure(blocks: &[Block]) -> Vec<PathFinding> {
    struct Open {
        line: u32,
        otherwise: bool,
        /// First block inside that is not an assignment.
        bad: Option<u32>,
    }
    let mut open: Vec<Open> = Vec::new();
    let mut findings = Vec::new();
    let mut refuse = |line: u32, message: String| {
        findings.push(finding(
            line,
            Code::PARSE,
            format!("line {line}: {message}"),
        ));
    };
    for b in blocks {
        match b.op {
            Op::If(_) => open.push(Open {
                line: b.line,
                otherwise: false,
                bad: None,
            }),
            Op::Else => match open.last_mut() {
                Some(o) if !o.otherwise => o.otherwise = true,
                Some(o) => refuse(b.line, format!("a second ELSE for the IF of line {}", o.line)),
                None => refuse(b.line, "ELSE without an IF".into()),
            },
            Op::EndIf => match open.pop() {
                Some(Open {
                    line: start,
                    bad: Some(bad),
                    ..
                }) => refuse(
                    bad,
                    format!("only R-parameter assignments may stand inside the IF of line {start}, so that every run takes the path this check simulates"),
                ),
                Some(_) => {}
                None => refuse(b.line, "ENDIF without an IF".into()),
            },
            Op::Assign { .. } | Op::AssignIf { .. } => {}
            _ => {
                if let Some(o) = open.last_mut() {
                    o.bad.get_or_insert(b.line);
                }
            }
        }
    }
    for o in open {
        refuse(o.line, "this IF is not closed by an ENDIF".into());
    }
    findings
}

/// Most `PARSE` findings reported for one text; the rest are summed up in one.
pub const MAX_PARSE_FINDINGS: usize = 100;

/// Parsing alone: every NC block with its 1-based line (comment, header and
/// blank lines give none), or the `PARSE` findings.
pub fn parse(dialect: Dialect, text: &str) -> Result<Vec<Block>, Vec<PathFinding>> {
    let out = parse_text(dialect, text);
    if out.findings.is_empty() {
        Ok(out.blocks)
    } else {
        Err(out.findings)
    }
}

fn parse_text(dialect: Dialect, text: &str) -> Parsed {
    let mut out = Parsed {
        blocks: Vec::with_capacity(text.len() / 24 + 1),
        findings: Vec::new(),
        refused: 0,
        lines: 0,
    };
    match dialect {
        Dialect::Sinumerik840d => siemens::parse(text, &mut out),
        Dialect::Fanuc => fanuc::parse(text, &mut out),
        other => out.findings.push(finding(
            1,
            Code::PARSE,
            format!(
                "line 1: the path check reads SINUMERIK 840D and FANUC programs, not {}",
                other.as_str()
            ),
        )),
    }
    if out.refused > MAX_PARSE_FINDINGS {
        let more = out.refused - MAX_PARSE_FINDINGS;
        let line = out.findings.last().map_or(1, |f| f.line);
        out.findings.push(finding(
            line,
            Code::PARSE,
            format!("line {line}: and {more} more lines outside the subset"),
        ));
    }
    out
}

/// The parsers' output.
struct Parsed {
    blocks: Vec<Block>,
    findings: Vec<PathFinding>,
    refused: usize,
    /// Lines in the text.
    lines: u32,
}

impl Parsed {
    /// Parses NC line `line` whose block text (comment stripped) is `body`
    /// with `parse`, which fills a block pushed for it in place (a motion block
    /// is a few hundred bytes; built where it stays, it is not copied again).
    fn block(
        &mut self,
        line: u32,
        raw: &str,
        body: Result<&str, String>,
        parse: impl FnOnce(&str, &mut Block) -> Result<(), String>,
    ) {
        self.lines = line;
        let body = match body {
            Ok("") => return,
            Ok(body) => body,
            Err(reason) => return self.refuse(line, raw, &reason),
        };
        self.blocks.push(Block {
            line,
            number: None,
            op: Op::Message,
        });
        let Some(slot) = self.blocks.last_mut() else {
            return;
        };
        if let Err(reason) = parse(body, slot) {
            self.blocks.pop();
            self.refuse(line, raw, &reason);
        }
    }

    /// Records line `line` that is no NC block (a header or trailer line).
    fn other(&mut self, line: u32, raw: &str, result: Result<(), String>) {
        self.lines = line;
        if let Err(reason) = result {
            self.refuse(line, raw, &reason);
        }
    }

    /// A `PARSE` finding for `raw` at `line`.
    fn refuse(&mut self, line: u32, raw: &str, reason: &str) {
        self.refused += 1;
        if self.refused <= MAX_PARSE_FINDINGS {
            self.findings.push(finding(
                line,
                Code::PARSE,
                format!("line {line}: {reason}: \"{}\"", snippet(raw)),
            ));
        }
    }
}

/// At most 60 characters of a line, printable ASCII only, for messages.
fn snippet(raw: &str) -> String {
    let mut s: String = raw
        .chars()
        .take(60)
        .map(|c| if (' '..='~').contains(&c) { c } else { '?' })
        .collect();
    if raw.chars().nth(60).is_some() {
        s.push_str("...");
    }
    s
}

fn finding(line: u32, rule: Code, message: String) -> PathFinding {
    PathFinding {
        line,
        rule,
        message,
    }
}

/// Every line of `text` with its 1-based number (a `\r` before `\n` dropped).
fn numbered_lines(text: &str) -> impl Iterator<Item = (u32, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (u32::try_from(i + 1).unwrap_or(u32::MAX), l))
}

/// An optional block number `N<n>` at the cursor.
fn block_number(c: &mut expr::Cursor<'_>) -> Result<Option<u32>, String> {
    if c.peek() == Some(b'N') && c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
        c.bump();
        let n = expr::small_uint(c.digits()).ok_or("the block number has more than 9 digits")?;
        return Ok(Some(n));
    }
    Ok(None)
}

/// Checks a literal's decimals and decimal point.
fn literal(n: Num, what: &str, max_decimals: u8, point: bool) -> Result<Num, String> {
    if point && !n.point {
        return Err(format!("{what} {} needs a decimal point", n.value));
    }
    if !point && n.point {
        return Err(format!("{what} must be a whole number"));
    }
    if n.decimals > max_decimals {
        return Err(format!(
            "{what} has {} decimals, at most {max_decimals} are written",
            n.decimals
        ));
    }
    Ok(n)
}

/// Parses one line of a dialect with its `body` and `block` functions: the
/// unit tests' way to read a single block.
#[cfg(test)]
fn one_block(
    line: &str,
    body: fn(&str) -> Result<&str, String>,
    block: fn(&str, &mut Block) -> Result<(), String>,
) -> Result<Op, String> {
    let mut b = Block {
        line: 1,
        number: None,
        op: Op::Message,
    };
    let text = body(line)?;
    assert!(!text.is_empty(), "{line} holds no block");
    block(text, &mut b)?;
    Ok(b.op)
}
