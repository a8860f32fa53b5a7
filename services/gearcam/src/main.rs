//! `gearcam`: the planning station command.

mod kb;
mod templates;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use clap::{Parser, Subcommand};
use gearcam::check::{self, CheckReport};
use gearcam::embedded::Embedded;
use gearcam::station::{self, Outcome, SubmitOptions};
use gearcam::{jobfile, store, DEFAULT_ENDPOINT};
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs, BusConfig, Mode};
use gearcam_proto::{JobId, MachineId};
use gearcam_template::Templates;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;

/// gearcam: from a gear drawing to a proven NC program in the machine's program store.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run every service and one agent per configured machine in this process.
    Up {
        /// Data directory (knowledge base, machines' program stores).
        #[arg(long, default_value = "gearcam-data")]
        data: PathBuf,
        #[command(flatten)]
        bus: BusArgs,
    },
    /// Start what `up` starts, submit the bundled example jobs, show the programs, stop.
    Demo {
        /// Data directory (knowledge base, machines' program stores).
        #[arg(long, default_value = "gearcam-data")]
        data: PathBuf,
    },
    /// Submit a job file over the bus.
    Submit {
        /// The job file (TOML; see examples/).
        job: PathBuf,
        #[command(flatten)]
        bus: BusArgs,
        /// Follow the job until the program is delivered (exit 0) or refused (exit 1).
        #[arg(long)]
        wait: bool,
        /// Print the outcome as JSON.
        #[arg(long)]
        json: bool,
        /// Seconds to wait for the outcome (with --wait) and for the services.
        #[arg(long, default_value_t = 60)]
        timeout: u64,
    },
    /// Compute the job locally (no bus) and print the result and the program.
    Check {
        /// The job file (TOML; see examples/).
        job: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Data directory holding the knowledge base (created and seeded if missing).
        #[arg(long, default_value = "gearcam-data")]
        data: PathBuf,
    },
    /// Run the planning station service on its own (job journal, re-drives).
    Station {
        /// The job journal (SQLite).
        #[arg(long, default_value = "gearcam-data/station.db")]
        journal: PathBuf,
        /// Re-drive a job after this many milliseconds without progress (then with backoff).
        #[arg(long, default_value_t = 5000)]
        redrive_ms: u64,
        #[command(flatten)]
        bus: BusArgs,
    },
    /// List every job in the station's journal.
    Jobs {
        #[command(flatten)]
        bus: BusArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Show one job's state.
    Status {
        /// The job id.
        job: JobId,
        #[command(flatten)]
        bus: BusArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// A machine's stored programs: history, show a version, roll back.
    Program {
        #[command(subcommand)]
        action: ProgramAction,
    },
    /// The knowledge base's libraries: list, show, add, edit, remove, CSV import/export.
    Kb(kb::KbArgs),
    /// After delivery: record the values actually used and the outcome; the job becomes a case.
    Confirm(kb::ConfirmArgs),
    /// The standard module library: analyze literal similarity, import, list, show templates.
    Templates(templates::TemplatesArgs),
    /// Run a Zenoh router (for a shop network without zenohd, and for tests).
    Router {
        #[command(flatten)]
        bus: BusArgs,
    },
}

#[derive(Debug, Subcommand)]
enum ProgramAction {
    /// Every stored version (of one program, if named), newest first.
    History {
        /// The machine, e.g. H01.
        #[arg(long)]
        machine: MachineId,
        /// Program name, e.g. SP_1001.
        name: Option<String>,
        #[command(flatten)]
        bus: BusArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Print one stored version's text.
    Show {
        /// The machine, e.g. H01.
        #[arg(long)]
        machine: MachineId,
        /// Program name.
        name: String,
        /// Version number (from `history`).
        seq: u64,
        #[command(flatten)]
        bus: BusArgs,
    },
    /// Make a stored version current again in the machine's program directory.
    Rollback {
        /// The machine, e.g. H01.
        #[arg(long)]
        machine: MachineId,
        /// Program name.
        name: String,
        /// Version number (from `history`).
        seq: u64,
        #[command(flatten)]
        bus: BusArgs,
    },
}

/// The example jobs `gearcam demo` submits, bundled into the binary: one or
/// more per gear class.
const DEMO_JOBS: &[(&str, &str)] = &[
    (
        "examples/spur_840d.toml",
        include_str!("../../../examples/spur_840d.toml"),
    ),
    (
        "examples/spur_by_part_840d.toml",
        include_str!("../../../examples/spur_by_part_840d.toml"),
    ),
    (
        "examples/helical_840d.toml",
        include_str!("../../../examples/helical_840d.toml"),
    ),
    (
        "examples/helical_climb_840d.toml",
        include_str!("../../../examples/helical_climb_840d.toml"),
    ),
    (
        "examples/helical_left_840d.toml",
        include_str!("../../../examples/helical_left_840d.toml"),
    ),
    (
        "examples/helical_climb_fanuc.toml",
        include_str!("../../../examples/helical_climb_fanuc.toml"),
    ),
    (
        "examples/multi_cut_shift_840d.toml",
        include_str!("../../../examples/multi_cut_shift_840d.toml"),
    ),
    (
        "examples/conical_840d.toml",
        include_str!("../../../examples/conical_840d.toml"),
    ),
    (
        "examples/crowned_840d.toml",
        include_str!("../../../examples/crowned_840d.toml"),
    ),
    (
        "examples/crowned_parabolic_840d.toml",
        include_str!("../../../examples/crowned_parabolic_840d.toml"),
    ),
    (
        "examples/worm_wheel_840d.toml",
        include_str!("../../../examples/worm_wheel_840d.toml"),
    ),
    (
        "examples/worm_wheel_tangential_840d.toml",
        include_str!("../../../examples/worm_wheel_tangential_840d.toml"),
    ),
    (
        "examples/helical_shift_fanuc.toml",
        include_str!("../../../examples/helical_shift_fanuc.toml"),
    ),
    (
        "examples/multi_gear_840d.toml",
        include_str!("../../../examples/multi_gear_840d.toml"),
    ),
];

/// Invalid jobs `gearcam demo` submits to show typed refusals; each file names
/// the error code it must get in a `# expect: CODE` line.
const DEMO_INVALID: &[(&str, &str)] = &[
    (
        "examples/invalid_base_pitch.toml",
        include_str!("../../../examples/invalid_base_pitch.toml"),
    ),
    (
        "examples/invalid_two_classes.toml",
        include_str!("../../../examples/invalid_two_classes.toml"),
    ),
    (
        "examples/invalid_crowning.toml",
        include_str!("../../../examples/invalid_crowning.toml"),
    ),
    (
        "examples/invalid_shift_range.toml",
        include_str!("../../../examples/invalid_shift_range.toml"),
    ),
    (
        "examples/invalid_curved_tooth.toml",
        include_str!("../../../examples/invalid_curved_tooth.toml"),
    ),
    (
        "examples/invalid_unknown_part.toml",
        include_str!("../../../examples/invalid_unknown_part.toml"),
    ),
];

/// The code an invalid example expects (its `# expect:` line).
fn expected_code(text: &str) -> Option<&str> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix("# expect:"))
        .map(str::trim)
}

