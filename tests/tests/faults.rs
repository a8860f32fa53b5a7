//! Fault tests with real processes on loopback: services killed with SIGKILL
//! and restarted while jobs are in flight, an agent offline for a whole
//! submission, a station restarted with jobs in its journal. In each, N jobs
//! submitted give exactly N programs at the agent — no duplicates, contents
//! and hashes right — and every job ends delivered.
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::thread;
use std::time::Duration;

use gearcam_testkit::Cluster;
use sha2::{Digest, Sha256};

const N: usize = 12;

fn job_text(i: usize) -> String {
    format!(
        r#"
[job]
id = "FT-{i:03}"
machine = "H01"
part_number = "FT-{i:03}"

[gear]
module_mm = 3.0
teeth = {teeth}
face_width_mm = 30.0
material = "20CrMnTi"
fixture_height_mm = 100.0
fixture_diameter_mm = 40.0

[hob]
id = "HOB-M3-80"
"#,
        teeth = 20 + i
    )
}

fn job_files(c: &Cluster) -> Vec<PathBuf> {
    (0..N)
        .map(|i| c.job_file(&format!("ft{i}.toml"), &job_text(i)))
        .collect()
}

/// Exactly N programs, one per job, no temporary files, file = index = station hashes.
fn assert_exactly_once(c: &Cluster, jobs: &[serde_json::Value]) {
    let files: BTreeSet<String> = std::fs::read_dir(c.program_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let expected: BTreeSet<String> = (0..N).map(|i| format!("_N_FT_{i:03}_MPF")).collect();
    assert_eq!(
        files, expected,
        "program directory holds exactly the N programs"
    );
    let conn = rusqlite::Connection::open(c.index_db()).unwrap();
    let rows: i64 = conn
        .query_row("SELECT COUNT(*) FROM programs", [], |r| r.get(0))
        .unwrap();
    let distinct: i64 = conn
        .query_row("SELECT COUNT(DISTINCT job) FROM programs", [], |r| r.get(0))
        .unwrap();
    assert_eq!(
        (rows, distinct),
        (N as i64, N as i64),
        "one index row per job, no duplicates"
    );
    for j in jobs {
        let id = j["job"].as_str().unwrap();
        let name = j["program"]["name"].as_str().unwrap();
        let text = std::fs::read(c.program_dir().join(format!("_N_{name}_MPF"))).unwrap();
        let hash = hex::encode(Sha256::digest(&text));
        assert_eq!(
            j["program"]["sha256"],
            hash.as_str(),
            "station's receipt hash for {id}"
        );
        let indexed: String = conn
            .query_row("SELECT sha256 FROM programs WHERE job = ?1", [id], |r| {
                r.get(0)
            })
            .unwrap();
        assert_eq!(indexed, hash, "index hash for {id}");
        assert!(
            String::from_utf8_lossy(&text).contains(&format!("; JOB {id}")),
            "program of {id} is its own"
        );
    }
}

/// Submits every job from a thread while `during` runs on this one.
fn submit_while(c: &mut Cluster, during: impl FnOnce(&mut Cluster)) {
    let files = job_files(c);
    let endpoint = c.endpoint.clone();
    let submitter = thread::spawn(move || {
        for f in files {
            let out = std::process::Command::new(gearcam_testkit::bin("gearcam"))
                .args([
                    "submit",
                    &f.display().to_string(),
                    "--connect",
                    &endpoint,
                    "--json",
                    "--timeout",
                    "60",
                ])
                .output()
                .expect("submit runs");
            assert!(
                out.status.success(),
                "submit: {}",
                String::from_utf8_lossy(&out.stdout)
            );
            thread::sleep(Duration::from_millis(50));
        }
    });
    during(c);
    submitter.join().expect("every submission journaled");
}

#[test]
fn agent_killed_during_delivery_and_restarted() {
    let mut c = Cluster::start();
    submit_while(&mut c, |c| {
        thread::sleep(Duration::from_millis(400));
        c.proc("agent").kill();
        thread::sleep(Duration::from_millis(800));
        c.proc("agent").restart();
    });
    let jobs = c.wait_all_delivered(N, Duration::from_secs(120));
    assert_exactly_once(&c, &jobs);
}

#[test]
fn middle_services_killed_and_restarted_with_jobs_in_flight() {
    let mut c = Cluster::start();
    submit_while(&mut c, |c| {
        for service in ["knowledge", "model", "template"] {
            thread::sleep(Duration::from_millis(250));
            c.proc(service).kill();
            thread::sleep(Duration::from_millis(400));
            c.proc(service).restart();
        }
    });
    let jobs = c.wait_all_delivered(N, Duration::from_secs(120));
    assert_exactly_once(&c, &jobs);
}

#[test]
fn station_killed_with_jobs_in_its_journal_finishes_them_after_restart() {
    // The agent is offline, so every job stays journaled and waiting.
    let mut c = Cluster::start_without_agent();
    for f in job_files(&c) {
        assert_eq!(c.submit(&f)["state"], "accepted");
    }
    c.proc("station").kill();
    c.proc("station").restart();
    c.start_agent();
    let jobs = c.wait_all_delivered(N, Duration::from_secs(120));
    assert_exactly_once(&c, &jobs);
}

#[test]
fn agent_offline_for_the_whole_submission_then_started() {
    let mut c = Cluster::start_without_agent();
    for f in job_files(&c) {
        c.submit(&f);
    }
    // Visible as waiting for the agent.
    let deadline = std::time::Instant::now() + Duration::from_secs(30);
    loop {
        let jobs = c.jobs().unwrap_or_default();
        if jobs.len() == N
            && jobs.iter().all(|j| {
                j["state"] == "waiting"
                    && j["waiting_for"]
                        .as_str()
                        .unwrap_or("")
                        .contains("agent/H01")
            })
        {
            break;
        }
        assert!(
            std::time::Instant::now() < deadline,
            "jobs not shown waiting for agent/H01: {jobs:#?}"
        );
        thread::sleep(Duration::from_millis(200));
    }
    c.start_agent();
    let jobs = c.wait_all_delivered(N, Duration::from_secs(120));
    assert_exactly_once(&c, &jobs);
}
