//! The library's reports for a person: the import report and a template's
//! decision table.

use super::*;

impl fmt::Display for ImportReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for a in &self.added {
            match a.previous {
                Some(p) => writeln!(
                    f,
                    "stored {} version {} ({} records; version {p} kept)",
                    a.id, a.version, a.records
                )?,
                None => writeln!(
                    f,
                    "stored {} version {} ({} records)",
                    a.id, a.version, a.records
                )?,
            }
        }
        for s in &self.skipped {
            writeln!(f, "unchanged {} version {} (skipped)", s.id, s.version)?;
        }
        writeln!(
            f,
            "{} new version(s), {} unchanged; the library holds {} similar and {} non-similar components\n",
            self.added.len(),
            self.skipped.len(),
            self.components.similar,
            self.components.non_similar
        )?;
        write!(f, "{}", self.similarity)
    }
}

impl fmt::Display for DecisionTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} version {} (class {}, {}), {} records, source sha256 {}",
            self.id,
            self.version,
            self.class,
            self.dialect.as_str(),
            self.rows.len(),
            self.source_sha256
        )?;
        writeln!(f, "decision table ((ID, P, S, T, N), (O)):")?;
        let opt = |o: &Option<String>| o.clone().unwrap_or_else(|| "-".into());
        let cells: Vec<[String; 8]> = self
            .rows
            .iter()
            .map(|r| {
                [
                    r.id.to_string(),
                    r.t.clone(),
                    r.n.to_string(),
                    r.scope.clone(),
                    opt(&r.calc_if),
                    opt(&r.calc),
                    opt(&r.out_if),
                    r.output.clone(),
                ]
            })
            .collect();
        let head = ["ID", "T", "N", "scope", "P: when", "S: calc", "P: if", "O"];
        // Long expressions would push O off the screen: the P and S columns are
        // at most this wide, longer cells are cut with `…` (--json has them whole).
        const MAX: usize = 28;
        let mut widths: Vec<usize> = head.iter().map(|h| h.chars().count()).collect();
        for row in &cells {
            for (w, c) in widths.iter_mut().zip(row) {
                *w = (*w).max(c.chars().count());
            }
        }
        for w in &mut widths[4..7] {
            *w = (*w).min(MAX);
        }
        let line = |row: &[String]| {
            let mut s = String::new();
            for (i, (c, w)) in row.iter().zip(&widths).enumerate() {
                if i == 7 {
                    s.push_str(c);
                } else {
                    let c = cut(c, *w);
                    if i == 0 || i == 2 {
                        s.push_str(&format!("{c:>w$}  "));
                    } else {
                        s.push_str(&format!("{c:<w$}  "));
                    }
                }
            }
            s.trim_end().to_string()
        };
        let head: Vec<String> = head.iter().map(|h| h.to_string()).collect();
        writeln!(f, "{}", line(&head))?;
        for row in &cells {
            writeln!(f, "{}", line(row))?;
        }
        Ok(())
    }
}

/// `s` cut to `width` characters, the last one `…` when cut.
pub(super) fn cut(s: &str, width: usize) -> String {
    if s.chars().count() <= width {
        return s.to_string();
    }
    let mut out: String = s.chars().take(width.saturating_sub(1)).collect();
    out.push('…');
    out
}
