//! The planning station's durable job journal (SQLite in WAL mode).
//!
//! Every accepted job is a row holding its encoded request, state, attempts and
//! the time it is next due to be re-driven. A job is acknowledged to the
//! submitter only after its row is committed and fsynced, so a station killed
//! at any point and started again re-drives every journaled job that is not
//! final. What the station can learn again (events) is committed without
//! its own fsync ([`Durability`]).

use gearcam_proto::Code;
use std::path::Path;

use gearcam_proto::{
    decode, encode, DeliveryReceipt, EventKind, JobError, JobEvent, JobId, JobRequest, JobState,
    JobStatus, MachineId, ProgramRef, Stage, Warning,
};
use rusqlite::{params, Connection, OptionalExtension};
use sha2::{Digest, Sha256};

/// A journal error.
#[derive(Debug, thiserror::Error)]
pub enum JournalError {
    /// SQLite failed.
    #[error("job journal (SQLite): {0}")]
    Sqlite(#[from] rusqlite::Error),
    /// A stored column is unreadable.
    #[error("job journal: unreadable {what}: {detail}")]
    Corrupt {
        /// Which column.
        what: &'static str,
        /// Why.
        detail: String,
    },
    /// The journal held jobs before and is now missing or empty: the
    /// station refuses to start rather than forget unfinished jobs.
    #[error("{0}")]
    Lost(String),
    /// The journal's directory cannot be created.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The error.
        #[source]
        source: std::io::Error,
    },
}

/// A job due to be (re)driven.
#[derive(Debug, Clone)]
pub struct Due {
    /// The job.
    pub job: JobId,
    /// Its machine.
    pub machine: MachineId,
    /// Its state.
    pub state: JobState,
    /// Attempts so far.
    pub attempts: u32,
    /// What it waits for, when waiting.
    pub waiting_for: Option<String>,
    /// The encoded request, ready to publish.
    pub request: Vec<u8>,
}

/// How durable a batch is once its transaction commits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Durability {
    /// On disk when the commit returns (the WAL fsynced): what the station
    /// acknowledges to a person (a submission, a cancellation) must be.
    Full,
    /// In the WAL when the commit returns, on disk at the next full commit or
    /// checkpoint: it survives the station's process dying, not the
    /// machine's power. For what the station learns again by itself: job
    /// events and the drives' bookkeeping. A job whose event is lost is
    /// re-driven, and the agent answers a re-drive with the receipt it keeps.
    Normal,
}

/// The journal.
#[derive(Debug)]
pub struct Journal {
    conn: Connection,
}

fn sha(bytes: &[u8]) -> String {
    hex::encode(Sha256::digest(bytes))
}

/// The unfinished jobs due, oldest first. Read through the partial index
/// of unfinished jobs by due time: without statistics SQLite would rather
/// scan the whole table in `seq` order for the `ORDER BY ... LIMIT`, and the
/// station asks ten times a second while the table holds every job ever.
const DUE: &str = "SELECT job, machine, state, attempts, request, waiting_for FROM jobs INDEXED BY jobs_due
     WHERE state NOT IN ('delivered', 'failed', 'superseded', 'cancelled') AND next_attempt_ms <= ?1 ORDER BY seq LIMIT ?2";

