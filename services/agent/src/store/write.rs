//! Writing programs durably, with an intent record so that a crash at any
//! point leaves a store the agent can finish or undo at its next start.
//!
//! Order of one group commit:
//!
//! 1. every file written to a temporary file beside its final name and
//!    made durable (on a local disk, one `syncfs` for the group; elsewhere
//!    an fsync each, in parallel); a failed write's temporary file is
//!    removed at once, and its program refused;
//! 2. at the same time as 1, one transaction inserts a `pending` row per
//!    program (the intent: job, revision, hash, text); both 1 and 2 are
//!    durable before any file is renamed (the intent of a program whose
//!    file failed is undone in 4);
//! 3. the station's word on each job (journaled for this machine, not
//!    cancelled), asked before 1 and 2 began so that its round trip overlaps
//!    their fsyncs: a program it does not confirm has its temporary file
//!    removed and is never renamed; then, per program, the file at the
//!    machine is compared again with what the checks saw (an operator's
//!    edit during the write is kept: the program is refused as changed at
//!    the machine), then the temporary file is renamed over the final name;
//!    the directory is fsynced;
//! 4. one transaction turns the renamed programs' rows to `stored` and
//!    deletes the rows of those not renamed; it is not fsynced on its own
//!    (steps 1–3 are durable, and they alone decide what `recover` makes of
//!    each row after a power cut), so the receipt waits for the fsyncs of 1
//!    and 2 (at once) and the directory's.
//!
//! A crash between 2 and 4 leaves `pending` rows: [`Store::recover`] (at
//! open) makes each `stored` when its file holds exactly its hash (the rename
//! happened) and deletes it otherwise (the old file is still there). So the
//! machine never holds a program the history does not show as current. A
//! file that already holds a program's exact bytes would make `recover` take
//! an unconfirmed intent for a rename: a group with such a program waits for
//! the station's word before 1 and 2, so no intent of a job the station did
//! not confirm can become history.

use gearcam_proto::Code;
use std::fs::{self, File};
use std::io::Write;
use std::path::{Path, PathBuf};

use gearcam_proto::{now_ms, DeliveryReceipt, JobError, NcProgram, Stage};
use rusqlite::params;

use super::{index_error, sha256_hex, Store};

/// A program of a batch that must be written.
#[derive(Debug)]
pub(super) struct Pending {
    pub(super) index: usize,
    pub(super) file_name: String,
    pub(super) hash: String,
    /// The hash of the file at the machine when the checks ran (`None`: no
    /// file); compared again right before the rename.
    pub(super) seen: Option<String>,
}

/// What storing a program needs.
#[derive(Debug)]
pub(super) enum Prepared {
    /// Already stored: the original receipt.
    Stored(DeliveryReceipt),
    /// To be written.
    Write(Pending),
    /// Refused because the file at the machine was changed there: once the
    /// station confirms the job, it is recorded as waiting on that edit
    /// (`Store::hold`), so an adoption of the edit ends it.
    Held { error: JobError, file_name: String },
}

impl Prepared {
    pub(super) fn held(error: JobError, file_name: String) -> Prepared {
        Prepared::Held { error, file_name }
    }
}

/// The station's word on each program's job: confirmed, or its error.
pub type Verdicts = Vec<Result<(), JobError>>;

/// A result per program of a batch: its receipt or its refusal.
pub type Results = Vec<Result<DeliveryReceipt, JobError>>;

/// The station's word on the job of each program of a batch, fetched once,
/// when it is first needed.
struct Confirm<'c> {
    ask: Option<Box<dyn FnOnce() -> Verdicts + 'c>>,
    verdicts: Vec<Result<(), JobError>>,
    n: usize,
}

