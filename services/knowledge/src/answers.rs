//! The change log and the confirmation of delivered jobs on the bus, beside
//! the libraries' queries ([`crate::service::answer`]): what
//! `gearcam kb changes` and `gearcam confirm` do on the database file, done
//! for a client of the bus (the web page, any station).
//!
//! - [`answer_log`] answers `gearcam/v1/kb-log[/{library}[/{id}]]`: the
//!   recorded changes ([`crate::audit`]), newest first, with their library's
//!   name as the bus and the CLI spell it and the old and new records.
//! - [`answer_confirm`] answers `gearcam/v1/kb-confirm/{user}/{job}`: the
//!   job becomes a case ([`crate::learn::confirm`], the CLI's validation and
//!   typed errors), recorded as the key's user's.
//!
//! Neither ever fails: every problem is a typed error (stage `knowledge`)
//! in the reply.

use gearcam_proto::plan::{ConfirmReply, ConfirmRequest, KbChange, KbLogReply, KbLogRequest};
use gearcam_proto::{decode, keys, Code, JobError, JobId, Message, Stage};
use rusqlite::Connection;
use serde_json::Value;

use crate::audit::{self, Change};
use crate::learn::{self, Confirmation};
use crate::library::{self, record_to_wire, Record};

/// Answers one query of the change log: the key names every library, one
/// library or one record; the payload (possibly empty) is a
/// [`KbLogRequest`].
pub fn answer_log(conn: &Connection, key: &str, payload: &[u8]) -> KbLogReply {
    match log_inner(conn, key, payload) {
        Ok(changes) => KbLogReply {
            changes,
            errors: vec![],
        },
        Err(errors) => KbLogReply {
            changes: vec![],
            errors,
        },
    }
}

fn log_inner(conn: &Connection, key: &str, payload: &[u8]) -> Result<Vec<KbChange>, Vec<JobError>> {
    let Some((library, id)) = keys::kb_log_of(key) else {
        return Err(vec![bad_key(
            keys::KB_LOG_FORM,
            key,
            "a change-log query names every library, one library or one record",
        )]);
    };
    let table = match &library {
        Some(name) => Some(library::library(name).map_err(|e| vec![e])?.table),
        None => None,
    };
    let req = if payload.is_empty() {
        KbLogRequest::default()
    } else {
        decoded::<KbLogRequest>(payload)?
    };
    if !(1..=KbLogRequest::MAX_LIMIT).contains(&req.limit) {
        return Err(vec![Stage::Knowledge.error(
            Code::FIELD_INVALID,
            "limit",
            format!("an integer in [1, {}]", KbLogRequest::MAX_LIMIT),
            req.limit.to_string(),
            "the change log is read at most this many changes at a time",
        )]);
    }
    let changes = audit::changes_of(conn, table, id.as_deref(), req.limit as usize)?;
    Ok(changes.iter().map(change_on_wire).collect())
}

/// A recorded change as the bus carries it: its library by name (`classes`,
/// not the table `gt_classes`), the old and the new record as records (a
/// machine's whole profile, not the JSON text of its row).
fn change_on_wire(c: &Change) -> KbChange {
    let name = library::LIBRARIES
        .iter()
        .find(|l| l.table == c.library)
        .map_or(c.library.as_str(), |l| l.name);
    KbChange {
        seq: c.seq,
        at_ms: c.at_ms,
        by: c.by.clone(),
        library: name.to_string(),
        record_id: c.record_id.clone(),
        op: c.op.clone(),
        old: c.old.as_deref().map(|j| record_to_wire(&logged_record(j))),
        new: c.new.as_deref().map(|j| record_to_wire(&logged_record(j))),
    }
}

/// A row the audit trail kept as JSON, as a record: a machine's row
/// (`profile_json` a text) becomes its profile with its `source`, as the
/// machines library reads it. A text that is not a JSON object (no trigger
/// writes one) is kept whole under `json`.
fn logged_record(json: &str) -> Record {
    let Ok(mut rec) = serde_json::from_str::<Record>(json) else {
        let mut rec = Record::new();
        rec.insert("json".into(), Value::from(json));
        return rec;
    };
    let profile = match rec.get("profile_json") {
        Some(Value::String(p)) => serde_json::from_str::<Record>(p).ok(),
        _ => None,
    };
    if let Some(mut profile) = profile {
        if let Some(source) = rec.remove("source") {
            profile.insert("source".into(), source);
        }
        rec = profile;
    }
    rec
}

