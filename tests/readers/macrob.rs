//! A clean-room reader of the FANUC programs gearcam writes for spiral face
//! milling (`fanuc-macro`, `fanuc-arcs`, `fanuc-chords`), written from
//! `docs/spiral.md` ("The FANUC macro", "Tangent arcs (G02/G03)", "Where the
//! spiral starts and ends", "Planar spiral groove"), `crates/nc/DIALECTS.md`
//! (the FANUC number and comment rules) and FANUC Custom Macro B convention,
//! without any of gearcam's own code.
//!
//! [`run_fanuc`] executes the text from its first block to `M30` (or `M02`)
//! and lists every motion block the control makes, in absolute mm of the work
//! frame.
//!
//! # The text
//!
//! - One block a line. `(…)` comments are removed (no `(` inside a comment,
//!   DIALECTS.md "comment lines in parentheses … no parentheses inside");
//!   spaces are ignored, as on the control. Outside comments only upper-case
//!   letters, digits and `# [ ] + - * / = . , %` are accepted (lower case is
//!   refused).
//! - `%` lines frame the tape. `O####` starts a program: the first program in
//!   the text is the main program, later ones are subprograms that `G65 P####`
//!   calls ("The family program": "the value-free subprogram stays in the
//!   control"; here it is in the same text). Without any `O` line the text
//!   from its first block is the main program. Reaching a `%` or another
//!   program's `O` line without `M30`/`M02`/`M99` is an error.
//! - An optional leading `N` sequence number is a label for `GOTO`.
//!
//! # Macro statements ("The FANUC macro", the `macrob` subset list)
//!
//! - `#i = expr`; variables #1–#33 (locals, one set per macro call level),
//!   #100–#199 and #500–#999 (commons), `#[expr]` indirection. Reading a
//!   variable that was never set (FANUC "vacant", #0 included) is refused:
//!   a control would read it as 0 in arithmetic or drop the address word,
//!   which would hide a generator bug.
//! - `+ − * /`, unary sign, `[ ]`; functions `SIN COS TAN` (degrees),
//!   `ATAN[y]/[x]` or `ATAN[y,x]` (degrees, 0 ≤ result < 360, FANUC's default
//!   range), `SQRT ABS`, `ROUND` (half away from zero), `FIX` (towards zero:
//!   FIX[−1.2] = −1), `FUP` (away from zero: FUP[−1.2] = −2). Inside an axis
//!   address (X Y Z I J) `ROUND` rounds to the least input increment instead
//!   (FANUC rule), 0.001 mm unless [`run_fanuc_quantised`] names another.
//! - Comparisons `EQ NE GT GE LT LE` (exact), `AND OR` between comparisons
//!   only (no bitwise use). Precedence: functions and brackets, `* /`, `+ −`,
//!   comparison, `AND`, `OR`.
//! - `WHILE [cond] DOm … ENDm` (m = 1…3, nested at most three deep, ranges may
//!   not cross), a bare `DOm … ENDm` loops for ever, `IF [cond] GOTO n`,
//!   `IF [cond] THEN #i = expr`, `GOTO n` (n may be an expression) within the
//!   current program; a `GOTO` into a loop from outside it is refused.
//!
//! # NC blocks
//!
//! - `G00 G01 G02 G03` (modal), `G04` dwell, `G15`/`G16` polar coordinates,
//!   `G17` plane, `G21` metric, `G90`/`G91`, `G94`, `G40 G49 G80` (cancels,
//!   no effect here), `G54` (the one work frame), `G65` calls; `M03 M04 M05
//!   M08 M09` (no motion), `M30`/`M02` end, `M99` return. `F` feed (mm/min,
//!   modal), `S` speed. Any other G or M code or address letter is refused.
//!   Two G codes of one group in a block: the last one counts (FANUC).
//! - Axis words X Y Z and arc words I J take a number, `#i`, `[expr]`, with
//!   an optional sign. A literal axis number must carry a decimal point
//!   (DIALECTS.md: "a decimal point is always written (12.0, never 12)"); a
//!   control reads `X12` as 12 increments, so it is refused as ambiguous.
//! - The position before the first move is unknown; the reader starts at
//!   (0, 0, 0), so the first move's `from` is (0, 0, 0) and not the machine's
//!   real position.
//! - `G16` ("The FANUC macro": "`G16` polar coordinates (X radius, Y angle
//!   about the work origin)"): in `G90` the target is (X·cos Y, X·sin Y) about
//!   the work origin, angle in degrees counter-clockwise from +X. A block that
//!   gives only X (radius) keeps the current point's angle about the origin;
//!   one that gives only Y (angle) keeps the current point's radius; one that
//!   gives neither (a Z-only plunge) leaves X Y where they are. Omitting the
//!   angle at the origin itself is refused (no angle there). `G91` and arcs
//!   under `G16` are refused. `G15` cancels.
//! - Arcs ("Tangent arcs (G02/G03)": "`I J`, the centre measured from the
//!   start"): G02 clockwise, G03 counter-clockwise seen from +Z (G17), centre
//!   = start + (I, J) in both G90 and G91, I or J omitted = 0, the end point
//!   equal to the start is a full circle. The start and end radii must agree
//!   within 0.001 mm. `R` arcs are outside the subset.
//! - A feed move needs an F in force (FANUC alarm otherwise); rapids carry no
//!   feed. Every block with an axis word is one move, even of zero length.
//!   Moves are reported by their end points only: a G00 is listed as the
//!   straight segment from → to (a control may move its axes independently),
//!   and G01 under G16 is a straight line in X Y, as FANUC interpolates it.
//!   The spindle state (M03/M05) is not checked against feed moves.
//!
//! # Calls ("The FANUC macro", "The family program")
//!
//! `G65 P#### <letters>` with argument specification I: A→#1 B→#2 C→#3 I→#4
//! J→#5 K→#6 D→#7 E→#8 F→#9 H→#11 M→#13 Q→#17 R→#18 S→#19 T→#20 U→#21 V→#22
//! W→#23 X→#24 Y→#25 Z→#26. The caller's locals are saved, the callee starts
//! with only its arguments set, `M99` restores the caller's and returns to the
//! block after the `G65`. At most four call levels. `L` (repeat count), a
//! second I/J/K (argument specification II) and arguments without a decimal
//! point are refused. Modal G states are not saved across a call.
//!
//! `budget` bounds the executed blocks (blank and comment-only lines are not
//! counted).

use std::collections::HashMap;

/// One motion the control makes, absolute mm in the work frame (X, Y, Z).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MillMove {
    /// 1-based line of the executed block.
    pub(crate) line: usize,
    /// Where the move starts; (0, 0, 0) before the first move (unknown start).
    pub(crate) from: (f64, f64, f64),
    /// Where the move ends.
    pub(crate) to: (f64, f64, f64),
    /// `G00`.
    pub(crate) rapid: bool,
    /// `G02`/`G03`: the XY centre, and whether it runs counter-clockwise (G03).
    pub(crate) arc: Option<((f64, f64), bool)>,
    /// The F in force for a feed move, mm/min; `None` for a rapid.
    pub(crate) feed: Option<f64>,
}

/// The executed program: every move, and the code that ended it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MillRun {
    pub(crate) moves: Vec<MillMove>,
    /// "M30" or "M02".
    pub(crate) ended_by: String,
}

/// Runs the whole program from its first block to M30, executing the macro
/// statements, loops, G65 calls (subprograms in the same text), polar mode,
/// etc. `budget` bounds executed blocks. Values are used exactly as computed
/// (no rounding to an input increment); the start point is (0, 0, 0).
pub(crate) fn run_fanuc(text: &str, budget: usize) -> Result<MillRun, String> {
    run_fanuc_quantised(text, budget, None)
}

