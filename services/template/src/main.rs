//! `gearcam-template`: the template service as its own process.

use std::path::PathBuf;

use clap::Parser;
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs};
use gearcam_template::{source, Templates, DEFAULT_FUEL};

/// The gearcam template service.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    #[command(flatten)]
    bus: BusArgs,
    /// Extra template directory (`*.j2`); a template there replaces the built-in one of the same id.
    #[arg(long)]
    templates: Option<PathBuf>,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    init_tracing("gearcam_template=info,gearcam_bus=info");
    let args = Args::parse();
    let templates = match &args.templates {
        Some(dir) => Templates::new(source::read_dir(dir)?, DEFAULT_FUEL)?,
        None => Templates::builtin(),
    };
    let bus = Bus::open(&args.bus.to_config()).await?;
    gearcam_template::service::run(bus, templates, cancel_on_signal()).await?;
    Ok(())
}
