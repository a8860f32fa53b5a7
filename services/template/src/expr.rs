//! The template expression language (docs/programs.md#standard-templates): small, safe, bounded.
//!
//! Arithmetic (`+ - * / %`), comparison (`== != < <= > >=`), boolean (`and or
//! not`), string concatenation (`+` of two strings), parentheses, literals
//! (`1.5`, `"text"`, `true`, `false`, `null`), parameters and variables by
//! (dotted) name (`m.x`, `ax.radial`, `R22`), and the functions below. No loops,
//! no assignment inside expressions, no I/O: an expression is a tree evaluated
//! once, and every evaluation counts its steps against a budget.
//!
//! | function | result |
//! |---|---|
//! | `nc(v)` | NC number, 3 decimals (mm, mm/min, rpm, s): `12.0`, `-3.125` |
//! | `deg(v)` | NC number, 4 decimals (angles) |
//! | `factor(v)` | NC number, 6 decimals (gearbox coupling factors) |
//! | `int(v)` | `v` rounded to an integer (written without a decimal point) |
//! | `abs sqrt trunc round` | as usual |
//! | `sin cos tan` | of an angle in degrees |
//! | `min(a, b)` `max(a, b)` | as usual |
//! | `has(v)` | `v` is not `null` |
//! | `if(c, a, b)` | `a` when `c`, else `b` (only the chosen branch is evaluated) |
//! | `upper(s)` | `s` in upper case |
//! | `text(v)` | a string, or an integer written without a decimal point, as text |
//! | `comment(s)` | free text made safe for an NC comment |
//! | `N()` | the next block number: `N10`, `N20`, ... |
//!
//! Numbers are written into NC text only through `nc`, `deg`, `factor` or as
//! integers: an output parameter that is a number with a fraction is an error,
//! so no template can print `12.300000000000001`.
//!
//! Compilation resolves every name to a slot once ([`compile`]); evaluation reads
//! slots by index, so a program of a hundred lines instantiates in microseconds.

use std::fmt;
use std::sync::Arc;

/// A value: number, string, boolean or null (a parameter the model does not set,
/// e.g. the Z of a move that only moves X).
#[derive(Debug, Clone, PartialEq, Default)]
pub enum TplValue {
    /// No value.
    #[default]
    Null,
    /// A number.
    Num(f64),
    /// Text.
    Str(Arc<str>),
    /// A truth value.
    Bool(bool),
}

impl TplValue {
    fn type_name(&self) -> &'static str {
        match self {
            TplValue::Null => "null",
            TplValue::Num(_) => "number",
            TplValue::Str(_) => "string",
            TplValue::Bool(_) => "boolean",
        }
    }
}

impl From<f64> for TplValue {
    fn from(v: f64) -> Self {
        TplValue::Num(v)
    }
}
impl From<i32> for TplValue {
    fn from(v: i32) -> Self {
        TplValue::Num(f64::from(v))
    }
}
impl From<u32> for TplValue {
    fn from(v: u32) -> Self {
        TplValue::Num(f64::from(v))
    }
}
impl From<u16> for TplValue {
    fn from(v: u16) -> Self {
        TplValue::Num(f64::from(v))
    }
}
impl From<bool> for TplValue {
    fn from(v: bool) -> Self {
        TplValue::Bool(v)
    }
}
impl From<&str> for TplValue {
    fn from(v: &str) -> Self {
        TplValue::Str(Arc::from(v))
    }
}
impl From<String> for TplValue {
    fn from(v: String) -> Self {
        TplValue::Str(Arc::from(v))
    }
}
impl From<Option<f64>> for TplValue {
    fn from(v: Option<f64>) -> Self {
        v.map_or(TplValue::Null, TplValue::Num)
    }
}

impl fmt::Display for TplValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TplValue::Null => f.write_str("null"),
            TplValue::Num(v) => write!(f, "{v}"),
            TplValue::Str(s) => write!(f, "{s:?}"),
            TplValue::Bool(b) => write!(f, "{b}"),
        }
    }
}

/// An expression that cannot be compiled: where and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("at column {column} of `{source_text}`: expected {expected}, got {got}")]
pub struct CompileError {
    /// The expression's text.
    pub source_text: String,
    /// 1-based column.
    pub column: usize,
    /// What was expected there.
    pub expected: String,
    /// What was found.
    pub got: String,
}

