//! Number literals and the parameter arithmetic of both dialects: 840D
//! R-parameter expressions (`R20+R22*(R26 MOD R24)`, `TRUNC(R25/R23)`) and
//! FANUC macro expressions (`#520+#522*#527`, `FIX[#525/#523]`, `[ ]`).
//!
//! An expression is compiled once, when its line is parsed, into postfix
//! tokens; evaluating it walks them with a fixed-size stack, so evaluation
//! never allocates. Nesting is bounded ([`MAX_NESTING`]) so that no input can
//! exhaust the parser's stack.

/// Deepest nesting of brackets and functions an expression may have.
pub const MAX_NESTING: usize = 16;

/// Most tokens one expression may compile to.
const MAX_TOKENS: usize = 256;

/// Evaluation stack size; [`MAX_NESTING`] bounds the depth to far less.
const STACK: usize = 64;

/// Number of parameters, indexed by their own number: 840D `R0`–`R999`,
/// FANUC retained common variables `#500`–`#999`.
pub const PARAMS: usize = 1000;

/// A byte cursor over one program line.
#[derive(Debug, Clone)]
pub(crate) struct Cursor<'a> {
    s: &'a [u8],
    pub(crate) i: usize,
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(s: &'a str) -> Self {
        Cursor {
            s: s.as_bytes(),
            i: 0,
        }
    }

    pub(crate) fn peek(&self) -> Option<u8> {
        self.s.get(self.i).copied()
    }

    pub(crate) fn peek_at(&self, ahead: usize) -> Option<u8> {
        self.s.get(self.i + ahead).copied()
    }

    pub(crate) fn bump(&mut self) {
        if self.i < self.s.len() {
            self.i += 1;
        }
    }

    pub(crate) fn at_end(&self) -> bool {
        self.i >= self.s.len()
    }

    /// Consumes `b` if it is next.
    pub(crate) fn eat(&mut self, b: u8) -> bool {
        if self.peek() == Some(b) {
            self.i += 1;
            true
        } else {
            false
        }
    }

    /// Consumes `word` if the input continues with it.
    pub(crate) fn eat_str(&mut self, word: &str) -> bool {
        let w = word.as_bytes();
        if self.s.len() >= self.i + w.len() && &self.s[self.i..self.i + w.len()] == w {
            self.i += w.len();
            true
        } else {
            false
        }
    }

    /// Consumes `word` if it is next and not followed by a letter or digit.
    pub(crate) fn eat_keyword(&mut self, word: &str) -> bool {
        let start = self.i;
        if self.eat_str(word) && !self.peek().is_some_and(|b| b.is_ascii_alphanumeric()) {
            true
        } else {
            self.i = start;
            false
        }
    }

    /// Skips spaces and tabs; true if any were skipped.
    pub(crate) fn skip_spaces(&mut self) -> bool {
        let start = self.i;
        while matches!(self.peek(), Some(b' ' | b'\t')) {
            self.i += 1;
        }
        self.i > start
    }

    /// A run of ASCII digits (possibly empty).
    pub(crate) fn digits(&mut self) -> &'a [u8] {
        let start = self.i;
        while self.peek().is_some_and(|b| b.is_ascii_digit()) {
            self.i += 1;
        }
        &self.s[start..self.i]
    }

    /// A run of identifier characters `A-Z a-z 0-9 _` (possibly empty).
    pub(crate) fn ident(&mut self) -> &'a [u8] {
        let start = self.i;
        while self
            .peek()
            .is_some_and(|b| b.is_ascii_alphanumeric() || b == b'_')
        {
            self.i += 1;
        }
        &self.s[start..self.i]
    }

    /// The text from `from` to the cursor.
    pub(crate) fn since(&self, from: usize) -> &'a [u8] {
        &self.s[from.min(self.i)..self.i]
    }
}

/// An unsigned integer of 1 to 9 ASCII digits; anything else is `None`.
pub(crate) fn small_uint(digits: &[u8]) -> Option<u32> {
    if digits.is_empty() || digits.len() > 9 || !digits.iter().all(u8::is_ascii_digit) {
        return None;
    }
    Some(
        digits
            .iter()
            .fold(0u32, |n, d| n * 10 + u32::from(d - b'0')),
    )
}

/// A number as written in the program: its value, how many decimals it had
/// and whether it had a decimal point (`12.0` has one; the count `25` not).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Num {
    /// The value.
    pub value: f64,
    /// Digits after the decimal point.
    pub decimals: u8,
    /// True when a decimal point was written.
    pub point: bool,
}

