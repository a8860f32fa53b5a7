//! Under `--json` a failure is JSON on standard output
//! (`{"ok": false, "exit": N, "errors": [...]}`) with a non-zero exit, for
//! every command, whatever failed: a refusal with typed errors, an unknown
//! record, an unreachable bus, a data directory that cannot be opened, a
//! wrong command line. Run as the real binary.

use std::process::Command;

/// Runs `gearcam ARGS`; the exit code and standard output as JSON.
fn run(args: &[&str]) -> (Option<i32>, serde_json::Value, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(args)
        .env_remove("RUST_LOG")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let v = serde_json::from_str(stdout.trim())
        .unwrap_or_else(|e| panic!("not JSON ({e}): {stdout:?}; stderr {stderr}"));
    (out.status.code(), v, stderr)
}

fn assert_failure(v: &serde_json::Value, exit: i32, code: &str) {
    assert_eq!(v["ok"], false, "{v}");
    assert_eq!(v["exit"], exit, "{v}");
    assert_eq!(v["errors"][0]["code"], code, "{v}");
    assert!(
        v["errors"][0]["message"]
            .as_str()
            .is_some_and(|m| !m.is_empty()),
        "{v}"
    );
}

#[test]
fn failures_under_json_are_json_on_stdout() {
    let data = tempfile::tempdir().unwrap();
    let d = data.path().to_str().unwrap();

    // A typed refusal of the local knowledge base: a field it does not have.
    let (code, v, _) = run(&[
        "kb",
        "--data",
        d,
        "--json",
        "edit",
        "hobs",
        "HOB-M3-80",
        "--set",
        "colour=red",
    ]);
    assert_eq!(code, Some(1));
    assert_eq!(v["ok"], false, "{v}");
    assert_eq!(v["exit"], 1);
    assert_eq!(v["errors"][0]["stage"], "knowledge", "{v}");
    assert!(v["errors"][0]["field"].as_str().is_some(), "{v}");

    // An unknown record: exit 3, its typed error.
    let (code, v, _) = run(&["kb", "--data", d, "--json", "show", "hobs", "NO-SUCH-HOB"]);
    assert_eq!(code, Some(3), "{v}");
    assert_eq!(v["exit"], 3);

    // The bus cannot be reached: exit 2, one error with the hint.
    let (code, v, _) = run(&["jobs", "--connect", "tcp/127.0.0.1:1", "--json"]);
    assert_eq!(code, Some(2));
    assert_failure(&v, 2, "UNREACHABLE");
    assert!(
        v["errors"][0]["message"]
            .as_str()
            .unwrap()
            .contains("gearcam up"),
        "{v}"
    );
    let (code, v, _) = run(&[
        "program",
        "history",
        "--machine",
        "H01",
        "--connect",
        "tcp/127.0.0.1:1",
        "--json",
    ]);
    assert_eq!(code, Some(2));
    assert_failure(&v, 2, "UNREACHABLE");

    // A data directory that cannot be opened.
    let file = data.path().join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    let (code, v, _) = run(&[
        "templates",
        "--data",
        file.to_str().unwrap(),
        "--json",
        "list",
    ]);
    assert_eq!(code, Some(2), "{v}");
    assert_failure(&v, 2, "UNREACHABLE");

    // A wrong command line: usage, 64, and JSON because --json was asked.
    let (code, v, stderr) = run(&["jobs", "--json", "--no-such-flag"]);
    assert_eq!(code, Some(64), "{stderr}");
    assert_failure(&v, 64, "USAGE");
    assert!(
        stderr.contains("--no-such-flag"),
        "a person still reads it: {stderr}"
    );
}

#[test]
fn without_json_a_failure_prints_nothing_on_stdout() {
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["jobs", "--connect", "tcp/127.0.0.1:1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        out.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}
