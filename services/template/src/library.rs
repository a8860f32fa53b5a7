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

/// Schema migrations in order; the index + 1 is the schema version.
const MIGRATIONS: &[&str] = &[r#"
CREATE TABLE components (
    id       INTEGER PRIMARY KEY,
    dialect  TEXT NOT NULL,
    module   TEXT NOT NULL CHECK (module IN ('main', 'preparation', 'synchronous', 'shift', 'conditions', 'motion')),
    kind     TEXT NOT NULL CHECK (kind IN ('similar', 'non_similar')),
    class    TEXT,
    scope    TEXT NOT NULL CHECK (scope IN ('part', 'unit', 'cut', 'move')),
    calc_if  TEXT,
    calc     TEXT,
    out_if   TEXT,
    output   TEXT NOT NULL,
    text     TEXT NOT NULL,
    CHECK ((kind = 'similar') = (class IS NULL))
);
CREATE UNIQUE INDEX components_text ON components (dialect, kind, IFNULL(class, ''), text);
CREATE TABLE template_versions (
    template        TEXT NOT NULL,
    class           TEXT NOT NULL,
    dialect         TEXT NOT NULL,
    version         INTEGER NOT NULL CHECK (version >= 1),
    source_sha256   TEXT NOT NULL,
    source          TEXT NOT NULL,
    imported_at_ms  INTEGER NOT NULL,
    PRIMARY KEY (template, version)
);
CREATE TABLE records (
    template   TEXT NOT NULL,
    version    INTEGER NOT NULL,
    id         INTEGER NOT NULL CHECK (id >= 1),
    component  INTEGER NOT NULL REFERENCES components (id),
    module     TEXT NOT NULL,
    kind       TEXT NOT NULL CHECK (kind IN ('similar', 'non_similar')),
    n          INTEGER NOT NULL CHECK (n >= 1),
    line       INTEGER NOT NULL,
    PRIMARY KEY (template, version, id),
    UNIQUE (template, version, module, n),
    FOREIGN KEY (template, version) REFERENCES template_versions (template, version)
);
CREATE INDEX records_component ON records (component);
CREATE VIEW decision_table AS
SELECT r.template AS template,
       r.version AS version,
       r.id AS id,
       c.output AS o,
       c.calc_if AS calc_if,
       c.calc AS calc,
       c.out_if AS out_if,
       r.module || ', ' || CASE r.kind WHEN 'similar' THEN 'similar' ELSE 'non-similar' END AS t,
       r.n AS n,
       c.scope AS scope,
       r.component AS component,
       r.line AS line,
       r.module AS module,
       r.kind AS kind
FROM records r JOIN components c ON c.id = r.component;
"#];

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

fn migrate(conn: &mut Connection) -> Result<(), LibraryError> {
    let found: i64 = conn.pragma_query_value(None, "user_version", |r| r.get(0))?;
    let known = MIGRATIONS.len() as i64;
    if found > known {
        return Err(LibraryError::SchemaTooNew { found, known });
    }
    let tx = conn.transaction()?;
    for (i, sql) in MIGRATIONS.iter().enumerate().skip(found as usize) {
        tx.execute_batch(sql)?;
        tx.pragma_update(None, "user_version", (i + 1) as i64)?;
    }
    tx.commit()?;
    Ok(())
}

/// The 1-based line of the `@version` line in a source (0 if none).
fn version_line(source: &str) -> u32 {
    source
        .lines()
        .position(|l| l.trim_start().starts_with("@version"))
        .map_or(0, |i| i as u32 + 1)
}

fn dialect_of(s: &str) -> Option<Dialect> {
    [
        Dialect::Sinumerik840d,
        Dialect::Fanuc,
        Dialect::Linuxcnc,
        Dialect::Wire3b,
    ]
    .into_iter()
    .find(|d| d.as_str() == s)
}

fn corrupt(id: &str, version: u32, what: &str, got: &str) -> LibraryError {
    LibraryError::Corrupt {
        id: id.to_string(),
        version,
        reason: format!("unknown {what} {got:?}"),
    }
}

/// The latest stored version of every template (of one dialect, if given),
/// parsed from its stored source, sorted by id.
fn latest_sources(
    conn: &Connection,
    dialect: Option<Dialect>,
) -> Result<Vec<TemplateFile>, LibraryError> {
    let mut stmt = conn.prepare(
        "SELECT t.template, t.version, t.source FROM template_versions t
         WHERE (?1 IS NULL OR t.dialect = ?1)
           AND t.version = (SELECT max(version) FROM template_versions WHERE template = t.template)
         ORDER BY t.template",
    )?;
    let rows = stmt.query_map([dialect.map(Dialect::as_str)], |r| {
        Ok((
            r.get::<_, String>(0)?,
            r.get::<_, u32>(1)?,
            r.get::<_, String>(2)?,
        ))
    })?;
    let mut out = Vec::new();
    for row in rows {
        let (id, version, source) = row?;
        out.push(
            stdcode::parse(&id, &source).map_err(|e| LibraryError::Corrupt {
                id,
                version,
                reason: format!("the stored source does not parse: {e}"),
            })?,
        );
    }
    Ok(out)
}

/// Splits the latest version of every class of `dialect` into similar and
/// non-similar components again and points their records at them.
fn relink(tx: &Transaction<'_>, dialect: Dialect) -> Result<(), LibraryError> {
    let files = latest_sources(tx, Some(dialect))?;
    let refs: Vec<&TemplateFile> = files.iter().collect();
    let kinds = classify(&refs);
    let mut insert_component = tx.prepare_cached(
        "INSERT OR IGNORE INTO components
         (dialect, module, kind, class, scope, calc_if, calc, out_if, output, text)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10)",
    )?;
    let mut find_component = tx.prepare_cached(
        "SELECT id FROM components
         WHERE dialect = ?1 AND kind = ?2 AND IFNULL(class, '') = IFNULL(?3, '') AND text = ?4",
    )?;
    let mut insert_record = tx.prepare_cached(
        "INSERT INTO records (template, version, id, component, module, kind, n, line)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
    )?;
    for (file, kinds) in files.iter().zip(&kinds) {
        tx.execute(
            "DELETE FROM records WHERE template = ?1 AND version = ?2",
            params![file.id, file.version],
        )?;
        for (r, kind) in file.records.iter().zip(kinds) {
            let class = match kind {
                Kind::Similar => None,
                Kind::NonSimilar => Some(file.class.as_str()),
            };
            let text = r.text();
            let calc = (!r.calc.is_empty()).then(|| {
                r.calc
                    .iter()
                    .map(|(v, e)| format!("{v} = {e}"))
                    .collect::<Vec<_>>()
                    .join("; ")
            });
            insert_component.execute(params![
                dialect.as_str(),
                r.module.as_str(),
                kind.as_str(),
                class,
                r.scope.as_str(),
                r.calc_if,
                calc,
                r.out_if,
                r.output,
                text
            ])?;
            let component: i64 = find_component.query_row(
                params![dialect.as_str(), kind.as_str(), class, text],
                |row| row.get(0),
            )?;
            insert_record.execute(params![
                file.id,
                file.version,
                r.id,
                component,
                r.module.as_str(),
                kind.as_str(),
                r.n,
                r.line
            ])?;
        }
    }
    Ok(())
}

