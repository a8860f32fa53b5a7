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
//!    removed and its intent deleted (one synchronous transaction, before
//!    any rename of the group; if it fails, nothing of the group is
//!    renamed), and is never renamed; then, per program, the file at the
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
    /// and made durable (module docs), renamed, the directory fsynced once,
    /// and all index rows inserted in one transaction; each result is as
    /// [`Store::store`] would give it alone. Programs that touch a file or
    /// job already pending in the batch are committed in a later group, so
    /// order is kept.
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
            // Two names of one file (a dialect's suffix given or not) share
            // its temporary file: never in one group.
            let file_name = gearcam_proto::naming::file_name(p.dialect, &p.name).ok();
            let clashes = pending.iter().any(|q| {
                let same_file = file_name.as_ref() == Some(&q.file_name);
                let q = &programs[q.index];
                same_file || q.name == p.name || (q.job_id == p.job_id && q.revision == p.revision)
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
        let pending = confirmed_first(pending, results, confirm);
        if pending.is_empty() {
            return;
        }
        let dir = self.config.program_dir.clone();
        // 1 and 2 at once: the temporary files are written and made durable
        // while the intents are committed, so the two flushes overlap; both
        // are durable before any rename.
        let stored_at = now_ms();
        let group_sync = self.group_sync;
        let (written, seqs) = std::thread::scope(|scope| {
            let writer = scope.spawn(|| write_temps((&dir, group_sync), programs, &pending));
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
        let mut unconfirmed = Vec::new();
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
                    unconfirmed.push(seq);
                }
                (Err(e), Ok(())) => {
                    results[q.index] = Some(Err(io_error(&dir, &q.file_name, &e)));
                    unwritten.push(seq);
                }
            }
        }
        // The intents of jobs the station did not confirm are gone for good
        // before anything is renamed: a later write of the same bytes must
        // not let `recover` take one for a rename. If they cannot be
        // deleted, nothing of the group is renamed.
        if !unconfirmed.is_empty() {
            if let Err(e) = self.delete_intents(&unconfirmed) {
                for (q, tmp) in ready {
                    let _ = fs::remove_file(&tmp);
                    results[q.index] = Some(Err(index_error(e.to_string())));
                }
                return;
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

    /// Deletes the intents `seqs` in one transaction, durable (synchronous
    /// FULL) when it returns.
    fn delete_intents(&mut self, seqs: &[i64]) -> rusqlite::Result<()> {
        let tx = self.conn.transaction()?;
        {
            let mut delete = tx.prepare_cached("DELETE FROM programs WHERE seq = ?1")?;
            for seq in seqs {
                delete.execute([seq])?;
            }
        }
        tx.commit()
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

/// The group to write: when a file already holds a program's bytes, only
/// the programs the station confirms, its word taken first (module docs);
/// the others get its error.
fn confirmed_first(
    pending: Vec<Pending>,
    results: &mut [Option<Result<DeliveryReceipt, JobError>>],
    confirm: &mut Confirm,
) -> Vec<Pending> {
    if !pending.iter().any(|q| q.seen.as_ref() == Some(&q.hash)) {
        return pending;
    }
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
    (dir, group_sync): (&Path, bool),
    programs: &[NcProgram],
    pending: &[Pending],
) -> Vec<std::io::Result<PathBuf>> {
    let text = |q: &Pending| programs[q.index].text.as_bytes();
    let barrier = (group_sync && pending.len() > 1)
        .then(|| group_sync::open(dir))
        .flatten();
    if let Some(barrier) = barrier {
        let written: Vec<_> = pending
            .iter()
            .map(|q| write_unsynced(dir, &q.file_name, text(q)))
            .collect();
        return match barrier.sync() {
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
            .zip(pending.chunks(pending.len().div_ceil(8)))
            .flat_map(|(h, chunk)| {
                h.join().unwrap_or_else(|_| {
                    chunk
                        .iter()
                        .map(|_| Err(std::io::Error::other("writer thread panicked")))
                        .collect()
                })
            })
            .collect()
    })
}

/// One durability barrier for the files a batch wrote.
pub(super) mod group_sync {
    use std::path::{Path, PathBuf};

    /// The file systems whose `syncfs` writes back every dirty file and
    /// flushes the disk's cache.
    const LOCAL_DISK: [&str; 3] = ["ext4", "xfs", "btrfs"];

    /// A program directory, opened before the files are written, whose file
    /// system one `syncfs` makes durable; the write-back errors of those
    /// files are reported to it.
    pub(super) struct Barrier(
        #[cfg_attr(not(target_os = "linux"), allow(dead_code))] std::fs::File,
    );

    /// True when `dir`'s file system is a local disk one (`LOCAL_DISK`)
    /// and the kernel's `syncfs` reports write-back errors (Linux 5.8 and
    /// later); otherwise each file is fsynced. Asked once, when the store
    /// opens: neither changes while the agent runs.
    pub(crate) fn available(dir: &Path) -> bool {
        cfg!(target_os = "linux") && reports_errors() && local_disk(dir)
    }

    /// The barrier of `dir`, opened before the files are written.
    pub(super) fn open(dir: &Path) -> Option<Barrier> {
        std::fs::File::open(dir).ok().map(Barrier)
    }

    impl Barrier {
        /// Writes back and flushes the file system.
        #[cfg(target_os = "linux")]
        pub(super) fn sync(&self) -> std::io::Result<()> {
            rustix::fs::syncfs(&self.0).map_err(std::io::Error::from)
        }

        #[cfg(not(target_os = "linux"))]
        pub(super) fn sync(&self) -> std::io::Result<()> {
            Err(std::io::Error::other("no syncfs on this system"))
        }
    }

    /// True from Linux 5.8, whose `syncfs` returns the errors of write-back
    /// since the descriptor was opened.
    fn reports_errors() -> bool {
        let Ok(release) = std::fs::read_to_string("/proc/sys/kernel/osrelease") else {
            return false;
        };
        let mut parts = release
            .trim()
            .split(|c: char| !c.is_ascii_digit())
            .map(|n| n.parse::<u32>().unwrap_or(0));
        let (major, minor) = (parts.next().unwrap_or(0), parts.next().unwrap_or(0));
        (major, minor) >= (5, 8)
    }

    /// True when the mount holding `dir` (the longest mount point it lies
    /// under, in `/proc/self/mountinfo`) is of a `LOCAL_DISK` type.
    fn local_disk(dir: &Path) -> bool {
        let (Ok(dir), Ok(table)) = (
            dir.canonicalize(),
            std::fs::read_to_string("/proc/self/mountinfo"),
        ) else {
            return false;
        };
        mount_type(&table, &dir).is_some_and(|t| LOCAL_DISK.contains(&t))
    }

    /// The file system type of the mount holding `dir` in a mountinfo
    /// table: per line, the mount point is the fifth field (spaces and
    /// other bytes written as \ooo) and the type follows the ` - `.
    pub(super) fn mount_type<'t>(table: &'t str, dir: &Path) -> Option<&'t str> {
        table
            .lines()
            .filter_map(|line| {
                let (mount, rest) = line.split_once(" - ")?;
                let point = unescape(mount.split(' ').nth(4)?);
                let kind = rest.split(' ').next()?;
                dir.starts_with(&point)
                    .then_some((point.components().count(), kind))
            })
            .max_by_key(|&(depth, _)| depth)
            .map(|(_, kind)| kind)
    }

    /// A mount point with its octal escapes (\040 a space) decoded.
    fn unescape(field: &str) -> PathBuf {
        let bytes = field.as_bytes();
        let mut out = Vec::with_capacity(bytes.len());
        let mut i = 0;
        while i < bytes.len() {
            let octal = bytes
                .get(i + 1..i + 4)
                .filter(|d| bytes[i] == b'\\' && d.iter().all(|b| (b'0'..=b'7').contains(b)));
            match octal {
                Some(d) => {
                    out.push(d.iter().fold(0u8, |v, b| v.wrapping_mul(8) + (b - b'0')));
                    i += 4;
                }
                None => {
                    out.push(bytes[i]);
                    i += 1;
                }
            }
        }
        PathBuf::from(String::from_utf8_lossy(&out).into_owned())
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
mod tests;
