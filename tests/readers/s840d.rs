//! Clean-room reader of gearcam's SINUMERIK 840D hobbing programs (dialect `sinumerik840d`).
//!
//! Written from the documents only (`docs/programs.md` "The hobbing program", "Dialect rules →
//! SINUMERIK 840D", "Path check", "Program names and files"; `docs/hobbing.md` §4 and §6;
//! `crates/nc/DIALECTS.md` "Siemens SINUMERIK 840D", "Parameters", "Branches"), sharing no code
//! with gearcam's own parser. It executes a program like a control would, from the first line to
//! the end code, and refuses (with `Err` naming the 1-based line) anything outside the documented
//! subset:
//!
//! * line 1 `%_N_{NAME}_MPF` with NAME 1–24 characters from `A–Z 0–9 _`, starting with two
//!   letters or `_` and a letter (programs.md "Program names and files"); line 2
//!   `;$PATH=/_N_MPF_DIR`;
//! * comments after `;` (outside a `"…"` string), printable ASCII only (DIALECTS.md);
//! * an optional block number `N…` at the start of a block;
//! * set-up before the first move: `G71`, `G90`/`G91`, `G94`, `DIAMOF` and a work offset
//!   (`G54`–`G57`, `G505`–`G599`) (programs.md "Dialect rules");
//! * `G0`/`G1`/`CIP` with axis words `X=expr` (`I1=` `K1=` the intermediate point of `CIP`),
//!   `G4 F=` dwell in seconds alone in its block, `F=` feed (modal), `S=` speed, `M` codes,
//!   `G90`/`G91`;
//! * R parameters `Rn=expr` with `+ - * / MOD TRUNC( )` and parentheses, `IF a op b` with
//!   `== <> < <= > >=`, at most one `ELSE`, `ENDIF`, nested, with only assignments inside
//!   (DIALECTS.md "Branches");
//! * the electronic gearbox `EGDEF(C,B,1[,Z,1][,Y,1])`,
//!   `EGONSYNE(C,"FINE",0,"DCT",B,0,num,den[,Z,0,f,1][,Y,0,f,1])` (four arguments per leading
//!   axis), `EGOFS(C)`, `EGDEL(C)`;
//! * `MSG("…")`, `MSG()`;
//! * the end `M2`/`M02`/`M30`, which must be the last block (comments may follow).
//!
//! Literal numbers in axis words, `F=`, `S=`, `I1=`/`K1=` must have a decimal point, no `-0`,
//! at most 3 decimals (lengths, feeds, speeds, dwell) or 4 for the rotary axes `A B C` (angles);
//! gearbox factors at most 6 decimals (DIALECTS.md "Numbers").
//!
//! Gearbox sequence, as a control keeps it: `EGONSYNE` needs an `EGDEF` of its following axis
//! with the same leading axes and a gearbox that is off; `EGDEF` of an axis already defined and
//! `EGDEL` of a gearbox still on are refused; the following axis is not programmed while coupled.
//! Also refused: `G1`/`CIP` without a feed in force, `G91` from an unknown position, and a
//! division or `MOD` by zero.

use std::collections::BTreeMap;

/// One motion block as executed: the axis positions after it (absolute, every axis the program
/// has set so far, by its letter as written: "X", "Z", "Y", "A", "C", ...).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AxisMove {
    /// 1-based line in the text.
    pub(crate) line: usize,
    /// `G0`.
    pub(crate) rapid: bool,
    /// `G4 F..` dwell (no axis motion).
    pub(crate) dwell_s: Option<f64>,
    /// F in force for a `G1` (or `CIP`) move.
    pub(crate) feed: Option<f64>,
    /// Electronic gearbox on (`EGONSYNE` active) during the move.
    pub(crate) coupled: bool,
    /// Positions after the block.
    pub(crate) to: BTreeMap<String, f64>,
}

/// The result of one run of a program.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct AxisRun {
    /// Motion blocks (and dwells) in execution order.
    pub(crate) moves: Vec<AxisMove>,
    /// `"M2"`, `"M02"` or `"M30"` as written.
    pub(crate) ended_by: String,
    /// `EGONSYNE` blocks executed.
    pub(crate) couplings: usize,
    /// R parameters at the end (those given in `r_init` or assigned by the program).
    pub(crate) r: BTreeMap<u32, f64>,
}

/// Runs the program from its first line to M2/M30: R parameter arithmetic (+ - * / MOD TRUNC,
/// parentheses), IF/ELSE/ENDIF around assignments, G0/G1/G4, G90/G91, CIP arcs (record the end
/// point), EGDEF/EGONSYNE/EGOFS/EGDEL, MSG, M codes, comments. Axis words `X=expr`.
/// `r_init` gives R parameters that hold over from earlier runs (the part counter).
///
/// The whole text is parsed first (so a fault in a branch that is not taken, or after the end,
/// is still refused), then executed. R parameters not in `r_init` and not yet assigned read as 0
/// (DIALECTS.md "Branches": "all start at 0").
pub(crate) fn run_840d(text: &str, r_init: &[(u32, f64)]) -> Result<AxisRun, String> {
    let program = parse_program(text)?;
    execute(&program, r_init)
}

// ---------------------------------------------------------------------------------------------
// Syntax
// ---------------------------------------------------------------------------------------------

/// Highest R parameter number of an 840D (DIALECTS.md "Parameters": R0–R999).
const R_MAX: u32 = 999;

/// Axis letters accepted in axis words. The letters come from the machine profile
/// (DIALECTS.md); these are the usual single-letter 840D machine axes.
const AXES: &[&str] = &["X", "Y", "Z", "A", "B", "C", "U", "V", "W"];

/// Rotary axes: angles with up to 4 decimals; the others are lengths with up to 3.
const ROTARY: &[&str] = &["A", "B", "C"];

/// A lexical token of a block (comment and block number removed).
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Tok {
    /// Letters followed by letters, digits or `_` (`G0`, `R20`, `X`, `MOD`, `EGDEF`, `I1`).
    Ident(String),
    /// An unsigned number literal as written.
    Num(String),
    /// A `"…"` string (without quotes).
    Str(String),
    /// `= + - * / ( ) , < > <= >= == <>`.
    Sym(&'static str),
}

/// A token with whether white space stood before it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Lexeme {
    pub(crate) tok: Tok,
    pub(crate) spaced: bool,
}

/// Binary arithmetic operators.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
}

/// Comparison operators of an `IF`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Cmp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

/// An R-parameter expression.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Expr {
    Num(f64),
    R(u32),
    Neg(Box<Expr>),
    Trunc(Box<Expr>),
    Bin(Op, Box<Expr>, Box<Expr>),
}

/// An expression with the literal it was written as, when it is a (signed) literal.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Value {
    pub(crate) expr: Expr,
    /// `Some("-12.6285")` when the word is a plain literal, for the number-form rules.
    pub(crate) literal: Option<String>,
}

/// One leading axis of `EGONSYNE`: axis, synchronised position, numerator, denominator.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Lead {
    pub(crate) axis: String,
    pub(crate) sync: f64,
    pub(crate) num: f64,
    pub(crate) den: f64,
}

/// A block of address words (`G`, `M`, `CIP`, `DIAMOF`, axes, `I1`, `K1`, `F`, `S`).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Words {
    pub(crate) g: Vec<u32>,
    /// M codes as written (`M2`, `M02`, `M30`, `M3`, ...) with their number.
    pub(crate) m: Vec<(String, u32)>,
    pub(crate) cip: bool,
    pub(crate) diamof: bool,
    pub(crate) axes: Vec<(String, Value)>,
    pub(crate) i1: Option<Value>,
    pub(crate) k1: Option<Value>,
    pub(crate) f: Option<Value>,
    pub(crate) s: Option<Value>,
}

/// One executable block.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Stmt {
    Assign(Vec<(u32, Expr)>),
    If(Expr, Cmp, Expr),
    Else,
    EndIf,
    EgDef {
        following: String,
        leading: Vec<String>,
    },
    EgOnSyne {
        following: String,
        leading: Vec<Lead>,
    },
    EgOfs(String),
    EgDel(String),
    Msg(Option<String>),
    Words(Box<Words>),
}

/// A parsed program: its name and the blocks with their 1-based lines.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Program {
    pub(crate) name: String,
    pub(crate) blocks: Vec<(usize, Stmt)>,
}

