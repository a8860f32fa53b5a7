//! Web page benchmark: how fast the planning office's page answers with a
//! full journal, and how soon a job's event reaches a page open in a
//! browser, next to what the bus alone takes in the same run.
//!
//! # What it measures
//!
//! 1. **Pages with `--jobs` jobs in the journal** (default 1,000). It starts
//!    the real processes on loopback (router, station, knowledge, model and
//!    template services, the agent of H01, and `gearcam web`), submits the
//!    jobs (the bundled `examples/spur_840d.toml`, each its own id and part
//!    number) until every one is delivered, signs in, and times each page
//!    from sending the request to the last byte of the answer: the queue
//!    (`/`, every job), the queue searched (`/?q=…`), one job
//!    (`/jobs/{job}`) and a new job's form (`/new/hobbing`, with its check).
//!    Beside them: the station's job list queried on the bus by the
//!    benchmark's own session (what every queue page asks first).
//! 2. **Event → open page.** A headless Chromium (WebDriver, Debian's
//!    `chromium-driver`) opens the queue page with its live stream; the
//!    benchmark submits `--live` more jobs one after another, and the page's
//!    script records, for every event it receives, `Date.now()` minus the
//!    event's own time stamp (set by the service that published it). Beside
//!    it: the same for the benchmark's own Zenoh subscriber on the events.
//!
//! Targets: pages ≤ 50 ms p95; an event in the page ≤ 250 ms p95.
//!
//! # Running it
//!
//! ```sh
//! cargo build --release --workspace --bins && cargo bench -p gearcam-tests --bench web
//! cargo bench -p gearcam-tests --bench web -- --jobs 1000 --live 100
//! ```
//!
//! The services are taken from next to the benchmark's executable
//! (`target/release/`), or from `$GEARCAM_BIN_DIR`.

// Bench code: clocks for timing, the environment for switches.
#![allow(clippy::disallowed_methods)]

#[allow(dead_code)]
#[path = "../tests/browser/harness.rs"]
mod harness;

use std::process::ExitCode;
use std::time::{Duration, Instant};

use anyhow::{anyhow, bail, ensure, Context, Result};
use gearcam_proto::{
    decode, encode, keys, now_ms, JobEvent, JobId, JobRequest, JobSpec, MachineId, StationReply,
};
use gearcam_testkit::web::{http, sign_in};
use harness::{Browser, Shop};
use zenoh::Session;

const EXAMPLE_JOB: &str = include_str!("../../examples/spur_840d.toml");

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("web benchmark failed: {e:#}");
            ExitCode::FAILURE
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct Options {
    jobs: usize,
    live: usize,
}

fn options() -> Result<Options> {
    let mut o = Options {
        jobs: 1000,
        live: 100,
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut n = |name: &str| -> Result<usize> {
            let v = args
                .next()
                .with_context(|| format!("{name} needs a number"))?;
            v.parse()
                .with_context(|| format!("{name} needs a number, got {v:?}"))
        };
        match a.as_str() {
            "--jobs" => o.jobs = n("--jobs")?,
            "--live" => o.live = n("--live")?,
            "--bench" => {}
            other => bail!("unknown argument {other:?}; usage: -- [--jobs N] [--live N]"),
        }
    }
    Ok(o)
}

fn run() -> Result<()> {
    let opts = options()?;
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?;
    rt.block_on(bench(opts))
}

