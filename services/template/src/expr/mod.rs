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

mod parse;
#[cfg(test)]
mod tests;
pub use parse::*;

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