fn err(line: usize, msg: impl std::fmt::Display) -> String {
    format!("line {line}: {msg}")
}

/// The 840D program name rule (programs.md "Program names and files"): 1–24 characters from
/// `A–Z 0–9 _`; the first two letters, or `_` and a letter.
fn check_name(name: &str) -> bool {
    let b = name.as_bytes();
    let charset = b
        .iter()
        .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || *c == b'_');
    let start =
        b.len() >= 2 && (b[0].is_ascii_uppercase() || b[0] == b'_') && b[1].is_ascii_uppercase();
    !b.is_empty() && b.len() <= 24 && charset && start
}

/// Splits a line into code and comment at the first `;` outside a string.
fn split_comment(s: &str) -> &str {
    let mut in_str = false;
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_str = !in_str,
            ';' if !in_str => return &s[..i],
            _ => {}
        }
    }
    s
}

fn lex(line: usize, code: &str) -> Result<Vec<Lexeme>, String> {
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    let mut spaced = true;
    while i < chars.len() {
        let c = chars[i];
        if c == ' ' || c == '\t' {
            spaced = true;
            i += 1;
            continue;
        }
        let tok = if c.is_ascii_uppercase() || c == '_' {
            let start = i;
            while i < chars.len()
                && (chars[i].is_ascii_uppercase() || chars[i].is_ascii_digit() || chars[i] == '_')
            {
                i += 1;
            }
            if i < chars.len() && chars[i].is_ascii_lowercase() {
                return Err(err(line, "lower-case letters outside a comment or string"));
            }
            Tok::Ident(chars[start..i].iter().collect())
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            let mut dots = 0;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                if chars[i] == '.' {
                    dots += 1;
                }
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            if dots > 1 || text == "." {
                return Err(err(line, format!("malformed number `{text}`")));
            }
            Tok::Num(text)
        } else if c == '"' {
            let start = i + 1;
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                i += 1;
            }
            if i >= chars.len() {
                return Err(err(line, "unterminated string"));
            }
            let s: String = chars[start..i].iter().collect();
            i += 1;
            Tok::Str(s)
        } else {
            let next = chars.get(i + 1).copied();
            let (sym, len): (&'static str, usize) = match (c, next) {
                ('<', Some('=')) => ("<=", 2),
                ('>', Some('=')) => (">=", 2),
                ('=', Some('=')) => ("==", 2),
                ('<', Some('>')) => ("<>", 2),
                ('<', _) => ("<", 1),
                ('>', _) => (">", 1),
                ('=', _) => ("=", 1),
                ('+', _) => ("+", 1),
                ('-', _) => ("-", 1),
                ('*', _) => ("*", 1),
                ('/', _) => ("/", 1),
                ('(', _) => ("(", 1),
                (')', _) => (")", 1),
                (',', _) => (",", 1),
                _ if c.is_ascii_lowercase() => {
                    return Err(err(line, "lower-case letters outside a comment or string"))
                }
                _ => return Err(err(line, format!("unexpected character `{c}`"))),
            };
            i += len;
            Tok::Sym(sym)
        };
        out.push(Lexeme { tok, spaced });
        spaced = false;
    }
    Ok(out)
}

/// A cursor over the tokens of one block.
struct Cur<'a> {
    toks: &'a [Lexeme],
    pos: usize,
    line: usize,
}

impl Cur<'_> {
    fn peek(&self) -> Option<&Tok> {
        self.toks.get(self.pos).map(|l| &l.tok)
    }
    fn next(&mut self) -> Option<&Tok> {
        let t = self.toks.get(self.pos).map(|l| &l.tok);
        self.pos += 1;
        t
    }
    fn at_end(&self) -> bool {
        self.pos >= self.toks.len()
    }
    fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Some(Tok::Sym(x)) if *x == s)
    }
    fn expect_sym(&mut self, s: &str) -> Result<(), String> {
        if self.is_sym(s) {
            self.pos += 1;
            Ok(())
        } else {
            Err(err(self.line, format!("expected `{s}`")))
        }
    }
    fn err(&self, msg: impl std::fmt::Display) -> String {
        err(self.line, msg)
    }
}

fn parse_num(line: usize, s: &str) -> Result<f64, String> {
    s.parse::<f64>()
        .map_err(|_| err(line, format!("malformed number `{s}`")))
}

/// `R` followed by 1–3 digits, R0–R999.
fn r_index(name: &str) -> Option<u32> {
    let digits = name.strip_prefix('R')?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse::<u32>().ok().filter(|n| *n <= R_MAX)
}

/// expr := term { (+|-) term }; term := unary { (*|/|MOD) unary };
/// unary := [+|-] unary | primary; primary := number | Rn | TRUNC(expr) | (expr).
fn parse_expr(c: &mut Cur) -> Result<Expr, String> {
    let mut lhs = parse_term(c)?;
    loop {
        let op = match c.peek() {
            Some(Tok::Sym("+")) => Op::Add,
            Some(Tok::Sym("-")) => Op::Sub,
            _ => return Ok(lhs),
        };
        c.pos += 1;
        let rhs = parse_term(c)?;
        lhs = Expr::Bin(op, Box::new(lhs), Box::new(rhs));
    }
}

fn parse_term(c: &mut Cur) -> Result<Expr, String> {
    let mut lhs = parse_unary(c)?;
    loop {
        let op = match c.peek() {
            Some(Tok::Sym("*")) => Op::Mul,
            Some(Tok::Sym("/")) => Op::Div,
            Some(Tok::Ident(s)) if s == "MOD" => Op::Mod,
            _ => return Ok(lhs),
        };
        c.pos += 1;
        let rhs = parse_unary(c)?;
        lhs = Expr::Bin(op, Box::new(lhs), Box::new(rhs));
    }
}

fn parse_unary(c: &mut Cur) -> Result<Expr, String> {
    if c.is_sym("-") {
        c.pos += 1;
        return Ok(Expr::Neg(Box::new(parse_unary(c)?)));
    }
    if c.is_sym("+") {
        c.pos += 1;
        return parse_unary(c);
    }
    parse_primary(c)
}

fn parse_primary(c: &mut Cur) -> Result<Expr, String> {
    let line = c.line;
    match c.next().cloned() {
        Some(Tok::Num(s)) => Ok(Expr::Num(parse_num(line, &s)?)),
        Some(Tok::Ident(s)) if s == "TRUNC" => {
            c.expect_sym("(")?;
            let e = parse_expr(c)?;
            c.expect_sym(")")?;
            Ok(Expr::Trunc(Box::new(e)))
        }
        Some(Tok::Ident(s)) => match r_index(&s) {
            Some(n) => Ok(Expr::R(n)),
            None => Err(err(
                line,
                format!("`{s}` is not an R parameter (R0–R999) or TRUNC"),
            )),
        },
        Some(Tok::Sym("(")) => {
            let e = parse_expr(c)?;
            c.expect_sym(")")?;
            Ok(e)
        }
        Some(t) => Err(err(line, format!("unexpected {t:?} in an expression"))),
        None => Err(err(line, "expression expected")),
    }
}

/// An expression, remembering whether it is a plain (signed) literal.
fn parse_value(c: &mut Cur) -> Result<Value, String> {
    let start = c.pos;
    let expr = parse_expr(c)?;
    let toks: Vec<&Tok> = c.toks[start..c.pos].iter().map(|l| &l.tok).collect();
    let literal = match toks.as_slice() {
        [Tok::Num(n)] => Some(n.clone()),
        [Tok::Sym("-"), Tok::Num(n)] => Some(format!("-{n}")),
        [Tok::Sym("+"), Tok::Num(n)] => Some(format!("+{n}")),
        _ => None,
    };
    Ok(Value { expr, literal })
}

