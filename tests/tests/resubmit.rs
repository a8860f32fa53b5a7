//! `gearcam submit` can be retried safely after it ended unreachable
//! (exit 2): the retry of a job the station had journaled must neither make
//! a second job nor be refused (`JOB_ID_EXISTS`) when the job was
//! delivered. Through real processes: the station is frozen (SIGSTOP) while
//! a job is submitted, so the submitter hears nothing; thawed, the station
//! journals and delivers it; the retry with the printed id reports the
//! job's real state and makes no second job.
// Test code: clocks for the waits.
#![allow(clippy::disallowed_methods)]

use std::process::Command;
use std::time::{Duration, Instant};

use gearcam_testkit::{gearcam, Cluster};

fn signal(pid: u32, sig: &str) {
    assert!(Command::new("kill")
        .args([sig, &pid.to_string()])
        .status()
        .unwrap()
        .success());
}

#[test]
fn a_submit_that_ended_unreachable_is_retried_safely_with_its_id() {
    let mut c = Cluster::start();
    let file = c.job_file(
        "spur.toml",
        &gearcam_testkit::examples::example("spur_840d.toml"),
    );
    let (_, v) = c.submit_wait(&file);
    assert_eq!(v["state"], "delivered", "{v}");

    let station = c.proc("station").pid();
    signal(station, "-STOP");
    let out = Command::new(gearcam_testkit::bin("gearcam"))
        .args([
            "submit",
            file.to_str().unwrap(),
            "--connect",
            &c.endpoint,
            "--json",
            "--timeout",
            "2",
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
    let id = v["job"].as_str().unwrap().to_string();
    assert!(
        v["retry"].as_str().unwrap().contains(&format!("--id {id}")),
        "{v}"
    );
    // Thawed, the station takes the request it had not answered.
    signal(station, "-CONT");
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let (_, out, _) = gearcam(&["status", &id, "--connect", &c.endpoint, "--json"]);
        let s: serde_json::Value = serde_json::from_str(&out).unwrap_or_default();
        if s["state"] == "delivered" {
            break;
        }
        assert!(
            Instant::now() < deadline,
            "the thawed station did not deliver {id}: {s}\n{}",
            c.logs()
        );
        std::thread::sleep(Duration::from_millis(200));
    }

    // The retry the CLI printed: the job's real state, no second job.
    let (code, out, err) = gearcam(&[
        "submit",
        file.to_str().unwrap(),
        "--connect",
        &c.endpoint,
        "--json",
        "--wait",
        "--id",
        &id,
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        (v["job"].as_str(), v["state"].as_str()),
        (Some(id.as_str()), Some("delivered")),
        "{v}"
    );
    let jobs = c.jobs().unwrap();
    assert_eq!(jobs.len(), 2, "{jobs:?}");
    // Another id in the file and on the command line: a usage error.
    let with_id = c.job_file(
        "with-id.toml",
        &gearcam_testkit::examples::example("spur_840d.toml")
            .replace("# id = \"SP-1001-A\"", "id = \"SP-1001-A\""),
    );
    let (code, _, err) = gearcam(&[
        "submit",
        with_id.to_str().unwrap(),
        "--connect",
        &c.endpoint,
        "--id",
        "OTHER-1",
    ]);
    assert_eq!(code, Some(64), "{err}");
    assert!(
        err.contains("SP-1001-A") && err.contains("OTHER-1"),
        "{err}"
    );
}
