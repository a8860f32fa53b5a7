//! The agent on the bus. Delivery is a request: the template service queries
//! `gearcam/v1/machines/{machine}/programs/{job}` with the program, and the
//! agent answers with its receipt only once file and index row are durable (or
//! with a typed refusal), and publishes the same as a job event. The store is
//! also queryable for lost receipts, history, versions and rollback.

use gearcam_bus::query::{run_queryable_batched, Answer};
use gearcam_bus::stage::codec_error;
use gearcam_bus::{Bus, CancellationToken};
use gearcam_proto::{
    decode, keys, DeliveryReply, EventKind, JobError, JobId, NcProgram, ProgramHistory, Stage,
};

use crate::store::{Store, StoreConfig};
use crate::AgentError;

/// Runs the agent for one machine until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    config: StoreConfig,
    shutdown: CancellationToken,
) -> Result<(), AgentError> {
    let machine = config.machine.clone();
    let mut store = Store::open(config)?;
    tracing::info!(%machine, dir = %store.config().program_dir.display(), "program store open");
    let prefix = format!("{}/machines/{machine}/", keys::PREFIX);
    let pattern = format!("{prefix}**");
    run_queryable_batched(
        &bus,
        &pattern,
        Some(&keys::agent_service(&machine)),
        Stage::Agent,
        shutdown,
        MAX_BATCH,
        |batch| {
            // Deliveries are stored together (one group commit); every other
            // query is answered on its own, after them.
            let mut answers: Vec<Option<Answer>> = batch.iter().map(|_| None).collect();
            let mut deliveries = Vec::new();
            for (i, (key, payload)) in batch.iter().enumerate() {
                let rest = key.strip_prefix(&prefix).unwrap_or_default();
                if let ["programs", job] = rest.split('/').collect::<Vec<_>>().as_slice() {
                    match decode_delivery(job, payload) {
                        Ok(program) => deliveries.push((i, program)),
                        Err(answer) => answers[i] = Some(answer),
                    }
                }
            }
            let programs: Vec<NcProgram> = deliveries.iter().map(|(_, p)| p.clone()).collect();
            for ((i, program), result) in deliveries.into_iter().zip(store.store_batch(&programs)) {
                answers[i] = Some(delivered(program, result));
            }
            for (i, (key, _)) in batch.iter().enumerate() {
                if answers[i].is_none() {
                    answers[i] = Some(answer_store_query(&mut store, &prefix, key));
                }
            }
            answers
                .into_iter()
                .map(|a| a.expect("every query answered"))
                .collect()
        },
    )
    .await?;
    Ok(())
}

/// Largest group of deliveries committed together.
const MAX_BATCH: usize = 256;

/// Answers a store query (lost receipts, history, versions, rollback).
fn answer_store_query(store: &mut Store, prefix: &str, key: &str) -> Answer {
    let rest = key.strip_prefix(prefix).unwrap_or_default();
    let parts: Vec<&str> = rest.split('/').collect();
    match parts.as_slice() {
        ["store", "jobs", job] => match store.stored_receipt(job) {
            Ok(Some(receipt)) => Answer::message(&DeliveryReply::Stored { receipt }),
            Ok(None) => Answer::message(&DeliveryReply::NotStored),
            Err(e) => Answer::error(e.to_string()),
        },
        ["store", "programs"] => history(store, None),
        ["store", "programs", name] => history(store, Some(name)),
        ["store", "programs", _name, "versions", seq] => {
            match seq.parse::<u64>().map(|s| store.version(s)) {
                Ok(Ok(Some(text))) => Answer::message(&text),
                Ok(Ok(None)) => Answer::error(format!(
                    "no version {seq} in the store of {}",
                    store.config().machine
                )),
                Ok(Err(e)) => Answer::error(e.to_string()),
                Err(_) => Answer::error(format!("version must be a number, got {seq:?}")),
            }
        }
        ["store", "programs", name, "rollback", seq] => match seq.parse::<u64>() {
            Ok(seq) => match store.rollback(name, seq) {
                Ok(receipt) => Answer::message(&DeliveryReply::Stored { receipt }),
                Err(error) => Answer::message(&DeliveryReply::Refused { error }),
            },
            Err(_) => Answer::error(format!("version must be a number, got {seq:?}")),
        },
        _ => Answer::error(format!("unknown agent key {key}")),
    }
}

fn history(store: &Store, name: Option<&str>) -> Answer {
    match store.history(name) {
        Ok(versions) => Answer::message(&ProgramHistory {
            machine: store.config().machine.clone(),
            versions,
        }),
        Err(e) => Answer::error(e.to_string()),
    }
}

fn refused(job: Option<JobId>, error: JobError) -> Answer {
    let mut a = Answer::message(&DeliveryReply::Refused {
        error: error.clone(),
    });
    if let Some(job) = job {
        a.events.push((
            job,
            EventKind::Failed {
                errors: vec![error],
            },
        ));
    }
    a
}

/// Decodes a delivery's program, or the refusal to answer with.
fn decode_delivery(job: &str, payload: &[u8]) -> Result<NcProgram, Answer> {
    let job_id = JobId::new(job).ok();
    let program = match decode::<NcProgram>(payload) {
        Ok(p) => p,
        Err(e) => {
            tracing::warn!(job, error = %e, "refusing an undecodable program");
            return Err(refused(job_id, codec_error::<NcProgram>(Stage::Agent, &e)));
        }
    };
    if job_id.as_ref() != Some(&program.job_id) {
        return Err(refused(
            job_id,
            JobError::job_id_mismatch(Stage::Agent, job, &program.job_id, "program"),
        ));
    }
    Ok(program)
}

/// The answer to a delivery once the store has decided.
fn delivered(
    program: NcProgram,
    result: Result<gearcam_proto::DeliveryReceipt, JobError>,
) -> Answer {
    match result {
        Ok(receipt) => {
            tracing::info!(job = %receipt.job_id, file = receipt.file_name, sha256 = receipt.sha256, duplicate = receipt.duplicate, "program stored");
            let mut a = Answer::message(&DeliveryReply::Stored {
                receipt: receipt.clone(),
            });
            a.events
                .push((program.job_id, EventKind::Delivered { receipt }));
            a
        }
        Err(error) => {
            tracing::info!(job = %program.job_id, code = error.code, "program refused");
            refused(Some(program.job_id), error)
        }
    }
}
