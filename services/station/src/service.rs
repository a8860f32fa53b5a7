//! The planning station as a service: it journals submitted jobs durably,
//! drives them through the pipeline, follows their events, and re-drives every
//! unfinished job until the agent's receipt arrives.
//!
//! - `gearcam/v1/station/submit/{user}` (query with a `JobRequest`): journal
//!   `user` as the submitter (a key without one is refused), check the ids
//!   and that the knowledge base knows the machine, journal, then answer
//!   `accepted` and publish the `accepted` event; the request is published
//!   right after. A resubmission (same job id, same spec) is answered with the
//!   job's status; the same id with another spec is refused.
//! - `gearcam/v1/station/jobs[/{job}]` (query): the journal's view, always a
//!   typed `StationReply`.
//! - `gearcam/v1/station/jobs/{job}/model` (query): the job's model as the
//!   model service published it, or a `StationReply::Refused` (module
//!   `models`).
//! - `gearcam/v1/station/cancel/{user}/{job}` (query with a
//!   `CancelRequest`): a job not yet final ends `cancelled`, by `user`, and a `cancelled` event is
//!   published; the agent, which asks the station before it stores, never
//!   stores it after. A final job is refused (`JOB_FINAL`), a cancelled one
//!   answered with its status again.
//! - `gearcam/v1/station/journaled/{machine}` (query with `JobIds`, an
//!   agent's question before it stores): the status of each asked job of that
//!   machine, read from the committed journal beside the loop (module
//!   `journaled`).
//! - Events of every job update the journal, and each job's model is
//!   journaled beside it as the model service publishes it (checked to be
//!   the model of the journaled request). Jobs without progress for
//!   `redrive` are re-driven with backoff: first the agent's store is asked for
//!   the job (a lost receipt), then the request is published again (every stage
//!   is idempotent; the agent answers a repeat with the original receipt).
//! - A job whose services or agent are offline (no liveliness token) waits
//!   (a `waiting` event names what is missing), and is re-driven as soon as
//!   the missing token appears.
//!
//! Changes are applied in batches, one SQLite transaction each (group commit).
//! A submission is checked (`submit`) before the transaction that journals it.

use gearcam_proto::Code;
use std::collections::HashSet;
use std::path::PathBuf;
use std::time::Duration;

use gearcam_bus::query::Retry;
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::{
    decode, encode, keys, now_ms, CancelRequest, DeliveryReply, EventKind, JobError, JobEvent,
    JobId, JobRequest, JobState, MachineId, Stage, StationReply,
};
use zenoh::handlers::FifoChannelHandler;
use zenoh::pubsub::Subscriber;
use zenoh::query::{Query, Queryable};
use zenoh::sample::{Sample, SampleKind};
use zenoh::Session;

use crate::journal::{Due, Durability, Journal, JournalError};

mod journaled;
mod models;
mod submit;