fn main() -> ExitCode {
    init_tracing("warn");
    let cli = Cli::parse();
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("gearcam: cannot start the runtime: {e}");
            return ExitCode::from(2);
        }
    };
    match rt.block_on(run(cli)) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("gearcam: {e:#}");
            ExitCode::from(2)
        }
    }
}

async fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Up { data, bus } => up(&data, &bus).await,
        Command::Demo { data } => demo(&data).await,
        Command::Submit {
            job,
            bus,
            wait,
            json,
            timeout,
        } => submit(&job, &bus, wait, json, timeout).await,
        Command::Check { job, json, data } => Ok(check_cmd(&job, json, &data)),
        Command::Router { bus } => router(&bus).await,
        Command::Kb(args) => Ok(kb::run(args)),
        Command::Confirm(args) => Ok(kb::confirm(args)),
        Command::Templates(args) => Ok(templates::run(args)),
        Command::Station {
            journal,
            redrive_ms,
            bus,
        } => station_cmd(journal, redrive_ms, &bus).await,
        Command::Jobs { bus, json } => jobs_cmd(&bus, json).await,
        Command::Status { job, bus, json } => status_cmd(&job, &bus, json).await,
        Command::Program { action } => program_cmd(action).await,
    }
}

fn embedded_config(bus: &BusArgs, default_listen: &str) -> BusConfig {
    let mut c = bus.to_config();
    c.mode.get_or_insert(Mode::Peer);
    if c.listen.is_empty() && c.config_file.is_none() {
        c.listen = vec![default_listen.to_string()];
    }
    if c.config_file.is_none() {
        c.multicast_scouting = Some(false);
    }
    c
}

