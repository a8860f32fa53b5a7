//! `gearcam program history|show|rollback`: a machine's program store.

use std::process::ExitCode;

use anyhow::Context;

use crate::cli::ProgramAction;
use crate::cmd::{join_bus, refused};
use crate::store;

pub async fn program(action: ProgramAction) -> anyhow::Result<ExitCode> {
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
