//! Assembly and the expression-driven algorithm (docs/programs.md#standard-templates, seed 000 §3.2).
//!
//! [`Compiled::new`] takes an assembled template (its records in ID order, see
//! [`crate::library`] for assembly from the module library), resolves every
//! parameter and variable name to a slot, compiles every expression once, and
//! nests the records by scope. [`Compiled::instantiate`] is the algorithm:
//!
//! 1. load the parameter values of the part scope into their slots (each inner
//!    scope's values are loaded when the scope is entered: per unit, cut, move);
//! 2. for each record in ID order:
//! 3. if it has calculation expressions (S) and its calculation condition (P)
//!    holds or is absent,
//! 4. evaluate them in order, each assignment visible to later ones and to
//!    later records (intermediate variables);
//! 5. if its output condition (P) holds or is absent,
//! 6. evaluate its output expression (O) into an NC line and append it;
//! 7. the lines are the program text.
//!
//! Steps 5 and 6 are taken in the order condition, then output: the result is
//! the same as evaluating the output first and testing the condition after,
//! and an output whose parameters do not exist when its condition is false
//! (the Z of a move that has none) is never evaluated. Evaluation is bounded
//! by a step budget and an output limit.

use std::collections::HashMap;

use gearcam_proto::Dialect;

use crate::expr::{self, EvalError, EvalState, TplExpr, TplValue};
use crate::params::{self, PartInput};
use crate::stdcode::{self, Scope, TemplateFile};

/// Expression steps one instantiation may take. A hobbing program needs a few
/// thousand; a runaway template stops here.
pub const STEP_BUDGET: u64 = 1_000_000;

/// Largest program text, bytes.
pub const MAX_PROGRAM_BYTES: usize = 1 << 20;

/// A template that cannot be compiled: the record's source line and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("template {template}, line {line} (record {id}): {message}")]
pub struct CompileError {
    /// Template id.
    pub template: String,
    /// Source line.
    pub line: u32,
    /// Record ID.
    pub id: u32,
    /// What is wrong.
    pub message: String,
}

/// An instantiation that failed: the record and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("template {template}, line {line} (record {id}): {error}")]
pub struct RunError {
    /// Template id.
    pub template: String,
    /// Source line of the record.
    pub line: u32,
    /// Record ID.
    pub id: u32,
    /// What went wrong.
    pub error: RunFailure,
}

/// Why an instantiation failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RunFailure {
    /// An expression failed.
    #[error("{0}")]
    Eval(EvalError),
    /// The program grew past [`MAX_PROGRAM_BYTES`].
    #[error("the program is larger than {MAX_PROGRAM_BYTES} bytes")]
    TooLarge,
}

/// An output piece: literal NC text or a parameter expression.
#[derive(Debug, Clone)]
enum Piece {
    Lit(String),
    TplExpr(TplExpr),
}

/// A compiled record.
#[derive(Debug, Clone)]
struct CRecord {
    id: u32,
    line: u32,
    calc_if: Option<TplExpr>,
    calc: Vec<(usize, TplExpr)>,
    out_if: Option<TplExpr>,
    output: Vec<Piece>,
}

/// The records nested by scope.
#[derive(Debug, Clone)]
enum Node {
    Rec(usize),
    Loop(Scope, Vec<Node>),
}

/// A compiled template, ready to instantiate many times.
#[derive(Debug, Clone)]
pub struct Compiled {
    /// Template id.
    pub id: String,
    /// Gear class.
    pub class: String,
    /// Dialect.
    pub dialect: Dialect,
    /// Version.
    pub version: u32,
    records: Vec<CRecord>,
    tree: Vec<Node>,
    slots: usize,
}

/// First slot of each scope's parameters; variables follow the parameters.
const PART_BASE: usize = 0;
const UNIT_BASE: usize = params::PART.len();
const CUT_BASE: usize = UNIT_BASE + params::UNIT.len();
const MOVE_BASE: usize = CUT_BASE + params::CUT.len();
const VAR_BASE: usize = MOVE_BASE + params::MOVE.len();

