//! The standard module library in SQLite (docs/programs.md#standard-templates; seed 000 §3.1.3–3.1.4).
//!
//! Template source files (`standard/*.tpl`, [`crate::stdcode`]) are imported
//! into one database: every record of every class is a **component** — a
//! *similar* component when another class of the dialect has the same line in
//! the same module (stored once, `class` NULL), a *non-similar* component of
//! its class otherwise ([`crate::similarity`]). Each imported file is a
//! **template version**; its **records** ⟨ID, component, T, N⟩ point at the
//! components, so one class's decision table ((ID, P, S, T, N), (O)) is the
//! `decision_table` view restricted to its template id and version.
//!
//! # Schema (`PRAGMA user_version` 1)
//!
//! - `components(id, dialect, module, kind, class, scope, calc_if, calc,
//!   out_if, output, text)`, `text` (the record's canonical line,
//!   [`Record::text`]) unique per (dialect, kind, class);
//! - `template_versions(template, class, dialect, version, source_sha256,
//!   source, imported_at_ms)`, primary key (template, version);
//! - `records(template, version, id, component, module, kind, n, line)`;
//! - view `decision_table(template, version, id, o, calc_if, calc, out_if, t,
//!   n, scope, component, line, module, kind)` with T written as `"module, similar"` or
//!   `"module, non-similar"`.
//!
//! Versions are never changed once stored. An import re-partitions the
//! latest version of every class of the dialects it touches, so a line a new
//! version shares with another class is stored once from then on; the
//! records of those versions are re-pointed at components with the same text
//! (their content does not change), and components no record uses any more
//! are removed. [`Library::assemble`] gives back exactly the records that were
//! imported; every import checks that before it commits.

use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use gearcam_proto::Dialect;
use rusqlite::{params, Connection, OptionalExtension, Transaction};
use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::similarity::{analyze, classify, module_name, Kind, Report};
use crate::stdcode::{self, parse_record, Module, Record, TemplateFile};

mod report;
mod store;
#[cfg(test)]
mod tests;
use store::*;

/// What can go wrong with the template library. Every message names the
/// template, what was expected and what was found.
#[derive(Debug, thiserror::Error)]
pub enum LibraryError {
    /// The database file cannot be opened or created.
    #[error("cannot open the template library {path}: {source}")]
    Open {
        /// The database file.
        path: PathBuf,
        /// What SQLite said.
        #[source]
        source: rusqlite::Error,
    },
    /// The directory for the database cannot be created.
    #[error("cannot create the directory {path} for the template library: {source}")]
    Io {
        /// The directory.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The database was written by a newer gearcam.
    #[error(
        "the template library has schema version {found}, this gearcam knows up to {known}; \
         use a newer gearcam"
    )]
    SchemaTooNew {
        /// `user_version` found.
        found: i64,
        /// The newest this build knows.
        known: i64,
    },
    /// A query failed.
    #[error("template library: {0}")]
    Db(#[from] rusqlite::Error),
    /// `import` was given a different number of files and sources.
    #[error("import: expected one source text per template file, got {files} file(s) and {sources} source(s)")]
    SourceCount {
        /// Files given.
        files: usize,
        /// Sources given.
        sources: usize,
    },
    /// The same template id twice in one import.
    #[error("import: template {id} is given twice; expected each template once")]
    Duplicate {
        /// The template id.
        id: String,
    },
    /// A parsed file is not what its source text parses to.
    #[error("import: template {id}: the parsed file is not the parse of the source given with it ({reason})")]
    NotItsSource {
        /// The template id.
        id: String,
        /// The parse error, or "records differ".
        reason: String,
    },
    /// The text changed but `@version` did not.
    #[error(
        "template {id}, line {line}: the text differs from version {stored} in the library; \
         expected @version {} or higher, got @version {given}: bump @version",
        stored + 1
    )]
    VersionNotBumped {
        /// The template id.
        id: String,
        /// The `@version` line of the source (0 if not found).
        line: u32,
        /// The latest stored version.
        stored: u32,
        /// The version in the source.
        given: u32,
    },
    /// The source's `@version` is older than the library's latest.
    #[error(
        "template {id}, line {line}: the library already holds version {stored}; \
         expected @version {} or higher, got the older @version {given}",
        stored + 1
    )]
    VersionBehind {
        /// The template id.
        id: String,
        /// The `@version` line of the source (0 if not found).
        line: u32,
        /// The latest stored version.
        stored: u32,
        /// The version in the source.
        given: u32,
    },
    /// No such template or version.
    #[error("template {id}{}: not in the library; it holds {}", .version.map(|v| format!(" version {v}")).unwrap_or_default(), if .available.is_empty() { "no templates (import some with `gearcam templates import`)".to_string() } else { .available.join(", ") })]
    NotFound {
        /// The template id asked for.
        id: String,
        /// The version asked for, if any.
        version: Option<u32>,
        /// What the library holds: `id` or `id v1, v2` entries.
        available: Vec<String>,
    },
    /// Stored rows that do not make a template (a broken or hand-edited database).
    #[error("template {id} version {version} in the library is inconsistent: {reason}")]
    Corrupt {
        /// The template id.
        id: String,
        /// The version.
        version: u32,
        /// What is wrong.
        reason: String,
    },
}

