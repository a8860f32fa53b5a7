//! Parametrised standard NC code: the template source format (docs/programs.md#standard-templates).
//!
//! A template file is the standard NC code of one gear class on one controller
//! dialect, one **record** per line, in program order. Each record is one
//! six-tuple ⟨ID, O, P, S, T, N⟩ of seed 000 §3.1.4:
//!
//! ```text
//! # comment
//! @template cylindrical_840d
//! @class cylindrical
//! @dialect sinumerik840d
//! @version 3
//!
//! preparation if: options.coolant :: {N()} M{mc.coolant_on} ; COOLANT ON
//! motion/move when: has(m.x) calc: w = " X=" + nc(m.x) if: m.kind == "rapid" :: {N()} G0 G90{w}
//! ```
//!
//! - `module[/scope]` — T: the control module (`main`, `preparation`,
//!   `synchronous`, `shift`, `conditions`, `motion`) and the scope the record is
//!   repeated over (`part`, the default: once; `unit`: per gear unit; `cut`: per
//!   cut of the unit; `move`: per move of the cut — see [`Scope`]);
//! - `when: EXPR` — P, the calculation condition: whether `calc:` is evaluated;
//! - `calc: VAR = EXPR; VAR = EXPR` — S, the calculation expressions;
//! - `if: EXPR` — P, the output condition: whether the line is emitted;
//! - `:: OUTPUT` — O, the output expression: NC text with `{EXPR}` parameters
//!   (the text form of `"G90 X" + X`).
//!
//! ID is the record's position in the file (1, 2, ...) and N its number within
//! its module (1, 2, ... in file order). Expressions are in the language of
//! [`crate::expr`]. This module only reads the text; nothing is evaluated here.

use std::fmt;
use std::str::FromStr;

use gearcam_proto::Dialect;

/// The six control modules of a hobbing program (seed 000 §3.1.2, table 1), in
/// assembly order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Module {
    /// Start and stop of the program, cycles, protected area.
    Main,
    /// Door, tool change, work load and unload, fixture, outer support.
    Preparation,
    /// The electronic gearbox: module, teeth, helix, hob starts and lead.
    Synchronous,
    /// Hob shift amount and direction, parts per shift.
    Shift,
    /// Coolant, chip conveyor, mist separator, speeds.
    Conditions,
    /// Interpolation, feeds, the moves A→B→C→D→E→A.
    Motion,
}

impl Module {
    /// Every module in assembly order.
    pub const ALL: [Module; 6] = [
        Module::Main,
        Module::Preparation,
        Module::Synchronous,
        Module::Shift,
        Module::Conditions,
        Module::Motion,
    ];

    /// The module's name in template files and in the database.
    pub fn as_str(self) -> &'static str {
        match self {
            Module::Main => "main",
            Module::Preparation => "preparation",
            Module::Synchronous => "synchronous",
            Module::Shift => "shift",
            Module::Conditions => "conditions",
            Module::Motion => "motion",
        }
    }
}

impl fmt::Display for Module {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl FromStr for Module {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Module::ALL
            .into_iter()
            .find(|m| m.as_str() == s)
            .ok_or_else(|| {
                format!(
                    "expected a module (main, preparation, synchronous, shift, conditions, motion), got {s:?}"
                )
            })
    }
}

/// What a record is repeated over. Scopes nest: a `cut` record sits inside a run
/// of `unit` records' scope, a `move` record inside a `cut`'s. A single-gear part
/// has one unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Scope {
    /// Once per program.
    Part,
    /// Once per gear unit (`u`, `k` parameters).
    Unit,
    /// Once per cut of the unit (`cut` parameters).
    Cut,
    /// Once per move of the cut (`m` parameters).
    Move,
}

impl Scope {
    /// Nesting depth: part 0, unit 1, cut 2, move 3.
    pub fn depth(self) -> usize {
        self as usize
    }

    /// The scope's name in template files.
    pub fn as_str(self) -> &'static str {
        match self {
            Scope::Part => "part",
            Scope::Unit => "unit",
            Scope::Cut => "cut",
            Scope::Move => "move",
        }
    }

    /// The scope one level deeper, if any.
    pub fn inner(self) -> Option<Scope> {
        match self {
            Scope::Part => Some(Scope::Unit),
            Scope::Unit => Some(Scope::Cut),
            Scope::Cut => Some(Scope::Move),
            Scope::Move => None,
        }
    }
}

