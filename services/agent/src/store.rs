//! The machine's part-program store: program files in the directory the
//! controller reads, plus an SQLite index. Writes are atomic and durable
//! before a receipt is given.
//!
//! A write is a temporary file in the same directory, made durable, renamed over
//! the final name, with an intent row in the index committed before the
//! rename (the order, and what a crash leaves, in `write`). A repeat of the
//! same job + revision + hash is answered with the original receipt; a
//! program changed at the machine (file hash differs from the index) is
//! never overwritten.

use gearcam_proto::Code;
use std::fs;
use std::path::{Path, PathBuf};

use gearcam_proto::{
    now_ms, DeliveryReceipt, Dialect, JobError, MachineId, NcProgram, ProgramText, ProgramVersion,
    Stage,
};
use rusqlite::{params, Connection, OptionalExtension};
use sha2::{Digest, Sha256};

use crate::AgentError;

mod check;
mod owner;
mod rebuild;
mod resolve;
mod write;

use write::{remove_stale_temporaries, write_atomically, Pending, Prepared};
pub use write::{Results, Verdicts};

pub use rebuild::Rebuilt;
pub use resolve::{Resolution, Resolved, Superseded};

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
    /// Fault injection for the fault tests; none in service.
    pub faults: Faults,
}

/// Faults the fault tests inject into a real agent process.
#[derive(Debug, Clone, Default)]
pub struct Faults {
    /// Abort the process right after the renames of a group commit, before
    /// the index says `stored` (the crash the intent record is for).
    pub crash_after_rename: bool,
    /// Pause this long after the temporary files are written, before the
    /// file at the machine is compared again and renamed over (widens the
    /// window an operator's edit could fall into).
    pub pause_before_rename_ms: u64,
}

/// A machine's program store.
#[derive(Debug)]
pub struct Store {
    config: StoreConfig,
    conn: Connection,
    /// Whether a group's files are made durable by one `syncfs`
    /// (`write::group_sync`), decided when the store opens.
    group_sync: bool,
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
        gearcam_bus::durable::refuse_if_lost(
            &config.index_path,
            &format!("the program index of {}", config.machine),
            &format!(
                "Restore it from a backup, or rebuild it from the program files and their headers: \
                 gearcam-agent --machine {} --program-dir {} --index {} --rebuild-index.",
                config.machine,
                config.program_dir.display(),
                config.index_path.display()
            ),
        )
        .map_err(AgentError::Lost)?;
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
             CREATE INDEX IF NOT EXISTS programs_by_file ON programs (file_name, seq);
             -- Jobs refused because their program was changed at the machine:
             -- an adoption of that edit ends them.
             CREATE TABLE IF NOT EXISTS held (
                 job       TEXT NOT NULL PRIMARY KEY,
                 file_name TEXT NOT NULL,
                 at_ms     INTEGER NOT NULL
             );
             -- Jobs an adopted edit ended: never stored after.
             CREATE TABLE IF NOT EXISTS superseded (
                 job     TEXT NOT NULL PRIMARY KEY,
                 name    TEXT NOT NULL,
                 seq     INTEGER NOT NULL,
                 by_user TEXT NOT NULL,
                 at_ms   INTEGER NOT NULL
             );",
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
        gearcam_bus::durable::mark(&config.index_path).map_err(io(&config.index_path))?;
        remove_stale_temporaries(&config.program_dir);
        let group_sync = write::group_sync::available(&config.program_dir);
        let mut store = Store {
            config,
            conn,
            group_sync,
        };
        store.recover()?;
        Ok(store)
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

    /// The checks of a program on its own ([`StoreConfig::check_program`]).
    pub fn check_program(&self, p: &NcProgram) -> Result<String, JobError> {
        self.config.check_program(p)
    }

    /// Checks a program and decides whether it must be written.
    fn prepare(&self, p: &NcProgram) -> Result<Prepared, JobError> {
        let file_name = self.check_program(p)?;
        // An operator's adoption ended this job: it is never stored.
        if let Some(s) = self.superseded(p.job_id.as_str())? {
            return Err(JobError::superseded(
                &self.config.machine,
                &s.name,
                s.seq,
                &s.by,
            ));
        }
        let hash = p.sha256.clone();
        // Idempotency: the same job and revision.
        let existing = self.row(
            "SELECT * FROM programs WHERE job = ?1 AND revision = ?2 AND state = 'stored'",
            params![p.job_id.as_str(), p.revision],
            |r| {
                Ok((
                    r.get::<_, String>("sha256")?,
                    self.receipt_from_row(r, true)?,
                ))
            },
        )?;
        if let Some((stored_hash, receipt)) = existing {
            if stored_hash == hash {
                // A repeat: the original receipt, once the machine is seen
                // to hold it (or a later version superseded it).
                if let Err(error) = self.check_still_held(&file_name, &hash) {
                    return Ok(Prepared::held(error, file_name));
                }
                return Ok(Prepared::Stored(receipt));
            }
            return Err(Stage::Agent.error(
                Code::REVISION_CONFLICT,
                "revision",
                format!("content with sha256 {stored_hash}"),
                format!("sha256 {hash}"),
                "this job revision was already stored with different content; send a new revision",
            ));
        }
        // A program name belongs to one part.
        self.check_owner(p, &file_name)?;
        // A program changed at the machine is never overwritten silently.
        let seen = match self.check_unchanged_at_machine(&file_name, &hash) {
            Ok(seen) => seen,
            Err(error) => return Ok(Prepared::held(error, file_name)),
        };
        Ok(Prepared::Write(Pending {
            index: 0,
            file_name,
            hash,
            seen,
        }))
    }
}

