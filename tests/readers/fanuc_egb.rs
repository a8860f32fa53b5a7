//! A second, independent reader of gearcam's FANUC hobbing programs (M-series control with the
//! electronic gear box, EGB), written from the documentation only (clean room):
//! `docs/programs.md` ("The hobbing program", "Dialect rules" → "FANUC with the electronic gear
//! box", "Path check", "Program names and files"), `docs/hobbing.md` (§4 the cycle, §6 the
//! machine profile) and `crates/nc/DIALECTS.md` ("FANUC (`fanuc`) …", "Parameters", "Branches").
//!
//! [`run_fanuc_egb`] runs a program from its first block to its end code the way the control
//! would and returns every motion block with the axis positions after it. Anything outside the
//! documented subset is refused with an `Err` naming the 1-based line.
//!
//! Format rules implemented (source in brackets):
//!
//! - Framing: `%` alone on the first and on the last line; the second line `O` and four digits,
//!   0001–7999, optionally followed by a title comment [programs.md, Dialect rules; Program names
//!   and files]. Nothing but comment lines may stand between the end code (`M30`/`M02`) and the
//!   closing `%`; a program without an end code is refused [programs.md, Path check, `END_AT_A`].
//! - Comments in parentheses, printable upper-case ASCII, no parentheses inside; a comment is a
//!   whole line or ends a block [programs.md, Dialect rules]. `%` inside a comment is refused too
//!   (reader's choice: `%` is the control's end-of-record code).
//! - Blocks: optional `N` number, then address words without `=` (letter, value); a value is a
//!   number or, for an axis word, a bracketed macro expression `Y[#520+#522*#527]`
//!   [DIALECTS.md, FANUC example].
//! - Numbers: lengths, feeds and dwells with a decimal point and at most 3 decimals, angles (A, C,
//!   `P`) at most 4; counts (`T`, `L`, `S`, `M`, `G`, `N`) without a point [programs.md, Dialect
//!   rules: "always with a decimal point except counts"]. An axis word without a point would be
//!   read in least input increments by a FANUC control (X450 = 0.45 mm), so it is refused.
//! - Set-up: `G21` (metric), `G90`/`G91`, `G94` (feed per minute) and a work offset `G54`–`G59`
//!   before the first move [programs.md, Dialect rules; DIALECTS.md]. `G20`, `G95`, `G98`, `G99`
//!   (other units, feed per revolution, G-code system A or canned-cycle return levels) are
//!   refused [programs.md, "One program is written in one G-code system"].
//! - Motion: `G00` rapid, `G01` feed, `G02`/`G03` arcs with `R` in the X–Z plane, `G04 X` dwell in
//!   seconds; `G00`–`G03` and `G90`/`G91` are modal, `F` is modal; a feed move needs a positive
//!   `F` in force (the control alarms otherwise). `G18` may be written (the X–Z plane); `G17` and
//!   `G19` are refused.
//! - Axes: H02's letters [DIALECTS.md, "the examples use … H02's (FANUC) values"]: `X` centre
//!   distance (radius), `Z` hob height, `Y` hob shift, `A` swivel, `C` table. `X Y Z` are lengths,
//!   `A C` angles. A position is kept on the control's input grid (0.001 mm, 0.0001°).
//! - Gearbox: `G81 T{z} L{±z0} [Q{mn} P{±β}]` couples, `G80` cancels; T 1–1000, 1 ≤ |L| ≤ 21,
//!   Q 0.1–25 mm and |P| ≤ 90° given together or not at all; a second `G81` while coupled and a
//!   `G80` while uncoupled are refused [programs.md, Dialect rules: "The EGB stays on from G81
//!   to G80"]. `G81.4`/`G80.4` are not written [programs.md, Open points] and are refused.
//! - Shift while coupled: the only form is `G01 G91 Y.. C..` (both words, nothing else moving);
//!   `C` never moves otherwise [programs.md: "while coupled, the shift axis moves only
//!   incrementally together with its table correction"; DIALECTS.md: "(coupled only)"].
//! - Macro variables: `#500`–`#999` (the retained common variables) may be read and assigned;
//!   expressions with `+ - * /`, unary minus, `FIX[ ]` and `[ ]`; `IF [a OP b] THEN #n=…` with
//!   `EQ NE LT LE GT GE` between spaces; `IF … GOTO`, `WHILE`, `GOTO` are refused
//!   [programs.md, Dialect rules; DIALECTS.md, Branches].
//! - Vacant variables behave as on a FANUC control: a variable neither assigned nor given in
//!   `vars_init` is vacant; arithmetic and `GE GT LE LT` read it as 0 (so a fresh control runs
//!   the path the check simulates with "all start at 0" [DIALECTS.md, Branches]), `EQ`/`NE`
//!   tell vacant from 0, `#n=#m` copies vacancy, and an axis word whose value is vacant is
//!   refused (the control would silently drop the word).
//! - `M` codes: one per block, optionally with an integer `S` (spindle rpm); `M98`/`M99`/`M198`
//!   (sub-programs) are refused; `M2`, `M02` and `M30` end the program.

use std::collections::BTreeMap;

/// One motion block as executed: the axis positions after it (absolute, every axis the program
/// has set so far, by its letter: "X", "Z", "Y", "A", "C", ...).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AxisMove {
    /// 1-based line in the text.
    pub(crate) line: usize,
    /// `G00`.
    pub(crate) rapid: bool,
    /// `G04 X..` dwell in seconds (no axis motion).
    pub(crate) dwell_s: Option<f64>,
    /// `F` in force for a `G01`/`G02`/`G03` move (mm/min, `G94`).
    pub(crate) feed: Option<f64>,
    /// EGB on (between `G81` and `G80`).
    pub(crate) coupled: bool,
    /// Axis positions after the block.
    pub(crate) to: BTreeMap<String, f64>,
}

/// The result of running a program to its end code.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AxisRun {
    /// Every motion block and dwell, in execution order.
    pub(crate) moves: Vec<AxisMove>,
    /// The end code as written (`M30`, `M02`, `M2`).
    pub(crate) ended_by: String,
    /// `G81` blocks executed.
    pub(crate) couplings: usize,
    /// Macro variables with a value at the end (vacant ones are absent).
    pub(crate) vars: BTreeMap<u32, f64>,
}

/// The retained common variables a program may use [DIALECTS.md, Parameters: "#500–#999"].
const VAR_RANGE: std::ops::RangeInclusive<u32> = 500..=999;

/// A macro expression [DIALECTS.md: `+ - * / FIX[ ] [ ]`].
#[derive(Debug, Clone, PartialEq)]
enum Expr {
    Num(f64),
    Var(u32),
    Neg(Box<Expr>),
    Bracket(Box<Expr>),
    Fix(Box<Expr>),
    Bin(Box<Expr>, u8, Box<Expr>),
}

/// A comparison of an `IF` condition.
#[derive(Debug, Clone, PartialEq)]
enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

/// The value of an address word: a literal as written, or a bracketed expression.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Lit {
        text: String,
        value: f64,
        point: bool,
        decimals: usize,
    },
    Expr(Expr),
}

/// One address word of a block.
#[derive(Debug, Clone, PartialEq)]
struct Word {
    letter: u8,
    value: Value,
}

/// Modal state of the control while the program runs.
#[derive(Debug, Clone, PartialEq)]
struct State {
    metric: bool,
    work_offset: bool,
    feed_per_minute: bool,
    /// `Some(true)` absolute (`G90`), `Some(false)` incremental (`G91`).
    absolute: Option<bool>,
    /// Modal motion code 0–3.
    motion: Option<u8>,
    feed: Option<f64>,
    coupled: bool,
    couplings: usize,
    pos: BTreeMap<String, f64>,
    vars: BTreeMap<u32, f64>,
    moves: Vec<AxisMove>,
}

