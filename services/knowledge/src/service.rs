//! The knowledge service on the bus, three tasks over one database file:
//!
//! - the stage: subscribes to job requests, publishes process plans and
//!   `planned` events, reports typed errors, and records each planned job;
//!   the case base is held in memory (columnar, see [`crate::cbr`]) and
//!   reloaded when another connection has changed the database;
//! - the library queryables on `gearcam/v1/kb/**` and
//!   `gearcam/v1/kb-changes/**` ([`answer`]): list, read, add, change and
//!   remove records of every library; beside them the change log on
//!   `gearcam/v1/kb-log/**` and the confirmation of delivered jobs on
//!   `gearcam/v1/kb-confirm/**` ([`crate::answers`]);
//! - a subscriber to job events that marks jobs delivered, for the learning
//!   loop ([`crate::learn`]).

use gearcam_proto::Code;
use std::path::PathBuf;

use gearcam_bus::stage::{run_stage, Handled, Output};
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::plan::{KbOp, KbRecord, KbReply, KbRequest};
use gearcam_proto::{
    decode, encode, keys, EventKind, JobError, JobEvent, JobRequest, Message, Stage,
};
use rusqlite::Connection;
use serde_json::Value;
use zenoh::handlers::FifoChannelHandler;
use zenoh::pubsub::Subscriber;
use zenoh::query::{Query, Queryable};
use zenoh::sample::Sample;

use crate::cbr::CaseBase;
use crate::library::{self, Record};
pub use crate::library::{record_from_wire, record_to_wire};
use crate::{db, history, learn, KnowledgeError};

/// Configuration of the knowledge service.
#[derive(Debug, Clone)]
pub struct Config {
    /// The SQLite database file (created and seeded if missing).
    pub db_path: PathBuf,
}

/// The liveliness name of the knowledge service.
pub const SERVICE: &str = "knowledge";

fn zerr(op: &'static str) -> impl FnOnce(zenoh::Error) -> KnowledgeError {
    move |e| {
        KnowledgeError::Bus(BusError::Zenoh {
            op,
            detail: e.to_string(),
        })
    }
}

/// The case base in memory, reloaded when the database changed under it.
struct Cases {
    base: CaseBase,
    data_version: i64,
}

fn data_version(conn: &Connection) -> Result<i64, KnowledgeError> {
    Ok(conn.pragma_query_value(None, "data_version", |r| r.get(0))?)
}

impl Cases {
    fn load(conn: &Connection) -> Result<Cases, KnowledgeError> {
        Ok(Cases {
            data_version: data_version(conn)?,
            base: history::load_case_base(conn)?,
        })
    }

    fn refresh(&mut self, conn: &Connection) -> Result<(), KnowledgeError> {
        let v = data_version(conn)?;
        if v != self.data_version {
            self.base = history::load_case_base(conn)?;
            self.data_version = v;
            tracing::info!(cases = self.base.len(), "case base reloaded");
        }
        Ok(())
    }
}

/// Runs the knowledge service until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    config: Config,
    shutdown: CancellationToken,
) -> Result<(), KnowledgeError> {
    let conn = db::open(&config.db_path)?;
    let kb_conn = db::open(&config.db_path)?;
    let events_conn = db::open(&config.db_path)?;
    let mut cases = Cases::load(&conn)?;
    tracing::info!(db = %config.db_path.display(), cases = cases.base.len(), "knowledge base open");

    // The library queryable and the events subscriber are in place before the
    // stage declares the service alive.
    let queryable = bus
        .session()
        .declare_queryable(keys::KB_ALL)
        .await
        .map_err(zerr("declare queryable"))?;
    let changes = bus
        .session()
        .declare_queryable(keys::KB_CHANGES_ALL)
        .await
        .map_err(zerr("declare queryable"))?;
    let log = bus
        .session()
        .declare_queryable(keys::KB_LOG_ALL)
        .await
        .map_err(zerr("declare queryable"))?;
    let confirm = bus
        .session()
        .declare_queryable(keys::KB_CONFIRM_ALL)
        .await
        .map_err(zerr("declare queryable"))?;
    let events = bus
        .session()
        .declare_subscriber(keys::ALL_JOB_EVENTS)
        .await
        .map_err(zerr("declare subscriber"))?;
    let queryables = LibraryQueryables {
        reads: queryable,
        changes,
        log,
        confirm,
    };
    let kb_task = tokio::spawn(serve_library(queryables, kb_conn, shutdown.clone()));
    let events_task = tokio::spawn(follow_events(events, events_conn, shutdown.clone()));

    let result = run_stage::<JobRequest, _>(
        &bus,
        keys::ALL_JOB_REQUESTS,
        SERVICE,
        Stage::Knowledge,
        shutdown.clone(),
        move |key, req| plan_request(&conn, &mut cases, key, &req),
    )
    .await;
    shutdown.cancel();
    let _ = kb_task.await;
    let _ = events_task.await;
    result?;
    Ok(())
}

