//! The knowledge base on the page: its libraries, their records and the
//! change log for everyone; edits, additions and removals for those who
//! may change it (admin, supervisor); the confirmation of a delivered job
//! (the learning loop) for every role.
//!
//! A client of the knowledge service over the bus, as `gearcam kb` is of
//! the database file: reads on `gearcam/v1/kb/…`, changes on
//! `gearcam/v1/kb-changes/{user}/…` and confirmations on
//! `gearcam/v1/kb-confirm/{user}/…` under the signed-in user's name, the
//! change log on `gearcam/v1/kb-log/…`. Only the libraries' descriptions
//! (fields, types, defaults, meanings) come from the knowledge crate's
//! definitions, which are code, not data. The service decides: every
//! typed error it gives is shown beside the field it names.
//!
//! # Layout
//!
//! - this module: the routes, the calls on the bus, and what the pages
//!   share (a record's fields as [`Slot`]s, values as text and back, links).
//! - `browse`: `/kb`, `/kb/{library}`, `/kb/{library}/{id}`, `/kb/changes`.
//! - `edit`: the forms that edit, add and remove records.
//! - `confirm`: `/jobs/{job}/confirm`.

mod browse;
mod confirm;
mod edit;

use std::time::Duration;

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use gearcam_bus::query::{CallError, Retry};
use gearcam_bus::Bus;
use gearcam_knowledge::library::{self, Check, Kind, Library, Need, Record};
use gearcam_knowledge::library::{record_from_wire, record_to_wire};
use gearcam_proto::plan::{
    ConfirmReply, ConfirmRequest, KbChange, KbLogReply, KbLogRequest, KbReply, KbRequest,
};
use gearcam_proto::{keys, JobError, JobId};
use maud::{html, Markup};
use serde_json::Value;

use super::auth::{self, Session};
use super::{errors_table, page, Web};

/// The knowledge base's pages.
pub(super) fn routes() -> Router<Web> {
    Router::new()
        .route("/kb", get(browse::libraries))
        .route("/kb/changes", get(browse::changes))
        .route("/kb/new/{library}", get(edit::add_form).post(edit::add))
        .route("/kb/{library}", get(browse::records))
        .route("/kb/{library}/{id}", get(browse::record))
        .route(
            "/kb/{library}/{id}/edit",
            get(edit::edit_form).post(edit::edit),
        )
        .route(
            "/kb/{library}/{id}/remove",
            get(edit::remove_form).post(edit::remove),
        )
        .route(
            "/jobs/{job}/confirm",
            get(confirm::form).post(confirm::confirm),
        )
}

/// A change is asked once: asked again after a lost reply, an addition
/// would find its own record (`DUPLICATE_ID`) and a confirmation its own
/// case; the page says the service did not answer instead.
const ONCE: Retry = Retry {
    timeout: Duration::from_secs(10),
    attempts: 1,
    pause: Duration::from_millis(0),
};

/// What a call to the knowledge service gave: its answer (the records, or
/// its typed errors), or why nothing answered.
type Answer<T> = Result<Result<T, Vec<JobError>>, CallError>;

/// The records of a reply, or its errors.
fn records_of(reply: KbReply) -> Result<Vec<Record>, Vec<JobError>> {
    if reply.errors.is_empty() {
        Ok(reply.records.iter().map(record_from_wire).collect())
    } else {
        Err(reply.errors)
    }
}

/// Reads every record of `lib`, or the one of `id`.
async fn read(bus: &Bus, lib: &Library, id: Option<&str>) -> Answer<Vec<Record>> {
    let key = match id {
        Some(id) => keys::kb_record(lib.name, id),
        None => keys::kb_library(lib.name),
    };
    let reply: KbReply = bus
        .call::<KbRequest, KbReply>(&key, None, Retry::default())
        .await?;
    Ok(records_of(reply))
}

/// Asks a change of `lib` (of the record `id`, when given) as `user`.
async fn change(
    bus: &Bus,
    user: &str,
    lib: &Library,
    id: Option<&str>,
    req: &KbRequest,
) -> Answer<Vec<Record>> {
    let key = keys::kb_change(user, lib.name, id);
    let reply: KbReply = bus.call(&key, Some(req), ONCE).await?;
    Ok(records_of(reply))
}

