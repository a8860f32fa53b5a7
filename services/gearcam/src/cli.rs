//! The `gearcam` command line: its arguments (clap) and the dispatch to one
//! module per command ([`crate::cmd`]).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use gearcam_bus::BusArgs;

use crate::bus_config::ClientArgs;
use gearcam_proto::JobId;

use crate::cmd::program::ProgramAction;
use crate::cmd::{self, kb, templates};

/// gearcam: from a gear drawing to a proven NC program in the machine's program store.
#[derive(Debug, Parser)]
#[command(version, about, after_help = crate::exit::HELP)]
pub struct Cli {
    /// Show the bus's own log lines too (-v warnings, -vv information,
    /// -vvv debugging; `RUST_LOG` overrides).
    #[arg(short, long, global = true, action = clap::ArgAction::Count)]
    pub verbose: u8,
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run every service and one agent per configured machine in this process.
    Up {
        /// Data directory (knowledge base, machines' program stores).
        #[arg(long, env = "GEARCAM_DATA", default_value = "gearcam-data")]
        data: PathBuf,
        /// Where the web page listens (any free port when this one is taken; the address is printed).
        #[arg(long, default_value = "127.0.0.1:8080")]
        web: std::net::SocketAddr,
        #[command(flatten)]
        bus: BusArgs,
    },
    /// Start what `up` starts, submit the bundled example jobs, show the programs, stop.
    Demo {
        /// Data directory (knowledge base, machines' program stores).
        #[arg(long, env = "GEARCAM_DATA", default_value = "gearcam-data")]
        data: PathBuf,
        /// Where the web page listens during the demo (any free port when this one is taken).
        #[arg(long, default_value = "127.0.0.1:8080")]
        web: std::net::SocketAddr,
        /// After the examples, keep the services and the web page running until Ctrl-C.
        #[arg(long)]
        serve: bool,
    },
    /// Submit a job file over the bus.
    Submit {
        /// The job file (TOML; see examples/).
        job: PathBuf,
        #[command(flatten)]
        bus: ClientArgs,
        /// Follow the job until the program is delivered (exit 0) or refused (exit 1).
        #[arg(long)]
        wait: bool,
        /// Print the outcome as JSON.
        #[arg(long)]
        json: bool,
        /// Seconds to wait for the outcome (with --wait) and for the services.
        #[arg(long, default_value_t = 60)]
        timeout: u64,
        /// The job's id (default: the file's `[job] id`, or a new one). The
        /// same id with the same job file is a resubmission: the station
        /// reports the job's real state and never makes a second job, so a
        /// submit that ended unreachable (exit 2) is retried safely with the
        /// id it printed.
        #[arg(long)]
        id: Option<gearcam_proto::JobId>,
    },
    /// Compute the job locally (no bus) and print the result and the program.
    Check {
        /// The job file (TOML; see examples/).
        job: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
        /// Data directory holding the knowledge base (created and seeded if missing).
        #[arg(long, env = "GEARCAM_DATA", default_value = "gearcam-data")]
        data: PathBuf,
        /// Where to write the SVG picture of a spiral or wire job
        /// (default: DATA/pictures/JOBFILE.svg, JOBFILE the job file's name).
        #[arg(long)]
        svg: Option<PathBuf>,
        /// Where to write the DXF of a wire job's outline (lines and arcs,
        /// closed; default: the picture's path with `.dxf`).
        #[arg(long)]
        dxf: Option<PathBuf>,
        #[command(flatten)]
        what_if: WhatIf,
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
    /// Serve the planning office's page: the jobs of the station's journal,
    /// each job's state, errors, warnings and program (a client of the bus).
    Web {
        /// Address to listen on (port 0: any free port; the address is printed).
        #[arg(long, default_value = "127.0.0.1:8080")]
        listen: std::net::SocketAddr,
        /// The users file (`gearcam web-user` writes it; passwords as
        /// Argon2 hashes; default DATA/web-users.toml).
        #[arg(long, env = "GEARCAM_WEB_USERS")]
        users: Option<PathBuf>,
        /// Data directory whose knowledge base and templates check a job
        /// while it is typed (as `gearcam check`; the job is submitted over the bus).
        #[arg(long, env = "GEARCAM_DATA", default_value = "gearcam-data")]
        data: PathBuf,
        #[command(flatten)]
        bus: ClientArgs,
    },
    /// Add a user of the web page or set their password (read from standard input).
    WebUser {
        /// The sign-in name (also the author the bus records for their changes).
        name: String,
        /// planner, operator, admin or supervisor.
        #[arg(long)]
        role: String,
        /// A machine an operator may change programs of (repeatable).
        #[arg(long = "machine")]
        machines: Vec<gearcam_proto::MachineId>,
        /// The users file (default DATA/web-users.toml).
        #[arg(long, env = "GEARCAM_WEB_USERS")]
        users: Option<PathBuf>,
        /// Data directory.
        #[arg(long, env = "GEARCAM_DATA", default_value = "gearcam-data")]
        data: PathBuf,
    },
    /// List every job in the station's journal.
    Jobs {
        #[command(flatten)]
        bus: ClientArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Show one job's state.
    Status {
        /// The job id.
        job: JobId,
        #[command(flatten)]
        bus: ClientArgs,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Cancel a journaled job that is not yet delivered: it ends `cancelled`
    /// (on the bus too, with who), and the machine's agent never stores its
    /// program after.
    Cancel {
        /// The job id.
        job: JobId,
        /// Who cancels it (default: the login name). With a configuration
        /// that logs in, it is the login, and --by may only repeat it.
        #[arg(long)]
        by: Option<String>,
        #[command(flatten)]
        bus: ClientArgs,
        /// Print the job's status as JSON.
        #[arg(long)]
        json: bool,
    },
    /// A machine's stored programs: history, show a version, roll back, resolve an edit at the machine.
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

/// Runs a parsed command; the exit code of its outcome.
pub async fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Up { data, web, bus } => cmd::up::up(&data, web, &bus).await,
        Command::Demo { data, web, serve } => cmd::demo::demo(&data, web, serve).await,
        Command::Submit {
            job,
            bus,
            wait,
            json,
            timeout,
            id,
        } => cmd::submit::submit(&job, &bus.bus_args(), wait, json, timeout, id).await,
        Command::Check {
            job,
            json,
            data,
            svg,
            dxf,
            what_if,
        } => Ok(cmd::check::check(
            &job,
            json,
            &data,
            what_if.settings().as_ref(),
            svg.as_deref(),
            dxf.as_deref(),
        )),
        Command::Router { bus } => cmd::router::router(&bus).await,
        Command::Kb(args) => Ok(kb::run(args)),
        Command::Confirm(args) => Ok(kb::confirm(args)),
        Command::Templates(args) => Ok(templates::run(args)),
        Command::Station {
            journal,
            redrive_ms,
            bus,
        } => cmd::station::station(journal, redrive_ms, &bus).await,
        Command::Web {
            listen,
            users,
            data,
            bus,
        } => {
            let users = users.unwrap_or_else(|| data.join(cmd::web::USERS_FILE));
            cmd::web::web(listen, &users, &data, &bus.bus_args()).await
        }
        Command::WebUser {
            name,
            role,
            machines,
            users,
            data,
        } => {
            let users = users.unwrap_or_else(|| data.join(cmd::web::USERS_FILE));
            Ok(cmd::web::web_user(&users, &name, &role, machines))
        }
        Command::Jobs { bus, json } => cmd::jobs::jobs(&bus.bus_args(), json).await,
        Command::Status { job, bus, json } => cmd::jobs::status(&job, &bus.bus_args(), json).await,
        Command::Cancel { job, by, bus, json } => {
            let bus = bus.bus_args();
            match crate::jobfile::who(&bus, by) {
                Ok(by) => cmd::jobs::cancel(&job, &by, &bus, json).await,
                Err(code) => Ok(code),
            }
        }
        Command::Program { action } => cmd::program::program(action).await,
    }
}

impl Cli {
    /// True when the command prints JSON (`--json`): its failures are JSON too.
    pub fn json(&self) -> bool {
        match &self.command {
            Command::Submit { json, .. }
            | Command::Check { json, .. }
            | Command::Jobs { json, .. }
            | Command::Status { json, .. }
            | Command::Cancel { json, .. } => *json,
            Command::Program { action } => action.json(),
            Command::Kb(args) => args.json,
            Command::Confirm(args) => args.json,
            Command::Templates(args) => args.json,
            Command::Up { .. }
            | Command::Demo { .. }
            | Command::Station { .. }
            | Command::Web { .. }
            | Command::WebUser { .. }
            | Command::Router { .. } => false,
        }
    }

    /// The log filter: the long-running commands (`up`, `station`,
    /// `router`) log warnings; a client command says what a person needs on
    /// its own, so the bus's log lines are shown only when asked (`-v`).
    pub fn log_filter(&self) -> &'static str {
        let serving = matches!(
            self.command,
            Command::Up { .. }
                | Command::Station { .. }
                | Command::Router { .. }
                | Command::Web { .. }
        );
        match (self.verbose, serving) {
            (0, false) => "off",
            (0, true) | (1, _) => "warn",
            (2, _) => "info",
            _ => "debug",
        }
    }
}

/// How `gearcam check` runs a hobbing program on the virtual machine: the
/// errors a shop knows of its machine and hob (all zero: the ideal
/// machine), and how finely.
#[derive(Debug, Clone, clap::Args)]
pub struct WhatIf {
    /// Centre-distance offset of the machine, mm (added to X).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub centre_distance_offset: f64,
    /// Swivel offset of the hob head, degrees.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub swivel_offset: f64,
    /// Radial runout of the mounted hob, mm.
    #[arg(long, default_value_t = 0.0)]
    pub hob_radial_runout: f64,
    /// Axial runout of the mounted hob, mm.
    #[arg(long, default_value_t = 0.0)]
    pub hob_axial_runout: f64,
    /// Runout of the workpiece on the table, mm.
    #[arg(long, default_value_t = 0.0)]
    pub table_runout: f64,
    /// Run a hobbing program on the virtual machine: the gear it cuts,
    /// measured and graded by ISO 1328-1:2013, and the run's safety findings
    /// (the fine run takes seconds; `--coarse` about half as long).
    #[arg(long)]
    pub simulate: bool,
    /// A quick look (outline within about 10 µm) instead of the fine run.
    #[arg(long, requires = "simulate")]
    pub coarse: bool,
}

impl WhatIf {
    /// The simulation settings, when asked to simulate.
    pub fn settings(&self) -> Option<gearcam_hobsim::simulate::Settings> {
        use gearcam_hobsim::simulate::Settings;
        if !self.simulate {
            return None;
        }
        let mut s = if self.coarse {
            Settings::coarse()
        } else {
            Settings::fine()
        };
        s.errors.centre_distance_mm = self.centre_distance_offset;
        s.errors.swivel_deg = self.swivel_offset;
        s.errors.hob_radial_mm = self.hob_radial_runout;
        s.errors.hob_axial_mm = self.hob_axial_runout;
        s.errors.table_mm = self.table_runout;
        Some(s)
    }
}