/// Answers one confirmation: the key names the user who confirms and the
/// job, the payload is a [`ConfirmRequest`]; `at_ms` is when.
pub fn answer_confirm(conn: &Connection, key: &str, payload: &[u8], at_ms: u64) -> ConfirmReply {
    let mut reply = ConfirmReply {
        job_id: String::new(),
        case_library: String::new(),
        case: None,
        hob: None,
        job: None,
        errors: vec![],
    };
    match confirm_inner(conn, key, payload, at_ms, &mut reply.job_id) {
        Ok(done) => {
            reply.case_library = done.case_library.to_string();
            reply.case = Some(record_to_wire(&done.case));
            reply.hob = done.hob.as_ref().map(record_to_wire);
            reply.job = Some(record_to_wire(&done.job));
        }
        Err(errors) => reply.errors = errors,
    }
    reply
}

/// Confirms the job the key names (see [`answer_confirm`]), writing its id
/// into `job_id` as soon as the key gives it.
fn confirm_inner(
    conn: &Connection,
    key: &str,
    payload: &[u8],
    at_ms: u64,
    job_id: &mut String,
) -> Result<learn::Confirmed, Vec<JobError>> {
    let Some((user, job)) = keys::kb_confirm_of(key) else {
        return Err(vec![bad_key(
            keys::KB_CONFIRM_FORM,
            key,
            "a confirmation names the user who confirms and the job",
        )]);
    };
    *job_id = job.to_string();
    let job = JobId::new(job).map_err(|e| {
        vec![Stage::Knowledge.error(
            Code::BAD_JOB_ID,
            "job",
            "a job id: 1–64 characters A–Z a–z 0–9 _ - starting with a letter or digit",
            job,
            e.to_string(),
        )]
    })?;
    if payload.is_empty() {
        return Err(vec![Stage::Knowledge.error(
            Code::FIELD_MISSING,
            "payload",
            format!("a MessagePack {} message", ConfirmRequest::KIND),
            "nothing",
            "a confirmation carries the values actually used and the outcome",
        )]);
    }
    let req = decoded::<ConfirmRequest>(payload)?;
    let c = Confirmation {
        job_id: job.as_str().to_string(),
        quantity: req.quantity,
        cutting_speed_m_min: req.cutting_speed_m_min,
        feed_mm_per_rev: req.feed_mm_per_rev,
        cuts: req.cuts,
        outcome: req.outcome,
        quality_achieved: req.quality_achieved,
        notes: req.notes,
        confidence: req.confidence,
        by: user.to_string(),
        at_ms,
        allow_undelivered: req.undelivered,
    };
    learn::confirm(conn, &c)
}

/// The refusal of a key not of the form `form`.
fn bad_key(form: &str, key: &str, message: &str) -> JobError {
    Stage::Knowledge.error(Code::BAD_KEY, "key", form, key, message)
}