fn err(line: usize, msg: impl AsRef<str>) -> String {
    format!("line {line}: {}", msg.as_ref())
}

/// Decimals an axis value may carry, and the control's grid for it.
fn axis_decimals(letter: u8) -> Option<usize> {
    match letter {
        b'X' | b'Y' | b'Z' => Some(3),
        b'A' | b'C' => Some(4),
        _ => None,
    }
}

fn round_to(v: f64, decimals: usize) -> f64 {
    let scale = 10f64.powi(decimals as i32);
    (v * scale).round() / scale + 0.0
}

/// Runs the program from its first block to its end (M30/M02): macro variables `#n` with
/// `+ - * / FIX[ ] [ ]`, `IF [..] THEN #n=...`, `G00`/`G01`/`G02`/`G03` (arcs with `R`, X-Z
/// plane), `G04`, `G90`/`G91` (incremental moves like `G01 G91 Y.. C..` update positions
/// incrementally), `G81`/`G80`, M codes, comments. `vars_init` gives retained variables that
/// hold over from earlier runs (a variable not given is vacant, as on a reset control).
///
/// Errors: the first line outside the subset or a run-time alarm (division by zero, a vacant
/// axis word, a feed move without `F`, an arc whose `R` is shorter than half its chord), as
/// `"line N: what is wrong"`.
pub(crate) fn run_fanuc_egb(text: &str, vars_init: &[(u32, f64)]) -> Result<AxisRun, String> {
    let mut vars = BTreeMap::new();
    for &(n, v) in vars_init {
        if !VAR_RANGE.contains(&n) {
            return Err(format!(
                "vars_init: #{n} is outside the retained variables #500-#999"
            ));
        }
        if !v.is_finite() {
            return Err(format!("vars_init: #{n} is not a finite number"));
        }
        vars.insert(n, v + 0.0);
    }
    let lines: Vec<&str> = text.lines().collect();
    if lines.first().copied() != Some("%") {
        return Err(err(1, "the first line must be `%` alone"));
    }
    if lines.len() < 3 {
        return Err(err(
            lines.len() + 1,
            "a program needs `%`, its O number and a closing `%`",
        ));
    }
    program_number_line(lines[1], 2)?;
    let last = lines.len();
    if lines[last - 1] != "%" {
        return Err(err(
            last,
            "the last line must be `%` alone (nothing may follow it)",
        ));
    }
    let mut st = State {
        metric: false,
        work_offset: false,
        feed_per_minute: false,
        absolute: None,
        motion: None,
        feed: None,
        coupled: false,
        couplings: 0,
        pos: BTreeMap::new(),
        vars,
        moves: Vec::new(),
    };
    let mut ended_by: Option<String> = None;
    for (idx, raw) in lines.iter().enumerate().take(last - 1).skip(2) {
        let line = idx + 1;
        let (code, comment) = split_comment(raw, line)?;
        if let Some(c) = comment {
            check_comment(c, line)?;
        }
        let code = code.trim();
        if code.is_empty() {
            if comment.is_none() {
                return Err(err(line, "empty line"));
            }
            continue;
        }
        if ended_by.is_some() {
            return Err(err(
                line,
                "block after the end code: only comments may follow it",
            ));
        }
        if code.contains('%') {
            return Err(err(line, "`%` inside the program"));
        }
        ended_by = block(code, line, &mut st)?;
    }
    match ended_by {
        Some(ended_by) => Ok(AxisRun {
            moves: st.moves,
            ended_by,
            couplings: st.couplings,
            vars: st.vars,
        }),
        None => Err(err(last, "no end code (M30/M02) before the closing `%`")),
    }
}

/// `O0001`–`O7999`, optionally with a title comment [programs.md, Program names and files].
fn program_number_line(raw: &str, line: usize) -> Result<(), String> {
    let (code, comment) = split_comment(raw, line)?;
    if let Some(c) = comment {
        check_comment(c, line)?;
    }
    let code = code.trim_end();
    let digits = code.strip_prefix('O').ok_or_else(|| {
        err(
            line,
            "the second line must be the program number O0001-O7999",
        )
    })?;
    if digits.len() != 4 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return Err(err(
            line,
            format!("program number `{code}` is not O and four digits"),
        ));
    }
    let n: u32 = digits
        .parse()
        .map_err(|_| err(line, "bad program number"))?;
    if !(1..=7999).contains(&n) {
        return Err(err(
            line,
            format!("program number O{digits} is outside O0001-O7999"),
        ));
    }
    Ok(())
}

/// Splits a line into its code and its trailing comment (without the parentheses).
fn split_comment(raw: &str, line: usize) -> Result<(&str, Option<&str>), String> {
    match raw.find('(') {
        None => {
            if raw.contains(')') {
                return Err(err(line, "`)` without `(`"));
            }
            Ok((raw, None))
        }
        Some(open) => {
            let (code, rest) = raw.split_at(open);
            if code.contains(')') {
                return Err(err(line, "`)` without `(`"));
            }
            let rest = rest.trim_end();
            let inner = rest
                .strip_prefix('(')
                .and_then(|r| r.strip_suffix(')'))
                .ok_or_else(|| err(line, "a comment must close with `)` at the end of the line"))?;
            Ok((code, Some(inner)))
        }
    }
}

/// Comment text: printable upper-case ASCII, no parentheses [programs.md, Dialect rules].
fn check_comment(c: &str, line: usize) -> Result<(), String> {
    for ch in c.chars() {
        if ch == '(' || ch == ')' {
            return Err(err(line, "parentheses inside a comment"));
        }
        if !(' '..='~').contains(&ch) {
            return Err(err(
                line,
                format!("character {ch:?} in a comment is not printable ASCII"),
            ));
        }
        if ch.is_ascii_lowercase() {
            return Err(err(line, "lower-case letter in a comment"));
        }
        if ch == '%' {
            return Err(err(line, "`%` in a comment (the end-of-record code)"));
        }
    }
    Ok(())
}

/// Executes one block (the code part of a line). Returns the end code when the block ends the
/// program.
fn block(code: &str, line: usize, st: &mut State) -> Result<Option<String>, String> {
    let mut rest = code;
    if let Some(after) = rest.strip_prefix('N') {
        let n = after.bytes().take_while(u8::is_ascii_digit).count();
        if n == 0 || n > 5 {
            return Err(err(line, "a sequence number is N and 1-5 digits"));
        }
        rest = after[n..].trim_start();
        if rest.is_empty() {
            return Err(err(line, "a sequence number alone is an empty block"));
        }
    }
    for kw in [
        "WHILE", "GOTO", "DO", "END", "SETVN", "POPEN", "BPRNT", "DPRNT",
    ] {
        if rest.starts_with(kw) {
            return Err(err(line, format!("`{kw}` is outside the subset")));
        }
    }
    if rest.starts_with('#') {
        let (n, e) = parse_assignment(rest, line)?;
        assign(st, n, &e, line)?;
        return Ok(None);
    }
    if let Some(after) = rest.strip_prefix("IF") {
        return conditional(after, line, st).map(|()| None);
    }
    let words = parse_words(rest, line)?;
    execute(&words, line, st)
}

fn assign(st: &mut State, n: u32, e: &Expr, line: usize) -> Result<(), String> {
    match eval(e, &st.vars, line)? {
        Some(v) => {
            st.vars.insert(n, v + 0.0);
        }
        None => {
            st.vars.remove(&n);
        }
    }
    Ok(())
}