/// The knowledge base's queryables, one per key space.
struct LibraryQueryables {
    /// `gearcam/v1/kb/**`: reads.
    reads: Queryable<FifoChannelHandler<Query>>,
    /// `gearcam/v1/kb-changes/**`: changes.
    changes: Queryable<FifoChannelHandler<Query>>,
    /// `gearcam/v1/kb-log/**`: the change log.
    log: Queryable<FifoChannelHandler<Query>>,
    /// `gearcam/v1/kb-confirm/**`: confirmations of delivered jobs.
    confirm: Queryable<FifoChannelHandler<Query>>,
}

/// Which queryable a query came to, and so which answer it gets.
#[derive(Debug, Clone, Copy)]
enum Asked {
    /// A library's read or change ([`answer`]).
    Library,
    /// The change log ([`crate::answers::answer_log`]).
    Log,
    /// A confirmation ([`crate::answers::answer_confirm`]).
    Confirm,
}

/// The library task: answers the queries on the read keys, the change
/// keys, the change log and the confirmations, one at a time on its own
/// connection, until `stop` is cancelled or a queryable closes.
async fn serve_library(q: LibraryQueryables, conn: Connection, stop: CancellationToken) {
    loop {
        let (query, asked) = tokio::select! {
            _ = stop.cancelled() => break,
            r = q.reads.recv_async() => match r {
                Ok(r) => (r, Asked::Library),
                Err(_) => break,
            },
            r = q.changes.recv_async() => match r {
                Ok(r) => (r, Asked::Library),
                Err(_) => break,
            },
            r = q.log.recv_async() => match r {
                Ok(r) => (r, Asked::Log),
                Err(_) => break,
            },
            r = q.confirm.recv_async() => match r {
                Ok(r) => (r, Asked::Confirm),
                Err(_) => break,
            },
        };
        let key = query.key_expr().as_str().to_string();
        let Some(bytes) = encoded_answer(&conn, &key, &query, asked) else {
            continue;
        };
        if let Err(e) = query.reply(query.key_expr().clone(), bytes).await {
            tracing::warn!(key, error = %e, "cannot send kb reply");
        }
    }
}

/// The encoded reply to one query of the knowledge base (a refusal is
/// logged with its first code), or `None` when the reply cannot be
/// encoded: that is logged and the query gets no reply.
fn encoded_answer(conn: &Connection, key: &str, query: &Query, asked: Asked) -> Option<Vec<u8>> {
    let payload = query
        .payload()
        .map(|p| p.to_bytes().into_owned())
        .unwrap_or_default();
    match asked {
        Asked::Library => {
            let reply = answer(conn, key, &payload);
            logged(key, &reply, &reply.errors)
        }
        Asked::Log => {
            let reply = crate::answers::answer_log(conn, key, &payload);
            logged(key, &reply, &reply.errors)
        }
        Asked::Confirm => {
            let reply =
                crate::answers::answer_confirm(conn, key, &payload, gearcam_proto::now_ms());
            if reply.errors.is_empty() {
                tracing::info!(key, job = reply.job_id, "job confirmed over the bus");
            }
            logged(key, &reply, &reply.errors)
        }
    }
}