/// NC number form (DIALECTS.md "Numbers"): a decimal point, at most `max_dec` decimals, never
/// `-0`, no explicit `+`.
fn check_form(line: usize, what: &str, v: &Value, max_dec: usize) -> Result<(), String> {
    let Some(lit) = &v.literal else { return Ok(()) };
    let body = lit.strip_prefix('-').unwrap_or(lit);
    if body.starts_with('+') {
        return Err(err(line, format!("{what}: explicit `+` in `{lit}`")));
    }
    let Some((int, frac)) = body.split_once('.') else {
        return Err(err(line, format!("{what}: `{lit}` has no decimal point")));
    };
    if int.is_empty() || frac.is_empty() {
        return Err(err(
            line,
            format!("{what}: `{lit}` needs digits on both sides of the point"),
        ));
    }
    if frac.len() > max_dec {
        return Err(err(
            line,
            format!("{what}: `{lit}` has more than {max_dec} decimals"),
        ));
    }
    if lit.starts_with('-') && body.bytes().all(|b| b == b'0' || b == b'.') {
        return Err(err(line, format!("{what}: `-0` is not written")));
    }
    Ok(())
}

fn parse_cmp(c: &mut Cur) -> Result<Cmp, String> {
    let cmp = match c.peek() {
        Some(Tok::Sym("==")) => Cmp::Eq,
        Some(Tok::Sym("<>")) => Cmp::Ne,
        Some(Tok::Sym("<")) => Cmp::Lt,
        Some(Tok::Sym("<=")) => Cmp::Le,
        Some(Tok::Sym(">")) => Cmp::Gt,
        Some(Tok::Sym(">=")) => Cmp::Ge,
        _ => return Err(c.err("IF needs a comparison == <> < <= > >=")),
    };
    c.pos += 1;
    Ok(cmp)
}

/// An argument of a gearbox or message call.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Arg {
    Axis(String),
    Str(String),
    Num(String, f64),
}

fn parse_args(c: &mut Cur) -> Result<Vec<Arg>, String> {
    c.expect_sym("(")?;
    let mut args = Vec::new();
    if c.is_sym(")") {
        c.pos += 1;
        return Ok(args);
    }
    loop {
        let line = c.line;
        let neg = if c.is_sym("-") {
            c.pos += 1;
            true
        } else {
            false
        };
        let arg = match (c.next().cloned(), neg) {
            (Some(Tok::Ident(s)), false) => Arg::Axis(s),
            (Some(Tok::Str(s)), false) => Arg::Str(s),
            (Some(Tok::Num(s)), _) => {
                let v = parse_num(line, &s)?;
                if neg {
                    Arg::Num(format!("-{s}"), -v)
                } else {
                    Arg::Num(s, v)
                }
            }
            _ => return Err(err(line, "argument must be an axis, a string or a number")),
        };
        args.push(arg);
        match c.next() {
            Some(Tok::Sym(",")) => {}
            Some(Tok::Sym(")")) => return Ok(args),
            _ => return Err(err(line, "expected `,` or `)` in the argument list")),
        }
    }
}

fn axis_arg(line: usize, a: &Arg, what: &str) -> Result<String, String> {
    match a {
        Arg::Axis(s) if AXES.contains(&s.as_str()) => Ok(s.clone()),
        _ => Err(err(
            line,
            format!("{what}: an axis letter expected, got {a:?}"),
        )),
    }
}

fn num_arg(line: usize, a: &Arg, what: &str) -> Result<(String, f64), String> {
    match a {
        Arg::Num(s, v) => Ok((s.clone(), *v)),
        _ => Err(err(line, format!("{what}: a number expected, got {a:?}"))),
    }
}

/// `EGDEF(following, lead, 1[, lead, 1]…)` (programs.md "Dialect rules → SINUMERIK 840D").
fn parse_egdef(line: usize, args: &[Arg]) -> Result<Stmt, String> {
    if args.len() < 3 || !args[1..].chunks_exact(2).remainder().is_empty() {
        return Err(err(
            line,
            "EGDEF needs the following axis and (leading axis, 1) pairs",
        ));
    }
    let following = axis_arg(line, &args[0], "EGDEF")?;
    let mut leading: Vec<String> = Vec::new();
    for pair in args[1..].chunks(2) {
        let axis = axis_arg(line, &pair[0], "EGDEF leading axis")?;
        let (text, _) = num_arg(line, &pair[1], "EGDEF coupling type")?;
        if text != "1" {
            return Err(err(
                line,
                format!("EGDEF coupling type `{text}`: only 1 is written"),
            ));
        }
        if axis == following || leading.contains(&axis) {
            return Err(err(line, format!("EGDEF: axis {axis} named twice")));
        }
        leading.push(axis);
    }
    Ok(Stmt::EgDef { following, leading })
}

/// `EGONSYNE(following, "FINE", pos, "DCT", lead, pos, num, den[, lead, pos, num, den]…)`.
fn parse_egonsyne(line: usize, args: &[Arg]) -> Result<Stmt, String> {
    if args.len() < 8 || !args[4..].chunks_exact(4).remainder().is_empty() {
        return Err(err(
            line,
            "EGONSYNE needs the following axis, \"FINE\", its position, \"DCT\" and four arguments per leading axis",
        ));
    }
    let following = axis_arg(line, &args[0], "EGONSYNE")?;
    if args[1] != Arg::Str("FINE".into()) {
        return Err(err(line, "EGONSYNE: block change mode must be \"FINE\""));
    }
    let (_, sync_following) = num_arg(line, &args[2], "EGONSYNE following position")?;
    let _ = sync_following;
    if args[3] != Arg::Str("DCT".into()) {
        return Err(err(line, "EGONSYNE: synchronisation mode must be \"DCT\""));
    }
    let mut leading: Vec<Lead> = Vec::new();
    for quad in args[4..].chunks(4) {
        let axis = axis_arg(line, &quad[0], "EGONSYNE leading axis")?;
        let (_, sync) = num_arg(line, &quad[1], "EGONSYNE synchronised position")?;
        let (num_text, num) = num_arg(line, &quad[2], "EGONSYNE numerator")?;
        let (den_text, den) = num_arg(line, &quad[3], "EGONSYNE denominator")?;
        if den == 0.0 {
            return Err(err(line, "EGONSYNE: zero denominator"));
        }
        let decimals = num_text.split_once('.').map_or(0, |(_, f)| f.len());
        if decimals > 6 || den_text.contains('.') {
            return Err(err(
                line,
                "EGONSYNE: factor with more than 6 decimals or a non-integer denominator",
            ));
        }
        if axis == following || leading.iter().any(|l| l.axis == axis) {
            return Err(err(line, format!("EGONSYNE: axis {axis} named twice")));
        }
        leading.push(Lead {
            axis,
            sync,
            num,
            den,
        });
    }
    Ok(Stmt::EgOnSyne { following, leading })
}

fn parse_call(line: usize, name: &str, c: &mut Cur) -> Result<Stmt, String> {
    let args = parse_args(c)?;
    if !c.at_end() {
        return Err(err(
            line,
            format!("{name}(…) must stand alone in its block"),
        ));
    }
    match name {
        "EGDEF" => parse_egdef(line, &args),
        "EGONSYNE" => parse_egonsyne(line, &args),
        "EGOFS" | "EGDEL" => {
            if args.len() != 1 {
                return Err(err(line, format!("{name} takes the following axis only")));
            }
            let axis = axis_arg(line, &args[0], name)?;
            Ok(if name == "EGOFS" {
                Stmt::EgOfs(axis)
            } else {
                Stmt::EgDel(axis)
            })
        }
        "MSG" => match args.as_slice() {
            [] => Ok(Stmt::Msg(None)),
            [Arg::Str(s)] => Ok(Stmt::Msg(Some(s.clone()))),
            _ => Err(err(line, "MSG takes one string or nothing")),
        },
        _ => Err(err(line, format!("`{name}(…)` is outside the 840D subset"))),
    }
}