/// As [`run_fanuc`], but with `increment_mm` set every axis and arc address
/// value (X Y Z I J, the `G16` angle included, in degrees) is rounded to that
/// least input increment, as a control does with a variable's value in an
/// address (0.001 for IS-B, 0.0001 for IS-C).
pub(crate) fn run_fanuc_quantised(
    text: &str,
    budget: usize,
    increment_mm: Option<f64>,
) -> Result<MillRun, String> {
    if let Some(q) = increment_mm {
        if !(q.is_finite() && q > 0.0) {
            return Err(format!("the input increment must be positive, got {q}"));
        }
    }
    let program = Program::parse(text)?;
    let mut machine = Machine::new(&program, increment_mm);
    machine.run(budget)
}

// ---------------------------------------------------------------------------
// Parsing

#[derive(Debug, Clone, Copy, PartialEq)]
enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Func {
    Sin,
    Cos,
    Tan,
    Sqrt,
    Abs,
    Round,
    Fix,
    Fup,
}

#[derive(Debug, Clone, PartialEq)]
enum Expr {
    Num(f64),
    Var(Box<Expr>),
    Neg(Box<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    Call(Func, Box<Expr>),
    Atan(Box<Expr>, Box<Expr>),
}

#[derive(Debug, Clone, PartialEq)]
struct Word {
    letter: char,
    value: Expr,
    /// A plain number literal written without a decimal point.
    bare_integer: bool,
}

#[derive(Debug, Clone, PartialEq)]
enum Stmt {
    Blank,
    Tape,
    ProgramNo(u32),
    Assign {
        index: Expr,
        value: Expr,
    },
    While {
        cond: Expr,
        id: u8,
    },
    Do(u8),
    End(u8),
    IfGoto {
        cond: Expr,
        target: Expr,
    },
    IfThen {
        cond: Expr,
        index: Expr,
        value: Expr,
    },
    Goto(Expr),
    Nc(Vec<Word>),
}

#[derive(Debug, Clone, PartialEq)]
struct Block {
    line: usize,
    label: Option<u32>,
    stmt: Stmt,
}

/// Removes comments and spaces; refuses characters outside the subset.
fn clean_line(raw: &str, line: usize) -> Result<String, String> {
    let mut out = String::new();
    let mut in_comment = false;
    for c in raw.chars() {
        if in_comment {
            match c {
                ')' => in_comment = false,
                '(' => return Err(format!("line {line}: '(' inside a comment")),
                _ => {}
            }
            continue;
        }
        match c {
            '(' => in_comment = true,
            ')' => return Err(format!("line {line}: ')' without '('")),
            ' ' | '\t' | '\r' => {}
            'A'..='Z'
            | '0'..='9'
            | '#'
            | '['
            | ']'
            | '+'
            | '-'
            | '*'
            | '/'
            | '='
            | '.'
            | ','
            | '%' => out.push(c),
            other => {
                return Err(format!(
                    "line {line}: character {other:?} is outside the subset"
                ))
            }
        }
    }
    if in_comment {
        return Err(format!("line {line}: comment not closed"));
    }
    Ok(out)
}

#[derive(Debug, Clone, PartialEq)]
struct Cursor {
    s: Vec<u8>,
    i: usize,
    line: usize,
}

impl Cursor {
    fn new(s: &str, line: usize) -> Cursor {
        Cursor {
            s: s.as_bytes().to_vec(),
            i: 0,
            line,
        }
    }

    fn err<T>(&self, what: &str) -> Result<T, String> {
        let rest = String::from_utf8_lossy(&self.s[self.i.min(self.s.len())..]).into_owned();
        Err(format!("line {}: {what} (at \"{rest}\")", self.line))
    }

    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    fn at_end(&self) -> bool {
        self.i >= self.s.len()
    }

    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    fn expect(&mut self, c: u8) -> Result<(), String> {
        if self.eat(c) {
            Ok(())
        } else {
            self.err(&format!("expected '{}'", c as char))
        }
    }

    fn starts_with(&self, kw: &str) -> bool {
        self.s[self.i.min(self.s.len())..].starts_with(kw.as_bytes())
    }

    fn eat_kw(&mut self, kw: &str) -> bool {
        if self.starts_with(kw) {
            self.i += kw.len();
            true
        } else {
            false
        }
    }

    fn digits(&mut self) -> Option<u32> {
        let start = self.i;
        while matches!(self.peek(), Some(b'0'..=b'9')) {
            self.i += 1;
        }
        if start == self.i {
            return None;
        }
        std::str::from_utf8(&self.s[start..self.i])
            .ok()?
            .parse()
            .ok()
    }

    /// A number literal: digits with at most one decimal point. Returns the
    /// value and whether a point was written.
    fn number(&mut self) -> Result<(f64, bool), String> {
        let start = self.i;
        let mut point = false;
        let mut digits = 0;
        while let Some(c) = self.peek() {
            match c {
                b'0'..=b'9' => digits += 1,
                b'.' if !point => point = true,
                _ => break,
            }
            self.i += 1;
        }
        if digits == 0 {
            self.i = start;
            return self.err("expected a number");
        }
        let text = String::from_utf8_lossy(&self.s[start..self.i]).into_owned();
        match text.parse::<f64>() {
            Ok(v) => Ok((v, point)),
            Err(_) => self.err("bad number"),
        }
    }