impl Compiled {
    /// Compiles an assembled template.
    pub fn new(t: &TemplateFile) -> Result<Self, CompileError> {
        let mut names: HashMap<String, usize> = HashMap::new();
        for (i, n) in params::PART
            .iter()
            .chain(params::UNIT)
            .chain(params::CUT)
            .chain(params::MOVE)
            .enumerate()
        {
            names.insert((*n).to_string(), i);
        }
        let mut next_var = VAR_BASE;
        let mut records = Vec::with_capacity(t.records.len());
        for r in &t.records {
            let err = |message: String| CompileError {
                template: t.id.clone(),
                line: r.line,
                id: r.id,
                message,
            };
            // A name of an inner scope is only visible inside that scope.
            let visible = |slot: usize| -> bool {
                let needed = if slot >= VAR_BASE {
                    Scope::Part
                } else if slot >= MOVE_BASE {
                    Scope::Move
                } else if slot >= CUT_BASE {
                    Scope::Cut
                } else if slot >= UNIT_BASE {
                    Scope::Unit
                } else {
                    Scope::Part
                };
                needed <= r.scope
            };
            let compile = |text: &str, names: &HashMap<String, usize>| {
                let mut resolve = |n: &str| names.get(n).copied().filter(|slot| visible(*slot));
                expr::compile(text, &mut resolve).map_err(|e| err(e.to_string()))
            };
            let calc_if = r
                .calc_if
                .as_deref()
                .map(|c| compile(c, &names))
                .transpose()?;
            let mut calc = Vec::with_capacity(r.calc.len());
            for (var, text) in &r.calc {
                let e = compile(text, &names)?;
                let slot = match names.get(var.as_str()) {
                    Some(&s) if s >= VAR_BASE => s,
                    Some(_) => {
                        return Err(err(format!(
                            "calc: assigns to {var:?}, which is a parameter; choose another variable name"
                        )))
                    }
                    None => {
                        names.insert(var.clone(), next_var);
                        next_var += 1;
                        next_var - 1
                    }
                };
                calc.push((slot, e));
            }
            let out_if = r
                .out_if
                .as_deref()
                .map(|c| compile(c, &names))
                .transpose()?;
            let mut output = Vec::new();
            let text = r.output.as_str();
            let mut lit_start = 0;
            let mut i = 0;
            while i < text.len() {
                if text.as_bytes()[i] == b'{' {
                    let end = stdcode::placeholder_end(text, i)
                        .ok_or_else(|| err(format!("unclosed parameter in {text:?}")))?;
                    if lit_start < i {
                        output.push(Piece::Lit(text[lit_start..i].to_string()));
                    }
                    output.push(Piece::TplExpr(compile(&text[i + 1..end - 1], &names)?));
                    i = end;
                    lit_start = end;
                } else {
                    i += 1;
                }
            }
            if lit_start < text.len() {
                output.push(Piece::Lit(text[lit_start..].to_string()));
            }
            records.push(CRecord {
                id: r.id,
                line: r.line,
                calc_if,
                calc,
                out_if,
                output,
            });
        }
        let scopes: Vec<Scope> = t.records.iter().map(|r| r.scope).collect();
        let mut pos = 0;
        let tree = nest(&scopes, &mut pos, Scope::Part).map_err(|at| CompileError {
            template: t.id.clone(),
            line: t.records[at].line,
            id: t.records[at].id,
            message: format!(
                "a {} record must follow a record of the scope just outside it (part > unit > cut > move)",
                t.records[at].scope.as_str()
            ),
        })?;
        Ok(Compiled {
            id: t.id.clone(),
            class: t.class.clone(),
            dialect: t.dialect,
            version: t.version,
            records,
            tree,
            slots: next_var,
        })
    }

    /// Instantiates the template for one part: the program text.
    pub fn instantiate(&self, input: &PartInput<'_>, budget: u64) -> Result<String, RunError> {
        let mut run = Run {
            t: self,
            vars: vec![TplValue::Null; self.slots],
            st: EvalState::new(budget),
            out: String::with_capacity(4096),
            input,
            unit: None,
            cut: None,
        };
        let machine = &input.model.plan.machine;
        run.st.params = match machine.dialect {
            gearcam_proto::Dialect::Fanuc => ("#", u32::from(machine.parameters.macro_first)),
            _ => ("R", u32::from(machine.parameters.r_first)),
        };
        params::fill_part(input, &mut run.vars[PART_BASE..UNIT_BASE]);
        run.nodes(&self.tree)?;
        Ok(run.out)
    }
}