/// `G` or `M` followed by digits: the number.
fn code_number(s: &str, letter: char) -> Option<u32> {
    let digits = s.strip_prefix(letter)?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

fn parse_words(c: &mut Cur) -> Result<Stmt, String> {
    let line = c.line;
    let mut w = Words {
        g: Vec::new(),
        m: Vec::new(),
        cip: false,
        diamof: false,
        axes: Vec::new(),
        i1: None,
        k1: None,
        f: None,
        s: None,
    };
    while !c.at_end() {
        if c.pos > 0 && !c.toks[c.pos].spaced {
            return Err(err(line, "address words must be separated by a space"));
        }
        let Some(Tok::Ident(word)) = c.next().cloned() else {
            return Err(err(line, "address word expected"));
        };
        if c.is_sym("=") {
            c.pos += 1;
            let v = parse_value(c)?;
            match word.as_str() {
                "F" if w.f.is_none() => w.f = Some(v),
                "S" if w.s.is_none() => w.s = Some(v),
                "I1" if w.i1.is_none() => w.i1 = Some(v),
                "K1" if w.k1.is_none() => w.k1 = Some(v),
                a if AXES.contains(&a) => {
                    if w.axes.iter().any(|(x, _)| x == a) {
                        return Err(err(line, format!("axis {a} written twice")));
                    }
                    w.axes.push((a.to_string(), v));
                }
                _ if r_index(&word).is_some() => {
                    return Err(err(
                        line,
                        "an R assignment must not share a block with other words",
                    ))
                }
                _ => {
                    return Err(err(
                        line,
                        format!("`{word}=` is outside the 840D subset or repeated"),
                    ))
                }
            }
            continue;
        }
        if let Some(n) = code_number(&word, 'G') {
            w.g.push(n);
        } else if let Some(n) = code_number(&word, 'M') {
            w.m.push((word.clone(), n));
        } else if word == "CIP" {
            w.cip = true;
        } else if word == "DIAMOF" {
            w.diamof = true;
        } else {
            return Err(err(line, format!("`{word}` is outside the 840D subset")));
        }
    }
    Ok(Stmt::Words(Box::new(w)))
}

fn parse_block(line: usize, toks: &[Lexeme]) -> Result<Stmt, String> {
    let mut c = Cur { toks, pos: 0, line };
    let first = match c.peek() {
        Some(Tok::Ident(s)) => s.clone(),
        _ => return Err(err(line, "a block must start with a word")),
    };
    match first.as_str() {
        "IF" => {
            c.pos += 1;
            let a = parse_expr(&mut c)?;
            let cmp = parse_cmp(&mut c)?;
            let b = parse_expr(&mut c)?;
            if !c.at_end() {
                return Err(err(line, "IF takes one comparison of two R expressions"));
            }
            Ok(Stmt::If(a, cmp, b))
        }
        "ELSE" | "ENDIF" => {
            c.pos += 1;
            if !c.at_end() {
                return Err(err(line, format!("{first} must stand alone")));
            }
            Ok(if first == "ELSE" {
                Stmt::Else
            } else {
                Stmt::EndIf
            })
        }
        _ if matches!(toks.get(1).map(|l| &l.tok), Some(Tok::Sym("("))) => {
            c.pos += 1;
            parse_call(line, &first, &mut c)
        }
        _ if r_index(&first).is_some() => {
            let mut assigns = Vec::new();
            while !c.at_end() {
                if c.pos > 0 && !c.toks[c.pos].spaced {
                    return Err(err(line, "assignments must be separated by a space"));
                }
                let n = match c.next() {
                    Some(Tok::Ident(s)) => r_index(s),
                    _ => None,
                };
                let Some(n) = n else {
                    return Err(err(
                        line,
                        "only R assignments may share a block with an R assignment",
                    ));
                };
                c.expect_sym("=")?;
                assigns.push((n, parse_expr(&mut c)?));
            }
            Ok(Stmt::Assign(assigns))
        }
        _ => parse_words(&mut c),
    }
}

/// Strips an optional block number `N<digits>` followed by a space or the end.
fn strip_block_number(line: usize, code: &str) -> Result<&str, String> {
    let t = code.trim_start_matches([' ', '\t']);
    if let Some(rest) = t.strip_prefix('N') {
        let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
        if digits > 0 {
            let after = &rest[digits..];
            if after.is_empty() || after.starts_with([' ', '\t']) {
                return Ok(after);
            }
            return Err(err(line, "block number must be followed by a space"));
        }
    }
    Ok(t)
}

/// Parses the whole text: header lines, blocks, the IF structure, and the end code as the last
/// block (DIALECTS.md "Branches": an IF without its ENDIF, an ENDIF or ELSE without an IF, a
/// second ELSE, or anything but an assignment inside is refused).
pub(crate) fn parse_program(text: &str) -> Result<Program, String> {
    let mut lines = text.split('\n').map(|l| l.strip_suffix('\r').unwrap_or(l));
    let first = lines.next().unwrap_or("");
    let name = first
        .strip_prefix("%_N_")
        .and_then(|r| r.strip_suffix("_MPF"))
        .ok_or_else(|| err(1, "first line must be %_N_{NAME}_MPF"))?;
    if !check_name(name) {
        return Err(err(
            1,
            format!("program name `{name}` breaks the 840D name rule"),
        ));
    }
    if lines.next() != Some(";$PATH=/_N_MPF_DIR") {
        return Err(err(2, "second line must be ;$PATH=/_N_MPF_DIR"));
    }
    // (inside the else branch yet?) per open IF
    let mut ifs: Vec<(usize, bool)> = Vec::new();
    let mut blocks = Vec::new();
    let mut ended: Option<usize> = None;
    for (i, raw) in lines.enumerate() {
        let line = i + 3;
        if let Some(c) = raw.chars().find(|c| !(' '..='~').contains(c) && *c != '\t') {
            return Err(err(line, format!("character {c:?} is not printable ASCII")));
        }
        let code = strip_block_number(line, split_comment(raw))?;
        let toks = lex(line, code)?;
        if toks.is_empty() {
            continue;
        }
        if let Some(end) = ended {
            return Err(err(
                line,
                format!("a block after the end of the program (line {end})"),
            ));
        }
        let stmt = parse_block(line, &toks)?;
        match &stmt {
            Stmt::If(..) => ifs.push((line, false)),
            Stmt::Else => match ifs.last_mut() {
                Some((_, seen)) if !*seen => *seen = true,
                Some(_) => return Err(err(line, "a second ELSE in one IF")),
                None => return Err(err(line, "ELSE without IF")),
            },
            Stmt::EndIf => {
                ifs.pop().ok_or_else(|| err(line, "ENDIF without IF"))?;
            }
            Stmt::Assign(_) => {}
            _ if !ifs.is_empty() => {
                return Err(err(
                    line,
                    "only R-parameter assignments may stand inside IF … ENDIF",
                ))
            }
            Stmt::Words(w) if w.m.iter().any(|(_, n)| *n == 2 || *n == 30) => ended = Some(line),
            _ => {}
        }
        blocks.push((line, stmt));
    }
    if let Some((line, _)) = ifs.last() {
        return Err(err(*line, "IF without ENDIF"));
    }
    if ended.is_none() {
        return Err(err(
            text.lines().count(),
            "the program has no end code M2/M30",
        ));
    }
    Ok(Program {
        name: name.to_string(),
        blocks,
    })
}

// ---------------------------------------------------------------------------------------------
// Execution
// ---------------------------------------------------------------------------------------------

fn eval(line: usize, e: &Expr, r: &BTreeMap<u32, f64>) -> Result<f64, String> {
    let v = match e {
        Expr::Num(v) => *v,
        Expr::R(n) => r.get(n).copied().unwrap_or(0.0),
        Expr::Neg(a) => -eval(line, a, r)?,
        Expr::Trunc(a) => eval(line, a, r)?.trunc(),
        Expr::Bin(op, a, b) => {
            let (x, y) = (eval(line, a, r)?, eval(line, b, r)?);
            match op {
                Op::Add => x + y,
                Op::Sub => x - y,
                Op::Mul => x * y,
                Op::Div | Op::Mod if y == 0.0 => return Err(err(line, "division by zero")),
                Op::Div => x / y,
                // Remainder with the sign of the dividend (truncating division).
                Op::Mod => x % y,
            }
        }
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(line, "arithmetic overflow"))
    }
}

/// The modal state of a run.
#[derive(Debug, Clone, PartialEq)]
struct State {
    metric: bool,
    diamof: bool,
    offset: bool,
    /// `Some(true)` G90, `Some(false)` G91.
    absolute: Option<bool>,
    per_minute: bool,
    feed: Option<f64>,
    pos: BTreeMap<String, f64>,
    /// Defined gearboxes: following axis → leading axes.
    defined: BTreeMap<String, Vec<String>>,
    /// Following axes whose gearbox is on.
    on: Vec<String>,
}

/// Frame of an IF being executed: whether its enclosing code runs, the condition, else seen.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Frame {
    parent: bool,
    cond: bool,
    in_else: bool,
}

