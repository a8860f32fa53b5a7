//! `gearcam program history|show|rollback|resolve`: a machine's program store.

use std::process::ExitCode;

use crate::bus_config::ClientArgs;
use anyhow::Context;
use clap::Subcommand;
use gearcam_proto::{DeliveryReceipt, JobId, MachineId, StoreRequest};

use crate::cmd::{join_bus, refused};
use crate::store;

/// `gearcam program …`: what to do with a machine's stored programs.
#[derive(Debug, Subcommand)]
pub enum ProgramAction {
    /// Every stored version (of one program, if named), newest first.
    History {
        /// The machine, e.g. H01.
        #[arg(long)]
        machine: MachineId,
        /// Program name, e.g. SP_1001.
        name: Option<String>,
        #[command(flatten)]
        bus: ClientArgs,
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
        bus: ClientArgs,
        /// Print the version and its text as JSON.
        #[arg(long)]
        json: bool,
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
        /// Who rolls it back (default: the login name, else `unknown`). With
        /// a configuration that logs in, it is the login, and --by may only
        /// repeat it.
        #[arg(long)]
        by: Option<String>,
        #[command(flatten)]
        bus: ClientArgs,
        /// Print the receipt of the version now current as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Resolve a program changed at the machine, after review: adopt the edit or replace it.
    ///
    /// A delivery to a program changed at the machine is refused
    /// (PROGRAM_CHANGED_AT_MACHINE) and its job waits. Either way the edit is
    /// kept in the history with who and when. --adopt is final: the jobs that
    /// waited to replace the edit end superseded and are never delivered over
    /// it (submit again for gearcam's program); after --replace they are
    /// delivered at their next re-drive.
    #[command(group(
        clap::ArgGroup::new("decision")
            .required(true)
            .args(["adopt", "replace"])
    ))]
    Resolve {
        /// The machine, e.g. H01.
        #[arg(long)]
        machine: MachineId,
        /// Program name, e.g. SP_1001.
        name: String,
        /// Decision: the edit at the machine becomes the current version (one of --adopt, --replace).
        #[arg(long)]
        adopt: bool,
        /// Decision: gearcam's current version is written back; the edit stays in the history.
        #[arg(long)]
        replace: bool,
        /// Who reviewed the edit (default: the login name, else `unknown`).
        /// With a configuration that logs in, it is the login, and --by may
        /// only repeat it.
        #[arg(long)]
        by: Option<String>,
        #[command(flatten)]
        bus: ClientArgs,
        /// Print the receipt of the version now current as JSON.
        #[arg(long)]
        json: bool,
    },
}

impl ProgramAction {
    /// True with `--json`.
    pub fn json(&self) -> bool {
        match self {
            ProgramAction::History { json, .. }
            | ProgramAction::Show { json, .. }
            | ProgramAction::Rollback { json, .. }
            | ProgramAction::Resolve { json, .. } => *json,
        }
    }
}

/// Runs `gearcam program …`: each action asks the machine's agent over the
/// bus and prints its answer, or its refusal.
pub async fn program(action: ProgramAction) -> anyhow::Result<ExitCode> {
    match action {
        ProgramAction::History {
            machine,
            name,
            bus,
            json,
        } => history(&machine, name.as_deref(), &bus, json).await,
        ProgramAction::Show {
            machine,
            name,
            seq,
            bus,
            json,
        } => show(&machine, &name, seq, &bus, json).await,
        ProgramAction::Rollback {
            machine,
            name,
            seq,
            by,
            bus,
            json,
        } => rollback(&machine, &name, seq, by, &bus, json).await,
        ProgramAction::Resolve {
            machine,
            name,
            adopt,
            replace: _,
            by,
            bus,
            json,
        } => resolve(&machine, &name, adopt, by, &bus, json).await,
    }
}

/// `gearcam program history`: every stored version (of one program, if
/// named), newest first, as a table or JSON.
async fn history(
    machine: &MachineId,
    name: Option<&str>,
    bus: &ClientArgs,
    json: bool,
) -> anyhow::Result<ExitCode> {
    let bus = join_bus(&bus.bus_args()).await?;
    let h = store::history(&bus, machine, name).await;
    bus.close().await;
    let h = match h.context(format!("asking the agent of {machine}"))? {
        Ok(h) => h,
        Err(error) => return Ok(refused(&[error])),
    };
    if json {
        return print_json(&h);
    }
    crate::out!("{}", history_table(&h));
    Ok(ExitCode::SUCCESS)
}

/// `gearcam program show`: one stored version's text (with the version, as
/// JSON).
async fn show(
    machine: &MachineId,
    name: &str,
    seq: u64,
    bus: &ClientArgs,
    json: bool,
) -> anyhow::Result<ExitCode> {
    let bus = join_bus(&bus.bus_args()).await?;
    let t = store::version(&bus, machine, name, seq).await;
    bus.close().await;
    match t.context(format!("asking the agent of {machine}"))? {
        Ok(t) if json => print_json(&t),
        Ok(t) => {
            crate::out!("{}", t.text);
            Ok(ExitCode::SUCCESS)
        }
        Err(error) => Ok(refused(&[error])),
    }
}