/// The template library: one SQLite database.
#[derive(Debug)]
pub struct Library {
    conn: Connection,
}

/// One stored template: its latest version and what it holds.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct TemplateSummary {
    /// Template id, e.g. `cylindrical_840d`.
    pub id: String,
    /// Gear class.
    pub class: String,
    /// Controller dialect.
    pub dialect: Dialect,
    /// The latest version.
    pub version: u32,
    /// Every stored version, ascending.
    pub versions: Vec<u32>,
    /// Records of the latest version.
    pub records: usize,
    /// Of those, records that are similar components.
    pub similar: usize,
    /// Of those, records that are non-similar components.
    pub non_similar: usize,
    /// SHA-256 of the latest version's source text.
    pub source_sha256: String,
    /// When the latest version was imported (Unix ms, as given to `import`).
    pub imported_at_ms: u64,
}

/// One class's decision table ((ID, P, S, T, N), (O)) for one version.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DecisionTable {
    /// Template id.
    pub id: String,
    /// Gear class.
    pub class: String,
    /// Controller dialect.
    pub dialect: Dialect,
    /// The version shown.
    pub version: u32,
    /// SHA-256 of the version's source text.
    pub source_sha256: String,
    /// When it was imported (Unix ms).
    pub imported_at_ms: u64,
    /// The rows in ID order.
    pub rows: Vec<DecisionRow>,
}

/// A row of a decision table: one record and its component.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DecisionRow {
    /// ID: position in the template.
    pub id: u32,
    /// O: the output expression.
    pub output: String,
    /// P: the calculation condition.
    pub calc_if: Option<String>,
    /// S: the calculation expressions, `;`-joined.
    pub calc: Option<String>,
    /// P: the output condition.
    pub out_if: Option<String>,
    /// T as written in the table: `"motion, non-similar"`.
    pub t: String,
    /// T: the module.
    #[serde(serialize_with = "module_name")]
    pub module: Module,
    /// T: similar or non-similar.
    pub kind: Kind,
    /// N: number within the module.
    pub n: u32,
    /// What the record repeats over: `part`, `unit`, `cut`, `move`.
    pub scope: String,
    /// The component's row id.
    pub component: i64,
    /// Line in the source file.
    pub line: u32,
}

/// What an import did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImportReport {
    /// Templates stored as a new version.
    pub added: Vec<Added>,
    /// Templates whose source equals the latest stored version.
    pub skipped: Vec<Skipped>,
    /// Component rows in the library after the import.
    pub components: ComponentCount,
    /// The similarity analysis of the latest version of every template in the
    /// library after the import.
    pub similarity: Report,
}

/// A template stored as a new version.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Added {
    /// Template id.
    pub id: String,
    /// The version stored.
    pub version: u32,
    /// The version it follows, if the library had one.
    pub previous: Option<u32>,
    /// Its records.
    pub records: usize,
}

/// A template left as it was: its source equals the latest stored version.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Skipped {
    /// Template id.
    pub id: String,
    /// The stored (and given) version.
    pub version: u32,
}

/// Component rows by kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct ComponentCount {
    /// Similar components (stored once for several classes).
    pub similar: usize,
    /// Non-similar components (one class each).
    pub non_similar: usize,
}