fn component_count(conn: &Connection) -> Result<ComponentCount, LibraryError> {
    let count = |kind: Kind| -> Result<usize, LibraryError> {
        Ok(conn.query_row(
            "SELECT count(*) FROM components WHERE kind = ?1",
            [kind.as_str()],
            |r| r.get(0),
        )?)
    };
    Ok(ComponentCount {
        similar: count(Kind::Similar)?,
        non_similar: count(Kind::NonSimilar)?,
    })
}

/// The stored facts of one template version.
struct VersionHead {
    class: String,
    dialect: Dialect,
    version: u32,
    sha: String,
    imported_at_ms: u64,
}

fn version_head(
    conn: &Connection,
    id: &str,
    version: Option<u32>,
) -> Result<VersionHead, LibraryError> {
    let row: Option<(String, String, u32, String, i64)> = conn
        .query_row(
            "SELECT class, dialect, version, source_sha256, imported_at_ms FROM template_versions
             WHERE template = ?1 AND (?2 IS NULL OR version = ?2)
             ORDER BY version DESC LIMIT 1",
            params![id, version],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?, r.get(3)?, r.get(4)?)),
        )
        .optional()?;
    let Some((class, dialect, version, sha, at)) = row else {
        return Err(LibraryError::NotFound {
            id: id.to_string(),
            version,
            available: available(conn)?,
        });
    };
    Ok(VersionHead {
        dialect: dialect_of(&dialect).ok_or_else(|| corrupt(id, version, "dialect", &dialect))?,
        class,
        version,
        sha,
        imported_at_ms: at.max(0) as u64,
    })
}

