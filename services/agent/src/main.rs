//! `gearcam-agent`: the delivery agent of one machine as its own process.

use std::path::PathBuf;

use clap::Parser;
use gearcam_agent::service::run;
use gearcam_agent::store::{Faults, StoreConfig};
use gearcam_bus::{cancel_on_signal, init_tracing, Bus, BusArgs};
use gearcam_proto::{Dialect, MachineId};

/// Controller dialects an agent can store for.
#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum DialectArg {
    Sinumerik840d,
    Fanuc,
    Linuxcnc,
    Wire3b,
    Wireiso,
}

/// The gearcam delivery agent of one machine.
#[derive(Debug, Parser)]
#[command(version, about)]
struct Args {
    #[command(flatten)]
    bus: BusArgs,
    /// The machine this agent serves, e.g. H01.
    #[arg(long)]
    machine: MachineId,
    /// The machine controller's dialect.
    #[arg(long, value_enum, default_value = "sinumerik840d")]
    dialect: DialectArg,
    /// Directory the controller reads programs from.
    #[arg(long)]
    program_dir: PathBuf,
    /// SQLite program index (default: index.db beside the program directory).
    #[arg(long)]
    index: Option<PathBuf>,
    /// Rebuild a lost (missing or emptied) program index from the program
    /// files and their headers, then exit; the lost index is kept beside.
    #[arg(long)]
    rebuild_index: bool,
    /// Fault injection for the fault tests: abort after renaming a program
    /// into place, before the index commit.
    #[arg(long, hide = true)]
    fault_crash_after_rename: bool,
    /// Fault injection for the fault tests: pause this many milliseconds
    /// between writing a program and renaming it into place.
    #[arg(long, hide = true, default_value_t = 0)]
    fault_pause_before_rename_ms: u64,
}

#[tokio::main(flavor = "multi_thread")]
async fn main() -> anyhow::Result<()> {
    init_tracing("gearcam_agent=info,gearcam_bus=info");
    let args = Args::parse();
    let index_path = args.index.clone().unwrap_or_else(|| {
        args.program_dir
            .parent()
            .map(|p| p.join("index.db"))
            .unwrap_or_else(|| "index.db".into())
    });
    let dialect = match args.dialect {
        DialectArg::Sinumerik840d => Dialect::Sinumerik840d,
        DialectArg::Fanuc => Dialect::Fanuc,
        DialectArg::Linuxcnc => Dialect::Linuxcnc,
        DialectArg::Wire3b => Dialect::Wire3b,
        DialectArg::Wireiso => Dialect::WireIso,
    };
    let config = StoreConfig {
        machine: args.machine,
        dialect,
        program_dir: args.program_dir,
        index_path,
        faults: Faults {
            crash_after_rename: args.fault_crash_after_rename,
            pause_before_rename_ms: args.fault_pause_before_rename_ms,
        },
    };
    if args.rebuild_index {
        let r = gearcam_agent::store::Store::rebuild(config)?;
        println!(
            "rebuilt the program index: {} program(s) indexed from their headers{}{}",
            r.programs,
            if r.skipped.is_empty() {
                String::new()
            } else {
                format!("; not programs, left alone: {}", r.skipped.join(", "))
            },
            r.moved_to
                .map(|p| format!("; the lost index is kept as {p}"))
                .unwrap_or_default()
        );
        return Ok(());
    }
    let bus = Bus::open(&args.bus.to_config()).await?;
    run(bus, config, cancel_on_signal()).await?;
    Ok(())
}