    fn expr(&mut self) -> Result<Expr, String> {
        let mut left = self.and_expr()?;
        while self.eat_kw("OR") {
            let right = self.and_expr()?;
            left = Expr::Bin(BinOp::Or, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn and_expr(&mut self) -> Result<Expr, String> {
        let mut left = self.cmp_expr()?;
        while self.eat_kw("AND") {
            let right = self.cmp_expr()?;
            left = Expr::Bin(BinOp::And, Box::new(left), Box::new(right));
        }
        Ok(left)
    }

    fn cmp_expr(&mut self) -> Result<Expr, String> {
        let left = self.add_expr()?;
        let ops = [
            ("EQ", BinOp::Eq),
            ("NE", BinOp::Ne),
            ("GT", BinOp::Gt),
            ("GE", BinOp::Ge),
            ("LT", BinOp::Lt),
            ("LE", BinOp::Le),
        ];
        for (kw, op) in ops {
            if self.eat_kw(kw) {
                let right = self.add_expr()?;
                return Ok(Expr::Bin(op, Box::new(left), Box::new(right)));
            }
        }
        Ok(left)
    }

    fn add_expr(&mut self) -> Result<Expr, String> {
        let mut left = self.mul_expr()?;
        loop {
            let op = if self.eat(b'+') {
                BinOp::Add
            } else if self.eat(b'-') {
                BinOp::Sub
            } else {
                return Ok(left);
            };
            let right = self.mul_expr()?;
            left = Expr::Bin(op, Box::new(left), Box::new(right));
        }
    }

    fn mul_expr(&mut self) -> Result<Expr, String> {
        let mut left = self.unary()?;
        loop {
            let op = if self.eat(b'*') {
                BinOp::Mul
            } else if self.eat(b'/') {
                BinOp::Div
            } else {
                return Ok(left);
            };
            let right = self.unary()?;
            left = Expr::Bin(op, Box::new(left), Box::new(right));
        }
    }

    fn unary(&mut self) -> Result<Expr, String> {
        if self.eat(b'-') {
            Ok(Expr::Neg(Box::new(self.unary()?)))
        } else if self.eat(b'+') {
            self.unary()
        } else {
            self.primary()
        }
    }

    fn bracketed(&mut self) -> Result<Expr, String> {
        self.expect(b'[')?;
        let e = self.expr()?;
        self.expect(b']')?;
        Ok(e)
    }

    fn variable(&mut self) -> Result<Expr, String> {
        self.expect(b'#')?;
        if self.peek() == Some(b'[') {
            Ok(Expr::Var(Box::new(self.bracketed()?)))
        } else {
            match self.digits() {
                Some(n) => Ok(Expr::Var(Box::new(Expr::Num(f64::from(n))))),
                None => self.err("expected a variable number after '#'"),
            }
        }
    }

    fn primary(&mut self) -> Result<Expr, String> {
        match self.peek() {
            Some(b'0'..=b'9') | Some(b'.') => Ok(Expr::Num(self.number()?.0)),
            Some(b'#') => self.variable(),
            Some(b'[') => self.bracketed(),
            _ => {
                if self.eat_kw("ATAN") {
                    self.expect(b'[')?;
                    let y = self.expr()?;
                    let x = if self.eat(b',') {
                        let x = self.expr()?;
                        self.expect(b']')?;
                        x
                    } else {
                        self.expect(b']')?;
                        if !self.eat(b'/') {
                            return self.err("ATAN needs two arguments: ATAN[y]/[x] or ATAN[y,x]");
                        }
                        self.bracketed()?
                    };
                    return Ok(Expr::Atan(Box::new(y), Box::new(x)));
                }
                let funcs = [
                    ("SIN", Func::Sin),
                    ("COS", Func::Cos),
                    ("TAN", Func::Tan),
                    ("SQRT", Func::Sqrt),
                    ("ABS", Func::Abs),
                    ("ROUND", Func::Round),
                    ("FIX", Func::Fix),
                    ("FUP", Func::Fup),
                ];
                for (kw, f) in funcs {
                    if self.starts_with(kw) && self.s.get(self.i + kw.len()) == Some(&b'[') {
                        self.i += kw.len();
                        return Ok(Expr::Call(f, Box::new(self.bracketed()?)));
                    }
                }
                self.err("expected a number, a variable, '[' or a function of the subset")
            }
        }
    }

    /// The value of an address word: an optional sign, then a number, a
    /// variable or a bracketed expression. Returns the value and whether it
    /// is a plain number written without a decimal point.
    fn word_value(&mut self) -> Result<(Expr, bool), String> {
        let negative = if self.eat(b'-') {
            true
        } else {
            self.eat(b'+');
            false
        };
        let (e, bare) = match self.peek() {
            Some(b'0'..=b'9') | Some(b'.') => {
                let (v, point) = self.number()?;
                (Expr::Num(v), !point)
            }
            Some(b'#') => (self.variable()?, false),
            Some(b'[') => (self.bracketed()?, false),
            _ => return self.err("expected a number, '#' or '[' after the address"),
        };
        Ok((if negative { Expr::Neg(Box::new(e)) } else { e }, bare))
    }

    fn loop_id(&mut self) -> Result<u8, String> {
        match self.digits() {
            Some(n @ 1..=3) => Ok(n as u8),
            _ => self.err("a loop number must be 1, 2 or 3"),
        }
    }

    fn at_end_or_err(&self) -> Result<(), String> {
        if self.at_end() {
            Ok(())
        } else {
            self.err("unexpected text")
        }
    }

    fn assignment(&mut self) -> Result<(Expr, Expr), String> {
        let Expr::Var(index) = self.variable()? else {
            return self.err("expected a variable");
        };
        self.expect(b'=')?;
        let value = self.expr()?;
        self.at_end_or_err()?;
        Ok((*index, value))
    }

    fn statement(&mut self) -> Result<Stmt, String> {
        if self.eat_kw("WHILE") {
            let cond = self.bracketed()?;
            if !self.eat_kw("DO") {
                return self.err("WHILE needs DOm");
            }
            let id = self.loop_id()?;
            self.at_end_or_err()?;
            return Ok(Stmt::While { cond, id });
        }
        if self.eat_kw("IF") {
            let cond = self.bracketed()?;
            if self.eat_kw("GOTO") {
                let (target, _) = self.word_value()?;
                self.at_end_or_err()?;
                return Ok(Stmt::IfGoto { cond, target });
            }
            if self.eat_kw("THEN") {
                let (index, value) = self.assignment()?;
                return Ok(Stmt::IfThen { cond, index, value });
            }
            return self.err("IF needs GOTO or THEN");
        }
        if self.eat_kw("GOTO") {
            let (target, _) = self.word_value()?;
            self.at_end_or_err()?;
            return Ok(Stmt::Goto(target));
        }
        if self.starts_with("DO") && matches!(self.s.get(self.i + 2), Some(b'0'..=b'9')) {
            self.i += 2;
            let id = self.loop_id()?;
            self.at_end_or_err()?;
            return Ok(Stmt::Do(id));
        }
        if self.starts_with("END") && matches!(self.s.get(self.i + 3), Some(b'0'..=b'9')) {
            self.i += 3;
            let id = self.loop_id()?;
            self.at_end_or_err()?;
            return Ok(Stmt::End(id));
        }
        if self.peek() == Some(b'#') {
            let (index, value) = self.assignment()?;
            return Ok(Stmt::Assign { index, value });
        }
        let mut words = Vec::new();
        while let Some(c) = self.peek() {
            if !c.is_ascii_uppercase() {
                return self.err("expected an address letter");
            }
            if c == b'N' {
                return self.err("a sequence number must start the block");
            }
            self.i += 1;
            let (value, bare_integer) = self.word_value()?;
            words.push(Word {
                letter: c as char,
                value,
                bare_integer,
            });
        }
        Ok(Stmt::Nc(words))
    }
}

fn parse_block(raw: &str, line: usize) -> Result<Block, String> {
    let s = clean_line(raw, line)?;
    if s.is_empty() {
        return Ok(Block {
            line,
            label: None,
            stmt: Stmt::Blank,
        });
    }
    if s.contains('%') {
        if s == "%" {
            return Ok(Block {
                line,
                label: None,
                stmt: Stmt::Tape,
            });
        }
        return Err(format!("line {line}: '%' must stand alone"));
    }
    let mut c = Cursor::new(&s, line);
    if c.eat(b'O') {
        return match c.digits() {
            Some(n) if c.at_end() => Ok(Block {
                line,
                label: None,
                stmt: Stmt::ProgramNo(n),
            }),
            _ => c.err("an O line holds the program number only"),
        };
    }
    let label = if c.peek() == Some(b'N') {
        c.i += 1;
        match c.digits() {
            Some(n) => Some(n),
            None => return c.err("N needs a sequence number"),
        }
    } else {
        None
    };
    let stmt = c.statement()?;
    Ok(Block { line, label, stmt })
}

#[derive(Debug, Clone, PartialEq)]
struct Program {
    blocks: Vec<Block>,
    /// Index of the first block to run.
    start: usize,
    /// Program number → index of its O block.
    programs: HashMap<u32, usize>,
    /// For each block, the index of the O block of its program (or usize::MAX).
    owner: Vec<usize>,
    /// (owner, label) → block index.
    labels: HashMap<(usize, u32), usize>,
    /// WHILE/DO index → END index and END index → WHILE/DO index.
    loop_end: HashMap<usize, usize>,
    loop_start: HashMap<usize, usize>,
}

impl Program {
    fn parse(text: &str) -> Result<Program, String> {
        let mut blocks = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            blocks.push(parse_block(raw, i + 1)?);
        }
        let mut programs = HashMap::new();
        let mut owner = Vec::with_capacity(blocks.len());
        let mut current = usize::MAX;
        let mut first_program = None;
        for (i, b) in blocks.iter().enumerate() {
            match b.stmt {
                Stmt::ProgramNo(n) => {
                    if programs.insert(n, i).is_some() {
                        return Err(format!("line {}: program O{n:04} defined twice", b.line));
                    }
                    first_program.get_or_insert(i);
                    current = i;
                }
                Stmt::Tape => current = usize::MAX,
                _ => {}
            }
            owner.push(current);
        }
        // Without an O line the main program starts at the first block that
        // is not the opening '%'.
        let start = match first_program {
            Some(i) => i + 1,
            None => blocks
                .iter()
                .position(|b| !matches!(b.stmt, Stmt::Tape | Stmt::Blank))
                .unwrap_or(blocks.len()),
        };
        let mut labels = HashMap::new();
        for (i, b) in blocks.iter().enumerate() {
            if let Some(n) = b.label {
                if labels.insert((owner[i], n), i).is_some() {
                    return Err(format!("line {}: sequence number N{n} used twice", b.line));
                }
            }
        }
        // Loops are matched statically, per program.
        let mut loop_end = HashMap::new();
        let mut loop_start = HashMap::new();
        let mut stack: Vec<(u8, usize)> = Vec::new();
        let mut stack_owner = usize::MAX;
        for (i, b) in blocks.iter().enumerate() {
            if owner[i] != stack_owner {
                if let Some(&(id, j)) = stack.last() {
                    return Err(format!("line {}: DO{id} without END{id}", blocks[j].line));
                }
                stack_owner = owner[i];
            }
            match b.stmt {
                Stmt::While { id, .. } | Stmt::Do(id) => {
                    if stack.iter().any(|&(k, _)| k == id) {
                        return Err(format!("line {}: DO{id} inside a DO{id} loop", b.line));
                    }
                    if stack.len() == 3 {
                        return Err(format!(
                            "line {}: loops nested more than three deep",
                            b.line
                        ));
                    }
                    stack.push((id, i));
                }
                Stmt::End(id) => match stack.pop() {
                    Some((k, j)) if k == id => {
                        loop_end.insert(j, i);
                        loop_start.insert(i, j);
                    }
                    Some((k, _)) => {
                        return Err(format!(
                            "line {}: END{id} closes a DO{k} (crossed loops)",
                            b.line
                        ))
                    }
                    None => return Err(format!("line {}: END{id} without DO{id}", b.line)),
                },
                _ => {}
            }
        }
        if let Some(&(id, j)) = stack.last() {
            return Err(format!("line {}: DO{id} without END{id}", blocks[j].line));
        }
        Ok(Program {
            blocks,
            start,
            programs,
            owner,
            labels,
            loop_end,
            loop_start,
        })
    }
}

// ---------------------------------------------------------------------------
// Execution

#[derive(Debug, Clone, Copy, PartialEq)]
enum Val {
    Num(f64),
    Bool(bool),
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Motion {
    Rapid,
    Linear,
    Cw,
    Ccw,
}

#[derive(Debug, Clone, PartialEq)]
struct Frame {
    return_to: usize,
}

#[derive(Debug, Clone, PartialEq)]
struct Machine<'a> {
    program: &'a Program,
    increment: Option<f64>,
    pos: (f64, f64, f64),
    motion: Option<Motion>,
    absolute: bool,
    polar: bool,
    feed: Option<f64>,
    locals: Vec<[Option<f64>; 34]>,
    commons: HashMap<u32, f64>,
    calls: Vec<Frame>,
    moves: Vec<MillMove>,
}

/// Argument specification I: G65 letter → local variable.
fn argument_variable(letter: char) -> Option<usize> {
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

const ARC_RADIUS_TOLERANCE_MM: f64 = 0.001;

impl<'a> Machine<'a> {
    fn new(program: &'a Program, increment: Option<f64>) -> Machine<'a> {
        Machine {
            program,
            increment,
            pos: (0.0, 0.0, 0.0),
            motion: None,
            absolute: true,
            polar: false,
            feed: None,
            locals: vec![[None; 34]],
            commons: HashMap::new(),
            calls: Vec::new(),
            moves: Vec::new(),
        }
    }

    fn var_number(&self, index: &Expr, line: usize) -> Result<u32, String> {
        let v = self.num(index, line, None)?;
        let n = v.round();
        if (v - n).abs() > 1e-9 || n < 0.0 {
            return Err(format!(
                "line {line}: variable number {v} is not a whole number"
            ));
        }
        Ok(n as u32)
    }

    fn read_var(&self, n: u32, line: usize) -> Result<f64, String> {
        let value = match n {
            1..=33 => self.locals.last().and_then(|l| l[n as usize]),
            100..=199 | 500..=999 => self.commons.get(&n).copied(),
            0 => None,
            _ => return Err(format!("line {line}: variable #{n} is outside the subset")),
        };
        value.ok_or_else(|| format!("line {line}: #{n} is read while vacant (never set)"))
    }

    fn write_var(&mut self, n: u32, v: f64, line: usize) -> Result<(), String> {
        if !v.is_finite() {
            return Err(format!("line {line}: #{n} would be set to {v}"));
        }
        match n {
            1..=33 => {
                if let Some(l) = self.locals.last_mut() {
                    l[n as usize] = Some(v);
                }
            }
            100..=199 | 500..=999 => {
                self.commons.insert(n, v);
            }
            _ => return Err(format!("line {line}: variable #{n} cannot be set")),
        }
        Ok(())
    }

    /// Evaluates an expression; `address_increment` is Some inside an axis
    /// address, where ROUND rounds to that increment.
    fn eval(&self, e: &Expr, line: usize, address_increment: Option<f64>) -> Result<Val, String> {
        let num = |e: &Expr| self.num(e, line, address_increment);
        let v = match e {
            Expr::Num(v) => *v,
            Expr::Var(index) => self.read_var(self.var_number(index, line)?, line)?,
            Expr::Neg(a) => -num(a)?,
            Expr::Call(f, a) => {
                let x = num(a)?;
                match f {
                    Func::Sin => x.to_radians().sin(),
                    Func::Cos => x.to_radians().cos(),
                    Func::Tan => {
                        let c = x.to_radians().cos();
                        if c.abs() < 1e-12 {
                            return Err(format!("line {line}: TAN[{x}] is undefined"));
                        }
                        x.to_radians().sin() / c
                    }
                    Func::Sqrt => {
                        if x < 0.0 {
                            return Err(format!("line {line}: SQRT of a negative number {x}"));
                        }
                        x.sqrt()
                    }
                    Func::Abs => x.abs(),
                    Func::Round => match address_increment {
                        Some(q) => (x / q).round() * q,
                        None => x.round(),
                    },
                    Func::Fix => x.trunc(),
                    Func::Fup => {
                        if x >= 0.0 {
                            x.ceil()
                        } else {
                            x.floor()
                        }
                    }
                }
            }
            Expr::Atan(y, x) => {
                let (y, x) = (num(y)?, num(x)?);
                if y == 0.0 && x == 0.0 {
                    return Err(format!("line {line}: ATAN[0]/[0] is undefined"));
                }
                let a = y.atan2(x).to_degrees();
                if a < 0.0 {
                    a + 360.0
                } else {
                    a
                }
            }
            Expr::Bin(op, a, b) => match op {
                BinOp::And | BinOp::Or => {
                    let (p, q) = (self.boolean(a, line)?, self.boolean(b, line)?);
                    return Ok(Val::Bool(if *op == BinOp::And { p && q } else { p || q }));
                }
                BinOp::Eq | BinOp::Ne | BinOp::Gt | BinOp::Ge | BinOp::Lt | BinOp::Le => {
                    let (p, q) = (num(a)?, num(b)?);
                    return Ok(Val::Bool(match op {
                        BinOp::Eq => p == q,
                        BinOp::Ne => p != q,
                        BinOp::Gt => p > q,
                        BinOp::Ge => p >= q,
                        BinOp::Lt => p < q,
                        _ => p <= q,
                    }));
                }
                BinOp::Add => num(a)? + num(b)?,
                BinOp::Sub => num(a)? - num(b)?,
                BinOp::Mul => num(a)? * num(b)?,
                BinOp::Div => {
                    let d = num(b)?;
                    if d == 0.0 {
                        return Err(format!("line {line}: division by zero"));
                    }
                    num(a)? / d
                }
            },
        };
        if !v.is_finite() {
            return Err(format!("line {line}: the value is not finite"));
        }
        Ok(Val::Num(v))
    }

    fn num(&self, e: &Expr, line: usize, address_increment: Option<f64>) -> Result<f64, String> {
        match self.eval(e, line, address_increment)? {
            Val::Num(v) => Ok(v),
            Val::Bool(_) => Err(format!("line {line}: a condition is used as a number")),
        }
    }

    fn boolean(&self, e: &Expr, line: usize) -> Result<bool, String> {
        match self.eval(e, line, None)? {
            Val::Bool(b) => Ok(b),
            Val::Num(_) => Err(format!(
                "line {line}: a number is used as a condition (use EQ NE GT GE LT LE)"
            )),
        }
    }

    fn integer(&self, w: &Word, line: usize) -> Result<u32, String> {
        let v = self.num(&w.value, line, None)?;
        let n = v.round();
        if (v - n).abs() > 1e-9 || !(0.0..=99_999_999.0).contains(&n) {
            return Err(format!("line {line}: {}{v} needs a whole number", w.letter));
        }
        Ok(n as u32)
    }

    fn goto(&self, pc: usize, target: &Expr, line: usize) -> Result<usize, String> {
        let v = self.num(target, line, None)?;
        let n = v.round();
        if (v - n).abs() > 1e-9 || !(1.0..=99_999.0).contains(&n) {
            return Err(format!("line {line}: GOTO {v} is not a sequence number"));
        }
        let owner = self.program.owner[pc];
        let Some(&to) = self.program.labels.get(&(owner, n as u32)) else {
            return Err(format!("line {line}: GOTO {n}: no N{n} in this program"));
        };
        for (&s, &e) in &self.program.loop_end {
            let inside = |i: usize| s < i && i <= e;
            if inside(to) && !inside(pc) {
                return Err(format!("line {line}: GOTO {n} jumps into a loop"));
            }
        }
        Ok(to)
    }

    fn run(&mut self, budget: usize) -> Result<MillRun, String> {
        let blocks = &self.program.blocks;
        let mut pc = self.program.start;
        let mut executed = 0usize;
        loop {
            let Some(block) = blocks.get(pc) else {
                return Err(format!(
                    "line {}: the text ends without M30 or M02",
                    blocks.len()
                ));
            };
            let line = block.line;
            if matches!(block.stmt, Stmt::Blank) {
                pc += 1;
                continue;
            }
            executed += 1;
            if executed > budget {
                return Err(format!(
                    "line {line}: the budget of {budget} executed blocks is used up"
                ));
            }
            pc = match &block.stmt {
                Stmt::Blank => pc + 1,
                Stmt::Tape => return Err(format!("line {line}: '%' reached without M30 or M02")),
                Stmt::ProgramNo(n) => {
                    return Err(format!(
                        "line {line}: ran into program O{n:04} without M30, M02 or M99"
                    ))
                }
                Stmt::Assign { index, value } => {
                    let n = self.var_number(index, line)?;
                    let v = self.num(value, line, None)?;
                    self.write_var(n, v, line)?;
                    pc + 1
                }
                Stmt::IfThen { cond, index, value } => {
                    if self.boolean(cond, line)? {
                        let n = self.var_number(index, line)?;
                        let v = self.num(value, line, None)?;
                        self.write_var(n, v, line)?;
                    }
                    pc + 1
                }
                Stmt::While { cond, .. } => {
                    if self.boolean(cond, line)? {
                        pc + 1
                    } else {
                        match self.program.loop_end.get(&pc) {
                            Some(&e) => e + 1,
                            None => return Err(format!("line {line}: loop without END")),
                        }
                    }
                }
                Stmt::Do(_) => pc + 1,
                Stmt::End(_) => match self.program.loop_start.get(&pc) {
                    Some(&s) => s,
                    None => return Err(format!("line {line}: END without DO")),
                },
                Stmt::IfGoto { cond, target } => {
                    if self.boolean(cond, line)? {
                        self.goto(pc, target, line)?
                    } else {
                        pc + 1
                    }
                }
                Stmt::Goto(target) => self.goto(pc, target, line)?,
                Stmt::Nc(words) => match self.nc_block(words, pc, line)? {
                    Flow::Next => pc + 1,
                    Flow::Jump(to) => to,
                    Flow::Stop(code) => {
                        return Ok(MillRun {
                            moves: std::mem::take(&mut self.moves),
                            ended_by: code.to_string(),
                        })
                    }
                },
            };
        }
    }

    fn call(&mut self, words: &[Word], pc: usize, line: usize) -> Result<Flow, String> {
        let mut target = None;
        let mut args: [Option<f64>; 34] = [None; 34];
        for (k, w) in words.iter().enumerate() {
            match w.letter {
                'G' if k == 0 => {}
                'G' => {
                    return Err(format!(
                        "line {line}: G65 must be the only G code of its block"
                    ))
                }
                'P' => target = Some(self.integer(w, line)?),
                'L' => {
                    return Err(format!(
                        "line {line}: G65 with a repeat count L is outside the subset"
                    ))
                }
                letter => {
                    let Some(n) = argument_variable(letter) else {
                        return Err(format!(
                            "line {line}: {letter} is not a G65 argument letter"
                        ));
                    };
                    if args[n].is_some() {
                        return Err(format!(
                            "line {line}: argument {letter} given twice (argument specification II is outside the subset)"
                        ));
                    }
                    if w.bare_integer {
                        return Err(format!(
                            "line {line}: argument {letter} without a decimal point (its unit depends on the control)"
                        ));
                    }
                    args[n] = Some(self.num(&w.value, line, None)?);
                }
            }
        }
        let Some(p) = target else {
            return Err(format!("line {line}: G65 without P"));
        };
        let Some(&o) = self.program.programs.get(&p) else {
            return Err(format!(
                "line {line}: G65 P{p}: no program O{p:04} in the text"
            ));
        };
        if self.calls.len() >= 4 {
            return Err(format!(
                "line {line}: macro calls nested more than four deep"
            ));
        }
        self.calls.push(Frame { return_to: pc + 1 });
        self.locals.push(args);
        Ok(Flow::Jump(o + 1))
    }

    fn nc_block(&mut self, words: &[Word], pc: usize, line: usize) -> Result<Flow, String> {
        if let Some(first) = words.first() {
            if first.letter == 'G' && self.integer(first, line)? == 65 {
                return self.call(words, pc, line);
            }
        }
        let mut motion = self.motion;
        let mut dwell = false;
        let mut axes: [Option<f64>; 5] = [None; 5]; // X Y Z I J
        let mut feed = None;
        let mut ms = Vec::new();
        let mut p_word = false;
        for w in words {
            match w.letter {
                'G' => match self.integer(w, line)? {
                    0 => motion = Some(Motion::Rapid),
                    1 => motion = Some(Motion::Linear),
                    2 => motion = Some(Motion::Cw),
                    3 => motion = Some(Motion::Ccw),
                    4 => dwell = true,
                    15 => self.polar = false,
                    16 => self.polar = true,
                    90 => self.absolute = true,
                    91 => self.absolute = false,
                    17 | 21 | 40 | 49 | 54 | 80 | 94 => {}
                    65 => return Err(format!("line {line}: G65 must start its block")),
                    g => return Err(format!("line {line}: G{g:02} is outside the subset")),
                },
                'M' => {
                    let m = self.integer(w, line)?;
                    match m {
                        2 | 3 | 4 | 5 | 8 | 9 | 30 | 99 => ms.push(m),
                        _ => return Err(format!("line {line}: M{m:02} is outside the subset")),
                    }
                }
                'F' => {
                    let f = self.num(&w.value, line, None)?;
                    if f <= 0.0 {
                        return Err(format!("line {line}: feed F{f} is not positive"));
                    }
                    feed = Some(f);
                }
                'S' => {
                    let s = self.num(&w.value, line, None)?;
                    if s < 0.0 {
                        return Err(format!("line {line}: negative spindle speed S{s}"));
                    }
                }
                'P' => {
                    self.num(&w.value, line, None)?;
                    p_word = true;
                }
                'X' | 'Y' | 'Z' | 'I' | 'J' => {
                    let k = match w.letter {
                        'X' => 0,
                        'Y' => 1,
                        'Z' => 2,
                        'I' => 3,
                        _ => 4,
                    };
                    if w.bare_integer {
                        return Err(format!(
                            "line {line}: {} without a decimal point (read as increments by a control)",
                            w.letter
                        ));
                    }
                    if axes[k].is_some() {
                        return Err(format!("line {line}: {} given twice", w.letter));
                    }
                    let q = self.increment.unwrap_or(0.001);
                    let mut v = self.num(&w.value, line, Some(q))?;
                    if let Some(q) = self.increment {
                        v = (v / q).round() * q;
                    }
                    axes[k] = Some(v);
                }
                other => {
                    return Err(format!(
                        "line {line}: address {other} is outside the subset"
                    ))
                }
            }
        }
        if let Some(f) = feed {
            self.feed = Some(f);
        }
        if dwell {
            if axes[1..].iter().any(Option::is_some) {
                return Err(format!("line {line}: G04 takes only X or P"));
            }
        } else {
            if p_word {
                return Err(format!("line {line}: P outside G04/G65"));
            }
            self.motion = motion;
            if axes.iter().any(Option::is_some) {
                self.make_move(axes, line)?;
            }
        }
        for m in ms {
            match m {
                30 => return Ok(Flow::Stop("M30")),
                2 => return Ok(Flow::Stop("M02")),
                99 => {
                    let Some(frame) = self.calls.pop() else {
                        return Err(format!("line {line}: M99 in the main program"));
                    };
                    self.locals.pop();
                    return Ok(Flow::Jump(frame.return_to));
                }
                _ => {}
            }
        }
        Ok(Flow::Next)
    }

    fn make_move(&mut self, axes: [Option<f64>; 5], line: usize) -> Result<(), String> {
        let Some(motion) = self.motion else {
            return Err(format!(
                "line {line}: an axis word with no motion code (G00-G03) in force"
            ));
        };
        let [x, y, z, i, j] = axes;
        let (px, py, pz) = self.pos;
        let arc = matches!(motion, Motion::Cw | Motion::Ccw);
        if !arc && (i.is_some() || j.is_some()) {
            return Err(format!("line {line}: I or J without G02/G03"));
        }
        let to = if self.polar {
            if !self.absolute {
                return Err(format!("line {line}: G91 under G16 is outside the subset"));
            }
            if arc {
                return Err(format!(
                    "line {line}: G02/G03 under G16 is outside the subset"
                ));
            }
            let (tx, ty) = if x.is_none() && y.is_none() {
                (px, py)
            } else {
                let r = match x {
                    Some(r) => r,
                    None => px.hypot(py),
                };
                let a = match y {
                    Some(a) => a,
                    None => {
                        if px.hypot(py) < 1e-12 {
                            return Err(format!(
                                "line {line}: G16 radius without an angle at the origin (no angle to keep)"
                            ));
                        }
                        py.atan2(px).to_degrees()
                    }
                };
                let (s, c) = a.to_radians().sin_cos();
                (r * c, r * s)
            };
            (tx, ty, z.unwrap_or(pz))
        } else if self.absolute {
            (x.unwrap_or(px), y.unwrap_or(py), z.unwrap_or(pz))
        } else {
            (
                px + x.unwrap_or(0.0),
                py + y.unwrap_or(0.0),
                pz + z.unwrap_or(0.0),
            )
        };
        let rapid = motion == Motion::Rapid;
        let feed = if rapid {
            None
        } else {
            match self.feed {
                Some(f) => Some(f),
                None => return Err(format!("line {line}: a feed move with no F in force")),
            }
        };
        let arc = if arc {
            let (ci, cj) = (i.unwrap_or(0.0), j.unwrap_or(0.0));
            let r0 = ci.hypot(cj);
            if r0 < 1e-9 {
                return Err(format!(
                    "line {line}: an arc needs I or J (R arcs are outside the subset)"
                ));
            }
            let centre = (px + ci, py + cj);
            let r1 = (to.0 - centre.0).hypot(to.1 - centre.1);
            if (r1 - r0).abs() > ARC_RADIUS_TOLERANCE_MM {
                return Err(format!(
                    "line {line}: arc radii differ: {r0:.6} at the start, {r1:.6} at the end"
                ));
            }
            Some((centre, motion == Motion::Ccw))
        } else {
            None
        };
        self.moves.push(MillMove {
            line,
            from: self.pos,
            to,
            rapid,
            arc,
            feed,
        });
        self.pos = to;
        Ok(())
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Flow {
    Next,
    Jump(usize),
    Stop(&'static str),
}

#[cfg(test)]
mod tests {
    use super::*;

    const ANNULUS: &str = include_str!("../golden/face_annulus_fanuc.nc");
    const ARCS: &str = include_str!("../golden/face_circle_arcs_fanuc.nc");
    const CHORDS: &str = include_str!("../golden/face_chords_fanuc.nc");
    const GROOVE: &str = include_str!("../golden/groove_fanuc.nc");
    const BUDGET: usize = 100_000;

    fn close(a: (f64, f64, f64), b: (f64, f64, f64), tol: f64) -> bool {
        (a.0 - b.0).abs() <= tol && (a.1 - b.1).abs() <= tol && (a.2 - b.2).abs() <= tol
    }

    fn assert_move(m: &MillMove, line: usize, to: (f64, f64, f64), rapid: bool, feed: Option<f64>) {
        assert_eq!(m.line, line, "{m:?}");
        assert!(close(m.to, to, 1e-9), "expected {to:?}, got {m:?}");
        assert_eq!(m.rapid, rapid, "{m:?}");
        assert_eq!(m.feed, feed, "{m:?}");
    }

    #[test]
    fn a_tiny_polar_macro_gives_exactly_these_moves() {
        let text = "%
O0001 (TINY)
#1=10.0
#2=0
G21 G90 G17
G00 Z5.0
G16
G00 X#1 Y90.0
G01 Z-1.0 F100.0
WHILE [#2 LT 3] DO1
#2=#2+1
G01 X[#1+#2] Y[90+#2*90] F200.0
END1
G01 Y90.0
G01 X6.0
G15
G00 Z5.0
M30
%
";
        let run = run_fanuc(text, 1000).expect("runs");
        assert_eq!(run.ended_by, "M30");
        let m = &run.moves;
        assert_eq!(m.len(), 9);
        assert_eq!(m[0].from, (0.0, 0.0, 0.0));
        assert_move(&m[0], 6, (0.0, 0.0, 5.0), true, None);
        assert_move(&m[1], 8, (0.0, 10.0, 5.0), true, None);
        assert_move(&m[2], 9, (0.0, 10.0, -1.0), false, Some(100.0));
        // The plunge leaves X Y exactly where they were.
        assert_eq!((m[2].to.0, m[2].to.1), (m[1].to.0, m[1].to.1));
        assert_move(&m[3], 12, (-11.0, 0.0, -1.0), false, Some(200.0));
        assert_move(&m[4], 12, (0.0, -12.0, -1.0), false, Some(200.0));
        assert_move(&m[5], 12, (13.0, 0.0, -1.0), false, Some(200.0));
        // Y only: the radius 13 is kept; X only: the angle 90 is kept.
        assert_move(&m[6], 14, (0.0, 13.0, -1.0), false, Some(200.0));
        assert_move(&m[7], 15, (0.0, 6.0, -1.0), false, Some(200.0));
        assert!(m.iter().all(|mv| mv.arc.is_none()));
        for w in m.windows(2) {
            assert_eq!(w[0].to, w[1].from);
        }
        assert_move(&m[8], 17, (0.0, 6.0, 5.0), true, None);
    }

    #[test]
    fn expressions_functions_and_branches() {
        let text = "O0002
#1=ROUND[2.5]+ROUND[-2.5]*10
#2=FIX[-1.2]*10+FUP[-1.2]
#3=FIX[1.7]+FUP[1.2]*10
#4=ATAN[-1]/[-1]
#5=ATAN[1,0]
#6=SQRT[16]+ABS[-3]+SIN[30]+COS[60]+TAN[45]
#7=2+3*4-[2+3]*4/2
#8=0
N10 #8=#8+1
IF [#8 LT 5] GOTO 10
IF [#8 EQ 5 AND #7 NE 0] THEN #9=1.0
IF [#8 GT 5 OR #7 EQ 0] THEN #9=2.0
#10=0
#11=0
WHILE [#10 LT 3] DO1
#10=#10+1
#12=0
WHILE [#12 LT 2] DO2
#12=#12+1
#11=#11+1
END2
END1
#[20+1]=#11*2
GOTO 20
#1=99
N20 G90 G01 X#1 Y#2 Z#3 F100.0
G01 X#4 Y#5 Z#6
G01 X#7 Y#8 Z#9
G01 X#21 Y[ROUND[1.23456]] Z-#21
M02
";
        let run = run_fanuc(text, 1000).expect("runs");
        assert_eq!(run.ended_by, "M02");
        let t: Vec<_> = run.moves.iter().map(|m| m.to).collect();
        assert!(close(t[0], (-27.0, -12.0, 21.0), 1e-12), "{t:?}");
        assert!(close(t[1], (225.0, 90.0, 9.0), 1e-9), "{t:?}");
        assert!(close(t[2], (4.0, 5.0, 1.0), 1e-12), "{t:?}");
        // ROUND inside an axis address rounds to 0.001 mm.
        assert!(close(t[3], (12.0, 1.235, -12.0), 1e-12), "{t:?}");
    }

    #[test]
    fn arcs_carry_their_centre_and_sense() {
        let text = "G90 G00 X10.0 Y0.0 Z0.0
G03 X0.0 Y10.0 I-10.0 J0.0 F50.0
G02 X10.0 Y0.0 J-10.0
G02 I-10.0
M30
";
        let run = run_fanuc(text, 100).expect("runs");
        let m = &run.moves;
        assert_eq!(m.len(), 4);
        assert_eq!(m[1].arc, Some(((0.0, 0.0), true)));
        assert_eq!(m[1].feed, Some(50.0));
        assert_eq!(m[2].arc, Some(((0.0, 0.0), false)));
        // A full circle: end = start.
        assert_eq!(m[3].from, m[3].to);
        assert_eq!(m[3].arc, Some(((0.0, 0.0), false)));
        let bad = "G90 G00 X10.0 Y0.0\nG02 X0.0 Y10.0 I-10.0 J0.1 F50.0\nM30\n";
        assert!(run_fanuc(bad, 100).unwrap_err().starts_with("line 2:"));
    }

    #[test]
    fn refusals_name_the_line() {
        let cases = [
            ("G00 X1.0\nG00 X10\nM30\n", "line 2:"),
            ("#1=1.0\nG00 X#2\nM30\n", "line 2:"),
            ("G01 X1.0\nM30\n", "line 1:"),
            ("G00 X1.0\nG18\nM30\n", "line 2:"),
            ("G00 X1.0\nG00 K1.0\nM30\n", "line 2:"),
            ("G00 X1.0\nG00 X1.0\n", "line 2:"),
            ("G00 X1.0\nG16\nG91 G00 X1.0 Y2.0\nM30\n", "line 3:"),
            ("G00 X1.0\nG01 X[#1\nM30\n", "line 2:"),
            ("G00 X1.0\nWHILE [1 LT 2] DO1\nEND2\nM30\n", "line 3:"),
            ("G00 X1.0\nG65 P9000 A1.0\nM30\n", "line 2:"),
            ("G00 X1.0\nM99\n", "line 2:"),
            ("G00 X1.0\nG00 X[SQRT[-1]]\nM30\n", "line 2:"),
            ("G00 X1.0\nG00 x1.0\nM30\n", "line 2:"),
            ("G00 Z1.0\nG16\nG00 X1.0\nM30\n", "line 3:"),
            ("G00 X1.0\n#1=1.0\nG00 X[#1 GT 0]\nM30\n", "line 3:"),
        ];
        for (text, prefix) in cases {
            let e = run_fanuc(text, 100).expect_err(text);
            assert!(e.starts_with(prefix), "{text:?}: {e}");
        }
        let forever = "N1 G00 X1.0\nGOTO 1\n";
        assert!(run_fanuc(forever, 50).unwrap_err().contains("budget"));
    }

    /// The body of the macro as "The FANUC macro" describes it, written here
    /// by hand: the variable table's numbers, G16, WHILE [#30 LE #8] DO1 per
    /// pass, WHILE [#32 LT #5] DO2 over the chords at angle #4·k/#5.
    const BODY: &str = "G21 G90 G17 G94 G40 G49 G80
S#11 M03
G00 Z#17
#30=1
WHILE [#30 LE #8] DO1
#31=0-#7*#30/#8
G16
G00 X#1 Y#3
G01 Z#31 F#13
F#9
#32=0
WHILE [#32 LT #5] DO2
#32=#32+1
#33=#4*#32/#5
G01 X[#1+[#2-#1]*#33/#4] Y[#3+#6*#33]
END2
G15
G00 Z#17
#30=#30+1
END1
M05
";

    fn standalone(args: &[(usize, f64)], body: &str) -> String {
        let mut s = String::from("%\nO1234 (STANDALONE)\n");
        for (n, v) in args {
            s.push_str(&format!("#{n}={v:?}\n"));
        }
        s.push_str(body);
        s.push_str("M30\n%\n");
        s
    }

    fn called(g65: &str, body: &str) -> String {
        format!("%\nO1235 (MAIN)\n{g65}\nM30\nO7001 (FAMILY)\n{body}M99\n%\n")
    }

    fn strip_lines(run: &MillRun) -> Vec<MillMove> {
        run.moves
            .iter()
            .map(|m| MillMove {
                line: 0,
                ..m.clone()
            })
            .collect()
    }

    #[test]
    fn the_g65_form_moves_as_the_standalone_form() {
        for sense in [1.0, -1.0] {
            let args = [
                (1, 20.0),
                (2, 10.0),
                (3, 30.0),
                (4, 720.0),
                (5, 8.0),
                (6, sense),
                (7, 1.0),
                (8, 2.0),
                (9, 400.0),
                (11, 1000.0),
                (13, 100.0),
                (17, 5.0),
            ];
            let own = run_fanuc(&standalone(&args, BODY), BUDGET).expect("standalone");
            let g65 = format!(
                "G65 P7001 A20.0 B10.0 C30.0 I720.0 J8.0 K{sense:?} D1.0 E2.0 F400.0 H1000.0 M100.0 Q5.0"
            );
            let call = run_fanuc(&called(&g65, BODY), BUDGET).expect("called");
            assert_eq!(call.ended_by, "M30");
            assert_eq!(strip_lines(&own), strip_lines(&call));
            // 1 + 2 passes × (approach, plunge, 8 chords, retract).
            assert_eq!(own.moves.len(), 1 + 2 * 11);
            // Chord k of a pass: radius 20 − 10·k/8, angle 30 + sense·90·k.
            for (k, m) in own.moves[3..11].iter().enumerate() {
                let k = (k + 1) as f64;
                let (r, a) = (
                    20.0 - 10.0 * k / 8.0,
                    (30.0 + sense * 90.0 * k).to_radians(),
                );
                assert!(close(m.to, (r * a.cos(), r * a.sin(), -0.5), 1e-9), "{m:?}");
                assert_eq!(m.feed, Some(400.0));
            }
            assert_move(
                &own.moves[13],
                23,
                (20.0 * 30f64.to_radians().cos(), 10.0, -1.0),
                false,
                Some(100.0),
            );
        }
    }

    #[test]
    fn the_documented_g65_line_runs_the_golden_body_as_the_golden_program() {
        // The G65 line of "The family program", letter for letter.
        let g65 =
            "G65 P7001 A133.5 B13.0 C0.0 I1440.0 J1452.0 K-1.0 D1.0 E1.0 F472.4 H859.0 M118.1 Q5.0";
        let lines: Vec<&str> = ANNULUS.lines().collect();
        let from = lines
            .iter()
            .position(|l| l.starts_with("G21"))
            .expect("G21");
        let to = lines.iter().position(|l| *l == "M05").expect("M05");
        let body: String = lines[from..=to].iter().map(|l| format!("{l}\n")).collect();
        let call = run_fanuc(&called(g65, &body), BUDGET).expect("called");
        let own = run_fanuc(ANNULUS, BUDGET).expect("golden");
        assert_eq!(strip_lines(&own), strip_lines(&call));
        // And the hand-written body reads the same as the golden one.
        let args = [
            (1, 133.5),
            (2, 13.0),
            (3, 0.0),
            (4, 1440.0),
            (5, 1452.0),
            (6, -1.0),
            (7, 1.0),
            (8, 1.0),
            (9, 472.4),
            (11, 859.0),
            (13, 118.1),
            (17, 5.0),
        ];
        let mine = run_fanuc(&standalone(&args, BODY), BUDGET).expect("hand");
        assert_eq!(strip_lines(&own), strip_lines(&mine));
    }

    #[derive(Debug, Clone, PartialEq)]
    struct Facts {
        moves: usize,
        /// Rapids that end at or below the face (Z <= 0).
        rapids_low: usize,
        /// Rapids straight up out of the cut (they start below the face).
        rapid_retracts: usize,
        lowest_z: f64,
        plunges: Vec<(usize, f64, f64, f64)>, // line, radius of XY, from z, to z
    }

    fn facts(run: &MillRun) -> Facts {
        let mut plunges = Vec::new();
        for m in &run.moves {
            if m.to.2 < m.from.2 && !m.rapid {
                plunges.push((m.line, m.to.0.hypot(m.to.1), m.from.2, m.to.2));
            }
        }
        Facts {
            moves: run.moves.len(),
            rapids_low: run
                .moves
                .iter()
                .filter(|m| m.rapid && m.to.2 <= 0.0)
                .count(),
            rapid_retracts: run
                .moves
                .iter()
                .filter(|m| {
                    m.rapid
                        && m.from.2 < 0.0
                        && m.to.2 > m.from.2
                        && m.to.0 == m.from.0
                        && m.to.1 == m.from.1
                })
                .count(),
            lowest_z: run
                .moves
                .iter()
                .map(|m| m.to.2)
                .fold(f64::INFINITY, f64::min),
            plunges,
        }
    }

    /// Every golden FANUC program: ends with M30, its last move a rapid up to
    /// the safe height 5, no rapid at or below the face, moves continuous.
    fn check_golden(text: &str, first_line: usize) -> (MillRun, Facts) {
        let run = run_fanuc(text, BUDGET).expect("golden runs");
        assert_eq!(run.ended_by, "M30");
        let last = run.moves.last().expect("moves");
        assert!(
            last.rapid && last.to.2 > 0.0 && last.from.2 < last.to.2,
            "{last:?}"
        );
        assert!((last.to.2 - 5.0).abs() < 1e-12);
        assert_eq!(run.moves[0].from, (0.0, 0.0, 0.0));
        assert_move(&run.moves[0], first_line, (0.0, 0.0, 5.0), true, None);
        for w in run.moves.windows(2) {
            assert_eq!(w[0].to, w[1].from);
        }
        let f = facts(&run);
        assert_eq!(f.rapids_low, 0);
        // Every rapid that starts below the face goes straight up.
        let from_below = run
            .moves
            .iter()
            .filter(|m| m.rapid && m.from.2 < 0.0)
            .count();
        assert_eq!(from_below, f.rapid_retracts);
        (run, f)
    }

    #[test]
    fn golden_annulus_macro() {
        let (run, f) = check_golden(ANNULUS, 29);
        // 1 + 1 pass × (approach, plunge, 1452 chords, retract).
        assert_eq!(f.moves, 1456);
        assert_eq!(f.lowest_z, -1.0);
        assert_eq!(f.plunges, vec![(35, 133.5, 5.0, -1.0)]);
        assert!(close(run.moves[1].to, (133.5, 0.0, 5.0), 1e-12));
        // The spiral ends at R2 = 13 after four whole turns.
        assert!(close(run.moves[1454].to, (13.0, 0.0, -1.0), 1e-9));
        assert_eq!(run.moves[2].feed, Some(118.1));
        assert_eq!(run.moves[3].feed, Some(472.4));
        // First chord: radius 133.5 − 120.5/1452, angle −360·4/1452 (clockwise).
        let (r, a) = (133.5 - 120.5 / 1452.0, (-1440.0f64 / 1452.0).to_radians());
        assert!(close(
            run.moves[3].to,
            (r * a.cos(), r * a.sin(), -1.0),
            1e-9
        ));
    }

    #[test]
    fn golden_groove_macro() {
        let (run, f) = check_golden(GROOVE, 29);
        // 1 + 4 passes × (approach, plunge, 731 chords, retract).
        assert_eq!(f.moves, 2937);
        assert_eq!(f.lowest_z, -4.0);
        let depths: Vec<f64> = f.plunges.iter().map(|p| p.3).collect();
        assert_eq!(depths, vec![-1.0, -2.0, -3.0, -4.0]);
        assert!(f.plunges.iter().all(|p| p.1 == 60.0 && p.2 == 5.0));
        for pass in 0..4 {
            let end = &run.moves[1 + pass * 734 + 732];
            assert!(
                close(end.to, (12.0, 0.0, -1.0 - pass as f64), 1e-9),
                "{end:?}"
            );
        }
    }

    #[test]
    fn golden_circle_arcs() {
        let (run, f) = check_golden(ARCS, 17);
        // 1 + 2 passes × (approach, plunge, 128 arcs, retract).
        assert_eq!(f.moves, 263);
        assert_eq!(f.lowest_z, -2.5);
        assert_eq!(
            f.plunges,
            vec![(19, 123.5, 5.0, -1.25), (150, 123.5, 5.0, -2.5)]
        );
        let arcs: Vec<&MillMove> = run.moves.iter().filter(|m| m.arc.is_some()).collect();
        assert_eq!(arcs.len(), 256);
        assert!(arcs.iter().all(|m| m.arc.is_some_and(|(_, ccw)| !ccw)));
        assert!(arcs.iter().all(|m| m.feed == Some(672.0)));
        let first = arcs[0].arc.expect("arc").0;
        assert!((first.0 - 0.5255).abs() < 1e-9 && (first.1 - 4.8930).abs() < 1e-9);
        // Each pass ends at the centre of the face.
        assert!(close(run.moves[130].to, (0.0, 0.0, -1.25), 1e-12));
        assert!(close(run.moves[261].to, (0.0, 0.0, -2.5), 1e-12));
    }

    #[test]
    fn golden_chords() {
        let (run, f) = check_golden(CHORDS, 17);
        // 1 + approach, plunge, 1578 chords, retract.
        assert_eq!(f.moves, 1582);
        assert_eq!(f.lowest_z, -0.8);
        // Inside-out, the plunge is in the hole: the Ø16 tool's disc spans
        // radii 8.5 to 24.5, clear of the face's inner edge at 25.
        assert_eq!(f.plunges, vec![(19, 16.5, 5.0, -0.8)]);
        assert!(close(run.moves[1580].to, (70.0, 0.0, -0.8), 1e-12));
        assert_eq!(run.moves[3].feed, Some(1488.1));
    }

    #[test]
    fn quantised_macro_moves_stay_near_the_exact_ones() {
        let exact = run_fanuc(ANNULUS, BUDGET).expect("exact");
        let isb = run_fanuc_quantised(ANNULUS, BUDGET, Some(0.001)).expect("IS-B");
        assert_eq!(exact.moves.len(), isb.moves.len());
        let worst = exact
            .moves
            .iter()
            .zip(&isb.moves)
            .map(|(a, b)| (a.to.0 - b.to.0).hypot(a.to.1 - b.to.1))
            .fold(0.0, f64::max);
        // Half a micrometre of radius and half a millidegree at 133.5 mm.
        assert!(
            worst > 0.0 && worst < 0.0005 + 133.5 * 0.0005f64.to_radians() + 1e-9,
            "{worst}"
        );
    }
}
