//! A bounded chaos run in CI. Every service is its own process behind a
//! router on loopback; while jobs are submitted, any process — the router
//! included — is killed with SIGKILL every 0.5–2 s and started again. At
//! the end every job is delivered exactly once: one file and one index row
//! per job, hashes equal to the receipts. It runs on the plain deployment
//! (TCP) and on the secure one (`deploy/secure/`: QUIC, a user per service,
//! the ACL, the size limits) with an authenticated planner's flood of
//! queries running beside it.
//!
//! CI runs 100 jobs for 60 s on each. A longer run for the figures:
//! `GEARCAM_CHAOS_JOBS=1000 GEARCAM_CHAOS_SECS=600 cargo test -p gearcam-tests --test chaos -- --nocapture`
//! (`GEARCAM_CHAOS_SEED` repeats a run).
// Test code: clocks, the environment for the switches.
#![allow(clippy::disallowed_methods)]

use std::collections::BTreeSet;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant};

use std::path::{Path, PathBuf};

use gearcam_testkit::secure::Secure;
use gearcam_testkit::{Cluster, Proc};
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

/// What the chaos run needs of a deployment.
trait Deployment {
    /// The deployment's directory; H01's store is under `H01/`.
    fn dir(&self) -> &Path;
    /// How a client reaches the bus: `--connect …` or `--config …`.
    fn client(&self) -> Vec<String>;
    /// The process labelled `label`.
    fn proc(&mut self, label: &str) -> &mut Proc;
    /// Every process's log.
    fn logs(&self) -> String;
}

impl Deployment for Cluster {
    fn dir(&self) -> &Path {
        Cluster::dir(self)
    }
    fn client(&self) -> Vec<String> {
        vec!["--connect".into(), self.endpoint.clone()]
    }
    fn proc(&mut self, label: &str) -> &mut Proc {
        Cluster::proc(self, label)
    }
    fn logs(&self) -> String {
        Cluster::logs(self)
    }
}

impl Deployment for Secure {
    fn dir(&self) -> &Path {
        Secure::dir(self)
    }
    fn client(&self) -> Vec<String> {
        vec!["--config".into(), self.cfg("planner").display().to_string()]
    }
    fn proc(&mut self, label: &str) -> &mut Proc {
        Secure::proc(self, label)
    }
    fn logs(&self) -> String {
        Secure::logs(self)
    }
}

// The chaos runs' template service does not run the virtual hobbing: its
// 100 jobs are 60 different gears, seconds each on the virtual machine, and
// the template service is killed and started again (losing the reports it
// keeps). What is tested here is delivery under faults; the simulation
// before delivery has its own tests.
const SIMULATION: &str = "off";

#[test]
fn chaos_every_job_delivered_exactly_once() {
    let mut cluster = Cluster::start_simulating(SIMULATION);
    run(&mut cluster, "plain");
}

/// The same run on the secure deployment, while a planner floods the
/// station, the knowledge base and H01's store with bursts of queries.
#[test]
fn chaos_on_the_secure_deployment_under_a_flood() {
    let mut secure = Secure::start_simulating(SIMULATION);
    let planner = secure.cfg("planner");
    let stop = Arc::new(AtomicBool::new(false));
    let flooding = stop.clone();
    let flood = thread::spawn(move || {
        let rt = tokio::runtime::Builder::new_multi_thread()
            .enable_all()
            .build()
            .expect("a runtime");
        rt.block_on(async {
            let config = zenoh::Config::from_file(&planner).expect("planner config");
            let session = zenoh::open(config).await.expect("the planner connects");
            let mut bursts = 0;
            while !flooding.load(Ordering::SeqCst) {
                gearcam_testkit::flood::burst(&session, bursts).await;
                bursts += 1;
            }
            bursts
        })
    });
    run(&mut secure, "secure");
    stop.store(true, Ordering::SeqCst);
    let bursts = flood.join().expect("the flood ran");
    println!("chaos (secure): {bursts} bursts of flood beside it");
}

