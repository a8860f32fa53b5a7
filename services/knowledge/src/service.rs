//! The knowledge service on the bus, three tasks over one database file:
//!
//! - the stage: subscribes to job requests, publishes process plans and
//!   `planned` events, reports typed errors, and records each planned job;
//!   the case base is held in memory (columnar, see [`crate::cbr`]) and
//!   reloaded when another connection has changed the database;
//! - the library queryable on `gearcam/v1/kb/**` ([`answer`]): list, read,
//!   add, change and remove records of every library;
//! - a subscriber to job events that marks jobs delivered, for the learning
//!   loop ([`crate::learn`]).

use gearcam_proto::Code;
use std::path::PathBuf;

use gearcam_bus::stage::{run_stage, Handled, Output};
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::plan::{KbOp, KbRecord, KbReply, KbRequest, KbValue};
use gearcam_proto::{
    decode, encode, keys, EventKind, JobError, JobEvent, JobRequest, Message, Stage,
};
use rusqlite::Connection;
use serde_json::Value;

use crate::cbr::CaseBase;
use crate::library::{self, Record};
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
    let events = bus
        .session()
        .declare_subscriber(keys::ALL_JOB_EVENTS)
        .await
        .map_err(zerr("declare subscriber"))?;
    let stop = shutdown.clone();
    let kb_task = tokio::spawn(async move {
        loop {
            let query = tokio::select! {
                _ = stop.cancelled() => break,
                q = queryable.recv_async() => match q {
                    Ok(q) => q,
                    Err(_) => break,
                },
                q = changes.recv_async() => match q {
                    Ok(q) => q,
                    Err(_) => break,
                },
            };
            let key = query.key_expr().as_str().to_string();
            let payload = query
                .payload()
                .map(|p| p.to_bytes().into_owned())
                .unwrap_or_default();
            let reply = answer(&kb_conn, &key, &payload);
            if !reply.errors.is_empty() {
                tracing::info!(
                    key,
                    code = reply.errors[0].code.as_str(),
                    "kb query refused"
                );
            }
            let bytes = match encode(&reply) {
                Ok(b) => b,
                Err(e) => {
                    tracing::error!(key, error = %e, "cannot encode kb reply");
                    continue;
                }
            };
            if let Err(e) = query.reply(query.key_expr().clone(), bytes).await {
                tracing::warn!(key, error = %e, "cannot send kb reply");
            }
        }
    });
    let stop = shutdown.clone();
    let events_task = tokio::spawn(async move {
        loop {
            let sample = tokio::select! {
                _ = stop.cancelled() => break,
                s = events.recv_async() => match s {
                    Ok(s) => s,
                    Err(_) => break,
                },
            };
            let Ok(ev) = decode::<JobEvent>(&sample.payload().to_bytes()) else {
                continue;
            };
            // Only the reporter that owns an event is believed: a delivery
            // from the machine's agent, a refusal from the stage's service.
            let reporter = keys::reporter_of(sample.key_expr().as_str()).unwrap_or_default();
            let machine = match &ev.event {
                EventKind::Delivered { receipt } => Some(receipt.machine.clone()),
                _ => None,
            };
            let owned = match &machine {
                Some(m) => keys::reporter_owns(reporter, &ev, m),
                None if ev.stage == Stage::Agent => reporter.starts_with("agent-"),
                None => reporter == ev.stage.as_str(),
            };
            if !owned {
                tracing::warn!(job = %ev.job_id, reporter, "ignored an event its reporter does not own");
                continue;
            }
            if let EventKind::Delivered { receipt } = &ev.event {
                match learn::record_delivered(&events_conn, receipt) {
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
                match learn::record_refused(&events_conn, ev.job_id.as_str()) {
                    Ok(true) => tracing::info!(job = %ev.job_id, "job refused by a later stage"),
                    Ok(false) => {}
                    Err(e) => {
                        tracing::warn!(job = %ev.job_id, error = %e, "cannot record the refusal")
                    }
                }
            }
        }
    });

    let result = run_stage::<JobRequest, _>(
        &bus,
        keys::ALL_JOB_REQUESTS,
        SERVICE,
        Stage::Knowledge,
        shutdown.clone(),
        move |key, req| {
            if keys::job_of(key).as_ref() != Some(&req.job_id) {
                return Err(vec![JobError::job_id_mismatch(
                    Stage::Knowledge,
                    key,
                    &req.job_id,
                    "request",
                )]);
            }
            if let Err(e) = cases.refresh(&conn) {
                tracing::warn!(error = %e, "cannot reload the case base; planning with the one in memory");
            }
            // Each family plans its own way; every plan goes out on the job's
            // plan key under its own envelope kind.
            let planned = crate::family::plan(&conn, &cases.base, &req)?;
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
        },
    )
    .await;
    shutdown.cancel();
    let _ = kb_task.await;
    let _ = events_task.await;
    result?;
    Ok(())
}

