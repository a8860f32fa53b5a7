//! `gearcam-template`: the template service as its own process.

use std::path::PathBuf;

use clap::Parser;
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs};
use gearcam_template::simulation::Mode;
use gearcam_template::{source, Templates, DEFAULT_FUEL};

/// The gearcam template service.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    #[command(flatten)]
    bus: BusArgs,
    /// The template library (SQLite; created and filled with the shipped
    /// standard code if missing). `gearcam templates import` adds versions.
    #[arg(long, default_value = "gearcam-data/templates.db")]
    library: PathBuf,
    /// A directory of template source files (`*.tpl`) used instead of the
    /// library's templates of the same id, without storing them (for trying a
    /// template before importing it).
    #[arg(long)]
    templates: Option<PathBuf>,
    /// How every hobbing program is run on the virtual machine before it
    /// is delivered: fine (9 sections, 1 µm), coarse (about 10 µm) or off.
    #[arg(long, value_enum, default_value = "fine")]
    simulation: Mode,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    init_tracing("gearcam_template=info,gearcam_bus=info");
    let args = Args::parse();
    let library = Templates::from_library(&args.library, DEFAULT_FUEL, gearcam_proto::now_ms())?;
    let templates = match &args.templates {
        Some(dir) => library.with(source::read_dir(dir)?)?,
        None => library,
    }
    .with_simulation(args.simulation.settings());
    for t in templates.list() {
        tracing::info!(template = %t.id, version = t.version, "compiled");
    }
    let bus = Bus::open(&args.bus.to_config()).await?;
    gearcam_template::service::run(bus, templates, cancel_on_signal()).await?;
    Ok(())
}
