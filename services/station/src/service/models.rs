//! The models the model service publishes (`gearcam/v1/jobs/{job}/model`),
//! journaled beside their jobs and answered on
//! `gearcam/v1/station/jobs/{job}/model`, so that a client (the web page's
//! pictures) reads a job's model after the job has ended, from the one
//! place that keeps it.
//!
//! A model is checked before it is kept: it decodes as a model of its
//! family, names the job of its key, and was computed from the very request
//! the station journaled for that job (so its machine is the job's). Any
//! other is logged and dropped. The answer is the model's message as
//! published, read with [`gearcam_proto::AnyModel`]. The job's request is
//! answered the same way on `gearcam/v1/station/jobs/{job}/request`.

use gearcam_proto::{
    keys, AnyModel, Code, Incoming, JobError, JobId, JobRequest, Stage, StationReply,
};
use zenoh::query::Query;
use zenoh::sample::Sample;

use super::{journal_error, reply_message, unknown_job};
use crate::journal::Journal;

/// Models taken in one batch at most, beside its events and submissions (a
/// model can be megabytes).
pub(super) const MAX_MODELS_PER_BATCH: usize = 64;

/// A published model: the key's job id as given and the message's bytes.
pub(super) struct Published {
    key: String,
    bytes: Vec<u8>,
}

impl Published {
    /// The model in a sample.
    pub(super) fn of(s: &Sample) -> Published {
        Published {
            key: s.key_expr().as_str().to_string(),
            bytes: s.payload().to_bytes().into_owned(),
        }
    }
}

/// The request a model was computed from (its plan's).
fn request_of(model: &AnyModel) -> &JobRequest {
    match model {
        AnyModel::Hobbing(m) => &m.plan.request,
        AnyModel::Spiral(m) => &m.plan.request,
        AnyModel::Wire(m) => &m.plan.request,
    }
}

/// The job of a published model when it may be kept, or why not.
fn checked(j: &Journal, p: &Published) -> Result<JobId, String> {
    let job = keys::job_of(&p.key).ok_or("its key names no job")?;
    let model = AnyModel::decode_incoming(&p.bytes).map_err(|e| e.to_string())?;
    if model.job_id() != &job {
        return Err(format!("it is the model of job {}", model.job_id()));
    }
    let journaled = j
        .request(&job)
        .map_err(|e| e.to_string())?
        .ok_or("the job is not in the journal")?;
    if request_of(&model) != &journaled {
        return Err("it was computed from another request than the job's".into());
    }
    Ok(job)
}

/// Journals each checked model (inside the batch's transaction); logs and
/// drops the others.
pub(super) fn journal_models(j: &Journal, models: &[Published]) {
    for p in models {
        match checked(j, p) {
            Ok(job) => match j.set_model(&job, &p.bytes) {
                Ok(true) => tracing::debug!(%job, bytes = p.bytes.len(), "model journaled"),
                Ok(false) => {
                    tracing::info!(%job, "a model of a job that has ended and has its model is not kept")
                }
                Err(e) => tracing::error!(%job, error = %e, "cannot journal the model"),
            },
            Err(why) => tracing::warn!(key = p.key, why, "ignored a model"),
        }
    }
}

/// The answer to a model view of `raw` (the key's job id as given): the
/// model's message as published, or the station's refusal.
pub(super) fn answer(journal: &Journal, raw: &str) -> Result<Vec<u8>, JobError> {
    let job = JobId::new(raw).map_err(|e| JobError::bad_id(Stage::Station, "job_id", &e))?;
    match journal.model(&job) {
        Ok(Some(Some(bytes))) => Ok(bytes),
        Ok(Some(None)) => Err(Stage::Station.error(
            Code::MODEL_NOT_JOURNALED,
            "job_id",
            "a job whose model the model service has published",
            job.as_str(),
            "the station has no model of this job yet: it is journaled when the model service publishes it; a job that failed before its model has none",
        )),
        Ok(None) => Err(unknown_job(&job)),
        Err(e) => Err(journal_error(e)),
    }
}

/// The answer to a request view of `raw` (the key's job id as given): the
/// request's message as journaled, or the station's refusal.
pub(super) fn request_answer(journal: &Journal, raw: &str) -> Result<Vec<u8>, JobError> {
    let job = JobId::new(raw).map_err(|e| JobError::bad_id(Stage::Station, "job_id", &e))?;
    match journal.request_bytes(&job) {
        Ok(Some(bytes)) => Ok(bytes),
        Ok(None) => Err(unknown_job(&job)),
        Err(e) => Err(journal_error(e)),
    }
}

/// Sends the [`answer`] (or [`request_answer`]) to a model (or request) view
/// (`gearcam/v1/station/jobs/{job}/model`).
pub(super) async fn reply(q: Query, answer: Result<Vec<u8>, JobError>) {
    match answer {
        Ok(bytes) => {
            if let Err(e) = q.reply(q.key_expr().clone(), bytes).await {
                tracing::warn!(error = %e, "cannot reply");
            }
        }
        Err(error) => {
            let refused = StationReply::Refused {
                errors: vec![error],
            };
            reply_message(q, &refused).await;
        }
    }
}
