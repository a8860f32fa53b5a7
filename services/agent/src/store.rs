//! The machine's part-program store: program files in the directory the
//! controller reads, plus an SQLite index. Writes are atomic and durable
//! before a receipt is given.
//!
//! Order of a write: temporary file in the same directory, write, fsync,
//! rename over the final name, fsync the directory, then the index row in a
//! synchronous (FULL) SQLite transaction. A repeat of the same job + revision +
//! hash is answered with the original receipt; a program changed at the
//! machine (file hash differs from the index) is never overwritten.

use std::fs::{self, File};
use std::io::Write;
use std::path::{Path, PathBuf};

use gearcam_proto::{
    naming, now_ms, DeliveryReceipt, Dialect, JobError, MachineId, NcProgram, ProgramText,
    ProgramVersion, Stage,
};
use rusqlite::{params, Connection, OptionalExtension};
use sha2::{Digest, Sha256};

use crate::AgentError;

mod owner;
mod resolve;

pub use resolve::Resolution;

/// Largest program the store accepts, bytes.
pub const MAX_PROGRAM_BYTES: usize = 1024 * 1024;

/// Configuration of a store.
#[derive(Debug, Clone)]
pub struct StoreConfig {
    /// The machine this store belongs to.
    pub machine: MachineId,
    /// The controller's dialect (decides the naming rule).
    pub dialect: Dialect,
    /// Directory the controller reads programs from.
    pub program_dir: PathBuf,
    /// SQLite index file.
    pub index_path: PathBuf,
}

/// A machine's program store.
#[derive(Debug)]
pub struct Store {
    config: StoreConfig,
    conn: Connection,
}

/// Lowercase hex SHA-256 of bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    hex::encode(Sha256::digest(bytes))
}

