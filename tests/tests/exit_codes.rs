//! The `gearcam` binary's exit codes have one meaning
//! each (`gearcam --help`, `services/gearcam/src/exit.rs`): 0 done, 1
//! refused (a failed job's status too), 2 unreachable, 3 not found, 64 usage.
//! Through the real binary and real services on loopback.

use gearcam_testkit::{gearcam, Cluster};

#[test]
fn usage_errors_are_64_not_2_and_help_is_0() {
    let (code, _, err) = gearcam(&["--no-such-flag"]);
    assert_eq!(code, Some(64), "{err}");
    let (code, _, err) = gearcam(&["submit"]);
    assert_eq!(code, Some(64), "{err}");
    let (code, out, _) = gearcam(&["--help"]);
    assert_eq!(code, Some(0));
    assert!(out.contains("Exit codes: 0 done"), "{out}");
}

#[test]
fn status_exit_codes_say_failed_unknown_and_unreachable() {
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
    // The history is a table with a header and dates; `program show
    // --json` prints the version and its text.
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

/// Not found is 3 wherever the thing asked for does not exist — a job
/// file, a library, a template — and a malformed endpoint is a usage
/// error (64) with a sentence that names the form, not an unreachable bus.
#[test]
fn missing_things_are_3_and_a_bad_endpoint_is_64() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data").display().to_string();
    let missing = dir.path().join("no-such-job.toml").display().to_string();
    let (code, _, err) = gearcam(&["check", &missing, "--data", &data]);
    assert_eq!(code, Some(3), "{err}");
    let (code, out, _) = gearcam(&["check", &missing, "--data", &data, "--json"]);
    assert_eq!(code, Some(3));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["ok"].as_bool(), v["exit"].as_u64()),
        (Some(false), Some(3)),
        "{v}"
    );
    assert_eq!(v["errors"][0]["code"], "JOB_FILE_NOT_FOUND", "{v}");
    let (code, _, err) = gearcam(&["submit", &missing]);
    assert_eq!(code, Some(3), "{err}");
    let (code, _, err) = gearcam(&["kb", "list", "nosuch", "--data", &data]);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("UNKNOWN_LIBRARY"), "{err}");
    let (code, _, err) = gearcam(&["templates", "show", "nosuch", "--data", &data]);
    assert_eq!(code, Some(3), "{err}");
    for bad in ["garbage", "udp/127.0.0.1:7447", "tcp/127.0.0.1"] {
        let (code, _, err) = gearcam(&["jobs", "--connect", bad]);
        assert_eq!(code, Some(64), "{bad}: {err}");
        assert!(err.contains("PROTOCOL/ADDRESS:PORT"), "{bad}: {err}");
        assert!(!err.contains("Json5Err"), "{bad}: {err}");
    }
}

/// One JSON shape for every failure: `ok` false, `exit` the exit code and
/// typed `errors`, beside what the command adds (the job and its state).
#[test]
fn every_json_failure_has_ok_exit_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data").display().to_string();
    let shape = |out: &str, exit: u64| -> serde_json::Value {
        let v: serde_json::Value =
            serde_json::from_str(out.trim()).unwrap_or_else(|e| panic!("{e}: {out}"));
        assert_eq!(v["ok"], false, "{v}");
        assert_eq!(v["exit"], exit, "{v}");
        assert!(
            v["errors"]
                .as_array()
                .is_some_and(|e| !e.is_empty() && e[0]["code"].is_string()),
            "{v}"
        );
        v
    };
    // Nothing listens on this port: unreachable, 2.
    let spur = gearcam_testkit::examples::dir().join("spur_840d.toml");
    let spur = spur.display().to_string();
    let (code, out, _) = gearcam(&["submit", &spur, "--json", "--connect", "tcp/127.0.0.1:9"]);
    assert_eq!(code, Some(2));
    let v = shape(&out, 2);
    assert_eq!(v["state"], "unreachable", "{v}");
    // A job file that does not parse: refused, 1.
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, "[job\n").unwrap();
    let (code, out, _) = gearcam(&["submit", &bad.display().to_string(), "--json"]);
    assert_eq!(code, Some(1));
    let v = shape(&out, 1);
    assert_eq!(v["state"], "rejected", "{v}");
    // A job the model refuses, checked locally: refused, 1.
    let invalid = gearcam_testkit::examples::dir().join("invalid_base_pitch.toml");
    let (code, out, _) = gearcam(&[
        "check",
        &invalid.display().to_string(),
        "--json",
        "--data",
        &data,
    ]);
    assert_eq!(code, Some(1));
    let v = shape(&out, 1);
    assert_eq!(v["errors"][0]["code"], "BASE_PITCH_MISMATCH", "{v}");
}