/// `reply` encoded, its refusal (`errors`) logged with the first code.
fn logged<M: Message>(key: &str, reply: &M, errors: &[JobError]) -> Option<Vec<u8>> {
    if let Some(first) = errors.first() {
        tracing::info!(key, code = first.code.as_str(), "kb query refused");
    }
    match encode(reply) {
        Ok(b) => Some(b),
        Err(e) => {
            tracing::error!(key, error = %e, "cannot encode kb reply");
            None
        }
    }
}

/// The events task: records, for the learning loop, every delivery and
/// every later stage's refusal heard on the job events, on its own
/// connection, until `stop` is cancelled or the subscriber closes.
async fn follow_events(
    events: Subscriber<FifoChannelHandler<Sample>>,
    conn: Connection,
    stop: CancellationToken,
) {
    loop {
        let sample = tokio::select! {
            _ = stop.cancelled() => break,
            s = events.recv_async() => match s {
                Ok(s) => s,
                Err(_) => break,
            },
        };
        // The events already waiting are recorded in one transaction: one
        // WAL commit for all of them, not one each.
        let mut waiting = vec![sample];
        while waiting.len() < 1024 {
            match events.try_recv() {
                Ok(Some(s)) => waiting.push(s),
                _ => break,
            }
        }
        let tx = conn.unchecked_transaction();
        for sample in &waiting {
            record_event(&conn, sample);
        }
        if let Err(e) = tx.and_then(|tx| tx.commit()) {
            tracing::warn!(error = %e, events = waiting.len(), "cannot commit the recorded events");
        }
    }
}

/// Records one job event: a delivery marks the job delivered, a later
/// stage's failure marks it refused. An event that does not decode is
/// skipped; one its reporter does not own is ignored (and logged).
fn record_event(conn: &Connection, sample: &Sample) {
    let Ok(ev) = decode::<JobEvent>(&sample.payload().to_bytes()) else {
        return;
    };
    let reporter = keys::reporter_of(sample.key_expr().as_str()).unwrap_or_default();
    if !believed(reporter, &ev) {
        tracing::warn!(job = %ev.job_id, reporter, "ignored an event its reporter does not own");
        return;
    }
    if let EventKind::Delivered { receipt } = &ev.event {
        match learn::record_delivered(conn, receipt) {
            Ok(true) => {
                tracing::info!(job = %receipt.job_id, "job delivered; ready to confirm")
            }
            Ok(false) => {}
            Err(e) => {
                tracing::warn!(job = %receipt.job_id, error = %e, "cannot record delivery")
            }
        }
    }
    // A later stage's refusal: the job is never left `planned`. The
    // knowledge service's own refusals come before a job is planned.
    if matches!(ev.event, EventKind::Failed { .. }) && ev.stage != Stage::Knowledge {
        match learn::record_refused(conn, ev.job_id.as_str()) {
            Ok(true) => tracing::info!(job = %ev.job_id, "job refused by a later stage"),
            Ok(false) => {}
            Err(e) => {
                tracing::warn!(job = %ev.job_id, error = %e, "cannot record the refusal")
            }
        }
    }
}

/// Only the reporter that owns an event is believed: a delivery from the
/// machine's agent, a refusal from the stage's service.
fn believed(reporter: &str, ev: &JobEvent) -> bool {
    let machine = match &ev.event {
        EventKind::Delivered { receipt } => Some(receipt.machine.clone()),
        _ => None,
    };
    match &machine {
        Some(m) => keys::reporter_owns(reporter, ev, m),
        None if ev.stage == Stage::Agent => reporter.starts_with("agent-"),
        None => reporter == ev.stage.as_str(),
    }
}

