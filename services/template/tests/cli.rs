//! The `gearcam-template` binary's command line, run as a process.

use std::process::Command;

#[test]
fn a_missing_template_directory_is_named_in_the_error() {
    let dir = tempfile::tempdir().unwrap();
    let library = dir.path().join("templates.db");
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam-template"))
        .args([
            "--library",
            library.to_str().unwrap(),
            "--templates",
            "/nonexistent/gearcam-templates",
            "--no-multicast-scouting",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("/nonexistent/gearcam-templates"), "{err}");
}
