//! `gearcam-model`: the model service as its own process.

use clap::Parser;
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs};

/// The gearcam model service.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    #[command(flatten)]
    bus: BusArgs,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    init_tracing("gearcam_model=info,gearcam_bus=info");
    let args = Args::parse();
    let bus = Bus::open(&args.bus.to_config()).await?;
    gearcam_model::service::run(bus, cancel_on_signal()).await?;
    Ok(())
}