impl Num {
    /// The value as an integer, when it was written without a decimal point.
    pub fn integer(&self) -> Option<i64> {
        if self.point || self.value.abs() > 1e15 {
            None
        } else {
            Some(self.value as i64)
        }
    }
}

/// A signed decimal literal, `-?d+(.d+)?`, at the cursor. At most 15 digits
/// before and 9 after the point.
pub(crate) fn number(c: &mut Cursor<'_>) -> Option<Num> {
    let start = c.i;
    let neg = match c.peek() {
        Some(b'-') => {
            c.bump();
            true
        }
        Some(b'+') => {
            c.bump();
            false
        }
        _ => false,
    };
    let int = c.digits();
    if int.is_empty() || int.len() > 15 {
        c.i = start;
        return None;
    }
    let mut value = int
        .iter()
        .fold(0.0f64, |n, d| n * 10.0 + f64::from(d - b'0'));
    let mut decimals = 0u8;
    let mut point = false;
    if c.peek() == Some(b'.') && c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) {
        c.bump();
        point = true;
        let frac = c.digits();
        if frac.len() > 9 {
            c.i = start;
            return None;
        }
        decimals = frac.len() as u8;
        let f = frac
            .iter()
            .fold(0.0f64, |n, d| n * 10.0 + f64::from(d - b'0'));
        value += f / 10f64.powi(i32::from(decimals));
    }
    if neg {
        value = -value;
    }
    Some(Num {
        value,
        decimals,
        point,
    })
}

/// The two expression syntaxes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Syntax {
    /// 840D: `R<n>`, `( )`, `TRUNC( )`, `MOD`.
    Siemens,
    /// FANUC: `#5nn`, `[ ]`, `FIX[ ]`.
    Fanuc,
}

/// One postfix token.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tok {
    Num(f64),
    Var(u16),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Trunc,
}

/// A compiled parameter expression.
#[derive(Debug, Clone, PartialEq)]
pub struct NcExpr {
    toks: Box<[Tok]>,
}

/// Why an expression could not be evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EvalError {
    /// Division (or `MOD`) by zero.
    DivisionByZero,
    /// The result is not a finite number.
    NotFinite,
}

impl std::fmt::Display for EvalError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EvalError::DivisionByZero => f.write_str("it divides by zero"),
            EvalError::NotFinite => f.write_str("its value is not a finite number"),
        }
    }
}

impl NcExpr {
    /// Evaluates with the parameter values `vars` (`R0`… or `#500`…).
    pub fn eval(&self, vars: &[f64; PARAMS]) -> Result<f64, EvalError> {
        let mut stack = [0.0f64; STACK];
        let mut n = 0usize;
        for t in self.toks.iter() {
            match *t {
                Tok::Num(_) | Tok::Var(_) if n >= STACK => return Err(EvalError::NotFinite),
                Tok::Num(v) => {
                    stack[n] = v;
                    n += 1;
                }
                Tok::Var(i) => {
                    stack[n] = vars.get(usize::from(i)).copied().unwrap_or(0.0);
                    n += 1;
                }
                Tok::Neg | Tok::Trunc => {
                    let Some(top) = n.checked_sub(1) else {
                        return Err(EvalError::NotFinite);
                    };
                    stack[top] = if *t == Tok::Neg {
                        -stack[top]
                    } else {
                        stack[top].trunc()
                    };
                }
                Tok::Add | Tok::Sub | Tok::Mul | Tok::Div | Tok::Mod => {
                    if n < 2 {
                        return Err(EvalError::NotFinite);
                    }
                    let (a, b) = (stack[n - 2], stack[n - 1]);
                    n -= 1;
                    stack[n - 1] = match t {
                        Tok::Add => a + b,
                        Tok::Sub => a - b,
                        Tok::Mul => a * b,
                        Tok::Div if b == 0.0 => return Err(EvalError::DivisionByZero),
                        Tok::Div => a / b,
                        _ if b == 0.0 => return Err(EvalError::DivisionByZero),
                        _ => a % b,
                    };
                }
            }
        }
        match (n, stack[0]) {
            (1, v) if v.is_finite() => Ok(v),
            _ => Err(EvalError::NotFinite),
        }
    }
}

/// A word's value: a literal or an expression.
#[derive(Debug, Clone, PartialEq)]
pub enum NcValue {
    /// A literal number.
    Num(Num),
    /// A parameter expression.
    Expr(NcExpr),
}

impl Default for NcValue {
    fn default() -> Self {
        NcValue::Num(Num::default())
    }
}