async fn up(data: &Path, bus: &BusArgs) -> anyhow::Result<ExitCode> {
    let config = embedded_config(bus, DEFAULT_ENDPOINT);
    let mut services = Embedded::start(&config, data, template_library(data)?)
        .await
        .with_context(|| format!("starting the services (listening on {:?})", config.listen))?;
    println!(
        "gearcam up: all services running; listening on {}",
        config.listen.join(", ")
    );
    println!("  knowledge base {}", data.join("knowledge.db").display());
    for (m, dir) in &services.machines {
        println!(
            "  agent {} ({}) stores programs in {}",
            m.id,
            m.dialect.as_str(),
            dir.display()
        );
    }
    println!("submit with: gearcam submit examples/spur_840d.toml --wait   (Ctrl-C stops)");
    let stop = cancel_on_signal();
    let result = services.serve_until(stop).await;
    services.stop().await;
    result.map(|()| ExitCode::SUCCESS)
}

fn progress(json: bool) -> ProgressBar {
    if json {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new_spinner();
    pb.set_style(
        ProgressStyle::with_template("{spinner} {elapsed} {msg}").expect("valid template"),
    );
    pb.enable_steady_tick(Duration::from_millis(120));
    pb
}

async fn demo(data: &Path) -> anyhow::Result<ExitCode> {
    let config = embedded_config(&BusArgs::default(), "tcp/127.0.0.1:0");
    let services = Embedded::start(&config, data, template_library(data)?).await?;
    println!(
        "gearcam demo: services up on a loopback session; data in {}\n",
        data.display()
    );
    let opts = SubmitOptions {
        wait: true,
        alive_timeout: Duration::from_secs(10),
        timeout: Duration::from_secs(30),
    };
    let mut all_ok = true;
    for (origin, text) in DEMO_JOBS {
        let spec = jobfile::parse(text, origin).map_err(|e| anyhow::anyhow!("{e}"))?;
        let req = jobfile::request(spec);
        println!("── {origin}: job {}", req.job_id);
        let pb = progress(false);
        let outcome = station::submit(&services.bus, &req, &opts, |ev| {
            pb.suspend(|| println!("   {}", station::describe(ev)));
        })
        .await?;
        pb.finish_and_clear();
        match outcome {
            Outcome::Delivered(r) => {
                println!(
                    "   delivered to {} as {} (sha256 {})\n",
                    r.machine, r.path, r.sha256
                );
                let text = std::fs::read_to_string(&r.path)
                    .with_context(|| format!("reading back {}", r.path))?;
                println!("{text}");
            }
            other => {
                all_ok = false;
                println!("   NOT delivered: {other:?}\n");
            }
        }
    }
    for (origin, text) in DEMO_INVALID {
        let code = expected_code(text).unwrap_or("an error");
        let spec = match jobfile::parse(text, origin) {
            Ok(spec) => spec,
            Err(e) => {
                print!(
                    "── {origin}: refused at the station\n{}",
                    check::format_errors(&[e])
                );
                continue;
            }
        };
        let req = jobfile::request(spec);
        println!(
            "── {origin}: job {} (invalid on purpose: expect {code})",
            req.job_id
        );
        match station::submit(&services.bus, &req, &opts, |_| {}).await? {
            Outcome::Failed(errors) => {
                print!("{}", check::format_errors(&errors));
                if !errors.iter().any(|e| e.code == code) {
                    all_ok = false;
                    println!("   expected the refusal to name {code}");
                }
            }
            other => {
                all_ok = false;
                println!("   expected a refusal, got {other:?}");
            }
        }
    }
    services.stop().await;
    println!(
        "\ngearcam demo: {}",
        if all_ok {
            "every example delivered, every invalid one refused with its named error"
        } else {
            "FAILED"
        }
    );
    Ok(if all_ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

async fn submit(
    job: &Path,
    bus_args: &BusArgs,
    wait: bool,
    json: bool,
    timeout: u64,
) -> anyhow::Result<ExitCode> {
    let spec = match jobfile::load(job) {
        Ok(s) => s,
        Err(e) => {
            if json {
                println!(
                    "{}",
                    json!({"job": null, "state": "rejected", "errors": [e]})
                );
            } else {
                eprintln!("gearcam: job file refused\n{}", check::format_errors(&[e]));
            }
            return Ok(ExitCode::FAILURE);
        }
    };
    let req = jobfile::request(spec);
    let config = client_config(bus_args);
    let bus = match Bus::open(&config).await {
        Ok(bus) => bus,
        Err(e) => {
            let message = format!(
                "cannot join the bus at {}: {e}; is `gearcam up` (or a router) running there?",
                config.connect.join(", ")
            );
            if json {
                println!(
                    "{}",
                    json!({"job": req.job_id, "state": "unreachable", "message": message})
                );
            } else {
                eprintln!("gearcam: {message}");
            }
            return Ok(ExitCode::from(2));
        }
    };
    let opts = SubmitOptions {
        wait,
        alive_timeout: Duration::from_secs(timeout.min(30)),
        timeout: Duration::from_secs(timeout),
    };
    let pb = progress(json);
    pb.set_message(format!("job {}", req.job_id));
    let outcome = station::submit(&bus, &req, &opts, |ev| {
        if !json {
            pb.suspend(|| eprintln!("{}", station::describe(ev)));
        }
    })
    .await;
    pb.finish_and_clear();
    bus.close().await;
    let outcome = match outcome {
        Ok(o) => o,
        Err(e) => {
            if json {
                println!(
                    "{}",
                    json!({"job": req.job_id, "state": "unreachable", "message": e.to_string()})
                );
            } else {
                eprintln!("gearcam: {e}");
            }
            return Ok(ExitCode::from(2));
        }
    };
    let (value, code) = match &outcome {
        Outcome::Submitted(s) => (serde_json::to_value(s)?, ExitCode::SUCCESS),
        Outcome::Delivered(r) => (
            json!({"job": r.job_id, "state": "delivered", "program": {"name": r.name, "sha256": r.sha256, "path": r.path}, "receipt": r}),
            ExitCode::SUCCESS,
        ),
        Outcome::Failed(errors) => (
            json!({"job": req.job_id, "state": "failed", "errors": errors}),
            ExitCode::FAILURE,
        ),
        Outcome::TimedOut(s) => (serde_json::to_value(s)?, ExitCode::from(2)),
    };
    if json {
        println!("{value}");
    } else {
        match &outcome {
            Outcome::Submitted(s) => println!("job {} journaled by the station ({})", s.job, s.state.as_str()),
            Outcome::Delivered(r) => println!("job {} delivered: {} (sha256 {})", r.job_id, r.path, r.sha256),
            Outcome::Failed(errors) => {
                eprintln!("job {} refused with {} error(s):\n{}", req.job_id, errors.len(), check::format_errors(errors))
            }
            Outcome::TimedOut(s) => eprintln!(
                "job {}: not finished within {timeout} s; it stays journaled and the station keeps driving it\n  {}",
                s.job,
                station::describe_status(s)
            ),
        }
    }
    Ok(code)
}

/// Joins the bus as a client ([`client_config`]).
async fn join_bus(bus_args: &BusArgs) -> anyhow::Result<Bus> {
    Bus::open(&client_config(bus_args))
        .await
        .context("joining the bus")
}

/// A client configuration: the given endpoints, or the local `gearcam up`.
fn client_config(bus_args: &BusArgs) -> BusConfig {
    let mut config = bus_args.to_config();
    if config.connect.is_empty() && config.config_file.is_none() {
        config.connect = vec![DEFAULT_ENDPOINT.to_string()];
    }
    if config.config_file.is_none() {
        config.mode.get_or_insert(Mode::Client);
        config.multicast_scouting.get_or_insert(false);
    }
    config
}

async fn station_cmd(
    journal: PathBuf,
    redrive_ms: u64,
    bus_args: &BusArgs,
) -> anyhow::Result<ExitCode> {
    let mut config = bus_args.to_config();
    if config.config_file.is_none() && config.connect.is_empty() && config.listen.is_empty() {
        config = client_config(bus_args);
    }
    let bus = Bus::open(&config).await.context("joining the bus")?;
    let cfg = gearcam_station::StationConfig {
        journal,
        redrive: Duration::from_millis(redrive_ms),
    };
    gearcam_station::run(bus, cfg, cancel_on_signal()).await?;
    Ok(ExitCode::SUCCESS)
}

async fn jobs_cmd(bus_args: &BusArgs, json: bool) -> anyhow::Result<ExitCode> {
    let bus = join_bus(bus_args).await?;
    let list = station::jobs(&bus).await;
    bus.close().await;
    let jobs = match list.context("asking the station")? {
        Ok(jobs) => jobs,
        Err(errors) => return Ok(refused(&errors)),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&jobs)?);
    } else {
        for s in &jobs {
            println!("{}", station::describe_status(s));
        }
        println!("{} job(s)", jobs.len());
    }
    Ok(ExitCode::SUCCESS)
}

async fn status_cmd(job: &JobId, bus_args: &BusArgs, json: bool) -> anyhow::Result<ExitCode> {
    let bus = join_bus(bus_args).await?;
    let status = station::status(&bus, job).await;
    bus.close().await;
    let status = match status.context("asking the station")? {
        Ok(status) => status,
        Err(errors) => return Ok(refused(&errors)),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&status)?);
    } else {
        println!("{}", station::describe_status(&status));
        print!("{}", check::format_errors(&status.errors));
    }
    Ok(ExitCode::SUCCESS)
}

