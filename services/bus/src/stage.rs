//! The loop of a pipeline stage: subscribe to a key pattern, decode and validate
//! every sample, hand it to the stage's pure handler, publish what it produced,
//! and report every failure as a typed error event on the job's events key.
//!
//! A malformed sample is logged and answered with a typed `Failed` event (when
//! its key names a job); a panicking handler is caught and reported the same
//! way. The loop keeps serving until shutdown.

use gearcam_proto::Code;
use std::panic::{catch_unwind, AssertUnwindSafe};

use gearcam_proto::{keys, EventKind, Incoming, JobError, JobId, Stage};
use tokio_util::sync::CancellationToken;

use crate::{Bus, BusError};

/// One message a handler wants published.
#[derive(Debug)]
pub struct Output {
    /// Key expression.
    pub key: String,
    /// Encoded payload.
    pub payload: Vec<u8>,
}

/// What a handler produced for one input.
#[derive(Debug, Default)]
pub struct Handled {
    /// Progress events to publish on the job's events key, before the outputs.
    pub events: Vec<EventKind>,
    /// Messages to publish.
    pub outputs: Vec<Output>,
}

/// A handler's failure: the typed errors to report for the job.
pub type Failure = Vec<JobError>;

/// Builds the typed error for an undecodable payload.
pub fn codec_error<T: Incoming>(stage: Stage, err: &gearcam_proto::CodecError) -> JobError {
    JobError {
        stage,
        code: err.code(),
        field: "payload".into(),
        expected: format!(
            "a MessagePack {} message, schema {}",
            T::KINDS,
            gearcam_proto::SCHEMA_VERSION
        ),
        got: match err {
            gearcam_proto::CodecError::UnknownVersion { got, .. } => format!("schema {got}"),
            gearcam_proto::CodecError::WrongKind { got, .. } => format!("kind {got}"),
            gearcam_proto::CodecError::TooLarge { got, .. } => format!("{got} bytes"),
            _ => "undecodable bytes".into(),
        },
        message: format!("{err}; the message was dropped, fix the sender and resubmit"),
    }
}

/// Runs a stage until `shutdown` is cancelled.
///
/// The stage's liveliness token `gearcam/v1/alive/{service}` is declared only
/// once the subscriber is in place, so a sender that waits for the token never
/// publishes into the void. `handle` receives the sample's key and the decoded message and returns what
/// to publish, or the typed errors for the job.
pub async fn run_stage<T, F>(
    bus: &Bus,
    pattern: &str,
    service: &str,
    stage: Stage,
    shutdown: CancellationToken,
    mut handle: F,
) -> Result<(), BusError>
where
    T: Incoming,
    F: FnMut(&str, T) -> Result<Handled, Failure>,
{
    let sub = bus
        .session()
        .declare_subscriber(pattern)
        .await
        .map_err(|e| BusError::Zenoh {
            op: "declare subscriber",
            detail: e.to_string(),
        })?;
    let _token = bus.alive_token(service).await?;
    tracing::info!(stage = stage.as_str(), pattern, service, "stage serving");
    loop {
        let sample = tokio::select! {
            _ = shutdown.cancelled() => break,
            s = sub.recv_async() => match s {
                Ok(s) => s,
                Err(_) => break,
            },
        };
        let key = sample.key_expr().as_str().to_string();
        let bytes = sample.payload().to_bytes();
        let job = keys::job_of(&key);
        let result = match T::decode_incoming(&bytes) {
            Err(e) => {
                tracing::warn!(stage = stage.as_str(), key, error = %e, "dropping undecodable message");
                Err(vec![codec_error::<T>(stage, &e)])
            }
            Ok(msg) => catch_unwind(AssertUnwindSafe(|| handle(&key, msg))).unwrap_or_else(|p| {
                let what = p
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                tracing::error!(
                    stage = stage.as_str(),
                    key,
                    panic = what,
                    "handler panicked"
                );
                Err(vec![JobError {
                    stage,
                    code: Code::INTERNAL_ERROR,
                    field: "-".into(),
                    expected: "a result".into(),
                    got: "a panic".into(),
                    message: format!(
                        "internal error in the {} stage: {what}; please report it",
                        stage.as_str()
                    ),
                }])
            }),
        };
        if let Err(e) = publish(bus, stage, job.as_ref(), &key, result).await {
            tracing::error!(stage = stage.as_str(), key, error = %e, "cannot publish");
        }
    }
    tracing::info!(stage = stage.as_str(), "stage stopped");
    Ok(())
}

async fn publish(
    bus: &Bus,
    stage: Stage,
    job: Option<&JobId>,
    key: &str,
    result: Result<Handled, Failure>,
) -> Result<(), BusError> {
    match (result, job) {
        (Ok(handled), job) => {
            if let Some(job) = job {
                for ev in handled.events {
                    bus.event(job, stage, ev).await?;
                }
            }
            for out in handled.outputs {
                bus.put_bytes(&out.key, out.payload).await?;
            }
        }
        (Err(errors), Some(job)) => {
            for e in &errors {
                tracing::info!(stage = stage.as_str(), %job, code = e.code.as_str(), field = e.field, "job failed");
            }
            bus.event(job, stage, EventKind::Failed { errors }).await?;
        }
        (Err(errors), None) => {
            tracing::warn!(
                stage = stage.as_str(),
                key,
                ?errors,
                "failure on a key that names no job; nothing to report to"
            );
        }
    }
    Ok(())
}