/// `#n=expr`.
fn parse_assignment(text: &str, line: usize) -> Result<(u32, Expr), String> {
    let mut p = ExprParser {
        s: text.as_bytes(),
        i: 0,
        line,
    };
    p.skip_ws();
    let n = p.var()?;
    p.skip_ws();
    if !p.eat(b'=') {
        return Err(err(line, format!("`#{n}` must be followed by `=`")));
    }
    let e = p.expr()?;
    p.skip_ws();
    if p.i != p.s.len() {
        return Err(err(
            line,
            format!("unexpected `{}` in the assignment", p.rest()),
        ));
    }
    Ok((n, e))
}

/// `IF [a OP b] THEN #n=expr`, the text after `IF`.
fn conditional(after: &str, line: usize, st: &mut State) -> Result<(), String> {
    let mut p = ExprParser {
        s: after.as_bytes(),
        i: 0,
        line,
    };
    if !p.skip_ws() {
        return Err(err(line, "`IF` must be followed by a space"));
    }
    if !p.eat(b'[') {
        return Err(err(line, "`IF` must be followed by `[condition]`"));
    }
    let a = p.expr()?;
    if !p.skip_ws() {
        return Err(err(line, "the comparison must stand between spaces"));
    }
    let op = match p.s.get(p.i..p.i + 2) {
        Some(b"EQ") => Cmp::Eq,
        Some(b"NE") => Cmp::Ne,
        Some(b"LT") => Cmp::Lt,
        Some(b"LE") => Cmp::Le,
        Some(b"GT") => Cmp::Gt,
        Some(b"GE") => Cmp::Ge,
        _ => {
            return Err(err(
                line,
                format!(
                    "expected EQ NE LT LE GT or GE at `{}` (AND/OR are outside the subset)",
                    p.rest()
                ),
            ))
        }
    };
    p.i += 2;
    if !p.skip_ws() {
        return Err(err(line, "the comparison must stand between spaces"));
    }
    let b = p.expr()?;
    p.skip_ws();
    if !p.eat(b']') {
        return Err(err(
            line,
            format!("expected `]` closing the condition at `{}`", p.rest()),
        ));
    }
    p.skip_ws();
    let tail = p.rest();
    if tail.starts_with("GOTO") {
        return Err(err(line, "`IF … GOTO` is outside the subset"));
    }
    let Some(assignment) = tail.strip_prefix("THEN") else {
        return Err(err(line, "`IF [..]` must be followed by `THEN #n=…`"));
    };
    let (n, e) = parse_assignment(assignment, line)?;
    let va = eval(&a, &st.vars, line)?;
    let vb = eval(&b, &st.vars, line)?;
    if compare(&op, va, vb) {
        assign(st, n, &e, line)?;
    }
    Ok(())
}

/// FANUC comparison with vacant values: EQ/NE tell vacant from 0, the others read it as 0.
fn compare(op: &Cmp, a: Option<f64>, b: Option<f64>) -> bool {
    let (x, y) = (a.unwrap_or(0.0), b.unwrap_or(0.0));
    match op {
        Cmp::Eq => a == b,
        Cmp::Ne => a != b,
        Cmp::Lt => x < y,
        Cmp::Le => x <= y,
        Cmp::Gt => x > y,
        Cmp::Ge => x >= y,
    }
}

fn eval(e: &Expr, vars: &BTreeMap<u32, f64>, line: usize) -> Result<Option<f64>, String> {
    let v = match e {
        Expr::Num(v) => Some(*v),
        Expr::Var(n) => vars.get(n).copied(),
        Expr::Bracket(inner) => eval(inner, vars, line)?,
        Expr::Neg(inner) => Some(-eval(inner, vars, line)?.unwrap_or(0.0)),
        Expr::Fix(inner) => Some(eval(inner, vars, line)?.unwrap_or(0.0).trunc()),
        Expr::Bin(a, op, b) => {
            let x = eval(a, vars, line)?.unwrap_or(0.0);
            let y = eval(b, vars, line)?.unwrap_or(0.0);
            Some(match op {
                b'+' => x + y,
                b'-' => x - y,
                b'*' => x * y,
                _ => {
                    if y == 0.0 {
                        return Err(err(line, "division by zero"));
                    }
                    x / y
                }
            })
        }
    };
    match v {
        Some(x) if !x.is_finite() => Err(err(line, "expression overflows")),
        _ => Ok(v.map(|x| x + 0.0)),
    }
}

/// Recursive-descent parser of macro expressions.
#[derive(Debug, Clone, PartialEq)]
struct ExprParser<'a> {
    s: &'a [u8],
    i: usize,
    line: usize,
}

impl ExprParser<'_> {
    fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }
    /// Skips spaces; true when there was at least one.
    fn skip_ws(&mut self) -> bool {
        let start = self.i;
        while self.peek() == Some(b' ') {
            self.i += 1;
        }
        self.i > start
    }
    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.i += 1;
            true
        } else {
            false
        }
    }
    fn rest(&self) -> String {
        String::from_utf8_lossy(&self.s[self.i.min(self.s.len())..]).into_owned()
    }
    /// `#n` with n in the retained block; `#[..]` (indirect) is refused.
    fn var(&mut self) -> Result<u32, String> {
        if !self.eat(b'#') {
            return Err(err(self.line, format!("expected `#` at `{}`", self.rest())));
        }
        let start = self.i;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.i += 1;
        }
        if self.i == start {
            return Err(err(
                self.line,
                "`#` must be followed by a variable number (indirect `#[..]` is outside the subset)",
            ));
        }
        let digits = String::from_utf8_lossy(&self.s[start..self.i]).into_owned();
        let n: u32 = digits
            .parse()
            .map_err(|_| err(self.line, format!("bad variable number `{digits}`")))?;
        if !VAR_RANGE.contains(&n) {
            return Err(err(
                self.line,
                format!("#{n} is outside the retained variables #500-#999"),
            ));
        }
        Ok(n)
    }
    fn expr(&mut self) -> Result<Expr, String> {
        let mut left = self.term()?;
        loop {
            let save = self.i;
            self.skip_ws();
            match self.peek() {
                Some(op @ (b'+' | b'-')) => {
                    self.i += 1;
                    let right = self.term()?;
                    left = Expr::Bin(Box::new(left), op, Box::new(right));
                }
                _ => {
                    self.i = save;
                    return Ok(left);
                }
            }
        }
    }
    fn term(&mut self) -> Result<Expr, String> {
        let mut left = self.factor()?;
        loop {
            let save = self.i;
            self.skip_ws();
            match self.peek() {
                Some(op @ (b'*' | b'/')) => {
                    self.i += 1;
                    let right = self.factor()?;
                    left = Expr::Bin(Box::new(left), op, Box::new(right));
                }
                _ => {
                    self.i = save;
                    return Ok(left);
                }
            }
        }
    }
    fn factor(&mut self) -> Result<Expr, String> {
        self.skip_ws();
        match self.peek() {
            Some(b'-') => {
                self.i += 1;
                Ok(Expr::Neg(Box::new(self.factor()?)))
            }
            Some(b'[') => {
                self.i += 1;
                let e = self.expr()?;
                self.skip_ws();
                if !self.eat(b']') {
                    return Err(err(self.line, format!("expected `]` at `{}`", self.rest())));
                }
                Ok(Expr::Bracket(Box::new(e)))
            }
            Some(b'#') => Ok(Expr::Var(self.var()?)),
            Some(c) if c.is_ascii_digit() => {
                let start = self.i;
                while self.peek().is_some_and(|c| c.is_ascii_digit()) {
                    self.i += 1;
                }
                if self.eat(b'.') {
                    let frac = self.i;
                    while self.peek().is_some_and(|c| c.is_ascii_digit()) {
                        self.i += 1;
                    }
                    if self.i == frac {
                        return Err(err(self.line, "a number needs digits after its point"));
                    }
                }
                let t = String::from_utf8_lossy(&self.s[start..self.i]).into_owned();
                t.parse()
                    .map(Expr::Num)
                    .map_err(|_| err(self.line, format!("bad number `{t}`")))
            }
            _ if self.s[self.i..].starts_with(b"FIX") => {
                self.i += 3;
                self.skip_ws();
                if !self.eat(b'[') {
                    return Err(err(self.line, "`FIX` must be followed by `[`"));
                }
                let e = self.expr()?;
                self.skip_ws();
                if !self.eat(b']') {
                    return Err(err(self.line, format!("expected `]` at `{}`", self.rest())));
                }
                Ok(Expr::Fix(Box::new(e)))
            }
            _ => Err(err(
                self.line,
                format!(
                    "expected a number, #n, [ or FIX at `{}` (other functions are outside the subset)",
                    self.rest()
                ),
            )),
        }
    }
}