impl FromStr for Scope {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "part" => Ok(Scope::Part),
            "unit" => Ok(Scope::Unit),
            "cut" => Ok(Scope::Cut),
            "move" => Ok(Scope::Move),
            _ => Err(format!(
                "expected a scope (part, unit, cut, move), got {s:?}"
            )),
        }
    }
}

/// One record ⟨ID, O, P, S, T, N⟩ of a template, as written in the source.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Record {
    /// ID: position in the template, 1-based, in source order.
    pub id: u32,
    /// T: the control module.
    pub module: Module,
    /// N: number within the module, 1-based, in source order.
    pub n: u32,
    /// What the record is repeated over.
    pub scope: Scope,
    /// P: the calculation condition (expression source), if any.
    pub calc_if: Option<String>,
    /// S: the calculation expressions, `(variable, expression source)`, in order.
    pub calc: Vec<(String, String)>,
    /// P: the output condition (expression source), if any.
    pub out_if: Option<String>,
    /// O: the output expression: NC text with `{EXPR}` parameters.
    pub output: String,
    /// Line in the source file, 1-based.
    pub line: u32,
}

impl Record {
    /// The record written back as one source line (without ID and N, which come
    /// from its position). Two records with the same text are the same component.
    pub fn text(&self) -> String {
        let mut s = String::from(self.module.as_str());
        if self.scope != Scope::Part {
            s.push('/');
            s.push_str(self.scope.as_str());
        }
        if let Some(c) = &self.calc_if {
            s.push_str(" when: ");
            s.push_str(c);
        }
        if !self.calc.is_empty() {
            s.push_str(" calc: ");
            let parts: Vec<String> = self
                .calc
                .iter()
                .map(|(v, e)| format!("{v} = {e}"))
                .collect();
            s.push_str(&parts.join("; "));
        }
        if let Some(c) = &self.out_if {
            s.push_str(" if: ");
            s.push_str(c);
        }
        s.push_str(" :: ");
        s.push_str(&self.output);
        s
    }

    /// The record's elements for the literal similarity (docs/programs.md#standard-templates): its letters
    /// and letter groups, numbers, symbols, and each `{…}` parameter as one
    /// element, in order. Module and conditions are part of the record.
    pub fn elements(&self) -> Vec<String> {
        elements(&self.text())
    }
}

/// Splits text into similarity elements: runs of letters (with `_`, and `.`
/// between letters: parameter names like `m.kind` are one element), runs of
/// digits (with a decimal point: the number of `G01` is one element), each `{…}` placeholder whole, each other
/// non-space character alone.
pub fn elements(text: &str) -> Vec<String> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'{' {
            let end = placeholder_end(text, i).unwrap_or(b.len());
            out.push(text[i..end].to_string());
            i = end;
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len()
                && (b[i].is_ascii_alphabetic()
                    || b[i] == b'_'
                    || (b[i] == b'.' && b.get(i + 1).is_some_and(|n| n.is_ascii_alphabetic())))
            {
                i += 1;
            }
            out.push(text[start..i].to_string());
        } else if c.is_ascii_digit() {
            let start = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            out.push(text[start..i].to_string());
        } else {
            let ch = text[i..].chars().next().unwrap_or(' ');
            out.push(ch.to_string());
            i += ch.len_utf8();
        }
    }
    out
}

/// A template source file, read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TemplateFile {
    /// Template id, `{class}_{dialect suffix}`, e.g. `cylindrical_840d`.
    pub id: String,
    /// Gear class the template programs.
    pub class: String,
    /// Controller dialect.
    pub dialect: Dialect,
    /// Version, at least 1.
    pub version: u32,
    /// The records in source order.
    pub records: Vec<Record>,
}

/// A template source that cannot be read: the line, what was expected, what was
/// found.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{file}:{line}: expected {expected}, got {got}")]
pub struct StdCodeError {
    /// File name or template id.
    pub file: String,
    /// Line, 1-based (0: the file as a whole).
    pub line: u32,
    /// What the line must be.
    pub expected: String,
    /// What it is.
    pub got: String,
}

