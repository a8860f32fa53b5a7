//! The planning station's side of a job on the bus: wait for the services,
//! submit the request, follow its events until the receipt or an error.

use std::time::Duration;

use gearcam_bus::{Bus, BusError};
use gearcam_proto::{
    decode, keys, DeliveryReceipt, EventKind, JobError, JobEvent, JobId, JobRequest, Stage,
};

/// How to submit.
#[derive(Debug, Clone)]
pub struct SubmitOptions {
    /// Follow the job until delivered or failed.
    pub wait: bool,
    /// How long to wait for the services to be alive.
    pub alive_timeout: Duration,
    /// How long to wait for the outcome once submitted.
    pub timeout: Duration,
}

/// How a submission ended.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// Submitted; not followed.
    Submitted(JobId),
    /// The agent stored the program.
    Delivered(DeliveryReceipt),
    /// A stage refused the job.
    Failed(Vec<JobError>),
    /// No outcome within the timeout; the last stage heard from.
    TimedOut {
        /// The job.
        job: JobId,
        /// Last stage that reported, if any.
        last_stage: Option<Stage>,
    },
}

/// The services a job for `machine` passes through.
pub fn services_for(req: &JobRequest) -> Vec<String> {
    vec![
        gearcam_knowledge::service::SERVICE.to_string(),
        gearcam_model::service::SERVICE.to_string(),
        gearcam_template::service::SERVICE.to_string(),
        keys::agent_service(&req.spec.job.machine),
    ]
}

/// Submits a job and, with `wait`, follows it; `on_event` sees every event.
pub async fn submit(
    bus: &Bus,
    req: &JobRequest,
    opts: &SubmitOptions,
    mut on_event: impl FnMut(&JobEvent),
) -> Result<Outcome, BusError> {
    let services = if opts.wait {
        services_for(req)
    } else {
        vec![gearcam_knowledge::service::SERVICE.to_string()]
    };
    bus.wait_alive(&services, opts.alive_timeout).await?;
    // Subscribe before publishing, so no event can be missed.
    let events = bus
        .session()
        .declare_subscriber(keys::job_events(&req.job_id))
        .await
        .map_err(|e| BusError::Zenoh {
            op: "declare subscriber",
            detail: e.to_string(),
        })?;
    bus.put(&keys::job_request(&req.job_id), req).await?;
    if !opts.wait {
        return Ok(Outcome::Submitted(req.job_id.clone()));
    }
    let deadline = tokio::time::Instant::now() + opts.timeout;
    let mut last_stage = None;
    loop {
        let sample = match tokio::time::timeout_at(deadline, events.recv_async()).await {
            Ok(Ok(s)) => s,
            Ok(Err(_)) | Err(_) => {
                return Ok(Outcome::TimedOut {
                    job: req.job_id.clone(),
                    last_stage,
                })
            }
        };
        let ev = match decode::<JobEvent>(&sample.payload().to_bytes()) {
            Ok(ev) => ev,
            Err(e) => {
                tracing::warn!(error = %e, "ignoring an undecodable event");
                continue;
            }
        };
        last_stage = Some(ev.stage);
        on_event(&ev);
        match ev.event {
            EventKind::Delivered { receipt } => return Ok(Outcome::Delivered(receipt)),
            EventKind::Failed { errors } => return Ok(Outcome::Failed(errors)),
            _ => {}
        }
    }
}

/// One line describing an event, for progress output.
pub fn describe(ev: &JobEvent) -> String {
    match &ev.event {
        EventKind::Planned { hob_id, confidence } => {
            format!("knowledge: planned with hob {hob_id} (confidence {confidence:.2})")
        }
        EventKind::Modelled { warnings } => {
            format!("model: validated and computed ({warnings} warning(s))")
        }
        EventKind::Programmed { name, sha256 } => {
            format!(
                "template: program {name} generated (sha256 {})",
                &sha256[..12.min(sha256.len())]
            )
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
    }
}