/// Splits a block into address words: a letter, then a number (`-`, digits, `.`, digits) or,
/// for an axis word, a bracketed expression.
fn parse_words(text: &str, line: usize) -> Result<Vec<Word>, String> {
    let s = text.as_bytes();
    let mut i = 0;
    let mut words: Vec<Word> = Vec::new();
    while i < s.len() {
        if s[i] == b' ' {
            i += 1;
            continue;
        }
        let letter = s[i];
        if !letter.is_ascii_uppercase() {
            return Err(err(
                line,
                format!(
                    "unexpected `{}` (an address letter was expected)",
                    char::from(letter)
                ),
            ));
        }
        if !b"GMSFXYZACRTLQP".contains(&letter) {
            return Err(err(
                line,
                format!("address `{}` is outside the subset", char::from(letter)),
            ));
        }
        if words.iter().any(|w| w.letter == letter && letter != b'G') {
            return Err(err(
                line,
                format!("address `{}` twice in one block", char::from(letter)),
            ));
        }
        i += 1;
        let value = if s.get(i) == Some(&b'[') {
            if axis_decimals(letter).is_none() {
                return Err(err(
                    line,
                    format!(
                        "only an axis word may be a macro expression, not `{}`",
                        char::from(letter)
                    ),
                ));
            }
            let mut p = ExprParser { s, i, line };
            let e = p.factor()?;
            i = p.i;
            Value::Expr(e)
        } else {
            let start = i;
            if s.get(i) == Some(&b'-') {
                i += 1;
            }
            let int_start = i;
            while s.get(i).is_some_and(u8::is_ascii_digit) {
                i += 1;
            }
            if i == int_start {
                return Err(err(
                    line,
                    format!(
                        "`{}` must be followed by a number (a bare `#` is outside the subset)",
                        char::from(letter)
                    ),
                ));
            }
            let mut point = false;
            let mut decimals = 0;
            if s.get(i) == Some(&b'.') {
                point = true;
                i += 1;
                let frac = i;
                while s.get(i).is_some_and(u8::is_ascii_digit) {
                    i += 1;
                }
                decimals = i - frac;
                if decimals == 0 {
                    return Err(err(
                        line,
                        format!("`{}` needs digits after its point", char::from(letter)),
                    ));
                }
            }
            let t = String::from_utf8_lossy(&s[start..i]).into_owned();
            let value: f64 = t
                .parse()
                .map_err(|_| err(line, format!("bad number `{t}`")))?;
            Value::Lit {
                text: t,
                value,
                point,
                decimals,
            }
        };
        words.push(Word { letter, value });
    }
    Ok(words)
}

/// A literal word that must be an unsigned integer count (`G`, `M`, `S`, `T`).
fn count(w: &Word, line: usize) -> Result<(String, f64), String> {
    match &w.value {
        Value::Lit {
            text, value, point, ..
        } if !*point && !text.starts_with('-') => Ok((text.clone(), *value)),
        Value::Lit { text, .. } => Err(err(
            line,
            format!(
                "`{}{text}` must be an unsigned integer (`G81.4`/`G80.4` and the like are outside the subset)",
                char::from(w.letter)
            ),
        )),
        Value::Expr(_) => Err(err(line, "an expression is not allowed here")),
    }
}

/// A literal with a decimal point and at most `max` decimals (lengths, feeds, angles, dwell).
fn decimal(w: &Word, max: usize, line: usize) -> Result<f64, String> {
    match &w.value {
        Value::Lit {
            text,
            value,
            point,
            decimals,
        } => {
            if !*point {
                return Err(err(
                    line,
                    format!(
                        "`{}{text}` needs a decimal point (without one a FANUC control reads least input increments)",
                        char::from(w.letter)
                    ),
                ));
            }
            if *decimals > max {
                return Err(err(
                    line,
                    format!(
                        "`{}{text}` has more than {max} decimals",
                        char::from(w.letter)
                    ),
                ));
            }
            Ok(*value)
        }
        Value::Expr(_) => Err(err(line, "an expression is not allowed here")),
    }
}

