//! The client side of the planning station: submit a job to the station
//! service (which journals it before it answers), follow it to its end, and
//! read the journal.

use gearcam_proto::Code;
use std::time::Duration;

use gearcam_bus::query::{CallError, Retry};
use gearcam_bus::Bus;
use gearcam_proto::{
    decode, keys, CancelRequest, DeliveryReceipt, EventKind, JobError, JobEvent, JobId, JobRequest,
    JobState, JobStatus, StationReply,
};

/// How to submit.
#[derive(Debug, Clone)]
pub struct SubmitOptions {
    /// Follow the job until delivered or failed.
    pub wait: bool,
    /// How long to wait for the station to be reachable.
    pub alive_timeout: Duration,
    /// How long to wait for the outcome once journaled.
    pub timeout: Duration,
}

/// How a submission ended.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// Journaled by the station; not followed.
    Submitted(Box<JobStatus>),
    /// The agent stored the program; the model's warnings (what to check
    /// before cutting).
    Delivered(Box<DeliveryReceipt>, Vec<gearcam_proto::Warning>),
    /// The station or a stage refused the job.
    Failed(Vec<JobError>),
    /// A person's decision ended the job before delivery: `superseded` (an
    /// operator adopted the edit at the machine it waited to replace) or
    /// `cancelled`; the errors say who and what.
    Ended(JobState, Vec<JobError>),
    /// Not finished within the timeout; the job stays journaled and the station
    /// keeps driving it.
    TimedOut(Box<JobStatus>),
}

/// Errors reaching the station.
#[derive(Debug, thiserror::Error)]
pub enum StationClientError {
    /// The station did not answer.
    #[error("the planning station did not answer ({0}); is `gearcam up` (or `gearcam station`) running and reachable?")]
    Unreachable(String),
}

/// Submits a job to the station and, with `wait`, follows it; `on_event`
/// sees every event of the job.
pub async fn submit(
    bus: &Bus,
    req: &JobRequest,
    opts: &SubmitOptions,
    mut on_event: impl FnMut(&JobEvent),
) -> Result<Outcome, StationClientError> {
    bus.wait_alive(&[keys::STATION_SERVICE.to_string()], opts.alive_timeout)
        .await
        .map_err(|e| StationClientError::Unreachable(e.to_string()))?;
    // Subscribe before submitting, so no progress event is missed.
    let events = bus
        .session()
        .declare_subscriber(keys::job_events(&req.job_id))
        .await
        .map_err(|e| StationClientError::Unreachable(e.to_string()))?;
    let retry = Retry {
        timeout: opts
            .timeout
            .clamp(Duration::from_secs(1), Duration::from_secs(10)),
        attempts: 3,
        pause: Duration::from_millis(300),
    };
    // Every try is the same request: a resubmission if an earlier one was
    // journaled. When no answer came, the journal may still hold the job.
    let reply: StationReply = match bus
        .call(&keys::station_submit(&req.submitted_by), Some(req), retry)
        .await
    {
        Ok(reply) => reply,
        Err(e) => match status_with(
            bus,
            &req.job_id,
            Retry {
                attempts: 1,
                ..retry
            },
        )
        .await
        {
            Ok(Ok(status)) => StationReply::Accepted {
                status: Box::new(status),
            },
            _ => return Err(StationClientError::Unreachable(e.to_string())),
        },
    };
    let accepted = match reply {
        StationReply::Refused { errors } => return Ok(Outcome::Failed(errors)),
        StationReply::Accepted { status } => *status,
        other => {
            return Err(StationClientError::Unreachable(format!(
                "the station answered a submission with {other:?}"
            )))
        }
    };
    if !opts.wait {
        return Ok(Outcome::Submitted(Box::new(accepted)));
    }
    let deadline = tokio::time::Instant::now() + opts.timeout;
    let mut last = accepted;
    loop {
        if let Some(outcome) = final_outcome(&last) {
            return Ok(outcome);
        }
        let poll = tokio::time::sleep(Duration::from_millis(500));
        tokio::select! {
            _ = tokio::time::sleep_until(deadline) => return Ok(Outcome::TimedOut(Box::new(last))),
            s = events.recv_async() => {
                if let Ok(s) = s {
                    if let Ok(ev) = decode::<JobEvent>(&s.payload().to_bytes()) {
                        on_event(&ev);
                        let end = matches!(ev.event, EventKind::Delivered { .. } | EventKind::Failed { .. });
                        if !end {
                            continue;
                        }
                    }
                }
            }
            _ = poll => {}
        }
        // The journal is the truth: read it after a final event or a poll interval.
        if let Ok(Ok(s)) = status(bus, &req.job_id).await {
            last = s;
        }
    }
}

