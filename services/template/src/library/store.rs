//! The library's SQLite tables: the schema and its migrations, the newest
//! sources, the links between similar components, and the assembly of a
//! template from its components.

use super::*;

/// Schema migrations in order; the index + 1 is the schema version.
pub(super) const MIGRATIONS: &[&str] = &[r#"
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

pub(super) fn migrate(conn: &mut Connection) -> Result<(), LibraryError> {
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
pub(super) fn version_line(source: &str) -> u32 {
    source
        .lines()
        .position(|l| l.trim_start().starts_with("@version"))
        .map_or(0, |i| i as u32 + 1)
}

pub(super) fn dialect_of(s: &str) -> Option<Dialect> {
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

pub(super) fn corrupt(id: &str, version: u32, what: &str, got: &str) -> LibraryError {
    LibraryError::Corrupt {
        id: id.to_string(),
        version,
        reason: format!("unknown {what} {got:?}"),
    }
}

/// The latest stored version of every template (of one dialect, if given),
/// parsed from its stored source, sorted by id.
pub(super) fn latest_sources(
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
pub(super) fn relink(tx: &Transaction<'_>, dialect: Dialect) -> Result<(), LibraryError> {
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

pub(super) fn component_count(conn: &Connection) -> Result<ComponentCount, LibraryError> {
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
pub(super) struct VersionHead {
    pub(super) class: String,
    pub(super) dialect: Dialect,
    pub(super) version: u32,
    pub(super) sha: String,
    pub(super) imported_at_ms: u64,
}

pub(super) fn version_head(
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
pub(super) fn available(conn: &Connection) -> Result<Vec<String>, LibraryError> {
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
pub(super) fn assemble(
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
