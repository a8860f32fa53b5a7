//! The `gearcam` binary against a bus where nothing answers, run as a process.

use std::path::Path;
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
    assert_eq!(
        (v["ok"].as_bool(), v["exit"].as_u64()),
        (Some(false), Some(2))
    );
    assert_eq!(v["errors"][0]["code"], "UNREACHABLE", "{v}");
    assert!(
        v["errors"][0]["message"]
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
    // No such file: not found (3).
    assert_eq!(out.status.code(), Some(3));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["errors"][0]["code"], "JOB_FILE_NOT_FOUND");
    // A file that is there but cannot be read (a directory): refused (1).
    let dir = std::env::temp_dir();
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["submit", &dir.display().to_string(), "--json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["errors"][0]["code"], "JOB_FILE_UNREADABLE");
}

/// The client commands offer only what a client uses:
/// where to connect, or a configuration file; never `--listen` or a mode
/// (`--mode router`).
#[test]
fn client_commands_offer_only_client_options() {
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

/// A bus failure says what to do, without the
/// bus's own log lines, source paths or colour codes; `-v` shows the log.
#[test]
fn a_bus_failure_says_what_to_do_without_log_noise() {
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

/// Job-file errors speak a planner's language: an
/// unknown key names the nearest known one, a type error says what the key
/// takes and what was given, an oversize part number is refused on its field.
#[test]
fn job_file_errors_name_the_key_and_suggest() {
    let dir = tempfile::tempdir().unwrap();
    let spur = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spur_840d.toml"),
    )
    .unwrap();
    let first_error = |name: &str, text: &str| {
        assert_ne!(
            text, spur,
            "{name}: the example changed; the test's edit did not apply"
        );
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
            .args(["check", &path.display().to_string(), "--json", "--data"])
            .arg(dir.path())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{name}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v["errors"][0].clone()
    };
    let e = first_error("typo.toml", &spur.replacen("teeth =", "teeht =", 1));
    assert_eq!(e["code"], "JOB_FILE_UNKNOWN_KEY", "{e}");
    assert_eq!(e["field"], "gear.teeht", "{e}");
    assert!(
        e["message"]
            .as_str()
            .unwrap()
            .contains("did you mean `teeth`?"),
        "{e}"
    );

    let e = first_error(
        "negative.toml",
        &spur.replacen("quantity = 20", "quantity = -5", 1),
    );
    assert_eq!(e["field"], "job.quantity", "{e}");
    // Parts start at 1: the expected value says so (0 is refused too).
    assert_eq!(e["expected"], "a whole number of parts, 1 or more", "{e}");
    assert_eq!(e["got"], "-5", "{e}");

    // An absurd number of teeth is refused on that field, not later on the
    // blank or the depth it throws off.
    let path = dir.path().join("teeth.toml");
    std::fs::write(&path, spur.replacen("teeth = 25", "teeth = 4000000000", 1)).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["check", &path.display().to_string(), "--json", "--data"])
        .arg(dir.path())
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let fields: Vec<&str> = v["errors"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["field"].as_str().unwrap())
        .collect();
    assert_eq!(fields, ["gear.teeth"], "{v}");
    assert_eq!(v["errors"][0]["code"], "TEETH_RANGE", "{v}");

    let long = format!("part_number = \"{}\"", "P".repeat(200));
    let e = first_error(
        "long.toml",
        &spur.replacen("part_number = \"SP-1001\"", &long, 1),
    );
    assert_eq!(e["field"], "job.part_number", "{e}");
    assert!(e["got"].as_str().unwrap().contains("200 characters"), "{e}");
}

/// Input errors say what is wrong where: a TOML syntax error gives the line,
/// the column and the parser's sentence on one line; `inf` is `NOT_FINITE`
/// on its key before any stage plans with it; a negative quantity is told
/// that parts start at 1; `resolve` without a decision names both.
#[test]
fn input_errors_name_the_place_and_the_real_cause() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data").display().to_string();
    let run = |file: &str, text: &str| {
        let path = dir.path().join(file);
        std::fs::write(&path, text).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
            .args([
                "check",
                &path.display().to_string(),
                "--json",
                "--data",
                &data,
            ])
            .output()
            .unwrap();
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        (out.status.code(), v["errors"][0].clone())
    };
    let (code, e) = run("syntax.toml", "[job]\nmachine = \"H01\"\n[gear\n");
    assert_eq!(code, Some(1));
    assert_eq!(e["field"], "line 3, column 6", "{e}");
    let message = e["message"].as_str().unwrap();
    assert!(
        message.contains("(line 3, column 6): invalid table header; expected"),
        "{e}"
    );
    assert!(
        !message.contains('\n') && e["expected"] != "see message",
        "{e}"
    );
    assert_eq!(e["got"], "[gear");

    let spur = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spur_840d.toml"),
    )
    .unwrap();
    let (code, e) = run(
        "inf.toml",
        &spur.replace("module_mm = 3.0", "module_mm = inf"),
    );
    assert_eq!(code, Some(1));
    assert_eq!(
        (e["code"].as_str(), e["field"].as_str(), e["got"].as_str()),
        (Some("NOT_FINITE"), Some("gear.module_mm"), Some("inf")),
        "{e}"
    );
    let (_, e) = run("qty.toml", &spur.replace("quantity = 20", "quantity = -1"));
    assert_eq!(e["expected"], "a whole number of parts, 1 or more", "{e}");

    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["program", "resolve", "SP_1001", "--machine", "H01"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(64));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--adopt|--replace"), "{err}");
}

/// `check` holds a job to the same size limit as the bus: a job the
/// station would refuse as too large is refused by `check` too, and by
/// `submit` before it sends anything.
#[test]
fn check_and_submit_hold_a_job_to_the_bus_size_limit() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data").display().to_string();
    let die = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/die_m1z40_iso.toml"),
    )
    .unwrap();
    let huge = die.replace(
        "material = \"SKD11\"",
        &format!("material = \"{}\"", "S".repeat(100 * 1024)),
    );
    let path = dir.path().join("huge.toml");
    std::fs::write(&path, huge).unwrap();
    let path = path.display().to_string();
    for args in [
        vec!["check", path.as_str(), "--json", "--data", data.as_str()],
        // Nothing listens there: the refusal comes before the bus.
        vec![
            "submit",
            path.as_str(),
            "--json",
            "--connect",
            "tcp/127.0.0.1:9",
        ],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(v["errors"][0]["code"], "MESSAGE_TOO_LARGE", "{args:?}");
    }
}

/// A job refused for its gear shows no figures of a gear it is not: a
/// module of -3 mm is MODULE_RANGE, without a pitch diameter of -75 mm.
#[test]
fn an_invalid_gear_prints_no_geometry() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data").display().to_string();
    let spur = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/spur_840d.toml"),
    )
    .unwrap();
    let path = dir.path().join("negative.toml");
    std::fs::write(&path, spur.replace("module_mm = 3.0", "module_mm = -3.0")).unwrap();
    let path = path.display().to_string();
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["check", &path, "--data", &data])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("MODULE_RANGE"), "{text}");
    assert!(
        !text.contains("-75") && !text.contains("geometry"),
        "{text}"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_gearcam"))
        .args(["check", &path, "--data", &data, "--json"])
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v.get("geometry").is_none(), "{v}");
}
