//! Resolving an operator's edit at the machine. The agent never overwrites a
//! program changed at the machine (`PROGRAM_CHANGED_AT_MACHINE`); a person who
//! reviewed the edit decides: adopt it as the current version, or replace it
//! with gearcam's version and keep the edit in the history. Either way the
//! edit becomes a version with who and when. The decision is final: an
//! adoption ends the jobs that waited to replace the edit (`superseded`,
//! never stored after, whatever re-drives them); after a replacement they
//! are delivered at their next re-drive.

use gearcam_proto::Code;
use std::fs;
use std::path::Path;

use gearcam_proto::{now_ms, DeliveryReceipt, JobError, JobId, NcProgram, Stage};
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

/// A job an adoption ended: the program, the adopted version and who.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Superseded {
    /// Program name.
    pub name: String,
    /// The adopted version.
    pub seq: u64,
    /// Who adopted it.
    pub by: String,
}

/// A resolution done.
#[derive(Debug, Clone, PartialEq)]
pub struct Resolved {
    /// The version now current, as a receipt.
    pub receipt: DeliveryReceipt,
    /// Its sequence number in the store.
    pub seq: u64,
    /// The jobs the adoption ended (none for a replacement).
    pub superseded: Vec<JobId>,
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
    /// Returns the version now current and the jobs an adoption ended.
    pub fn resolve(
        &mut self,
        name: &str,
        resolution: Resolution,
        by: &str,
    ) -> Result<Resolved, JobError> {
        if !gearcam_proto::delivery::valid_by(by) {
            return Err(Stage::Agent.error(
                Code::BAD_STORE_REQUEST,
                "by",
                "who resolves the edit: 1 to 64 characters on one line",
                by.chars().take(80).collect::<String>(),
                "a resolution is recorded with the name of the person who decided",
            ));
        }
        let latest = self.latest(name)?;
        let path = self.config.program_dir.join(&latest.file_name);
        let edit = self.edit_at_machine(&latest, &path, resolution)?;
        let version = Version {
            name,
            latest: &latest,
            dialect: self.config.dialect.as_str(),
            now: now_ms(),
            by,
        };
        let now = version.now;
        let mut superseded = Vec::new();
        let current = match (resolution, edit) {
            (Resolution::Adopt, Some(edit)) => {
                superseded = self.adopt(&version, &edit)?;
                edit
            }
            (Resolution::Adopt, None) => unreachable!("refused above"),
            (Resolution::Replace, edit) => {
                self.replace(&version, edit.as_deref(), &path)?;
                latest.text.clone()
            }
        };
        let seq = self.current_seq(&latest.file_name)?;
        let receipt = DeliveryReceipt {
            job_id: JobId::new(latest.job.clone()).map_err(|e| {
                Stage::Agent.error(
                    Code::STORE_INDEX_ERROR,
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
        };
        Ok(Resolved {
            receipt,
            seq,
            superseded,
        })
    }

    /// The newest version of program `name` the index knows (pending ones
    /// aside), or `UNKNOWN_PROGRAM` when this store never held it.
    fn latest(&self, name: &str) -> Result<Latest, JobError> {
        self.conn
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
                    Code::UNKNOWN_PROGRAM,
                    "name",
                    format!("a program in the store of {}", self.config.machine),
                    name,
                    "this machine's store has never held a program of this name",
                )
            })
    }

    /// The edit at the machine: the text of the file at `path` when it
    /// differs from the newest version, or none when the file was deleted
    /// (which only a replacement can resolve). `NO_CONFLICT` when the file
    /// is the current version, is not text, or is gone and would be adopted.
    fn edit_at_machine(
        &self,
        latest: &Latest,
        path: &Path,
        resolution: Resolution,
    ) -> Result<Option<String>, JobError> {
        let on_disk = match fs::read(path) {
            Ok(bytes) => Some(bytes),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(io_error(path)(e)),
        };
        let no_conflict = |got: String, message: &str| {
            Stage::Agent.error(
                Code::NO_CONFLICT,
                "name",
                format!(
                    "a program of {} changed at the machine",
                    self.config.machine
                ),
                got,
                message.to_string(),
            )
        };
        match on_disk {
            Some(bytes) if sha256_hex(&bytes) == latest.sha256 => Err(no_conflict(
                format!("{} as gearcam stored it", latest.file_name),
                "the file at the machine is the current version; there is nothing to resolve",
            )),
            Some(bytes) => Ok(Some(String::from_utf8(bytes).map_err(|_| {
                Stage::Agent.error(
                    Code::NO_CONFLICT,
                    "name",
                    "a text program at the machine",
                    format!("{} is not UTF-8 text", latest.file_name),
                    "the file at the machine is not a text program; look at it at the machine",
                )
            })?)),
            None if resolution == Resolution::Adopt => Err(no_conflict(
                format!("no file {} at the machine", latest.file_name),
                "the program was deleted at the machine; there is no edit to adopt (--replace writes gearcam's version back)",
            )),
            None => Ok(None),
        }
    }