impl Journal {
    /// Opens (creating if needed) the journal at `path`.
    pub fn open(path: &Path) -> Result<Journal, JournalError> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| JournalError::Io {
                path: dir.display().to_string(),
                source: e,
            })?;
        }
        gearcam_bus::durable::refuse_if_lost(
            path,
            "the station's job journal",
            "Restore it from a backup (the station keeps nothing else of the unfinished jobs); \
             without one, the jobs not yet delivered must be submitted again \
             (`gearcam program history` at each machine shows what was delivered).",
        )
        .map_err(JournalError::Lost)?;
        let conn = Connection::open(path)?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        conn.pragma_update(None, "synchronous", "FULL")?;
        // 32 MiB of page cache: the jobs being driven and their models stay
        // in memory instead of being read back from the file for every event.
        conn.pragma_update(None, "cache_size", -32768)?;
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS jobs (
                 seq             INTEGER PRIMARY KEY AUTOINCREMENT,
                 job             TEXT NOT NULL UNIQUE,
                 machine         TEXT NOT NULL,
                 part_number     TEXT NOT NULL,
                 request         BLOB NOT NULL,
                 request_sha256  TEXT NOT NULL,
                 state           TEXT NOT NULL,
                 attempts        INTEGER NOT NULL DEFAULT 0,
                 accepted_at_ms  INTEGER NOT NULL,
                 updated_at_ms   INTEGER NOT NULL,
                 next_attempt_ms INTEGER NOT NULL,
                 waiting_for     TEXT,
                 receipt_json    TEXT,
                 errors_json     TEXT
             );
             DROP INDEX IF EXISTS jobs_due;
             CREATE INDEX jobs_due ON jobs (next_attempt_ms) WHERE state NOT IN ('delivered', 'failed', 'superseded', 'cancelled');",
        )?;
        // The model's warnings, kept so that status can show them: a journal
        // from before the column gains it (its jobs have none recorded).
        add_column(&conn, "warnings_json", "TEXT")?;
        // Each job's model as the model service published it, kept so that
        // a client reads it after the job has ended (the web page draws its
        // picture). In a table of its own: a model is kilobytes, and in the
        // job's row every state change would rewrite it.
        conn.execute_batch(
            "CREATE TABLE IF NOT EXISTS models (
                 job   TEXT PRIMARY KEY REFERENCES jobs (job),
                 model BLOB NOT NULL
             );",
        )?;
        move_models(&conn)?;
        // Parts to cut, kept beside the request so that a list of a
        // thousand jobs does not decode a thousand requests: a journal
        // from before the column gains it, filled from each job's request.
        if add_column(&conn, "quantity", "INTEGER NOT NULL DEFAULT 0")? {
            fill_quantities(&conn)?;
        }
        gearcam_bus::durable::mark(path).map_err(|e| JournalError::Io {
            path: path.display().to_string(),
            source: e,
        })?;
        conn.set_prepared_statement_cache_capacity(64);
        Ok(Journal { conn })
    }

    /// Runs `f` in one transaction (group commit for a batch of changes),
    /// committed as `durability` says.
    pub fn batch<T>(
        &mut self,
        durability: Durability,
        f: impl FnOnce(&Journal) -> T,
    ) -> Result<T, JournalError> {
        let level = match durability {
            Durability::Full => "FULL",
            Durability::Normal => "NORMAL",
        };
        // Outside a transaction the level may change from one commit to
        // the next; the journal is in WAL mode, where a FULL commit also
        // makes every NORMAL commit before it durable.
        self.conn.pragma_update(None, "synchronous", level)?;
        self.conn.execute_batch("BEGIN IMMEDIATE")?;
        let out = f(self);
        self.conn.execute_batch("COMMIT")?;
        self.conn.pragma_update(None, "synchronous", "FULL")?;
        Ok(out)
    }

    /// `execute` on a cached statement: the journal runs the same few
    /// statements for every job, and parsing each again costs more than
    /// running it.
    fn exec<P: rusqlite::Params>(&self, sql: &str, params: P) -> rusqlite::Result<usize> {
        self.conn.prepare_cached(sql)?.execute(params)
    }

    /// Adds `new` to the job's warnings (the model's, kept for status),
    /// each once: a program produced again repeats its warnings.
    fn add_warnings(&self, job: &str, new: &[Warning]) -> rusqlite::Result<()> {
        if new.is_empty() {
            return Ok(());
        }
        let kept: Option<String> = self
            .row(
                "SELECT warnings_json FROM jobs WHERE job = ?1",
                [job],
                |r| r.get(0),
            )
            .optional()?
            .flatten();
        let mut all: Vec<Warning> = kept
            .and_then(|j| serde_json::from_str(&j).ok())
            .unwrap_or_default();
        for w in new {
            if !all.contains(w) {
                all.push(w.clone());
            }
        }
        self.exec(
            "UPDATE jobs SET warnings_json = ?2 WHERE job = ?1",
            params![job, serde_json::to_string(&all).unwrap_or_default()],
        )?;
        Ok(())
    }

    /// `query_row` on a cached statement.
    fn row<T, P: rusqlite::Params>(
        &self,
        sql: &str,
        params: P,
        f: impl FnOnce(&rusqlite::Row<'_>) -> rusqlite::Result<T>,
    ) -> rusqlite::Result<T> {
        self.conn.prepare_cached(sql)?.query_row(params, f)
    }

    /// Journals a request. The same request again is accepted as is (idempotent);
    /// a different spec under a known job id is refused (`JOB_ID_EXISTS`).
    pub fn submit(&self, req: &JobRequest, now: u64) -> Result<JobStatus, JobError> {
        let bytes = encode(req).map_err(|e| {
            station_error(
                Code::ENCODE_FAILED,
                "-",
                "an encodable request",
                &e.to_string(),
            )
        })?;
        let hash = sha(&bytes);
        let known: Option<Vec<u8>> = self
            .row(
                "SELECT request FROM jobs WHERE job = ?1",
                [req.job_id.as_str()],
                |r| r.get(0),
            )
            .optional()
            .map_err(db_error)?;
        match known {
            // A resubmission is the same job id with the same spec; who sent
            // it and when may differ (a client's retry).
            Some(stored) => {
                // The id is the request's; whether the spec carried it (a
                // file's `[job] id`, `submit --id`) or the client made it up
                // does not make another job.
                let without_id = |spec: &gearcam_proto::JobSpec| {
                    let mut spec = spec.clone();
                    spec.job.id = None;
                    spec
                };
                let same = decode::<JobRequest>(&stored)
                    .is_ok_and(|s| without_id(&s.spec) == without_id(&req.spec));
                if !same {
                    return Err(station_error(
                        Code::JOB_ID_EXISTS,
                        "job_id",
                        "a job id not used by another job spec",
                        req.job_id.as_str(),
                    ));
                }
            }
            None => {
                self.conn
                    .execute(
                        "INSERT INTO jobs (job, machine, part_number, request, request_sha256, state, accepted_at_ms, updated_at_ms, next_attempt_ms, quantity)
                         VALUES (?1, ?2, ?3, ?4, ?5, 'accepted', ?6, ?6, ?6, ?7)",
                        params![req.job_id.as_str(), req.spec.job.machine.as_str(), req.spec.job.part_number, bytes, hash, now as i64, req.spec.job.quantity],
                    )
                    .map_err(db_error)?;
            }
        }
        self.status(&req.job_id)
            .map_err(|e| {
                station_error(
                    Code::JOURNAL_ERROR,
                    "-",
                    "a readable journal",
                    &e.to_string(),
                )
            })?
            .ok_or_else(|| {
                station_error(Code::JOURNAL_ERROR, "-", "the row just written", "nothing")
            })
    }

    /// Applies a job event `reporter` published (the last chunk of its key);
    /// returns true when the job is known and changed. An event its reporter
    /// does not own (a `delivered` not from the job's machine's agent, a
    /// stage's state from another service) is ignored and logged. Final
    /// states never change; progress pushes the next re-drive to
    /// `now + redrive_ms`.
    pub fn apply(
        &self,
        reporter: &str,
        ev: &JobEvent,
        now: u64,
        redrive_ms: u64,
    ) -> Result<bool, JournalError> {
        let row: Option<(String, String)> = self
            .row(
                "SELECT state, machine FROM jobs WHERE job = ?1",
                [ev.job_id.as_str()],
                |r| Ok((r.get(0)?, r.get(1)?)),
            )
            .optional()?;
        let Some((current, machine)) = row else {
            return Ok(false);
        };
        let Some(current) = JobState::parse(&current) else {
            return Ok(false);
        };
        let machine = MachineId::new(machine).map_err(|e| corrupt("machine", e))?;
        let owned = gearcam_proto::keys::reporter_owns(reporter, ev, &machine);
        if !owned {
            tracing::warn!(job = %ev.job_id, reporter, stage = ev.stage.as_str(), "ignored an event its reporter does not own");
            return Ok(false);
        }
        // A cancelled job whose program the agent stored all the same (the
        // cancellation reached the station while the agent was storing it):
        // the job stays cancelled, and its status shows what the machine
        // holds.
        if let (JobState::Cancelled, EventKind::Delivered { receipt }) = (current, &ev.event) {
            tracing::warn!(job = %ev.job_id, file = receipt.file_name, "a cancelled job's program was stored before the agent heard of the cancellation");
            return Ok(self.exec(
                "UPDATE jobs SET receipt_json = ?2, updated_at_ms = ?3 WHERE job = ?1 AND receipt_json IS NULL",
                params![
                    ev.job_id.as_str(),
                    serde_json::to_string(receipt).unwrap_or_default(),
                    now as i64
                ],
            )? > 0);
        }
        if current.is_final() {
            return Ok(false);
        }
        if ev.stage == Stage::Station {
            // The station's own announcements: already in the journal.
            return Ok(false);
        }
        let next = (now + redrive_ms) as i64;
        let job = ev.job_id.as_str();
        let n = match &ev.event {
            EventKind::Accepted { .. } => 0,
            EventKind::Planned { .. } => self.set_state(job, JobState::Planned, now, next)?,
            EventKind::Modelled { warnings } => {
                self.exec(
                    "UPDATE jobs SET warnings_json = ?2 WHERE job = ?1",
                    params![job, serde_json::to_string(warnings).unwrap_or_default()],
                )?;
                self.set_state(job, JobState::Modelled, now, next)?
            }
            EventKind::Programmed { warnings, .. } => {
                self.add_warnings(job, warnings)?;
                self.set_state(job, JobState::Programmed, now, next)?
            }
            EventKind::Waiting { reason } => self.exec(
                "UPDATE jobs SET state = 'waiting', waiting_for = ?2, updated_at_ms = ?3, next_attempt_ms = ?4 WHERE job = ?1",
                params![job, reason, now as i64, next],
            )?,
            EventKind::Delivered { receipt } => self.delivered(receipt, now)?,
            EventKind::Failed { errors } => self.ended(job, JobState::Failed, errors, now)?,
            EventKind::Superseded { name, seq, by } => {
                let why = JobError::superseded(&machine, name, *seq, by);
                self.ended(job, JobState::Superseded, &[why], now)?
            }
            // The station's own: never from another reporter (refused above).
            EventKind::Cancelled { .. } => 0,
        };
        Ok(n > 0)
    }

    /// Ends a job in the final `state`, with why.
    fn ended(
        &self,
        job: &str,
        state: JobState,
        why: &[JobError],
        now: u64,
    ) -> Result<usize, JournalError> {
        Ok(self.exec(
            "UPDATE jobs SET state = ?2, errors_json = ?3, updated_at_ms = ?4, waiting_for = NULL WHERE job = ?1",
            params![
                job,
                state.as_str(),
                serde_json::to_string(why).unwrap_or_default(),
                now as i64
            ],
        )?)
    }

    /// Cancels a job that is not final (`cancelled`, with who); the job's
    /// status after, or `None` for an unknown job. A final job is left as it
    /// is: the caller sees its state.
    pub fn cancel(
        &self,
        job: &JobId,
        by: &str,
        now: u64,
    ) -> Result<Option<JobStatus>, JournalError> {
        self.exec(
            "UPDATE jobs SET state = 'cancelled', errors_json = ?2, updated_at_ms = ?3, waiting_for = NULL
             WHERE job = ?1 AND state NOT IN ('delivered', 'failed', 'superseded', 'cancelled')",
            params![
                job.as_str(),
                serde_json::to_string(&[JobError::cancelled(by)]).unwrap_or_default(),
                now as i64
            ],
        )?;
        self.status(job)
    }

    fn set_state(
        &self,
        job: &str,
        state: JobState,
        now: u64,
        next: i64,
    ) -> Result<usize, JournalError> {
        Ok(self.exec(
            "UPDATE jobs SET state = ?2, waiting_for = NULL, updated_at_ms = ?3, next_attempt_ms = ?4 WHERE job = ?1",
            params![job, state.as_str(), now as i64, next],
        )?)
    }

    /// Records a job as delivered with its receipt.
    pub fn delivered(&self, receipt: &DeliveryReceipt, now: u64) -> Result<usize, JournalError> {
        Ok(self.exec(
            "UPDATE jobs SET state = 'delivered', receipt_json = ?2, waiting_for = NULL, updated_at_ms = ?3
             WHERE job = ?1 AND state NOT IN ('delivered', 'failed', 'superseded', 'cancelled')",
            params![
                receipt.job_id.as_str(),
                serde_json::to_string(receipt).unwrap_or_default(),
                now as i64
            ],
        )?)
    }

    /// Records that the job was (re)sent.
    pub fn sent(&self, job: &JobId, now: u64, next_attempt: u64) -> Result<(), JournalError> {
        self.exec(
            "UPDATE jobs SET attempts = attempts + 1, waiting_for = NULL, updated_at_ms = ?2, next_attempt_ms = ?3,
                    state = CASE WHEN state = 'waiting' THEN 'accepted' ELSE state END
             WHERE job = ?1",
            params![job.as_str(), now as i64, next_attempt as i64],
        )?;
        Ok(())
    }

    /// Records that the job waits for something, until `next_attempt`.
    pub fn waiting(
        &self,
        job: &JobId,
        reason: &str,
        now: u64,
        next_attempt: u64,
    ) -> Result<(), JournalError> {
        self.exec(
            "UPDATE jobs SET state = 'waiting', waiting_for = ?2, updated_at_ms = ?3, next_attempt_ms = ?4
             WHERE job = ?1 AND state NOT IN ('delivered', 'failed', 'superseded', 'cancelled')",
            params![job.as_str(), reason, now as i64, next_attempt as i64],
        )?;
        Ok(())
    }

    /// Makes every unfinished job of `machine` (or of every machine) due now.
    pub fn wake(&self, machine: Option<&str>, now: u64) -> Result<usize, JournalError> {
        Ok(self.exec(
            "UPDATE jobs SET next_attempt_ms = ?2 WHERE state NOT IN ('delivered', 'failed', 'superseded', 'cancelled') AND (?1 IS NULL OR machine = ?1)",
            params![machine, now as i64],
        )?)
    }

    /// Unfinished jobs due at `now`, oldest first, at most `limit`.
    pub fn due(&self, now: u64, limit: usize) -> Result<Vec<Due>, JournalError> {
        let mut stmt = self.conn.prepare_cached(DUE)?;
        let rows = stmt.query_map(params![now as i64, limit as i64], |r| {
            Ok((
                r.get::<_, String>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, String>(2)?,
                r.get::<_, u32>(3)?,
                r.get::<_, Vec<u8>>(4)?,
                r.get::<_, Option<String>>(5)?,
            ))
        })?;
        let mut out = Vec::new();
        for row in rows {
            let (job, machine, state, attempts, request, waiting_for) = row?;
            out.push(Due {
                job: JobId::new(job).map_err(|e| corrupt("job", e))?,
                machine: MachineId::new(machine).map_err(|e| corrupt("machine", e))?,
                state: JobState::parse(&state).ok_or_else(|| corrupt("state", state))?,
                attempts,
                waiting_for,
                request,
            });
        }
        Ok(out)
    }

    /// One job's status.
    pub fn status(&self, job: &JobId) -> Result<Option<JobStatus>, JournalError> {
        status_in(&self.conn, job)
    }

    /// Every job, oldest first.
    pub fn list(&self) -> Result<Vec<JobStatus>, JournalError> {
        let mut stmt = self
            .conn
            .prepare_cached(&format!("{SELECT_STATUS} ORDER BY seq"))?;
        let rows = stmt.query_map([], row_parts)?;
        let mut out = Vec::new();
        for r in rows {
            out.push(status_from(r?)?);
        }
        Ok(out)
    }

    /// Journals the model the model service published for `job` (its
    /// encoded message, as published); true when kept. A job that has
    /// ended keeps the model it has: a model arriving later (a forged one,
    /// or one of a job that ended before its model) does not replace it.
    pub fn set_model(&self, job: &JobId, model: &[u8]) -> Result<bool, JournalError> {
        Ok(self.exec(
            "INSERT INTO models (job, model)
             SELECT job, ?2 FROM jobs WHERE job = ?1
             ON CONFLICT (job) DO UPDATE SET model = excluded.model
             WHERE (SELECT state FROM jobs WHERE job = ?1)
                   NOT IN ('delivered', 'failed', 'superseded', 'cancelled')",
            params![job.as_str(), model],
        )? > 0)
    }

    /// The model journaled for `job` (its encoded message): `None` for an
    /// unknown job, `Some(None)` for a job without one yet.
    pub fn model(&self, job: &JobId) -> Result<Option<Option<Vec<u8>>>, JournalError> {
        self.column(Column::Model, job)
    }

    /// The machine of `job`, if journaled.
    pub fn machine(&self, job: &JobId) -> Result<Option<MachineId>, JournalError> {
        let machine: Option<String> = self.column(Column::Machine, job)?;
        machine
            .map(|m| MachineId::new(m).map_err(|e| corrupt("machine", e)))
            .transpose()
    }

    /// The request of a job as journaled (its encoded message).
    pub fn request_bytes(&self, job: &JobId) -> Result<Option<Vec<u8>>, JournalError> {
        self.column(Column::Request, job)
    }

    /// One column of `job`'s row: `None` for an unknown job.
    fn column<T: rusqlite::types::FromSql>(
        &self,
        column: Column,
        job: &JobId,
    ) -> Result<Option<T>, JournalError> {
        let sql = match column {
            Column::Model => {
                "SELECT m.model FROM jobs j LEFT JOIN models m ON m.job = j.job WHERE j.job = ?1"
            }
            Column::Machine => "SELECT machine FROM jobs WHERE job = ?1",
            Column::Request => "SELECT request FROM jobs WHERE job = ?1",
        };
        Ok(self
            .conn
            .prepare_cached(sql)?
            .query_row([job.as_str()], |r| r.get(0))
            .optional()?)
    }

    /// The request of a job, decoded.
    pub fn request(&self, job: &JobId) -> Result<Option<JobRequest>, JournalError> {
        self.request_bytes(job)?
            .map(|b| decode(&b).map_err(|e| corrupt("request", e)))
            .transpose()
    }
}