use models::Published;
use submit::{check_submits, Verdict};

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
    let inputs = Inputs::declare(bus.session()).await?;
    // The agents' question is answered beside the loop, and stops with it.
    let answering = shutdown.child_token();
    let _stop_answering = answering.clone().drop_guard();
    journaled::serve(bus.session(), &config.journal, answering).await?;
    let _token = bus.alive_token(keys::STATION_SERVICE).await?;
    let mut alive: HashSet<String> = HashSet::new();
    let mut machines: HashSet<MachineId> = HashSet::new();
    // Every unfinished job is due at start: a restarted station finishes its journal.
    let woken = journal.wake(None, now_ms())?;
    tracing::info!(journal = %config.journal.display(), unfinished = woken, "station serving");
    let mut tick = tokio::time::interval(Duration::from_millis(100));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    // Jobs being driven: each in its own task (a re-drive may wait on a
    // frozen agent's store), at most MAX_IN_FLIGHT; the loop never awaits one.
    let mut drives = Drives::default();
    loop {
        let mut new_submits: Vec<Query> = Vec::new();
        let mut new_events: Vec<(String, JobEvent)> = Vec::new();
        let mut new_models: Vec<Published> = Vec::new();
        let mut new_views: Vec<Query> = Vec::new();
        let mut drive_now = false;
        tokio::select! {
            _ = shutdown.cancelled() => break,
            q = inputs.submits.recv_async() => if let Ok(q) = q { new_submits.push(q) },
            s = inputs.events.recv_async() => if let Ok(s) = s {
                if let Some(ev) = reported(&s) { new_events.push(ev) }
            },
            s = inputs.models.recv_async() => if let Ok(s) = s { new_models.push(Published::of(&s)) },
            q = inputs.views.recv_async() => if let Ok(q) = q { new_views.push(q) },
            q = inputs.list_view.recv_async() => if let Ok(q) = q { new_views.push(q) },
            q = inputs.cancels.recv_async() => if let Ok(q) = q {
                let (reply, cancelled) = cancel_reply(&journal, &q);
                reply_message(q, &reply).await;
                if let Some((job, by)) = cancelled {
                    publish_cancelled(&bus, job, by).await;
                }
            },
            s = inputs.alive.recv_async() => if let Ok(s) = s {
                track_alive(&journal, &mut alive, &s)?;
            },
            Some(done) = drives.tasks.join_next_with_id(), if !drives.tasks.is_empty() => {
                let mut updates = Vec::new();
                drives.finished(done, &mut updates);
                while let Some(done) = drives.tasks.try_join_next_with_id() {
                    drives.finished(done, &mut updates);
                }
                let announce = waiting_events(&updates);
                journal.batch(Durability::Normal, |j| apply_updates(j, updates))??;
                // Journaled first: a client that sees the event and asks for
                // the job's status reads a status that has it.
                for (job, reason) in announce {
                    let waiting = EventKind::Waiting { reason };
                    if let Err(e) = bus.event(&job, Stage::Station, waiting).await {
                        tracing::warn!(%job, error = %e, "cannot publish the waiting event");
                    }
                }
            },
            _ = tick.tick() => drive_now = true,
        }
        inputs.take_waiting(
            &mut new_views,
            &mut new_submits,
            &mut new_events,
            &mut new_models,
        );
        if !new_submits.is_empty() || !new_events.is_empty() || !new_models.is_empty() {
            // Ids and machines are checked before the journal's transaction:
            // the machine check may ask the knowledge base.
            let checked = check_submits(&bus, &mut machines, new_submits).await;
            let now = now_ms();
            // A model before the events of the same batch: the job's
            // `delivered` among them must not end it before its model is kept.
            // A submission is acknowledged once durable, and a model is
            // published once (a re-drive that finds the receipt does not
            // make it again); events only need to survive the process (the
            // journal's Durability).
            let durability = if checked.is_empty() && new_models.is_empty() {
                Durability::Normal
            } else {
                Durability::Full
            };
            let (replies, to_send) = journal.batch(durability, |j| {
                models::journal_models(j, &new_models);
                journal_batch(j, &new_events, checked, now, redrive_ms)
            })?;
            // The journal is committed: acknowledge, then drive the new jobs.
            acknowledge(&bus, replies, &to_send).await;
            drives.start(&bus, &alive, redrive_ms, to_send);
        }
        // A view is answered once the events that reached the station
        // before it are journaled: a client that saw a job's event and then
        // asks for its status reads a status that has it.
        answer_views(&mut journal, new_views).await;
        if drive_now && drives.has_room() {
            let due = journal.due(now_ms(), 2048)?;
            drives.start(&bus, &alive, redrive_ms, due);
        }
    }
    // Prompt: the drives in flight are dropped; their jobs stay due in the
    // journal and are driven again at the next start.
    drives.tasks.abort_all();
    tracing::info!("station stopped");
    Ok(())
}

/// The station's inputs on the bus: the queries it answers, the job events
/// it journals and the liveliness tokens of the services a job waits for.
struct Inputs {
    submits: Queryable<FifoChannelHandler<Query>>,
    views: Queryable<FifoChannelHandler<Query>>,
    list_view: Queryable<FifoChannelHandler<Query>>,
    cancels: Queryable<FifoChannelHandler<Query>>,
    events: Subscriber<FifoChannelHandler<Sample>>,
    models: Subscriber<FifoChannelHandler<Sample>>,
    alive: Subscriber<FifoChannelHandler<Sample>>,
}