impl Frame {
    fn active(self) -> bool {
        self.parent && (self.cond != self.in_else)
    }
}

fn execute(p: &Program, r_init: &[(u32, f64)]) -> Result<AxisRun, String> {
    let mut r: BTreeMap<u32, f64> = r_init.iter().copied().collect();
    let mut st = State {
        metric: false,
        diamof: false,
        offset: false,
        absolute: None,
        per_minute: false,
        feed: None,
        pos: BTreeMap::new(),
        defined: BTreeMap::new(),
        on: Vec::new(),
    };
    let mut frames: Vec<Frame> = Vec::new();
    let mut moves = Vec::new();
    let mut couplings = 0;
    for (line, stmt) in &p.blocks {
        let line = *line;
        let active = frames.last().is_none_or(|f| f.active());
        match stmt {
            Stmt::If(a, cmp, b) => {
                let cond = if active {
                    let (x, y) = (eval(line, a, &r)?, eval(line, b, &r)?);
                    match cmp {
                        Cmp::Eq => x == y,
                        Cmp::Ne => x != y,
                        Cmp::Lt => x < y,
                        Cmp::Le => x <= y,
                        Cmp::Gt => x > y,
                        Cmp::Ge => x >= y,
                    }
                } else {
                    false
                };
                frames.push(Frame {
                    parent: active,
                    cond,
                    in_else: false,
                });
            }
            Stmt::Else => {
                if let Some(f) = frames.last_mut() {
                    f.in_else = true;
                }
            }
            Stmt::EndIf => {
                frames.pop();
            }
            _ if !active => {}
            Stmt::Assign(list) => {
                for (n, e) in list {
                    let v = eval(line, e, &r)?;
                    r.insert(*n, v);
                }
            }
            Stmt::EgDef { following, leading } => {
                if st.defined.contains_key(following) {
                    return Err(err(
                        line,
                        format!(
                            "EGDEF: a gearbox for {following} is already defined (EGDEL first)"
                        ),
                    ));
                }
                st.defined.insert(following.clone(), leading.clone());
            }
            Stmt::EgOnSyne { following, leading } => {
                let Some(def) = st.defined.get(following) else {
                    return Err(err(line, format!("EGONSYNE: no EGDEF for {following}")));
                };
                let axes: Vec<&String> = leading.iter().map(|l| &l.axis).collect();
                if def.len() != axes.len() || def.iter().zip(&axes).any(|(a, b)| a != *b) {
                    return Err(err(
                        line,
                        format!("EGONSYNE: leading axes {axes:?} differ from EGDEF's {def:?}"),
                    ));
                }
                if st.on.contains(following) {
                    return Err(err(
                        line,
                        format!("EGONSYNE: the gearbox of {following} is already on"),
                    ));
                }
                st.on.push(following.clone());
                couplings += 1;
            }
            Stmt::EgOfs(following) => {
                if !st.defined.contains_key(following) {
                    return Err(err(
                        line,
                        format!("EGOFS: no gearbox defined for {following}"),
                    ));
                }
                st.on.retain(|a| a != following);
            }
            Stmt::EgDel(following) => {
                if st.on.contains(following) {
                    return Err(err(
                        line,
                        format!("EGDEL: the gearbox of {following} is still on (EGOFS first)"),
                    ));
                }
                if st.defined.remove(following).is_none() {
                    return Err(err(
                        line,
                        format!("EGDEL: no gearbox defined for {following}"),
                    ));
                }
            }
            Stmt::Msg(_) => {}
            Stmt::Words(w) => {
                if let Some(end) = words(line, w, &mut st, &r, &mut moves)? {
                    return Ok(AxisRun {
                        moves,
                        ended_by: end,
                        couplings,
                        r,
                    });
                }
            }
        }
    }
    // parse_program guarantees an end code; reaching here means it was in no executed block.
    Err(err(
        p.blocks.last().map_or(1, |b| b.0),
        "the program ran past its last block without M2/M30",
    ))
}

/// Executes one block of address words; returns the end code when the block ends the program.
fn words(
    line: usize,
    w: &Words,
    st: &mut State,
    r: &BTreeMap<u32, f64>,
    moves: &mut Vec<AxisMove>,
) -> Result<Option<String>, String> {
    // G codes: modal settings first, then the motion of the block.
    let mut motion: Option<u32> = None;
    let mut dwell = false;
    let mut distance: Option<bool> = None;
    for g in &w.g {
        match g {
            0 | 1 => {
                if motion.is_some() || w.cip {
                    return Err(err(line, "two motion codes in one block"));
                }
                motion = Some(*g);
            }
            4 => dwell = true,
            90 | 91 => {
                if distance.is_some() {
                    return Err(err(line, "G90 and G91 in one block"));
                }
                distance = Some(*g == 90);
            }
            94 => st.per_minute = true,
            71 => st.metric = true,
            54..=57 | 505..=599 => st.offset = true,
            _ => return Err(err(line, format!("G{g} is outside the 840D subset"))),
        }
    }
    if w.diamof {
        st.diamof = true;
    }
    if distance.is_some() {
        st.absolute = distance;
    }
    if dwell {
        let only_f = w.g.len() == 1
            && w.m.is_empty()
            && !w.cip
            && !w.diamof
            && w.axes.is_empty()
            && w.i1.is_none()
            && w.k1.is_none()
            && w.s.is_none();
        let Some(f) = w.f.as_ref().filter(|_| only_f) else {
            return Err(err(line, "G4 stands alone in its block with F= seconds"));
        };
        check_form(line, "dwell F", f, 3)?;
        let t = eval(line, &f.expr, r)?;
        if t <= 0.0 {
            return Err(err(line, "dwell time must be positive"));
        }
        moves.push(AxisMove {
            line,
            rapid: false,
            dwell_s: Some(t),
            feed: None,
            coupled: !st.on.is_empty(),
            to: st.pos.clone(),
        });
        return Ok(None);
    }
    if let Some(f) = &w.f {
        check_form(line, "feed F", f, 3)?;
        let v = eval(line, &f.expr, r)?;
        if v <= 0.0 {
            return Err(err(line, "feed must be positive"));
        }
        st.feed = Some(v);
    }
    if let Some(s) = &w.s {
        check_form(line, "speed S", s, 3)?;
        if eval(line, &s.expr, r)? < 0.0 {
            return Err(err(line, "negative spindle speed"));
        }
    }
    let is_motion = motion.is_some() || w.cip;
    if !w.axes.is_empty() && !is_motion {
        return Err(err(line, "axis words need G0, G1 or CIP in their block"));
    }
    if (w.i1.is_some() || w.k1.is_some()) && !w.cip {
        return Err(err(line, "I1/K1 only with CIP"));
    }
    if is_motion {
        if w.axes.is_empty() {
            return Err(err(line, "a motion code without an axis word"));
        }
        if !(st.metric && st.diamof && st.offset) {
            return Err(err(
                line,
                "a move before the set-up (G71, DIAMOF and the work offset)",
            ));
        }
        let Some(absolute) = st.absolute else {
            return Err(err(line, "a move before G90/G91"));
        };
        let start = st.pos.clone();
        let mut to = st.pos.clone();
        for (axis, v) in &w.axes {
            let max_dec = if ROTARY.contains(&axis.as_str()) {
                4
            } else {
                3
            };
            check_form(line, &format!("axis {axis}"), v, max_dec)?;
            let val = eval(line, &v.expr, r)?;
            let target = if absolute {
                val
            } else {
                match start.get(axis) {
                    Some(p) => p + val,
                    None => {
                        return Err(err(
                            line,
                            format!("G91 move of {axis} from an unknown position"),
                        ))
                    }
                }
            };
            if st.on.contains(axis) {
                return Err(err(
                    line,
                    format!("{axis} is the following axis of an active gearbox"),
                ));
            }
            to.insert(axis.clone(), target);
        }
        let rapid = motion == Some(0);
        if !rapid && !st.per_minute {
            return Err(err(line, "a feed move before G94"));
        }
        let feed = if rapid {
            None
        } else {
            match st.feed {
                Some(f) => Some(f),
                None => return Err(err(line, "a feed move without F")),
            }
        };
        if w.cip {
            cip_check(line, w, &start, &to, absolute, r)?;
        }
        st.pos = to.clone();
        moves.push(AxisMove {
            line,
            rapid,
            dwell_s: None,
            feed,
            coupled: !st.on.is_empty(),
            to,
        });
    }
    let ends: Vec<&(String, u32)> = w.m.iter().filter(|(_, n)| *n == 2 || *n == 30).collect();
    match ends.as_slice() {
        [] => Ok(None),
        [(text, _)] => Ok(Some(text.clone())),
        _ => Err(err(line, "two end codes in one block")),
    }
}

