//! `gearcam web`: the planning office's page ([`crate::web`]) on the bus.

use std::net::SocketAddr;
use std::process::ExitCode;

use gearcam_bus::{cancel_on_signal, BusArgs};

use crate::cmd::join_bus;

pub async fn web(listen: SocketAddr, bus_args: &BusArgs) -> anyhow::Result<ExitCode> {
    let bus = join_bus(bus_args).await?;
    let served = crate::web::serve(bus.clone(), listen, cancel_on_signal()).await;
    bus.close().await;
    served?;
    Ok(ExitCode::SUCCESS)
}
