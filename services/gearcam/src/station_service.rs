//! The planning station as a service: it journals submitted jobs durably,
//! drives them through the pipeline, follows their events, and re-drives every
//! unfinished job until the agent's receipt arrives.
//!
//! - `gearcam/v1/station/submit` (query with a `JobRequest`): journal, then
//!   answer `accepted`; the request is published right after.
//! - `gearcam/v1/station/jobs[/{job}]` (query): the journal's view.
//! - Events of every job update the journal. Jobs without progress for
//!   `redrive` are re-driven with backoff: first the agent's store is asked for
//!   the job (a lost receipt), then the request is published again (every stage
//!   is idempotent; the agent answers a repeat with the original receipt).
//! - A job whose services or agent are offline (no liveliness token) waits, and
//!   is re-driven as soon as the missing token appears.
//!
//! Changes are applied in batches, one SQLite transaction each (group commit).

use std::collections::HashSet;
use std::path::PathBuf;
use std::time::Duration;

use gearcam_bus::query::Retry;
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::{
    decode, encode, keys, now_ms, DeliveryReply, JobEvent, JobId, JobList, JobRequest, StationReply,
};
use zenoh::query::Query;
use zenoh::sample::SampleKind;

use crate::journal::{Due, Journal, JournalError};

/// Configuration of the station service.
#[derive(Debug, Clone)]
pub struct StationConfig {
    /// The journal file.
    pub journal: PathBuf,
    /// A job without progress for this long is re-driven (then with backoff).
    pub redrive: Duration,
}

