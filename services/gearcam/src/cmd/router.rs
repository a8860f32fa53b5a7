//! `gearcam router`: a Zenoh router for a shop network without zenohd, and for tests.

use std::process::ExitCode;

use anyhow::Context;
use gearcam_bus::{cancel_on_signal, Bus, BusArgs};

use crate::bus_config;

pub async fn router(bus_args: &BusArgs) -> anyhow::Result<ExitCode> {
    let config = bus_config::router(bus_args);
    let bus = Bus::open(&config).await.context("starting the router")?;
    crate::outln!("gearcam router: listening on {}", config.listen.join(", "));
    cancel_on_signal().cancelled().await;
    bus.close().await;
    Ok(ExitCode::SUCCESS)
}
