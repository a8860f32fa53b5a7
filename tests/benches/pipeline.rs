//! Pipeline benchmark: how many jobs per second gearcam turns into durably
//! stored NC programs, at what submit→receipt latency, next to what Zenoh
//! itself does for one request/reply of the same sizes in the same run.
//!
//! # What it measures
//!
//! 1. **The pipeline.** It starts the real processes on loopback (a router,
//!    the planning station, the knowledge, model and template services and the
//!    agent of H01, as [`Cluster::start`] does), opens its own client session
//!    to the router and submits N jobs (the bundled `examples/spur_840d.toml`,
//!    each with job id `BENCH-{i}` and part number `BP-{i}`, so each program
//!    gets its own file) by querying `gearcam/v1/station/submit/{user}`, with at most
//!    `--window` jobs in flight. A job's latency runs from sending the
//!    submission to receiving its `delivered` event (the agent's receipt, given
//!    only once file and index row are durable). It reports jobs/s, p50 and p99,
//!    and the p50/p99 time at which each stage's event arrived.
//! 2. **Raw Zenoh request/reply.** A `gearcam-echo` process (this crate's
//!    helper binary) answers queries through the same router. It is queried N
//!    times with the same window, each query carrying as many bytes as an
//!    encoded `JobRequest` and answered with as many bytes as an encoded
//!    `NcProgram` (both measured in this run: the program by a listening
//!    queryable on a warm-up job's delivery key).
//! 3. **The ratio** of the two, and a check that the agent's program directory
//!    holds exactly one file per job (plus the warm-up job's), with one index
//!    row each and the hashes of the receipts.
//!
//! It runs twice: a throughput run (`--jobs`, default 2000, at window 64,
//! held to ≥ 1,000 jobs/s) and a latency run (`--latency-jobs`, default 500,
//! at window 1, held to a submit→receipt p99 ≤ 10 ms), each beside raw Zenoh
//! at the same window; the last lines say whether each target is met. With
//! `--window W` it makes one run at that window instead. By Little's law the
//! latency under load is about window ÷ throughput.
//!
//! # Running it
//!
//! The services must be built in release (the `bench` profile) for meaningful
//! figures; the benchmark looks for them next to its own executable
//! (`target/release/`, or `$GEARCAM_BIN_DIR`):
//!
//! ```sh
//! cargo build --release --workspace --bins && cargo bench -p gearcam-tests --bench pipeline
//! cargo bench -p gearcam-tests --bench pipeline -- --jobs 10000 --window 128
//! ```
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]

use std::collections::HashMap;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, ensure, Context, Result};
use gearcam_proto::{
    decode, encode, keys, now_ms, DeliveryReceipt, EventKind, JobEvent, JobId, JobRequest, JobSpec,
    MachineId, StationReply,
};
use gearcam_testkit::{Cluster, Proc};
use sha2::{Digest, Sha256};
use tokio::sync::{oneshot, Semaphore};
use zenoh::Session;

/// The job every submission is made from (its id and part number replaced).
const EXAMPLE_JOB: &str = include_str!("../../examples/spur_840d.toml");
/// The command that builds what the benchmark runs.
const COMMAND: &str =
    "cargo build --release --workspace --bins && cargo bench -p gearcam-tests --bench pipeline";
/// Binaries the benchmark starts.
const BINARIES: [&str; 6] = [
    "gearcam",
    "gearcam-knowledge",
    "gearcam-model",
    "gearcam-template",
    "gearcam-agent",
    "gearcam-echo",
];
/// Liveliness tokens to wait for before submitting.
const ALIVE: [&str; 6] = [
    "gearcam/v1/alive/station",
    "gearcam/v1/alive/knowledge",
    "gearcam/v1/alive/model",
    "gearcam/v1/alive/template",
    "gearcam/v1/alive/agent/H01",
    "bench/alive/echo",
];
/// The warm-up job, whose delivery is also listened to for the program's size.
const PROBE_JOB: &str = "BENCH-PROBE";
/// How long the processes may take to declare their liveliness tokens.
const STARTUP_TIMEOUT: Duration = Duration::from_secs(60);
/// How long one query (submission or echo) may take.
const QUERY_TIMEOUT: Duration = Duration::from_secs(30);
/// How long one job may take from submission to receipt.
const JOB_TIMEOUT: Duration = Duration::from_secs(120);