impl Store {
    /// The SHA-256 of the file `file_name` at the machine, `None` when there
    /// is no such file.
    pub(super) fn disk_hash(&self, file_name: &str) -> Result<Option<String>, JobError> {
        let path = self.config.program_dir.join(file_name);
        match fs::read(&path) {
            Ok(bytes) => Ok(Some(sha256_hex(&bytes))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(Stage::Agent.error(
                Code::STORE_IO_ERROR,
                "-",
                "a readable file",
                e.to_string(),
                format!("cannot read {}", path.display()),
            )),
        }
    }

    /// One row of `sql`, or none; the statement is kept prepared (the
    /// checks before a write run these for every program).
    pub(super) fn row<T, P: rusqlite::Params>(
        &self,
        sql: &str,
        params: P,
        f: impl FnOnce(&rusqlite::Row<'_>) -> rusqlite::Result<T>,
    ) -> Result<Option<T>, JobError> {
        self.conn
            .prepare_cached(sql)
            .and_then(|mut st| st.query_row(params, f).optional())
            .map_err(index_error)
    }

    /// The hash of the newest version the index knows for `file_name`.
    fn indexed_hash(&self, file_name: &str) -> Result<Option<String>, JobError> {
        self.row(
                "SELECT sha256 FROM programs WHERE file_name = ?1 AND state != 'pending' ORDER BY seq DESC LIMIT 1",
                [file_name],
                |r| r.get(0),
            )
    }

    /// Refuses when the file in the program directory differs from the last
    /// version the index knows (changed or created at the machine); returns
    /// the file's hash as seen (`None`: no file), to be compared again right
    /// before the rename. A file holding exactly the program being delivered
    /// is this delivery's own write that a crash cut off between the rename
    /// and the index commit: writing the same bytes again loses nothing.
    fn check_unchanged_at_machine(
        &self,
        file_name: &str,
        incoming: &str,
    ) -> Result<Option<String>, JobError> {
        let Some(disk_hash) = self.disk_hash(file_name)? else {
            return Ok(None);
        };
        if disk_hash == incoming {
            return Ok(Some(disk_hash));
        }
        if self.indexed_hash(file_name)?.as_deref() != Some(disk_hash.as_str()) {
            return Err(
                self.changed_at_machine(file_name, &format!("a file with sha256 {disk_hash}"))
            );
        }
        Ok(Some(disk_hash))
    }

    /// A repeated delivery of a version the index holds: the machine must
    /// still hold it, unless a later version superseded it. An edit or a
    /// deletion at the machine since is a conflict (the job waits), never
    /// "delivered, duplicate" with a hash the machine no longer holds.
    fn check_still_held(&self, file_name: &str, hash: &str) -> Result<(), JobError> {
        if self.indexed_hash(file_name)?.as_deref() != Some(hash) {
            return Ok(()); // superseded by a later version: the receipt stands
        }
        match self.disk_hash(file_name)? {
            Some(h) if h == hash => Ok(()),
            Some(h) => Err(self.changed_at_machine(file_name, &format!("a file with sha256 {h}"))),
            None => Err(self.changed_at_machine(file_name, "no file (deleted at the machine)")),
        }
    }

    /// `PROGRAM_CHANGED_AT_MACHINE` for `file_name`, with what to run.
    pub(super) fn changed_at_machine(&self, file_name: &str, got: &str) -> JobError {
        let machine = &self.config.machine;
        let name = self
            .conn
            .query_row(
                "SELECT name FROM programs WHERE file_name = ?1 AND state != 'pending' ORDER BY seq DESC LIMIT 1",
                [file_name],
                |r| r.get::<_, String>(0),
            )
            .optional()
            .ok()
            .flatten();
        let how = match name {
            Some(name) => format!(
                "after review, `gearcam program resolve {name} --machine {machine} --adopt` keeps the edit as the current version, `--replace` writes gearcam's version back (the edit stays in the history)"
            ),
            None => "the file was created at the machine, not by gearcam: rename or remove it there".to_string(),
        };
        Stage::Agent.error(
            Code::PROGRAM_CHANGED_AT_MACHINE,
            "name",
            format!("{file_name} unchanged since gearcam stored it"),
            got.to_string(),
            format!("{file_name} at {machine} was changed at the machine; it was kept and nothing was overwritten; {how}"),
        )
    }

    /// The receipt of a job already stored (latest revision), for a station
    /// whose receipt was lost.
    ///
    /// A receipt the machine no longer bears out (the file was edited or
    /// deleted since, and no later version superseded it) is not given: the
    /// station then delivers again and meets the conflict.
    pub fn stored_receipt(&self, job: &str) -> Result<Option<DeliveryReceipt>, AgentError> {
        let receipt = self
            .conn
            .query_row(
                "SELECT * FROM programs WHERE job = ?1 AND state = 'stored' ORDER BY revision DESC LIMIT 1",
                [job],
                |r| self.receipt_from_row(r, true),
            )
            .optional()?;
        Ok(receipt.filter(|r| self.check_still_held(&r.file_name, &r.sha256).is_ok()))
    }

    /// Every stored version, newest first; only those of program `name` if given.
    pub fn history(&self, name: Option<&str>) -> Result<Vec<ProgramVersion>, AgentError> {
        let mut stmt = self.conn.prepare(
            "SELECT seq, name, file_name, job, revision, sha256, size_bytes, stored_at_ms, state,
                    seq = (SELECT MAX(seq) FROM programs p2 WHERE p2.file_name = programs.file_name AND p2.state != 'pending') AS current,
                    part, by_user
             FROM programs WHERE (?1 IS NULL OR name = ?1) AND state != 'pending' ORDER BY seq DESC",
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
                "SELECT 1 FROM programs WHERE name = ?1 AND state != 'pending' LIMIT 1",
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
                "SELECT text FROM programs WHERE seq = ?1 AND name = ?2 AND state != 'pending'",
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
    pub fn rollback(
        &mut self,
        name: &str,
        seq: u64,
        by: &str,
    ) -> Result<DeliveryReceipt, JobError> {
        if !gearcam_proto::delivery::valid_by(by) {
            return Err(Stage::Agent.error(
                Code::BAD_STORE_REQUEST,
                "by",
                "who rolls back: 1 to 64 characters on one line",
                by.chars().take(80).collect::<String>(),
                "a rollback is recorded with the name of the person who decided",
            ));
        }
        let v = self
            .version(name, seq)
            .map_err(|e| {
                Stage::Agent.error(
                    Code::STORE_INDEX_ERROR,
                    "-",
                    "a readable index",
                    e.to_string(),
                    "the program index could not be read",
                )
            })?
            .ok_or_else(|| {
                Stage::Agent.error(
                    Code::UNKNOWN_VERSION,
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
                Code::STORE_IO_ERROR,
                "-",
                "a writable program directory",
                e.to_string(),
                format!("cannot write {}", path.display()),
            )
        })?;
        let stored_at = now_ms();
        self.conn
            .execute(
                "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part, by_user)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, 'rollback', ?9, ?10, ?11)",
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
                    v.version.part_number,
                    by
                ],
            )
            .map_err(index_error)?;
        Ok(DeliveryReceipt {
            job_id: gearcam_proto::JobId::new(v.version.job.clone()).map_err(|e| {
                Stage::Agent.error(
                    Code::STORE_INDEX_ERROR,
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

fn index_error(e: impl std::fmt::Display) -> JobError {
    Stage::Agent.error(
        Code::STORE_INDEX_ERROR,
        "-",
        "a writable index",
        e.to_string(),
        "the program index could not be read or written",
    )
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
            faults: Faults::default(),
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
            form: None,
            simulation: None,
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
        let r = s.rollback("SP_1", first, "operator Li").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "first\n");
        assert_eq!(r.sha256, sha256_hex(b"first\n"));
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(
            (h.len(), h[0].state.as_str(), h[0].current),
            (3, "rollback", true)
        );
        assert_eq!(
            s.rollback("SP_1", 999, "x").unwrap_err().code,
            "UNKNOWN_VERSION"
        );
        assert_eq!(
            s.rollback("SP_1", first, " ").unwrap_err().code,
            "BAD_STORE_REQUEST"
        );
        // The receipt of a job can be asked for again.
        assert_eq!(
            s.stored_receipt("J2").unwrap().unwrap().sha256,
            sha256_hex(b"second\n")
        );
        assert!(s.stored_receipt("J9").unwrap().is_none());
    }
}
