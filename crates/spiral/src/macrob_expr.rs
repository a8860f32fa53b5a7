//! The expressions of the Macro B subset that [`crate::macrob`] replays:
//! numbers and variables `#n`, arithmetic `+ - * /` with `[ ]`, the
//! functions `SIN COS TAN ATAN SQRT ABS ROUND FIX FUP` (degrees, as on the
//! control) and the comparisons `EQ NE GT GE LT LE` with `AND OR`, evaluated
//! over the variables the replay keeps.

use std::collections::HashMap;

/// The value of variable `#n`; a variable not yet set is an error.
pub(crate) fn var(vars: &HashMap<u32, f64>, n: u32) -> Result<f64, String> {
    vars.get(&n)
        .copied()
        .ok_or_else(|| format!("#{n} is used before it is set"))
}

/// Evaluates an expression (the subset's grammar, with precedence
/// OR < AND < comparison < + - < * / < unary < primary).
pub(crate) fn eval<'a>(vars: &'a HashMap<u32, f64>, s: &'a str) -> Result<f64, String> {
    let tokens = tokenize(s)?;
    let mut p = Parser { vars, tokens, i: 0 };
    let v = p.or()?;
    if p.i != p.tokens.len() {
        return Err(format!("unexpected {:?} in {s}", p.tokens[p.i]));
    }
    Ok(v)
}

/// A token, its text borrowed from the expression (no allocation per
/// token: the replay evaluates an expression every time a loop runs it).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Tok<'a> {
    Num(f64),
    Var(u32),
    Word(&'a str),
    Op(char),
    Open,
    Close,
}

fn tokenize(s: &str) -> Result<Vec<Tok<'_>>, String> {
    let mut out = Vec::new();
    let mut chars = s.char_indices().peekable();
    // The end of the run of characters from `start` that `keep` accepts.
    let run = |chars: &mut std::iter::Peekable<std::str::CharIndices>, keep: fn(char) -> bool| {
        while chars.next_if(|&(_, c)| keep(c)).is_some() {}
        chars.peek().map_or(s.len(), |&(j, _)| j)
    };
    while let Some(&(i, c)) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
        } else if c.is_ascii_digit() || c == '.' {
            let end = run(&mut chars, |c| c.is_ascii_digit() || c == '.');
            let t = &s[i..end];
            out.push(Tok::Num(t.parse().map_err(|_| format!("bad number {t}"))?));
        } else if c == '#' {
            chars.next();
            let end = run(&mut chars, |c| c.is_ascii_digit());
            let t = &s[i + 1..end];
            out.push(Tok::Var(
                t.parse().map_err(|_| format!("bad variable #{t}"))?,
            ));
        } else if c.is_ascii_alphabetic() {
            let end = run(&mut chars, |c| c.is_ascii_alphabetic());
            out.push(Tok::Word(&s[i..end]));
        } else if "+-*/".contains(c) {
            out.push(Tok::Op(c));
            chars.next();
        } else if c == '[' {
            out.push(Tok::Open);
            chars.next();
        } else if c == ']' {
            out.push(Tok::Close);
            chars.next();
        } else {
            return Err(format!("character {c:?} outside the subset"));
        }
    }
    Ok(out)
}

struct Parser<'a> {
    vars: &'a HashMap<u32, f64>,
    tokens: Vec<Tok<'a>>,
    i: usize,
}

impl Parser<'_> {
    fn peek_word(&self, w: &str) -> bool {
        matches!(self.tokens.get(self.i), Some(Tok::Word(x)) if *x == w)
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
            Tok::Var(n) => var(self.vars, n),
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
                Ok(match f {
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