/// An unknown machine is named the same way by `check` (the knowledge
/// service, locally) and `submit` (the station): every family's machines,
/// each family named, so neither lists only the hobbing machines.
#[test]
fn check_and_submit_list_the_same_machines_for_an_unknown_one() {
    let c = Cluster::start();
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data").display().to_string();
    let job = c.job_file(
        "h99.toml",
        &gearcam_testkit::examples::example("spur_840d.toml")
            .replace("machine = \"H01\"", "machine = \"H99\""),
    );
    let job = job.display().to_string();
    let (_, out, _) = gearcam(&["check", &job, "--json", "--data", &data]);
    let checked: serde_json::Value = serde_json::from_str(&out).unwrap();
    let (_, out, _) = gearcam(&["submit", &job, "--json", "--connect", &c.endpoint]);
    let submitted: serde_json::Value = serde_json::from_str(&out).unwrap();
    let list = |v: &serde_json::Value| -> String {
        let e = v["errors"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["code"] == "UNKNOWN_MACHINE")
            .unwrap_or_else(|| panic!("{v}"));
        let expected = e["expected"].as_str().unwrap();
        expected
            .split_once("the knowledge base's machines: ")
            .unwrap_or_else(|| panic!("{expected}"))
            .1
            .to_string()
    };
    assert_eq!(list(&checked), list(&submitted));
    assert_eq!(
        list(&checked),
        "H01, H02 (hobbing); M01, M02 (spiral face milling); W01, W02 (wire EDM)"
    );
    // A program of a machine without an agent on the bus: the hint names
    // the machines whose agents are there, not `gearcam up`.
    let (code, _, err) = gearcam(&[
        "program",
        "history",
        "--machine",
        "H99",
        "--connect",
        &c.endpoint,
    ]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("AGENT_OFFLINE") && err.contains("whose agent is on the bus: H01"),
        "{err}"
    );
    assert!(!err.contains("gearcam up"), "{err}");
}

/// Runs the real `gearcam` binary with `args` in `cwd` as a user who cannot
/// write `dir`'s files: as root (who writes anything) the binary is copied
/// into `dir` and run by `setpriv` as the unprivileged user 65534; as any
/// other user the binary runs as is and the read-only modes stop it.
fn gearcam_as_other_user(
    dir: &std::path::Path,
    cwd: &std::path::Path,
    args: &[&str],
) -> (Option<i32>, String, String) {
    use std::os::unix::fs::PermissionsExt;
    let root = std::process::Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| o.stdout.trim_ascii() == b"0");
    let mut cmd = if root {
        let copy = dir.join("gearcam");
        if !copy.exists() {
            std::fs::copy(gearcam_testkit::process::bin("gearcam"), &copy).unwrap();
        }
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o755)).unwrap();
        let mut cmd = std::process::Command::new("setpriv");
        cmd.args(["--reuid=65534", "--regid=65534", "--clear-groups"])
            .arg(&copy);
        cmd
    } else {
        std::process::Command::new(gearcam_testkit::process::bin("gearcam"))
    };
    let out = cmd
        .args(args)
        .current_dir(cwd)
        .stdin(std::process::Stdio::null())
        .output()
        .expect("setpriv (util-linux) runs the binary as another user");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A data directory this user cannot write is exit 2 with "not writable"
/// and the reason, before any database complains, for the commands that
/// read as well as those that write; and `gearcam up` in a working
/// directory it cannot write says so instead of asking whether it runs.
#[test]
fn a_data_directory_that_cannot_be_written_is_2_not_writable() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    let spur = gearcam_testkit::examples::dir().join("spur_840d.toml");
    let spur = spur.display().to_string();
    // A knowledge base made while the directory was writable, then every
    // file and the directory made read-only.
    let (code, _, err) = gearcam(&[
        "kb",
        "list",
        "machines",
        "--data",
        &data.display().to_string(),
    ]);
    assert_eq!(code, Some(0), "{err}");
    for entry in std::fs::read_dir(&data).unwrap() {
        let path = entry.unwrap().path();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o444)).unwrap();
    }
    std::fs::set_permissions(&data, std::fs::Permissions::from_mode(0o555)).unwrap();
    let d = data.display().to_string();
    for args in [
        vec!["kb", "list", "machines", "--data", &d],
        vec!["templates", "list", "--data", &d],
        vec!["check", &spur, "--data", &d],
    ] {
        let (code, _, err) = gearcam_as_other_user(dir.path(), dir.path(), &args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(
            err.contains(&format!("data directory {d} is not writable"))
                && err.contains("permission denied"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("readonly database"), "{args:?}: {err}");
    }
    let (code, out, _) = gearcam_as_other_user(
        dir.path(),
        dir.path(),
        &["check", &spur, "--data", &d, "--json"],
    );
    assert_eq!(code, Some(2));
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(v["errors"][0]["code"], "DATA_DIR_NOT_WRITABLE", "{v}");
    assert_eq!(v["errors"][0]["got"], d.as_str(), "{v}");
    // `gearcam up` in a working directory it cannot write: the default
    // data directory there cannot be made.
    let cwd = dir.path().join("readonly-cwd");
    std::fs::create_dir(&cwd).unwrap();
    std::fs::set_permissions(&cwd, std::fs::Permissions::from_mode(0o555)).unwrap();
    let (code, _, err) =
        gearcam_as_other_user(dir.path(), &cwd, &["up", "--listen", "tcp/127.0.0.1:0"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("gearcam-data is not writable: cannot make it: permission denied")
            && err.contains("--data or GEARCAM_DATA"),
        "{err}"
    );
    assert!(!err.contains("is `gearcam up`"), "{err}");
    // Writable again, so the temporary directory can be removed.
    std::fs::set_permissions(&data, std::fs::Permissions::from_mode(0o755)).unwrap();
}