/// The dialect suffix used in template ids: `840d`, `fanuc`, `linuxcnc`, `3b`.
pub fn dialect_suffix(d: Dialect) -> &'static str {
    match d {
        Dialect::Sinumerik840d => "840d",
        Dialect::Fanuc => "fanuc",
        Dialect::Linuxcnc => "linuxcnc",
        Dialect::Wire3b => "3b",
        Dialect::WireIso => "iso-wire",
    }
}

fn parse_dialect(s: &str) -> Option<Dialect> {
    [
        Dialect::Sinumerik840d,
        Dialect::Fanuc,
        Dialect::Linuxcnc,
        Dialect::Wire3b,
        Dialect::WireIso,
    ]
    .into_iter()
    .find(|d| d.as_str() == s)
}

/// Reads a template file. `file` names it in errors.
pub fn parse(file: &str, text: &str) -> Result<TemplateFile, StdCodeError> {
    let err = |line: usize, expected: &str, got: &str| StdCodeError {
        file: file.to_string(),
        line: line as u32,
        expected: expected.to_string(),
        got: got.to_string(),
    };
    let (mut id, mut class, mut dialect, mut version) = (None, None, None, None);
    let mut records: Vec<Record> = Vec::new();
    let mut per_module = [0u32; 6];
    for (i, raw) in text.lines().enumerate() {
        let lineno = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if let Some(rest) = line.strip_prefix('@') {
            let (key, value) = rest.split_once(char::is_whitespace).unwrap_or((rest, ""));
            let value = value.trim();
            match key {
                "template" => id = Some(value.to_string()),
                "class" => class = Some(value.to_string()),
                "dialect" => {
                    dialect = Some(parse_dialect(value).ok_or_else(|| {
                        err(
                            lineno,
                            "a dialect (sinumerik840d, fanuc, linuxcnc, wire3b)",
                            value,
                        )
                    })?)
                }
                "version" => {
                    version = Some(
                        value
                            .parse::<u32>()
                            .ok()
                            .filter(|v| *v >= 1)
                            .ok_or_else(|| err(lineno, "a version number of at least 1", value))?,
                    )
                }
                _ => {
                    return Err(err(
                        lineno,
                        "@template, @class, @dialect or @version",
                        &format!("@{key}"),
                    ))
                }
            }
            continue;
        }
        let mut rec = parse_record(line).map_err(|(expected, got)| err(lineno, &expected, &got))?;
        rec.id = records.len() as u32 + 1;
        let slot = &mut per_module[rec.module as usize];
        *slot += 1;
        rec.n = *slot;
        rec.line = lineno as u32;
        records.push(rec);
    }
    let id = id.ok_or_else(|| err(0, "an @template line", "none"))?;
    let class = class.ok_or_else(|| err(0, "an @class line", "none"))?;
    let dialect = dialect.ok_or_else(|| err(0, "an @dialect line", "none"))?;
    let version = version.ok_or_else(|| err(0, "an @version line", "none"))?;
    let want = format!("{class}_{}", dialect_suffix(dialect));
    if id != want {
        return Err(err(0, &format!("@template {want} (class _ dialect)"), &id));
    }
    if records.is_empty() {
        return Err(err(0, "at least one record", "none"));
    }
    Ok(TemplateFile {
        id,
        class,
        dialect,
        version,
        records,
    })
}