/// Prints a service's typed refusal; exit code 1.
fn refused(errors: &[gearcam_proto::JobError]) -> ExitCode {
    eprint!("{}", check::format_errors(errors));
    ExitCode::FAILURE
}

async fn program_cmd(action: ProgramAction) -> anyhow::Result<ExitCode> {
    match action {
        ProgramAction::History {
            machine,
            name,
            bus,
            json,
        } => {
            let bus = join_bus(&bus).await?;
            let h = store::history(&bus, &machine, name.as_deref()).await;
            bus.close().await;
            let h = match h.context(format!("asking the agent of {machine}"))? {
                Ok(h) => h,
                Err(error) => return Ok(refused(&[error])),
            };
            if json {
                println!("{}", serde_json::to_string_pretty(&h)?);
            } else {
                for v in &h.versions {
                    println!(
                        "{:>6} {} {:<24} {:<10} job {} rev {} sha256 {} {} bytes",
                        v.seq,
                        if v.current { "*" } else { " " },
                        v.name,
                        v.state,
                        v.job,
                        v.revision,
                        &v.sha256[..12.min(v.sha256.len())],
                        v.size_bytes
                    );
                }
            }
            Ok(ExitCode::SUCCESS)
        }
        ProgramAction::Show {
            machine,
            name,
            seq,
            bus,
        } => {
            let bus = join_bus(&bus).await?;
            let t = store::version(&bus, &machine, &name, seq).await;
            bus.close().await;
            match t.context(format!("asking the agent of {machine}"))? {
                Ok(t) => {
                    print!("{}", t.text);
                    Ok(ExitCode::SUCCESS)
                }
                Err(error) => Ok(refused(&[error])),
            }
        }
        ProgramAction::Rollback {
            machine,
            name,
            seq,
            bus,
        } => {
            let bus = join_bus(&bus).await?;
            let r = store::rollback(&bus, &machine, &name, seq).await;
            bus.close().await;
            match r.context(format!("asking the agent of {machine}"))? {
                Ok(receipt) => {
                    println!(
                        "{} is version {seq} again: {} (sha256 {})",
                        name, receipt.path, receipt.sha256
                    );
                    Ok(ExitCode::SUCCESS)
                }
                Err(error) => Ok(refused(&[error])),
            }
        }
    }
}