/// `gearcam program rollback`: makes version `seq` current again, by the
/// login (`--by` may only repeat it); prints the new receipt.
async fn rollback(
    machine: &MachineId,
    name: &str,
    seq: u64,
    by: Option<String>,
    bus: &ClientArgs,
    json: bool,
) -> anyhow::Result<ExitCode> {
    let changed = change_as(machine, name, by, bus, |by| StoreRequest::Rollback {
        seq,
        by,
    })
    .await?;
    match changed {
        Ok((receipt, _)) if json => print_json(&receipt),
        Ok((receipt, _)) => {
            crate::outln!(
                "{} is version {seq} again: {} (sha256 {})",
                name,
                receipt.path,
                receipt.sha256
            );
            Ok(ExitCode::SUCCESS)
        }
        Err(code) => Ok(code),
    }
}

/// Sends the change `request` (made with the login) of program `name` to the
/// store of `machine`: the receipt and the jobs superseded, or the exit code
/// when the login cannot be had (`--by` other than it) or the agent refuses.
async fn change_as(
    machine: &MachineId,
    name: &str,
    by: Option<String>,
    bus: &ClientArgs,
    request: impl FnOnce(String) -> StoreRequest,
) -> anyhow::Result<Result<(DeliveryReceipt, Vec<JobId>), ExitCode>> {
    let by = match crate::jobfile::who(&bus.bus_args(), by) {
        Ok(by) => by,
        Err(code) => return Ok(Err(code)),
    };
    let bus = join_bus(&bus.bus_args()).await?;
    let r = store::change(&bus, machine, name, &request(by)).await;
    bus.close().await;
    Ok(r.context(format!("asking the agent of {machine}"))?
        .map_err(|error| refused(&[error])))
}

/// `gearcam program resolve`: adopts the edit at the machine (`adopt`) or
/// writes gearcam's version back, by the login; prints the version now
/// current and what becomes of the jobs that waited.
async fn resolve(
    machine: &MachineId,
    name: &str,
    adopt: bool,
    by: Option<String>,
    bus: &ClientArgs,
    json: bool,
) -> anyhow::Result<ExitCode> {
    let changed = change_as(machine, name, by, bus, |by| {
        if adopt {
            StoreRequest::Adopt { by }
        } else {
            StoreRequest::Replace { by }
        }
    })
    .await?;
    match changed {
        Ok((receipt, superseded)) if json => {
            let mut v = serde_json::to_value(&receipt)?;
            v["superseded"] = serde_json::to_value(&superseded)?;
            print_json(&v)
        }
        Ok((receipt, superseded)) => {
            print_resolved(machine, name, adopt, &receipt, &superseded);
            Ok(ExitCode::SUCCESS)
        }
        Err(code) => Ok(code),
    }
}

/// A resolution for a person: which version is now current, and whether
/// the jobs that waited are delivered (a replacement) or ended superseded
/// (an adoption).
fn print_resolved(
    machine: &MachineId,
    name: &str,
    adopt: bool,
    receipt: &DeliveryReceipt,
    superseded: &[JobId],
) {
    let what = if adopt {
        "the edit at the machine is now the current version"
    } else {
        "gearcam's version is back at the machine; the edit is kept in the history"
    };
    crate::outln!(
        "{name} at {machine}: {what}: {} (sha256 {})",
        receipt.path,
        receipt.sha256
    );
    if !adopt {
        crate::outln!(
            "jobs waiting on this program are delivered at their next re-drive (gearcam jobs)"
        );
    } else if superseded.is_empty() {
        crate::outln!("no job was waiting to replace it");
    } else {
        let jobs: Vec<&str> = superseded.iter().map(JobId::as_str).collect();
        crate::outln!(
            "{} job(s) that waited to replace it end superseded and are never delivered over it: {}; submit again for gearcam's program",
            jobs.len(),
            jobs.join(", ")
        );
    }
}

/// A machine's program history as a table for a person: a header, one line
/// per version (newest first), the current one marked `*`, dates in UTC.
pub fn history_table(h: &gearcam_proto::ProgramHistory) -> String {
    let mut out = format!(
        "{:>6}  {:<3} {:<24} {:<20} {:<12} {:<23} {:<36} {:>3}  {:<12} {:>8}  {}\n",
        "SEQ", "CUR", "NAME", "PART", "STATE", "STORED", "JOB", "REV", "SHA256", "BYTES", "BY"
    );
    for v in &h.versions {
        out.push_str(&format!(
            "{:>6}  {:<3} {:<24} {:<20} {:<12} {:<23} {:<36} {:>3}  {:<12} {:>8}  {}\n",
            v.seq,
            if v.current { "*" } else { "" },
            v.name,
            v.part_number,
            v.state,
            crate::output::utc(v.stored_at_ms),
            v.job,
            v.revision,
            &v.sha256[..12.min(v.sha256.len())],
            v.size_bytes,
            v.by
        ));
    }
    if h.versions.is_empty() {
        out.push_str(&format!("(no programs stored for {})\n", h.machine));
    }
    out
}

/// Prints `value` as JSON; done.
fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<ExitCode> {
    crate::outln!("{}", serde_json::to_string_pretty(value)?);
    Ok(ExitCode::SUCCESS)
}
