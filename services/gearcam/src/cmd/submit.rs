//! `gearcam submit`: a job file to the planning station over the bus, followed
//! to its receipt with `--wait`.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use gearcam_bus::{Bus, BusArgs};
use gearcam_proto::{JobRequest, JobSpec};
use serde_json::json;

use crate::bus_config;
use crate::check;
use crate::cmd::progress;
use crate::jobfile;
use crate::output::failure_json;
use crate::station::{self, Outcome, SubmitOptions};

/// Runs `gearcam submit JOB`: the job file, checked here, to the station;
/// with `wait`, followed to its receipt or its end within `timeout` seconds.
pub async fn submit(
    job: &Path,
    bus_args: &BusArgs,
    wait: bool,
    json: bool,
    timeout: u64,
    id: Option<gearcam_proto::JobId>,
) -> anyhow::Result<ExitCode> {
    let spec = match job_spec(job, json, id) {
        Ok(spec) => spec,
        Err(code) => return Ok(code),
    };
    let req = match job_request(spec, bus_args, json) {
        Ok(req) => req,
        Err(code) => return Ok(code),
    };
    let retry_hint = format!(
        "the station may have journaled job {id} before the answer was lost; submit again with `--id {id}`: \
         the same id and job file is a resubmission, answered with the job's real state, never a second job",
        id = req.job_id
    );
    let bus = match join(bus_args, json, &req).await {
        Ok(bus) => bus,
        Err(code) => return Ok(code),
    };
    let opts = SubmitOptions {
        wait,
        alive_timeout: Duration::from_secs(timeout.min(30)),
        timeout: Duration::from_secs(timeout),
    };
    let pb = progress(json);
    pb.set_message(format!("job {}", req.job_id));
    let outcome = station::submit(&bus, &req, &opts, |ev| {
        if !json {
            pb.suspend(|| eprintln!("{}", station::describe(ev)));
        }
    })
    .await;
    pb.finish_and_clear();
    bus.close().await;
    let outcome = match outcome {
        Ok(o) => o,
        Err(e) => {
            if json {
                crate::outln!(
                    "{}",
                    failure_json(
                        crate::exit::UNREACHABLE,
                        &[],
                        &e.to_string(),
                        json!({"job": req.job_id, "state": "unreachable", "retry": retry_hint})
                    )
                );
            } else {
                eprintln!("gearcam: {e}\n{retry_hint}");
            }
            return Ok(crate::exit::code(crate::exit::UNREACHABLE));
        }
    };
    let (value, code) = outcome_json(&outcome, &req, timeout)?;
    if json {
        crate::outln!("{value}");
    } else {
        print_outcome(&outcome, &req, timeout);
    }
    Ok(code)
}

/// The job file's spec, with `--id` as its id: the refusal printed when the
/// file does not load, a usage error when `--id` differs from the file's id.
fn job_spec(job: &Path, json: bool, id: Option<gearcam_proto::JobId>) -> Result<JobSpec, ExitCode> {
    let mut spec = match jobfile::load(job) {
        Ok(s) => s,
        Err(e) => {
            let code = crate::exit::for_errors(std::slice::from_ref(&e));
            if json {
                crate::outln!(
                    "{}",
                    failure_json(code, &[e], "", json!({"job": null, "state": "rejected"}))
                );
            } else {
                eprintln!("gearcam: job file refused\n{}", check::format_errors(&[e]));
            }
            return Err(crate::exit::code(code));
        }
    };
    if let Some(id) = id {
        if let Some(file_id) = spec.job.id.as_ref().filter(|f| **f != id) {
            return Err(crate::output::fail(
                crate::exit::USAGE,
                &[],
                &format!(
                    "gearcam: --id {id} differs from the job file's [job] id = \"{file_id}\"; give one of them"
                ),
            ));
        }
        spec.job.id = Some(id);
    }
    Ok(spec)
}