/// The payload decoded as a `T`, or the codec's typed error.
fn decoded<T: Message>(payload: &[u8]) -> Result<T, Vec<JobError>> {
    decode::<T>(payload).map_err(|e| {
        vec![Stage::Knowledge.error(
            e.code(),
            "payload",
            format!(
                "a MessagePack {} message, schema {}",
                T::KIND,
                gearcam_proto::SCHEMA_VERSION
            ),
            e.to_string(),
            format!("the query's payload is not a {}", T::KIND),
        )]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{db, plan};
    use gearcam_proto::plan::{KbOp, KbRecord, KbRequest, KbValue};
    use gearcam_proto::{encode, DeliveryReceipt};
    use serde_json::json;

    fn edit_coating(conn: &Connection, user: &str, coating: &str) {
        let mut set = KbRecord::new();
        set.insert("coating".into(), KbValue::Text(coating.into()));
        let req = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: String::new(),
        };
        let key = keys::kb_change(user, "hobs", Some("HOB-M3-80"));
        let reply = crate::service::answer(conn, &key, &encode(&req).unwrap());
        assert!(reply.errors.is_empty(), "{:?}", reply.errors);
    }

    /// The log names who changed what, newest first, by library name, with
    /// the old and the new record; one library's and one record's log hold
    /// only theirs; a limit bounds it.
    #[test]
    fn the_change_log_reads_newest_first_with_who_old_and_new() {
        let conn = db::open_in_memory().unwrap();
        edit_coating(&conn, "admin", "TiAlN");
        edit_coating(&conn, "supervisor", "AlCrN");
        let log = answer_log(&conn, &keys::kb_log(None, None), &[]);
        assert!(log.errors.is_empty(), "{:?}", log.errors);
        let c = &log.changes[0];
        assert_eq!(
            (
                c.by.as_str(),
                c.library.as_str(),
                c.record_id.as_str(),
                c.op.as_str()
            ),
            ("supervisor", "hobs", "HOB-M3-80", "edit")
        );
        let coating = |r: &Option<KbRecord>| r.as_ref().unwrap()["coating"].clone();
        assert_eq!(coating(&c.old), KbValue::Text("TiAlN".into()));
        assert_eq!(coating(&c.new), KbValue::Text("AlCrN".into()));
        assert_eq!(log.changes[1].by, "admin");
        assert!(log.changes[0].seq > log.changes[1].seq);
        assert!(log.changes.len() <= KbLogRequest::DEFAULT_LIMIT as usize);
        // A change of the class tree (table `gt_classes`) is the library `classes`'s.
        let mut set = KbRecord::new();
        set.insert("name".into(), KbValue::Text("spur and helical".into()));
        let req = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: String::new(),
        };
        let key = keys::kb_change("admin", "classes", Some("cylindrical"));
        let reply = crate::service::answer(&conn, &key, &encode(&req).unwrap());
        assert!(reply.errors.is_empty(), "{:?}", reply.errors);
        let classes = answer_log(&conn, &keys::kb_log(Some("classes"), None), &[]);
        assert_eq!(classes.changes[0].library, "classes");
        assert_eq!(classes.changes[0].record_id, "cylindrical");
        assert!(classes.changes.iter().all(|c| c.library == "classes"));
        let one = answer_log(&conn, &keys::kb_log(Some("hobs"), Some("HOB-M3-80")), &[]);
        assert!(one.changes.iter().all(|c| c.record_id == "HOB-M3-80"));
        let two = encode(&KbLogRequest { limit: 2 }).unwrap();
        assert_eq!(
            answer_log(&conn, &keys::kb_log(None, None), &two)
                .changes
                .len(),
            2
        );
    }

    #[test]
    fn a_machines_change_carries_its_profile_not_its_row() {
        let conn = db::open_in_memory().unwrap();
        let mut set = KbRecord::new();
        set.insert("limits.max_hob_rpm".into(), KbValue::Float(1200.0));
        let req = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: String::new(),
        };
        let key = keys::kb_change("admin", "machines", Some("H01"));
        let reply = crate::service::answer(&conn, &key, &encode(&req).unwrap());
        assert!(reply.errors.is_empty(), "{:?}", reply.errors);
        let log = answer_log(&conn, &keys::kb_log(Some("machines"), Some("H01")), &[]);
        let new = log.changes[0].new.as_ref().unwrap();
        let KbValue::Map(limits) = &new["limits"] else {
            panic!("no limits in {new:?}")
        };
        assert_eq!(limits["max_hob_rpm"], KbValue::Float(1200.0));
        assert!(new.contains_key("source") && !new.contains_key("profile_json"));
    }

    #[test]
    fn a_bad_log_query_is_refused_by_name() {
        let conn = db::open_in_memory().unwrap();
        let e = &answer_log(&conn, &keys::kb_log(Some("gears"), None), &[]).errors[0];
        assert_eq!(e.code, Code::UNKNOWN_LIBRARY);
        let zero = encode(&KbLogRequest { limit: 0 }).unwrap();
        let e = &answer_log(&conn, &keys::kb_log(None, None), &zero).errors[0];
        assert_eq!(
            (e.code, e.field.as_str(), e.got.as_str()),
            (Code::FIELD_INVALID, "limit", "0")
        );
        let e = &answer_log(&conn, &keys::kb_log(None, None), b"junk").errors[0];
        assert_eq!(e.field, "payload");
        let e = &answer_log(&conn, "gearcam/v1/kb-log/a/b/c", &[]).errors[0];
        assert_eq!(
            (e.code, e.expected.as_str()),
            (Code::BAD_KEY, keys::KB_LOG_FORM)
        );
    }

    fn request() -> ConfirmRequest {
        ConfirmRequest {
            quantity: Some(20),
            cutting_speed_m_min: Some(95.0),
            feed_mm_per_rev: None,
            cuts: None,
            outcome: "ok".into(),
            quality_achieved: Some(7),
            notes: "good flanks".into(),
            confidence: 0.9,
            undelivered: false,
        }
    }

    /// A planned and delivered job confirmed on the bus becomes a case
    /// recorded as the key's user's; before delivery, and with a wrong
    /// outcome, it is refused with the CLI's typed errors.
    #[test]
    fn a_delivered_job_confirmed_on_the_bus_becomes_the_users_case() {
        let conn = db::open_in_memory().unwrap();
        let p = plan::plan(&conn, &plan::tests::request(json!({}), json!({}))).unwrap();
        learn::record_planned(&conn, &p, 1).unwrap();
        let key = keys::kb_confirm("planner", &JobId::new("J1").unwrap());
        let payload = encode(&request()).unwrap();
        let r = answer_confirm(&conn, &key, &payload, 5);
        assert_eq!(
            (r.errors[0].code, r.errors[0].got.as_str()),
            (Code::JOB_STATE, "planned")
        );
        let receipt: DeliveryReceipt = serde_json::from_value(json!({
            "job_id": "J1", "machine": "H01", "name": "P_1", "file_name": "_N_P_1_MPF",
            "path": "/x", "revision": 1, "sha256": "00", "size_bytes": 1,
            "stored_at_ms": 2, "duplicate": false
        }))
        .unwrap();
        assert!(learn::record_delivered(&conn, &receipt).unwrap());
        let mut wrong = request();
        wrong.outcome = "fine".into();
        let r = answer_confirm(&conn, &key, &encode(&wrong).unwrap(), 5);
        let e = &r.errors[0];
        assert_eq!(
            (e.code, e.field.as_str(), e.got.as_str()),
            (Code::FIELD_INVALID, "outcome", "\"fine\"")
        );
        let r = answer_confirm(&conn, &key, &payload, 5);
        assert!(r.errors.is_empty(), "{:?}", r.errors);
        assert_eq!(
            (r.job_id.as_str(), r.case_library.as_str()),
            ("J1", "cases")
        );
        let case = r.case.unwrap();
        assert_eq!(case["id"], KbValue::Text("JOB-J1".into()));
        let KbValue::Text(provenance) = &case["provenance"] else {
            panic!("{case:?}")
        };
        assert!(provenance.contains("by planner"), "{provenance}");
        assert_eq!(r.job.unwrap()["state"], KbValue::Text("confirmed".into()));
        assert!(r.hob.is_some());
        let log = answer_log(&conn, &keys::kb_log(Some("cases"), Some("JOB-J1")), &[]);
        assert_eq!(log.changes[0].by, "planner (confirm J1)");
    }

    #[test]
    fn a_bad_confirmation_is_refused_by_name() {
        let conn = db::open_in_memory().unwrap();
        let payload = encode(&request()).unwrap();
        let e = &answer_confirm(&conn, "gearcam/v1/kb-confirm/J1", &payload, 5).errors[0];
        assert_eq!(
            (e.code, e.expected.as_str()),
            (Code::BAD_KEY, keys::KB_CONFIRM_FORM)
        );
        let e = &answer_confirm(&conn, "gearcam/v1/kb-confirm/planner/-J", &payload, 5).errors[0];
        assert_eq!((e.code, e.got.as_str()), (Code::BAD_JOB_ID, "-J"));
        let key = keys::kb_confirm("planner", &JobId::new("NOPE").unwrap());
        let r = answer_confirm(&conn, &key, &payload, 5);
        assert_eq!(
            (r.job_id.as_str(), r.errors[0].code),
            ("NOPE", Code::UNKNOWN_JOB)
        );
        let e = &answer_confirm(&conn, &key, &[], 5).errors[0];
        assert_eq!((e.code, e.field.as_str()), (Code::FIELD_MISSING, "payload"));
    }
}