/// Executes a block of address words.
fn execute(words: &[Word], line: usize, st: &mut State) -> Result<Option<String>, String> {
    let find = |l: u8| words.iter().find(|w| w.letter == l);
    let gs: Vec<u32> = words
        .iter()
        .filter(|w| w.letter == b'G')
        .map(|w| count(w, line).map(|(_, v)| v as u32))
        .collect::<Result<_, _>>()?;

    // M block: M [S], nothing else [DIALECTS.md: `N170 M03 S358`].
    if let Some(m) = find(b'M') {
        let (text, value) = count(m, line)?;
        if matches!(value as u32, 98 | 99 | 198) {
            return Err(err(
                line,
                format!("M{text}: sub-programs are outside the subset"),
            ));
        }
        if words.iter().any(|w| w.letter != b'M' && w.letter != b'S') {
            return Err(err(
                line,
                "an M block holds only its M code and a spindle speed S",
            ));
        }
        if let Some(s) = find(b'S') {
            count(s, line)?;
        }
        return Ok(matches!(value as u32, 2 | 30).then(|| format!("M{text}")));
    }
    if find(b'S').is_some() {
        return Err(err(line, "S only with its M code"));
    }

    // Group checks.
    let mut motion: Option<u8> = None;
    let mut other_groups: Vec<u32> = Vec::new();
    for &g in &gs {
        match g {
            0..=3 => {
                if motion.is_some() {
                    return Err(err(line, "two motion codes in one block"));
                }
                motion = Some(g as u8);
            }
            4 | 18 | 21 | 54..=59 | 80 | 81 | 90 | 91 | 94 => {
                let group = |c: u32| match c {
                    4 => 0,
                    18 => 16,
                    21 => 6,
                    54..=59 => 14,
                    80 | 81 => 9,
                    90 | 91 => 3,
                    _ => 5,
                };
                if other_groups.iter().any(|&o| group(o) == group(g)) {
                    return Err(err(line, format!("G{g} with another code of its group")));
                }
                other_groups.push(g);
            }
            20 => return Err(err(line, "G20 (inch) is outside the subset")),
            17 | 19 => {
                return Err(err(
                    line,
                    format!("G{g}: the arcs are in the X-Z plane (G18)"),
                ))
            }
            95 | 98 | 99 => {
                return Err(err(
                    line,
                    format!("G{g}: feed per revolution, G-code system A or a canned-cycle return level, outside the subset"),
                ))
            }
            _ => return Err(err(line, format!("G{g} is outside the subset"))),
        }
    }

    // Gearbox on / off.
    if other_groups.contains(&81) {
        if motion.is_some()
            || other_groups.len() > 1
            || words.iter().any(|w| !b"GTLQP".contains(&w.letter))
        {
            return Err(err(
                line,
                "G81 stands alone with T, L and optionally Q and P",
            ));
        }
        let t = find(b'T').ok_or_else(|| err(line, "G81 without T (teeth)"))?;
        let (_, t) = count(t, line)?;
        if !(1.0..=1000.0).contains(&t) {
            return Err(err(line, format!("G81 T{t} is outside 1-1000")));
        }
        let l = find(b'L').ok_or_else(|| err(line, "G81 without L (hob starts)"))?;
        let l = match &l.value {
            Value::Lit {
                value,
                point: false,
                ..
            } => *value,
            _ => return Err(err(line, "G81 L must be a signed integer")),
        };
        if l == 0.0 || l.abs() > 21.0 {
            return Err(err(line, format!("G81 L{l}: |L| must be 1-21")));
        }
        match (find(b'Q'), find(b'P')) {
            (None, None) => {}
            (Some(q), Some(p)) => {
                let q = decimal(q, 3, line)?;
                if !(0.1..=25.0).contains(&q) {
                    return Err(err(line, format!("G81 Q{q} is outside 0.1-25 mm")));
                }
                let p = decimal(p, 4, line)?;
                if p.abs() > 90.0 {
                    return Err(err(line, format!("G81 P{p}: |P| must be at most 90")));
                }
            }
            _ => return Err(err(line, "G81 Q and P come together or not at all")),
        }
        if st.coupled {
            return Err(err(line, "G81 while the gearbox is already coupled"));
        }
        st.coupled = true;
        st.couplings += 1;
        return Ok(None);
    }
    for l in [b'T', b'L', b'Q', b'P'] {
        if find(l).is_some() {
            return Err(err(
                line,
                format!("`{}` only in a G81 block", char::from(l)),
            ));
        }
    }
    if other_groups.contains(&80) {
        if words.len() != 1 {
            return Err(err(line, "G80 stands alone"));
        }
        if !st.coupled {
            return Err(err(line, "G80 while the gearbox is not coupled"));
        }
        st.coupled = false;
        return Ok(None);
    }

    // Dwell.
    if other_groups.contains(&4) {
        if words.len() != 2 {
            return Err(err(line, "G04 stands alone with X (seconds)"));
        }
        let x = find(b'X').ok_or_else(|| err(line, "G04 without X (seconds)"))?;
        let s = decimal(x, 3, line)?;
        if s < 0.0 {
            return Err(err(line, "a negative dwell"));
        }
        st.moves.push(AxisMove {
            line,
            rapid: false,
            dwell_s: Some(s),
            feed: None,
            coupled: st.coupled,
            to: st.pos.clone(),
        });
        return Ok(None);
    }

    // Modal codes, then the move.
    for &g in &other_groups {
        match g {
            21 => st.metric = true,
            54..=59 => st.work_offset = true,
            90 => st.absolute = Some(true),
            91 => st.absolute = Some(false),
            94 => st.feed_per_minute = true,
            _ => {} // G18: the only plane
        }
    }
    if let Some(m) = motion {
        st.motion = Some(m);
    }
    if let Some(f) = find(b'F') {
        let f = decimal(f, 3, line)?;
        if f <= 0.0 {
            return Err(err(line, "a feed must be positive"));
        }
        st.feed = Some(f);
    }
    let axes: Vec<&Word> = words
        .iter()
        .filter(|w| axis_decimals(w.letter).is_some())
        .collect();
    let r_word = find(b'R');
    if axes.is_empty() {
        if r_word.is_some() {
            return Err(err(line, "R without an arc end point"));
        }
        return Ok(None);
    }
    if !st.metric {
        return Err(err(line, "a move before G21 (metric)"));
    }
    if !st.work_offset {
        return Err(err(line, "a move before the work offset (G54-G59)"));
    }
    if !st.feed_per_minute {
        return Err(err(line, "a move before G94 (feed per minute)"));
    }
    let Some(absolute) = st.absolute else {
        return Err(err(line, "a move before G90/G91"));
    };
    let Some(mode) = st.motion else {
        return Err(err(line, "axis words without a motion code G00-G03"));
    };
    let has = |l: u8| axes.iter().any(|w| w.letter == l);
    if st.coupled && (has(b'Y') || has(b'C')) {
        if mode != 1 || absolute || !has(b'Y') || !has(b'C') || axes.len() != 2 {
            return Err(err(
                line,
                "while coupled the shift moves only as `G01 G91 Y.. C..` (both words, no other axis)",
            ));
        }
    } else if has(b'C') {
        return Err(err(
            line,
            "C moves only as the shift correction `G01 G91 Y.. C..` while coupled",
        ));
    }
    let start_x = st.pos.get("X").copied();
    let start_z = st.pos.get("Z").copied();
    for w in &axes {
        let Some(dec) = axis_decimals(w.letter) else {
            continue;
        };
        let v = match &w.value {
            Value::Lit { .. } => decimal(w, dec, line)?,
            Value::Expr(e) => eval(e, &st.vars, line)?.ok_or_else(|| {
                err(
                    line,
                    format!(
                        "the {} word's expression is vacant (the control would ignore the word)",
                        char::from(w.letter)
                    ),
                )
            })?,
        };
        let key = char::from(w.letter).to_string();
        let target = if absolute {
            v
        } else {
            st.pos.get(&key).copied().unwrap_or(0.0) + v
        };
        st.pos.insert(key, round_to(target, dec));
    }
    match mode {
        2 | 3 => {
            if axes.iter().any(|w| w.letter != b'X' && w.letter != b'Z') {
                return Err(err(line, "an arc moves only X and Z"));
            }
            let r =
                r_word.ok_or_else(|| err(line, "an arc without R (I/K are outside the subset)"))?;
            let r = decimal(r, 3, line)?;
            let (Some(x0), Some(z0)) = (start_x, start_z) else {
                return Err(err(line, "an arc from an unknown X or Z"));
            };
            let x1 = st.pos.get("X").copied().unwrap_or(x0);
            let z1 = st.pos.get("Z").copied().unwrap_or(z0);
            let chord = (x1 - x0).hypot(z1 - z0);
            if chord < 1e-9 {
                return Err(err(line, "an arc with R that ends where it starts"));
            }
            if r == 0.0 || chord / 2.0 > r.abs() + 0.001 {
                return Err(err(
                    line,
                    format!("R{r} is too small for a chord of {chord:.3} mm"),
                ));
            }
        }
        _ => {
            if r_word.is_some() {
                return Err(err(line, "R only in an arc block"));
            }
        }
    }
    let feed = if mode == 0 {
        None
    } else {
        Some(st.feed.ok_or_else(|| err(line, "a feed move without F"))?)
    };
    st.moves.push(AxisMove {
        line,
        rapid: mode == 0,
        dwell_s: None,
        feed,
        coupled: st.coupled,
        to: st.pos.clone(),
    });
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
        pairs.iter().map(|(k, v)| (k.to_string(), *v)).collect()
    }

    fn mv(
        line: usize,
        rapid: bool,
        feed: Option<f64>,
        coupled: bool,
        to: &[(&str, f64)],
    ) -> AxisMove {
        AxisMove {
            line,
            rapid,
            dwell_s: None,
            feed,
            coupled,
            to: axes(to),
        }
    }

    const TINY: &str = "%