impl Inputs {
    /// Declares every queryable and subscriber, before the station's own
    /// token says it serves; the liveliness subscriber takes the tokens
    /// already present (history) so a job waits only for what is offline.
    async fn declare(session: &Session) -> Result<Inputs, StationError> {
        let submits = session
            .declare_queryable(keys::STATION_SUBMIT_ANY)
            .await
            .map_err(zerr("declare queryable"))?;
        let views = session
            .declare_queryable(keys::STATION_JOB_ANY)
            .await
            .map_err(zerr("declare queryable"))?;
        let list_view = session
            .declare_queryable(keys::STATION_JOBS)
            .await
            .map_err(zerr("declare queryable"))?;
        let cancels = session
            .declare_queryable(keys::STATION_CANCEL_ANY)
            .await
            .map_err(zerr("declare queryable"))?;
        let events = session
            .declare_subscriber(keys::ALL_JOB_EVENTS)
            .await
            .map_err(zerr("declare subscriber"))?;
        let models = session
            .declare_subscriber(keys::ALL_JOB_MODELS)
            .await
            .map_err(zerr("declare subscriber"))?;
        let alive = session
            .liveliness()
            .declare_subscriber(keys::ALIVE_ANY)
            .history(true)
            .await
            .map_err(zerr("liveliness subscriber"))?;
        Ok(Inputs {
            submits,
            views,
            list_view,
            cancels,
            events,
            models,
            alive,
        })
    }

    /// Group commit: takes whatever else is already waiting (up to a bound
    /// per batch), so one transaction journals them all. Views are taken
    /// first: every event that reached the station before one of them is
    /// then taken too, and journaled before the view is answered. A view
    /// waits for one journal commit, not for one per query ahead of it.
    fn take_waiting(
        &self,
        new_views: &mut Vec<Query>,
        new_submits: &mut Vec<Query>,
        new_events: &mut Vec<(String, JobEvent)>,
        new_models: &mut Vec<Published>,
    ) {
        while new_views.len() < 1024 {
            match self.views.try_recv() {
                Ok(Some(q)) => new_views.push(q),
                _ => break,
            }
        }
        while new_submits.len() < 1024 {
            match self.submits.try_recv() {
                Ok(Some(q)) => new_submits.push(q),
                _ => break,
            }
        }
        // With views taken, every event before them is taken, however many.
        let events_cap = if new_views.is_empty() {
            4096
        } else {
            usize::MAX
        };
        while new_events.len() < events_cap {
            match self.events.try_recv() {
                Ok(Some(s)) => {
                    if let Some(ev) = reported(&s) {
                        new_events.push(ev);
                    }
                }
                _ => break,
            }
        }
        while new_models.len() < models::MAX_MODELS_PER_BATCH {
            match self.models.try_recv() {
                Ok(Some(s)) => new_models.push(Published::of(&s)),
                _ => break,
            }
        }
    }
}

/// Publishes the `cancelled` event of a job cancelled now, after its reply.
async fn publish_cancelled(bus: &Bus, job: JobId, by: String) {
    tracing::info!(%job, by, "job cancelled");
    if let Err(e) = bus
        .event(&job, Stage::Station, EventKind::Cancelled { by })
        .await
    {
        tracing::warn!(%job, error = %e, "cannot publish the cancelled event");
    }
}

/// Follows the liveliness tokens: a service or agent that appears wakes the
/// jobs waiting for it (an agent its machine's jobs, a pipeline stage every
/// job); one that disappears makes the next drives wait.
fn track_alive(
    journal: &Journal,
    alive: &mut HashSet<String>,
    s: &Sample,
) -> Result<(), StationError> {
    let name = keys::alive_of(s.key_expr().as_str())
        .unwrap_or_default()
        .to_string();
    if s.kind() == SampleKind::Put {
        if let Some(machine) = keys::agent_machine_of(&name) {
            journal.wake(Some(machine), now_ms())?;
        } else if PIPELINE.contains(&name.as_str()) {
            journal.wake(None, now_ms())?;
        }
        alive.insert(name);
    } else {
        alive.remove(&name);
    }
    Ok(())
}