/// A column read by job ([`Journal::column`]).
#[derive(Debug, Clone, Copy)]
enum Column {
    Model,
    Machine,
    Request,
}

/// One job's status read on `conn` (the journal's or a reader's).
fn status_in(conn: &Connection, job: &JobId) -> Result<Option<JobStatus>, JournalError> {
    let mut stmt = conn.prepare_cached(&format!("{SELECT_STATUS} WHERE job = ?1"))?;
    let row = stmt.query_row([job.as_str()], row_parts).optional()?;
    row.map(status_from).transpose()
}

const SELECT_STATUS: &str = "SELECT job, machine, part_number, state, attempts, accepted_at_ms, updated_at_ms, waiting_for, receipt_json, errors_json, warnings_json, quantity FROM jobs";

type Parts = (
    String,
    String,
    String,
    String,
    u32,
    i64,
    i64,
    Option<String>,
    Option<String>,
    Option<String>,
    Option<String>,
    u32,
);

fn row_parts(r: &rusqlite::Row<'_>) -> rusqlite::Result<Parts> {
    Ok((
        r.get(0)?,
        r.get(1)?,
        r.get(2)?,
        r.get(3)?,
        r.get(4)?,
        r.get(5)?,
        r.get(6)?,
        r.get(7)?,
        r.get(8)?,
        r.get(9)?,
        r.get(10)?,
        r.get(11)?,
    ))
}