/// Command-line options (after `--`).
#[derive(Debug, Clone, Copy)]
struct Options {
    /// Jobs to submit (and echo queries to send) in the throughput run.
    jobs: usize,
    /// Jobs of the latency run (window 1).
    latency_jobs: usize,
    /// Most jobs (queries) in flight at once: given, one run at this window;
    /// not given, a throughput run at 64 and a latency run at 1.
    window: Option<usize>,
}

impl Options {
    fn parse(args: impl Iterator<Item = String>) -> Result<Options> {
        let mut opts = Options {
            jobs: 2000,
            latency_jobs: 500,
            window: None,
        };
        let mut args = args;
        while let Some(arg) = args.next() {
            let mut number = |name: &str| -> Result<usize> {
                let v = args
                    .next()
                    .with_context(|| format!("{name} needs a number"))?;
                let n: usize = v
                    .parse()
                    .with_context(|| format!("{name} needs a positive number, got {v:?}"))?;
                ensure!(n > 0, "{name} needs a positive number, got 0");
                Ok(n)
            };
            match arg.as_str() {
                "--jobs" => opts.jobs = number("--jobs")?,
                "--window" => opts.window = Some(number("--window")?),
                "--latency-jobs" => opts.latency_jobs = number("--latency-jobs")?,
                // `cargo bench` passes `--bench` to every bench binary.
                "--bench" => {}
                other => bail!(
                    "unknown argument {other:?}; usage: cargo bench -p gearcam-tests --bench pipeline -- [--jobs N] [--latency-jobs M] [--window W]"
                ),
            }
        }
        ensure!(
            opts.jobs + opts.latency_jobs <= 99_999,
            "--jobs is at most 99999 (job ids are BENCH-00000 … BENCH-99999)"
        );
        Ok(opts)
    }
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("pipeline benchmark failed: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<()> {
    let opts = Options::parse(std::env::args().skip(1))?;
    let bin_dir = check_binaries()?;
    println!(
        "gearcam pipeline benchmark: {}, binaries from {}",
        match opts.window {
            Some(w) => format!("{} jobs at window {w}", opts.jobs),
            None => format!(
                "{} jobs at window 64, then {} at window 1",
                opts.jobs, opts.latency_jobs
            ),
        },
        bin_dir.display()
    );
    let cluster = Cluster::start();
    let echo = Proc::start(
        cluster.dir.path(),
        "echo",
        "gearcam-echo",
        &["--connect".to_string(), cluster.endpoint.clone()],
    );
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .context("cannot start the tokio runtime")?;
    let result = rt.block_on(bench(&cluster, opts));
    if result.is_err() {
        eprintln!("{}", log_tails(&cluster, &echo, 30));
    }
    result
}

/// The directory holding the service binaries; fails naming the command that
/// builds them when one is missing.
fn check_binaries() -> Result<PathBuf> {
    let dir = match std::env::var_os("GEARCAM_BIN_DIR") {
        Some(d) => PathBuf::from(d),
        None => std::env::current_exe()
            .context("cannot find the benchmark's own executable")?
            .parent()
            .and_then(|deps| deps.parent())
            .context("the benchmark executable is not in target/<profile>/deps")?
            .to_path_buf(),
    };
    let missing: Vec<&str> = BINARIES
        .iter()
        .copied()
        .filter(|b| !dir.join(b).exists())
        .collect();
    ensure!(
        missing.is_empty(),
        "{} missing in {}: build the release binaries first: `{COMMAND}`",
        missing.join(", "),
        dir.display()
    );
    Ok(dir)
}

/// One run of the pipeline beside raw Zenoh at the same window, and the
/// target it is held to.
struct Phase {
    jobs: usize,
    window: usize,
    /// The first job's number (job ids of phases do not overlap).
    first: usize,
    target: Target,
}

/// What a phase is held to.
#[derive(Clone, Copy)]
enum Target {
    /// At least this many jobs per second.
    Throughput(f64),
    /// A submit→receipt p99 of at most this many milliseconds.
    P99(f64),
    /// None: a run with the window given on the command line.
    None,
}

async fn bench(cluster: &Cluster, opts: Options) -> Result<()> {
    let session = open_session(&cluster.endpoint).await?;
    wait_alive(&session).await?;
    let tracker = Tracker::default();
    let _events = tracker.subscribe(&session).await?;
    let template: JobSpec =
        toml::from_str(EXAMPLE_JOB).context("examples/spur_840d.toml is not a valid job file")?;

    // Warm-up job: its delivery query (template → agent) is also heard by a
    // queryable of ours that does not answer, to measure the program's size.
    let probe = job_request(&template, PROBE_JOB, "BP-PROBE")?;
    let nc_size = probe_program_size(&session, &tracker, probe).await?;
    let request_size = encode(&job_request(&template, "BENCH-00000", "BP-00000")?)?.len();
    println!("payloads: job_request {request_size} B, nc_program {nc_size} B (encoded, measured)");

    let phases = match opts.window {
        Some(window) => vec![Phase {
            jobs: opts.jobs,
            window,
            first: 0,
            target: Target::None,
        }],
        None => vec![
            Phase {
                jobs: opts.jobs,
                window: 64,
                first: 0,
                target: Target::Throughput(1000.0),
            },
            Phase {
                jobs: opts.latency_jobs,
                window: 1,
                first: opts.jobs,
                target: Target::P99(10.0),
            },
        ],
    };
    let mut all_jobs = Vec::new();
    let mut held = Vec::new();
    for phase in phases {
        let requests = (phase.first..phase.first + phase.jobs)
            .map(|i| job_request(&template, &format!("BENCH-{i:05}"), &format!("BP-{i:05}")))
            .collect::<Result<Vec<_>>>()?;
        let (pipeline, jobs) = run_pipeline(&session, &tracker, requests, phase.window).await?;
        println!();
        println!(
            "pipeline, window {} (station → knowledge → model → template → agent, durable, separate processes)",
            phase.window
        );
        println!(
            "  {} jobs in {:.2} s: {:.0} jobs/s; submit→receipt p50 {}, p99 {}",
            phase.jobs,
            pipeline.elapsed.as_secs_f64(),
            pipeline.rate(),
            ms(pipeline.percentile(50.0)),
            ms(pipeline.percentile(99.0)),
        );
        for (stage, p50, p99) in stage_percentiles(&jobs) {
            println!("    {stage:<28} p50 {:>9}  p99 {:>9}", ms(p50), ms(p99));
        }
        // Raw Zenoh request/reply of the same sizes through the same router.
        let raw = run_echo(&session, phase.jobs, phase.window, request_size, nc_size).await?;
        println!("  raw zenoh request/reply, same window (bench → router → gearcam-echo, {request_size} B query, {nc_size} B reply)");
        println!(
            "    {} queries in {:.2} s: {:.0} req/s; p50 {}, p99 {}",
            phase.jobs,
            raw.elapsed.as_secs_f64(),
            raw.rate(),
            ms(raw.percentile(50.0)),
            ms(raw.percentile(99.0)),
        );
        println!(
            "  pipeline vs raw: throughput {:.1} % of raw; latency p50 {:.1}×, p99 {:.1}× raw",
            100.0 * pipeline.rate() / raw.rate(),
            ratio(pipeline.percentile(50.0), raw.percentile(50.0)),
            ratio(pipeline.percentile(99.0), raw.percentile(99.0)),
        );
        let verdict = match phase.target {
            Target::Throughput(min) => Some((
                pipeline.rate() >= min,
                format!(
                    "throughput at window {}: {:.0} jobs/s (target ≥ {min:.0} jobs/s)",
                    phase.window,
                    pipeline.rate()
                ),
            )),
            Target::P99(max) => {
                let p99 = pipeline.percentile(99.0).as_secs_f64() * 1e3;
                Some((
                    p99 <= max,
                    format!(
                        "submit→receipt p99 at window {}: {p99:.2} ms (target ≤ {max:.0} ms)",
                        phase.window
                    ),
                ))
            }
            Target::None => None,
        };
        held.extend(verdict);
        all_jobs.extend(jobs);
    }

    let verified = verify_store(cluster, &all_jobs)?;
    println!();
    println!("verified: {verified}");
    for (met, line) in &held {
        println!("{} {line}", if *met { "met:    " } else { "NOT MET:" });
    }
    session
        .close()
        .await
        .map_err(|e| anyhow!("cannot close the Zenoh session: {e}"))?;
    Ok(())
}

async fn open_session(endpoint: &str) -> Result<Session> {
    let mut config = zenoh::Config::default();
    let setting = |e: zenoh::Error| anyhow!("invalid Zenoh setting: {e}");
    config.insert_json5("mode", "\"client\"").map_err(setting)?;
    config
        .insert_json5("connect/endpoints", &format!("[\"{endpoint}\"]"))
        .map_err(setting)?;
    config
        .insert_json5("scouting/multicast/enabled", "false")
        .map_err(setting)?;
    zenoh::open(config)
        .await
        .map_err(|e| anyhow!("cannot open a Zenoh session to the router {endpoint}: {e}"))
}

/// Waits until every process has declared its liveliness token.
async fn wait_alive(session: &Session) -> Result<()> {
    let start = Instant::now();
    for key in ALIVE {
        loop {
            let replies = session
                .liveliness()
                .get(key)
                .timeout(Duration::from_millis(500))
                .await
                .map_err(|e| anyhow!("liveliness query {key} failed: {e}"))?;
            if replies.recv_async().await.is_ok() {
                break;
            }
            ensure!(
                start.elapsed() < STARTUP_TIMEOUT,
                "{key} not declared after {STARTUP_TIMEOUT:?}: a process did not start"
            );
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }
    Ok(())
}

/// A job request made from the example with its own id and part number.
fn job_request(template: &JobSpec, job: &str, part: &str) -> Result<JobRequest> {
    let job_id = JobId::new(job.to_string()).with_context(|| format!("job id {job}"))?;
    let mut spec = template.clone();
    spec.job.id = Some(job_id.clone());
    spec.job.part_number = part.to_string();
    spec.job.machine = MachineId::new("H01".to_string()).context("machine id H01")?;
    Ok(JobRequest {
        job_id,
        submitted_at_ms: now_ms(),
        submitted_by: "pipeline-bench".into(),
        spec,
    })
}

/// Where a job's events arrived, relative to its submission.
#[derive(Debug, Default, Clone)]
struct Progress {
    accepted: Option<Duration>,
    planned: Option<Duration>,
    modelled: Option<Duration>,
    programmed: Option<Duration>,
}

/// A job followed from submission to its end.
#[derive(Debug)]
struct Following {
    sent: Instant,
    progress: Progress,
    end: Option<oneshot::Sender<Result<DeliveryReceipt, String>>>,
}

/// Routes the events of every job to the task that submitted it.
#[derive(Debug, Default, Clone)]
struct Tracker {
    jobs: Arc<Mutex<HashMap<String, Following>>>,
}

impl Tracker {
    /// Subscribes to every job's events; the subscriber lives as long as the
    /// returned value.
    async fn subscribe(&self, session: &Session) -> Result<zenoh::pubsub::Subscriber<()>> {
        let tracker = self.clone();
        session
            .declare_subscriber(keys::ALL_JOB_EVENTS)
            .callback(move |sample| {
                if let Ok(ev) = decode::<JobEvent>(&sample.payload().to_bytes()) {
                    tracker.on_event(ev);
                }
            })
            .await
            .map_err(|e| anyhow!("cannot subscribe to {}: {e}", keys::ALL_JOB_EVENTS))
    }

    fn on_event(&self, ev: JobEvent) {
        let mut jobs = self.jobs.lock().unwrap_or_else(|p| p.into_inner());
        let Some(job) = jobs.get_mut(ev.job_id.as_str()) else {
            return;
        };
        let at = Some(job.sent.elapsed());
        let end = match ev.event {
            EventKind::Planned { .. } => {
                job.progress.planned = job.progress.planned.or(at);
                None
            }
            EventKind::Modelled { .. } => {
                job.progress.modelled = job.progress.modelled.or(at);
                None
            }
            EventKind::Programmed { .. } => {
                job.progress.programmed = job.progress.programmed.or(at);
                None
            }
            EventKind::Accepted { .. } | EventKind::Waiting { .. } => None,
            EventKind::Delivered { receipt } => Some(Ok(receipt)),
            EventKind::Failed { errors } => Some(Err(errors
                .iter()
                .map(|e| format!("{} {} {}: {}", e.stage.as_str(), e.code, e.field, e.message))
                .collect::<Vec<_>>()
                .join("; "))),
            EventKind::Superseded { name, .. } => {
                Some(Err(format!("superseded by an edit of {name}")))
            }
            EventKind::Cancelled { by } => Some(Err(format!("cancelled by {by}"))),
        };
        if let Some(end) = end {
            if let Some(tx) = job.end.take() {
                // The submitting task may have given up (timeout); nothing to tell then.
                let _ = tx.send(end);
            }
        }
    }

    /// Starts following a job; call before submitting it.
    fn follow(&self, job: &str) -> oneshot::Receiver<Result<DeliveryReceipt, String>> {
        let (tx, rx) = oneshot::channel();
        let mut jobs = self.jobs.lock().unwrap_or_else(|p| p.into_inner());
        jobs.insert(
            job.to_string(),
            Following {
                sent: Instant::now(),
                progress: Progress::default(),
                end: Some(tx),
            },
        );
        rx
    }

    /// Stops following a job and returns its progress.
    fn finish(&self, job: &str) -> Progress {
        let mut jobs = self.jobs.lock().unwrap_or_else(|p| p.into_inner());
        jobs.remove(job).map(|f| f.progress).unwrap_or_default()
    }
}

/// One job's outcome.
#[derive(Debug)]
struct JobResult {
    latency: Duration,
    progress: Progress,
    receipt: DeliveryReceipt,
}

/// Submits a job through the station and waits for its receipt.
async fn submit_and_follow(
    session: &Session,
    tracker: &Tracker,
    req: JobRequest,
) -> Result<JobResult> {
    let job = req.job_id.to_string();
    let payload = encode(&req)?;
    let ended = tracker.follow(&job);
    let start = Instant::now();
    let outcome = async {
        let replies = session
            .get(keys::station_submit(&req.submitted_by))
            .payload(payload)
            .timeout(QUERY_TIMEOUT)
            .await
            .map_err(|e| anyhow!("{job}: submit query failed: {e}"))?;
        let reply = replies
            .recv_async()
            .await
            .map_err(|_| anyhow!("{job}: the station did not answer within {QUERY_TIMEOUT:?}"))?;
        let sample = reply.result().map_err(|e| {
            anyhow!(
                "{job}: the station answered with an error: {}",
                String::from_utf8_lossy(&e.payload().to_bytes())
            )
        })?;
        let accepted = start.elapsed();
        match decode::<StationReply>(&sample.payload().to_bytes())
            .with_context(|| format!("{job}: undecodable station reply"))?
        {
            StationReply::Accepted { .. } => {}
            StationReply::Refused { errors } => bail!("{job}: the station refused it: {errors:?}"),
            other => bail!("{job}: the station answered a submission with {other:?}"),
        }
        let receipt = tokio::time::timeout(JOB_TIMEOUT, ended)
            .await
            .map_err(|_| anyhow!("{job}: no receipt within {JOB_TIMEOUT:?}"))?
            .map_err(|_| anyhow!("{job}: the event subscriber went away"))?
            .map_err(|errors| anyhow!("{job}: failed: {errors}"))?;
        Ok((accepted, receipt))
    }
    .await;
    let latency = start.elapsed();
    let mut progress = tracker.finish(&job);
    let (accepted, receipt) = outcome?;
    progress.accepted = Some(accepted);
    Ok(JobResult {
        latency,
        progress,
        receipt,
    })
}

/// Submits the warm-up job while a silent queryable on its delivery key hears
/// the template service's request to the agent; returns the encoded
/// `NcProgram`'s size. Zenoh routes a query to every matching queryable when
/// none is complete, and the agent's answer still ends the delivery.
async fn probe_program_size(
    session: &Session,
    tracker: &Tracker,
    req: JobRequest,
) -> Result<usize> {
    let key = keys::machine_program(&req.spec.job.machine, &req.job_id);
    let (tx, rx) = oneshot::channel::<usize>();
    let tx = Mutex::new(Some(tx));
    let listener = session
        .declare_queryable(&key)
        .callback(move |query| {
            let size = query.payload().map(|p| p.len()).unwrap_or(0);
            if let Some(tx) = tx.lock().unwrap_or_else(|p| p.into_inner()).take() {
                let _ = tx.send(size);
            }
            // Dropping the query unanswered tells the querier this side is done.
        })
        .await
        .map_err(|e| anyhow!("cannot declare the listening queryable {key}: {e}"))?;
    // Give the declaration time to reach the router before the job gets there.
    tokio::time::sleep(Duration::from_millis(200)).await;
    submit_and_follow(session, tracker, req)
        .await
        .context("the warm-up job was not delivered")?;
    let size = tokio::time::timeout(Duration::from_secs(5), rx)
        .await
        .ok()
        .and_then(Result::ok)
        .with_context(|| format!("the delivery of {PROBE_JOB} was not heard on {key}"))?;
    listener
        .undeclare()
        .await
        .map_err(|e| anyhow!("cannot undeclare {key}: {e}"))?;
    ensure!(size > 0, "the delivery of {PROBE_JOB} carried no program");
    Ok(size)
}

/// Latencies of a run and its wall-clock time.
#[derive(Debug)]
struct Run {
    elapsed: Duration,
    latencies: Vec<Duration>,
}

impl Run {
    fn new(elapsed: Duration, mut latencies: Vec<Duration>) -> Run {
        latencies.sort();
        Run { elapsed, latencies }
    }

    fn rate(&self) -> f64 {
        self.latencies.len() as f64 / self.elapsed.as_secs_f64()
    }

    fn percentile(&self, p: f64) -> Duration {
        percentile(&self.latencies, p)
    }
}

/// Nearest-rank percentile of sorted values.
fn percentile(sorted: &[Duration], p: f64) -> Duration {
    if sorted.is_empty() {
        return Duration::ZERO;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil() as usize;
    sorted[rank.clamp(1, sorted.len()) - 1]
}

fn ms(d: Duration) -> String {
    format!("{:.2} ms", d.as_secs_f64() * 1e3)
}

fn ratio(a: Duration, b: Duration) -> f64 {
    a.as_secs_f64() / b.as_secs_f64().max(1e-9)
}

/// Submits every request, at most `window` in flight.
async fn run_pipeline(
    session: &Session,
    tracker: &Tracker,
    requests: Vec<JobRequest>,
    window: usize,
) -> Result<(Run, Vec<JobResult>)> {
    let permits = Arc::new(Semaphore::new(window));
    let mut tasks = tokio::task::JoinSet::new();
    let start = Instant::now();
    for req in requests {
        let permit = permits.clone().acquire_owned().await?;
        let (session, tracker) = (session.clone(), tracker.clone());
        tasks.spawn(async move {
            let result = submit_and_follow(&session, &tracker, req).await;
            drop(permit);
            result
        });
    }
    let mut jobs = Vec::new();
    let mut failures = Vec::new();
    while let Some(joined) = tasks.join_next().await {
        match joined.context("a submitting task panicked")? {
            Ok(job) => jobs.push(job),
            Err(e) => failures.push(format!("{e:#}")),
        }
    }
    let elapsed = start.elapsed();
    if !failures.is_empty() {
        bail!(
            "{} of {} jobs did not end delivered; first: {}",
            failures.len(),
            failures.len() + jobs.len(),
            failures[..failures.len().min(5)].join(" | ")
        );
    }
    let run = Run::new(elapsed, jobs.iter().map(|j| j.latency).collect());
    Ok((run, jobs))
}

/// When a stage's event arrived, read from a job's progress.
type StageTime = fn(&Progress) -> Option<Duration>;

/// p50 and p99 of when each stage's event arrived after submission.
fn stage_percentiles(jobs: &[JobResult]) -> Vec<(&'static str, Duration, Duration)> {
    let stages: [(&str, StageTime); 4] = [
        ("station journaled (reply)", |p| p.accepted),
        ("knowledge: planned event", |p| p.planned),
        ("model: modelled event", |p| p.modelled),
        ("template: programmed event", |p| p.programmed),
    ];
    let mut rows: Vec<(&'static str, Duration, Duration)> = stages
        .iter()
        .map(|(name, get)| {
            let mut v: Vec<Duration> = jobs.iter().filter_map(|j| get(&j.progress)).collect();
            v.sort();
            (*name, percentile(&v, 50.0), percentile(&v, 99.0))
        })
        .collect();
    let mut done: Vec<Duration> = jobs.iter().map(|j| j.latency).collect();
    done.sort();
    rows.push((
        "agent: delivered (receipt)",
        percentile(&done, 50.0),
        percentile(&done, 99.0),
    ));
    rows
}

/// Queries the echo process `n` times, at most `window` in flight.
async fn run_echo(
    session: &Session,
    n: usize,
    window: usize,
    request_size: usize,
    reply_size: usize,
) -> Result<Run> {
    let key = format!("bench/echo/{reply_size}");
    let payload = vec![0xa5_u8; request_size];
    let once = |session: Session, key: String, payload: Vec<u8>| async move {
        let start = Instant::now();
        let replies = session
            .get(&key)
            .payload(payload)
            .timeout(QUERY_TIMEOUT)
            .await
            .map_err(|e| anyhow!("echo query failed: {e}"))?;
        let reply = replies
            .recv_async()
            .await
            .map_err(|_| anyhow!("gearcam-echo did not answer within {QUERY_TIMEOUT:?}"))?;
        let sample = reply
            .result()
            .map_err(|e| anyhow!("gearcam-echo answered with an error: {e:?}"))?;
        ensure!(
            sample.payload().len() == reply_size,
            "gearcam-echo answered {} bytes, expected {reply_size}",
            sample.payload().len()
        );
        Ok::<Duration, anyhow::Error>(start.elapsed())
    };
    // Warm-up: one window's worth, not measured.
    for _ in 0..window.min(n) {
        once(session.clone(), key.clone(), payload.clone()).await?;
    }
    let permits = Arc::new(Semaphore::new(window));
    let mut tasks = tokio::task::JoinSet::new();
    let start = Instant::now();
    for _ in 0..n {
        let permit = permits.clone().acquire_owned().await?;
        let query = once(session.clone(), key.clone(), payload.clone());
        tasks.spawn(async move {
            let result = query.await;
            drop(permit);
            result
        });
    }
    let mut latencies = Vec::with_capacity(n);
    while let Some(joined) = tasks.join_next().await {
        latencies.push(joined.context("an echo task panicked")??);
    }
    Ok(Run::new(start.elapsed(), latencies))
}

/// Checks that the agent stored every job exactly once: one file per job
/// (plus the warm-up job's) with the receipt's hash, one index row per job.
fn verify_store(cluster: &Cluster, jobs: &[JobResult]) -> Result<String> {
    let dir = cluster.program_dir();
    let files: Vec<String> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot list the program directory {}", dir.display()))?
        .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect::<std::io::Result<_>>()
        .with_context(|| format!("cannot list the program directory {}", dir.display()))?;
    let expected = jobs.len() + 1;
    ensure!(
        files.len() == expected,
        "{} holds {} files, expected {expected} ({} jobs and the warm-up job)",
        dir.display(),
        files.len(),
        jobs.len()
    );
    let mut duplicates = 0;
    for job in jobs {
        let r = &job.receipt;
        duplicates += usize::from(r.duplicate);
        let path = dir.join(&r.file_name);
        let text = std::fs::read(&path)
            .with_context(|| format!("{}: receipt names {}", r.job_id, path.display()))?;
        ensure!(
            hex::encode(Sha256::digest(&text)) == r.sha256,
            "{}: {} does not hash to the receipt's {}",
            r.job_id,
            path.display(),
            r.sha256
        );
    }
    let conn = rusqlite::Connection::open_with_flags(
        cluster.index_db(),
        rusqlite::OpenFlags::SQLITE_OPEN_READ_ONLY,
    )
    .context("cannot open the agent's index")?;
    let (rows, distinct_jobs, distinct_files): (i64, i64, i64) = conn
        .query_row(
            "SELECT COUNT(*), COUNT(DISTINCT job), COUNT(DISTINCT file_name) FROM programs
             WHERE job LIKE 'BENCH-%' AND job <> ?1",
            [PROBE_JOB],
            |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
        )
        .context("cannot read the agent's index")?;
    let n = jobs.len() as i64;
    ensure!(
        rows == n && distinct_jobs == n && distinct_files == n,
        "the agent's index has {rows} rows for {distinct_jobs} jobs and {distinct_files} files, expected {n} of each"
    );
    Ok(format!(
        "{expected} program files ({} jobs + warm-up) with the receipts' hashes, {rows} index rows \
         (one per job, one file each), {duplicates} duplicate receipts",
        jobs.len()
    ))
}

/// The last lines of every process's log, for a failure.
fn log_tails(cluster: &Cluster, echo: &Proc, lines: usize) -> String {
    cluster
        .procs
        .iter()
        .chain(std::iter::once(echo))
        .map(|p| {
            let text = std::fs::read_to_string(&p.log).unwrap_or_default();
            let tail: Vec<&str> = text.lines().rev().take(lines).collect();
            let tail: Vec<&str> = tail.into_iter().rev().collect();
            format!(
                "--- {} (last {lines} lines) ---\n{}",
                p.name,
                tail.join("\n")
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}
