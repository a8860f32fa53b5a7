//! A read-only view of the journal on its own connection.
//!
//! In WAL mode a reader sees the last committed state and neither waits for
//! the writer nor holds it up: the station's loop may be in the middle of a
//! group commit (an fsync) while a reader answers from what is already
//! durable.

use std::path::Path;

use gearcam_proto::{JobId, JobStatus};
use rusqlite::{Connection, OpenFlags};

use super::{status_in, JournalError};

/// The committed journal, read on a connection of its own.
#[derive(Debug)]
pub struct JournalReader {
    conn: Connection,
}

impl JournalReader {
    /// Opens the journal at `path` (made by [`super::Journal::open`]) for
    /// reading only.
    pub fn open(path: &Path) -> Result<JournalReader, JournalError> {
        let conn = Connection::open_with_flags(
            path,
            OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX,
        )?;
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        Ok(JournalReader { conn })
    }

    /// One job's status as last committed.
    pub fn status(&self, job: &JobId) -> Result<Option<JobStatus>, JournalError> {
        status_in(&self.conn, job)
    }
}