/// One group commit, inside the journal's transaction: journals the new
/// events, then the checked submissions; returns each query's reply and
/// the jobs accepted now, to send once the transaction is committed.
fn journal_batch(
    j: &Journal,
    new_events: &[(String, JobEvent)],
    checked: Vec<(Query, Verdict)>,
    now: u64,
    redrive_ms: u64,
) -> (Vec<(Query, StationReply)>, Vec<Due>) {
    for (reporter, ev) in new_events {
        if let Err(e) = j.apply(reporter, ev, now, redrive_ms) {
            tracing::error!(job = %ev.job_id, error = %e, "cannot journal event");
        }
    }
    let mut replies = Vec::new();
    let mut to_send = Vec::new();
    for (q, verdict) in checked {
        let reply = match verdict {
            Err(errors) => StationReply::Refused { errors },
            Ok(req) => match j.submit(&req, now) {
                Ok(status) => {
                    if status.attempts == 0 && status.state == gearcam_proto::JobState::Accepted {
                        if let Ok(request) = encode(&req) {
                            to_send.push(Due {
                                job: req.job_id.clone(),
                                machine: req.spec.job.machine.clone(),
                                state: status.state,
                                attempts: 0,
                                waiting_for: None,
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
}

/// Once the journal is committed: answers every submission, then publishes
/// the `accepted` event of each job accepted now.
async fn acknowledge(bus: &Bus, replies: Vec<(Query, StationReply)>, to_send: &[Due]) {
    for (q, reply) in replies {
        reply_message(q, &reply).await;
    }
    for d in to_send {
        let accepted = EventKind::Accepted {
            machine: d.machine.clone(),
        };
        if let Err(e) = bus.event(&d.job, Stage::Station, accepted).await {
            tracing::warn!(job = %d.job, error = %e, "cannot publish the accepted event");
        }
    }
}

/// Jobs driven at most at once: each may wait up to the store query's
/// timeout on an agent that does not answer.
const MAX_IN_FLIGHT: usize = 64;

/// The drives in flight.
#[derive(Default)]
struct Drives {
    tasks: tokio::task::JoinSet<Option<Update>>,
    /// The job of each running task.
    jobs: std::collections::HashMap<tokio::task::Id, JobId>,
    in_flight: HashSet<JobId>,
}

impl Drives {
    fn has_room(&self) -> bool {
        self.tasks.len() < MAX_IN_FLIGHT
    }

    /// Starts a drive for each job not already in flight, while there is room;
    /// the others stay due in the journal for a later tick.
    fn start(&mut self, bus: &Bus, alive: &HashSet<String>, redrive_ms: u64, due: Vec<Due>) {
        for d in due {
            if !self.has_room() {
                break;
            }
            if self.in_flight.contains(&d.job) {
                continue;
            }
            let agent = keys::agent_service(&d.machine);
            let missing: Vec<String> = PIPELINE
                .iter()
                .copied()
                .chain(std::iter::once(agent.as_str()))
                .filter(|s| !alive.contains(*s))
                .map(str::to_string)
                .collect();
            self.in_flight.insert(d.job.clone());
            let job = d.job.clone();
            let bus = bus.clone();
            let task = self
                .tasks
                .spawn(async move { drive(&bus, missing, redrive_ms, d).await });
            self.jobs.insert(task.id(), job);
        }
    }

    /// Takes a finished drive's journal change.
    fn finished(
        &mut self,
        done: Result<(tokio::task::Id, Option<Update>), tokio::task::JoinError>,
        updates: &mut Vec<Update>,
    ) {
        let id = match done {
            Ok((id, update)) => {
                updates.extend(update);
                id
            }
            Err(e) => {
                // A panicked drive (a bug): its job stays due in the journal.
                tracing::error!(error = %e, "a drive failed");
                e.id()
            }
        };
        if let Some(job) = self.jobs.remove(&id) {
            self.in_flight.remove(&job);
        }
    }
}

/// A journal change decided while driving jobs.
#[derive(Debug)]
enum Update {
    /// The job waits for what the reason names, until the time given; the
    /// flag says its reason is new, so its `waiting` event is published
    /// once the change is journaled.
    Waiting(JobId, String, u64, bool),
    Sent(JobId, u64),
    Delivered(Box<gearcam_proto::DeliveryReceipt>),
}

/// The `waiting` events to publish for `updates` once they are journaled.
fn waiting_events(updates: &[Update]) -> Vec<(JobId, String)> {
    updates
        .iter()
        .filter_map(|u| match u {
            Update::Waiting(job, reason, _, true) => Some((job.clone(), reason.clone())),
            _ => None,
        })
        .collect()
}

fn apply_updates(j: &Journal, updates: Vec<Update>) -> Result<(), JournalError> {
    let now = now_ms();
    for u in updates {
        match u {
            Update::Waiting(job, reason, next, _) => j.waiting(&job, &reason, now, next)?,
            Update::Sent(job, next) => j.sent(&job, now, next)?,
            Update::Delivered(receipt) => {
                j.delivered(&receipt, now)?;
            }
        }
    }
    Ok(())
}

/// Sends (or re-drives) one job; returns the journal change to commit, or
/// nothing when the bus failed (the job stays due and is driven again).
async fn drive(bus: &Bus, missing: Vec<String>, redrive_ms: u64, d: Due) -> Option<Update> {
    let now = now_ms();
    if !missing.is_empty() {
        let reason = format!("offline: {}", missing.join(", "));
        let new = d.waiting_for.as_deref() != Some(reason.as_str());
        return Some(Update::Waiting(d.job, reason, now + 1000, new));
    }
    if d.attempts > 0 {
        // A re-drive: the receipt may have been lost; ask the agent's store first.
        let retry = Retry {
            timeout: Duration::from_secs(2),
            attempts: 1,
            pause: Duration::ZERO,
        };
        let asked = bus
            .call::<JobRequest, DeliveryReply>(&keys::store_job(&d.machine, &d.job), None, retry)
            .await;
        if let Ok(DeliveryReply::Stored { receipt }) = asked {
            tracing::info!(job = %d.job, "receipt recovered from the agent's store");
            return Some(Update::Delivered(Box::new(receipt)));
        }
        tracing::info!(job = %d.job, attempt = d.attempts + 1, state = d.state.as_str(), "job re-driven");
    }
    let backoff = redrive_ms
        .saturating_mul(1 << d.attempts.min(4))
        .min(60_000);
    match bus.put_bytes(&keys::job_request(&d.job), d.request).await {
        Ok(()) => Some(Update::Sent(d.job, now + backoff)),
        Err(e) => {
            tracing::warn!(job = %d.job, error = %e, "cannot send the job; it stays due");
            None
        }
    }
}

/// A job event with its reporter (the key's last chunk), if it decodes.
fn reported(s: &zenoh::sample::Sample) -> Option<(String, JobEvent)> {
    let reporter = keys::reporter_of(s.key_expr().as_str())?.to_string();
    let ev = decode::<JobEvent>(&s.payload().to_bytes()).ok()?;
    Some((reporter, ev))
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

/// The reply to a cancel query, and the job and who when it was cancelled
/// now (the event to publish).
fn cancel_reply(journal: &Journal, q: &Query) -> (StationReply, Option<(JobId, String)>) {
    let refused = |error: JobError| {
        (
            StationReply::Refused {
                errors: vec![error],
            },
            None,
        )
    };
    let key = q.key_expr().as_str();
    let Some((user, raw)) = keys::station_cancel_of(key) else {
        return refused(Stage::Station.error(
            Code::BAD_KEY,
            "key",
            keys::STATION_CANCEL_FORM,
            key,
            "a job is cancelled on the key of the user who cancels it; the station records that user",
        ));
    };
    let job = match JobId::new(raw) {
        Ok(job) => job,
        Err(e) => return refused(JobError::bad_id(Stage::Station, "job_id", &e)),
    };
    let payload = q
        .payload()
        .map(|p| p.to_bytes().into_owned())
        .unwrap_or_default();
    // Who cancels is the user of the key (a secure router grants it to that
    // login only), not the name in the payload.
    let by = match decode::<CancelRequest>(&payload) {
        Ok(_) => user.to_string(),
        Err(e) => {
            return refused(gearcam_bus::stage::codec_error::<CancelRequest>(
                Stage::Station,
                &e,
            ))
        }
    };
    if !gearcam_proto::delivery::valid_by(&by) {
        return refused(Stage::Station.error(
            Code::BAD_CANCEL_REQUEST,
            "by",
            "who cancels the job: 1 to 64 characters on one line",
            by.chars().take(80).collect::<String>(),
            "a cancellation is recorded with the name of the person who decided",
        ));
    }
    let before = match journal.status(&job) {
        Ok(s) => s,
        Err(e) => return refused(journal_error(e)),
    };
    let Some(before) = before else {
        return refused(unknown_job(&job));
    };
    if before.state == JobState::Cancelled {
        return (
            StationReply::Status {
                status: Box::new(before),
            },
            None,
        );
    }
    if before.state.is_final() {
        return refused(Stage::Station.error(
            Code::JOB_FINAL,
            "job_id",
            "a job not yet delivered, failed or superseded",
            format!("{job}: {}", before.state.as_str()),
            "the job has ended already; there is nothing to cancel",
        ));
    }
    match journal.cancel(&job, &by, now_ms()) {
        Ok(Some(status)) if status.state == JobState::Cancelled => (
            StationReply::Status {
                status: Box::new(status),
            },
            Some((job, by)),
        ),
        // It ended on its own in between: its status says how.
        Ok(Some(status)) => refused(Stage::Station.error(
            Code::JOB_FINAL,
            "job_id",
            "a job not yet delivered, failed or superseded",
            format!("{job}: {}", status.state.as_str()),
            "the job has ended already; there is nothing to cancel",
        )),
        Ok(None) => refused(unknown_job(&job)),
        Err(e) => refused(journal_error(e)),
    }
}

fn unknown_job(job: &JobId) -> JobError {
    JobError::new(
        Stage::Station,
        Code::UNKNOWN_JOB,
        "job_id",
        "a job in this station's journal (gearcam jobs)",
        job.as_str(),
        "the station has no such job",
    )
}

fn journal_error(e: JournalError) -> JobError {
    JobError::new(
        Stage::Station,
        Code::JOURNAL_ERROR,
        "-",
        "a readable journal",
        e.to_string(),
        "the station could not read its journal; see its log",
    )
}

/// The answer to one view: bytes as kept (a model, a request) or a reply.
enum ViewAnswer {
    Kept(Result<Vec<u8>, JobError>),
    Reply(StationReply),
}

/// Answers the views taken (a job's status, model or request, the list,
/// a job's request), each from the journal as it now is. The answers
/// are read first and sent after, so no borrow of the journal is held
/// while a reply is sent.
async fn answer_views(journal: &mut Journal, views: Vec<Query>) {
    let answers: Vec<(Query, ViewAnswer)> = views
        .into_iter()
        .map(|q| {
            let journal = &*journal;
            let key = q.key_expr().as_str().to_string();
            let answer = if let Some(raw) = keys::station_job_model_of(&key) {
                ViewAnswer::Kept(models::answer(journal, raw))
            } else if let Some(raw) = keys::station_job_request_of(&key) {
                ViewAnswer::Kept(models::request_answer(journal, raw))
            } else {
                ViewAnswer::Reply(view_reply(journal, &key))
            };
            (q, answer)
        })
        .collect();
    for (q, answer) in answers {
        match answer {
            ViewAnswer::Kept(answer) => models::reply(q, answer).await,
            ViewAnswer::Reply(reply) => reply_message(q, &reply).await,
        }
    }
}

/// The reply to a view query (`jobs` or `jobs/{job}`), computed from the journal.
fn view_reply(journal: &Journal, key: &str) -> StationReply {
    let refused = |error: JobError| StationReply::Refused {
        errors: vec![error],
    };
    let unreadable = |e: JournalError| refused(journal_error(e));
    if key == keys::STATION_JOBS {
        return match journal.list() {
            Ok(jobs) => StationReply::Jobs { jobs },
            Err(e) => unreadable(e),
        };
    }
    let raw = keys::station_job_of(key).unwrap_or(key);
    let job = match JobId::new(raw) {
        Ok(job) => job,
        Err(e) => return refused(JobError::bad_id(Stage::Station, "job_id", &e)),
    };
    match journal.status(&job) {
        Ok(Some(status)) => StationReply::Status {
            status: Box::new(status),
        },
        Ok(None) => refused(unknown_job(&job)),
        Err(e) => unreadable(e),
    }
}