impl Library {
    /// Opens (and creates or migrates) the library at `path`, in WAL mode.
    pub fn open(path: &Path) -> Result<Library, LibraryError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| LibraryError::Io {
                path: dir.to_path_buf(),
                source,
            })?;
        }
        let open_err = |source| LibraryError::Open {
            path: path.to_path_buf(),
            source,
        };
        let mut conn = Connection::open(path).map_err(open_err)?;
        conn.pragma_update(None, "journal_mode", "WAL")
            .map_err(open_err)?;
        conn.pragma_update(None, "foreign_keys", "ON")
            .map_err(open_err)?;
        conn.busy_timeout(std::time::Duration::from_secs(5))
            .map_err(open_err)?;
        migrate(&mut conn)?;
        Ok(Library { conn })
    }

    /// The schema version (`PRAGMA user_version`).
    pub fn schema_version(&self) -> Result<i64, LibraryError> {
        Ok(self
            .conn
            .pragma_query_value(None, "user_version", |r| r.get(0))?)
    }

    /// Imports template files, `sources[i]` being the text `files[i]` was
    /// parsed from. All or nothing: on an error nothing is stored.
    ///
    /// A file whose source equals the latest stored version is skipped; a
    /// changed source must carry a higher `@version` and is stored beside the
    /// older versions. The latest versions of every class of the dialects
    /// touched are then split again into similar and non-similar components.
    pub fn import(
        &mut self,
        files: &[TemplateFile],
        sources: &[&str],
        imported_at_ms: u64,
    ) -> Result<ImportReport, LibraryError> {
        if files.len() != sources.len() {
            return Err(LibraryError::SourceCount {
                files: files.len(),
                sources: sources.len(),
            });
        }
        let mut seen = std::collections::BTreeSet::new();
        for (file, source) in files.iter().zip(sources) {
            if !seen.insert(file.id.as_str()) {
                return Err(LibraryError::Duplicate {
                    id: file.id.clone(),
                });
            }
            match stdcode::parse(&file.id, source) {
                Ok(parsed) if parsed == *file => {}
                Ok(_) => {
                    return Err(LibraryError::NotItsSource {
                        id: file.id.clone(),
                        reason: "the records differ".into(),
                    })
                }
                Err(e) => {
                    return Err(LibraryError::NotItsSource {
                        id: file.id.clone(),
                        reason: e.to_string(),
                    })
                }
            }
        }
        let tx = self.conn.transaction()?;
        let mut added = Vec::new();
        let mut skipped = Vec::new();
        let mut touched: Vec<Dialect> = Vec::new();
        for (file, source) in files.iter().zip(sources) {
            let sha = hex::encode(Sha256::digest(source.as_bytes()));
            let latest: Option<(u32, String)> = tx
                .query_row(
                    "SELECT version, source_sha256 FROM template_versions
                     WHERE template = ?1 ORDER BY version DESC LIMIT 1",
                    [&file.id],
                    |r| Ok((r.get(0)?, r.get(1)?)),
                )
                .optional()?;
            let line = version_line(source);
            match latest {
                Some((stored, stored_sha)) if stored_sha == sha => {
                    skipped.push(Skipped {
                        id: file.id.clone(),
                        version: stored,
                    });
                    continue;
                }
                Some((stored, _)) if file.version == stored => {
                    return Err(LibraryError::VersionNotBumped {
                        id: file.id.clone(),
                        line,
                        stored,
                        given: file.version,
                    })
                }
                Some((stored, _)) if file.version < stored => {
                    return Err(LibraryError::VersionBehind {
                        id: file.id.clone(),
                        line,
                        stored,
                        given: file.version,
                    })
                }
                _ => {}
            }
            tx.execute(
                "INSERT INTO template_versions
                 (template, class, dialect, version, source_sha256, source, imported_at_ms)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
                params![
                    file.id,
                    file.class,
                    file.dialect.as_str(),
                    file.version,
                    sha,
                    source,
                    imported_at_ms as i64
                ],
            )?;
            added.push(Added {
                id: file.id.clone(),
                version: file.version,
                previous: latest.map(|(v, _)| v),
                records: file.records.len(),
            });
            if !touched.contains(&file.dialect) {
                touched.push(file.dialect);
            }
        }
        for dialect in touched {
            relink(&tx, dialect)?;
        }
        tx.execute(
            "DELETE FROM components WHERE id NOT IN (SELECT component FROM records)",
            [],
        )?;
        for a in &added {
            let file = files
                .iter()
                .find(|f| f.id == a.id)
                .expect("added from files");
            let back = assemble(&tx, &a.id, Some(a.version))?;
            if back != *file {
                return Err(LibraryError::Corrupt {
                    id: a.id.clone(),
                    version: a.version,
                    reason:
                        "assembling the stored components does not give back the imported records"
                            .into(),
                });
            }
        }
        let similarity = analyze(&latest_sources(&tx, None)?);
        let components = component_count(&tx)?;
        tx.commit()?;
        Ok(ImportReport {
            added,
            skipped,
            components,
            similarity,
        })
    }

    /// Every stored template with its latest version, sorted by id.
    pub fn list(&self) -> Result<Vec<TemplateSummary>, LibraryError> {
        let mut stmt = self.conn.prepare(
            "SELECT t.template, t.class, t.dialect, t.version, t.source_sha256, t.imported_at_ms,
                    (SELECT group_concat(version) FROM
                        (SELECT version FROM template_versions WHERE template = t.template ORDER BY version)),
                    (SELECT count(*) FROM records r WHERE r.template = t.template AND r.version = t.version),
                    (SELECT count(*) FROM records r WHERE r.template = t.template AND r.version = t.version
                        AND r.kind = 'similar')
             FROM template_versions t
             WHERE t.version = (SELECT max(version) FROM template_versions WHERE template = t.template)
             ORDER BY t.template",
        )?;
        let rows = stmt.query_map([], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, String>(2)?,
                r.get::<_, u32>(3)?,
                r.get::<_, String>(4)?,
                r.get::<_, i64>(5)?,
                r.get::<_, String>(6)?,
                r.get::<_, usize>(7)?,
                r.get::<_, usize>(8)?,
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (id, class, dialect, version, sha, at, versions, records, similar) = row?;
            out.push(TemplateSummary {
                dialect: dialect_of(&dialect)
                    .ok_or_else(|| corrupt(&id, version, "dialect", &dialect))?,
                versions: versions.split(',').filter_map(|v| v.parse().ok()).collect(),
                id,
                class,
                version,
                records,
                similar,
                non_similar: records - similar,
                source_sha256: sha,
                imported_at_ms: at.max(0) as u64,
            });
        }
        Ok(out)
    }

    /// Assembles a template from its components (docs/programs.md#standard-templates): the class's similar
    /// and non-similar components per module ordered by N, then all records by
    /// ID. `None`: the latest version. The result equals the parsed source
    /// file record for record.
    pub fn assemble(&self, id: &str, version: Option<u32>) -> Result<TemplateFile, LibraryError> {
        assemble(&self.conn, id, version)
    }

    /// The decision table of a template version (`None`: the latest), in ID
    /// order.
    pub fn show(&self, id: &str, version: Option<u32>) -> Result<DecisionTable, LibraryError> {
        let head = version_head(&self.conn, id, version)?;
        let mut stmt = self.conn.prepare(
            "SELECT id, o, calc_if, calc, out_if, t, n, scope, component, line, module, kind
             FROM decision_table WHERE template = ?1 AND version = ?2 ORDER BY id",
        )?;
        let rows = stmt.query_map(params![id, head.version], |r| {
            Ok((
                DecisionRow {
                    id: r.get(0)?,
                    output: r.get(1)?,
                    calc_if: r.get(2)?,
                    calc: r.get(3)?,
                    out_if: r.get(4)?,
                    t: r.get(5)?,
                    module: Module::Main,
                    kind: Kind::NonSimilar,
                    n: r.get(6)?,
                    scope: r.get(7)?,
                    component: r.get(8)?,
                    line: r.get(9)?,
                },
                r.get::<_, String>(10)?,
                r.get::<_, String>(11)?,
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (mut row, module, kind) = row?;
            row.module = module
                .parse()
                .map_err(|_| corrupt(id, head.version, "module", &module))?;
            row.kind =
                Kind::parse(&kind).ok_or_else(|| corrupt(id, head.version, "kind", &kind))?;
            out.push(row);
        }
        Ok(DecisionTable {
            id: id.to_string(),
            class: head.class,
            dialect: head.dialect,
            version: head.version,
            source_sha256: head.sha,
            imported_at_ms: head.imported_at_ms,
            rows: out,
        })
    }

    /// The latest version of every template, assembled, sorted by id: what
    /// the template service compiles at start.
    pub fn latest_versions(&self) -> Result<Vec<TemplateFile>, LibraryError> {
        let ids: Vec<String> = self
            .conn
            .prepare("SELECT DISTINCT template FROM template_versions ORDER BY template")?
            .query_map([], |r| r.get(0))?
            .collect::<Result<_, _>>()?;
        ids.iter().map(|id| self.assemble(id, None)).collect()
    }

    /// Component rows by kind.
    pub fn component_count(&self) -> Result<ComponentCount, LibraryError> {
        component_count(&self.conn)
    }
}
