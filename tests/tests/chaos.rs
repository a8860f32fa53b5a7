//! Issue 13: a bounded chaos run in CI. Every service is its own process
//! behind a router on loopback; while jobs are submitted, any process — the
//! router included — is killed with SIGKILL every 0.5–2 s and started again.
//! At the end every job is delivered exactly once: one file and one index row
//! per job, hashes equal to the receipts.
//!
//! CI runs 100 jobs for 60 s. A longer run for the figures:
//! `GEARCAM_CHAOS_JOBS=1000 GEARCAM_CHAOS_SECS=600 cargo test -p gearcam-tests --test chaos -- --nocapture`
//! (`GEARCAM_CHAOS_SEED` repeats a run).
// Test code: clocks, the environment for the switches.
#![allow(clippy::disallowed_methods)]

use std::collections::BTreeSet;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use gearcam_testkit::Cluster;
use sha2::{Digest, Sha256};

fn setting(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn job_text(i: usize) -> String {
    format!(
        r#"
[job]
id = "CH-{i:04}"
machine = "H01"
part_number = "CH-{i:04}"

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
        teeth = 20 + i % 60
    )
}

/// xorshift64*: a small reproducible generator for the kill schedule.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

#[test]
fn chaos_every_job_delivered_exactly_once() {
    let jobs = setting("GEARCAM_CHAOS_JOBS", 100) as usize;
    let secs = setting("GEARCAM_CHAOS_SECS", 60);
    let seed = setting("GEARCAM_CHAOS_SEED", 0x9E37_79B9_7F4A_7C15).max(1);
    let mut c = Cluster::start();
    let files: Vec<_> = (0..jobs)
        .map(|i| c.job_file(&format!("ch{i}.toml"), &job_text(i)))
        .collect();

    // The submitter: each job until the station journals it; a submit that
    // ends unreachable (the router or the station is down) is retried with
    // its id, which is a resubmission.
    let endpoint = c.endpoint.clone();
    let submitted = Arc::new(AtomicBool::new(false));
    let done = submitted.clone();
    let submitter = thread::spawn(move || {
        let mut retries = 0;
        for (i, f) in files.iter().enumerate() {
            let id = format!("CH-{i:04}");
            loop {
                let out = std::process::Command::new(gearcam_testkit::bin("gearcam"))
                    .args([
                        "submit",
                        f.to_str().unwrap(),
                        "--connect",
                        &endpoint,
                        "--json",
                    ])
                    .args(["--timeout", "5", "--id", &id])
                    .output()
                    .expect("submit runs");
                if out.status.success() {
                    break;
                }
                assert_eq!(
                    out.status.code(),
                    Some(2),
                    "submit of {id} refused: {}",
                    String::from_utf8_lossy(&out.stdout)
                );
                retries += 1;
                thread::sleep(Duration::from_millis(200));
            }
        }
        done.store(true, Ordering::SeqCst);
        retries
    });

    // The chaos: SIGKILL a random process every 0.5–2 s, start it again
    // after 0–500 ms; a process that stopped by itself is started too.
    let labels = [
        "router",
        "station",
        "knowledge",
        "model",
        "template",
        "agent",
    ];
    let mut rng = Rng(seed);
    let start = Instant::now();
    let mut kills = 0;
    while start.elapsed() < Duration::from_secs(secs) || !submitted.load(Ordering::SeqCst) {
        assert!(
            start.elapsed() < Duration::from_secs(secs + 600),
            "the submissions did not finish\n{}",
            c.logs()
        );
        thread::sleep(Duration::from_millis(500 + rng.next() % 1500));
        if start.elapsed() < Duration::from_secs(secs) {
            let label = labels[(rng.next() % labels.len() as u64) as usize];
            c.proc(label).kill();
            kills += 1;
            thread::sleep(Duration::from_millis(rng.next() % 500));
        }
        for label in labels {
            if !c.proc(label).running() {
                c.proc(label).restart();
            }
        }
    }
    let retries = submitter.join().expect("every job journaled");

    // Converged: every job delivered, exactly once.
    let converge = Instant::now();
    let states = c.wait_all_delivered(jobs, Duration::from_secs(300));
    println!(
        "chaos: {jobs} jobs, {kills} kills over {secs} s (seed {seed}), {retries} submit retries; \
         converged {:.1} s after the last kill",
        converge.elapsed().as_secs_f64()
    );
    let files: BTreeSet<String> = std::fs::read_dir(c.program_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let expected: BTreeSet<String> = (0..jobs).map(|i| format!("_N_CH_{i:04}_MPF")).collect();
    assert_eq!(files, expected, "exactly one file per job, nothing else");
    let conn = rusqlite::Connection::open(c.index_db()).unwrap();
    let (rows, distinct): (i64, i64) = conn
        .query_row(
            "SELECT COUNT(*), COUNT(DISTINCT job) FROM programs WHERE state = 'stored'",
            [],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .unwrap();
    let pending: i64 = conn
        .query_row(
            "SELECT COUNT(*) FROM programs WHERE state != 'stored'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    assert_eq!(
        (rows, distinct, pending),
        (jobs as i64, jobs as i64, 0),
        "one stored row per job"
    );
    for j in &states {
        let id = j["job"].as_str().unwrap();
        let name = j["program"]["name"].as_str().unwrap();
        let text = std::fs::read(c.program_dir().join(format!("_N_{name}_MPF"))).unwrap();
        let hash = hex::encode(Sha256::digest(&text));
        assert_eq!(
            j["program"]["sha256"],
            hash.as_str(),
            "receipt hash of {id}"
        );
        assert!(
            String::from_utf8_lossy(&text).contains(&format!("; JOB {id}\n")),
            "{id}'s own program"
        );
    }
}