impl<'c> Confirm<'c> {
    fn new(n: usize, ask: impl FnOnce() -> Verdicts + 'c) -> Confirm<'c> {
        Confirm {
            ask: Some(Box::new(ask)),
            verdicts: Vec::new(),
            n,
        }
    }

    /// Every program's verdict, waiting for the answer the first time; a
    /// program the answer leaves out is not confirmed.
    fn verdicts(&mut self) -> &[Result<(), JobError>] {
        if let Some(ask) = self.ask.take() {
            let mut v = ask();
            v.truncate(self.n);
            let missing = crate::guard::unasked("the answer named fewer jobs than were asked");
            v.resize(self.n, Err(missing));
            self.verdicts = v;
        }
        &self.verdicts
    }
}

fn io_error(dir: &Path, file_name: &str, e: &std::io::Error) -> JobError {
    Stage::Agent.error(
        Code::STORE_IO_ERROR,
        "-",
        "a writable program directory",
        e.to_string(),
        format!(
            "cannot write {} (disk full?); the job waits and is delivered once the store can write again",
            dir.join(file_name).display()
        ),
    )
}

impl Store {
    /// Stores several programs with one group commit: every file is written
    /// and fsynced (in parallel), renamed, the directory fsynced once, and all
    /// index rows inserted in one transaction; each result is as [`Store::store`]
    /// would give it alone. Programs that touch a file or job already pending
    /// in the batch are committed in a later group, so order is kept.
    pub fn store_batch(
        &mut self,
        programs: &[NcProgram],
    ) -> Vec<Result<DeliveryReceipt, JobError>> {
        self.store_confirmed(programs, || vec![Ok(()); programs.len()])
            .0
    }

    /// [`Store::store_batch`] for programs whose jobs the station has yet to
    /// confirm: `ask` gives its word on each program's job (the agent asks
    /// before storing begins, so the round trip overlaps the writes' fsyncs).
    /// A program it does not confirm gets the station's error and is never
    /// renamed into the program directory, nor left in the index, nor
    /// recorded as waiting on an edit at the machine. Returns each program's
    /// result and the station's verdict on its job.
    pub fn store_confirmed(
        &mut self,
        programs: &[NcProgram],
        ask: impl FnOnce() -> Verdicts,
    ) -> (Results, Verdicts) {
        let mut confirm = Confirm::new(programs.len(), ask);
        let mut held = Vec::new();
        let mut results: Vec<Option<Result<DeliveryReceipt, JobError>>> =
            vec![None; programs.len()];
        let mut pending: Vec<Pending> = Vec::new();
        for (i, p) in programs.iter().enumerate() {
            let clashes = pending.iter().any(|q| {
                let q = &programs[q.index];
                q.name == p.name || (q.job_id == p.job_id && q.revision == p.revision)
            });
            if clashes {
                let pending = std::mem::take(&mut pending);
                self.flush(programs, pending, &mut results, &mut confirm);
            }
            match self.prepare(p) {
                Ok(Prepared::Stored(receipt)) => results[i] = Some(Ok(receipt)),
                Ok(Prepared::Write(q)) => pending.push(Pending { index: i, ..q }),
                Ok(Prepared::Held { error, file_name }) => {
                    results[i] = Some(Err(error));
                    held.push((i, file_name));
                }
                Err(e) => results[i] = Some(Err(e)),
            }
        }
        self.flush(programs, pending, &mut results, &mut confirm);
        let verdicts = confirm.verdicts().to_vec();
        for (i, file_name) in held {
            if let (Ok(()), Some(Err(error))) = (&verdicts[i], &results[i]) {
                self.hold(&programs[i], &file_name, error);
            }
        }
        let results = results
            .into_iter()
            .zip(&verdicts)
            .map(|(r, v)| match v {
                Err(e) => Err(e.clone()),
                Ok(()) => r.expect("every program has a result"),
            })
            .collect();
        (results, verdicts)
    }