/// The template library of the data directory (`templates.db`), with the
/// shipped standard code imported where it is newer.
fn template_library(data: &Path) -> anyhow::Result<Templates> {
    Ok(Templates::from_library(
        &data.join("templates.db"),
        gearcam_template::DEFAULT_FUEL,
        gearcam_proto::now_ms(),
    )?)
}

fn check_cmd(job: &Path, json: bool, data: &Path) -> ExitCode {
    let report = match jobfile::load(job) {
        Err(e) => CheckReport::failed(vec![e]),
        Ok(spec) => {
            let req = jobfile::request(spec);
            match gearcam_knowledge::db::open(&data.join("knowledge.db")) {
                Ok(conn) => match template_library(data) {
                    Ok(templates) => check::check(&conn, &templates, &req),
                    Err(e) => check::CheckReport::failed(vec![gearcam_proto::JobError {
                        stage: gearcam_proto::Stage::Template,
                        code: "TEMPLATE_LIBRARY_UNREADABLE".into(),
                        field: "data".into(),
                        expected: "a readable template library (templates.db)".into(),
                        got: data.join("templates.db").display().to_string(),
                        message: format!("{e:#}"),
                    }]),
                },
                Err(e) => {
                    eprintln!(
                        "gearcam: cannot open the knowledge base in {}: {e}",
                        data.display()
                    );
                    return ExitCode::from(2);
                }
            }
        }
    };
    if json {
        match serde_json::to_string_pretty(&report) {
            Ok(s) => println!("{s}"),
            Err(e) => {
                eprintln!("gearcam: cannot write JSON: {e}");
                return ExitCode::from(2);
            }
        }
    } else {
        print!("{}", check::format_human(&report));
    }
    if report.ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

async fn router(bus_args: &BusArgs) -> anyhow::Result<ExitCode> {
    let mut config = bus_args.to_config();
    if config.config_file.is_none() {
        config.mode = Some(Mode::Router);
        config.multicast_scouting.get_or_insert(false);
    }
    let bus = Bus::open(&config).await.context("starting the router")?;
    println!("gearcam router: listening on {}", config.listen.join(", "));
    cancel_on_signal().cancelled().await;
    bus.close().await;
    Ok(ExitCode::SUCCESS)
}