impl Store {
    /// Opens (creating if needed) the store.
    pub fn open(config: StoreConfig) -> Result<Store, AgentError> {
        let io = |p: &Path| {
            let p = p.display().to_string();
            move |e| AgentError::Io { path: p, source: e }
        };
        fs::create_dir_all(&config.program_dir).map_err(io(&config.program_dir))?;
        if let Some(dir) = config.index_path.parent() {
            fs::create_dir_all(dir).map_err(io(dir))?;
        }
        let conn = Connection::open(&config.index_path)?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "FULL")?;
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS programs (
                 seq          INTEGER PRIMARY KEY AUTOINCREMENT,
                 name         TEXT NOT NULL,
                 file_name    TEXT NOT NULL,
                 job          TEXT NOT NULL,
                 revision     INTEGER NOT NULL,
                 sha256       TEXT NOT NULL,
                 size_bytes   INTEGER NOT NULL,
                 dialect      TEXT NOT NULL,
                 stored_at_ms INTEGER NOT NULL,
                 state        TEXT NOT NULL,
                 text         TEXT NOT NULL
             );
             CREATE UNIQUE INDEX IF NOT EXISTS programs_by_job ON programs (job, revision) WHERE state = 'stored';
             CREATE INDEX IF NOT EXISTS programs_by_file ON programs (file_name, seq);",
        )?;
        // Columns added after the first release: the part a program name
        // belongs to, and who resolved an edit at the machine.
        for (column, decl) in [
            ("part", "TEXT NOT NULL DEFAULT ''"),
            ("by_user", "TEXT NOT NULL DEFAULT ''"),
        ] {
            let has: bool = conn
                .prepare("SELECT 1 FROM pragma_table_info('programs') WHERE name = ?1")?
                .exists([column])?;
            if !has {
                conn.execute_batch(&format!("ALTER TABLE programs ADD COLUMN {column} {decl}"))?;
            }
        }
        remove_stale_temporaries(&config.program_dir);
        Ok(Store { config, conn })
    }

    /// The store's configuration.
    pub fn config(&self) -> &StoreConfig {
        &self.config
    }

    fn receipt_from_row(
        &self,
        r: &rusqlite::Row<'_>,
        duplicate: bool,
    ) -> rusqlite::Result<DeliveryReceipt> {
        let file_name: String = r.get("file_name")?;
        Ok(DeliveryReceipt {
            job_id: gearcam_proto::JobId::new(r.get::<_, String>("job")?).map_err(|e| {
                rusqlite::Error::FromSqlConversionFailure(
                    0,
                    rusqlite::types::Type::Text,
                    Box::new(e),
                )
            })?,
            machine: self.config.machine.clone(),
            name: r.get("name")?,
            path: self
                .config
                .program_dir
                .join(&file_name)
                .display()
                .to_string(),
            file_name,
            revision: r.get("revision")?,
            sha256: r.get("sha256")?,
            size_bytes: r.get::<_, i64>("size_bytes")? as u64,
            stored_at_ms: r.get::<_, i64>("stored_at_ms")? as u64,
            duplicate,
        })
    }

    /// Validates and stores a program; returns the receipt once the file and
    /// the index row are durable, or a typed refusal.
    pub fn store(&mut self, p: &NcProgram) -> Result<DeliveryReceipt, JobError> {
        self.store_batch(std::slice::from_ref(p))
            .pop()
            .expect("one result per program")
    }

    /// Stores several programs with one group commit: every file is written
    /// and fsynced (in parallel), renamed, the directory fsynced once, and all
    /// index rows inserted in one transaction; each result is as [`Store::store`]
    /// would give it alone. Programs that touch a file or job already pending
    /// in the batch are committed in a later group, so order is kept.
    pub fn store_batch(
        &mut self,
        programs: &[NcProgram],
    ) -> Vec<Result<DeliveryReceipt, JobError>> {
        let mut results: Vec<Option<Result<DeliveryReceipt, JobError>>> =
            vec![None; programs.len()];
        let mut pending: Vec<Pending> = Vec::new();
        for (i, p) in programs.iter().enumerate() {
            let clashes = pending.iter().any(|q| {
                let q = &programs[q.index];
                q.name == p.name || (q.job_id == p.job_id && q.revision == p.revision)
            });
            if clashes {
                self.flush(programs, std::mem::take(&mut pending), &mut results);
            }
            match self.prepare(p) {
                Ok(Prepared::Stored(receipt)) => results[i] = Some(Ok(receipt)),
                Ok(Prepared::Write { file_name, hash }) => pending.push(Pending {
                    index: i,
                    file_name,
                    hash,
                }),
                Err(e) => results[i] = Some(Err(e)),
            }
        }
        self.flush(programs, pending, &mut results);
        results
            .into_iter()
            .map(|r| r.expect("every program has a result"))
            .collect()
    }

    /// Checks a program and decides whether it must be written.
    fn prepare(&self, p: &NcProgram) -> Result<Prepared, JobError> {
        if p.machine != self.config.machine {
            return Err(Stage::Agent.error(
                "WRONG_MACHINE",
                "machine",
                self.config.machine.to_string(),
                p.machine.to_string(),
                "this agent stores programs for its own machine only",
            ));
        }
        if p.dialect != self.config.dialect {
            return Err(Stage::Agent.error(
                "WRONG_DIALECT",
                "dialect",
                self.config.dialect.as_str(),
                p.dialect.as_str(),
                "the program is written for another controller",
            ));
        }
        let file_name = naming::file_name(p.dialect, &p.name).map_err(|rule| {
            Stage::Agent.error(
                "BAD_PROGRAM_NAME",
                "name",
                rule.clone(),
                p.name.clone(),
                format!("program name refused: {rule}"),
            )
        })?;
        if p.text.len() > MAX_PROGRAM_BYTES {
            return Err(Stage::Agent.error(
                "PROGRAM_TOO_LARGE",
                "text",
                format!("at most {MAX_PROGRAM_BYTES} bytes"),
                format!("{} bytes", p.text.len()),
                "the program exceeds the store's size limit",
            ));
        }
        let hash = sha256_hex(p.text.as_bytes());
        if hash != p.sha256 {
            return Err(Stage::Agent.error(
                "HASH_MISMATCH",
                "sha256",
                hash,
                p.sha256.clone(),
                "the program text does not match its hash; it was damaged on the way",
            ));
        }
        // Idempotency: the same job and revision.
        let existing = self
            .conn
            .query_row(
                "SELECT * FROM programs WHERE job = ?1 AND revision = ?2 AND state = 'stored'",
                params![p.job_id.as_str(), p.revision],
                |r| {
                    Ok((
                        r.get::<_, String>("sha256")?,
                        self.receipt_from_row(r, true)?,
                    ))
                },
            )
            .optional()
            .map_err(index_error)?;
        if let Some((stored_hash, receipt)) = existing {
            if stored_hash == hash {
                return Ok(Prepared::Stored(receipt));
            }
            return Err(Stage::Agent.error(
                "REVISION_CONFLICT",
                "revision",
                format!("content with sha256 {stored_hash}"),
                format!("sha256 {hash}"),
                "this job revision was already stored with different content; send a new revision",
            ));
        }
        // A program name belongs to one part.
        self.check_owner(p, &file_name)?;
        // A program changed at the machine is never overwritten silently.
        self.check_unchanged_at_machine(&file_name, &hash)?;
        Ok(Prepared::Write { file_name, hash })
    }

    /// Writes the pending programs durably and records them in one transaction.
    fn flush(
        &mut self,
        programs: &[NcProgram],
        pending: Vec<Pending>,
        results: &mut [Option<Result<DeliveryReceipt, JobError>>],
    ) {
        if pending.is_empty() {
            return;
        }
        let dir = self.config.program_dir.clone();
        let io_error = |file_name: &str, e: std::io::Error| {
            Stage::Agent.error(
                "STORE_IO_ERROR",
                "-",
                "a writable program directory",
                e.to_string(),
                format!("cannot write {}", dir.join(file_name).display()),
            )
        };
        // Temporary files written and fsynced in parallel: concurrent fsyncs
        // share the file system's journal commits.
        let written: Vec<std::io::Result<PathBuf>> = std::thread::scope(|scope| {
            let handles: Vec<_> = pending
                .chunks(pending.len().div_ceil(8))
                .map(|chunk| {
                    let dir = &dir;
                    scope.spawn(move || {
                        chunk
                            .iter()
                            .map(|q| {
                                write_temp(dir, &q.file_name, programs[q.index].text.as_bytes())
                            })
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            handles
                .into_iter()
                .flat_map(|h| {
                    h.join().unwrap_or_else(|_| {
                        vec![Err(std::io::Error::other("writer thread panicked"))]
                    })
                })
                .collect()
        });
        let mut renamed = Vec::new();
        for (q, tmp) in pending.into_iter().zip(written) {
            match tmp.and_then(|tmp| fs::rename(&tmp, dir.join(&q.file_name))) {
                Ok(()) => renamed.push(q),
                Err(e) => results[q.index] = Some(Err(io_error(&q.file_name, e))),
            }
        }
        if let Err(e) = File::open(&dir).and_then(|d| d.sync_all()) {
            for q in renamed {
                results[q.index] = Some(Err(io_error(&q.file_name, e.kind().into())));
            }
            return;
        }
        let stored_at = now_ms();
        let committed = (|| -> rusqlite::Result<()> {
            let tx = self.conn.transaction()?;
            {
                let mut insert = tx.prepare_cached(
                    "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part)
                     VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, 'stored', ?9, ?10)",
                )?;
                for q in &renamed {
                    let p = &programs[q.index];
                    insert.execute(params![
                        p.name,
                        q.file_name,
                        p.job_id.as_str(),
                        p.revision,
                        q.hash,
                        p.text.len() as i64,
                        p.dialect.as_str(),
                        stored_at as i64,
                        p.text,
                        p.part_number
                    ])?;
                }
            }
            tx.commit()
        })();
        for q in renamed {
            let p = &programs[q.index];
            results[q.index] = Some(match &committed {
                Err(e) => Err(Stage::Agent.error(
                    "STORE_INDEX_ERROR",
                    "-",
                    "a writable index",
                    e.to_string(),
                    "the program index could not be written",
                )),
                Ok(()) => Ok(DeliveryReceipt {
                    job_id: p.job_id.clone(),
                    machine: self.config.machine.clone(),
                    name: p.name.clone(),
                    path: dir.join(&q.file_name).display().to_string(),
                    file_name: q.file_name,
                    revision: p.revision,
                    sha256: q.hash,
                    size_bytes: p.text.len() as u64,
                    stored_at_ms: stored_at,
                    duplicate: false,
                }),
            });
        }
    }
}

/// A program of a batch that must be written.
#[derive(Debug)]
struct Pending {
    index: usize,
    file_name: String,
    hash: String,
}

/// What storing a program needs.
#[derive(Debug)]
enum Prepared {
    /// Already stored: the original receipt.
    Stored(DeliveryReceipt),
    /// To be written under this file name.
    Write { file_name: String, hash: String },
}

impl Store {
    /// Refuses when the file in the program directory differs from the last
    /// version the index knows (changed or created at the machine). A file
    /// holding exactly the program being delivered is this delivery's own
    /// write that a crash cut off between the rename and the index commit:
    /// writing the same bytes again and committing the row loses nothing.
    fn check_unchanged_at_machine(&self, file_name: &str, incoming: &str) -> Result<(), JobError> {
        let path = self.config.program_dir.join(file_name);
        if !path.exists() {
            return Ok(());
        }
        let on_disk = fs::read(&path).map_err(|e| {
            Stage::Agent.error(
                "STORE_IO_ERROR",
                "-",
                "a readable file",
                e.to_string(),
                format!("cannot read {}", path.display()),
            )
        })?;
        let disk_hash = sha256_hex(&on_disk);
        if disk_hash == incoming {
            return Ok(());
        }
        let indexed: Option<String> = self
            .conn
            .query_row(
                "SELECT sha256 FROM programs WHERE file_name = ?1 ORDER BY seq DESC LIMIT 1",
                [file_name],
                |r| r.get(0),
            )
            .optional()
            .map_err(index_error)?;
        if indexed.as_deref() != Some(disk_hash.as_str()) {
            let machine = &self.config.machine;
            let name = self
                .conn
                .query_row(
                    "SELECT name FROM programs WHERE file_name = ?1 ORDER BY seq DESC LIMIT 1",
                    [file_name],
                    |r| r.get::<_, String>(0),
                )
                .optional()
                .map_err(index_error)?;
            let how = match name {
                Some(name) => format!(
                    "after review, `gearcam program resolve {name} --machine {machine} --adopt` keeps the edit as the current version, `--replace` writes gearcam's version back (the edit stays in the history)"
                ),
                None => "the file was created at the machine, not by gearcam: rename or remove it there".to_string(),
            };
            return Err(Stage::Agent.error(
                "PROGRAM_CHANGED_AT_MACHINE",
                "name",
                format!("{file_name} unchanged since gearcam stored it"),
                format!("a file with sha256 {disk_hash}"),
                format!("{file_name} at {machine} was changed at the machine; it was kept and nothing was overwritten; {how}"),
            ));
        }
        Ok(())
    }

    /// The receipt of a job already stored (latest revision), for a station
    /// whose receipt was lost.
    pub fn stored_receipt(&self, job: &str) -> Result<Option<DeliveryReceipt>, AgentError> {
        Ok(self
            .conn
            .query_row(
                "SELECT * FROM programs WHERE job = ?1 AND state = 'stored' ORDER BY revision DESC LIMIT 1",
                [job],
                |r| self.receipt_from_row(r, true),
            )
            .optional()?)
    }

    /// Every stored version, newest first; only those of program `name` if given.
    pub fn history(&self, name: Option<&str>) -> Result<Vec<ProgramVersion>, AgentError> {
        let mut stmt = self.conn.prepare(
            "SELECT seq, name, file_name, job, revision, sha256, size_bytes, stored_at_ms, state,
                    seq = (SELECT MAX(seq) FROM programs p2 WHERE p2.file_name = programs.file_name) AS current,
                    part, by_user
             FROM programs WHERE ?1 IS NULL OR name = ?1 ORDER BY seq DESC",
        )?;
        let rows = stmt.query_map([name], |r| {
            Ok(ProgramVersion {
                seq: r.get::<_, i64>(0)? as u64,
                name: r.get(1)?,
                file_name: r.get(2)?,
                job: r.get(3)?,
                revision: r.get(4)?,
                sha256: r.get(5)?,
                size_bytes: r.get::<_, i64>(6)? as u64,
                stored_at_ms: r.get::<_, i64>(7)? as u64,
                state: r.get(8)?,
                current: r.get(9)?,
                part_number: r.get(10)?,
                by: r.get(11)?,
            })
        })?;
        Ok(rows.collect::<Result<_, _>>()?)
    }

    /// True when the store has ever held a program called `name`.
    pub fn knows(&self, name: &str) -> Result<bool, AgentError> {
        Ok(self
            .conn
            .query_row(
                "SELECT 1 FROM programs WHERE name = ?1 LIMIT 1",
                [name],
                |_| Ok(()),
            )
            .optional()?
            .is_some())
    }

    /// Version `seq` of program `name`, with its text; `None` when the store
    /// has no such version of that program.
    pub fn version(&self, name: &str, seq: u64) -> Result<Option<ProgramText>, AgentError> {
        let text: Option<String> = self
            .conn
            .query_row(
                "SELECT text FROM programs WHERE seq = ?1 AND name = ?2",
                params![seq as i64, name],
                |r| r.get(0),
            )
            .optional()?;
        let Some(text) = text else { return Ok(None) };
        let version = self.history(Some(name))?.into_iter().find(|v| v.seq == seq);
        Ok(version.map(|version| ProgramText { version, text }))
    }

    /// Makes version `seq` of program `name` current again: writes its text to
    /// the program directory (atomically) and records a `rollback` version.
    pub fn rollback(&mut self, name: &str, seq: u64) -> Result<DeliveryReceipt, JobError> {
        let v = self
            .version(name, seq)
            .map_err(|e| {
                Stage::Agent.error(
                    "STORE_INDEX_ERROR",
                    "-",
                    "a readable index",
                    e.to_string(),
                    "the program index could not be read",
                )
            })?
            .ok_or_else(|| {
                Stage::Agent.error(
                    "UNKNOWN_VERSION",
                    "seq",
                    format!("a stored version of {name} (gearcam program history)"),
                    seq.to_string(),
                    "no such version of this program in the store",
                )
            })?;
        let file_name = v.version.file_name.clone();
        self.check_unchanged_at_machine(&file_name, &v.version.sha256)?;
        let path = self.config.program_dir.join(&file_name);
        write_atomically(&self.config.program_dir, &file_name, v.text.as_bytes()).map_err(|e| {
            Stage::Agent.error(
                "STORE_IO_ERROR",
                "-",
                "a writable program directory",
                e.to_string(),
                format!("cannot write {}", path.display()),
            )
        })?;
        let stored_at = now_ms();
        self.conn
            .execute(
                "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, 'rollback', ?9, ?10)",
                params![
                    v.version.name,
                    file_name,
                    v.version.job,
                    v.version.revision,
                    v.version.sha256,
                    v.text.len() as i64,
                    self.config.dialect.as_str(),
                    stored_at as i64,
                    v.text,
                    v.version.part_number
                ],
            )
            .map_err(index_error)?;
        Ok(DeliveryReceipt {
            job_id: gearcam_proto::JobId::new(v.version.job.clone()).map_err(|e| {
                Stage::Agent.error(
                    "STORE_INDEX_ERROR",
                    "job",
                    "a valid job id",
                    v.version.job.clone(),
                    e.to_string(),
                )
            })?,
            machine: self.config.machine.clone(),
            name: v.version.name,
            path: path.display().to_string(),
            file_name,
            revision: v.version.revision,
            sha256: v.version.sha256,
            size_bytes: v.text.len() as u64,
            stored_at_ms: stored_at,
            duplicate: false,
        })
    }
}

fn index_error(e: rusqlite::Error) -> JobError {
    Stage::Agent.error(
        "STORE_INDEX_ERROR",
        "-",
        "a writable index",
        e.to_string(),
        "the program index could not be read or written",
    )
}

/// Removes temporary files a killed agent left behind (`.{name}.tmp-{pid}`):
/// they never became programs, since a program exists only once renamed.
fn remove_stale_temporaries(dir: &Path) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with('.') && name.contains(".tmp-") {
            match fs::remove_file(entry.path()) {
                Ok(()) => tracing::info!(file = %name, "removed an unfinished temporary file"),
                Err(e) => {
                    tracing::warn!(file = %name, error = %e, "cannot remove an unfinished temporary file")
                }
            }
        }
    }
}

