//! The `gearcam` binary against a bus where nothing answers, run as a process.

use std::process::Command;

#[test]
fn submit_to_an_unreachable_bus_exits_2_and_names_the_endpoint() {
    // A port nobody listens on: the client session opens, no station answers.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let job =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spur_840d.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args([
            "submit",
            &job.display().to_string(),
            "--connect",
            &format!("tcp/127.0.0.1:{port}"),
            "--json",
            "--timeout",
            "1",
        ])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["state"], "unreachable");
    assert!(
        v["message"]
            .as_str()
            .unwrap()
            .contains(&format!("tcp/127.0.0.1:{port}")),
        "{v}"
    );
}

#[test]
fn submit_refuses_an_unreadable_job_file_before_touching_the_bus() {
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["submit", "/nonexistent/job.toml", "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["errors"][0]["code"], "JOB_FILE_UNREADABLE");
}

/// Issue 12, point 11: the client commands offer only what a client uses:
/// where to connect, or a configuration file; never `--listen` or a mode
/// (`--mode router`).
#[test]
fn point_11_client_commands_offer_only_client_options() {
    for args in [
        vec!["submit", "--help"],
        vec!["jobs", "--help"],
        vec!["status", "--help"],
        vec!["program", "history", "--help"],
        vec!["program", "rollback", "--help"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
            .args(&args)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}");
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(help.contains("--connect"), "{args:?}: {help}");
        for absent in ["--listen", "--mode", "multicast"] {
            assert!(!help.contains(absent), "{args:?} offers {absent}: {help}");
        }
    }
}

/// Issue 12, point 9 (in part): a bus failure says what to do, without the
/// bus's own log lines, source paths or colour codes; `-v` shows the log.
#[test]
fn point_9_a_bus_failure_says_what_to_do_without_log_noise() {
    let run = |verbose: bool| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_gearcam"));
        if verbose {
            cmd.arg("-v");
        }
        let out = cmd
            .args(["status", "SOME-JOB", "--connect", "tcp/127.0.0.1:1"])
            .env_remove("RUST_LOG")
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (code, err) = run(false);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("is `gearcam up` (or the router) running?"),
        "{err}"
    );
    for noise in ["WARN", ".rs:", "\u{1b}[", "registry"] {
        assert!(!err.contains(noise), "{noise:?} in: {err}");
    }
    let (code, err) = run(true);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("WARN"), "-v shows the bus's log: {err}");
    assert!(!err.contains("\u{1b}["), "no colour into a pipe: {err}");
}
