//! `gearcam`: the planning station command. Everything it does is in the
//! library: [`gearcam::cli`] parses and dispatches, one module per command in
//! [`gearcam::cmd`].

use std::process::ExitCode;

use clap::Parser;
use gearcam::cli::{run, Cli};
use gearcam::{exit, output};
use gearcam_bus::init_tracing;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // A wrong command line is a usage error (64), never confused
            // with an unreachable bus (2); JSON too when `--json` was asked.
            output::set_json(asked_for_json());
            return output::fail(exit::USAGE, &[], e.render().to_string().trim_end());
        }
        Err(e) => {
            // Help and version are answers, not errors.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    output::set_json(cli.json());
    init_tracing(cli.log_filter());
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
        Err(e) => output::fail(
            exit::UNREACHABLE,
            &[],
            &format!(
                "gearcam: {}; is `gearcam up` (or the router) running?",
                without_source_paths(&format!("{e:#}"))
            ),
        ),
    }
}

/// True when the command line has `--json` (read before it parses).
#[allow(clippy::disallowed_methods)]
fn asked_for_json() -> bool {
    std::env::args_os().any(|a| a == "--json")
}

/// A message without the library's source locations (` at /…/src/x.rs:42.`)
/// that the bus's errors carry: they mean nothing to a person at the machine.
fn without_source_paths(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(i) = rest.find(" at /") {
        out.push_str(&rest[..i]);
        let tail = &rest[i + 1..];
        // The location ends after `.rs:LINE` (and an optional `.`).
        match tail.find(".rs:") {
            Some(j) => {
                let after = &tail[j + 4..];
                let digits = after.chars().take_while(char::is_ascii_digit).count();
                let mut end = j + 4 + digits;
                if tail[end..].starts_with('.') {
                    end += 1;
                }
                rest = &tail[end..];
            }
            None => {
                rest = tail;
                out.push(' ');
            }
        }
    }
    out.push_str(rest);
    out.trim_end().to_string()
}