/// Reads one record line (without ID, N and line, set by the caller).
pub(crate) fn parse_record(line: &str) -> Result<Record, (String, String)> {
    let sep = find_outside_quotes(line, "::", 0).ok_or_else(|| {
        (
            "a record `module[/scope] [when: ..] [calc: ..] [if: ..] :: OUTPUT`".to_string(),
            line.to_string(),
        )
    })?;
    let head = line[..sep].trim();
    let output = line[sep + 2..].trim_start().to_string();
    check_placeholders(&output)?;
    let (tee, mut rest) = head.split_once(char::is_whitespace).unwrap_or((head, ""));
    let (module, scope) = match tee.split_once('/') {
        Some((m, s)) => (
            m,
            s.parse::<Scope>()
                .map_err(|_| ("a scope (part, unit, cut, move)".to_string(), s.to_string()))?,
        ),
        None => (tee, Scope::Part),
    };
    let module: Module = module.parse().map_err(|_| {
        (
            "a module (main, preparation, synchronous, shift, conditions, motion)".to_string(),
            module.to_string(),
        )
    })?;
    let (mut calc_if, mut calc, mut out_if) = (None, Vec::new(), None);
    // Clauses in the fixed order when:, calc:, if: — each optional.
    rest = rest.trim();
    let clauses = ["when:", "calc:", "if:"];
    let mut next_allowed = 0;
    while !rest.is_empty() {
        let Some(k) = clauses.iter().position(|c| rest.starts_with(c)) else {
            return Err((
                "a clause `when:`, `calc:` or `if:` before `::`".into(),
                rest.to_string(),
            ));
        };
        if k < next_allowed {
            return Err((
                "clauses in the order when:, calc:, if:, each once".into(),
                rest.to_string(),
            ));
        }
        next_allowed = k + 1;
        let body_start = clauses[k].len();
        let end = clauses
            .iter()
            .filter_map(|c| find_outside_quotes(rest, &format!(" {c}"), body_start))
            .min()
            .unwrap_or(rest.len());
        let body = rest[body_start..end].trim();
        if body.is_empty() {
            return Err((
                format!("an expression after `{}`", clauses[k]),
                "nothing".into(),
            ));
        }
        match k {
            0 => calc_if = Some(body.to_string()),
            1 => {
                for part in split_outside_quotes(body, ';') {
                    let part = part.trim();
                    let (var, expr) = part.split_once('=').ok_or_else(|| {
                        ("an assignment `VAR = EXPR`".to_string(), part.to_string())
                    })?;
                    let var = var.trim();
                    let expr = expr.trim();
                    let ok_var = !var.is_empty()
                        && var.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
                        && var.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
                    if !ok_var || expr.is_empty() || expr.starts_with('=') {
                        return Err((
                            "an assignment `VAR = EXPR` with a plain variable name".into(),
                            part.to_string(),
                        ));
                    }
                    calc.push((var.to_string(), expr.to_string()));
                }
            }
            _ => out_if = Some(body.to_string()),
        }
        rest = rest[end..].trim_start();
    }
    Ok(Record {
        id: 0,
        module,
        n: 0,
        scope,
        calc_if,
        calc,
        out_if,
        output,
        line: 0,
    })
}

