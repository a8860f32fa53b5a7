//! The `gearcam` binary never panics on a closed pipe
//! (`gearcam jobs | true`, `| head -1`). A reader that stops early is not an
//! error: the output is dropped and the command ends normally.

use std::process::{Command, Stdio};

/// Runs `gearcam args` with its standard output a pipe whose read end is
/// closed before the command writes; returns the exit code and stderr.
fn with_closed_stdout(args: &[&str]) -> (Option<i32>, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_closed_pipe_is_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().display().to_string();
    let job = gearcam_testkit::examples::dir().join("spur_840d.toml");
    let job = job.display().to_string();
    for args in [
        vec!["check", job.as_str(), "--data", data.as_str()],
        vec!["check", job.as_str(), "--json", "--data", data.as_str()],
        vec!["kb", "--data", data.as_str(), "list", "hobs"],
        vec!["templates", "--data", data.as_str(), "list"],
    ] {
        let (code, err) = with_closed_stdout(&args);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert_ne!(code, Some(101), "{args:?}: {err}");
        assert_eq!(code, Some(0), "{args:?}: {err}");
    }
}