fn final_outcome(s: &JobStatus) -> Option<Outcome> {
    match s.state {
        JobState::Delivered => s
            .receipt
            .clone()
            .map(|r| Outcome::Delivered(Box::new(r), s.warnings.clone())),
        JobState::Failed => Some(Outcome::Failed(s.errors.clone())),
        JobState::Superseded | JobState::Cancelled => {
            Some(Outcome::Ended(s.state, s.errors.clone()))
        }
        _ => None,
    }
}

/// One job's status from the station's journal, or the station's typed
/// refusal (`UNKNOWN_JOB`, `BAD_JOB_ID`).
pub async fn status(bus: &Bus, job: &JobId) -> Result<Result<JobStatus, Vec<JobError>>, CallError> {
    status_with(bus, job, Retry::default()).await
}

async fn status_with(
    bus: &Bus,
    job: &JobId,
    retry: Retry,
) -> Result<Result<JobStatus, Vec<JobError>>, CallError> {
    let reply = bus
        .call::<JobRequest, StationReply>(&keys::station_job(job), None, retry)
        .await?;
    Ok(match reply {
        StationReply::Status { status } => Ok(*status),
        StationReply::Refused { errors } => Err(errors),
        other => Err(vec![unexpected(&other)]),
    })
}

/// Cancels a job (`by` is who); its status after, or the station's typed
/// refusal (`UNKNOWN_JOB`, `JOB_FINAL`, `BAD_CANCEL_REQUEST`).
pub async fn cancel(
    bus: &Bus,
    job: &JobId,
    by: &str,
) -> Result<Result<JobStatus, Vec<JobError>>, CallError> {
    let request = CancelRequest { by: by.to_string() };
    let reply = bus
        .call::<CancelRequest, StationReply>(
            &keys::station_cancel(by, job),
            Some(&request),
            Retry::default(),
        )
        .await?;
    Ok(match reply {
        StationReply::Status { status } => Ok(*status),
        StationReply::Refused { errors } => Err(errors),
        other => Err(vec![unexpected(&other)]),
    })
}

/// Every job in the station's journal, oldest first, or the station's refusal.
pub async fn jobs(bus: &Bus) -> Result<Result<Vec<JobStatus>, Vec<JobError>>, CallError> {
    let reply = bus
        .call::<JobRequest, StationReply>(keys::STATION_JOBS, None, Retry::default())
        .await?;
    Ok(match reply {
        StationReply::Jobs { jobs } => Ok(jobs),
        StationReply::Refused { errors } => Err(errors),
        other => Err(vec![unexpected(&other)]),
    })
}

fn unexpected(reply: &StationReply) -> JobError {
    JobError::new(
        gearcam_proto::Stage::Station,
        Code::UNEXPECTED_REPLY,
        "reply",
        "the reply of the station's protocol for this query",
        format!("{reply:?}"),
        "the station answered with another kind of reply; is it another version?",
    )
}