O0042 (TINY TEST)
(A COMMENT LINE)
N10 G21
N20 G90 G94 G54
N30 G00 X100.0 Z50.0
#501=2.5
#502=4
IF [#502 GE 3] THEN #503=#501*2+1.25 (TAKEN)
IF [#502 LT 3] THEN #504=1.0 (NOT TAKEN)
N40 G00 Y[#503-FIX[#502/3]*0.5]
N50 G81 T20 L-2 Q2.0 P10.0 (EGB ON)
N60 M3 S300
N70 G01 G91 Y1.5 C-0.75 F50.0
N80 G90 X90.0
N90 G04 X1.5
N100 G03 Z30.0 R15.0 F20.0
N110 G00 G91 X5.0
N120 M5
N130 G80
N140 G90 Z50.0
N150 M30 (END)
%
";

    #[test]
    fn tiny_program_exact_moves() {
        let run = run_fanuc_egb(TINY, &[]).expect("tiny program runs");
        let dwell = AxisMove {
            line: 16,
            rapid: false,
            dwell_s: Some(1.5),
            feed: None,
            coupled: true,
            to: axes(&[("C", -0.75), ("X", 90.0), ("Y", 7.25), ("Z", 50.0)]),
        };
        let expected = vec![
            mv(6, true, None, false, &[("X", 100.0), ("Z", 50.0)]),
            // #503 = 2.5*2+1.25 = 6.25; FIX[4/3] = 1 -> 6.25 - 0.5
            mv(
                11,
                true,
                None,
                false,
                &[("X", 100.0), ("Y", 5.75), ("Z", 50.0)],
            ),
            // incremental shift while coupled: Y 5.75 + 1.5, C from 0
            mv(
                14,
                false,
                Some(50.0),
                true,
                &[("C", -0.75), ("X", 100.0), ("Y", 7.25), ("Z", 50.0)],
            ),
            // G01 and F50 modal, G90 again
            mv(
                15,
                false,
                Some(50.0),
                true,
                &[("C", -0.75), ("X", 90.0), ("Y", 7.25), ("Z", 50.0)],
            ),
            dwell,
            mv(
                17,
                false,
                Some(20.0),
                true,
                &[("C", -0.75), ("X", 90.0), ("Y", 7.25), ("Z", 30.0)],
            ),
            mv(
                18,
                true,
                None,
                true,
                &[("C", -0.75), ("X", 95.0), ("Y", 7.25), ("Z", 30.0)],
            ),
            // after G80, modal G00, back to G90
            mv(
                21,
                true,
                None,
                false,
                &[("C", -0.75), ("X", 95.0), ("Y", 7.25), ("Z", 50.0)],
            ),
        ];
        assert_eq!(run.moves, expected);
        assert_eq!(run.ended_by, "M30");
        assert_eq!(run.couplings, 1);
        let vars: BTreeMap<u32, f64> = [(501, 2.5), (502, 4.0), (503, 6.25)].into_iter().collect();
        assert_eq!(run.vars, vars, "the IF not taken leaves #504 vacant");
    }

    #[test]
    fn refusals_name_the_line() {
        let cases: &[(&str, &str, &str)] = &[
            (
                "N30 G00 X100.0 Z50.0",
                "N30 G00 X100 Z50.0",
                "line 6: `X100` needs a decimal point",
            ),
            (
                "N30 G00 X100.0 Z50.0",
                "N30 G00 X100.0 Z50.0001",
                "line 6: `Z50.0001` has more than 3",
            ),
            (
                "N50 G81 T20 L-2 Q2.0 P10.0 (EGB ON)",
                "N50 G81.4 T20 L-2",
                "line 12:",
            ),
            (
                "N50 G81 T20 L-2 Q2.0 P10.0 (EGB ON)",
                "N50 G81 T20 L-22",
                "line 12: G81 L-22",
            ),
            (
                "N50 G81 T20 L-2 Q2.0 P10.0 (EGB ON)",
                "N50 G81 T20 L-2 Q2.0",
                "line 12: G81 Q and P",
            ),
            (
                "N70 G01 G91 Y1.5 C-0.75 F50.0",
                "N70 G01 G90 Y1.5 C-0.75 F50.0",
                "line 14: while coupled",
            ),
            (
                "N70 G01 G91 Y1.5 C-0.75 F50.0",
                "N70 G01 G91 Y1.5 F50.0",
                "line 14: while coupled",
            ),
            ("N20 G90 G94 G54", "N20 G90 G98 G54", "line 5: G98"),
            (
                "N20 G90 G94 G54",
                "N20 G90 G54",
                "line 6: a move before G94",
            ),
            ("(A COMMENT LINE)", "(a comment line)", "line 3: lower-case"),
            (
                "(A COMMENT LINE)",
                "WHILE [#501 LT 3] DO1",
                "line 3: `WHILE`",
            ),
            (
                "IF [#502 LT 3] THEN #504=1.0 (NOT TAKEN)",
                "IF [#502 LT 3] GOTO 10",
                "line 10: `IF … GOTO`",
            ),
            (
                "IF [#502 LT 3] THEN #504=1.0 (NOT TAKEN)",
                "IF [#502 LT 3] THEN #104=1.0",
                "line 10: #104 is outside",
            ),
            ("#502=4", "#502=4/[#501-2.5]", "line 8: division by zero"),
            (
                "N40 G00 Y[#503-FIX[#502/3]*0.5]",
                "N40 G00 Y[#509]",
                "line 11: the Y word's expression is vacant",
            ),
            (
                "N100 G03 Z30.0 R15.0 F20.0",
                "N100 G03 Z30.0 R9.0 F20.0",
                "line 17: R9 is too small",
            ),
            (
                "N100 G03 Z30.0 R15.0 F20.0",
                "N100 G17 G03 Z30.0 R15.0",
                "line 17: G17",
            ),
            (
                "N130 G80",
                "N130 G80\nN131 G80",
                "line 21: G80 while the gearbox is not coupled",
            ),
            (
                "N150 M30 (END)",
                "N150 M30 (END)\nN160 G00 X1.0",
                "line 23: block after the end code",
            ),
            ("N150 M30 (END)", "N150 M5", "line 23: no end code"),
            (
                "O0042 (TINY TEST)",
                "O8000 (TINY TEST)",
                "line 2: program number O8000",
            ),
            ("N60 M3 S300", "N60 M98 P1000", "line 13: M98"),
            (
                "N30 G00 X100.0 Z50.0",
                "N30 G00 X#501 Z50.0",
                "line 6: `X` must be followed by a number",
            ),
        ];
        for (from, to, want) in cases {
            assert!(TINY.contains(from), "{from}");
            let text = TINY.replacen(from, to, 1);
            let got = run_fanuc_egb(&text, &[]).expect_err(to);
            assert!(got.starts_with(want), "{to}: got {got:?}, want {want:?}");
        }
        let got =
            run_fanuc_egb(&TINY.replacen("N10 G21", "N10 G21\n\n", 1), &[]).expect_err("blank");
        assert!(got.starts_with("line 5: empty line"), "{got}");
        let got = run_fanuc_egb(&format!("{TINY}\n"), &[]).expect_err("after %");
        assert!(
            got.starts_with("line 24: the last line must be `%`"),
            "{got}"
        );
    }

    #[test]
    fn vacant_versus_zero_in_conditions() {
        let text = "%
O0001
N10 G21
#500=#501
IF [#501 EQ 0] THEN #502=1.0
IF [#501 GE 0] THEN #503=1.0
#504=#501+0
IF [#504 EQ 0] THEN #505=1.0
N20 M2
%";
        let run = run_fanuc_egb(text, &[]).expect("runs");
        let want: BTreeMap<u32, f64> = [(503, 1.0), (504, 0.0), (505, 1.0)].into_iter().collect();
        assert_eq!(run.vars, want);
        assert_eq!(run.ended_by, "M2");
        assert!(run.moves.is_empty());
    }

    /// The FANUC example of DIALECTS.md, its concrete lines assembled into a program (`..`
    /// placeholders filled): the part counter wraps, the shift position comes from the macro
    /// expression in the Y word, and the coupled shift move updates Y and C incrementally.
    #[test]
    fn dialects_example() {
        let text = "%
O2002 (SP-2002 HOBBING)
(JOB SP-2002-1795286615641-9740)
N10 G21 (METRIC INPUT)
N20 G90 G94 G54
N30 G00 G90 X450.0
N40 G00 G90 Z550.0
N50 G00 G90 A-12.6284
N20 M10 (FIXTURE CLAMP)
#501=3.0 (NORMAL MODULE MN, MM)
#520=-21.738
#522=9.433
#523=3
#524=5
IF [#525 GE #523*#524] THEN #525=0
#526=FIX[#525/#523]
#527=#526-FIX[#526/#524]*#524
N190 G00 G90 X82.5 Y[#520+#522*#527]
N160 G81 T25 L1 Q3.0 P15.0 (EGB ON)
N170 M03 S358 (HOB ON, RPM)
N200 G01 G90 G94 X74.05 F7.162
N205 G01 G91 Y9.433 C5.601 F100.0
N210 G02 G90 X74.05 Z500.0 R60.0 F10.0
N215 G04 X2.0 (DWELL, S)
N216 G00 G90 X450.0
N250 G80 (EGB OFF)
N300 M00 (STOP FOR THE HOB CHANGE)
N390 M30 (END OF PROGRAM)
%";
        // In the document N190 (an absolute Y move) comes after the G81 of N160; the dialect
        // rule allows a coupled Y move only as `G01 G91 Y.. C..`, so that order is refused and
        // the shift is placed before the coupling here, as in the golden programs.
        let doc_order = text.replace(
            "N190 G00 G90 X82.5 Y[#520+#522*#527]\nN160 G81 T25 L1 Q3.0 P15.0 (EGB ON)\nN170 M03 S358 (HOB ON, RPM)\n",
            "N160 G81 T25 L1 Q3.0 P15.0 (EGB ON)\nN170 M03 S358 (HOB ON, RPM)\nN190 G00 G90 X82.5 Y[#520+#522*#527]\n",
        );
        assert_ne!(doc_order, text);
        let refused = run_fanuc_egb(&doc_order, &[(525, 14.0)]).expect_err("coupled absolute Y");
        assert!(refused.starts_with("line 20: while coupled"), "{refused}");
        // #525 = 14: FIX[14/3] = 4 steps, position 4 -> Y = -21.738 + 4*9.433 = 15.994.
        let run = run_fanuc_egb(text, &[(525, 14.0)]).expect("runs");
        assert_eq!(run.moves.len(), 9);
        assert_eq!(run.moves[3].to["Y"], 15.994);
        assert_eq!(run.moves[3].to["X"], 82.5);
        assert_eq!(run.moves[5].to["Y"], 25.427);
        assert_eq!(run.moves[5].to["C"], 5.601);
        assert_eq!(run.moves[5].feed, Some(100.0));
        assert_eq!(run.moves[6].to["Z"], 500.0);
        assert_eq!(run.moves[7].dwell_s, Some(2.0));
        assert!(!run.moves[3].coupled);
        assert!(run.moves[4..9].iter().all(|m| m.coupled));
        assert_eq!(run.moves[8].to["X"], 450.0);
        assert!(run.moves[8].coupled, "G80 follows the return");
        assert_eq!(run.vars[&525], 14.0);
        // #525 = 15 wraps to 0: the first position.
        let run = run_fanuc_egb(text, &[(525, 15.0)]).expect("runs");
        assert_eq!(run.moves[3].to["Y"], -21.738);
        assert_eq!(run.vars[&525], 0.0);
    }

    /// What a golden H02 program says, for the report.
    #[derive(Debug, Clone, PartialEq)]
    struct Summary {
        motion_blocks: usize,
        dwells: usize,
        first: BTreeMap<String, f64>,
        last: BTreeMap<String, f64>,
        ends_at_retract: bool,
        couplings: usize,
    }

    fn summary(name: &str, text: &str, init: &[(u32, f64)]) -> (AxisRun, Summary) {
        let run = run_fanuc_egb(text, init).unwrap_or_else(|e| panic!("{name}: {e}"));
        let motions: Vec<&AxisMove> = run.moves.iter().filter(|m| m.dwell_s.is_none()).collect();
        let first = motions[0].to.clone();
        let last = motions[motions.len() - 1].to.clone();
        // The retract position: X of the first move that sets X, Z of the first that sets Z.
        let rx = motions.iter().find_map(|m| m.to.get("X")).copied();
        let rz = motions.iter().find_map(|m| m.to.get("Z")).copied();
        let ends_at_retract =
            rx.is_some() && last.get("X").copied() == rx && last.get("Z").copied() == rz;
        let s = Summary {
            motion_blocks: motions.len(),
            dwells: run.moves.len() - motions.len(),
            first,
            last,
            ends_at_retract,
            couplings: run.couplings,
        };
        println!(
            "{name}: {} motion blocks (+{} dwell), first {:?}, last {:?}, ends at retract: {}, G81: {}, end {}, vars {:?}",
            s.motion_blocks, s.dwells, s.first, s.last, s.ends_at_retract, s.couplings, run.ended_by, run.vars
        );
        (run, s)
    }

    /// Counts the lines of a program that the reader must see as motion blocks: a G00-G03 word
    /// and an axis word, independently of the reader.
    fn motion_lines(text: &str) -> usize {
        text.lines()
            .filter(|l| !l.starts_with('(') && !l.starts_with('#') && !l.starts_with("IF"))
            .map(|l| l.split('(').next().unwrap_or(""))
            .filter(|l| {
                let w: Vec<&str> = l.split_whitespace().collect();
                w.iter().any(|x| ["G00", "G01", "G02", "G03"].contains(x))
                    && w.iter().any(|x| x.starts_with(['X', 'Y', 'Z', 'A', 'C']))
            })
            .count()
    }

    const GOLDEN: &[(&str, &str)] = &[
        (
            "conical_840d.H02.nc",
            include_str!("../golden/conical_840d.H02.nc"),
        ),
        (
            "crowned_840d.H02.nc",
            include_str!("../golden/crowned_840d.H02.nc"),
        ),
        (
            "crowned_parabolic_840d.H02.nc",
            include_str!("../golden/crowned_parabolic_840d.H02.nc"),
        ),
        (
            "helical_840d.H02.nc",
            include_str!("../golden/helical_840d.H02.nc"),
        ),
        (
            "helical_climb_840d.H02.nc",
            include_str!("../golden/helical_climb_840d.H02.nc"),
        ),
        (
            "helical_climb_fanuc.H02.nc",
            include_str!("../golden/helical_climb_fanuc.H02.nc"),
        ),
        (
            "helical_left_840d.H02.nc",
            include_str!("../golden/helical_left_840d.H02.nc"),
        ),
        (
            "helical_shift_fanuc.H02.nc",
            include_str!("../golden/helical_shift_fanuc.H02.nc"),
        ),
        (
            "multi_cut_shift_840d.H02.nc",
            include_str!("../golden/multi_cut_shift_840d.H02.nc"),
        ),
        (
            "multi_gear_840d.H02.nc",
            include_str!("../golden/multi_gear_840d.H02.nc"),
        ),
        (
            "spur_840d.H02.nc",
            include_str!("../golden/spur_840d.H02.nc"),
        ),
        (
            "spur_by_part_840d.H02.nc",
            include_str!("../golden/spur_by_part_840d.H02.nc"),
        ),
        (
            "worm_wheel_840d.H02.nc",
            include_str!("../golden/worm_wheel_840d.H02.nc"),
        ),
        (
            "worm_wheel_tangential_840d.H02.nc",
            include_str!("../golden/worm_wheel_tangential_840d.H02.nc"),
        ),
    ];

    /// Motion blocks, dwells and G81 couplings of every golden H02 program, counted by hand
    /// from the files.
    const EXPECTED: &[(&str, usize, usize, usize)] = &[
        ("conical_840d.H02.nc", 12, 0, 1),
        ("crowned_840d.H02.nc", 12, 0, 1),
        ("crowned_parabolic_840d.H02.nc", 19, 0, 1),
        ("helical_840d.H02.nc", 10, 0, 1),
        ("helical_climb_840d.H02.nc", 10, 0, 1),
        ("helical_climb_fanuc.H02.nc", 10, 0, 1),
        ("helical_left_840d.H02.nc", 10, 0, 1),
        ("helical_shift_fanuc.H02.nc", 16, 0, 1),
        ("multi_cut_shift_840d.H02.nc", 18, 0, 1),
        ("multi_gear_840d.H02.nc", 19, 0, 2),
        ("spur_840d.H02.nc", 10, 0, 1),
        ("spur_by_part_840d.H02.nc", 10, 0, 1),
        ("worm_wheel_840d.H02.nc", 10, 1, 1),
        ("worm_wheel_tangential_840d.H02.nc", 11, 0, 1),
    ];

    #[test]
    fn every_golden_program_runs_to_its_end_at_the_retract_position() {
        assert_eq!(GOLDEN.len(), EXPECTED.len());
        for ((name, text), (ename, blocks, dwells, couplings)) in GOLDEN.iter().zip(EXPECTED) {
            assert_eq!(name, ename);
            let (run, s) = summary(name, text, &[]);
            assert_eq!(run.ended_by, "M30", "{name}");
            assert_eq!(s.motion_blocks, *blocks, "{name}: {}", s.motion_blocks);
            assert_eq!(s.motion_blocks, motion_lines(text), "{name}");
            assert_eq!(s.dwells, *dwells, "{name}");
            assert_eq!(s.couplings, *couplings, "{name}");
            // Every program starts with the radial retract to X450 and ends at X450 Z550.
            assert_eq!(s.first, axes(&[("X", 450.0)]), "{name}");
            assert_eq!(s.last["X"], 450.0, "{name}");
            assert_eq!(s.last["Z"], 550.0, "{name}");
            assert!(s.ends_at_retract, "{name}");
            // The hob returns to the retract position while the gearbox is still coupled
            // (G80 follows the return), except multi_gear's first unit.
            assert!(run.moves.last().is_some_and(|m| m.coupled), "{name}");
            // The end code is the last block before the closing `%`.
            let lines: Vec<&str> = text.lines().collect();
            assert!(lines[lines.len() - 2].contains("M30"), "{name}");
            // No feed move without feed, and every feed move is coupled.
            for m in &run.moves {
                if !m.rapid && m.dwell_s.is_none() {
                    assert!(m.feed.is_some_and(|f| f > 0.0), "{name} line {}", m.line);
                    assert!(m.coupled, "{name} line {}", m.line);
                }
            }
        }
    }

    fn golden(name: &str) -> &'static str {
        GOLDEN
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, t)| *t)
            .unwrap_or_else(|| panic!("{name}"))
    }

    #[test]
    fn golden_shift_program_follows_the_part_counter() {
        let text = golden("helical_shift_fanuc.H02.nc");
        // Fresh control: #525 vacant, read as 0 -> first position.
        let (run, _) = summary("helical_shift_fanuc.H02.nc (fresh)", text, &[]);
        let y: Vec<f64> = run
            .moves
            .iter()
            .filter_map(|m| m.to.get("Y").copied())
            .collect();
        assert!(y.iter().all(|&v| v == -21.738));
        assert_eq!(run.vars[&525], 1.0);
        // 3 parts per step, 5 positions: the 13th part (counter 12) cuts at step 4.
        let (run, _) = summary("helical_shift_fanuc.H02.nc (#525=12)", text, &[(525, 12.0)]);
        assert_eq!(run.moves.last().map(|m| m.to["Y"]), Some(15.994));
        assert_eq!(run.vars[&525], 13.0);
        // Counter 15 >= 3*5 wraps to 0.
        let (run, _) = summary("helical_shift_fanuc.H02.nc (#525=15)", text, &[(525, 15.0)]);
        assert_eq!(run.moves.last().map(|m| m.to["Y"]), Some(-21.738));
        assert_eq!(run.vars[&525], 1.0);
    }

    #[test]
    fn golden_tangential_worm_wheel_shift_move() {
        let (run, _) = summary(
            "worm_wheel_tangential_840d.H02.nc",
            golden("worm_wheel_tangential_840d.H02.nc"),
            &[],
        );
        let shift = run
            .moves
            .iter()
            .find(|m| m.to.contains_key("C"))
            .expect("shift move");
        assert_eq!(shift.line, 44);
        assert!(shift.coupled && !shift.rapid);
        assert_eq!(shift.feed, Some(7.958));
        assert_eq!(shift.to["Y"], 78.383); // -81.384 + 159.767
        assert_eq!(shift.to["C"], 152.4359);
        // C = c_per_y * dY with the comment's 0.954112 deg/mm = 360 cos(2.3715°)/(pi*3*40).
        let c_per_y = 360.0 * 2.3715f64.to_radians().cos() / (std::f64::consts::PI * 3.0 * 40.0);
        assert!((152.4359 / 159.767 - c_per_y).abs() < 1e-5);
        assert!((c_per_y - 0.954112).abs() < 1e-6);
    }

    /// Mid-point of a G18 arc (Z horizontal, X vertical, G03 counter-clockwise seen from +Y).
    fn arc_mid(x0: f64, z0: f64, x1: f64, z1: f64, r: f64, ccw: bool) -> (f64, f64) {
        let (du, dv) = (z1 - z0, x1 - x0);
        let l = du.hypot(dv);
        let (nu, nv) = if ccw {
            (-dv / l, du / l)
        } else {
            (dv / l, -du / l)
        };
        let h = (r * r - l * l / 4.0).sqrt();
        let (mu, mv) = ((z0 + z1) / 2.0, (x0 + x1) / 2.0);
        // The centre lies at m + n*h on the left (ccw) or right (cw) of the chord; the arc's
        // mid-point on the far side of the chord from the centre.
        (mv - nv * (r - h), mu - nu * (r - h))
    }

    #[test]
    fn golden_crowning_arc_bulges_outwards_by_cb() {
        let text = golden("crowned_840d.H02.nc");
        let (run, _) = summary("crowned_840d.H02.nc", text, &[]);
        let i = run
            .moves
            .iter()
            .position(|m| m.line == 44)
            .expect("the arc");
        let (a, b) = (&run.moves[i - 1], &run.moves[i]);
        assert_eq!((a.to["X"], a.to["Z"]), (81.23, 140.0));
        assert_eq!((b.to["X"], b.to["Z"]), (81.23, 100.0));
        assert!(text
            .lines()
            .nth(43)
            .is_some_and(|l| l.contains("G03") && l.contains("R10000.01")));
        let (xm, zm) = arc_mid(81.23, 140.0, 81.23, 100.0, 10000.01, true);
        assert!((zm - 120.0).abs() < 1e-9);
        // CB = 0.02 in the header comment: the middle of the face 0.02 mm further out.
        assert!((xm - 81.25).abs() < 1e-4, "{xm}");
        // The parabolic version reaches its CB = 0.03 at the middle chord point.
        let (run, _) = summary(
            "crowned_parabolic_840d.H02.nc",
            golden("crowned_parabolic_840d.H02.nc"),
            &[],
        );
        let mid = run
            .moves
            .iter()
            .find(|m| m.to.get("Z") == Some(&118.0))
            .expect("middle");
        assert_eq!(mid.to["X"], 79.188);
    }
}
