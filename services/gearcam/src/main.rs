//! `gearcam`: the planning station command. Everything it does is in the
//! library: [`gearcam::cli`] parses and dispatches, one module per command in
//! [`gearcam::cmd`].

use std::process::ExitCode;

use clap::Parser;
use gearcam::cli::{run, Cli};
use gearcam_bus::init_tracing;

fn main() -> ExitCode {
    init_tracing("warn");
    let cli = Cli::parse();
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("gearcam: cannot start the runtime: {e}");
            return ExitCode::from(2);
        }
    };
    match rt.block_on(run(cli)) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("gearcam: {e:#}");
            ExitCode::from(2)
        }
    }
}