/// A wire record as a JSON record.
pub fn record_from_wire(r: &KbRecord) -> Record {
    r.iter()
        .map(|(k, v)| (k.clone(), value_from_wire(v)))
        .collect()
}

fn value_from_wire(v: &KbValue) -> Value {
    match v {
        KbValue::Null => Value::Null,
        KbValue::Bool(b) => Value::from(*b),
        KbValue::Int(i) => Value::from(*i),
        KbValue::Float(x) => Value::from(*x),
        KbValue::Text(s) => Value::from(s.as_str()),
        KbValue::List(l) => Value::Array(l.iter().map(value_from_wire).collect()),
        KbValue::Map(m) => Value::Object(record_from_wire(m)),
    }
}

/// A JSON record as a wire record.
pub fn record_to_wire(r: &Record) -> KbRecord {
    r.iter()
        .map(|(k, v)| (k.clone(), value_to_wire(v)))
        .collect()
}

fn value_to_wire(v: &Value) -> KbValue {
    match v {
        Value::Null => KbValue::Null,
        Value::Bool(b) => KbValue::Bool(*b),
        Value::Number(n) => n
            .as_i64()
            .map(KbValue::Int)
            .unwrap_or_else(|| KbValue::Float(n.as_f64().unwrap_or(f64::NAN))),
        Value::String(s) => KbValue::Text(s.clone()),
        Value::Array(a) => KbValue::List(a.iter().map(value_to_wire).collect()),
        Value::Object(m) => KbValue::Map(record_to_wire(m)),
    }
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

fn answer_inner(
    conn: &Connection,
    key: &str,
    payload: &[u8],
    library_name: &mut String,
) -> Result<Vec<Record>, Vec<JobError>> {
    // A change key names the user who asks, whom a secure router lets use
    // only their own name: the change is recorded as theirs.
    let (user, (lib, id)) = match (keys::kb_of(key), keys::kb_change_of(key)) {
        (Some(read), _) => (None, read),
        (None, Some((user, change))) => (Some(user), change),
        (None, None) => {
            return Err(vec![Stage::Knowledge.error(
                Code::BAD_KEY,
                "key",
                keys::KB_KEY_FORMS,
                key,
                "a knowledge-base query names a library and, for one record, its id",
            )])
        }
    };
    *library_name = lib.clone();
    let lib = library::library(&lib).map_err(|e| vec![e])?;
    let req = if payload.is_empty() {
        KbRequest {
            op: if id.is_some() { KbOp::Get } else { KbOp::List },
            record: None,
            set: KbRecord::new(),
            by: String::new(),
        }
    } else {
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
        })?
    };
    let need_id = |op: &str| {
        id.clone().ok_or_else(|| {
            vec![Stage::Knowledge.error(
                Code::MISSING_ID,
                "key",
                keys::kb_record_form(lib.name),
                key,
                format!("{op} needs the record's id in the key"),
            )]
        })
    };
    // Reads on the read keys, changes on the change keys (with who makes
    // them): the access control grants them to different users.
    let is_change = matches!(req.op, KbOp::Add | KbOp::Edit | KbOp::Remove);
    if is_change != user.is_some() {
        let (expected, message) = if is_change {
            (
                format!(
                    "list or get on {key}; a change on {}",
                    keys::kb_change("{user}", lib.name, id.as_deref())
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
        return Err(vec![Stage::Knowledge.error(
            Code::KB_WRONG_KEY,
            "op",
            expected,
            format!("{:?}", req.op).to_lowercase(),
            message,
        )]);
    }
    if let Some(user) = &user {
        crate::audit::acting_as(conn, user).map_err(|e| {
            vec![Stage::Knowledge.error(
                Code::KNOWLEDGE_BASE_ERROR,
                "-",
                "a writable knowledge base",
                e.to_string(),
                "the change could not be recorded",
            )]
        })?;
    }
    match req.op {
        KbOp::List => Ok(library::list(conn, &lib)?),
        KbOp::Get => {
            let id = need_id("get")?;
            match library::get(conn, &lib, &id)? {
                Some(r) => Ok(vec![r]),
                None => Err(vec![Stage::Knowledge.error(
                    Code::NOT_FOUND,
                    lib.key,
                    format!("an existing {} id", lib.name),
                    id.as_str(),
                    format!("there is no record {id:?} in {}", lib.name),
                )]),
            }
        }
        KbOp::Add => {
            let Some(rec) = req.record.as_ref() else {
                return Err(vec![Stage::Knowledge.error(
                    Code::FIELD_MISSING,
                    "record",
                    "the record to add",
                    "nothing",
                    "an add request carries the whole record",
                )]);
            };
            let mut rec = record_from_wire(rec);
            if let Some(id) = &id {
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
            Ok(vec![library::add(conn, &lib, &rec)?])
        }
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