/// `CIP X=.. Z=.. I1=.. K1=..` (absolute, X–Z): the end axes only X and Z, the intermediate
/// point both I1 and K1, and the three points not on one line (else there is no circle).
fn cip_check(
    line: usize,
    w: &Words,
    start: &BTreeMap<String, f64>,
    to: &BTreeMap<String, f64>,
    absolute: bool,
    r: &BTreeMap<u32, f64>,
) -> Result<(), String> {
    if !absolute {
        return Err(err(line, "CIP is written with absolute (G90) points only"));
    }
    if w.axes.iter().any(|(a, _)| a != "X" && a != "Z") {
        return Err(err(line, "CIP moves X and Z only"));
    }
    let (Some(i1), Some(k1)) = (&w.i1, &w.k1) else {
        return Err(err(line, "CIP needs its intermediate point I1= K1="));
    };
    check_form(line, "I1", i1, 3)?;
    check_form(line, "K1", k1, 3)?;
    let (Some(x0), Some(z0)) = (start.get("X"), start.get("Z")) else {
        return Err(err(line, "CIP from an unknown X or Z"));
    };
    let (Some(x2), Some(z2)) = (to.get("X"), to.get("Z")) else {
        return Err(err(line, "CIP to an unknown X or Z"));
    };
    let (x1, z1) = (eval(line, &i1.expr, r)?, eval(line, &k1.expr, r)?);
    let cross = (x1 - x0) * (z2 - z0) - (z1 - z0) * (x2 - x0);
    let scale = ((x2 - x0).powi(2) + (z2 - z0).powi(2)).max((x1 - x0).powi(2) + (z1 - z0).powi(2));
    if scale == 0.0 || cross.abs() <= 1e-12 * scale {
        return Err(err(
            line,
            "CIP: start, intermediate and end point lie on one line",
        ));
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;

    const SPUR: &str = include_str!("../golden/spur_840d.H01.nc");
    const SPUR_BY_PART: &str = include_str!("../golden/spur_by_part_840d.H01.nc");
    const HELICAL: &str = include_str!("../golden/helical_840d.H01.nc");
    const HELICAL_LEFT: &str = include_str!("../golden/helical_left_840d.H01.nc");
    const HELICAL_CLIMB: &str = include_str!("../golden/helical_climb_840d.H01.nc");
    const HELICAL_CLIMB_FANUC: &str = include_str!("../golden/helical_climb_fanuc.H01.nc");
    const HELICAL_SHIFT_FANUC: &str = include_str!("../golden/helical_shift_fanuc.H01.nc");
    const CONICAL: &str = include_str!("../golden/conical_840d.H01.nc");
    const CROWNED: &str = include_str!("../golden/crowned_840d.H01.nc");
    const CROWNED_PARABOLIC: &str = include_str!("../golden/crowned_parabolic_840d.H01.nc");
    const MULTI_CUT_SHIFT: &str = include_str!("../golden/multi_cut_shift_840d.H01.nc");
    const MULTI_GEAR: &str = include_str!("../golden/multi_gear_840d.H01.nc");
    const WORM_WHEEL: &str = include_str!("../golden/worm_wheel_840d.H01.nc");
    const WORM_WHEEL_TANGENTIAL: &str = include_str!("../golden/worm_wheel_tangential_840d.H01.nc");

    const GOLDEN: &[(&str, &str)] = &[
        ("conical_840d.H01.nc", CONICAL),
        ("crowned_840d.H01.nc", CROWNED),
        ("crowned_parabolic_840d.H01.nc", CROWNED_PARABOLIC),
        ("helical_840d.H01.nc", HELICAL),
        ("helical_climb_840d.H01.nc", HELICAL_CLIMB),
        ("helical_climb_fanuc.H01.nc", HELICAL_CLIMB_FANUC),
        ("helical_left_840d.H01.nc", HELICAL_LEFT),
        ("helical_shift_fanuc.H01.nc", HELICAL_SHIFT_FANUC),
        ("multi_cut_shift_840d.H01.nc", MULTI_CUT_SHIFT),
        ("multi_gear_840d.H01.nc", MULTI_GEAR),
        ("spur_840d.H01.nc", SPUR),
        ("spur_by_part_840d.H01.nc", SPUR_BY_PART),
        ("worm_wheel_840d.H01.nc", WORM_WHEEL),
        ("worm_wheel_tangential_840d.H01.nc", WORM_WHEEL_TANGENTIAL),
    ];

    fn axes(pairs: &[(&str, f64)]) -> BTreeMap<String, f64> {
        pairs.iter().map(|(a, v)| (a.to_string(), *v)).collect()
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    const TINY: &str = "%_N_TINY_1_MPF
;$PATH=/_N_MPF_DIR
; A HAND-MADE PROGRAM
N10 G71 G90 G94 DIAMOF
N20 G54
N30 R1=2.5
N40 R2=R1*4-(7 MOD 3) ; 10 - 1 = 9
N50 IF R2>8
N60 R3=TRUNC(R2/4) ; 2
N70 ELSE
N80 R3=-1
N90 ENDIF
N100 IF R2<>9
N110 R9=1
N120 ENDIF
N130 G0 G90 X=100.0 Z=50.0
N140 G0 X=R3*10+0.5 ; 20.5
N150 EGDEF(C,B,1)
N160 EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25)
N170 M3 S=100.0
N180 G1 G94 Z=40.0 F=12.5
N190 G91 G1 Z=-5.0
N200 G4 F=1.5
N210 G90 CIP X=20.5 Z=25.0 I1=22.0 K1=30.0 F=10.0
N220 M5
N230 EGOFS(C)
N240 EGDEL(C)
N250 G0 X=100.0 A=-1.25
N260 MSG(\"DONE; OK\")
N270 R4=R4+1
N280 M30 ; END
; TRAILING COMMENT
";

    #[test]
    fn tiny_program_exact_moves() {
        let run = run_840d(TINY, &[(4, 6.0)]).expect("tiny program runs");
        let expected = vec![
            AxisMove {
                line: 16,
                rapid: true,
                dwell_s: None,
                feed: None,
                coupled: false,
                to: axes(&[("X", 100.0), ("Z", 50.0)]),
            },
            AxisMove {
                line: 17,
                rapid: true,
                dwell_s: None,
                feed: None,
                coupled: false,
                to: axes(&[("X", 20.5), ("Z", 50.0)]),
            },
            AxisMove {
                line: 21,
                rapid: false,
                dwell_s: None,
                feed: Some(12.5),
                coupled: true,
                to: axes(&[("X", 20.5), ("Z", 40.0)]),
            },
            AxisMove {
                line: 22,
                rapid: false,
                dwell_s: None,
                feed: Some(12.5),
                coupled: true,
                to: axes(&[("X", 20.5), ("Z", 35.0)]),
            },
            AxisMove {
                line: 23,
                rapid: false,
                dwell_s: Some(1.5),
                feed: None,
                coupled: true,
                to: axes(&[("X", 20.5), ("Z", 35.0)]),
            },
            AxisMove {
                line: 24,
                rapid: false,
                dwell_s: None,
                feed: Some(10.0),
                coupled: true,
                to: axes(&[("X", 20.5), ("Z", 25.0)]),
            },
            AxisMove {
                line: 28,
                rapid: true,
                dwell_s: None,
                feed: None,
                coupled: false,
                to: axes(&[("A", -1.25), ("X", 100.0), ("Z", 25.0)]),
            },
        ];
        assert_eq!(run.moves, expected);
        assert_eq!(run.ended_by, "M30");
        assert_eq!(run.couplings, 1);
        let r: BTreeMap<u32, f64> = [(1, 2.5), (2, 9.0), (3, 2.0), (4, 7.0)]
            .into_iter()
            .collect();
        assert_eq!(run.r, r, "R9 is never set: R2<>9 is false");
    }

    #[test]
    fn else_branch_taken() {
        let text = TINY.replace("N50 IF R2>8", "N50 IF R2>=9.5");
        let run = run_840d(&text, &[]).expect("runs");
        assert_eq!(run.moves[1].to["X"], -9.5);
        assert_eq!(run.r[&3], -1.0);
        assert_eq!(run.r[&4], 1.0, "R4 starts at 0 without r_init");
    }

    fn refused(text: &str, line: usize, what: &str) {
        match run_840d(text, &[]) {
            Ok(_) => panic!("accepted, expected refusal at line {line} ({what})"),
            Err(e) => assert!(e.starts_with(&format!("line {line}:")), "{what}: got `{e}`"),
        }
    }

    #[test]
    fn refusals_name_the_line() {
        refused(
            &TINY.replace("N20 G54", "N20 G54 G95"),
            5,
            "G95 feed per revolution",
        );
        refused(
            &TINY.replace("N60 R3=TRUNC(R2/4) ; 2", "N60 M7"),
            9,
            "M code inside IF",
        );
        refused(
            &TINY.replace("N90 ENDIF\n", ""),
            15,
            "a move inside IF (its ENDIF missing)",
        );
        refused(
            &TINY.replace("N280 M30 ; END", "N280 IF R4>0\nN281 R4=0"),
            31,
            "IF without ENDIF",
        );
        refused(
            &TINY.replace("N120 ENDIF", "N120 ELSE\nN121 ELSE\nN122 ENDIF"),
            16,
            "second ELSE",
        );
        refused(
            &TINY.replace("N280 M30 ; END", "N280 M5"),
            32,
            "no end code",
        );
        refused(
            &TINY.replace("; TRAILING COMMENT", "N290 M9"),
            32,
            "block after the end",
        );
        refused(
            &TINY.replace("B,0,1,25)", "B,0,1)"),
            19,
            "EGONSYNE leading axis with 3 arguments",
        );
        refused(&TINY.replace("(7 MOD 3)", "(7 MOD 0)"), 7, "MOD by zero");
        refused(&TINY.replace(" F=12.5", ""), 21, "G1 without feed");
        refused(
            &TINY.replace("Z=40.0", "Z=40"),
            21,
            "length without decimal point",
        );
        refused(
            &TINY.replace("A=-1.25", "A=-1.12345"),
            28,
            "angle with 5 decimals",
        );
        refused(&TINY.replace("N130 G0", "N130 g0"), 16, "lower case");
        refused(
            &TINY.replace("N20 G54\n", ""),
            15,
            "move before the work offset",
        );
        refused(&TINY.replace("I1=22.0", "I1=20.5"), 24, "collinear CIP");
        refused(
            &TINY.replace("N240 EGDEL(C)", "N240 GOTOF ENDE"),
            27,
            "GOTOF",
        );
        refused(&TINY.replace("N230 EGOFS(C)\n", ""), 26, "EGDEL while on");
        refused(
            &TINY.replace("%_N_TINY_1_MPF", "%_N_1TINY_MPF"),
            1,
            "name starts with a digit",
        );
        refused(
            &TINY.replace(";$PATH=/_N_MPF_DIR", "; PATH"),
            2,
            "missing path line",
        );
        refused(
            &TINY.replace("N140 G0 X=", "N140 X="),
            17,
            "axis word without motion code",
        );
        refused(
            &TINY.replace("N200 G4 F=1.5", "N200 G4 F=1.5 X=3.0"),
            23,
            "G4 with an axis",
        );
    }

    /// The blocks of the DIALECTS.md "Siemens SINUMERIK 840D" example, verbatim where they are
    /// complete (its block numbers repeat; the example's `CIP X=..` placeholder line is left
    /// out), with the shift data of the multi-cut golden program.
    const DIALECTS_EXAMPLE: &str = "%_N_SP_2002_MPF
;$PATH=/_N_MPF_DIR
; free comment text
N10 G71 G90 G94 DIAMOF
N20 G54
N30 G0 G90 X=300.0
N40 G0 G90 Z=350.0
N50 G0 G90 A=-12.6284
N60 G0 G90 Z=154.278
N70 G0 G90 X=173.75
N20 M10 ; FIXTURE CLAMP
N50 R1=3.0 ; NORMAL MODULE MN, MM
N51 R20=-21.738
N52 R22=9.433
N53 R23=4
N54 R24=5
N150 IF R25>=R23*R24
N160 R25=0
N170 ENDIF
N180 R26=TRUNC(R25/R23)
N160 EGDEF(C,B,1,Y,1)
N170 EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25,Y,0,1.526579,1)
N180 M3 S=358.099 ; HOB ON, RPM
N190 G0 G90 X=82.5 Y=R20+R22*(R26 MOD R24)
N200 G1 G90 G94 X=74.05 F=7.162
N215 G4 F=2.0 ; DWELL, S
N250 EGOFS(C)
N280 M9 ; COOLANT OFF FOR THE HOB CHANGE
N290 MSG(\"CHANGE HOB TO HOB-M2-70\")
N300 M0 ; STOP FOR THE HOB CHANGE
N340 EGDEL(C)
N350 R25=R25+1
N390 M2 ; END OF PROGRAM
";

    #[test]
    fn dialects_md_example_runs() {
        let run = run_840d(DIALECTS_EXAMPLE, &[(25, 13.0)]).expect("the documented example runs");
        assert_eq!(run.moves.len(), 8);
        assert_eq!(
            run.moves[4].to,
            axes(&[("A", -12.6284), ("X", 173.75), ("Z", 154.278)])
        );
        // R26 = TRUNC(13/4) = 3; Y = -21.738 + 9.433 * (3 MOD 5) = 6.561
        let shift = &run.moves[5];
        assert!(shift.rapid && shift.coupled);
        assert!(
            close(shift.to["Y"], 6.561) && shift.to["X"] == 82.5,
            "{:?}",
            shift.to
        );
        assert_eq!(
            (run.moves[6].feed, run.moves[6].to["X"]),
            (Some(7.162), 74.05)
        );
        assert_eq!((run.moves[7].dwell_s, run.moves[7].feed), (Some(2.0), None));
        assert_eq!((run.ended_by.as_str(), run.couplings), ("M2", 1));
        assert_eq!((run.r[&25], run.r[&26]), (14.0, 3.0));
    }

    /// The retract position: X of the first move that sets X, Z of the first that sets Z.
    fn retract(run: &AxisRun) -> (f64, f64) {
        let x = run
            .moves
            .iter()
            .find_map(|m| m.to.get("X").copied())
            .unwrap_or(f64::NAN);
        let z = run
            .moves
            .iter()
            .find_map(|m| m.to.get("Z").copied())
            .unwrap_or(f64::NAN);
        (x, z)
    }

    fn motion(run: &AxisRun) -> Vec<&AxisMove> {
        run.moves.iter().filter(|m| m.dwell_s.is_none()).collect()
    }

    #[test]
    fn every_golden_program_runs_to_its_end() {
        // (file, motion blocks, dwells, couplings), counted by hand from the golden text
        let expect: &[(&str, usize, usize, usize)] = &[
            ("conical_840d.H01.nc", 12, 0, 1),
            ("crowned_840d.H01.nc", 12, 0, 1),
            ("crowned_parabolic_840d.H01.nc", 19, 0, 1),
            ("helical_840d.H01.nc", 10, 0, 1),
            ("helical_climb_840d.H01.nc", 10, 0, 1),
            ("helical_climb_fanuc.H01.nc", 10, 0, 1),
            ("helical_left_840d.H01.nc", 10, 0, 1),
            ("helical_shift_fanuc.H01.nc", 15, 0, 1),
            ("multi_cut_shift_840d.H01.nc", 17, 0, 1),
            ("multi_gear_840d.H01.nc", 19, 0, 2),
            ("spur_840d.H01.nc", 10, 0, 1),
            ("spur_by_part_840d.H01.nc", 10, 0, 1),
            ("worm_wheel_840d.H01.nc", 10, 1, 1),
            ("worm_wheel_tangential_840d.H01.nc", 11, 0, 1),
        ];
        for (name, text) in GOLDEN {
            let run = run_840d(text, &[]).unwrap_or_else(|e| panic!("{name}: {e}"));
            let mv = motion(&run);
            let dwells = run.moves.len() - mv.len();
            let (first, last) = (mv[0], mv[mv.len() - 1]);
            let (rx, rz) = retract(&run);
            let at_retract = close(last.to["X"], rx) && close(last.to["Z"], rz);
            println!(
                "{name}: {} motion blocks, {dwells} dwell(s), couplings {}, first line {} {:?}, last line {} {:?} (coupled {}), retract X={rx} Z={rz}, ends there: {at_retract}, {}",
                mv.len(),
                run.couplings,
                first.line,
                first.to,
                last.line,
                last.to,
                last.coupled,
                run.ended_by
            );
            let e = expect
                .iter()
                .find(|e| e.0 == *name)
                .unwrap_or_else(|| panic!("{name} expected"));
            assert_eq!((mv.len(), dwells, run.couplings), (e.1, e.2, e.3), "{name}");
            assert_eq!(run.ended_by, "M2", "{name}");
            // Every program starts with the radial retract to X=300 alone, then Z=350 alone.
            assert_eq!(first.to, axes(&[("X", 300.0)]), "{name}");
            assert!(first.rapid && !first.coupled, "{name}");
            assert_eq!(mv[1].to, axes(&[("X", 300.0), ("Z", 350.0)]), "{name}");
            assert_eq!((rx, rz), (300.0, 350.0), "{name}");
            // The last motion is a rapid back up to Z=350 at X=300: the retract position.
            assert!(last.rapid && at_retract, "{name}: ends at {:?}", last.to);
            assert_eq!(last.to.get("Z"), Some(&350.0), "{name}");
            // Every feed move is coupled (the gearbox is on before depth).
            for m in &mv {
                if !m.rapid {
                    assert!(
                        m.coupled && m.feed.is_some_and(|f| f > 0.0),
                        "{name} line {}",
                        m.line
                    );
                }
            }
        }
    }

    #[test]
    fn spur_moves_exactly() {
        let run = run_840d(SPUR, &[]).expect("spur runs");
        let lines: Vec<usize> = run.moves.iter().map(|m| m.line).collect();
        assert_eq!(lines, vec![22, 23, 24, 25, 26, 41, 43, 45, 48, 49]);
        assert_eq!(
            run.moves[2].to,
            axes(&[("A", 2.3715), ("X", 300.0), ("Z", 350.0)])
        );
        assert_eq!(
            run.moves[4].to,
            axes(&[("A", 2.3715), ("X", 173.75), ("Z", 154.278)])
        );
        let cut = &run.moves[6];
        assert_eq!(
            (cut.rapid, cut.feed, cut.coupled),
            (false, Some(28.634), true)
        );
        assert_eq!(cut.to, axes(&[("A", 2.3715), ("X", 73.75), ("Z", 75.722)]));
        assert!(run.moves[9].coupled, "EGOFS comes after the return to A");
        let r: BTreeMap<u32, f64> = [(1, 3.0), (2, 25.0), (3, 0.0), (4, 1.0), (5, 2.3715)]
            .into_iter()
            .collect();
        assert_eq!(run.r, r);
    }

    #[test]
    fn crowned_cip_records_the_end_point() {
        let run = run_840d(CROWNED, &[]).expect("runs");
        let arc = run.moves.iter().find(|m| m.line == 46).expect("CIP block");
        assert_eq!(arc.to, axes(&[("A", 2.3715), ("X", 81.23), ("Z", 100.0)]));
        assert_eq!(
            (arc.rapid, arc.feed, arc.coupled),
            (false, Some(19.099), true)
        );
    }

    #[test]
    fn worm_wheel_dwell() {
        let run = run_840d(WORM_WHEEL, &[]).expect("runs");
        let d = run
            .moves
            .iter()
            .find(|m| m.dwell_s.is_some())
            .expect("dwell");
        assert_eq!((d.line, d.dwell_s, d.coupled), (46, Some(15.08), true));
        assert_eq!(d.to, axes(&[("A", 0.0), ("X", 96.301), ("Z", 82.5)]));
    }

    #[test]
    fn worm_wheel_tangential_feeds_along_y_and_stays_shifted() {
        let run = run_840d(WORM_WHEEL_TANGENTIAL, &[]).expect("runs");
        let y: Vec<(usize, f64)> = run
            .moves
            .iter()
            .filter(|m| m.to.contains_key("Y"))
            .map(|m| (m.line, m.to["Y"]))
            .collect();
        assert_eq!(
            y.first(),
            Some(&(42, -80.384)),
            "Y first set at the tangential start"
        );
        let feed = run.moves.iter().find(|m| !m.rapid).expect("feed move");
        assert_eq!(
            (feed.line, feed.feed, feed.to["Y"], feed.to["X"]),
            (46, Some(7.958), 78.384, 96.301)
        );
        // The return to A moves X and Z only: the hob ends shifted to the tangential end.
        assert_eq!(run.moves.last().map(|m| m.to["Y"]), Some(78.384));
    }

    #[test]
    fn multi_gear_couples_each_unit_once() {
        let run = run_840d(MULTI_GEAR, &[]).expect("runs");
        assert_eq!(run.couplings, 2);
        // The hob change between the units happens uncoupled, at X=300 Z=350.
        let change: Vec<&AxisMove> = run
            .moves
            .iter()
            .filter(|m| (58..=62).contains(&m.line))
            .collect();
        assert!(change.iter().all(|m| !m.coupled));
        assert_eq!(run.r[&2], 18.0, "second unit's teeth");
    }

    fn shift_y(run: &AxisRun) -> Vec<f64> {
        run.moves
            .iter()
            .filter_map(|m| m.to.get("Y").copied())
            .collect()
    }

    #[test]
    fn multi_cut_part_counter_rolls_over() {
        // R20=-21.738 R22=9.433 R23=4 parts per step R24=5 positions: R23*R24 = 20 parts.
        let fresh = run_840d(MULTI_CUT_SHIFT, &[]).expect("runs");
        assert!(shift_y(&fresh).iter().all(|y| close(*y, -21.738)));
        assert_eq!(fresh.r[&25], 1.0);
        assert_eq!(fresh.r[&26], 0.0);

        let seventh = run_840d(MULTI_CUT_SHIFT, &[(25, 7.0)]).expect("runs");
        assert_eq!(seventh.r[&26], 1.0);
        assert!(shift_y(&seventh).iter().all(|y| close(*y, -21.738 + 9.433)));

        let last = run_840d(MULTI_CUT_SHIFT, &[(25, 19.0)]).expect("runs");
        assert_eq!((last.r[&25], last.r[&26]), (20.0, 4.0));
        let y = shift_y(&last);
        assert!(y.iter().all(|y| close(*y, -21.738 + 4.0 * 9.433)), "{y:?}");

        for counter in [20.0, 23.0] {
            let rolled = run_840d(MULTI_CUT_SHIFT, &[(25, counter)]).expect("runs");
            assert_eq!(
                (rolled.r[&25], rolled.r[&26]),
                (1.0, 0.0),
                "R25={counter} rolls over"
            );
            assert_eq!(shift_y(&rolled), shift_y(&fresh));
            assert_eq!(rolled.moves.len(), fresh.moves.len());
        }
        // Only the shift position differs between runs: the other axes are the same.
        for (a, b) in fresh.moves.iter().zip(&last.moves) {
            let strip = |m: &AxisMove| {
                let mut t = m.to.clone();
                t.remove("Y");
                t
            };
            assert_eq!(strip(a), strip(b), "line {}", a.line);
        }
    }

    #[test]
    fn helical_shift_counter_per_three_parts() {
        // R23=3, R24=5: 15 parts before the counter starts again.
        let run = run_840d(HELICAL_SHIFT_FANUC, &[(25, 14.0)]).expect("runs");
        assert!(shift_y(&run)
            .iter()
            .all(|y| close(*y, -21.738 + 4.0 * 9.433)));
        let rolled = run_840d(HELICAL_SHIFT_FANUC, &[(25, 15.0)]).expect("runs");
        assert!(shift_y(&rolled).iter().all(|y| close(*y, -21.738)));
        assert_eq!(rolled.r[&25], 1.0);
    }
}
