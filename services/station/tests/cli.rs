//! The `gearcam-station` binary as a process: a journal it cannot create is
//! refused, naming the path, before the station serves anything.

use std::process::Command;

#[test]
fn a_journal_that_cannot_be_created_is_refused_by_path() {
    let dir = tempfile::tempdir().unwrap();
    // A file where the journal's directory should be.
    let blocker = dir.path().join("not-a-dir");
    std::fs::write(&blocker, b"").unwrap();
    let journal = blocker.join("station.db");
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam-station"))
        .args([
            "--mode",
            "peer",
            "--listen",
            "tcp/127.0.0.1:0",
            "--no-multicast-scouting",
            "--journal",
            &journal.display().to_string(),
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not-a-dir"), "{err}");
}