fn status_from(p: Parts) -> Result<JobStatus, JournalError> {
    let (
        job,
        machine,
        part_number,
        state,
        attempts,
        accepted,
        updated,
        waiting_for,
        receipt,
        errors,
        warnings,
        quantity,
    ) = p;
    let receipt: Option<DeliveryReceipt> = receipt
        .map(|j| serde_json::from_str(&j).map_err(|e| corrupt("receipt", e)))
        .transpose()?;
    let errors: Vec<JobError> = errors
        .map(|j| serde_json::from_str(&j).map_err(|e| corrupt("errors", e)))
        .transpose()?
        .unwrap_or_default();
    let warnings: Vec<Warning> = warnings
        .map(|j| serde_json::from_str(&j).map_err(|e| corrupt("warnings", e)))
        .transpose()?
        .unwrap_or_default();
    Ok(JobStatus {
        job: JobId::new(job).map_err(|e| corrupt("job", e))?,
        machine: MachineId::new(machine).map_err(|e| corrupt("machine", e))?,
        part_number,
        state: JobState::parse(&state).ok_or_else(|| corrupt("state", state))?,
        attempts,
        accepted_at_ms: accepted as u64,
        updated_at_ms: updated as u64,
        waiting_for,
        program: receipt.as_ref().map(|r| ProgramRef {
            name: r.name.clone(),
            sha256: r.sha256.clone(),
            path: r.path.clone(),
        }),
        receipt,
        errors,
        warnings,
        quantity,
    })
}

