//! Compiling an expression of the template language: the parser.

use super::*;

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

pub(super) struct Parser<'a, 'r> {
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

pub(super) fn bin(op: BinOp, l: TplExpr, r: TplExpr) -> TplExpr {
    TplExpr::Bin(BinOpBox(Box::new((op, l, r))))
}