/// The stage's handler: plans one job request, received on `key`, with the
/// case base reloaded first when the database changed (a reload that fails
/// is logged and the one in memory serves). Each family plans its own way;
/// every plan goes out on the job's plan key under its own envelope kind,
/// after its `planned` event.
fn plan_request(
    conn: &Connection,
    cases: &mut Cases,
    key: &str,
    req: &JobRequest,
) -> Result<Handled, Vec<JobError>> {
    if keys::job_of(key).as_ref() != Some(&req.job_id) {
        return Err(vec![JobError::job_id_mismatch(
            Stage::Knowledge,
            key,
            &req.job_id,
            "request",
        )]);
    }
    if let Err(e) = cases.refresh(conn) {
        tracing::warn!(error = %e, "cannot reload the case base; planning with the one in memory");
    }
    let planned = crate::family::plan(conn, &cases.base, req)?;
    let payload = planned.payload.map_err(|e| {
        vec![gearcam_bus::stage::codec_error::<JobRequest>(
            Stage::Knowledge,
            &e,
        )]
    })?;
    Ok(Handled {
        events: vec![EventKind::Planned {
            hob_id: planned.tool,
            confidence: planned.confidence,
        }],
        outputs: vec![Output {
            key: keys::job_plan(&req.job_id),
            payload,
        }],
    })
}

/// Answers one library query: the key names the library (and record), the
/// payload (possibly empty) is a [`KbRequest`]. Never fails: every problem is
/// a typed error in the reply.
pub fn answer(conn: &Connection, key: &str, payload: &[u8]) -> KbReply {
    let mut reply = KbReply {
        library: String::new(),
        records: vec![],
        errors: vec![],
    };
    match answer_inner(conn, key, payload, &mut reply.library) {
        Ok(records) => reply.records = records.iter().map(record_to_wire).collect(),
        Err(errors) => reply.errors = errors,
    }
    reply
}

/// Answers one library query (see [`answer`]), writing the library's name
/// into `library_name` as soon as the key gives it: the key is read, the
/// request decoded, the operation checked against the key, the change (if
/// any) recorded as its user's, and the operation done.
fn answer_inner(
    conn: &Connection,
    key: &str,
    payload: &[u8],
    library_name: &mut String,
) -> Result<Vec<Record>, Vec<JobError>> {
    let KbKey {
        user,
        library: name,
        id,
    } = kb_key(key)?;
    *library_name = name.clone();
    let lib = library::library(&name).map_err(|e| vec![e])?;
    let req = request_of(payload, id.is_some())?;
    check_key_for_op(key, &lib, id.as_deref(), user.is_some(), req.op)?;
    if let Some(user) = &user {
        act_as_user(conn, user)?;
    }
    let need_id = |op: &str| record_id(key, &lib, id.as_ref(), op);
    match req.op {
        KbOp::List => Ok(library::list(conn, &lib)?),
        KbOp::Get => get_record(conn, &lib, &need_id("get")?),
        KbOp::Add => add_record(conn, &lib, id.as_ref(), req.record.as_ref()),
        KbOp::Edit => {
            let id = need_id("edit")?;
            Ok(vec![library::edit(
                conn,
                &lib,
                &id,
                &record_from_wire(&req.set),
            )?])
        }
        KbOp::Remove => {
            let id = need_id("remove")?;
            Ok(vec![library::remove(conn, &lib, &id)?])
        }
    }
}

/// What a library query's key names.
struct KbKey {
    /// The user who asks, on a change key only.
    user: Option<String>,
    /// The library.
    library: String,
    /// The record, when the key names one.
    id: Option<String>,
}

/// A library query's key read: a read key, or a change key. A change key
/// names the user who asks, whom a secure router lets use only their own
/// name: the change is recorded as theirs.
fn kb_key(key: &str) -> Result<KbKey, Vec<JobError>> {
    match (keys::kb_of(key), keys::kb_change_of(key)) {
        (Some((library, id)), _) => Ok(KbKey {
            user: None,
            library,
            id,
        }),
        (None, Some((user, (library, id)))) => Ok(KbKey {
            user: Some(user),
            library,
            id,
        }),
        (None, None) => Err(vec![Stage::Knowledge.error(
            Code::BAD_KEY,
            "key",
            keys::KB_KEY_FORMS,
            key,
            "a knowledge-base query names a library and, for one record, its id",
        )]),
    }
}

/// The query's request: decoded from its payload, or, for an empty
/// payload, a read (get when the key names a record, list otherwise).
fn request_of(payload: &[u8], has_id: bool) -> Result<KbRequest, Vec<JobError>> {
    if payload.is_empty() {
        return Ok(KbRequest {
            op: if has_id { KbOp::Get } else { KbOp::List },
            record: None,
            set: KbRecord::new(),
            by: String::new(),
        });
    }
    decode::<KbRequest>(payload).map_err(|e| {
        vec![Stage::Knowledge.error(
            e.code(),
            "payload",
            format!(
                "a MessagePack {} message, schema {}",
                KbRequest::KIND,
                gearcam_proto::SCHEMA_VERSION
            ),
            e.to_string(),
            "the query's payload is not a knowledge-base request",
        )]
    })
}