/// The request the station journaled for `job` (to submit the same job
/// again), or the station's refusal (`UNKNOWN_JOB`, `BAD_JOB_ID`).
pub async fn request(
    bus: &Bus,
    job: &JobId,
) -> Result<Result<JobRequest, Vec<JobError>>, CallError> {
    let bytes = bus
        .call_bytes(&keys::station_job_request(job), None, Retry::default())
        .await?;
    if let Ok(StationReply::Refused { errors }) = decode::<StationReply>(&bytes) {
        return Ok(Err(errors));
    }
    Ok(decode::<JobRequest>(&bytes).map_err(|e| {
        vec![JobError::new(
            gearcam_proto::Stage::Station,
            Code::UNEXPECTED_REPLY,
            "reply",
            "the journaled request of the job (job_request)",
            e.to_string(),
            "the station answered with something else; is it another version?",
        )]
    }))
}

/// One line describing an event, for progress output.
pub fn describe(ev: &JobEvent) -> String {
    match &ev.event {
        EventKind::Accepted { machine } => format!("station: journaled for {machine}"),
        EventKind::Planned { hob_id, confidence } => {
            format!("knowledge: planned with tool {hob_id} (confidence {confidence:.2})")
        }
        EventKind::Modelled { warnings } => {
            let mut line = format!(
                "model: validated and computed ({} warning(s))",
                warnings.len()
            );
            line.push_str(&format_warnings(warnings));
            line
        }
        EventKind::Programmed {
            name,
            sha256,
            predicted_grade,
            warnings,
        } => {
            let mut line = format!(
                "template: program {name} generated (sha256 {})",
                &sha256[..12.min(sha256.len())]
            );
            if let Some(g) = predicted_grade {
                line.push_str(&format!(
                    "; virtual hobbing predicts ISO 1328-1 class {g}"
                ));
            }
            line.push_str(&format_warnings(warnings));
            line
        }
        EventKind::Delivered { receipt } => format!(
            "agent {}: stored {} ({} bytes){}",
            receipt.machine,
            receipt.path,
            receipt.size_bytes,
            if receipt.duplicate {
                " — already stored, original receipt"
            } else {
                ""
            }
        ),
        EventKind::Waiting { reason } => format!("{}: waiting — {reason}", ev.stage.as_str()),
        EventKind::Failed { errors } => format!(
            "{}: failed with {} error(s)",
            ev.stage.as_str(),
            errors.len()
        ),
        EventKind::Superseded { name, seq, by } => format!(
            "{}: superseded — {by} adopted the edit at the machine of {name} (version {seq}); the job is not delivered over it",
            ev.stage.as_str()
        ),
        EventKind::Cancelled { by } => format!("station: cancelled by {by}"),
    }
}

/// The warnings, one line each (`  ! CODE field: what to check`), each
/// line starting with a newline; empty for none.
pub fn format_warnings(warnings: &[gearcam_proto::Warning]) -> String {
    warnings
        .iter()
        .map(|w| format!("\n  ! {} {}: {}", w.code, w.field, w.message))
        .collect()
}

/// A status line for `gearcam jobs` / `gearcam status` (the model's warnings
/// on the lines after).
pub fn describe_status(s: &JobStatus) -> String {
    let mut line = format!(
        "{:<40} {:<10} {:<6} {:<16} attempts {}",
        s.job,
        s.state.as_str(),
        s.machine,
        s.part_number,
        s.attempts
    );
    if let Some(w) = &s.waiting_for {
        line.push_str(&format!("  ({w})"));
    }
    if let Some(p) = &s.program {
        line.push_str(&format!(
            "  {} sha256 {}",
            p.path,
            &p.sha256[..12.min(p.sha256.len())]
        ));
    }
    match (s.state, s.errors.first()) {
        // Ended by a person's decision: who and what.
        (JobState::Superseded | JobState::Cancelled, Some(e)) => {
            line.push_str(&format!("  {}: {}", e.code, e.got));
        }
        (_, Some(e)) => line.push_str(&format!("  {} {}", e.code, e.field)),
        (_, None) => {}
    }
    line.push_str(&format_warnings(&s.warnings));
    line
}