/// The newest `limit` changes of every library, of `library`, or of its
/// record `id`.
async fn log(
    bus: &Bus,
    library: Option<&str>,
    id: Option<&str>,
    limit: u32,
) -> Answer<Vec<KbChange>> {
    let reply: KbLogReply = bus
        .call(
            &keys::kb_log(library, id),
            Some(&KbLogRequest { limit }),
            Retry::default(),
        )
        .await?;
    Ok(if reply.errors.is_empty() {
        Ok(reply.changes)
    } else {
        Err(reply.errors)
    })
}

/// Confirms the delivered job `job` as `user`.
async fn confirm_job(
    bus: &Bus,
    user: &str,
    job: &JobId,
    req: &ConfirmRequest,
) -> Result<ConfirmReply, CallError> {
    bus.call(&keys::kb_confirm(user, job), Some(req), ONCE)
        .await
}

/// The page of a knowledge service that does not answer.
fn silent(session: &Session, e: &CallError) -> Response {
    let body = html! {
        h1 { "The knowledge service does not answer" }
        p.refused role="alert" { "Is " code { "gearcam up" } " (or the knowledge service) running? " (e.to_string()) }
    };
    (
        StatusCode::SERVICE_UNAVAILABLE,
        page("Knowledge service unreachable", Some(session), body),
    )
        .into_response()
}

/// A page of the knowledge service's typed errors: 404 when each says
/// there is no such library or record, else `status`.
fn refused(session: &Session, what: &str, errors: &[JobError], status: StatusCode) -> Response {
    let status = if errors.iter().all(|e| {
        matches!(
            e.code,
            gearcam_proto::Code::NOT_FOUND | gearcam_proto::Code::UNKNOWN_LIBRARY
        )
    }) {
        StatusCode::NOT_FOUND
    } else {
        status
    };
    let body = html! {
        p { a href="/kb" { "← knowledge base" } }
        h1 { (what) }
        (errors_table(errors))
    };
    (status, page(what, Some(session), body)).into_response()
}

/// The refusal of a change by a user whose role may not change the
/// knowledge base.
fn forbidden(session: &Session) -> Response {
    auth::refuse(
        StatusCode::FORBIDDEN,
        &format!(
            "changing the knowledge base needs the role admin or supervisor; {} is signed in as {}, who may read it only",
            session.user.name,
            session.user.role.as_str()
        ),
    )
}

/// The library named `name` (its definition), or the page saying there
/// is none.
fn lib_of(session: &Session, name: &str) -> Result<Library, Response> {
    library::library(name)
        .map_err(|e| refused(session, "No such library", &[e], StatusCode::NOT_FOUND))
}

/// A record id from a path, refused when a key chunk cannot hold it
/// (empty, or with `/ * $ ? #`, or a leading `@`): every id of the
/// knowledge base can.
fn id_of(session: &Session, lib: &Library, id: &str) -> Result<String, Response> {
    let ok = !id.is_empty()
        && !id.starts_with('@')
        && !id
            .chars()
            .any(|c| matches!(c, '/' | '*' | '$' | '?' | '#') || c.is_control());
    if ok {
        return Ok(id.to_string());
    }
    let e = gearcam_proto::Stage::Knowledge.error(
        gearcam_proto::Code::NOT_FOUND,
        lib.key,
        format!("an existing {} id", lib.name),
        id,
        "no record has such an id",
    );
    Err(refused(
        session,
        "No such record",
        &[e],
        StatusCode::NOT_FOUND,
    ))
}

/// `s` as one segment of a path: everything but `A–Z a–z 0–9 - _ . ~`
/// percent-encoded.
fn segment(s: &str) -> String {
    s.bytes()
        .map(|b| match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'_' | b'.' | b'~' => {
                (b as char).to_string()
            }
            _ => format!("%{b:02X}"),
        })
        .collect()
}

/// The page of a library.
fn library_href(lib: &str) -> String {
    format!("/kb/{}", segment(lib))
}

/// The page of a record.
fn record_href(lib: &str, id: &str) -> String {
    format!("/kb/{}/{}", segment(lib), segment(id))
}

/// The change log, of a library or a record.
fn log_href(lib: Option<&str>, id: Option<&str>) -> String {
    match (lib, id) {
        (Some(l), Some(i)) => format!("/kb/changes?library={}&record={}", segment(l), segment(i)),
        (Some(l), None) => format!("/kb/changes?library={}", segment(l)),
        _ => "/kb/changes".to_string(),
    }
}