/// Errors of the station service.
#[derive(Debug, thiserror::Error)]
pub enum StationError {
    /// The journal failed.
    #[error(transparent)]
    Journal(#[from] JournalError),
    /// The bus failed.
    #[error(transparent)]
    Bus(#[from] BusError),
}

fn zerr(op: &'static str) -> impl FnOnce(zenoh::Error) -> BusError {
    move |e| BusError::Zenoh {
        op,
        detail: e.to_string(),
    }
}

const PIPELINE: [&str; 3] = ["knowledge", "model", "template"];

/// Runs the station until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    config: StationConfig,
    shutdown: CancellationToken,
) -> Result<(), StationError> {
    let mut journal = Journal::open(&config.journal)?;
    let redrive_ms = config.redrive.as_millis() as u64;
    let session = bus.session().clone();
    let submits = session
        .declare_queryable(keys::STATION_SUBMIT)
        .await
        .map_err(zerr("declare queryable"))?;
    let views = session
        .declare_queryable(format!("{}/station/jobs/**", keys::PREFIX))
        .await
        .map_err(zerr("declare queryable"))?;
    let list_view = session
        .declare_queryable(keys::STATION_JOBS)
        .await
        .map_err(zerr("declare queryable"))?;
    let events = session
        .declare_subscriber(keys::ALL_JOB_EVENTS)
        .await
        .map_err(zerr("declare subscriber"))?;
    let alive_sub = session
        .liveliness()
        .declare_subscriber(format!("{}/alive/**", keys::PREFIX))
        .history(true)
        .await
        .map_err(zerr("liveliness subscriber"))?;
    let _token = bus.alive_token(keys::STATION_SERVICE).await?;
    let mut alive: HashSet<String> = HashSet::new();
    // Every unfinished job is due at start: a restarted station finishes its journal.
    let woken = journal.wake(None, now_ms())?;
    tracing::info!(journal = %config.journal.display(), unfinished = woken, "station serving");
    let mut tick = tokio::time::interval(Duration::from_millis(100));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    loop {
        let mut new_submits: Vec<Query> = Vec::new();
        let mut new_events: Vec<JobEvent> = Vec::new();
        let mut drive_now = false;
        tokio::select! {
            _ = shutdown.cancelled() => break,
            q = submits.recv_async() => if let Ok(q) = q { new_submits.push(q) },
            s = events.recv_async() => if let Ok(s) = s {
                if let Ok(ev) = decode::<JobEvent>(&s.payload().to_bytes()) { new_events.push(ev) }
            },
            q = views.recv_async() => if let Ok(q) = q {
                let reply = view_reply(&journal, q.key_expr().as_str());
                answer_view(reply, q).await
            },
            q = list_view.recv_async() => if let Ok(q) = q {
                let reply = view_reply(&journal, q.key_expr().as_str());
                answer_view(reply, q).await
            },
            s = alive_sub.recv_async() => if let Ok(s) = s {
                let name = s.key_expr().as_str().trim_start_matches(&format!("{}/alive/", keys::PREFIX)).to_string();
                if s.kind() == SampleKind::Put {
                    if let Some(machine) = name.strip_prefix("agent/") {
                        journal.wake(Some(machine), now_ms())?;
                    } else if PIPELINE.contains(&name.as_str()) {
                        journal.wake(None, now_ms())?;
                    }
                    alive.insert(name);
                } else {
                    alive.remove(&name);
                }
            },
            _ = tick.tick() => drive_now = true,
        }
        // Group commit: take whatever else is already waiting.
        while new_submits.len() < 1024 {
            match submits.try_recv() {
                Ok(Some(q)) => new_submits.push(q),
                _ => break,
            }
        }
        while new_events.len() < 4096 {
            match events.try_recv() {
                Ok(Some(s)) => {
                    if let Ok(ev) = decode::<JobEvent>(&s.payload().to_bytes()) {
                        new_events.push(ev);
                    }
                }
                _ => break,
            }
        }
        if !new_submits.is_empty() || !new_events.is_empty() {
            let now = now_ms();
            let (replies, to_send) = journal.batch(|j| {
                for ev in &new_events {
                    if let Err(e) = j.apply(ev, now, redrive_ms) {
                        tracing::error!(job = %ev.job_id, error = %e, "cannot journal event");
                    }
                }
                let mut replies = Vec::new();
                let mut to_send = Vec::new();
                for q in new_submits {
                    let payload = q
                        .payload()
                        .map(|p| p.to_bytes().into_owned())
                        .unwrap_or_default();
                    let reply = match decode::<JobRequest>(&payload) {
                        Err(e) => StationReply::Refused {
                            errors: vec![gearcam_bus::stage::codec_error::<JobRequest>(
                                gearcam_proto::Stage::Station,
                                &e,
                            )],
                        },
                        Ok(req) => match j.submit(&req, now) {
                            Ok(status) => {
                                if status.attempts == 0 {
                                    if let Ok(request) = encode(&req) {
                                        to_send.push(Due {
                                            job: req.job_id.clone(),
                                            machine: req.spec.job.machine.clone(),
                                            state: status.state,
                                            attempts: 0,
                                            request,
                                        });
                                    }
                                }
                                StationReply::Accepted {
                                    status: Box::new(status),
                                }
                            }
                            Err(e) => StationReply::Refused { errors: vec![e] },
                        },
                    };
                    replies.push((q, reply));
                }
                (replies, to_send)
            })?;
            // The journal is committed: acknowledge, then drive the new jobs.
            for (q, reply) in replies {
                reply_message(q, &reply).await;
            }
            if !to_send.is_empty() {
                let updates = drive(&bus, &alive, redrive_ms, to_send).await?;
                journal.batch(|j| apply_updates(j, updates))??;
            }
        }
        if drive_now {
            let due = journal.due(now_ms(), 2048)?;
            if !due.is_empty() {
                let updates = drive(&bus, &alive, redrive_ms, due).await?;
                journal.batch(|j| apply_updates(j, updates))??;
            }
        }
    }
    tracing::info!("station stopped");
    Ok(())
}

/// A journal change decided while driving jobs.
#[derive(Debug)]
enum Update {
    Waiting(JobId, String, u64),
    Sent(JobId, u64),
    Delivered(Box<gearcam_proto::DeliveryReceipt>),
}

fn apply_updates(j: &Journal, updates: Vec<Update>) -> Result<(), JournalError> {
    let now = now_ms();
    for u in updates {
        match u {
            Update::Waiting(job, reason, next) => j.waiting(&job, &reason, now, next)?,
            Update::Sent(job, next) => j.sent(&job, now, next)?,
            Update::Delivered(receipt) => {
                j.delivered(&receipt, now)?;
            }
        }
    }
    Ok(())
}

/// Sends (or re-drives) jobs; returns the journal changes to commit.
async fn drive(
    bus: &Bus,
    alive: &HashSet<String>,
    redrive_ms: u64,
    due: Vec<Due>,
) -> Result<Vec<Update>, StationError> {
    let now = now_ms();
    let mut updates = Vec::with_capacity(due.len());
    for d in due {
        let agent = keys::agent_service(&d.machine);
        let missing: Vec<&str> = PIPELINE
            .iter()
            .copied()
            .chain(std::iter::once(agent.as_str()))
            .filter(|s| !alive.contains(*s))
            .collect();
        if !missing.is_empty() {
            updates.push(Update::Waiting(
                d.job,
                format!("offline: {}", missing.join(", ")),
                now + 1000,
            ));
            continue;
        }
        if d.attempts > 0 {
            // A re-drive: the receipt may have been lost; ask the agent's store first.
            let retry = Retry {
                timeout: Duration::from_secs(2),
                attempts: 1,
                pause: Duration::ZERO,
            };
            let asked = bus
                .call::<JobRequest, DeliveryReply>(
                    &keys::store_job(&d.machine, &d.job),
                    None,
                    retry,
                )
                .await;
            if let Ok(DeliveryReply::Stored { receipt }) = asked {
                tracing::info!(job = %d.job, "receipt recovered from the agent's store");
                updates.push(Update::Delivered(Box::new(receipt)));
                continue;
            }
            tracing::info!(job = %d.job, attempt = d.attempts + 1, state = d.state.as_str(), "job re-driven");
        }
        let backoff = redrive_ms
            .saturating_mul(1 << d.attempts.min(4))
            .min(60_000);
        bus.put_bytes(&keys::job_request(&d.job), d.request).await?;
        updates.push(Update::Sent(d.job, now + backoff));
    }
    Ok(updates)
}

async fn reply_message<T: gearcam_proto::Message>(q: Query, msg: &T) {
    let sent = match encode(msg) {
        Ok(bytes) => q.reply(q.key_expr().clone(), bytes).await,
        Err(e) => q.reply_err(e.to_string().into_bytes()).await,
    };
    if let Err(e) = sent {
        tracing::warn!(error = %e, "cannot reply");
    }
}

/// The reply to a view query (`jobs` or `jobs/{job}`), computed from the journal.
fn view_reply(journal: &Journal, key: &str) -> Result<Vec<u8>, String> {
    if key == keys::STATION_JOBS {
        let jobs = journal.list().map_err(|e| e.to_string())?;
        return encode(&JobList { jobs }).map_err(|e| e.to_string());
    }
    let job = key
        .rsplit('/')
        .next()
        .and_then(|j| JobId::new(j).ok())
        .ok_or_else(|| format!("not a job key: {key}"))?;
    match journal.status(&job).map_err(|e| e.to_string())? {
        Some(s) => encode(&s).map_err(|e| e.to_string()),
        None => Err(format!("unknown job {job}: not in this station's journal")),
    }
}

async fn answer_view(reply: Result<Vec<u8>, String>, q: Query) {
    let sent = match reply {
        Ok(bytes) => q.reply(q.key_expr().clone(), bytes).await,
        Err(e) => q.reply_err(e.into_bytes()).await,
    };
    if let Err(e) = sent {
        tracing::warn!(error = %e, "cannot reply");
    }
}
