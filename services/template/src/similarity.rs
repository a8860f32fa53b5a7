//! Literal similarity of standard NC code and the split into similar and
//! non-similar components (docs/programs.md#standard-templates; seed 000 §3.1.3).
//!
//! Two lines are compared element by element, position by position:
//!
//! ```text
//! Sim(S1, S2) = K / (M + N − K)
//! ```
//!
//! with M and N the number of elements of each line (letters and letter groups,
//! numbers, symbols, `{…}` parameters — see [`crate::stdcode::elements`]) and K
//! the number of positions where both lines have the same element. Two empty
//! lines are similar: seed 000 §3.1.3, "0 与 0 的相似度为 1".
//!
//! [`analyze`] splits the records of every module of every class of a dialect:
//! a record whose line has Sim = 1 with a line of the same module in another
//! class, and the same text (Sim = 1 is blind to spacing, the NC output is
//! not), is a **similar component**, stored once for every class that has it;
//! the others are **non-similar components** of their class, stored once per
//! class and text. The [`Report`] counts the lines each way and the storage the
//! split saves. The same split decides what the template library stores
//! ([`crate::library`]), so the report and the database agree row for row.
//!
//! Everything here is pure: plain data in, plain data out.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

use gearcam_proto::Dialect;
use serde::{Serialize, Serializer};

use crate::stdcode::{Module, Record, TemplateFile};

/// The literal similarity `K / (M + N − K)` of two element sequences.
///
/// K counts the positions `i < min(M, N)` where `a[i] == b[i]`: order
/// matters, and a shifted line shares fewer elements. 0 vs 0 elements is 1.
pub fn sim(a: &[String], b: &[String]) -> f64 {
    let k = shared(a, b);
    let denominator = a.len() + b.len() - k;
    if denominator == 0 {
        return 1.0;
    }
    k as f64 / denominator as f64
}

/// K: the number of positions where both sequences have the same element.
fn shared(a: &[String], b: &[String]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x == y).count()
}

/// Whether a record is stored once for several classes or for its own class.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Sim = 1 (same text) with a record of the same module in another class.
    Similar,
    /// Only its own class has this line.
    NonSimilar,
}

impl Kind {
    /// The kind's name in the database: `similar`, `non_similar`.
    pub fn as_str(self) -> &'static str {
        match self {
            Kind::Similar => "similar",
            Kind::NonSimilar => "non_similar",
        }
    }

    /// The kind as written in a module type T: `similar`, `non-similar`.
    pub fn label(self) -> &'static str {
        match self {
            Kind::Similar => "similar",
            Kind::NonSimilar => "non-similar",
        }
    }

    /// Reads [`Kind::as_str`] back.
    pub fn parse(s: &str) -> Option<Kind> {
        match s {
            "similar" => Some(Kind::Similar),
            "non_similar" => Some(Kind::NonSimilar),
            _ => None,
        }
    }
}

/// The kind of every record of templates of one dialect: `kinds[f][r]` for
/// record `r` of `files[f]`. A record is similar when a file of another class
/// has a record of the same module with the same text (hence Sim = 1).
pub fn classify(files: &[&TemplateFile]) -> Vec<Vec<Kind>> {
    let mut classes_of: BTreeMap<(Module, String), BTreeSet<&str>> = BTreeMap::new();
    for f in files {
        for r in &f.records {
            classes_of
                .entry((r.module, r.text()))
                .or_default()
                .insert(f.class.as_str());
        }
    }
    files
        .iter()
        .map(|f| {
            f.records
                .iter()
                .map(|r| {
                    if classes_of[&(r.module, r.text())].len() > 1 {
                        Kind::Similar
                    } else {
                        Kind::NonSimilar
                    }
                })
                .collect()
        })
        .collect()
}

/// The similarity analysis of a set of templates: one section per dialect.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// One section per dialect, in the order `sinumerik840d`, `fanuc`, ….
    pub dialects: Vec<DialectReport>,
}

/// The analysis of the classes of one dialect.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DialectReport {
    /// The controller dialect.
    pub dialect: Dialect,
    /// The classes compared, sorted.
    pub classes: Vec<String>,
    /// One row per control module, in assembly order (all six).
    pub modules: Vec<ModuleReport>,
    /// The sums over the modules.
    pub total: Storage,
}

