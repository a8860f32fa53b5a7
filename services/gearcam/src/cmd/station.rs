//! `gearcam station`: the planning station as its own process.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use gearcam_bus::{cancel_on_signal, Bus, BusArgs};

use crate::bus_config;

pub async fn station(
    journal: PathBuf,
    redrive_ms: u64,
    bus_args: &BusArgs,
) -> anyhow::Result<ExitCode> {
    let config = bus_config::service(bus_args);
    let bus = Bus::open(&config).await.context("joining the bus")?;
    let cfg = gearcam_station::StationConfig {
        journal,
        redrive: Duration::from_millis(redrive_ms),
    };
    gearcam_station::run(bus, cfg, cancel_on_signal()).await?;
    Ok(ExitCode::SUCCESS)
}