async fn bench(opts: Options) -> Result<()> {
    let shop = Shop::start(&["H01"]);
    let session = open_session(&shop.cluster.endpoint).await?;
    let template: JobSpec =
        toml::from_str(EXAMPLE_JOB).context("examples/spur_840d.toml is not a valid job file")?;
    println!("gearcam web benchmark: {} jobs in the journal", opts.jobs);
    let started = Instant::now();
    submit_all(&session, &template, "WB", opts.jobs, 32).await?;
    wait_delivered(&session, opts.jobs).await?;
    println!(
        "  journal filled: {} jobs delivered in {:.1} s",
        opts.jobs,
        started.elapsed().as_secs_f64()
    );

    let addr = shop.base.trim_start_matches("http://").to_string();
    let cookie = sign_in(&addr, "planner");
    let one = format!("/jobs/WB-{:05}", opts.jobs / 2);
    let search = format!("/?q=WBP-{:05}", opts.jobs / 3);
    println!("\n  page (server-side, request → last byte)     p50        p95        target");
    for (what, path, n) in [
        ("queue, every job", "/", 60),
        ("queue searched", search.as_str(), 60),
        ("one job", one.as_str(), 100),
        ("new job form with its check", "/new/hobbing", 40),
    ] {
        let mut times = Vec::with_capacity(n);
        for _ in 0..n {
            let t = Instant::now();
            let (code, body) = get(&addr, path, &cookie)?;
            times.push(t.elapsed());
            ensure!(code == 200, "{path}: {code}\n{body}");
        }
        report(what, &mut times, "≤ 50 ms");
    }
    let mut times = Vec::new();
    for _ in 0..60 {
        let t = Instant::now();
        let replies = session
            .get(keys::STATION_JOBS)
            .timeout(Duration::from_secs(10))
            .await
            .map_err(|e| anyhow!("station jobs: {e}"))?;
        let reply = replies.recv_async().await.map_err(|e| anyhow!("{e}"))?;
        let _ = reply.result().map_err(|e| anyhow!("{e:?}"))?;
        times.push(t.elapsed());
    }
    report("bus: the station's job list alone", &mut times, "(share)");

    live(&shop, &session, &template, opts.live).await
}