/// Nests records by scope from `pos` at `level`; `Err(index)` names a record that
/// jumps more than one scope inward.
fn nest(scopes: &[Scope], pos: &mut usize, level: Scope) -> Result<Vec<Node>, usize> {
    let mut nodes = Vec::new();
    while *pos < scopes.len() {
        let s = scopes[*pos];
        if s < level {
            break;
        }
        if s == level {
            nodes.push(Node::Rec(*pos));
            *pos += 1;
            continue;
        }
        let inner = level.inner().filter(|i| *i == s).ok_or(*pos)?;
        nodes.push(Node::Loop(inner, nest(scopes, pos, inner)?));
    }
    Ok(nodes)
}

struct Run<'a> {
    t: &'a Compiled,
    vars: Vec<TplValue>,
    st: EvalState,
    out: String,
    input: &'a PartInput<'a>,
    unit: Option<usize>,
    cut: Option<usize>,
}

impl Run<'_> {
    fn nodes(&mut self, nodes: &[Node]) -> Result<(), RunError> {
        for node in nodes {
            match node {
                Node::Rec(i) => self.record(*i)?,
                Node::Loop(Scope::Unit, body) => {
                    let units = self.input.units;
                    for (i, u) in units.iter().enumerate() {
                        params::fill_unit(i, units.len(), u, &mut self.vars[UNIT_BASE..CUT_BASE]);
                        self.unit = Some(i);
                        self.nodes(body)?;
                    }
                }
                Node::Loop(Scope::Cut, body) => {
                    let Some(u) = self.unit.map(|i| &self.input.units[i]) else {
                        continue;
                    };
                    let cuts = &u.kin.cuts;
                    for (i, c) in cuts.iter().enumerate() {
                        params::fill_cut(cuts.len(), c, &mut self.vars[CUT_BASE..MOVE_BASE]);
                        self.cut = Some(i);
                        self.nodes(body)?;
                    }
                }
                Node::Loop(Scope::Move, body) => {
                    let (Some(u), Some(c)) = (self.unit, self.cut) else {
                        continue;
                    };
                    let moves = &self.input.units[u].kin.cuts[c].moves;
                    for (i, m) in moves.iter().enumerate() {
                        params::fill_move(i, m, &mut self.vars[MOVE_BASE..VAR_BASE]);
                        self.nodes(body)?;
                    }
                }
                Node::Loop(Scope::Part, body) => self.nodes(body)?,
            }
        }
        Ok(())
    }

    fn record(&mut self, i: usize) -> Result<(), RunError> {
        let r = &self.t.records[i];
        let fail = |error: RunFailure| RunError {
            template: self.t.id.clone(),
            line: r.line,
            id: r.id,
            error,
        };
        let eval = |e: EvalError| fail(RunFailure::Eval(e));
        // Steps 3–4: calculation condition, calculation expressions.
        if !r.calc.is_empty() {
            let go = match &r.calc_if {
                Some(c) => c.eval_bool(&self.vars, &mut self.st).map_err(eval)?,
                None => true,
            };
            if go {
                for (slot, e) in &r.calc {
                    let v = e.eval(&self.vars, &mut self.st).map_err(eval)?;
                    self.vars[*slot] = v;
                }
            }
        }
        // Steps 5–6: output condition, output expression.
        if let Some(c) = &r.out_if {
            if !c.eval_bool(&self.vars, &mut self.st).map_err(eval)? {
                return Ok(());
            }
        }
        for piece in &r.output {
            match piece {
                Piece::Lit(s) => self.out.push_str(s),
                Piece::TplExpr(e) => e
                    .write_to(&self.vars, &mut self.st, &mut self.out)
                    .map_err(eval)?,
            }
        }
        self.out.push('\n');
        if self.out.len() > MAX_PROGRAM_BYTES {
            return Err(fail(RunFailure::TooLarge));
        }
        Ok(())
    }
}