/// What the library holds, for a "not found" message: `id v1, v2` entries.
fn available(conn: &Connection) -> Result<Vec<String>, LibraryError> {
    let mut versions: BTreeMap<String, Vec<u32>> = BTreeMap::new();
    let mut stmt =
        conn.prepare("SELECT template, version FROM template_versions ORDER BY template, version")?;
    for row in stmt.query_map([], |r| Ok((r.get::<_, String>(0)?, r.get::<_, u32>(1)?)))? {
        let (id, v) = row?;
        versions.entry(id).or_default().push(v);
    }
    Ok(versions
        .into_iter()
        .map(|(id, vs)| {
            let vs: Vec<String> = vs.iter().map(|v| format!("v{v}")).collect();
            format!("{id} {}", vs.join(" "))
        })
        .collect())
}

/// docs/programs.md#standard-templates assembly from the stored components.
fn assemble(
    conn: &Connection,
    id: &str,
    version: Option<u32>,
) -> Result<TemplateFile, LibraryError> {
    let head = version_head(conn, id, version)?;
    let version = head.version;
    let bad = |reason: String| LibraryError::Corrupt {
        id: id.to_string(),
        version,
        reason,
    };
    let mut stmt = conn.prepare_cached(
        "SELECT r.id, r.n, r.line, c.text, c.kind FROM records r JOIN components c ON c.id = r.component
         WHERE r.template = ?1 AND r.version = ?2 AND r.module = ?3
           AND (c.kind = 'similar' OR c.class = ?4)
         ORDER BY r.n",
    )?;
    let mut records: Vec<Record> = Vec::new();
    for module in Module::ALL {
        // The module's similar and non-similar components, by N.
        let rows = stmt.query_map(params![id, version, module.as_str(), head.class], |r| {
            Ok((
                r.get::<_, u32>(0)?,
                r.get::<_, u32>(1)?,
                r.get::<_, u32>(2)?,
                r.get::<_, String>(3)?,
            ))
        })?;
        for (expected_n, row) in (1u32..).zip(rows) {
            let (rid, n, line, text) = row?;
            if n != expected_n {
                return Err(bad(format!(
                    "module {module}: expected N {expected_n}, got N {n} (record {rid})"
                )));
            }
            let mut record = parse_record(&text).map_err(|(expected, got)| {
                bad(format!(
                    "component {text:?}: expected {expected}, got {got}"
                ))
            })?;
            if record.module != module {
                return Err(bad(format!(
                    "record {rid}: expected a {module} component, got {text:?}"
                )));
            }
            record.id = rid;
            record.n = n;
            record.line = line;
            records.push(record);
        }
    }
    // Then the records of all modules in ID order.
    records.sort_by_key(|r| r.id);
    for (expected, r) in (1u32..).zip(&records) {
        if r.id != expected {
            return Err(bad(format!(
                "expected record ID {expected}, got {} (a record is missing or points at another class's component)",
                r.id
            )));
        }
    }
    if records.is_empty() {
        return Err(bad("no records".into()));
    }
    Ok(TemplateFile {
        id: id.to_string(),
        class: head.class,
        dialect: head.dialect,
        version,
        records,
    })
}

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
fn cut(s: &str, width: usize) -> String {
    if s.chars().count() <= width {
        return s.to_string();
    }
    let mut out: String = s.chars().take(width.saturating_sub(1)).collect();
    out.push('…');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn source(class: &str, version: u32, body: &str) -> String {
        format!(
            "# test template\n@template {class}_840d\n@class {class}\n@dialect sinumerik840d\n@version {version}\n{body}"
        )
    }

    const CYL: &str = "main :: %{program.file}\n\
        main :: ;$PATH=/_N_MPF_DIR\n\
        conditions if: options.coolant :: {N()} M{mc.coolant_on} ; COOLANT ON\n\
        synchronous/unit :: {N()} R1={nc(u.module)}\n\
        motion/move calc: w = \" X=\" + nc(m.x); v = \"a; b\" if: m.kind == \"rapid\" :: {N()} G0 G90{w}\n\
        motion/move if: m.kind == \"feed\" :: {N()} G1 G94{w} F={nc(m.feed)}\n\
        conditions if: options.coolant :: {N()} M{mc.coolant_off}\n\
        main :: {N()} M30\n";

    const CON: &str = "main :: %{program.file}\n\
        main :: ;$PATH=/_N_MPF_DIR\n\
        main :: ; CONE ANGLE {deg(cone)}\n\
        conditions if: options.coolant :: {N()} M{mc.coolant_on} ; COOLANT ON\n\
        synchronous/unit :: {N()} R1={nc(u.module)}\n\
        motion/move when: has(m.x) calc: w = \" X=\" + nc(m.x) :: {N()} G1 G94{w} F={nc(m.feed)}\n\
        main :: {N()} M30\n";

    fn file(text: &str) -> TemplateFile {
        stdcode::parse("test.tpl", text).unwrap()
    }

    fn count(lib: &Library, sql: &str) -> i64 {
        lib.conn.query_row(sql, [], |r| r.get(0)).unwrap()
    }

    fn import(lib: &mut Library, texts: &[&str]) -> Result<ImportReport, LibraryError> {
        let files: Vec<TemplateFile> = texts.iter().map(|t| file(t)).collect();
        lib.import(&files, texts, 1_700_000_000_000)
    }

    #[test]
    fn two_classes_share_their_similar_lines_and_assemble_back_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let mut lib = Library::open(&dir.path().join("data/templates.db")).unwrap();
        assert_eq!(lib.schema_version().unwrap(), 1);
        let (cyl, con) = (source("cylindrical", 1, CYL), source("conical", 1, CON));
        let report = import(&mut lib, &[&cyl, &con]).unwrap();
        assert_eq!(report.added.len(), 2);
        assert!(report.skipped.is_empty());

        // Shared by both: main %, main $PATH, coolant on, R1, M30 = 5 similar
        // components stored once. Own: cylindrical's 2 moves + coolant off,
        // conical's cone line + move = 5.
        assert_eq!(
            count(
                &lib,
                "SELECT count(*) FROM components WHERE kind = 'similar'"
            ),
            5
        );
        assert_eq!(
            count(&lib, "SELECT count(*) FROM components WHERE kind = 'similar' AND text = 'main :: {N()} M30'"),
            1
        );
        assert_eq!(
            count(
                &lib,
                "SELECT count(*) FROM components WHERE kind = 'non_similar'"
            ),
            5
        );
        assert_eq!(count(&lib, "SELECT count(*) FROM records"), 15);
        assert_eq!(
            report.components,
            ComponentCount {
                similar: 5,
                non_similar: 5
            }
        );
        // The analysis agrees with the database row for row.
        let total = report.similarity.dialects[0].total;
        assert_eq!(
            (total.lines, total.lines_stored, total.lines_saved),
            (15, 10, 5)
        );

        // Assembly gives back the parsed sources exactly (ID, N, line, clauses).
        assert_eq!(lib.assemble("cylindrical_840d", None).unwrap(), file(&cyl));
        assert_eq!(lib.assemble("conical_840d", Some(1)).unwrap(), file(&con));
        assert_eq!(lib.latest_versions().unwrap(), vec![file(&con), file(&cyl)]);

        // The decision table names T as "module, kind" and keeps S `;`-joined.
        let table = lib.show("cylindrical_840d", None).unwrap();
        assert_eq!(table.rows.len(), 8);
        let r5 = &table.rows[4];
        assert_eq!(r5.t, "motion, non-similar");
        assert_eq!((r5.id, r5.n, r5.scope.as_str()), (5, 1, "move"));
        assert_eq!(
            r5.calc.as_deref(),
            Some("w = \" X=\" + nc(m.x); v = \"a; b\"")
        );
        assert_eq!(r5.out_if.as_deref(), Some("m.kind == \"rapid\""));
        assert_eq!(table.rows[7].t, "main, similar");
        assert_eq!(table.rows[7].n, 3);
        let shown = table.to_string();
        assert!(
            shown.contains(
                "cylindrical_840d version 1 (class cylindrical, sinumerik840d), 8 records"
            ),
            "{shown}"
        );

        let list = lib.list().unwrap();
        assert_eq!(list.len(), 2);
        assert_eq!(list[1].id, "cylindrical_840d");
        assert_eq!(
            (
                list[1].version,
                list[1].records,
                list[1].similar,
                list[1].non_similar
            ),
            (1, 8, 5, 3)
        );
        assert_eq!(list[1].versions, vec![1]);
    }

    #[test]
    fn versions_unchanged_skipped_unbumped_refused_bumped_kept_beside() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("templates.db");
        let mut lib = Library::open(&path).unwrap();
        let (cyl, con) = (source("cylindrical", 1, CYL), source("conical", 1, CON));
        import(&mut lib, &[&cyl, &con]).unwrap();

        // Unchanged: skipped, nothing written.
        let again = import(&mut lib, &[&cyl, &con]).unwrap();
        assert!(again.added.is_empty());
        assert_eq!(again.skipped.len(), 2);
        assert_eq!(count(&lib, "SELECT count(*) FROM template_versions"), 2);

        // Changed text, same @version: refused, naming template, line and versions.
        let changed = source("cylindrical", 1, &CYL.replace("M30", "M2"));
        let e = import(&mut lib, &[&changed]).unwrap_err();
        assert!(
            matches!(e, LibraryError::VersionNotBumped { ref id, line: 5, stored: 1, given: 1 } if id == "cylindrical_840d"),
            "{e:?}"
        );
        let msg = e.to_string();
        assert!(
            msg.contains("template cylindrical_840d, line 5")
                && msg.contains("expected @version 2 or higher, got @version 1: bump @version"),
            "{msg}"
        );

        // Bumped: version 2 beside 1.
        let v2 = source("cylindrical", 2, &CYL.replace("M30", "M2"));
        let r = import(&mut lib, &[&v2, &con]).unwrap();
        assert_eq!(
            r.added,
            vec![Added {
                id: "cylindrical_840d".into(),
                version: 2,
                previous: Some(1),
                records: 8
            }]
        );
        assert_eq!(r.skipped.len(), 1);
        assert_eq!(lib.assemble("cylindrical_840d", None).unwrap(), file(&v2));
        assert_eq!(
            lib.assemble("cylindrical_840d", Some(1)).unwrap(),
            file(&cyl)
        );
        assert_eq!(lib.list().unwrap()[1].versions, vec![1, 2]);
        // M30 is now conical's alone: a non-similar component of conical;
        // version 1 of cylindrical still uses the similar M30, so it stays too.
        assert_eq!(
            count(
                &lib,
                "SELECT count(*) FROM components WHERE text = 'main :: {N()} M30'"
            ),
            2
        );
        assert_eq!(
            lib.show("conical_840d", None).unwrap().rows[6].t,
            "main, non-similar"
        );

        // An older version than the library's latest: refused.
        let e = import(&mut lib, &[&source("cylindrical", 1, "main :: M2\n")]).unwrap_err();
        assert!(
            matches!(
                e,
                LibraryError::VersionBehind {
                    stored: 2,
                    given: 1,
                    ..
                }
            ),
            "{e:?}"
        );

        // Reopening keeps everything; the schema is not migrated twice.
        drop(lib);
        let lib = Library::open(&path).unwrap();
        assert_eq!(lib.assemble("cylindrical_840d", None).unwrap().version, 2);
        assert_eq!(lib.schema_version().unwrap(), 1);
    }

    #[test]
    fn a_line_a_new_version_shares_becomes_similar_for_the_other_class_too() {
        let dir = tempfile::tempdir().unwrap();
        let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
        let (cyl, con) = (source("cylindrical", 1, CYL), source("conical", 1, CON));
        import(&mut lib, &[&cyl, &con]).unwrap();
        let cone = "main :: ; CONE ANGLE {deg(cone)}";
        let sql = format!("SELECT count(*) FROM components WHERE text = '{cone}'");
        assert_eq!(count(&lib, &sql), 1);
        assert_eq!(
            lib.show("conical_840d", None).unwrap().rows[2].t,
            "main, non-similar"
        );

        // Cylindrical version 2 gets conical's own line: it is stored once, as
        // a similar component, and conical's record points at it; conical's
        // non-similar copy is gone and conical still assembles to its source.
        let v2 = source("cylindrical", 2, &format!("{cone}\n{CYL}"));
        let r = import(&mut lib, &[&v2]).unwrap();
        assert_eq!(r.added.len(), 1);
        assert_eq!(count(&lib, &sql), 1);
        assert_eq!(count(&lib, &format!("{sql} AND kind = 'similar'")), 1);
        assert_eq!(
            lib.show("conical_840d", None).unwrap().rows[2].t,
            "main, similar"
        );
        assert_eq!(lib.assemble("conical_840d", None).unwrap(), file(&con));
        assert_eq!(lib.assemble("cylindrical_840d", None).unwrap(), file(&v2));
        assert_eq!(
            lib.assemble("cylindrical_840d", Some(1)).unwrap(),
            file(&cyl)
        );
    }

    #[test]
    fn a_failed_import_stores_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
        let cyl = source("cylindrical", 1, CYL);
        import(&mut lib, &[&cyl]).unwrap();
        let con = source("conical", 1, CON);
        let bad = source("cylindrical", 1, "main :: M2\n");
        assert!(import(&mut lib, &[&con, &bad]).is_err());
        assert_eq!(count(&lib, "SELECT count(*) FROM template_versions"), 1);
        assert!(matches!(
            lib.assemble("conical_840d", None),
            Err(LibraryError::NotFound { .. })
        ));
        // A file given twice, or a file that is not its source's parse.
        assert!(matches!(
            import(&mut lib, &[&con, &con]),
            Err(LibraryError::Duplicate { .. })
        ));
        let e = lib.import(&[file(&con)], &[&cyl], 0).unwrap_err();
        assert!(matches!(e, LibraryError::NotItsSource { .. }), "{e:?}");
    }

    #[test]
    fn not_found_names_what_the_library_holds() {
        let dir = tempfile::tempdir().unwrap();
        let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
        let e = lib.show("spur_840d", None).unwrap_err();
        assert!(e.to_string().contains("no templates"), "{e}");
        import(&mut lib, &[&source("cylindrical", 1, CYL)]).unwrap();
        let e = lib.assemble("cylindrical_840d", Some(4)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "template cylindrical_840d version 4: not in the library; it holds cylindrical_840d v1"
        );
    }

    #[test]
    fn the_shipped_standard_code_assembles_back_from_the_library() {
        let sources = crate::builtin::builtin_sources();
        let files: Vec<TemplateFile> = sources
            .iter()
            .map(|(name, text)| stdcode::parse(name, text).unwrap())
            .collect();
        let texts: Vec<&str> = sources.iter().map(|(_, t)| *t).collect();
        let dir = tempfile::tempdir().unwrap();
        let mut lib = Library::open(&dir.path().join("t.db")).unwrap();
        let report = lib.import(&files, &texts, 0).unwrap();
        assert_eq!(report.added.len(), files.len());
        let mut sorted = files.clone();
        sorted.sort_by(|a, b| a.id.cmp(&b.id));
        assert_eq!(lib.latest_versions().unwrap(), sorted);
        // The library stores exactly the components the analysis counts.
        let stored: usize = report
            .similarity
            .dialects
            .iter()
            .map(|d| d.total.lines_stored)
            .sum();
        assert_eq!(
            report.components.similar + report.components.non_similar,
            stored
        );
    }

    #[test]
    fn a_newer_schema_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.db");
        drop(Library::open(&path).unwrap());
        let conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "user_version", 9).unwrap();
        drop(conn);
        assert!(matches!(
            Library::open(&path),
            Err(LibraryError::SchemaTooNew { found: 9, known: 1 })
        ));
    }
}