/// The analysis of one control module across the classes of a dialect.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModuleReport {
    /// The control module.
    #[serde(serialize_with = "module_name")]
    pub module: Module,
    /// Lines (records) of this module per class.
    pub lines: BTreeMap<String, usize>,
    /// The similar components, each stored once, in order of first appearance.
    pub similar: Vec<SharedLine>,
    /// Non-similar lines per class.
    pub non_similar: BTreeMap<String, usize>,
    /// Every non-similar line with the closest line of another class.
    pub own: Vec<OwnLine>,
    /// Lines and bytes, written out and stored.
    pub storage: Storage,
}

/// A similar component: one line shared by several classes.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SharedLine {
    /// The record's canonical text ([`Record::text`]).
    pub text: String,
    /// The classes whose template has the line, sorted.
    pub classes: Vec<String>,
    /// How many records use it (at least the number of classes).
    pub uses: usize,
}

/// A non-similar line and the most similar line of the same module in another
/// class of the dialect.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OwnLine {
    /// The class whose line it is.
    pub class: String,
    /// ID: the record's position in its template.
    pub id: u32,
    /// N: its number within the module.
    pub n: u32,
    /// The record's canonical text.
    pub text: String,
    /// The closest line of another class, if any other class has this module.
    pub closest: Option<Closest>,
}

/// The line of another class most similar to an [`OwnLine`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Closest {
    /// Its class.
    pub class: String,
    /// Its ID in that class's template.
    pub id: u32,
    /// Its canonical text.
    pub text: String,
    /// Sim of the two lines.
    pub sim: f64,
    /// K: elements the two lines share, position by position.
    pub k: usize,
    /// M: elements of the own line.
    pub m: usize,
    /// N: elements of the other line.
    pub n: usize,
}

/// What storing the components once saves: lines and bytes (canonical text
/// plus a newline) as written in the templates, as stored, and the difference.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Storage {
    /// Records over all classes.
    pub lines: usize,
    /// Records that are similar components.
    pub shared_lines: usize,
    /// Records that are non-similar components.
    pub own_lines: usize,
    /// Distinct similar components (stored once each).
    pub similar_stored: usize,
    /// Distinct non-similar components (stored once per class and text).
    pub own_stored: usize,
    /// Components stored: `similar_stored + own_stored`.
    pub lines_stored: usize,
    /// `lines − lines_stored`.
    pub lines_saved: usize,
    /// Bytes of all records.
    pub bytes: usize,
    /// Bytes of the stored components.
    pub bytes_stored: usize,
    /// `bytes − bytes_stored`.
    pub bytes_saved: usize,
}

impl Storage {
    /// Lines saved as a percentage of the lines written (0 for no lines).
    pub fn lines_saved_percent(&self) -> f64 {
        percent(self.lines_saved, self.lines)
    }

    /// Bytes saved as a percentage of the bytes written (0 for no bytes).
    pub fn bytes_saved_percent(&self) -> f64 {
        percent(self.bytes_saved, self.bytes)
    }

    fn add(&mut self, o: &Storage) {
        self.lines += o.lines;
        self.shared_lines += o.shared_lines;
        self.own_lines += o.own_lines;
        self.similar_stored += o.similar_stored;
        self.own_stored += o.own_stored;
        self.lines_stored += o.lines_stored;
        self.lines_saved += o.lines_saved;
        self.bytes += o.bytes;
        self.bytes_stored += o.bytes_stored;
        self.bytes_saved += o.bytes_saved;
    }
}

pub(crate) fn module_name<S: Serializer>(m: &Module, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(m.as_str())
}

fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// Splits every class's records into similar and non-similar components, per
/// dialect and module, and counts what storing each component once saves.
///
/// Files of the same class (and dialect) count as one class: a line is similar
/// only when another class has it.
pub fn analyze(files: &[TemplateFile]) -> Report {
    let mut by_dialect: BTreeMap<&str, Vec<&TemplateFile>> = BTreeMap::new();
    for f in files {
        by_dialect.entry(f.dialect.as_str()).or_default().push(f);
    }
    let mut dialects: Vec<DialectReport> = by_dialect
        .into_values()
        .map(|fs| analyze_dialect(&fs))
        .collect();
    dialects.sort_by_key(|d| dialect_rank(d.dialect));
    Report { dialects }
}

