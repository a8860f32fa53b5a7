//! Rebuilding a lost program index from the program files and their
//! headers (the recovery the agent names when it refuses to start on an
//! index that was there and is now missing or empty).
//!
//! Every program gearcam writes names its job and part in its header
//! (`; JOB …` / `; PART …` on 840D, `(JOB …)` / `(PART …)` on FANUC). The
//! rebuilt index holds one `rebuilt` version per program file, with that job
//! and part, so the program names keep their parts and the next delivery to
//! a file is checked against what is there. The lost index is kept beside,
//! renamed, for whoever wants to look at it.

use std::fs;

use gearcam_proto::{naming, now_ms, Dialect};
use rusqlite::params;

use super::{sha256_hex, Store, StoreConfig};
use crate::AgentError;

/// What a rebuild found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rebuilt {
    /// Program files indexed.
    pub programs: usize,
    /// Files in the directory that are not programs of this controller
    /// (left alone, not indexed).
    pub skipped: Vec<String>,
    /// Where the lost index was moved, if there was one.
    pub moved_to: Option<String>,
}

impl Store {
    /// Moves the lost index aside, opens a fresh one and indexes every
    /// program file of the directory from its header.
    pub fn rebuild(config: StoreConfig) -> Result<Rebuilt, AgentError> {
        let io = |path: &std::path::Path, e: std::io::Error| AgentError::Io {
            path: path.display().to_string(),
            source: e,
        };
        let mut moved_to = None;
        if config.index_path.exists() {
            let aside = config
                .index_path
                .with_extension(format!("lost-{}", now_ms()));
            fs::rename(&config.index_path, &aside).map_err(|e| io(&config.index_path, e))?;
            moved_to = Some(aside.display().to_string());
        }
        for suffix in ["-wal", "-shm"] {
            let mut side = config.index_path.as_os_str().to_owned();
            side.push(suffix);
            let _ = fs::remove_file(side);
        }
        let marker = gearcam_bus::durable::marker_of(&config.index_path);
        if marker.exists() {
            fs::remove_file(&marker).map_err(|e| io(&marker, e))?;
        }
        let store = Store::open(config)?;
        let dir = store.config.program_dir.clone();
        let mut entries: Vec<String> = fs::read_dir(&dir)
            .map_err(|e| io(&dir, e))?
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| !n.starts_with('.'))
            .collect();
        entries.sort();
        let (mut programs, mut skipped) = (0, Vec::new());
        for file_name in entries {
            let Some(name) = program_name(store.config.dialect, &file_name) else {
                skipped.push(file_name);
                continue;
            };
            let path = dir.join(&file_name);
            let Ok(text) = fs::read_to_string(&path) else {
                skipped.push(file_name);
                continue;
            };
            let job = header(&text, "JOB").unwrap_or_else(|| "UNKNOWN".to_string());
            let part = header(&text, "PART").unwrap_or_default();
            store.conn.execute(
                "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part, by_user)
                 VALUES (?1, ?2, ?3, 1, ?4, ?5, ?6, ?7, 'rebuilt', ?8, ?9, 'rebuild')",
                params![
                    name,
                    file_name,
                    job,
                    sha256_hex(text.as_bytes()),
                    text.len() as i64,
                    store.config.dialect.as_str(),
                    now_ms() as i64,
                    text,
                    part
                ],
            )?;
            programs += 1;
        }
        Ok(Rebuilt {
            programs,
            skipped,
            moved_to,
        })
    }
}

/// The program name of a file under the controller's naming rule, if the
/// file is one of its programs.
fn program_name(dialect: Dialect, file_name: &str) -> Option<String> {
    let name = match dialect {
        Dialect::Sinumerik840d => file_name.strip_prefix("_N_")?.strip_suffix("_MPF")?,
        Dialect::Fanuc | Dialect::WireIso => file_name,
        Dialect::Linuxcnc => file_name.strip_suffix(".ngc")?,
        // A 4B program's name keeps its `.4b`.
        Dialect::Wire3b if file_name.ends_with(".4b") => file_name,
        Dialect::Wire3b => file_name.strip_suffix(".3b")?,
    };
    (naming::file_name(dialect, name).ok()? == file_name).then(|| name.to_string())
}

/// The value of a header comment line `; KEY value` or `(KEY value)`.
fn header(text: &str, key: &str) -> Option<String> {
    text.lines().take(40).find_map(|line| {
        let line = line.trim();
        let body = line
            .strip_prefix(';')
            .or_else(|| line.strip_prefix('(').and_then(|l| l.strip_suffix(')')))?;
        let value = body.trim_start().strip_prefix(key)?.strip_prefix(' ')?;
        Some(value.trim().to_string()).filter(|v| !v.is_empty())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_and_names_are_read_back() {
        let text = "%_N_SP_1_MPF\n;$PATH=/_N_MPF_DIR\n; JOB SP-1-42\n; PART SP-1\nN10 M2\n";
        assert_eq!(header(text, "JOB").as_deref(), Some("SP-1-42"));
        assert_eq!(header(text, "PART").as_deref(), Some("SP-1"));
        let fanuc = "%\nO2107 (HG-2107 HOBBING)\n(JOB HG-2107-7)\n(PART HG-2107)\nM30\n%\n";
        assert_eq!(header(fanuc, "JOB").as_deref(), Some("HG-2107-7"));
        assert_eq!(header(fanuc, "PART").as_deref(), Some("HG-2107"));
        assert_eq!(
            program_name(Dialect::Sinumerik840d, "_N_SP_1_MPF").as_deref(),
            Some("SP_1")
        );
        assert_eq!(program_name(Dialect::Sinumerik840d, "notes.txt"), None);
        assert_eq!(
            program_name(Dialect::Fanuc, "O2107").as_deref(),
            Some("O2107")
        );
        assert_eq!(program_name(Dialect::Fanuc, "O9001"), None);
    }

    /// An index emptied by a fault is not taken as a fresh one, which would
    /// forget the whole history silently: it is refused and rebuilt from the
    /// files.
    #[test]
    fn an_emptied_index_is_refused_and_rebuilt_from_the_files() {
        let dir = tempfile::tempdir().unwrap();
        let config = super::super::tests::store(dir.path()).config().clone();
        {
            let mut s = Store::open(config.clone()).unwrap();
            let mut p = super::super::tests::program(
                "J1",
                "SP_1",
                "%_N_SP_1_MPF\n; JOB J1\n; PART P-1\nM2\n",
            );
            p.part_number = "P-1".into();
            s.store(&p).unwrap();
        }
        fs::write(&config.index_path, b"").unwrap();
        for suffix in ["-wal", "-shm"] {
            let mut side = config.index_path.as_os_str().to_owned();
            side.push(suffix);
            let _ = fs::remove_file(side);
        }
        let e = Store::open(config.clone()).unwrap_err().to_string();
        assert!(
            e.contains("is empty") && e.contains("--rebuild-index"),
            "{e}"
        );
        fs::write(dir.path().join("programs/notes.txt"), "not a program").unwrap();
        let r = Store::rebuild(config.clone()).unwrap();
        assert_eq!(
            (r.programs, r.skipped.as_slice()),
            (1, ["notes.txt".to_string()].as_slice())
        );
        let s = Store::open(config).unwrap();
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(
            (
                h[0].job.as_str(),
                h[0].part_number.as_str(),
                h[0].state.as_str()
            ),
            ("J1", "P-1", "rebuilt")
        );
    }
}