/// One field of a record as the pages show it: a field of a flat library,
/// or a nested field of a machine's profile by its dotted path.
#[derive(Debug, Clone)]
struct Slot {
    /// The field's name, or dotted path (`limits.max_hob_rpm`).
    name: String,
    /// The name with its unit, e.g. `module_mm (mm)`.
    label: String,
    /// The field's type, when the library describes it.
    kind: Option<Kind>,
    /// The values it takes, when the library lists them.
    choices: &'static [&'static str],
    /// What it means.
    doc: String,
    /// Required, optional or its default.
    need: String,
}

/// A field's unit as its library says it: the last words of its meaning
/// after a comma when they are one token (`normal module mn, mm` → `mm`);
/// for a machine's nested fields, which have no meaning written, the unit
/// its name ends with (`…_mm`, `…_deg`, `…_rpm`, `…_mm_min`).
fn unit(doc: &str, name: &str) -> Option<String> {
    if let Some((_, last)) = doc.rsplit_once(", ") {
        let last = last.trim();
        // A list of examples (`coating, e.g. none, TiN`) is no unit.
        if !last.is_empty()
            && last.chars().count() <= 10
            && !last.contains(' ')
            && !doc.contains("e.g.")
        {
            return Some(last.to_string());
        }
        return None;
    }
    let leaf = name.rsplit('.').next().unwrap_or(name);
    [
        ("_mm_min", "mm/min"),
        ("_mm", "mm"),
        ("_deg", "degrees"),
        ("_rpm", "rpm"),
    ]
    .iter()
    .find(|(suffix, _)| leaf.ends_with(suffix))
    .map(|(_, u)| u.to_string())
}

/// The slots of `lib`'s records: its fields, or, for a library of nested
/// records (machines), the dotted paths of `sample`.
fn slots(lib: &Library, sample: Option<&Record>) -> Vec<Slot> {
    if !lib.fields.is_empty() {
        return lib
            .fields
            .iter()
            .map(|f| Slot {
                name: f.name.to_string(),
                label: labelled(f.name, unit(f.doc, f.name)),
                kind: Some(f.kind),
                choices: match f.check {
                    Check::OneOf(c) => c,
                    _ => &[],
                },
                doc: f.doc.to_string(),
                need: match f.need {
                    Need::Required => "required".to_string(),
                    other => other.to_string(),
                },
            })
            .collect();
    }
    sample
        .map(flatten)
        .unwrap_or_default()
        .into_iter()
        .map(|(name, _)| Slot {
            label: labelled(&name, unit("", &name)),
            name,
            kind: None,
            choices: &[],
            doc: String::new(),
            need: "required".to_string(),
        })
        .collect()
}

fn labelled(name: &str, unit: Option<String>) -> String {
    match unit {
        Some(u) => format!("{name} ({u})"),
        None => name.to_string(),
    }
}

/// A record's fields by dotted path, nested maps opened (a list stays one
/// value).
fn flatten(rec: &Record) -> Vec<(String, Value)> {
    let mut out = Vec::new();
    for (k, v) in rec {
        match v {
            Value::Object(m) => {
                for (path, leaf) in flatten(m) {
                    out.push((format!("{k}.{path}"), leaf));
                }
            }
            other => out.push((k.clone(), other.clone())),
        }
    }
    out
}

/// The value at a dotted path of a record.
fn value_at<'a>(rec: &'a Record, path: &str) -> Option<&'a Value> {
    let mut parts = path.split('.');
    let mut cur = rec.get(parts.next()?)?;
    for p in parts {
        cur = cur.as_object()?.get(p)?;
    }
    Some(cur)
}