/// Reads on the read keys, changes on the change keys (with who makes
/// them): the access control grants them to different users.
fn check_key_for_op(
    key: &str,
    lib: &library::Library,
    id: Option<&str>,
    on_change_key: bool,
    op: KbOp,
) -> Result<(), Vec<JobError>> {
    let is_change = matches!(op, KbOp::Add | KbOp::Edit | KbOp::Remove);
    if is_change == on_change_key {
        return Ok(());
    }
    let (expected, message) = if is_change {
        (
            format!(
                "list or get on {key}; a change on {}",
                keys::kb_change("{user}", lib.name, id)
            ),
            "changes to the knowledge base are asked on the kb-changes keys, which the access control grants to administrators",
        )
    } else {
        (
            format!(
                "add, edit or remove on {key}; reads on {}",
                keys::kb_library(lib.name)
            ),
            "the kb-changes keys take changes only",
        )
    };
    Err(vec![Stage::Knowledge.error(
        Code::KB_WRONG_KEY,
        "op",
        expected,
        format!("{op:?}").to_lowercase(),
        message,
    )])
}

/// Names the user of a change key as the one acting, so that the audit
/// trail records the change as theirs.
fn act_as_user(conn: &Connection, user: &str) -> Result<(), Vec<JobError>> {
    crate::audit::acting_as(conn, user).map_err(|e| {
        vec![Stage::Knowledge.error(
            Code::KNOWLEDGE_BASE_ERROR,
            "-",
            "a writable knowledge base",
            e.to_string(),
            "the change could not be recorded",
        )]
    })
}

/// The record's id from the key, which `op` (get, edit, remove) needs.
fn record_id(
    key: &str,
    lib: &library::Library,
    id: Option<&String>,
    op: &str,
) -> Result<String, Vec<JobError>> {
    id.cloned().ok_or_else(|| {
        vec![Stage::Knowledge.error(
            Code::MISSING_ID,
            "key",
            keys::kb_record_form(lib.name),
            key,
            format!("{op} needs the record's id in the key"),
        )]
    })
}

/// Get: the one record of that id, or a typed error when there is none.
fn get_record(
    conn: &Connection,
    lib: &library::Library,
    id: &str,
) -> Result<Vec<Record>, Vec<JobError>> {
    match library::get(conn, lib, id)? {
        Some(r) => Ok(vec![r]),
        None => Err(vec![Stage::Knowledge.error(
            Code::NOT_FOUND,
            lib.key,
            format!("an existing {} id", lib.name),
            id,
            format!("there is no record {id:?} in {}", lib.name),
        )]),
    }
}

/// Add: the whole record, whose key is the id in the query's key when that
/// names one (filled in when the record leaves it out).
fn add_record(
    conn: &Connection,
    lib: &library::Library,
    id: Option<&String>,
    rec: Option<&KbRecord>,
) -> Result<Vec<Record>, Vec<JobError>> {
    let Some(rec) = rec else {
        return Err(vec![Stage::Knowledge.error(
            Code::FIELD_MISSING,
            "record",
            "the record to add",
            "nothing",
            "an add request carries the whole record",
        )]);
    };
    let mut rec = record_from_wire(rec);
    if let Some(id) = id {
        match rec.get(lib.key) {
            None => {
                rec.insert(lib.key.to_string(), Value::from(id.as_str()));
            }
            Some(v) if v.as_str() == Some(id.as_str()) => {}
            Some(v) => {
                return Err(vec![Stage::Knowledge.error(
                    Code::ID_MISMATCH,
                    lib.key,
                    id.as_str(),
                    library::cell(v),
                    "the record's key differs from the id in the query's key",
                )])
            }
        }
    }
    Ok(vec![library::add(conn, lib, &rec)?])
}
