//! `gearcam jobs`, `gearcam status` and `gearcam cancel`: the station's
//! journal.

use std::process::ExitCode;

use anyhow::Context;
use gearcam_bus::BusArgs;
use gearcam_proto::{JobId, JobStatus};

use crate::check;
use crate::cmd::{join_bus, refused};
use crate::station;

pub async fn jobs(bus_args: &BusArgs, json: bool) -> anyhow::Result<ExitCode> {
    let bus = join_bus(bus_args).await?;
    let list = station::jobs(&bus).await;
    bus.close().await;
    let jobs = match list.context("asking the station")? {
        Ok(jobs) => jobs,
        Err(errors) => return Ok(refused(&errors)),
    };
    if json {
        crate::outln!("{}", serde_json::to_string_pretty(&jobs)?);
    } else {
        for s in &jobs {
            crate::outln!("{}", station::describe_status(s));
        }
        crate::outln!("{} job(s)", jobs.len());
    }
    Ok(ExitCode::SUCCESS)
}

pub async fn status(job: &JobId, bus_args: &BusArgs, json: bool) -> anyhow::Result<ExitCode> {
    let bus = join_bus(bus_args).await?;
    let answer = station::status(&bus, job).await;
    bus.close().await;
    let status = match answered(answer)? {
        Ok(status) => status,
        Err(code) => return Ok(code),
    };
    if json {
        crate::outln!("{}", serde_json::to_string_pretty(&status)?);
    } else {
        crate::outln!("{}", station::describe_status(&status));
        crate::out!("{}", check::format_errors(&status.errors));
    }
    // A failed job's status is its refusal.
    Ok(if status.state == gearcam_proto::JobState::Failed {
        crate::exit::code(crate::exit::REFUSED)
    } else {
        ExitCode::SUCCESS
    })
}

pub async fn cancel(
    job: &JobId,
    by: &str,
    bus_args: &BusArgs,
    json: bool,
) -> anyhow::Result<ExitCode> {
    let bus = join_bus(bus_args).await?;
    let answer = station::cancel(&bus, job, by).await;
    bus.close().await;
    let status = match answered(answer)? {
        Ok(status) => status,
        Err(code) => return Ok(code),
    };
    if json {
        crate::outln!("{}", serde_json::to_string_pretty(&status)?);
    } else {
        crate::outln!("{}", station::describe_status(&status));
        crate::outln!(
            "job {job} is cancelled: the agent of {} will not store its program",
            status.machine
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The station's answer about one job: its status, or the refusal printed
/// and its exit code; an error when the station did not answer.
fn answered(
    answer: Result<Result<JobStatus, Vec<gearcam_proto::JobError>>, gearcam_bus::query::CallError>,
) -> anyhow::Result<Result<JobStatus, ExitCode>> {
    Ok(match answer.context("asking the station")? {
        Ok(status) => Ok(status),
        Err(errors) => Err(refused(&errors)),
    })
}