    /// Adopts `edit` as the current version. The adopted version and the end
    /// of the jobs that waited to replace it are one transaction: no crash
    /// leaves the edit adopted and a waiting job free to overwrite it.
    /// Returns the jobs ended.
    fn adopt(&mut self, version: &Version<'_>, edit: &str) -> Result<Vec<JobId>, JobError> {
        let tx = self.conn.transaction().map_err(index_error)?;
        version.insert(&tx, "adopted", edit).map_err(index_error)?;
        let seq = tx.last_insert_rowid();
        let latest = version.latest;
        let superseded = supersede(
            &tx,
            &latest.file_name,
            version.name,
            seq,
            version.by,
            version.now,
        )
        .map_err(index_error)?;
        tx.commit().map_err(index_error)?;
        Ok(superseded)
    }

    /// Writes gearcam's newest version back to `path` and records it as
    /// `restored`. The edit, if any, is recorded before the file is
    /// replaced: a crash in between leaves the edit as the newest version,
    /// as if adopted, never lost.
    fn replace(
        &self,
        version: &Version<'_>,
        edit: Option<&str>,
        path: &Path,
    ) -> Result<(), JobError> {
        let latest = version.latest;
        if let Some(edit) = edit {
            version
                .insert(&self.conn, "machine-edit", edit)
                .map_err(index_error)?;
        }
        write_atomically(
            &self.config.program_dir,
            &latest.file_name,
            latest.text.as_bytes(),
        )
        .map_err(io_error(path))?;
        version
            .insert(&self.conn, "restored", &latest.text)
            .map_err(index_error)?;
        // gearcam's version is current again: the jobs that waited
        // are delivered at their next re-drive.
        self.conn
            .execute("DELETE FROM held WHERE file_name = ?1", [&latest.file_name])
            .map_err(index_error)?;
        Ok(())
    }

    /// The sequence number of the newest version of `file_name` (pending
    /// ones aside): the version a resolution made current.
    fn current_seq(&self, file_name: &str) -> Result<u64, JobError> {
        Ok(self
            .conn
            .query_row(
                "SELECT MAX(seq) FROM programs WHERE file_name = ?1 AND state != 'pending'",
                [file_name],
                |r| r.get::<_, i64>(0),
            )
            .map_err(index_error)? as u64)
    }

    /// Records that job `p` waits on the edit at the machine of `file_name`
    /// (its delivery was refused with `PROGRAM_CHANGED_AT_MACHINE`), so that
    /// an adoption of the edit ends it. Other refusals are not recorded.
    pub(super) fn hold(&self, p: &NcProgram, file_name: &str, error: &JobError) {
        if error.code != Code::PROGRAM_CHANGED_AT_MACHINE {
            return;
        }
        if let Err(e) = self.conn.execute(
            "INSERT OR REPLACE INTO held (job, file_name, at_ms) VALUES (?1, ?2, ?3)",
            params![p.job_id.as_str(), file_name, now_ms() as i64],
        ) {
            tracing::error!(job = %p.job_id, error = %e, "cannot record the job waiting on the edit at the machine");
        }
    }

    /// Whether an adoption ended `job`, and by which version.
    pub fn superseded(&self, job: &str) -> Result<Option<Superseded>, JobError> {
        self.row(
            "SELECT name, seq, by_user FROM superseded WHERE job = ?1",
            [job],
            |r| {
                Ok(Superseded {
                    name: r.get(0)?,
                    seq: r.get::<_, i64>(1)? as u64,
                    by: r.get(2)?,
                })
            },
        )
    }
}

/// A version a resolution records: of the newest version's program, file,
/// job and part, with the store's dialect, the time and who decided.
struct Version<'a> {
    name: &'a str,
    latest: &'a Latest,
    dialect: &'a str,
    now: u64,
    by: &'a str,
}

impl Version<'_> {
    /// Inserts the version with `state` and `text` into the index.
    fn insert(
        &self,
        conn: &rusqlite::Connection,
        state: &str,
        text: &str,
    ) -> rusqlite::Result<usize> {
        let latest = self.latest;
        conn.execute(
            "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part, by_user)
             VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)",
            params![
                self.name,
                latest.file_name,
                latest.job,
                latest.revision,
                sha256_hex(text.as_bytes()),
                text.len() as i64,
                self.dialect,
                self.now as i64,
                state,
                text,
                latest.part,
                self.by
            ],
        )
    }
}

/// The error of a failed read or write of the program file at `path`.
fn io_error(path: &Path) -> impl Fn(std::io::Error) -> JobError + '_ {
    move |e| {
        Stage::Agent.error(
            Code::STORE_IO_ERROR,
            "-",
            "a readable and writable program directory",
            e.to_string(),
            format!("cannot read or write {}", path.display()),
        )
    }
}

