//! Resolving an operator's edit at the machine. The agent never overwrites a
//! program changed at the machine (`PROGRAM_CHANGED_AT_MACHINE`); a person who
//! reviewed the edit decides: adopt it as the current version, or replace it
//! with gearcam's version and keep the edit in the history. Either way the
//! edit becomes a version with who and when, and the jobs waiting on the
//! conflict are delivered at their next re-drive.

use std::fs;

use gearcam_proto::{now_ms, DeliveryReceipt, JobError, JobId, Stage};
use rusqlite::{params, OptionalExtension};

use super::{index_error, sha256_hex, write_atomically, Store};

/// What to do with an edit at the machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resolution {
    /// The file at the machine becomes the current version (`adopted`).
    Adopt,
    /// gearcam's current version is written back (`restored`); the edit is
    /// kept as a `machine-edit` version.
    Replace,
}

/// The newest version of a program, as the index has it.
#[derive(Debug)]
struct Latest {
    file_name: String,
    job: String,
    revision: u32,
    sha256: String,
    text: String,
    part: String,
}

impl Store {
    /// Resolves the conflict between the file of program `name` at the
    /// machine and the newest version the index knows; `by` is who decided.
    /// Returns the receipt of the version now current.
    pub fn resolve(
        &mut self,
        name: &str,
        resolution: Resolution,
        by: &str,
    ) -> Result<DeliveryReceipt, JobError> {
        if by.trim().is_empty() || by.chars().any(char::is_control) || by.chars().count() > 64 {
            return Err(Stage::Agent.error(
                "BAD_STORE_REQUEST",
                "by",
                "who resolves the edit: 1 to 64 characters on one line",
                by.chars().take(80).collect::<String>(),
                "a resolution is recorded with the name of the person who decided",
            ));
        }
        let latest = self
            .conn
            .query_row(
                "SELECT file_name, job, revision, sha256, text, part FROM programs
                 WHERE name = ?1 AND state != 'pending' ORDER BY seq DESC LIMIT 1",
                [name],
                |r| {
                    Ok(Latest {
                        file_name: r.get(0)?,
                        job: r.get(1)?,
                        revision: r.get(2)?,
                        sha256: r.get(3)?,
                        text: r.get(4)?,
                        part: r.get(5)?,
                    })
                },
            )
            .optional()
            .map_err(index_error)?
            .ok_or_else(|| {
                Stage::Agent.error(
                    "UNKNOWN_PROGRAM",
                    "name",
                    format!("a program in the store of {}", self.config.machine),
                    name,
                    "this machine's store has never held a program of this name",
                )
            })?;
        let path = self.config.program_dir.join(&latest.file_name);
        let io_error = |e: std::io::Error| {
            Stage::Agent.error(
                "STORE_IO_ERROR",
                "-",
                "a readable and writable program directory",
                e.to_string(),
                format!("cannot read or write {}", path.display()),
            )
        };
        let on_disk = match fs::read(&path) {
            Ok(bytes) => Some(bytes),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(io_error(e)),
        };
        let no_conflict = |got: String, message: &str| {
            Stage::Agent.error(
                "NO_CONFLICT",
                "name",
                format!(
                    "a program of {} changed at the machine",
                    self.config.machine
                ),
                got,
                message.to_string(),
            )
        };
        let edit = match on_disk {
            Some(bytes) if sha256_hex(&bytes) == latest.sha256 => {
                return Err(no_conflict(
                    format!("{} as gearcam stored it", latest.file_name),
                    "the file at the machine is the current version; there is nothing to resolve",
                ))
            }
            Some(bytes) => Some(String::from_utf8(bytes).map_err(|_| {
                Stage::Agent.error(
                    "NO_CONFLICT",
                    "name",
                    "a text program at the machine",
                    format!("{} is not UTF-8 text", latest.file_name),
                    "the file at the machine is not a text program; look at it at the machine",
                )
            })?),
            None if resolution == Resolution::Adopt => {
                return Err(no_conflict(
                    format!("no file {} at the machine", latest.file_name),
                    "the program was deleted at the machine; there is no edit to adopt (--replace writes gearcam's version back)",
                ))
            }
            None => None,
        };
        let now = now_ms();
        let insert = |conn: &rusqlite::Connection, state: &str, text: &str| {
            conn.execute(
                "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part, by_user)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)",
                params![
                    name,
                    latest.file_name,
                    latest.job,
                    latest.revision,
                    sha256_hex(text.as_bytes()),
                    text.len() as i64,
                    self.config.dialect.as_str(),
                    now as i64,
                    state,
                    text,
                    latest.part,
                    by
                ],
            )
        };
        let current = match (resolution, edit) {
            (Resolution::Adopt, Some(edit)) => {
                insert(&self.conn, "adopted", &edit).map_err(index_error)?;
                edit
            }
            (Resolution::Adopt, None) => unreachable!("refused above"),
            (Resolution::Replace, edit) => {
                // The edit is recorded before the file is replaced: a crash in
                // between leaves the edit as the newest version, as if
                // adopted, never lost.
                if let Some(edit) = &edit {
                    insert(&self.conn, "machine-edit", edit).map_err(index_error)?;
                }
                write_atomically(
                    &self.config.program_dir,
                    &latest.file_name,
                    latest.text.as_bytes(),
                )
                .map_err(io_error)?;
                insert(&self.conn, "restored", &latest.text).map_err(index_error)?;
                latest.text.clone()
            }
        };
        Ok(DeliveryReceipt {
            job_id: JobId::new(latest.job.clone()).map_err(|e| {
                Stage::Agent.error(
                    "STORE_INDEX_ERROR",
                    "job",
                    "a valid job id",
                    latest.job.clone(),
                    e.to_string(),
                )
            })?,
            machine: self.config.machine.clone(),
            name: name.to_string(),
            path: path.display().to_string(),
            file_name: latest.file_name.clone(),
            revision: latest.revision,
            sha256: sha256_hex(current.as_bytes()),
            size_bytes: current.len() as u64,
            stored_at_ms: now,
            duplicate: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{program, store};
    use super::*;

    /// Issue 12 point 2: an edit at the machine blocked every later delivery
    /// of the program, with no way forward but deleting the file, and the
    /// edit never reached the history.
    #[test]
    fn point_2_an_edit_is_adopted_as_a_version_with_who_and_when() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "first, feed lowered by the operator\n").unwrap();
        let blocked = s.store(&program("J2", "SP_1", "second\n")).unwrap_err();
        assert_eq!(blocked.code, "PROGRAM_CHANGED_AT_MACHINE");

        let receipt = s.resolve("SP_1", Resolution::Adopt, "operator Li").unwrap();
        assert_eq!(
            receipt.sha256,
            sha256_hex(b"first, feed lowered by the operator\n")
        );
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(
            (h[0].state.as_str(), h[0].current, h[0].by.as_str()),
            ("adopted", true, "operator Li")
        );
        let text = s.version("SP_1", h[0].seq).unwrap().unwrap().text;
        assert_eq!(text, "first, feed lowered by the operator\n");
        // Nothing left to resolve, and the waiting delivery now goes through.
        assert_eq!(
            s.resolve("SP_1", Resolution::Adopt, "x").unwrap_err().code,
            "NO_CONFLICT"
        );
        s.store(&program("J2", "SP_1", "second\n")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "second\n");
    }

    #[test]
    fn point_2_a_replaced_edit_is_kept_in_the_history() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "operator edit\n").unwrap();
        s.resolve("SP_1", Resolution::Replace, "planner Wang")
            .unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "first\n");
        let h = s.history(Some("SP_1")).unwrap();
        let states: Vec<_> = h.iter().map(|v| (v.state.as_str(), v.current)).collect();
        assert_eq!(
            states,
            [
                ("restored", true),
                ("machine-edit", false),
                ("stored", false)
            ]
        );
        assert_eq!(
            s.version("SP_1", h[1].seq).unwrap().unwrap().text,
            "operator edit\n"
        );
        assert_eq!(h[1].by, "planner Wang");
        // A deleted file: nothing to adopt, but it can be written back.
        fs::remove_file(&path).unwrap();
        assert_eq!(
            s.resolve("SP_1", Resolution::Adopt, "x").unwrap_err().code,
            "NO_CONFLICT"
        );
        s.resolve("SP_1", Resolution::Replace, "x").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "first\n");
        assert_eq!(
            s.resolve("SP_1", Resolution::Replace, "").unwrap_err().code,
            "BAD_STORE_REQUEST"
        );
        assert_eq!(
            s.resolve("NOPE", Resolution::Replace, "x")
                .unwrap_err()
                .code,
            "UNKNOWN_PROGRAM"
        );
    }
}