/// Event → page: the browser's latencies beside the bus's.
async fn live(shop: &Shop, session: &Session, template: &JobSpec, n: usize) -> Result<()> {
    let b = Browser::start().await;
    b.sign_in(shop, "planner").await;
    b.client.goto(&shop.url("/")).await?;
    b.client
        .execute(
            "window.lat = []; const s = new EventSource('/events'); s.addEventListener('job', (e) => { const ev = JSON.parse(e.data); window.lat.push(Date.now() - ev.at_ms); }); await new Promise((r) => s.addEventListener('open', r));",
            vec![],
        )
        .await?;
    let bus = session
        .declare_subscriber(keys::ALL_JOB_EVENTS)
        .await
        .map_err(|e| anyhow!("{e}"))?;
    let bus_lat = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
    let sink = bus_lat.clone();
    tokio::spawn(async move {
        while let Ok(s) = bus.recv_async().await {
            if let Ok(ev) = decode::<JobEvent>(&s.payload().to_bytes()) {
                let now = now_ms();
                sink.lock().unwrap().push(now.saturating_sub(ev.at_ms));
            }
        }
    });
    for i in 0..n {
        submit_all(session, template, &format!("LV{i}"), 1, 1).await?;
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    tokio::time::sleep(Duration::from_secs(2)).await;
    let page: Vec<u64> =
        serde_json::from_value(b.client.execute("return window.lat;", vec![]).await?)?;
    let bus: Vec<u64> = bus_lat.lock().unwrap().clone();
    println!("\n  event → where it is seen (ms, event time stamp → receipt)   events   p50    p95    target");
    for (what, mut v, target) in [
        ("the open page's script (browser)", page, "≤ 250 ms"),
        ("the bus alone (Zenoh subscriber)", bus, "(share)"),
    ] {
        ensure!(!v.is_empty(), "{what}: no event arrived");
        v.sort_unstable();
        let p = |q: f64| v[((v.len() as f64 * q).ceil() as usize).clamp(1, v.len()) - 1];
        println!(
            "  {what:<58} {:>6} {:>5} {:>6}    {target}",
            v.len(),
            p(0.5),
            p(0.95)
        );
    }
    b.stop().await;
    Ok(())
}

fn report(what: &str, times: &mut [Duration], target: &str) {
    times.sort_unstable();
    let p = |q: f64| times[((times.len() as f64 * q).ceil() as usize).clamp(1, times.len()) - 1];
    println!(
        "  {what:<42} {:>7.2} ms {:>7.2} ms   {target}",
        p(0.5).as_secs_f64() * 1e3,
        p(0.95).as_secs_f64() * 1e3
    );
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
        .map_err(|e| anyhow!("cannot open a Zenoh session to {endpoint}: {e}"))
}

/// Submits `n` jobs `{prefix}-{i}` (part `{prefix}P-{i}`), `window` at a time.
async fn submit_all(
    session: &Session,
    template: &JobSpec,
    prefix: &str,
    n: usize,
    window: usize,
) -> Result<()> {
    let ids: Vec<usize> = (0..n).collect();
    for chunk in ids.chunks(window) {
        let mut asks = tokio::task::JoinSet::new();
        for i in chunk {
            let (session, mut spec) = (session.clone(), template.clone());
            let job = JobId::new(format!("{prefix}-{i:05}")).map_err(|e| anyhow!("{e}"))?;
            spec.job.id = Some(job.clone());
            spec.job.part_number = format!("{prefix}P-{i:05}");
            spec.job.machine = MachineId::new("H01").map_err(|e| anyhow!("{e}"))?;
            let req = JobRequest {
                job_id: job,
                submitted_at_ms: now_ms(),
                submitted_by: "web-bench".into(),
                spec,
            };
            asks.spawn(async move { submit(&session, &req).await });
        }
        while let Some(r) = asks.join_next().await {
            r??;
        }
    }
    Ok(())
}

async fn submit(session: &Session, req: &JobRequest) -> Result<()> {
    let replies = session
        .get(keys::station_submit("web-bench"))
        .payload(encode(req).map_err(|e| anyhow!("{e}"))?)
        .timeout(Duration::from_secs(30))
        .await
        .map_err(|e| anyhow!("submit: {e}"))?;
    let reply = replies
        .recv_async()
        .await
        .map_err(|e| anyhow!("submit: {e}"))?;
    let sample = reply.result().map_err(|e| anyhow!("submit: {e:?}"))?;
    match decode::<StationReply>(&sample.payload().to_bytes()) {
        Ok(StationReply::Accepted { .. }) => Ok(()),
        other => Err(anyhow!("submit: {other:?}")),
    }
}

/// Waits until the station's journal holds `n` delivered jobs.
async fn wait_delivered(session: &Session, n: usize) -> Result<()> {
    let deadline = Instant::now() + Duration::from_secs(600);
    let mut last = String::from("no answer from the station");
    loop {
        let replies = session
            .get(keys::STATION_JOBS)
            .timeout(Duration::from_secs(10))
            .await
            .map_err(|e| anyhow!("{e}"))?;
        if let Ok(reply) = replies.recv_async().await {
            if let Ok(sample) = reply.result() {
                if let Ok(StationReply::Jobs { jobs }) =
                    decode::<StationReply>(&sample.payload().to_bytes())
                {
                    let done = jobs
                        .iter()
                        .filter(|j| j.state == gearcam_proto::JobState::Delivered)
                        .count();
                    if done >= n {
                        return Ok(());
                    }
                    if let Some(j) = jobs.iter().find(|j| {
                        j.state.is_final() && j.state != gearcam_proto::JobState::Delivered
                    }) {
                        bail!("job {} ended {}: {:?}", j.job, j.state.as_str(), j.errors);
                    }
                    last = format!("{done} of {} delivered", jobs.len());
                }
            }
        }
        ensure!(
            Instant::now() < deadline,
            "the jobs were not all delivered in 10 minutes: {last}"
        );
        tokio::time::sleep(Duration::from_millis(500)).await;
    }
}

fn get(addr: &str, path: &str, cookie: &str) -> Result<(u16, String)> {
    let (code, _, body) = http(addr, "GET", path, &format!("Cookie: {cookie}\r\n"), "");
    Ok((code, body))
}
