//! The agents' question before they store a group of programs
//! (`gearcam/v1/station/journaled/{machine}` with a `JobIds` payload):
//! the status of each asked job journaled for that machine.
//!
//! It is answered beside the station's loop, from the committed journal on a
//! read-only connection ([`JournalReader`]), not behind the loop's next group
//! commit: what the agent needs is committed before it matters. A job is
//! acknowledged only once its row is durable, and a cancellation is
//! committed before it is answered, so a job that reached an agent is in the
//! committed journal, and a cancelled one is there as cancelled.

use std::path::Path;

use gearcam_bus::CancellationToken;
use gearcam_proto::{decode, encode, keys, Code, JobError, JobIds, Stage, StationReply};
use zenoh::handlers::FifoChannelHandler;
use zenoh::query::{Query, Queryable};
use zenoh::Session;

use super::{journal_error, zerr, StationError};
use crate::journal::JournalReader;

/// Declares the queryable and answers it until `shutdown` is cancelled.
pub(super) async fn serve(
    session: &Session,
    journal: &Path,
    shutdown: CancellationToken,
) -> Result<tokio::task::JoinHandle<()>, StationError> {
    let reader = JournalReader::open(journal)?;
    let queries = session
        .declare_queryable(keys::STATION_JOURNALED_ANY)
        .await
        .map_err(zerr("declare queryable"))?;
    Ok(tokio::spawn(answer_all(queries, reader, shutdown)))
}

async fn answer_all(
    queries: Queryable<FifoChannelHandler<Query>>,
    reader: JournalReader,
    shutdown: CancellationToken,
) {
    loop {
        let q = tokio::select! {
            _ = shutdown.cancelled() => break,
            q = queries.recv_async() => match q {
                Ok(q) => q,
                Err(_) => break,
            },
        };
        // The pattern admits one chunk, the machine; a key naming none
        // matches no job's machine and is answered with no job.
        let machine = keys::station_journaled_of(q.key_expr().as_str()).unwrap_or("");
        let reply = journaled_reply(&reader, machine, &q);
        let sent = match encode(&reply) {
            Ok(bytes) => q.reply(q.key_expr().clone(), bytes).await,
            Err(e) => q.reply_err(e.to_string().into_bytes()).await,
        };
        if let Err(e) = sent {
            tracing::warn!(error = %e, "cannot answer an agent's question");
        }
    }
}

/// The status of each asked job journaled for `machine` (a job unknown, or
/// of another machine, is left out: the agent stores none of its programs).
fn journaled_reply(reader: &JournalReader, machine: &str, q: &Query) -> StationReply {
    let refused = |error: JobError| StationReply::Refused {
        errors: vec![error],
    };
    let payload = q
        .payload()
        .map(|p| p.to_bytes().into_owned())
        .unwrap_or_default();
    let asked = match decode::<JobIds>(&payload) {
        Ok(asked) => asked,
        Err(e) => {
            return refused(gearcam_bus::stage::codec_error::<JobIds>(
                Stage::Station,
                &e,
            ))
        }
    };
    if asked.jobs.len() > JobIds::MAX {
        return refused(Stage::Station.error(
            Code::TOO_MANY_JOBS,
            "jobs",
            format!("at most {} jobs", JobIds::MAX),
            format!("{} jobs", asked.jobs.len()),
            "ask about a large group in parts",
        ));
    }
    let mut jobs = Vec::with_capacity(asked.jobs.len());
    for job in &asked.jobs {
        match reader.status(job) {
            Ok(Some(status)) if status.machine.as_str() == machine => jobs.push(status),
            Ok(_) => {}
            Err(e) => return refused(journal_error(e)),
        }
    }
    StationReply::Jobs { jobs }
}