/// The request to submit, by the connection's login (the name the router
/// checks); refused here, before joining the bus, when it is larger than a
/// request on the bus may be.
fn job_request(spec: JobSpec, bus_args: &BusArgs, json: bool) -> Result<JobRequest, ExitCode> {
    let mut req = jobfile::request(spec);
    // Submitted by the connection's login, the name the router checks.
    req.submitted_by = jobfile::who(bus_args, None)?;
    if let Err(e) = jobfile::check_size(&req) {
        if json {
            crate::outln!(
                "{}",
                failure_json(
                    crate::exit::REFUSED,
                    std::slice::from_ref(&e),
                    "",
                    json!({"job": req.job_id, "state": "rejected"})
                )
            );
        } else {
            eprintln!("gearcam: job refused\n{}", check::format_errors(&[e]));
        }
        return Err(crate::exit::code(crate::exit::REFUSED));
    }
    Ok(req)
}

/// Joins the bus as a client; when it cannot, says so (the job was not
/// submitted) and where a router was expected.
async fn join(bus_args: &BusArgs, json: bool, req: &JobRequest) -> Result<Bus, ExitCode> {
    let config = bus_config::client(bus_args);
    match Bus::open(&config).await {
        Ok(bus) => Ok(bus),
        Err(e) => {
            let message = format!(
                "cannot join the bus at {}: {e}; is `gearcam up` (or a router) running there?",
                config.connect.join(", ")
            );
            if json {
                crate::outln!(
                    "{}",
                    failure_json(
                        crate::exit::UNREACHABLE,
                        &[],
                        &message,
                        json!({"job": req.job_id, "state": "unreachable"})
                    )
                );
            } else {
                eprintln!("gearcam: {message}");
            }
            Err(crate::exit::code(crate::exit::UNREACHABLE))
        }
    }
}

/// The outcome as the JSON `--json` prints, and the exit code it ends with.
fn outcome_json(
    outcome: &Outcome,
    req: &JobRequest,
    timeout: u64,
) -> anyhow::Result<(serde_json::Value, ExitCode)> {
    Ok(match outcome {
        Outcome::Submitted(s) => (serde_json::to_value(s)?, ExitCode::SUCCESS),
        Outcome::Delivered(r, warnings) => (
            json!({"job": r.job_id, "state": "delivered", "program": {"name": r.name, "sha256": r.sha256, "path": r.path}, "receipt": r, "warnings": warnings}),
            ExitCode::SUCCESS,
        ),
        Outcome::Failed(errors) => {
            let code = crate::exit::for_errors(errors);
            (
                failure_json(code, errors, "", json!({"job": req.job_id, "state": "failed"})),
                crate::exit::code(code),
            )
        }
        Outcome::Ended(state, errors) => (
            failure_json(
                crate::exit::REFUSED,
                errors,
                "",
                json!({"job": req.job_id, "state": state.as_str()}),
            ),
            crate::exit::code(crate::exit::REFUSED),
        ),
        Outcome::TimedOut(s) => (
            failure_json(
                crate::exit::UNFINISHED,
                &[],
                &format!(
                    "not finished within {timeout} s; the job stays journaled and the station keeps driving it"
                ),
                serde_json::to_value(s)?,
            ),
            crate::exit::code(crate::exit::UNFINISHED),
        ),
    })
}

/// The outcome for a person: what was journaled or delivered on stdout, a
/// refusal, an end or a timeout on stderr.
fn print_outcome(outcome: &Outcome, req: &JobRequest, timeout: u64) {
    match outcome {
        Outcome::Submitted(s) => crate::outln!("job {} journaled by the station ({})", s.job, s.state.as_str()),
        Outcome::Delivered(r, warnings) => crate::outln!(
            "job {} delivered: {} (sha256 {}){}",
            r.job_id,
            r.path,
            r.sha256,
            station::format_warnings(warnings)
        ),
        Outcome::Failed(errors) => {
            eprintln!("job {} refused with {} error(s):\n{}", req.job_id, errors.len(), check::format_errors(errors))
        }
        Outcome::Ended(state, errors) => eprintln!(
            "job {} {}, not delivered:\n{}",
            req.job_id,
            state.as_str(),
            check::format_errors(errors)
        ),
        Outcome::TimedOut(s) => eprintln!(
            "job {}: not finished within {timeout} s; it stays journaled and the station keeps driving it\n  {}",
            s.job,
            station::describe_status(s)
        ),
    }
}