/// Byte index of `pat` in `s` at or after `from`, outside `"…"` strings.
fn find_outside_quotes(s: &str, pat: &str, from: usize) -> Option<usize> {
    let b = s.as_bytes();
    let mut in_str = false;
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'"' {
            in_str = !in_str;
        } else if !in_str && i >= from && s[i..].starts_with(pat) {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// Splits at `sep` outside strings and parentheses.
fn split_outside_quotes(s: &str, sep: char) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut in_str, mut depth, mut start) = (false, 0i32, 0);
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_str = !in_str,
            '(' if !in_str => depth += 1,
            ')' if !in_str => depth -= 1,
            c if c == sep && !in_str && depth == 0 => {
                out.push(&s[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

/// End (exclusive) of the `{…}` placeholder starting at `start`, honouring strings.
pub(crate) fn placeholder_end(s: &str, start: usize) -> Option<usize> {
    let b = s.as_bytes();
    let mut in_str = false;
    let mut i = start + 1;
    while i < b.len() {
        match b[i] {
            b'"' => in_str = !in_str,
            b'}' if !in_str => return Some(i + 1),
            b'{' if !in_str => return None,
            _ => {}
        }
        i += 1;
    }
    None
}

fn check_placeholders(output: &str) -> Result<(), (String, String)> {
    let b = output.as_bytes();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'{' => {
                let end = placeholder_end(output, i).ok_or_else(|| {
                    (
                        "a closed `{EXPR}` parameter".to_string(),
                        output[i..].to_string(),
                    )
                })?;
                if output[i + 1..end - 1].trim().is_empty() {
                    return Err(("an expression inside `{}`".into(), "{}".into()));
                }
                i = end;
            }
            b'}' => {
                return Err((
                    "no `}` outside a parameter".to_string(),
                    output[i..].to_string(),
                ))
            }
            _ => i += 1,
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str =
        "@template cylindrical_840d\n@class cylindrical\n@dialect sinumerik840d\n@version 3\n";

    #[test]
    fn reads_records_with_id_module_number_and_clauses() {
        let text = format!(
            "{HEAD}# a comment\nmain :: %{{program.file}}\npreparation if: options.coolant :: {{N()}} M{{mc.coolant_on}} ; COOLANT ON\n\
             motion/move when: has(m.x) calc: w = \" X=\" + nc(m.x); v = 1 if: m.kind == \"rapid\" :: {{N()}} G0 G90{{w}}\n\
             preparation :: M{{mc.fixture_clamp}}\n"
        );
        let t = parse("t", &text).unwrap();
        assert_eq!(t.id, "cylindrical_840d");
        assert_eq!(t.version, 3);
        assert_eq!(t.records.len(), 4);
        let r = &t.records[2];
        assert_eq!(
            (r.id, r.module, r.n, r.scope),
            (3, Module::Motion, 1, Scope::Move)
        );
        assert_eq!(r.calc_if.as_deref(), Some("has(m.x)"));
        assert_eq!(
            r.calc,
            vec![
                ("w".to_string(), "\" X=\" + nc(m.x)".to_string()),
                ("v".to_string(), "1".to_string())
            ]
        );
        assert_eq!(r.out_if.as_deref(), Some("m.kind == \"rapid\""));
        assert_eq!(r.output, "{N()} G0 G90{w}");
        assert_eq!(r.line, 8);
        // N counts within the module.
        assert_eq!(
            (t.records[3].module, t.records[3].n),
            (Module::Preparation, 2)
        );
    }

    #[test]
    fn text_round_trips() {
        let text = format!(
            "{HEAD}motion/cut when: cut.resync calc: a = 1; b = \"x; y\" if: a > 0 :: G0 {{nc(a)}}\n"
        );
        let t = parse("t", &text).unwrap();
        let again = parse("t", &format!("{HEAD}{}\n", t.records[0].text())).unwrap();
        assert_eq!(again.records[0].calc, t.records[0].calc);
        assert_eq!(again.records[0].text(), t.records[0].text());
    }

    #[test]
    fn errors_name_the_line_and_what_was_expected() {
        let e = parse("t.tpl", &format!("{HEAD}motion/tooth :: G0\n")).unwrap_err();
        assert_eq!(e.line, 5);
        assert_eq!(e.expected, "a scope (part, unit, cut, move)");
        assert_eq!(e.got, "tooth");
        let e = parse("t.tpl", &format!("{HEAD}shaping :: G0\n")).unwrap_err();
        assert!(e.expected.contains("module"), "{e}");
        let e = parse("t.tpl", &format!("{HEAD}main G0 X1\n")).unwrap_err();
        assert!(e.expected.contains("::"), "{e}");
        let e = parse("t.tpl", &format!("{HEAD}main if: a calc: b = 1 :: G0\n")).unwrap_err();
        assert!(e.expected.contains("order"), "{e}");
        let e = parse("t.tpl", &format!("{HEAD}main :: G0 {{nc(x)\n")).unwrap_err();
        assert!(e.expected.contains("closed"), "{e}");
        let e = parse(
            "t.tpl",
            "@template conical_840d\n@class cylindrical\n@dialect sinumerik840d\n@version 1\nmain :: M2\n",
        )
        .unwrap_err();
        assert_eq!(e.got, "conical_840d");
        let e = parse("t.tpl", "@class cylindrical\n").unwrap_err();
        assert!(e.expected.contains("@template"), "{e}");
    }

    #[test]
    fn elements_split_letters_numbers_symbols_and_parameters() {
        assert_eq!(
            elements("G25 X{nc(Xmin)} ; R1=3.5"),
            vec!["G", "25", "X", "{nc(Xmin)}", ";", "R", "1", "=", "3.5"]
        );
        assert_eq!(
            elements("if: m.kind == 1"),
            vec!["if", ":", "m.kind", "=", "=", "1"]
        );
        assert!(elements("   ").is_empty());
    }
}