    /// Writes the pending programs durably and records them (module docs);
    /// a program whose job the station does not confirm is left out before
    /// its rename.
    fn flush(
        &mut self,
        programs: &[NcProgram],
        pending: Vec<Pending>,
        results: &mut [Option<Result<DeliveryReceipt, JobError>>],
        confirm: &mut Confirm,
    ) {
        // A file already holding a program's bytes: the station's word
        // first (module docs).
        let pending = if pending.iter().any(|q| q.seen.as_ref() == Some(&q.hash)) {
            let verdicts = confirm.verdicts();
            pending
                .into_iter()
                .filter(|q| match &verdicts[q.index] {
                    Ok(()) => true,
                    Err(e) => {
                        results[q.index] = Some(Err(e.clone()));
                        false
                    }
                })
                .collect()
        } else {
            pending
        };
        if pending.is_empty() {
            return;
        }
        let dir = self.config.program_dir.clone();
        // 1 and 2 at once: the temporary files are written and fsynced
        // while the intents are committed, so the two fsyncs overlap; both
        // are durable before any rename.
        let stored_at = now_ms();
        let (written, seqs) = std::thread::scope(|scope| {
            let writer = scope.spawn(|| write_temps(&dir, programs, &pending));
            let seqs = self.record_intents(programs, &pending, stored_at);
            let written = writer.join().unwrap_or_else(|_| {
                pending
                    .iter()
                    .map(|_| Err(std::io::Error::other("writer thread panicked")))
                    .collect()
            });
            (written, seqs)
        });
        let seqs = match seqs {
            Ok(seqs) => seqs,
            Err(e) => {
                for (q, tmp) in pending.into_iter().zip(written) {
                    if let Ok(tmp) = tmp {
                        let _ = fs::remove_file(&tmp);
                    }
                    results[q.index] = Some(Err(index_error(e.to_string())));
                }
                return;
            }
        };
        // A program the station does not confirm, or whose file could not
        // be written, is refused, its intent undone.
        let verdicts = confirm.verdicts();
        let (mut ready, mut seqs_ready, mut unwritten) = (Vec::new(), Vec::new(), Vec::new());
        for ((q, tmp), seq) in pending.into_iter().zip(written).zip(seqs) {
            match (tmp, &verdicts[q.index]) {
                (Ok(tmp), Ok(())) => {
                    ready.push((q, tmp));
                    seqs_ready.push(seq);
                }
                (tmp, Err(e)) => {
                    if let Ok(tmp) = tmp {
                        let _ = fs::remove_file(&tmp);
                    }
                    results[q.index] = Some(Err(e.clone()));
                    unwritten.push(seq);
                }
                (Err(e), Ok(())) => {
                    results[q.index] = Some(Err(io_error(&dir, &q.file_name, &e)));
                    unwritten.push(seq);
                }
            }
        }
        if self.config.faults.pause_before_rename_ms > 0 {
            std::thread::sleep(std::time::Duration::from_millis(
                self.config.faults.pause_before_rename_ms,
            ));
        }
        // 3. Compare again, then rename.
        let (renamed, mut undone) = self.rename_unchanged(&dir, ready, seqs_ready, results);
        undone.extend(unwritten);
        let synced = File::open(&dir).and_then(|d| d.sync_all());
        if self.config.faults.crash_after_rename && !renamed.is_empty() {
            tracing::error!("fault injection: aborting after the rename, before the index commit");
            std::process::abort();
        }
        // 4. Stored (or undone) in the index.
        let committed = self.settle_intents(&renamed, &undone);
        for (q, _) in renamed {
            let p = &programs[q.index];
            results[q.index] = Some(match (&synced, &committed) {
                (Err(e), _) => Err(io_error(&dir, &q.file_name, e)),
                (_, Err(e)) => Err(index_error(e.to_string())),
                (Ok(()), Ok(())) => Ok(DeliveryReceipt {
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

    /// Step 2: one transaction inserts a `pending` row (the intent) per
    /// program to write, committed before any rename. Returns the rows'
    /// sequence numbers, in the order of `pending`.
    fn record_intents(
        &mut self,
        programs: &[NcProgram],
        pending: &[Pending],
        stored_at: u64,
    ) -> rusqlite::Result<Vec<i64>> {
        let tx = self.conn.transaction()?;
        let mut seqs = Vec::with_capacity(pending.len());
        {
            let mut insert = tx.prepare_cached(
                "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part)
                 VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, 'pending', ?9, ?10)",
            )?;
            for q in pending {
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
                seqs.push(tx.last_insert_rowid());
            }
        }
        tx.commit()?;
        Ok(seqs)
    }

    /// Step 3: per program, compares the file at the machine again with what
    /// the checks saw (an operator's edit during the write is kept and the
    /// program refused), then renames the temporary file over the final
    /// name. A program not renamed gets its error in `results` and its
    /// temporary file removed. Returns the renamed programs with their
    /// rows, and the rows to undo.
    fn rename_unchanged(
        &self,
        dir: &Path,
        ready: Vec<(Pending, PathBuf)>,
        seqs: Vec<i64>,
        results: &mut [Option<Result<DeliveryReceipt, JobError>>],
    ) -> (Vec<(Pending, i64)>, Vec<i64>) {
        let mut renamed = Vec::new();
        let mut undone = Vec::new();
        for ((q, tmp), seq) in ready.into_iter().zip(seqs) {
            let outcome = match self.disk_hash(&q.file_name) {
                Err(e) => Err(e),
                Ok(now) if now != q.seen => Err(self.changed_at_machine(
                    &q.file_name,
                    now.as_deref().unwrap_or("no file (deleted)"),
                )),
                Ok(_) => fs::rename(&tmp, dir.join(&q.file_name))
                    .map_err(|e| io_error(dir, &q.file_name, &e)),
            };
            match outcome {
                Ok(()) => renamed.push((q, seq)),
                Err(e) => {
                    let _ = fs::remove_file(&tmp);
                    results[q.index] = Some(Err(e));
                    undone.push(seq);
                }
            }
        }
        (renamed, undone)
    }

    /// Step 4: one transaction turns the renamed programs' rows to `stored`
    /// and deletes the rows of those not renamed.
    fn settle_intents(
        &mut self,
        renamed: &[(Pending, i64)],
        undone: &[i64],
    ) -> rusqlite::Result<()> {
        // Not fsynced on its own: the intents and the renames are durable
        // already, and after a power cut `recover` comes to the same rows
        // from them; the next full commit (the next batch's intents) makes
        // it durable too. One fsync less per batch.
        self.conn.pragma_update(None, "synchronous", "NORMAL")?;
        let settled = (|| {
            let tx = self.conn.transaction()?;
            let mut stored =
                tx.prepare_cached("UPDATE programs SET state = 'stored' WHERE seq = ?1")?;
            for (_, seq) in renamed {
                stored.execute([seq])?;
            }
            let mut delete = tx.prepare_cached("DELETE FROM programs WHERE seq = ?1")?;
            for seq in undone {
                delete.execute([seq])?;
            }
            drop((stored, delete));
            tx.commit()
        })();
        self.conn.pragma_update(None, "synchronous", "FULL")?;
        settled
    }

    /// Finishes or undoes the writes a crash cut off (module docs): a
    /// `pending` row whose file holds exactly its hash was renamed and becomes
    /// `stored`; any other is deleted. Returns (finished, undone).
    pub(super) fn recover(&mut self) -> Result<(usize, usize), crate::AgentError> {
        let pending: Vec<(i64, String, String)> = self
            .conn
            .prepare("SELECT seq, file_name, sha256 FROM programs WHERE state = 'pending'")?
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)))?
            .collect::<Result<_, _>>()?;
        let (mut finished, mut undone) = (0, 0);
        for (seq, file_name, hash) in pending {
            let path = self.config.program_dir.join(&file_name);
            let on_disk = match fs::read(&path) {
                Ok(bytes) => Some(sha256_hex(&bytes)),
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
                Err(e) => {
                    return Err(crate::AgentError::Io {
                        path: path.display().to_string(),
                        source: e,
                    })
                }
            };
            if on_disk.as_deref() == Some(hash.as_str()) {
                self.conn
                    .execute("UPDATE programs SET state = 'stored' WHERE seq = ?1", [seq])?;
                finished += 1;
                tracing::info!(file = %file_name, seq, "finished a write a crash cut off after the rename");
            } else {
                self.conn
                    .execute("DELETE FROM programs WHERE seq = ?1", [seq])?;
                undone += 1;
                tracing::info!(file = %file_name, seq, "undid a write a crash cut off before the rename");
            }
        }
        Ok((finished, undone))
    }
}

/// Removes temporary files a killed agent left behind (`.{name}.tmp-{pid}`):
/// they never became programs, since a program exists only once renamed.
pub(super) fn remove_stale_temporaries(dir: &Path) {
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

/// Step 1: writes each pending program to a temporary file beside its final
/// name and makes it durable. Returns each one's temporary file or error,
/// in the order of `pending`.
///
/// Several files in a directory on a local disk file system are written,
/// then made durable together by one `syncfs` of that file system: one
/// cache flush for the group, where an fsync each costs a flush each (on a
/// disk without a journal, 15 files took 11 ms fsynced in parallel and
/// 5 ms with one `syncfs`). Elsewhere (a network share, which the control
/// may read the programs from; another system) each file is fsynced, in
/// parallel (concurrent fsyncs share a journal's commits where there is
/// one).
fn write_temps(
    dir: &Path,
    programs: &[NcProgram],
    pending: &[Pending],
) -> Vec<std::io::Result<PathBuf>> {
    let text = |q: &Pending| programs[q.index].text.as_bytes();
    if pending.len() > 1 && group_sync::local_disk(dir) {
        let written: Vec<_> = pending
            .iter()
            .map(|q| write_unsynced(dir, &q.file_name, text(q)))
            .collect();
        return match group_sync::sync(dir) {
            Ok(()) => written,
            // Which file failed is not known: none is durable.
            Err(e) => written
                .into_iter()
                .map(|w| {
                    if let Ok(tmp) = w {
                        let _ = fs::remove_file(&tmp);
                    }
                    Err(std::io::Error::new(e.kind(), e.to_string()))
                })
                .collect(),
        };
    }
    std::thread::scope(|scope| {
        let handles: Vec<_> = pending
            .chunks(pending.len().div_ceil(8))
            .map(|chunk| {
                scope.spawn(move || {
                    chunk
                        .iter()
                        .map(|q| write_temp(dir, &q.file_name, text(q)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles
            .into_iter()
            .flat_map(|h| {
                h.join()
                    .unwrap_or_else(|_| vec![Err(std::io::Error::other("writer thread panicked"))])
            })
            .collect()
    })
}

/// One durability barrier for the files a batch wrote.
mod group_sync {
    use std::path::Path;

    /// True when `dir` is on a local disk file system whose `syncfs` writes
    /// back every dirty file and flushes the disk's cache (ext4, XFS,
    /// Btrfs).
    #[cfg(target_os = "linux")]
    pub(super) fn local_disk(dir: &Path) -> bool {
        const EXT4: i64 = 0xEF53;
        const XFS: i64 = 0x5846_5342;
        const BTRFS: i64 = 0x9123_683E;
        rustix::fs::statfs(dir).is_ok_and(|st| {
            // `FsWord` is i64 here, narrower on some systems.
            #[allow(clippy::useless_conversion)]
            let kind = i64::from(st.f_type);
            [EXT4, XFS, BTRFS].contains(&kind)
        })
    }

    #[cfg(not(target_os = "linux"))]
    pub(super) fn local_disk(_dir: &Path) -> bool {
        false
    }

    /// Writes back and flushes the file system holding `dir` (errors of
    /// any file's write-back since the directory was opened are reported).
    #[cfg(target_os = "linux")]
    pub(super) fn sync(dir: &Path) -> std::io::Result<()> {
        let d = std::fs::File::open(dir)?;
        rustix::fs::syncfs(&d).map_err(std::io::Error::from)
    }

    #[cfg(not(target_os = "linux"))]
    pub(super) fn sync(_dir: &Path) -> std::io::Result<()> {
        Err(std::io::Error::other("no syncfs on this system"))
    }
}

/// Writes `bytes` to a temporary file beside `dir/file_name`, not synced
/// (the group's `syncfs` makes it durable); on failure the temporary file
/// is removed at once.
fn write_unsynced(dir: &Path, file_name: &str, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    match File::create(&tmp).and_then(|mut f| f.write_all(bytes)) {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `bytes` to a temporary file beside `dir/file_name` and fsyncs it;
/// on failure the temporary file is removed at once.
fn write_temp(dir: &Path, file_name: &str, bytes: &[u8]) -> std::io::Result<PathBuf> {
    let tmp = dir.join(format!(".{file_name}.tmp-{}", std::process::id()));
    let written = File::create(&tmp).and_then(|mut f| {
        f.write_all(bytes)?;
        f.sync_all()
    });
    match written {
        Ok(()) => Ok(tmp),
        Err(e) => {
            let _ = fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `bytes` to `dir/file_name` atomically and durably.
pub(super) fn write_atomically(dir: &Path, file_name: &str, bytes: &[u8]) -> std::io::Result<()> {
    let tmp = write_temp(dir, file_name, bytes)?;
    if let Err(e) = fs::rename(&tmp, dir.join(file_name)) {
        let _ = fs::remove_file(&tmp);
        return Err(e);
    }
    File::open(dir)?.sync_all()
}

#[cfg(test)]
mod tests {
    use super::super::tests::{program, store};
    use super::*;

    /// An operator's edit made while the program is being written (after the
    /// checks, before the rename) is not overwritten.
    #[test]
    fn an_edit_during_the_write_is_kept() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        let second = program("J2", "SP_1", "second\n");
        let Prepared::Write(q) = s.prepare(&second).unwrap() else {
            panic!("a new version is written")
        };
        // The operator saves an edit now, between the checks and the rename.
        let path = dir.path().join("programs/_N_SP_1_MPF");
        fs::write(&path, "operator edit\n").unwrap();
        let mut results = vec![None];
        let mut confirm = Confirm::new(1, || vec![Ok(())]);
        s.flush(
            std::slice::from_ref(&second),
            vec![q],
            &mut results,
            &mut confirm,
        );
        let e = results[0].take().unwrap().unwrap_err();
        assert_eq!(e.code, "PROGRAM_CHANGED_AT_MACHINE");
        assert_eq!(fs::read_to_string(&path).unwrap(), "operator edit\n");
        // No row for the refused write, no temporary file left.
        assert_eq!(s.history(Some("SP_1")).unwrap().len(), 1);
        assert_eq!(
            fs::read_dir(dir.path().join("programs")).unwrap().count(),
            1
        );
    }

    /// A crash between the rename and the index commit must not leave the
    /// machine holding a program the history does not show: the intent row
    /// is finished (renamed) or undone (not renamed) at open.
    #[test]
    fn recovery_finishes_or_undoes_each_intent() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        s.store(&program("J9", "SP_2", "other\n")).unwrap();
        let intent = |s: &Store, job: &str, name: &str, text: &str| {
            s.conn
                .execute(
                    "INSERT INTO programs (name, file_name, job, revision, sha256, size_bytes, dialect, stored_at_ms, state, text, part)
                     VALUES (?1, ?2, ?3, 1, ?4, ?5, 'sinumerik840d', 1, 'pending', ?6, 'P')",
                    params![name, format!("_N_{name}_MPF"), job, sha256_hex(text.as_bytes()), text.len() as i64, text],
                )
                .unwrap();
        };
        // J2 was renamed into place, J3 was not, when the agent died.
        intent(&s, "J2", "SP_1", "second\n");
        fs::write(dir.path().join("programs/_N_SP_1_MPF"), "second\n").unwrap();
        intent(&s, "J3", "SP_2", "never renamed\n");
        drop(s);
        let s = store(dir.path());
        let h = s.history(Some("SP_1")).unwrap();
        assert_eq!(
            (h[0].job.as_str(), h[0].state.as_str(), h[0].current),
            ("J2", "stored", true)
        );
        let h = s.history(Some("SP_2")).unwrap();
        assert_eq!((h.len(), h[0].job.as_str()), (1, "J9"));
        let pending: i64 = s
            .conn
            .query_row(
                "SELECT COUNT(*) FROM programs WHERE state = 'pending'",
                [],
                |r| r.get(0),
            )
            .unwrap();
        assert_eq!(pending, 0);
    }

    /// A failed write removes its temporary file at once, not at restart.
    #[test]
    fn a_failed_write_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        // A directory where the file should be: the write fails, even as root.
        let target = dir.path().join("_N_X_MPF");
        fs::create_dir(&target).unwrap();
        assert!(write_atomically(dir.path(), "_N_X_MPF", b"x\n").is_err());
        let names: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("_N_X_MPF")]);
    }

    /// The intent is committed while the files are written: a program
    /// whose file cannot be written is refused, its intent undone, and the
    /// rest of its group stored.
    #[test]
    fn a_file_that_cannot_be_written_is_refused_and_its_intent_undone() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        // A directory where the temporary file would go: its write fails.
        let blocked = format!(".{}.tmp-{}", "_N_SP_2_MPF", std::process::id());
        fs::create_dir(dir.path().join("programs").join(&blocked)).unwrap();
        let group = [
            program("J1", "SP_1", "first\n"),
            program("J2", "SP_2", "blocked\n"),
            program("J3", "SP_3", "third\n"),
        ];
        let results = s.store_batch(&group);
        assert!(results[0].is_ok() && results[2].is_ok(), "{results:?}");
        let refused = results[1].as_ref().unwrap_err();
        assert_eq!(refused.code, Code::STORE_IO_ERROR, "{refused:?}");
        let rows: Vec<(String, String)> = s
            .conn
            .prepare("SELECT job, state FROM programs ORDER BY job")
            .unwrap()
            .query_map([], |r| Ok((r.get(0)?, r.get(1)?)))
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(
            rows,
            vec![
                ("J1".into(), "stored".into()),
                ("J3".into(), "stored".into())
            ]
        );
        assert!(!dir.path().join("programs/_N_SP_2_MPF").exists());
    }

    fn not_journaled() -> JobError {
        Stage::Agent.error(
            Code::JOB_NOT_JOURNALED,
            "job_id",
            "a job journaled for H01",
            "no such job",
            "the agent stores only programs of journaled jobs",
        )
    }

    /// The names in the program directory: (programs, temporary files).
    fn files(dir: &Path) -> (Vec<String>, Vec<String>) {
        let mut names: Vec<String> = fs::read_dir(dir.join("programs"))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names.into_iter().partition(|n| !n.contains(".tmp-"))
    }

    fn rows_of(s: &Store, job: &str) -> i64 {
        s.conn
            .query_row("SELECT COUNT(*) FROM programs WHERE job = ?1", [job], |r| {
                r.get(0)
            })
            .unwrap()
    }

    /// The station's word is waited for once the files are written (its
    /// round trip overlaps their fsyncs); a job it does not confirm leaves
    /// no file, temporary file or row, and gets the station's error.
    #[test]
    fn an_unconfirmed_job_is_written_aside_but_never_renamed_nor_indexed() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        let batch = [
            program("J1", "SP_1", "first\n"),
            program("J2", "SP_2", "second\n"),
        ];
        let mut at_ask = None;
        let (results, verdicts) = s.store_confirmed(&batch, || {
            at_ask = Some(files(dir.path()));
            vec![Ok(()), Err(not_journaled())]
        });
        let (programs, temporaries) = at_ask.expect("the station was asked");
        assert!(programs.is_empty(), "{programs:?}");
        assert_eq!(temporaries.len(), 2, "{temporaries:?}");
        assert!(results[0].is_ok() && verdicts[0].is_ok(), "{results:?}");
        assert_eq!(
            results[1].as_ref().unwrap_err().code,
            Code::JOB_NOT_JOURNALED
        );
        assert!(verdicts[1].is_err());
        assert_eq!(files(dir.path()), (vec!["_N_SP_1_MPF".into()], vec![]));
        assert_eq!((rows_of(&s, "J1"), rows_of(&s, "J2")), (1, 0));
    }

    /// A file already holding the delivery's bytes would let `recover` take
    /// an intent for a rename: such a program waits for the station's word
    /// before anything is written or recorded.
    #[test]
    fn a_file_holding_the_same_bytes_waits_for_the_station_first() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "same\n")).unwrap();
        let mut at_ask = None;
        let (results, _) = s.store_confirmed(&[program("J2", "SP_1", "same\n")], || {
            at_ask = Some(files(dir.path()));
            vec![Err(not_journaled())]
        });
        assert_eq!(at_ask, Some((vec!["_N_SP_1_MPF".into()], vec![])));
        assert_eq!(
            results[0].as_ref().unwrap_err().code,
            Code::JOB_NOT_JOURNALED
        );
        assert_eq!((rows_of(&s, "J1"), rows_of(&s, "J2")), (1, 0));
        // Confirmed, it is stored as a new version of the same bytes.
        let (results, _) = s.store_confirmed(&[program("J2", "SP_1", "same\n")], || vec![Ok(())]);
        assert!(results[0].is_ok(), "{results:?}");
        assert_eq!(rows_of(&s, "J2"), 1);
    }

    /// A program refused because its file was changed at the machine is
    /// recorded as waiting on the edit only once the station confirms its
    /// job: an adoption of the edit never ends a job the station does not
    /// know.
    #[test]
    fn only_a_confirmed_job_waits_on_an_edit_at_the_machine() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        s.store(&program("J1", "SP_1", "first\n")).unwrap();
        fs::write(dir.path().join("programs/_N_SP_1_MPF"), "operator edit\n").unwrap();
        let held = |s: &Store, job: &str| -> i64 {
            s.conn
                .query_row("SELECT COUNT(*) FROM held WHERE job = ?1", [job], |r| {
                    r.get(0)
                })
                .unwrap()
        };
        let (results, _) = s.store_confirmed(&[program("J2", "SP_1", "second\n")], || {
            vec![Err(not_journaled())]
        });
        assert_eq!(
            results[0].as_ref().unwrap_err().code,
            Code::JOB_NOT_JOURNALED
        );
        assert_eq!(held(&s, "J2"), 0);
        let (results, _) = s.store_confirmed(&[program("J3", "SP_1", "third\n")], || vec![Ok(())]);
        let code = &results[0].as_ref().unwrap_err().code;
        assert_eq!(*code, Code::PROGRAM_CHANGED_AT_MACHINE);
        assert_eq!(held(&s, "J3"), 1);
    }
}
