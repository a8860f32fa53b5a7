//! `gearcam program history|show|rollback`: a machine's program store.

use std::process::ExitCode;

use crate::bus_config::ClientArgs;
use anyhow::Context;
use clap::Subcommand;
use gearcam_proto::MachineId;

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
        bus: ClientArgs,
    },
}

pub async fn program(action: ProgramAction) -> anyhow::Result<ExitCode> {
    match action {
        ProgramAction::History {
            machine,
            name,
            bus,
            json,
        } => {
            let bus = join_bus(&bus.bus_args()).await?;
            let h = store::history(&bus, &machine, name.as_deref()).await;
            bus.close().await;
            let h = match h.context(format!("asking the agent of {machine}"))? {
                Ok(h) => h,
                Err(error) => return Ok(refused(&[error])),
            };
            if json {
                crate::outln!("{}", serde_json::to_string_pretty(&h)?);
            } else {
                for v in &h.versions {
                    crate::outln!(
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
            let bus = join_bus(&bus.bus_args()).await?;
            let t = store::version(&bus, &machine, &name, seq).await;
            bus.close().await;
            match t.context(format!("asking the agent of {machine}"))? {
                Ok(t) => {
                    crate::out!("{}", t.text);
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
            let bus = join_bus(&bus.bus_args()).await?;
            let r = store::rollback(&bus, &machine, &name, seq).await;
            bus.close().await;
            match r.context(format!("asking the agent of {machine}"))? {
                Ok(receipt) => {
                    crate::outln!(
                        "{} is version {seq} again: {} (sha256 {})",
                        name,
                        receipt.path,
                        receipt.sha256
                    );
                    Ok(ExitCode::SUCCESS)
                }
                Err(error) => Ok(refused(&[error])),
            }
        }
    }
}
