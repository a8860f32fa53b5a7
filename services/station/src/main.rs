//! `gearcam-station`: the planning station as its own process (the same as
//! `gearcam station`).

use std::path::PathBuf;
use std::time::Duration;

use clap::Parser;
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs};
use gearcam_station::StationConfig;

/// The gearcam planning station: the durable job journal that drives every
/// job to its receipt.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    #[command(flatten)]
    bus: BusArgs,
    /// The job journal (SQLite).
    #[arg(long, default_value = "gearcam-data/station.db")]
    journal: PathBuf,
    /// Re-drive a job after this many milliseconds without progress (then with backoff).
    #[arg(long, default_value_t = 5000)]
    redrive_ms: u64,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    init_tracing("gearcam_station=info,gearcam_bus=info");
    let args = Args::parse();
    let bus = Bus::open(&args.bus.to_config()).await?;
    let config = StationConfig {
        journal: args.journal,
        redrive: Duration::from_millis(args.redrive_ms),
    };
    gearcam_station::run(bus, config, cancel_on_signal()).await?;
    Ok(())
}