/// Writes `bytes` to a temporary file beside `dir/file_name` and fsyncs it.
fn write_temp(dir: &Path, file_name: &str, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    let mut f = File::create(&tmp)?;
    f.write_all(bytes)?;
    f.sync_all()?;
    Ok(tmp)
}

/// Writes `bytes` to `dir/file_name` atomically and durably.
fn write_atomically(dir: &Path, file_name: &str, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    {
        let mut f = File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
    }
    fs::rename(&tmp, dir.join(file_name))?;
    File::open(dir)?.sync_all()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use gearcam_proto::{JobId, TemplateRef};

    pub(super) fn store(dir: &Path) -> Store {
        Store::open(StoreConfig {
            machine: MachineId::new("H01").unwrap(),
            dialect: Dialect::Sinumerik840d,
            program_dir: dir.join("programs"),
            index_path: dir.join("index.db"),
        })
        .unwrap()
    }

    pub(super) fn program(job: &str, name: &str, text: &str) -> NcProgram {
        NcProgram {
            job_id: JobId::new(job).unwrap(),
            machine: MachineId::new("H01").unwrap(),
            name: name.into(),
            revision: 1,
            dialect: Dialect::Sinumerik840d,
            text: text.into(),
            sha256: sha256_hex(text.as_bytes()),
            template: TemplateRef {
                id: "t".into(),
                version: 1,
            },
            part_number: "P".into(),
            cases: vec![],
            model_version: "m".into(),
            generator: "g".into(),
            path_check: Default::default(),
        }
    }

    #[test]
    fn stores_file_and_index_row_and_repeats_are_idempotent() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        let p = program("J1", "SP_1001", "%_N_SP_1001_MPF\nM2\n");
        let r = s.store(&p).unwrap();
        assert!(!r.duplicate);
        let on_disk = fs::read(dir.path().join("programs/_N_SP_1001_MPF")).unwrap();
        assert_eq!(sha256_hex(&on_disk), r.sha256);
        let again = s.store(&p).unwrap();
        assert!(again.duplicate);
        assert_eq!(again.stored_at_ms, r.stored_at_ms);
        let rows: i64 = s
            .conn
            .query_row("SELECT COUNT(*) FROM programs", [], |r| r.get(0))
            .unwrap();
        assert_eq!(rows, 1);
        // No temporary file is left behind.
        let names: Vec<_> = fs::read_dir(dir.path().join("programs"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("_N_SP_1001_MPF")]);
    }

    #[test]
    fn refuses_path_names_bad_hashes_and_other_machines() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        assert_eq!(
            s.store(&program("J1", "../EVIL", "x")).unwrap_err().code,
            "BAD_PROGRAM_NAME"
        );
        let mut p = program("J2", "SP_1", "x");
        p.sha256 = "00".into();
        assert_eq!(s.store(&p).unwrap_err().code, "HASH_MISMATCH");
        let mut p = program("J3", "SP_1", "x");
        p.machine = MachineId::new("H09").unwrap();
        assert_eq!(s.store(&p).unwrap_err().code, "WRONG_MACHINE");
        assert_eq!(
            fs::read_dir(dir.path().join("programs")).unwrap().count(),
            0
        );
    }

    #[test]
    fn a_crash_between_the_rename_and_the_index_commit_is_finished_not_refused() {
        // The agent killed after renaming the new file into place and before
        // committing its index row: at the next delivery of the same program
        // the file holds exactly its bytes. That is not an operator's edit.
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let second = program("J2", "SP_1", "second\n");
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, second.text.as_bytes()).unwrap();
        let receipt = s
            .store(&second)
            .expect("its own unfinished write is finished");
        assert_eq!(receipt.sha256, second.sha256);
        assert_eq!(fs::read_to_string(&path).unwrap(), "second\n");
        // Another content is still an edit at the machine.
        fs::write(&path, "operator edit\n").unwrap();
        let err = s.store(&program("J3", "SP_1", "third\n")).unwrap_err();
        assert_eq!(err.code, "PROGRAM_CHANGED_AT_MACHINE");
    }

    #[test]
    fn keeps_a_program_changed_at_the_machine() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "operator edit\n").unwrap();
        let err = s.store(&program("J2", "SP_1", "second\n")).unwrap_err();
        assert_eq!(err.code, "PROGRAM_CHANGED_AT_MACHINE");
        assert_eq!(fs::read_to_string(&path).unwrap(), "operator edit\n");
    }

    #[test]
    fn a_batch_stores_each_program_once_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        let mut bad = program("J4", "SP_4", "x");
        bad.sha256 = "00".into();
        let batch = vec![
            program("J1", "SP_1", "one\n"),
            program("J2", "SP_2", "two\n"),
            program("J1", "SP_1", "one\n"), // repeat inside the batch
            program("J3", "SP_1", "one again\n"), // same file, later job
            bad,
        ];
        let results = s.store_batch(&batch);
        assert!(!results[0].as_ref().unwrap().duplicate);
        assert!(!results[1].as_ref().unwrap().duplicate);
        let repeat = results[2].as_ref().unwrap();
        assert!(repeat.duplicate);
        assert_eq!(
            repeat.stored_at_ms,
            results[0].as_ref().unwrap().stored_at_ms
        );
        assert!(results[3].is_ok());
        assert_eq!(results[4].as_ref().unwrap_err().code, "HASH_MISMATCH");
        let path = dir.path().join("programs/_N_SP_1_MPF");
        assert_eq!(fs::read_to_string(path).unwrap(), "one again\n");
        let rows: i64 = s
            .conn
            .query_row("SELECT COUNT(*) FROM programs", [], |r| r.get(0))
            .unwrap();
        assert_eq!(rows, 3);
        let names: Vec<_> = fs::read_dir(dir.path().join("programs"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names.len(), 2, "no temporary files left: {names:?}");
    }

    #[test]
    fn an_unfinished_temporary_file_is_removed_at_open() {
        let dir = tempfile::tempdir().unwrap();
        fs::create_dir_all(dir.path().join("programs")).unwrap();
        fs::write(
            dir.path().join("programs/._N_SP_1_MPF.tmp-99999"),
            "half a prog",
        )
        .unwrap();
        fs::write(dir.path().join("programs/_N_OPERATOR_MPF"), "kept").unwrap();
        let _s = store(dir.path());
        let names: Vec<_> = fs::read_dir(dir.path().join("programs"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("_N_OPERATOR_MPF")]);
    }

    #[test]
    fn keeps_versions_and_rolls_back() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        s.store(&program("J2", "SP_1", "second\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        assert_eq!(fs::read_to_string(&path).unwrap(), "second\n");
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(h.len(), 2);
        assert!(h[0].current && !h[1].current);
        let first = h[1].seq;
        assert_eq!(s.version("SP_1", first).unwrap().unwrap().text, "first\n");
        let r = s.rollback("SP_1", first).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "first\n");
        assert_eq!(r.sha256, sha256_hex(b"first\n"));
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(
            (h.len(), h[0].state.as_str(), h[0].current),
            (3, "rollback", true)
        );
        assert_eq!(s.rollback("SP_1", 999).unwrap_err().code, "UNKNOWN_VERSION");
        // The receipt of a job can be asked for again.
        assert_eq!(
            s.stored_receipt("J2").unwrap().unwrap().sha256,
            sha256_hex(b"second\n")
        );
        assert!(s.stored_receipt("J9").unwrap().is_none());
    }
}