fn dialect_rank(d: Dialect) -> usize {
    match d {
        Dialect::Sinumerik840d => 0,
        Dialect::Fanuc => 1,
        Dialect::Linuxcnc => 2,
        Dialect::Wire3b => 3,
        Dialect::WireIso => 4,
    }
}

fn analyze_dialect(files: &[&TemplateFile]) -> DialectReport {
    let dialect = files[0].dialect;
    let kinds = classify(files);
    let classes: Vec<String> = files
        .iter()
        .map(|f| f.class.clone())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    let mut modules = Vec::new();
    let mut total = Storage::default();
    for module in Module::ALL {
        // (class, record, kind) of this module, in file order.
        let rows: Vec<(&str, &Record, Kind)> = files
            .iter()
            .zip(&kinds)
            .flat_map(|(f, ks)| {
                f.records
                    .iter()
                    .zip(ks)
                    .filter(|(r, _)| r.module == module)
                    .map(|(r, k)| (f.class.as_str(), r, *k))
            })
            .collect();
        let report = analyze_module(module, &classes, &rows);
        total.add(&report.storage);
        modules.push(report);
    }
    DialectReport {
        dialect,
        classes,
        modules,
        total,
    }
}

fn analyze_module(
    module: Module,
    classes: &[String],
    rows: &[(&str, &Record, Kind)],
) -> ModuleReport {
    let texts: Vec<String> = rows.iter().map(|(_, r, _)| r.text()).collect();
    let elements: Vec<Vec<String>> = rows.iter().map(|(_, r, _)| r.elements()).collect();
    let mut lines: BTreeMap<String, usize> = classes.iter().map(|c| (c.clone(), 0)).collect();
    let mut non_similar = lines.clone();
    let mut similar: Vec<SharedLine> = Vec::new();
    let mut own_seen: BTreeSet<(&str, &str)> = BTreeSet::new();
    let mut own = Vec::new();
    let mut storage = Storage::default();
    for (i, &(class, record, kind)) in rows.iter().enumerate() {
        let text = &texts[i];
        let bytes = text.len() + 1;
        *lines.entry(class.to_string()).or_default() += 1;
        storage.lines += 1;
        storage.bytes += bytes;
        match kind {
            Kind::Similar => {
                storage.shared_lines += 1;
                match similar.iter_mut().find(|s| &s.text == text) {
                    Some(s) => {
                        s.uses += 1;
                        if !s.classes.iter().any(|c| c == class) {
                            s.classes.push(class.to_string());
                            s.classes.sort();
                        }
                    }
                    None => {
                        storage.similar_stored += 1;
                        storage.bytes_stored += bytes;
                        similar.push(SharedLine {
                            text: text.clone(),
                            classes: vec![class.to_string()],
                            uses: 1,
                        });
                    }
                }
            }
            Kind::NonSimilar => {
                storage.own_lines += 1;
                *non_similar.entry(class.to_string()).or_default() += 1;
                if own_seen.insert((class, text.as_str())) {
                    storage.own_stored += 1;
                    storage.bytes_stored += bytes;
                }
                let closest = rows
                    .iter()
                    .enumerate()
                    .filter(|(_, (c, _, _))| *c != class)
                    .map(|(j, (c, r, _))| {
                        let (a, b) = (&elements[i], &elements[j]);
                        (sim(a, b), shared(a, b), j, *c, r.id)
                    })
                    .max_by(|x, y| x.0.total_cmp(&y.0).then(y.2.cmp(&x.2)))
                    .map(|(s, k, j, c, id)| Closest {
                        class: c.to_string(),
                        id,
                        text: texts[j].clone(),
                        sim: s,
                        k,
                        m: elements[i].len(),
                        n: elements[j].len(),
                    });
                own.push(OwnLine {
                    class: class.to_string(),
                    id: record.id,
                    n: record.n,
                    text: text.clone(),
                    closest,
                });
            }
        }
    }
    storage.lines_stored = storage.similar_stored + storage.own_stored;
    storage.lines_saved = storage.lines - storage.lines_stored;
    storage.bytes_saved = storage.bytes - storage.bytes_stored;
    ModuleReport {
        module,
        lines,
        similar,
        non_similar,
        own,
        storage,
    }
}