/// Ends the jobs held on `file_name`: superseded by version `seq` of `name`,
/// adopted by `by`. Returns them.
fn supersede(
    conn: &rusqlite::Connection,
    file_name: &str,
    name: &str,
    seq: i64,
    by: &str,
    now: u64,
) -> rusqlite::Result<Vec<JobId>> {
    // A job held once but stored since (the file was put back as it was)
    // waits for nothing: it is not superseded.
    conn.execute(
        "DELETE FROM held WHERE file_name = ?1 AND job IN (SELECT job FROM programs WHERE state = 'stored')",
        [file_name],
    )?;
    let jobs: Vec<String> = conn
        .prepare("SELECT job FROM held WHERE file_name = ?1 ORDER BY at_ms")?
        .query_map([file_name], |r| r.get(0))?
        .collect::<rusqlite::Result<_>>()?;
    conn.execute(
        "INSERT OR REPLACE INTO superseded (job, name, seq, by_user, at_ms)
         SELECT job, ?2, ?3, ?4, ?5 FROM held WHERE file_name = ?1",
        params![file_name, name, seq, by, now as i64],
    )?;
    conn.execute("DELETE FROM held WHERE file_name = ?1", [file_name])?;
    Ok(jobs
        .into_iter()
        .filter_map(|j| JobId::new(j).ok())
        .collect())
}

#[cfg(test)]
mod tests {
    use super::super::tests::{program, store};
    use super::*;

    /// An edit at the machine must not block every later delivery of the
    /// program with no way forward but deleting the file, nor stay out of the
    /// history: adopted, it becomes a version with who adopted it and when.
    #[test]
    fn an_edit_is_adopted_as_a_version_with_who_and_when() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "first, feed lowered by the operator\n").unwrap();
        let blocked = s.store(&program("J2", "SP_1", "second\n")).unwrap_err();
        assert_eq!(blocked.code, "PROGRAM_CHANGED_AT_MACHINE");

        let resolved = s.resolve("SP_1", Resolution::Adopt, "operator Li").unwrap();
        assert_eq!(
            resolved.receipt.sha256,
            sha256_hex(b"first, feed lowered by the operator\n")
        );
        // The job that waited to replace the edit ends with the adoption.
        assert_eq!(resolved.superseded, [JobId::new("J2").unwrap()]);
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(
            (h[0].state.as_str(), h[0].current, h[0].by.as_str()),
            ("adopted", true, "operator Li")
        );
        let text = s.version("SP_1", h[0].seq).unwrap().unwrap().text;
        assert_eq!(text, "first, feed lowered by the operator\n");
        // Nothing left to resolve. The waiting job, re-driven, is refused
        // for good: the adopted edit stays at the machine.
        assert_eq!(
            s.resolve("SP_1", Resolution::Adopt, "x").unwrap_err().code,
            "NO_CONFLICT"
        );
        let e = s.store(&program("J2", "SP_1", "second\n")).unwrap_err();
        assert_eq!(e.code, "JOB_SUPERSEDED");
        assert!(
            e.got.contains(&format!("version {} of SP_1", resolved.seq))
                && e.got.contains("operator Li"),
            "{e:?}"
        );
        assert_eq!(
            fs::read_to_string(&path).unwrap(),
            "first, feed lowered by the operator\n"
        );
        assert_eq!(
            s.superseded("J2").unwrap().map(|x| (x.name, x.seq, x.by)),
            Some(("SP_1".to_string(), resolved.seq, "operator Li".to_string()))
        );
        // A job submitted again after the decision is a new job: delivered.
        s.store(&program("J3", "SP_1", "second\n")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "second\n");
    }

    /// A job held on an edit, then stored once the file was put back as it
    /// was, is not superseded by a later adoption: it waits for nothing.
    #[test]
    fn a_job_stored_since_it_was_held_is_not_superseded() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "operator edit\n").unwrap();
        assert!(s.store(&program("J2", "SP_1", "second\n")).is_err());
        // The operator puts the file back; J2 goes through.
        fs::write(&path, "first\n").unwrap();
        s.store(&program("J2", "SP_1", "second\n")).unwrap();
        fs::write(&path, "another edit\n").unwrap();
        let resolved = s.resolve("SP_1", Resolution::Adopt, "operator Li").unwrap();
        assert!(resolved.superseded.is_empty(), "{:?}", resolved.superseded);
        // Its receipt stands.
        assert!(s.superseded("J2").unwrap().is_none());
    }

    /// After a replacement the job that waited is delivered: nothing
    /// superseded it.
    #[test]
    fn a_replacement_lets_the_waiting_job_through() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "operator edit\n").unwrap();
        assert_eq!(
            s.store(&program("J2", "SP_1", "second\n"))
                .unwrap_err()
                .code,
            "PROGRAM_CHANGED_AT_MACHINE"
        );
        let resolved = s
            .resolve("SP_1", Resolution::Replace, "planner Wang")
            .unwrap();
        assert!(resolved.superseded.is_empty());
        s.store(&program("J2", "SP_1", "second\n")).unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "second\n");
        assert_eq!(s.superseded("J2").unwrap(), None);
    }

    #[test]
    fn a_replaced_edit_is_kept_in_the_history() {
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
