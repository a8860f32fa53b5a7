//! The write order, the station's word and the group's durability.

use super::super::tests::{program, store};
use super::super::{Faults, StoreConfig};
use super::*;
use gearcam_proto::Dialect;

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

/// The intents of jobs the station does not confirm are deleted, for
/// good, before anything of their group is renamed: seen from another
/// connection while the store pauses before its renames, the confirmed
/// job's intent is there and the unconfirmed one's is gone.
#[test]
fn unconfirmed_intents_are_gone_before_the_renames() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = Store::open(StoreConfig {
        faults: Faults {
            pause_before_rename_ms: 1500,
            ..Faults::default()
        },
        ..store(dir.path()).config().clone()
    })
    .unwrap();
    let index = dir.path().join("index.db");
    let storing = std::thread::spawn(move || {
        let batch = [
            program("J1", "SP_1", "first\n"),
            program("J2", "SP_2", "second\n"),
        ];
        s.store_confirmed(&batch, || vec![Ok(()), Err(not_journaled())])
            .0
    });
    let other = rusqlite::Connection::open(&index).unwrap();
    let state = |job: &str| -> Option<String> {
        other
            .query_row("SELECT state FROM programs WHERE job = ?1", [job], |r| {
                r.get(0)
            })
            .ok()
    };
    // Wait for the intents, then look inside the pause.
    let mut polls = 0;
    while state("J1").is_none() {
        polls += 1;
        assert!(polls < 500, "no intent recorded");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    let (j1, j2) = (state("J1"), state("J2"));
    let results = storing.join().unwrap();
    assert_eq!(j1.as_deref(), Some("pending"), "still inside the pause");
    assert_eq!(j2, None);
    assert!(results[0].is_ok() && results[1].is_err(), "{results:?}");
}

/// The mount holding a directory is the longest mount point above it,
/// compared component by component, with its escapes decoded.
#[test]
fn the_mount_of_a_directory_is_the_longest_mount_point_above_it() {
    let table = "22 1 8:1 / / rw,relatime shared:1 - ext4 /dev/sda1 rw\n\
                 30 22 0:26 / /mnt/cnc\\040share rw shared:5 - cifs //ctl/prog rw\n\
                 31 22 0:27 / /mnt/cnc rw - nfs4 ctl:/p rw\n";
    let kind = |d: &str| group_sync::mount_type(table, Path::new(d));
    assert_eq!(kind("/var/programs"), Some("ext4"));
    assert_eq!(kind("/mnt/cnc share/H01"), Some("cifs"));
    assert_eq!(kind("/mnt/cnc/H01"), Some("nfs4"));
    assert_eq!(kind("/mnt/cncx/H01"), Some("ext4"));
}

/// Two names of one file (`PD-1` and `PD-1.3b` are both the file
/// `PD-1.3b` in the 3B dialect) are never written in one group: they
/// would share its temporary file. The later is stored after the
/// earlier, as a new version, each under its own receipt.
#[test]
fn two_names_of_one_file_are_stored_one_after_the_other() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = Store::open(StoreConfig {
        dialect: Dialect::Wire3b,
        ..store(dir.path()).config().clone()
    })
    .unwrap();
    let wire = |job: &str, name: &str, text: &str| NcProgram {
        dialect: Dialect::Wire3b,
        ..program(job, name, text)
    };
    let results = s.store_batch(&[
        wire("J1", "PD-1", "first\n"),
        wire("J2", "PD-1.3b", "second\n"),
    ]);
    assert!(results.iter().all(Result::is_ok), "{results:?}");
    let path = dir.path().join("programs/PD-1.3b");
    assert_eq!(fs::read_to_string(path).unwrap(), "second\n");
    let hashes: Vec<String> = results.into_iter().map(|r| r.unwrap().sha256).collect();
    assert_eq!(hashes, [sha256_hex(b"first\n"), sha256_hex(b"second\n")]);
}
