//! One module per `gearcam` command, and what they share.

pub mod check;
pub mod demo;
pub mod jobs;
pub mod kb;
pub mod program;
pub mod router;
pub mod station;
pub mod submit;
pub mod templates;
pub mod up;
pub mod web;

use std::process::ExitCode;
use std::time::Duration;

use anyhow::Context;
use gearcam_bus::{Bus, BusArgs};
use indicatif::{ProgressBar, ProgressStyle};

use crate::{bus_config, check as report};

pub fn progress(json: bool) -> ProgressBar {
    if json {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new_spinner();
    pb.set_style(
        ProgressStyle::with_template("{spinner} {elapsed} {msg}").expect("valid template"),
    );
    pb.enable_steady_tick(Duration::from_millis(120));
    pb
}

/// Joins the bus as a client ([`bus_config::client`]).
pub async fn join_bus(bus_args: &BusArgs) -> anyhow::Result<Bus> {
    Bus::open(&bus_config::client(bus_args))
        .await
        .context("joining the bus")
}

/// Prints a typed refusal (a service's, or the local knowledge base's);
/// exit code 3 when what was asked for does not exist, else 1 ([`crate::exit`]).
pub fn refused(errors: &[gearcam_proto::JobError]) -> ExitCode {
    crate::output::fail(
        crate::exit::for_errors(errors),
        errors,
        &format!(
            "gearcam: refused with {} error(s):\n{}",
            errors.len(),
            report::format_errors(errors)
        ),
    )
}
