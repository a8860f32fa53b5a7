//! `gearcam-knowledge`: the knowledge service as its own process.

use std::path::PathBuf;

use clap::Parser;
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs};
use gearcam_knowledge::service::{run, Config};

/// The gearcam knowledge service.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    #[command(flatten)]
    bus: BusArgs,
    /// SQLite knowledge base (created and seeded if missing).
    #[arg(long, default_value = "gearcam-data/knowledge.db")]
    db: PathBuf,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    init_tracing("gearcam_knowledge=info,gearcam_bus=info");
    let args = Args::parse();
    let bus = Bus::open(&args.bus.to_config()).await?;
    run(bus, Config { db_path: args.db }, cancel_on_signal()).await?;
    Ok(())
}