impl NcValue {
    /// The value with the parameters `vars`.
    pub fn eval(&self, vars: &[f64; PARAMS]) -> Result<f64, EvalError> {
        match self {
            NcValue::Num(n) => Ok(n.value),
            NcValue::Expr(e) => e.eval(vars),
        }
    }

    /// The literal, when the value is one.
    pub fn literal(&self) -> Option<Num> {
        match self {
            NcValue::Num(n) => Some(*n),
            NcValue::Expr(_) => None,
        }
    }
}

/// A comparison of an `IF` (840D `==` `<>` `<` `<=` `>` `>=`, FANUC `EQ` `NE`
/// `LT` `LE` `GT` `GE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rel {
    /// Equal.
    Eq,
    /// Not equal.
    Ne,
    /// Less than.
    Lt,
    /// Less than or equal.
    Le,
    /// Greater than.
    Gt,
    /// Greater than or equal.
    Ge,
}

/// The condition of an `IF`: two expressions compared.
#[derive(Debug, Clone, PartialEq)]
pub struct Cond {
    /// Left-hand side.
    pub left: NcValue,
    /// The comparison.
    pub rel: Rel,
    /// Right-hand side.
    pub right: NcValue,
}

impl Cond {
    /// True when the comparison holds with the parameters `vars`.
    pub fn eval(&self, vars: &[f64; PARAMS]) -> Result<bool, EvalError> {
        let (a, b) = (self.left.eval(vars)?, self.right.eval(vars)?);
        Ok(match self.rel {
            Rel::Eq => a == b,
            Rel::Ne => a != b,
            Rel::Lt => a < b,
            Rel::Le => a <= b,
            Rel::Gt => a > b,
            Rel::Ge => a >= b,
        })
    }
}

