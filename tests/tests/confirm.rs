//! A job becomes a case only when it was delivered, or
//! when the planner says what really ran. Through the real binary and
//! services: a job the model refused is `refused` in the knowledge base,
//! never `planned`; `confirm --undelivered` of it is refused and adds no
//! case; `--outcome` has no silent default.
// Test code: a clock for the wait.
#![allow(clippy::disallowed_methods)]

use gearcam_testkit::{gearcam, Cluster};

#[test]
fn a_refused_job_never_becomes_a_case() {
    let cluster = Cluster::start();
    let data = cluster.dir.path().display().to_string();
    let invalid = gearcam_testkit::examples::example("invalid_base_pitch.toml");
    let job = cluster.job_file("invalid.toml", &invalid);
    let (_, v) = cluster.submit_wait(&job);
    assert_eq!(v["state"], "failed", "{v}");
    let id = v["job"].as_str().unwrap().to_string();

    // The knowledge base heard the refusal: the job is `refused`.
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    let state = loop {
        let (code, out, err) = gearcam(&["kb", "--data", &data, "show", "jobs", &id, "--json"]);
        assert_eq!(code, Some(0), "{err}");
        let rec: serde_json::Value = serde_json::from_str(&out).unwrap();
        let state = rec["state"].as_str().unwrap_or_default().to_string();
        if state != "planned" || std::time::Instant::now() > deadline {
            break state;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    assert_eq!(state, "refused");

    // Confirming it, even as undelivered with values, is refused; no case.
    let cases_before = gearcam(&["kb", "--data", &data, "list", "cases", "--json"]).1;
    let (code, _, err) = gearcam(&[
        "confirm",
        &id,
        "--data",
        &data,
        "--undelivered",
        "--outcome",
        "ok",
        "--cutting-speed",
        "90",
        "--feed",
        "2",
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("JOB_STATE") && err.contains("refused"),
        "{err}"
    );
    let cases_after = gearcam(&["kb", "--data", &data, "list", "cases", "--json"]).1;
    assert_eq!(cases_before, cases_after, "a case was added");

    // `--outcome` must be said.
    let (code, _, err) = gearcam(&["confirm", &id, "--data", &data]);
    assert_eq!(code, Some(64), "{err}");
    assert!(err.contains("--outcome"), "{err}");
}