/// A value as the pages show it and a form holds it: nothing for no
/// value, a text as itself, a list or map as JSON, a number exactly.
fn text_of(v: &Value) -> String {
    match v {
        Value::Null => String::new(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// The value a form's `text` stands for in `slot` (whose value is
/// `current`, if known): typed by the field's type when it reads as one,
/// else sent as the text it is, for the knowledge service to refuse by
/// name (a text in a number field is its `FIELD_INVALID`). No text is no
/// value.
fn typed(slot: &Slot, current: Option<&Value>, text: &str) -> Value {
    let t = text.trim();
    if t.is_empty() {
        return Value::Null;
    }
    let number = || {
        t.parse::<i64>()
            .map(Value::from)
            .ok()
            .or_else(|| t.parse::<f64>().ok().map(Value::from))
    };
    let boolean = || match t.to_ascii_lowercase().as_str() {
        "true" | "yes" | "1" => Some(Value::from(true)),
        "false" | "no" | "0" => Some(Value::from(false)),
        _ => None,
    };
    let read = match (slot.kind, current) {
        (Some(Kind::Real), _) => t.parse::<f64>().ok().map(Value::from),
        (Some(Kind::Int), _) => number(),
        (Some(Kind::Bool), _) => boolean(),
        (Some(Kind::Text), _) | (None, Some(Value::String(_))) => None,
        (None, Some(Value::Number(_))) => number(),
        (None, Some(Value::Bool(_))) => boolean(),
        (None, _) => serde_json::from_str::<Value>(t).ok(),
    };
    read.unwrap_or_else(|| Value::from(t))
}

/// A record as a list of its fields, every one, with labels and units.
fn record_list(lib: &Library, rec: &Record) -> Markup {
    let slots = slots(lib, Some(rec));
    html! {
        table.record {
            tbody {
                @for s in &slots {
                    tr {
                        th scope="row" { (s.label) }
                        td data-field=(s.name) { (value_at(rec, &s.name).map(text_of).unwrap_or_default()) }
                    }
                }
            }
        }
    }
}

/// The wire form of a record (for a request).
fn wire(rec: &Record) -> gearcam_proto::plan::KbRecord {
    record_to_wire(rec)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn units_come_from_the_meaning_or_a_nested_fields_name() {
        assert_eq!(
            unit("normal module mn, mm", "module_mm").as_deref(),
            Some("mm")
        );
        assert_eq!(
            unit("cutting speed vc, m/min", "x").as_deref(),
            Some("m/min")
        );
        assert_eq!(unit("coating, e.g. none, TiN", "coating"), None);
        assert_eq!(unit("", "limits.max_hob_rpm").as_deref(), Some("rpm"));
        assert_eq!(
            unit("", "limits.max_axial_feed_mm_min").as_deref(),
            Some("mm/min")
        );
        assert_eq!(unit("human name", "name"), None);
    }

    #[test]
    fn a_text_reads_as_its_fields_type_or_stays_text_for_the_service_to_refuse() {
        let hobs = library::library("hobs").unwrap();
        let slot = |n: &str| {
            slots(&hobs, None)
                .into_iter()
                .find(|s| s.name == n)
                .unwrap()
        };
        assert_eq!(typed(&slot("module_mm"), None, " 3 "), json!(3.0));
        assert_eq!(typed(&slot("module_mm"), None, "three"), json!("three"));
        assert_eq!(typed(&slot("starts"), None, "2"), json!(2));
        assert_eq!(typed(&slot("coating"), None, "12"), json!("12"));
        assert_eq!(typed(&slot("coating"), None, ""), Value::Null);
        let nested = Slot {
            name: "limits.module_mm".into(),
            label: String::new(),
            kind: None,
            choices: &[],
            doc: String::new(),
            need: String::new(),
        };
        assert_eq!(
            typed(&nested, Some(&json!([1.0, 2.0])), "[1, 8]"),
            json!([1, 8])
        );
        assert_eq!(typed(&nested, Some(&json!(1.0)), "x"), json!("x"));
        assert_eq!(typed(&nested, Some(&json!("YK")), "123"), json!("123"));
    }

    #[test]
    fn nested_records_open_by_dotted_path() {
        let rec: Record = serde_json::from_value(json!({
            "id": "H01", "limits": {"max_hob_rpm": 1000.0, "x_mm": [0.0, 300.0]}
        }))
        .unwrap();
        let paths: Vec<String> = flatten(&rec).into_iter().map(|(p, _)| p).collect();
        assert_eq!(paths, ["id", "limits.max_hob_rpm", "limits.x_mm"]);
        assert_eq!(value_at(&rec, "limits.max_hob_rpm"), Some(&json!(1000.0)));
        assert_eq!(
            text_of(value_at(&rec, "limits.x_mm").unwrap()),
            "[0.0,300.0]"
        );
        assert_eq!(segment("a b/c"), "a%20b%2Fc");
    }
}