/// Compiles a condition at the cursor: 840D `R25>=R23*R24`, FANUC
/// `#525 GE #523*#524` (the contents of its `[ ]`).
pub(crate) fn condition(c: &mut Cursor<'_>, syntax: Syntax) -> Result<Cond, &'static str> {
    let left = expression(c, syntax)?;
    let spaced = c.skip_spaces();
    let rel = match syntax {
        Syntax::Siemens => {
            let two = [c.peek(), c.peek_at(1)];
            let (rel, len) = match two {
                [Some(b'='), Some(b'=')] => (Rel::Eq, 2),
                [Some(b'<'), Some(b'>')] => (Rel::Ne, 2),
                [Some(b'<'), Some(b'=')] => (Rel::Le, 2),
                [Some(b'>'), Some(b'=')] => (Rel::Ge, 2),
                [Some(b'<'), _] => (Rel::Lt, 1),
                [Some(b'>'), _] => (Rel::Gt, 1),
                _ => return Err("a comparison (== <> < <= > >=) is expected"),
            };
            c.i += len;
            rel
        }
        Syntax::Fanuc => {
            let words = [
                ("EQ", Rel::Eq),
                ("NE", Rel::Ne),
                ("LT", Rel::Lt),
                ("LE", Rel::Le),
                ("GT", Rel::Gt),
                ("GE", Rel::Ge),
            ];
            match words.iter().find(|(w, _)| spaced && c.eat_keyword(w)) {
                Some((_, rel)) => *rel,
                None => return Err("a comparison (EQ NE LT LE GT GE, between spaces) is expected"),
            }
        }
    };
    if !c.skip_spaces() && syntax == Syntax::Fanuc {
        return Err("a space is expected after the comparison");
    }
    let right = expression(c, syntax)?;
    Ok(Cond { left, rel, right })
}

/// Compiles an expression at the cursor. It ends before the first character
/// that cannot continue it (840D: spaces end it unless an operator follows).
/// A lone literal comes back as [`NcValue::Num`].
pub(crate) fn expression(c: &mut Cursor<'_>, syntax: Syntax) -> Result<NcValue, &'static str> {
    if let Some(n) = lone_literal(c, syntax) {
        return Ok(NcValue::Num(n));
    }
    let mut p = Compiler {
        syntax,
        out: Vec::new(),
        depth: 0,
        literal: None,
    };
    p.expr(c)?;
    Ok(p.finish())
}

/// Compiles one operand at the cursor: a literal, a parameter, a bracketed
/// expression or a function (the form of a FANUC address value, `X#501`,
/// `Y[#520+#522*#527]`).
pub(crate) fn operand(c: &mut Cursor<'_>, syntax: Syntax) -> Result<NcValue, &'static str> {
    if let Some(n) = number(c) {
        return Ok(NcValue::Num(n));
    }
    let mut p = Compiler {
        syntax,
        out: Vec::new(),
        depth: 0,
        literal: None,
    };
    p.factor(c)?;
    Ok(p.finish())
}

/// A literal at the cursor that no operator continues (the common case, read
/// without compiling anything). The cursor stays put otherwise.
fn lone_literal(c: &mut Cursor<'_>, syntax: Syntax) -> Option<Num> {
    let start = c.i;
    let n = number(c)?;
    let end = c.i;
    c.skip_spaces();
    let continues = match c.peek() {
        Some(b'+' | b'-' | b'*' | b'/') => true,
        Some(b'M') => syntax == Syntax::Siemens && c.i > end && c.eat_keyword("MOD"),
        _ => false,
    };
    c.i = if continues { start } else { end };
    (!continues).then_some(n)
}

struct Compiler {
    syntax: Syntax,
    out: Vec<Tok>,
    depth: usize,
    /// The last literal read, to return a lone literal as such.
    literal: Option<Num>,
}

impl Compiler {
    /// The compiled value; a lone literal stays a literal.
    fn finish(self) -> NcValue {
        match (self.out.as_slice(), self.literal) {
            ([Tok::Num(_)], Some(n)) => NcValue::Num(n),
            _ => NcValue::Expr(NcExpr {
                toks: self.out.into_boxed_slice(),
            }),
        }
    }

    fn push(&mut self, t: Tok) -> Result<(), &'static str> {
        if self.out.len() >= MAX_TOKENS {
            return Err("the expression is too long");
        }
        self.out.push(t);
        Ok(())
    }

    /// Skips spaces only if an operator follows them (840D); FANUC bracket
    /// contents may not hold spaces at all in our subset, but are tolerated.
    fn operator(&self, c: &mut Cursor<'_>, ops: &[&str]) -> Option<usize> {
        let start = c.i;
        c.skip_spaces();
        for (k, op) in ops.iter().enumerate() {
            let ok = match op.as_bytes() {
                [one] => c.eat(*one),
                // A keyword operator needs a space before it and ends at a non-letter.
                _ => c.i > start && c.eat_keyword(op),
            };
            if ok {
                c.skip_spaces();
                return Some(k);
            }
        }
        c.i = start;
        None
    }

    fn expr(&mut self, c: &mut Cursor<'_>) -> Result<(), &'static str> {
        self.term(c)?;
        while let Some(k) = self.operator(c, &["+", "-"]) {
            self.term(c)?;
            self.push(if k == 0 { Tok::Add } else { Tok::Sub })?;
        }
        Ok(())
    }

    fn term(&mut self, c: &mut Cursor<'_>) -> Result<(), &'static str> {
        self.factor(c)?;
        let ops: &[&str] = match self.syntax {
            Syntax::Siemens => &["*", "/", "MOD"],
            Syntax::Fanuc => &["*", "/"],
        };
        while let Some(k) = self.operator(c, ops) {
            self.factor(c)?;
            self.push([Tok::Mul, Tok::Div, Tok::Mod][k])?;
        }
        Ok(())
    }

    fn factor(&mut self, c: &mut Cursor<'_>) -> Result<(), &'static str> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err("the expression is nested too deeply");
        }
        let r = self.factor_inner(c);
        self.depth -= 1;
        r
    }

    fn factor_inner(&mut self, c: &mut Cursor<'_>) -> Result<(), &'static str> {
        let (open, close, func) = match self.syntax {
            Syntax::Siemens => (b'(', b')', "TRUNC("),
            Syntax::Fanuc => (b'[', b']', "FIX["),
        };
        match c.peek() {
            Some(b'-') if !c.peek_at(1).is_some_and(|b| b.is_ascii_digit()) => {
                c.bump();
                self.factor(c)?;
                self.push(Tok::Neg)
            }
            Some(b'-' | b'0'..=b'9') => {
                let n = number(c).ok_or("a number is malformed")?;
                self.literal = Some(n);
                self.push(Tok::Num(n.value))
            }
            Some(b) if b == open => {
                c.bump();
                self.group(c, close)
            }
            Some(b'R') if self.syntax == Syntax::Siemens => {
                c.bump();
                let i = param_index(c.digits()).ok_or("an R parameter is not R0 to R999")?;
                self.push(Tok::Var(i))
            }
            Some(b'#') if self.syntax == Syntax::Fanuc => {
                c.bump();
                let i = macro_index(c.digits()).ok_or("a macro variable is not #500 to #999")?;
                self.push(Tok::Var(i))
            }
            _ if c.eat_str(func) => {
                self.group(c, close)?;
                self.push(Tok::Trunc)
            }
            _ => Err("an operand is missing or unknown"),
        }
    }

    fn group(&mut self, c: &mut Cursor<'_>, close: u8) -> Result<(), &'static str> {
        c.skip_spaces();
        self.expr(c)?;
        c.skip_spaces();
        if c.eat(close) {
            Ok(())
        } else {
            Err("a bracket is not closed")
        }
    }
}

/// `R<n>` number from its digits: 0–999.
pub(crate) fn param_index(digits: &[u8]) -> Option<u16> {
    match small_uint(digits) {
        Some(n) if n < PARAMS as u32 && digits.len() <= 3 => u16::try_from(n).ok(),
        _ => None,
    }
}

/// `#n` number from its digits: the retained common variables 500–999 (the
/// part counter must survive a power cycle, so #100–#199 are not offered).
pub(crate) fn macro_index(digits: &[u8]) -> Option<u16> {
    match small_uint(digits) {
        Some(n) if (500..1000).contains(&n) && digits.len() == 3 => u16::try_from(n).ok(),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eval(text: &str, syntax: Syntax, vars: &[f64; PARAMS]) -> Result<f64, EvalError> {
        let mut c = Cursor::new(text);
        let v = expression(&mut c, syntax).unwrap();
        assert!(c.at_end(), "{text}: stopped at {}", c.i);
        v.eval(vars)
    }

    #[test]
    fn siemens_shift_expression_with_mod_and_trunc() {
        let mut r = [0.0; PARAMS];
        r[20] = -26.738;
        r[22] = 9.433;
        r[23] = 4.0;
        r[24] = 6.0;
        r[25] = 27.0;
        // R26 = TRUNC(27/4) = 6; 6 MOD 6 = 0 → the start again.
        r[26] = eval("TRUNC(R25/R23)", Syntax::Siemens, &r).unwrap();
        assert_eq!(r[26], 6.0);
        let y = eval("R20+R22*(R26 MOD R24)", Syntax::Siemens, &r).unwrap();
        assert!((y + 26.738).abs() < 1e-12);
        r[25] = 9.0;
        r[26] = eval("TRUNC(R25/R23)", Syntax::Siemens, &r).unwrap();
        let y = eval("R20+R22*(R26 MOD R24)", Syntax::Siemens, &r).unwrap();
        assert!((y - (-26.738 + 2.0 * 9.433)).abs() < 1e-12);
    }

    #[test]
    fn precedence_unary_minus_and_fanuc_brackets() {
        let mut v = [0.0; PARAMS];
        // FANUC variables are indexed by their own number.
        v[525] = 9.0;
        v[523] = 4.0;
        assert_eq!(eval("1+2*3-4/2", Syntax::Siemens, &v), Ok(5.0));
        assert_eq!(eval("-(1+2)*-2", Syntax::Siemens, &v), Ok(6.0));
        assert_eq!(eval("FIX[#525/#523]", Syntax::Fanuc, &v), Ok(2.0));
        assert_eq!(eval("[1+2]*[3-1]", Syntax::Fanuc, &v), Ok(6.0));
        assert_eq!(eval("FIX[-7.5]", Syntax::Fanuc, &v), Ok(-7.0));
        assert_eq!(
            eval("R1/R2", Syntax::Siemens, &v),
            Err(EvalError::DivisionByZero)
        );
    }

    #[test]
    fn a_space_ends_the_expression_unless_an_operator_follows() {
        let mut c = Cursor::new("R1 Z=2.0");
        let v = expression(&mut c, Syntax::Siemens).unwrap();
        assert!(matches!(v, NcValue::Expr(_)));
        assert_eq!(c.i, 2);
        let mut c = Cursor::new("-26.738 ;");
        assert_eq!(
            expression(&mut c, Syntax::Siemens).unwrap(),
            NcValue::Num(Num {
                value: -26.738,
                decimals: 3,
                point: true
            })
        );
    }

    #[test]
    fn malformed_expressions_are_refused() {
        for bad in [
            "R1000", "(1+2", "TRUNC(1", "1+", "#499", "#1000", "MOD 2", "--",
        ] {
            let mut c = Cursor::new(bad);
            let syntax = if bad.starts_with('#') {
                Syntax::Fanuc
            } else {
                Syntax::Siemens
            };
            assert!(expression(&mut c, syntax).is_err(), "{bad}");
        }
        let deep = format!("{}1{}", "(".repeat(100), ")".repeat(100));
        assert!(expression(&mut Cursor::new(&deep), Syntax::Siemens).is_err());
    }
}