/// Adds the column `name` of type `decl` to the jobs table of a journal
/// written before it existed; a journal that has it is left as it is.
fn add_column(conn: &Connection, name: &str, decl: &str) -> Result<bool, JournalError> {
    let has: bool = conn
        .prepare("SELECT 1 FROM pragma_table_info('jobs') WHERE name = ?1")?
        .exists([name])?;
    if !has {
        conn.execute_batch(&format!("ALTER TABLE jobs ADD COLUMN {name} {decl}"))?;
    }
    Ok(!has)
}

/// Moves the models of a journal that kept them in the jobs' rows into
/// their own table, and drops the column.
fn move_models(conn: &Connection) -> Result<(), JournalError> {
    let has: bool = conn
        .prepare("SELECT 1 FROM pragma_table_info('jobs') WHERE name = 'model'")?
        .exists([])?;
    if has {
        conn.execute_batch(
            "BEGIN IMMEDIATE;
             INSERT OR IGNORE INTO models (job, model)
                 SELECT job, model FROM jobs WHERE model IS NOT NULL;
             ALTER TABLE jobs DROP COLUMN model;
             COMMIT;",
        )?;
    }
    Ok(())
}

/// Fills the new `quantity` column of a journal from each job's request.
fn fill_quantities(conn: &Connection) -> Result<(), JournalError> {
    let rows: Vec<(i64, Vec<u8>)> = conn
        .prepare("SELECT seq, request FROM jobs")?
        .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))?
        .collect::<Result<_, _>>()?;
    for (seq, bytes) in rows {
        // A request this version cannot read keeps 0: "not said", as from
        // an older station; the job itself is left as it is.
        match decode::<JobRequest>(&bytes) {
            Ok(req) => {
                conn.execute(
                    "UPDATE jobs SET quantity = ?2 WHERE seq = ?1",
                    params![seq, req.spec.job.quantity],
                )?;
            }
            Err(e) => {
                tracing::warn!(seq, error = %e, "a journaled request does not decode; its quantity stays unknown")
            }
        }
    }
    Ok(())
}

fn corrupt(what: &'static str, e: impl std::fmt::Display) -> JournalError {
    JournalError::Corrupt {
        what,
        detail: e.to_string(),
    }
}

fn station_error(code: Code, field: &str, expected: &str, got: &str) -> JobError {
    let message = match code {
        Code::JOB_ID_EXISTS => {
            "this job id is already journaled with a different job spec (a resubmission must carry the same spec); use a new job id"
        }
        _ => "the station could not journal the job; see its log",
    };
    JobError::new(Stage::Station, code, field, expected, got, message)
}

fn db_error(e: rusqlite::Error) -> JobError {
    station_error(
        Code::JOURNAL_ERROR,
        "-",
        "a writable journal",
        &e.to_string(),
    )
}

mod reader;
pub use reader::JournalReader;

#[cfg(test)]
mod tests;
