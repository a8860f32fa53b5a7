//! The `gearcam-agent` binary's command line, run as a process.

use std::process::Command;

fn agent() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gearcam-agent"))
}

#[test]
fn refuses_a_machine_id_with_a_path_separator_naming_the_rule() {
    let dir = tempfile::tempdir().unwrap();
    let out = agent()
        .args([
            "--machine",
            "H/01",
            "--program-dir",
            &dir.path().display().to_string(),
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("invalid machine id") && err.contains("'/'"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing created"
    );
}

#[test]
fn requires_the_machine_and_its_program_directory() {
    let out = agent().output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--machine") && err.contains("--program-dir"),
        "{err}"
    );
}