/// The text report writes out the closest line of another class when it is at
/// least this similar: a candidate for writing the two lines the same way.
pub const NEAR_SIM: f64 = 0.75;

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.dialects.is_empty() {
            return writeln!(f, "no templates to compare");
        }
        for (i, d) in self.dialects.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        Ok(())
    }
}

impl fmt::Display for DialectReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}: {} class(es): {}",
            self.dialect.as_str(),
            self.classes.len(),
            self.classes.join(", ")
        )?;
        writeln!(
            f,
            "  lines per class and module; shared = lines that are similar components \
             (Sim = 1 with another class), own = non-similar lines"
        )?;
        let widths: Vec<usize> = self.classes.iter().map(|c| c.len().max(5)).collect();
        let mut head = format!("  {:<12}", "module");
        for (c, w) in self.classes.iter().zip(&widths) {
            head.push_str(&format!(" {c:>w$}"));
        }
        head.push_str("  lines shared  own stored  saved");
        writeln!(f, "{head}")?;
        let row = |name: &str, per_class: Vec<usize>, s: &Storage| {
            let mut line = format!("  {name:<12}");
            for (n, w) in per_class.iter().zip(&widths) {
                line.push_str(&format!(" {n:>w$}"));
            }
            line.push_str(&format!(
                "  {:>5} {:>6} {:>4} {:>6} {:>6} ({:.1} %)",
                s.lines,
                s.shared_lines,
                s.own_lines,
                s.lines_stored,
                s.lines_saved,
                s.lines_saved_percent()
            ));
            line
        };
        for m in &self.modules {
            let per_class = self.classes.iter().map(|c| m.lines[c]).collect();
            writeln!(f, "{}", row(m.module.as_str(), per_class, &m.storage))?;
        }
        let per_class = self
            .classes
            .iter()
            .map(|c| self.modules.iter().map(|m| m.lines[c]).sum())
            .collect();
        writeln!(f, "{}", row("total", per_class, &self.total))?;
        let t = &self.total;
        writeln!(
            f,
            "  stored: {} similar + {} non-similar components = {} of {} lines; \
             {} of {} bytes, {} saved ({:.1} %)",
            t.similar_stored,
            t.own_stored,
            t.lines_stored,
            t.lines,
            t.bytes_stored,
            t.bytes,
            t.bytes_saved,
            t.bytes_saved_percent()
        )?;
        writeln!(
            f,
            "  per module: S = similar component (stored once; [all] = every class), \
             N = non-similar component of its class (#ID, and the closest line of another class)"
        )?;
        for m in &self.modules {
            if m.storage.lines == 0 {
                continue;
            }
            writeln!(
                f,
                "  {}: {} similar, {} non-similar component(s)",
                m.module, m.storage.similar_stored, m.storage.own_stored
            )?;
            for s in &m.similar {
                let who = if s.classes.len() == self.classes.len() {
                    "all".to_string()
                } else {
                    s.classes.join(" ")
                };
                writeln!(f, "    S [{who}] {}", s.text)?;
            }
            // One entry per class and text; a line used twice lists both IDs.
            let mut shown: Vec<(&OwnLine, Vec<u32>)> = Vec::new();
            for o in &m.own {
                match shown
                    .iter_mut()
                    .find(|(p, _)| p.class == o.class && p.text == o.text)
                {
                    Some((_, ids)) => ids.push(o.id),
                    None => shown.push((o, vec![o.id])),
                }
            }
            for (o, ids) in shown {
                let ids: Vec<String> = ids.iter().map(|i| format!("#{i}")).collect();
                writeln!(f, "    N {} {}: {}", o.class, ids.join(" "), o.text)?;
                if let Some(c) = &o.closest {
                    write!(
                        f,
                        "      closest: Sim {:.3} (K {} of M {}, N {}) with {} #{}",
                        c.sim, c.k, c.m, c.n, c.class, c.id
                    )?;
                    if c.sim >= NEAR_SIM {
                        write!(f, ": {}", c.text)?;
                    }
                    writeln!(f)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stdcode::{elements, parse};
    use approx::assert_relative_eq;

    fn els(s: &str) -> Vec<String> {
        elements(s)
    }

    #[test]
    fn sim_of_a_changed_parameter_is_k_over_m_plus_n_minus_k() {
        // G, 01, X, {nc(X)}, F, {nc(F)} against the same with {nc(F2)}: K = 5,
        // M = N = 6, Sim = 5 / (6 + 6 − 5) = 5/7.
        let a = els("G01 X{nc(X)} F{nc(F)}");
        let b = els("G01 X{nc(X)} F{nc(F2)}");
        assert_eq!((a.len(), b.len(), shared(&a, &b)), (6, 6, 5));
        assert_relative_eq!(sim(&a, &b), 5.0 / 7.0);
        assert_relative_eq!(sim(&a, &a), 1.0);
    }

    #[test]
    fn sim_of_lines_of_different_length() {
        // G, 00, G, 90, X, {x} (M = 6) against G, 00, G, 90, X, {x}, Z, {z}
        // (N = 8): K = 6, Sim = 6 / (6 + 8 − 6) = 3/4.
        let a = els("G00 G90 X{x}");
        let b = els("G00 G90 X{x} Z{z}");
        assert_relative_eq!(sim(&a, &b), 0.75);
        assert_relative_eq!(sim(&b, &a), 0.75);
        // Nothing in common: K = 0.
        assert_relative_eq!(sim(&els("M30"), &els("G1 X1")), 0.0);
    }

    #[test]
    fn zero_against_zero_elements_is_similar() {
        // Seed 000 §3.1.3: "0 与 0 的相似度为 1".
        assert_relative_eq!(sim(&[], &[]), 1.0);
        assert_relative_eq!(sim(&[], &els("M30")), 0.0);
    }

    #[test]
    fn order_matters() {
        // The same elements in another order share only the positions that agree:
        // X, {x}, Z, {z} against Z, {z}, X, {x}: K = 0.
        assert_relative_eq!(sim(&els("X{x} Z{z}"), &els("Z{z} X{x}")), 0.0);
        // M7 M8 against M8 M7: M, 7, M, 8 vs M, 8, M, 7: K = 2, Sim = 2/6.
        assert_relative_eq!(sim(&els("M7 M8"), &els("M8 M7")), 1.0 / 3.0);
    }

    fn tpl(class: &str, dialect: &str, suffix: &str, body: &str) -> TemplateFile {
        let text = format!(
            "@template {class}_{suffix}\n@class {class}\n@dialect {dialect}\n@version 1\n{body}"
        );
        parse(&format!("{class}_{suffix}.tpl"), &text).unwrap()
    }

    /// Three classes of one dialect: spur and conical share their main lines and
    /// the coolant line; all three share the gearbox line; the moves differ.
    pub(crate) fn three_classes() -> Vec<TemplateFile> {
        vec![
            tpl(
                "cylindrical",
                "sinumerik840d",
                "840d",
                "main :: %_N_{program.name}_MPF\n\
                 synchronous :: EGON(C, \"FINE\", Y, {nc(k)}, Z)\n\
                 conditions if: options.coolant :: M7\n\
                 motion :: G01 X{nc(X)} F{nc(F)}\n\
                 main :: M30\n",
            ),
            tpl(
                "conical",
                "sinumerik840d",
                "840d",
                "main :: %_N_{program.name}_MPF\n\
                 synchronous :: EGON(C, \"FINE\", Y, {nc(k)}, Z)\n\
                 conditions if: options.coolant :: M7\n\
                 motion :: G01 X{nc(X)} F{nc(F2)}\n\
                 motion :: G01 X{nc(X)} F{nc(F2)}\n\
                 main :: M30\n",
            ),
            tpl(
                "crowned",
                "sinumerik840d",
                "840d",
                "main :: %_N_{program.name}_MPF ; CROWNED\n\
                 synchronous :: EGON(C, \"FINE\", Y, {nc(k)}, Z)\n\
                 motion :: G02 X{nc(X)} F{nc(F)}\n",
            ),
        ]
    }

    #[test]
    fn analyze_splits_three_classes_into_similar_and_own_lines() {
        let r = analyze(&three_classes());
        assert_eq!(r.dialects.len(), 1);
        let d = &r.dialects[0];
        assert_eq!(d.classes, vec!["conical", "crowned", "cylindrical"]);
        let module = |m: Module| d.modules.iter().find(|x| x.module == m).unwrap();

        let main = module(Module::Main);
        assert_eq!(
            main.lines,
            BTreeMap::from([
                ("conical".to_string(), 2),
                ("crowned".to_string(), 1),
                ("cylindrical".to_string(), 2)
            ])
        );
        assert_eq!(
            main.similar,
            vec![
                SharedLine {
                    text: "main :: %_N_{program.name}_MPF".into(),
                    classes: vec!["conical".into(), "cylindrical".into()],
                    uses: 2,
                },
                SharedLine {
                    text: "main :: M30".into(),
                    classes: vec!["conical".into(), "cylindrical".into()],
                    uses: 2,
                },
            ]
        );
        assert_eq!(main.non_similar["crowned"], 1);
        // 5 lines, 2 similar components + 1 own: 3 stored, 2 saved.
        assert_eq!(
            (
                main.storage.lines,
                main.storage.lines_stored,
                main.storage.lines_saved
            ),
            (5, 3, 2)
        );

        let sync = module(Module::Synchronous);
        assert_eq!(sync.similar.len(), 1);
        assert_eq!(sync.similar[0].classes.len(), 3);
        assert_eq!((sync.storage.lines, sync.storage.lines_stored), (3, 1));

        // Motion: no two classes share a line. Conical's two equal lines are one
        // non-similar component; its closest line elsewhere is cylindrical's, 5/7.
        let motion = module(Module::Motion);
        assert!(motion.similar.is_empty());
        assert_eq!(motion.non_similar["conical"], 2);
        assert_eq!((motion.storage.lines, motion.storage.lines_stored), (4, 3));
        let conical = motion.own.iter().find(|o| o.class == "conical").unwrap();
        let closest = conical.closest.as_ref().unwrap();
        assert_eq!(closest.class, "cylindrical");
        // The record's elements start with "motion", ":", ":": M = N = 9, K = 8,
        // Sim = 8 / (9 + 9 − 8) = 0.8.
        assert_eq!((closest.k, closest.m, closest.n), (8, 9, 9));
        assert_relative_eq!(closest.sim, 0.8);

        // Totals: 14 lines; stored 2 + 1 + 1 (main, sync) + 1 (conditions) + 3
        // (motion) = 8.
        assert_eq!(d.total.lines, 14);
        assert_eq!(d.total.lines_stored, 8);
        assert_eq!(d.total.lines_saved, 6);
        assert_eq!(d.total.similar_stored, 4);
        assert_eq!(d.total.own_stored, 4);
        assert!(d.total.bytes_saved > 0 && d.total.bytes_saved < d.total.bytes);
        assert_relative_eq!(d.total.lines_saved_percent(), 600.0 / 14.0);

        let text = r.to_string();
        assert!(text.contains("sinumerik840d: 3 class(es)"), "{text}");
        assert!(text.contains("S [all] synchronous :: EGON"), "{text}");
        assert!(
            text.contains("S [conical cylindrical] main :: M30"),
            "{text}"
        );
        assert!(
            text.contains(
                "N conical #4 #5: motion :: G01 X{nc(X)} F{nc(F2)}\n      \
                 closest: Sim 0.800 (K 8 of M 9, N 9) with cylindrical #4: motion :: G01"
            ),
            "{text}"
        );
    }

    #[test]
    fn dialects_are_compared_apart() {
        let mut files = three_classes();
        files.push(tpl(
            "cylindrical",
            "fanuc",
            "fanuc",
            "main :: %_N_{program.name}_MPF\nmain :: M30\n",
        ));
        let r = analyze(&files);
        assert_eq!(r.dialects.len(), 2);
        assert_eq!(r.dialects[0].dialect, Dialect::Sinumerik840d);
        let fanuc = &r.dialects[1];
        assert_eq!(fanuc.dialect, Dialect::Fanuc);
        // Alone in its dialect: nothing is similar, nothing saved.
        assert_eq!(fanuc.total.shared_lines, 0);
        assert_eq!(fanuc.total.lines_saved, 0);
        assert_eq!(r.dialects[0].total.lines, 14);
    }
}