/// Submits the jobs while killing processes, then checks every job was
/// delivered exactly once.
fn run(d: &mut dyn Deployment, name: &str) {
    let jobs = setting("GEARCAM_CHAOS_JOBS", 100) as usize;
    let secs = setting("GEARCAM_CHAOS_SECS", 60);
    let seed = setting("GEARCAM_CHAOS_SEED", 0x9E37_79B9_7F4A_7C15).max(1);
    let files: Vec<PathBuf> = (0..jobs)
        .map(|i| {
            let path = d.dir().join(format!("ch{i}.toml"));
            std::fs::write(&path, job_text(i)).expect("a job file");
            path
        })
        .collect();
    let client = d.client();
    let program_dir = d.dir().join("H01/programs");
    let index_db = d.dir().join("H01/index.db");

    // The submitter: each job until the station journals it; a submit that
    // ends unreachable (the router or the station is down) is retried with
    // its id, which is a resubmission.
    let submit_client = client.clone();
    let submitted = Arc::new(AtomicBool::new(false));
    let done = submitted.clone();
    let submitter = thread::spawn(move || {
        let mut retries = 0;
        for (i, f) in files.iter().enumerate() {
            let id = format!("CH-{i:04}");
            loop {
                let out = std::process::Command::new(gearcam_testkit::bin("gearcam"))
                    .args(["submit", f.to_str().unwrap(), "--json"])
                    .args(&submit_client)
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
            d.logs()
        );
        thread::sleep(Duration::from_millis(500 + rng.next() % 1500));
        if start.elapsed() < Duration::from_secs(secs) {
            let label = labels[(rng.next() % labels.len() as u64) as usize];
            d.proc(label).kill();
            kills += 1;
            thread::sleep(Duration::from_millis(rng.next() % 500));
        }
        for label in labels {
            if !d.proc(label).running() {
                d.proc(label).restart();
            }
        }
    }
    let retries = submitter.join().expect("every job journaled");

    // Converged: every job delivered, exactly once.
    let converge = Instant::now();
    let states = wait_all_delivered(d, &client, jobs, Duration::from_secs(300));
    println!(
        "chaos ({name}): {jobs} jobs, {kills} kills over {secs} s (seed {seed}), {retries} submit retries; \
         converged {:.1} s after the last kill",
        converge.elapsed().as_secs_f64()
    );
    let files: BTreeSet<String> = std::fs::read_dir(&program_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    let expected: BTreeSet<String> = (0..jobs).map(|i| format!("_N_CH_{i:04}_MPF")).collect();
    assert_eq!(files, expected, "exactly one file per job, nothing else");
    let conn = rusqlite::Connection::open(&index_db).unwrap();
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
        let text = std::fs::read(program_dir.join(format!("_N_{name}_MPF"))).unwrap();
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

/// Waits until the station lists `n` jobs, every one delivered; their
/// statuses.
fn wait_all_delivered(
    d: &dyn Deployment,
    client: &[String],
    n: usize,
    timeout: Duration,
) -> Vec<serde_json::Value> {
    let start = Instant::now();
    let mut last = Vec::new();
    while start.elapsed() < timeout {
        let out = std::process::Command::new(gearcam_testkit::bin("gearcam"))
            .args(["jobs", "--json"])
            .args(client)
            .output()
            .expect("gearcam jobs runs");
        if let Ok(serde_json::Value::Array(jobs)) = serde_json::from_slice(&out.stdout) {
            if jobs.len() == n && jobs.iter().all(|j| j["state"] == "delivered") {
                return jobs;
            }
            last = jobs;
        }
        thread::sleep(Duration::from_millis(300));
    }
    let states: Vec<String> = last
        .iter()
        .map(|j| format!("{} {} {}", j["job"], j["state"], j["waiting_for"]))
        .collect();
    panic!(
        "not all {n} jobs delivered after {timeout:?}: {states:#?}\n{}",
        d.logs()
    );
}
