//! `gearcam`: the planning station command. Everything it does is in the
//! library: [`gearcam::cli`] parses and dispatches, one module per command in
//! [`gearcam::cmd`].

use std::process::ExitCode;

use clap::Parser;
use gearcam::cli::{run, Cli};
use gearcam::exit;
use gearcam_bus::init_tracing;

fn main() -> ExitCode {
    init_tracing("warn");
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // Help and version are answers, not errors; a wrong command line
            // is a usage error (64), never confused with an unreachable bus (2).
            let _ = e.print();
            return if e.use_stderr() {
                exit::code(exit::USAGE)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let rt = match tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("gearcam: cannot start the runtime: {e}");
            return exit::code(exit::UNREACHABLE);
        }
    };
    match rt.block_on(run(cli)) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("gearcam: {e:#}; is `gearcam up` (or the router) running?");
            exit::code(exit::UNREACHABLE)
        }
    }
}
