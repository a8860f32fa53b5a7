//! Issue 12, point 7: the `gearcam` binary's exit codes have one meaning
//! each (`gearcam --help`, `services/gearcam/src/exit.rs`): 0 done, 1
//! refused (a failed job's status too), 2 unreachable, 3 not found, 64 usage.
//! Through the real binary and real services on loopback.

use gearcam_testkit::{gearcam, Cluster};

#[test]
fn point_7_usage_errors_are_64_not_2_and_help_is_0() {
    let (code, _, err) = gearcam(&["--no-such-flag"]);
    assert_eq!(code, Some(64), "{err}");
    let (code, _, err) = gearcam(&["submit"]);
    assert_eq!(code, Some(64), "{err}");
    let (code, out, _) = gearcam(&["--help"]);
    assert_eq!(code, Some(0));
    assert!(out.contains("Exit codes: 0 done"), "{out}");
}

#[test]
fn point_7_status_exit_codes_say_failed_unknown_and_unreachable() {
    let cluster = Cluster::start();
    let endpoint = cluster.endpoint.clone();
    let e = endpoint.as_str();
    // A job a stage refuses: submitted, then its status is a refusal (1).
    let invalid = gearcam_testkit::examples::example("invalid_base_pitch.toml");
    let job = cluster.job_file("invalid.toml", &invalid);
    let (_, v) = cluster.submit_wait(&job);
    assert_eq!(v["state"], "failed", "{v}");
    let id = v["job"].as_str().expect("the job id").to_string();
    let (code, out, err) = gearcam(&["status", &id, "--connect", e]);
    assert_eq!(code, Some(1), "{out}{err}");
    assert!(out.contains("BASE_PITCH_MISMATCH"), "{out}");
    // An unknown job, program and version: not found (3).
    let (code, _, err) = gearcam(&["status", "NO-SUCH-JOB", "--connect", e]);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("UNKNOWN_JOB"), "{err}");
    let (code, _, err) = gearcam(&[
        "program",
        "history",
        "--machine",
        "H01",
        "NOPE",
        "--connect",
        e,
    ]);
    assert_eq!(code, Some(3), "{err}");
    // A delivered job's status is 0.
    let spur = cluster.job_file(
        "spur.toml",
        &gearcam_testkit::examples::example("spur_840d.toml"),
    );
    let (_, v) = cluster.submit_wait(&spur);
    assert_eq!(v["state"], "delivered", "{v}");
    let id = v["job"].as_str().unwrap().to_string();
    let (code, _, err) = gearcam(&["status", &id, "--connect", e]);
    assert_eq!(code, Some(0), "{err}");
    let name = v["program"]["name"].as_str().unwrap().to_string();
    // Issue 12 point 9: the history is a table with a header and dates;
    // point 8: `program show --json` prints the version and its text.
    let (code, out, err) = gearcam(&[
        "program",
        "history",
        "--machine",
        "H01",
        &name,
        "--connect",
        e,
    ]);
    assert_eq!(code, Some(0), "{err}");
    let header = out.lines().next().unwrap_or_default();
    for column in ["SEQ", "CUR", "NAME", "STATE", "STORED", "JOB", "SHA256"] {
        assert!(header.contains(column), "{out}");
    }
    assert!(
        out.lines()
            .nth(1)
            .is_some_and(|l| l.contains(" UTC ") && l.contains(&name)),
        "{out}"
    );
    let (code, out, err) = gearcam(&[
        "program",
        "show",
        "--machine",
        "H01",
        &name,
        "1",
        "--connect",
        e,
        "--json",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let shown: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert!(
        shown["text"].as_str().is_some_and(|t| t.contains(&name)),
        "{shown}"
    );
    assert_eq!(shown["version"]["name"], name.as_str());
    let (code, _, err) = gearcam(&[
        "program",
        "show",
        "--machine",
        "H01",
        &name,
        "999999",
        "--connect",
        e,
    ]);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("UNKNOWN_VERSION"), "{err}");
    drop(cluster);
    // Nothing listens any more: unreachable (2).
    let (code, _, err) = gearcam(&["status", "NO-SUCH-JOB", "--connect", e]);
    assert_eq!(code, Some(2), "{err}");
}