/// An evaluation that failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum EvalError {
    /// An operation on values of the wrong type, or a value that cannot be written.
    #[error("{0}")]
    Type(String),
    /// The step budget is spent.
    #[error("the evaluation budget of {0} steps is spent")]
    Budget(u64),
}

/// Evaluation state of one instantiation: the step budget and the block counter.
#[derive(Debug, Clone)]
pub struct EvalState {
    /// Steps left.
    pub steps_left: u64,
    budget: u64,
    /// The last block number given by `N()`.
    pub block: u32,
    /// What `P(n)` writes: the parameter letter (`R`, `#`) and the number of
    /// slot 1 (the machine profile's free block).
    pub params: (&'static str, u32),
}

impl EvalState {
    /// A state with `budget` steps.
    pub fn new(budget: u64) -> Self {
        EvalState {
            steps_left: budget,
            budget,
            block: 0,
            params: ("R", 1),
        }
    }

    fn step(&mut self) -> Result<(), EvalError> {
        if self.steps_left == 0 {
            return Err(EvalError::Budget(self.budget));
        }
        self.steps_left -= 1;
        Ok(())
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    And,
    Or,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Func {
    Nc,
    Deg,
    Factor,
    Int,
    Abs,
    Sqrt,
    Trunc,
    Round,
    Sin,
    Cos,
    Tan,
    Min,
    Max,
    Has,
    If,
    Upper,
    Text,
    Comment,
    Block,
    Param,
}

impl Func {
    fn lookup(name: &str) -> Option<(Func, usize)> {
        Some(match name {
            "nc" => (Func::Nc, 1),
            "deg" => (Func::Deg, 1),
            "factor" => (Func::Factor, 1),
            "int" => (Func::Int, 1),
            "abs" => (Func::Abs, 1),
            "sqrt" => (Func::Sqrt, 1),
            "trunc" => (Func::Trunc, 1),
            "round" => (Func::Round, 1),
            "sin" => (Func::Sin, 1),
            "cos" => (Func::Cos, 1),
            "tan" => (Func::Tan, 1),
            "min" => (Func::Min, 2),
            "max" => (Func::Max, 2),
            "has" => (Func::Has, 1),
            "if" => (Func::If, 3),
            "upper" => (Func::Upper, 1),
            "text" => (Func::Text, 1),
            "comment" => (Func::Comment, 1),
            "N" => (Func::Block, 0),
            "P" => (Func::Param, 1),
            _ => return None,
        })
    }
}

/// A compiled expression.
#[derive(Debug, Clone, PartialEq)]
pub enum TplExpr {
    /// A constant.
    Const(TplValue),
    /// A parameter or variable slot, with its name for messages.
    Slot(usize, Arc<str>),
    /// `-e`.
    Neg(Box<TplExpr>),
    /// `not e`.
    Not(Box<TplExpr>),
    /// A binary operation.
    Bin(BinOpBox),
    /// A function call.
    Call(FuncBox),
}

/// Boxed binary node (keeps [`TplExpr`] small).
#[derive(Debug, Clone, PartialEq)]
pub struct BinOpBox(Box<(BinOp, TplExpr, TplExpr)>);

/// Boxed call node.
#[derive(Debug, Clone, PartialEq)]
pub struct FuncBox(Box<(Func, Vec<TplExpr>)>);

/// Compiles `text`; `resolve` gives the slot of a name or `None` when the name
/// is unknown.
pub fn compile(
    text: &str,
    resolve: &mut dyn FnMut(&str) -> Option<usize>,
) -> Result<TplExpr, CompileError> {
    let mut p = Parser {
        text,
        b: text.as_bytes(),
        pos: 0,
        resolve,
    };
    let e = p.or()?;
    p.ws();
    if p.pos < p.b.len() {
        return Err(p.err("an operator or the end of the expression"));
    }
    Ok(e)
}

struct Parser<'a, 'r> {
    text: &'a str,
    b: &'a [u8],
    pos: usize,
    resolve: &'r mut dyn FnMut(&str) -> Option<usize>,
}

impl Parser<'_, '_> {
    fn err(&self, expected: &str) -> CompileError {
        let got = if self.pos >= self.b.len() {
            "the end".to_string()
        } else {
            format!("`{}`", &self.text[self.pos..])
        };
        CompileError {
            source_text: self.text.to_string(),
            column: self.pos + 1,
            expected: expected.to_string(),
            got,
        }
    }

    fn ws(&mut self) {
        while self.pos < self.b.len() && self.b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn eat(&mut self, s: &str) -> bool {
        self.ws();
        if self.text[self.pos..].starts_with(s) {
            self.pos += s.len();
            true
        } else {
            false
        }
    }

    fn eat_word(&mut self, w: &str) -> bool {
        self.ws();
        let rest = &self.text[self.pos..];
        if rest.starts_with(w)
            && !rest[w.len()..]
                .bytes()
                .next()
                .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_' || c == b'.')
        {
            self.pos += w.len();
            true
        } else {
            false
        }
    }

    fn or(&mut self) -> Result<TplExpr, CompileError> {
        let mut l = self.and()?;
        while self.eat_word("or") {
            let r = self.and()?;
            l = bin(BinOp::Or, l, r);
        }
        Ok(l)
    }

    fn and(&mut self) -> Result<TplExpr, CompileError> {
        let mut l = self.not()?;
        while self.eat_word("and") {
            let r = self.not()?;
            l = bin(BinOp::And, l, r);
        }
        Ok(l)
    }

    fn not(&mut self) -> Result<TplExpr, CompileError> {
        if self.eat_word("not") {
            return Ok(TplExpr::Not(Box::new(self.not()?)));
        }
        self.cmp()
    }

    fn cmp(&mut self) -> Result<TplExpr, CompileError> {
        let l = self.add()?;
        for (s, op) in [
            ("==", BinOp::Eq),
            ("!=", BinOp::Ne),
            ("<=", BinOp::Le),
            (">=", BinOp::Ge),
            ("<", BinOp::Lt),
            (">", BinOp::Gt),
        ] {
            if self.eat(s) {
                let r = self.add()?;
                return Ok(bin(op, l, r));
            }
        }
        Ok(l)
    }

    fn add(&mut self) -> Result<TplExpr, CompileError> {
        let mut l = self.mul()?;
        loop {
            if self.eat("+") {
                let r = self.mul()?;
                l = bin(BinOp::Add, l, r);
            } else if self.eat("-") {
                let r = self.mul()?;
                l = bin(BinOp::Sub, l, r);
            } else {
                return Ok(l);
            }
        }
    }

    fn mul(&mut self) -> Result<TplExpr, CompileError> {
        let mut l = self.unary()?;
        loop {
            if self.eat("*") {
                let r = self.unary()?;
                l = bin(BinOp::Mul, l, r);
            } else if self.eat("/") {
                let r = self.unary()?;
                l = bin(BinOp::Div, l, r);
            } else if self.eat("%") {
                let r = self.unary()?;
                l = bin(BinOp::Rem, l, r);
            } else {
                return Ok(l);
            }
        }
    }

    fn unary(&mut self) -> Result<TplExpr, CompileError> {
        if self.eat("-") {
            return Ok(TplExpr::Neg(Box::new(self.unary()?)));
        }
        self.primary()
    }

    fn primary(&mut self) -> Result<TplExpr, CompileError> {
        self.ws();
        let Some(&c) = self.b.get(self.pos) else {
            return Err(self.err("a value"));
        };
        if c == b'(' {
            self.pos += 1;
            let e = self.or()?;
            if !self.eat(")") {
                return Err(self.err("`)`"));
            }
            return Ok(e);
        }
        if c == b'"' {
            let start = self.pos + 1;
            let Some(len) = self.text[start..].find('"') else {
                return Err(self.err("a closing `\"`"));
            };
            self.pos = start + len + 1;
            return Ok(TplExpr::Const(TplValue::from(
                &self.text[start..start + len],
            )));
        }
        if c.is_ascii_digit() || c == b'.' {
            let start = self.pos;
            while self.pos < self.b.len()
                && (self.b[self.pos].is_ascii_digit() || self.b[self.pos] == b'.')
            {
                self.pos += 1;
            }
            let t = &self.text[start..self.pos];
            return t
                .parse::<f64>()
                .map(|v| TplExpr::Const(TplValue::Num(v)))
                .map_err(|_| {
                    self.pos = start;
                    self.err("a number")
                });
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = self.pos;
            while self.pos < self.b.len()
                && (self.b[self.pos].is_ascii_alphanumeric()
                    || self.b[self.pos] == b'_'
                    || self.b[self.pos] == b'.')
            {
                self.pos += 1;
            }
            let name = &self.text[start..self.pos];
            match name {
                "true" => return Ok(TplExpr::Const(TplValue::Bool(true))),
                "false" => return Ok(TplExpr::Const(TplValue::Bool(false))),
                "null" => return Ok(TplExpr::Const(TplValue::Null)),
                _ => {}
            }
            if self.eat("(") {
                let Some((func, arity)) = Func::lookup(name) else {
                    self.pos = start;
                    return Err(self.err("a known function (nc, deg, factor, int, abs, sqrt, trunc, round, sin, cos, tan, min, max, has, if, upper, text, comment, N)"));
                };
                let mut args = Vec::new();
                if !self.eat(")") {
                    loop {
                        args.push(self.or()?);
                        if self.eat(")") {
                            break;
                        }
                        if !self.eat(",") {
                            return Err(self.err("`,` or `)`"));
                        }
                    }
                }
                if args.len() != arity {
                    self.pos = start;
                    return Err(self.err(&format!(
                        "{arity} argument(s) for {name}(), not {}",
                        args.len()
                    )));
                }
                return Ok(TplExpr::Call(FuncBox(Box::new((func, args)))));
            }
            let Some(slot) = (self.resolve)(name) else {
                self.pos = start;
                return Err(self.err("a known parameter or a variable set by an earlier calc:"));
            };
            return Ok(TplExpr::Slot(slot, Arc::from(name)));
        }
        Err(self.err("a value"))
    }
}

fn bin(op: BinOp, l: TplExpr, r: TplExpr) -> TplExpr {
    TplExpr::Bin(BinOpBox(Box::new((op, l, r))))
}

fn num(v: &TplValue, what: &str) -> Result<f64, EvalError> {
    match v {
        TplValue::Num(x) => Ok(*x),
        other => Err(EvalError::Type(format!(
            "{what} needs a number, got {} {other}",
            other.type_name()
        ))),
    }
}

fn truth(v: &TplValue, what: &str) -> Result<bool, EvalError> {
    match v {
        TplValue::Bool(b) => Ok(*b),
        other => Err(EvalError::Type(format!(
            "{what} needs true or false, got {} {other}",
            other.type_name()
        ))),
    }
}

fn fixed(v: &TplValue, decimals: usize, name: &str) -> Result<TplValue, EvalError> {
    let x = num(v, name)?;
    let mut s = String::with_capacity(16);
    if push_fixed(&mut s, x, decimals) {
        Ok(TplValue::from(s))
    } else {
        Err(EvalError::Type(format!("{name}() cannot write {x}")))
    }
}

pub use gearcam_nc::number::push_fixed;

impl TplExpr {
    /// Evaluates against the slot values `vars`.
    pub fn eval(&self, vars: &[TplValue], st: &mut EvalState) -> Result<TplValue, EvalError> {
        st.step()?;
        match self {
            TplExpr::Const(v) => Ok(v.clone()),
            TplExpr::Slot(i, _) => Ok(vars.get(*i).cloned().unwrap_or(TplValue::Null)),
            TplExpr::Neg(e) => Ok(TplValue::Num(-num(&e.eval(vars, st)?, "`-`")?)),
            TplExpr::Not(e) => Ok(TplValue::Bool(!truth(&e.eval(vars, st)?, "`not`")?)),
            TplExpr::Bin(b) => {
                let (op, l, r) = &*b.0;
                match op {
                    BinOp::And => {
                        if !truth(&l.eval(vars, st)?, "`and`")? {
                            return Ok(TplValue::Bool(false));
                        }
                        Ok(TplValue::Bool(truth(&r.eval(vars, st)?, "`and`")?))
                    }
                    BinOp::Or => {
                        if truth(&l.eval(vars, st)?, "`or`")? {
                            return Ok(TplValue::Bool(true));
                        }
                        Ok(TplValue::Bool(truth(&r.eval(vars, st)?, "`or`")?))
                    }
                    _ => {
                        let a = l.eval(vars, st)?;
                        let c = r.eval(vars, st)?;
                        binary(*op, &a, &c)
                    }
                }
            }
            TplExpr::Call(c) => {
                let (f, args) = &*c.0;
                call(*f, args, vars, st)
            }
        }
    }

    /// Evaluates an output parameter straight into NC text: string joins,
    /// number functions and `if` write into `out` without building the
    /// intermediate strings; anything else is evaluated and written by
    /// [`write_output`]. The text is the same as evaluating and writing.
    pub fn write_to(
        &self,
        vars: &[TplValue],
        st: &mut EvalState,
        out: &mut String,
    ) -> Result<(), EvalError> {
        match self {
            TplExpr::Const(TplValue::Str(s)) => {
                st.step()?;
                out.push_str(s);
                Ok(())
            }
            TplExpr::Bin(b) if b.0 .0 == BinOp::Add && self.is_text() => {
                st.step()?;
                let (_, l, r) = &*b.0;
                for side in [l, r] {
                    if side.is_text() {
                        side.write_to(vars, st, out)?;
                    } else {
                        match side.eval(vars, st)? {
                            TplValue::Str(s) => out.push_str(&s),
                            other => {
                                return Err(EvalError::Type(format!(
                                    "`+` joins two strings here, got {} {other} (write numbers with nc(), deg(), factor() or text())",
                                    other.type_name()
                                )))
                            }
                        }
                    }
                }
                Ok(())
            }
            TplExpr::Call(c) => {
                let (f, args) = &*c.0;
                let decimals = match f {
                    Func::Nc => 3,
                    Func::Deg => 4,
                    Func::Factor => 6,
                    Func::If => {
                        st.step()?;
                        let go = args[0].eval_bool(vars, st)?;
                        return args[if go { 1 } else { 2 }].write_to(vars, st, out);
                    }
                    _ => return write_output(out, &self.eval(vars, st)?),
                };
                st.step()?;
                let x = num(&args[0].eval(vars, st)?, "an NC number")?;
                if push_fixed(out, x, decimals) {
                    Ok(())
                } else {
                    Err(EvalError::Type(format!("cannot write {x} as an NC number")))
                }
            }
            _ => write_output(out, &self.eval(vars, st)?),
        }
    }

    /// True when the expression certainly gives text (a string constant, a text
    /// function, a join with text, an `if` between texts).
    fn is_text(&self) -> bool {
        match self {
            TplExpr::Const(TplValue::Str(_)) => true,
            TplExpr::Bin(b) => {
                let (op, l, r) = &*b.0;
                *op == BinOp::Add && (l.is_text() || r.is_text())
            }
            TplExpr::Call(c) => {
                let (f, args) = &*c.0;
                match f {
                    Func::Nc
                    | Func::Deg
                    | Func::Factor
                    | Func::Text
                    | Func::Upper
                    | Func::Comment
                    | Func::Block => true,
                    Func::If => args[1].is_text() && args[2].is_text(),
                    _ => false,
                }
            }
            _ => false,
        }
    }

    /// Evaluates a condition: must give true or false.
    pub fn eval_bool(&self, vars: &[TplValue], st: &mut EvalState) -> Result<bool, EvalError> {
        truth(&self.eval(vars, st)?, "a condition")
    }
}

fn binary(op: BinOp, a: &TplValue, b: &TplValue) -> Result<TplValue, EvalError> {
    use BinOp::*;
    match op {
        Add => match (a, b) {
            (TplValue::Num(x), TplValue::Num(y)) => Ok(TplValue::Num(x + y)),
            (TplValue::Str(x), TplValue::Str(y)) => {
                let mut s = String::with_capacity(x.len() + y.len());
                s.push_str(x);
                s.push_str(y);
                Ok(TplValue::from(s))
            }
            _ => Err(EvalError::Type(format!(
                "`+` adds two numbers or joins two strings, got {} {a} and {} {b} (write numbers with nc(), deg(), factor() or int())",
                a.type_name(),
                b.type_name()
            ))),
        },
        Sub | Mul | Div | Rem => {
            let (x, y) = (num(a, "arithmetic")?, num(b, "arithmetic")?);
            Ok(TplValue::Num(match op {
                Sub => x - y,
                Mul => x * y,
                Div => x / y,
                _ => x % y,
            }))
        }
        Eq => Ok(TplValue::Bool(a == b)),
        Ne => Ok(TplValue::Bool(a != b)),
        Lt | Le | Gt | Ge => {
            let (x, y) = (num(a, "a comparison")?, num(b, "a comparison")?);
            Ok(TplValue::Bool(match op {
                Lt => x < y,
                Le => x <= y,
                Gt => x > y,
                _ => x >= y,
            }))
        }
        And | Or => unreachable!("short-circuit operators are evaluated in TplExpr::eval"),
    }
}

fn call(
    f: Func,
    args: &[TplExpr],
    vars: &[TplValue],
    st: &mut EvalState,
) -> Result<TplValue, EvalError> {
    if f == Func::If {
        let c = args[0].eval_bool(vars, st)?;
        return args[if c { 1 } else { 2 }].eval(vars, st);
    }
    if f == Func::Block {
        st.block += 10;
        return Ok(TplValue::from(format!("N{}", st.block)));
    }
    let a = args[0].eval(vars, st)?;
    let math = |g: fn(f64) -> f64, name: &str| -> Result<TplValue, EvalError> {
        Ok(TplValue::Num(g(num(&a, name)?)))
    };
    match f {
        Func::Nc => fixed(&a, 3, "nc"),
        Func::Deg => fixed(&a, 4, "deg"),
        Func::Factor => fixed(&a, 6, "factor"),
        Func::Int => math(f64::round, "int"),
        Func::Abs => math(f64::abs, "abs"),
        Func::Sqrt => math(f64::sqrt, "sqrt"),
        Func::Trunc => math(f64::trunc, "trunc"),
        Func::Round => math(f64::round, "round"),
        Func::Sin => math(|d| d.to_radians().sin(), "sin"),
        Func::Cos => math(|d| d.to_radians().cos(), "cos"),
        Func::Tan => math(|d| d.to_radians().tan(), "tan"),
        Func::Min | Func::Max => {
            let x = num(&a, "min/max")?;
            let y = num(&args[1].eval(vars, st)?, "min/max")?;
            Ok(TplValue::Num(if f == Func::Min {
                x.min(y)
            } else {
                x.max(y)
            }))
        }
        Func::Has => Ok(TplValue::Bool(a != TplValue::Null)),
        Func::Upper => match &a {
            TplValue::Str(s) => Ok(TplValue::from(s.to_ascii_uppercase())),
            other => Err(EvalError::Type(format!(
                "upper() needs a string, got {} {other}",
                other.type_name()
            ))),
        },
        Func::Text => {
            let mut out = String::new();
            write_output(&mut out, &a)?;
            Ok(TplValue::from(out))
        }
        Func::Comment => Ok(TplValue::from(comment_text(&plain(&a)))),
        Func::Param => {
            // Slot n of the machine's free parameter block, as the dialect
            // writes it: P(25) is R25 on H01, #525 on H02.
            let n = num(&a, "P")?;
            if !(n >= 1.0
                && n <= f64::from(gearcam_proto::ParameterBlock::SLOTS)
                && n.fract() == 0.0)
            {
                return Err(EvalError::Type(format!(
                    "P() takes a parameter slot 1 to {}, got {n}",
                    gearcam_proto::ParameterBlock::SLOTS
                )));
            }
            let (letter, first) = st.params;
            Ok(TplValue::from(format!("{letter}{}", first + n as u32 - 1)))
        }
        Func::If | Func::Block => unreachable!("handled above"),
    }
}

/// A value as plain text for comments: strings bare, numbers as Rust prints them.
fn plain(v: &TplValue) -> String {
    match v {
        TplValue::Str(s) => s.to_string(),
        TplValue::Num(x) => x.to_string(),
        TplValue::Bool(b) => b.to_string(),
        TplValue::Null => String::new(),
    }
}

/// Appends a value to NC output: strings as they are, integral numbers without a
/// decimal point; anything else is an error (format it with `nc()` and friends).
pub fn write_output(out: &mut String, v: &TplValue) -> Result<(), EvalError> {
    match v {
        TplValue::Str(s) => {
            out.push_str(s);
            Ok(())
        }
        TplValue::Num(x) if x.fract() == 0.0 && x.abs() < 1e15 => {
            use std::fmt::Write;
            let _ = write!(out, "{}", *x as i64);
            Ok(())
        }
        other => Err(EvalError::Type(format!(
            "cannot write {} {other} into NC text (numbers with a fraction need nc(), deg() or factor())",
            other.type_name()
        ))),
    }
}

/// Free text made safe for an NC comment (840D `; ...`, FANUC `( ... )`): one
/// line of printable ASCII (control characters become spaces, other characters
/// `?`), parentheses as brackets (a FANUC comment cannot contain them), at most
/// 120 characters.
pub fn comment_text(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '(' => '[',
            ')' => ']',
            ' '..='~' => c,
            c if c.is_control() || c.is_whitespace() => ' ',
            _ => '?',
        })
        .take(120)
        .collect::<String>()
        .trim_end()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(text: &str, names: &[(&str, TplValue)]) -> Result<TplValue, String> {
        let mut resolve = |n: &str| names.iter().position(|(k, _)| *k == n);
        let e = compile(text, &mut resolve).map_err(|e| e.to_string())?;
        let vars: Vec<TplValue> = names.iter().map(|(_, v)| v.clone()).collect();
        e.eval(&vars, &mut EvalState::new(1000))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn arithmetic_comparison_and_logic() {
        let p = [("X1", TplValue::Num(74.05)), ("f1", TplValue::Num(100.0))];
        assert_eq!(run("X1 + f1", &p), Ok(TplValue::Num(174.05)));
        assert_eq!(run("2 + 3 * 4 - -1", &p), Ok(TplValue::Num(15.0)));
        assert_eq!(run("(2 + 3) * 4 / 5 % 3", &p), Ok(TplValue::Num(1.0)));
        assert_eq!(
            run("X1 > 70 and not (f1 == 3)", &p),
            Ok(TplValue::Bool(true))
        );
        assert_eq!(run("false or 1 <= 0", &p), Ok(TplValue::Bool(false)));
        // Short-circuit: the right side would be a type error.
        assert_eq!(run("false and 1", &p), Ok(TplValue::Bool(false)));
    }

    #[test]
    fn strings_and_nc_formatting() {
        let p = [("X", TplValue::Num(74.05)), ("Z", TplValue::Num(-0.00001))];
        // docs/programs.md#standard-templates: "G90 X" + X + " Z" + Z, with the numbers written as NC numbers.
        assert_eq!(
            run("\"G90 X\" + nc(X) + \" Z\" + nc(Z)", &p),
            Ok(TplValue::from("G90 X74.05 Z0.0"))
        );
        assert_eq!(run("deg(2.37154321)", &p), Ok(TplValue::from("2.3715")));
        assert_eq!(run("factor(1.5265789)", &p), Ok(TplValue::from("1.526579")));
        assert!(run("\"X\" + X", &p).unwrap_err().contains("nc()"));
    }

    #[test]
    fn functions() {
        let p = [("m.x", TplValue::Null), ("s", TplValue::from("a(b);c"))];
        assert_eq!(run("has(m.x)", &p), Ok(TplValue::Bool(false)));
        assert_eq!(
            run("if(has(m.x), nc(m.x), \"\")", &p),
            Ok(TplValue::from(""))
        );
        assert_eq!(run("upper(\"right\")", &p), Ok(TplValue::from("RIGHT")));
        assert_eq!(
            run("\"R26*\" + text(2) + text(s)", &p),
            Ok(TplValue::from("R26*2a(b);c"))
        );
        assert!(run("text(2.5)", &p).is_err());
        assert_eq!(run("int(2.6) + trunc(2.6)", &p), Ok(TplValue::Num(5.0)));
        assert_eq!(run("round(sin(30) * 1000)", &p), Ok(TplValue::Num(500.0)));
        assert_eq!(run("max(1, 2) + min(1, 2)", &p), Ok(TplValue::Num(3.0)));
    }

    #[test]
    fn compile_errors_name_the_column() {
        let e = run("1 +", &[]).unwrap_err();
        assert!(e.contains("column 4") && e.contains("a value"), "{e}");
        let e = run("nope + 1", &[]).unwrap_err();
        assert!(e.contains("known parameter"), "{e}");
        let e = run("exec(1)", &[]).unwrap_err();
        assert!(e.contains("known function"), "{e}");
        let e = run("nc(1, 2)", &[]).unwrap_err();
        assert!(e.contains("1 argument"), "{e}");
        let e = run("(1", &[]).unwrap_err();
        assert!(e.contains("`)`"), "{e}");
    }

    #[test]
    fn evaluation_is_bounded() {
        let mut resolve = |_: &str| None;
        let e = compile("1 + 1 + 1 + 1", &mut resolve).unwrap();
        let err = e.eval(&[], &mut EvalState::new(3)).unwrap_err();
        assert_eq!(err, EvalError::Budget(3));
    }

    #[test]
    fn output_writes_integers_and_refuses_fractions() {
        let mut s = String::new();
        write_output(&mut s, &TplValue::Num(25.0)).unwrap();
        write_output(&mut s, &TplValue::from(" X")).unwrap();
        assert_eq!(s, "25 X");
        assert!(write_output(&mut s, &TplValue::Num(0.1)).is_err());
        assert!(write_output(&mut s, &TplValue::Null).is_err());
    }
}
