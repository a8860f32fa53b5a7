//! Reading the knowledge base: its libraries with their fields, a
//! library's records as a table, one record with every field, and the
//! change log newest first (who, when, which record, old → new).

use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Extension;
use gearcam_knowledge::library::record_from_wire;
use gearcam_knowledge::library::{self, Library, Record};
use gearcam_proto::plan::{KbChange, KbLogRequest};
use gearcam_proto::{Code, Stage};
use maud::{html, Markup};
use serde::Deserialize;
use serde_json::Value;

use super::super::auth::Session;
use super::super::{page, Web};
use super::{
    flatten, id_of, lib_of, library_href, log, log_href, read, record_href, record_list, refused,
    segment, silent, slots, text_of, value_at,
};

/// `GET /kb`: every library, what it holds, its key and its fields (name,
/// type, need or default, meaning), and a link to the change log.
pub(super) async fn libraries(Extension(session): Extension<Session>) -> Markup {
    let body = html! {
        h1 { "Knowledge base" }
        p { "The shop's process knowledge, served by the knowledge service. "
            a href=(log_href(None, None)) #changes-link { "Every change" } " (who, when, old → new)." }
        ul.libraries {
            @for lib in library::LIBRARIES {
                li { a href=(library_href(lib.name)) { (lib.name) } " — " (lib.doc) }
            }
        }
        @for lib in library::LIBRARIES {
            section.library id=(format!("lib-{}", lib.name)) {
                h2 { a href=(library_href(lib.name)) { (lib.name) } }
                p { (lib.doc) "; key " code { (lib.key) } }
                @if lib.fields.is_empty() {
                    p.help { "Each record is a whole machine profile: its fields are nested groups (axes, limits, settings, …), shown on each record's page." }
                } @else {
                    table.fields {
                        thead { tr { th { "field" } th { "type" } th { "default" } th { "meaning" } } }
                        tbody {
                            @for s in slots(lib, None) {
                                tr {
                                    td { code { (s.label) } }
                                    td { (s.kind.map(|k| k.to_string()).unwrap_or_default()) }
                                    td { (s.need) }
                                    td { (s.doc) @if !s.choices.is_empty() { " (" (s.choices.join(", ")) ")" } }
                                }
                            }
                        }
                    }
                }
            }
        }
    };
    page("Knowledge base", Some(&session), body)
}

/// At most this many characters of a value in a table cell.
const CELL: usize = 40;

/// The columns of a library's table: every field, or a machine's
/// top-level values (its nested groups are on its page).
fn columns(lib: &Library, records: &[Record]) -> Vec<String> {
    if !lib.fields.is_empty() {
        return lib.fields.iter().map(|f| f.name.to_string()).collect();
    }
    records
        .first()
        .map(|r| {
            r.iter()
                .filter(|(_, v)| !v.is_object() && !v.is_array())
                .map(|(k, _)| k.clone())
                .collect()
        })
        .unwrap_or_default()
}

/// A value cut to [`CELL`] characters for a table.
fn cell(v: &Value) -> String {
    let t = text_of(v);
    if t.chars().count() > CELL {
        format!("{}…", t.chars().take(CELL).collect::<String>())
    } else {
        t
    }
}

/// `GET /kb/{library}`: its records as a table, each key a link to the
/// record; for those who may change the knowledge base, a link to add one.
pub(super) async fn records(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(name): Path<String>,
) -> Response {
    let lib = match lib_of(&session, &name) {
        Ok(l) => l,
        Err(r) => return r,
    };
    let records = match read(&web.bus, &lib, None).await {
        Ok(Ok(r)) => r,
        Ok(Err(errors)) => {
            return refused(&session, lib.name, &errors, StatusCode::BAD_GATEWAY);
        }
        Err(e) => return silent(&session, &e),
    };
    let cols = columns(&lib, &records);
    let body = html! {
        p { a href="/kb" { "← knowledge base" } }
        h1 { (lib.name) }
        p { (lib.doc) ". " (records.len()) " record(s). "
            a href=(log_href(Some(lib.name), None)) { "Changes of " (lib.name) } }
        @if session.user.may_edit_kb() {
            p { a #add href=(format!("/kb/new/{}", segment(lib.name))) { "Add a record" } }
        }
        div.wide style="overflow-x:auto" {
            table #records {
                thead { tr { @for c in &cols { th { (c) } } } }
                tbody {
                    @for r in &records {
                        @let id = r.get(lib.key).map(text_of).unwrap_or_default();
                        tr data-id=(id) {
                            @for c in &cols {
                                @if c == lib.key {
                                    td { a href=(record_href(lib.name, &id)) { (id) } }
                                } @else {
                                    td { (r.get(c).map(cell).unwrap_or_default()) }
                                }
                            }
                        }
                    }
                }
            }
        }
    };
    (StatusCode::OK, page(lib.name, Some(&session), body)).into_response()
}

/// What a record's page was reached after: a change just made.
#[derive(Debug, Default, Deserialize)]
pub(super) struct Done {
    /// `added` or `edited`.
    #[serde(default)]
    done: String,
}

/// `GET /kb/{library}/{id}`: one record, every field; for those who may
/// change the knowledge base, links to edit it, add a copy and remove it.
pub(super) async fn record(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((name, id)): Path<(String, String)>,
    Query(done): Query<Done>,
) -> Response {
    let lib = match lib_of(&session, &name) {
        Ok(l) => l,
        Err(r) => return r,
    };
    let id = match id_of(&session, &lib, &id) {
        Ok(id) => id,
        Err(r) => return r,
    };
    let rec = match read(&web.bus, &lib, Some(&id)).await {
        Ok(Ok(mut r)) if !r.is_empty() => r.swap_remove(0),
        Ok(Ok(_)) => return refused(&session, "No such record", &[], StatusCode::NOT_FOUND),
        Ok(Err(errors)) => {
            return refused(
                &session,
                &format!("{} {id}", lib.name),
                &errors,
                StatusCode::BAD_GATEWAY,
            );
        }
        Err(e) => return silent(&session, &e),
    };
    let here = record_href(lib.name, &id);
    let body = html! {
        p { a href=(library_href(lib.name)) { "← " (lib.name) } }
        h1 { (lib.name) " " (id) }
        @match done.done.as_str() {
            "added" => p.ok #done role="status" { "Added by " (session.user.name) ". The record as the knowledge base holds it now:" },
            "edited" => p.ok #done role="status" { "Changed by " (session.user.name) ". The record as the knowledge base holds it now:" },
            _ => {},
        }
        @if session.user.may_edit_kb() {
            p.actions {
                a #edit href=(format!("{here}/edit")) { "Edit" } " · "
                a #copy href=(format!("/kb/new/{}?from={}", segment(lib.name), segment(&id))) { "Add a copy" } " · "
                a #remove href=(format!("{here}/remove")) { "Remove" }
            }
        }
        (record_list(&lib, &rec))
        p { a href=(log_href(Some(lib.name), Some(&id))) { "Changes of this record" } }
    };
    (
        StatusCode::OK,
        page(&format!("{} {id}", lib.name), Some(&session), body),
    )
        .into_response()
}

/// The change log's filter: a library, a record of it, how many.
#[derive(Debug, Default, Deserialize)]
pub(super) struct LogQuery {
    #[serde(default)]
    library: String,
    #[serde(default)]
    record: String,
    #[serde(default)]
    limit: String,
}

/// `GET /kb/changes`: the change log newest first — when, who, what, the
/// library and record, and for an edit each field's old → new value —, of
/// every library or of one (`library`), of one record (`record`), at most
/// `limit` (default 50).
pub(super) async fn changes(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Query(q): Query<LogQuery>,
) -> Response {
    let limit = match q.limit.trim() {
        "" => KbLogRequest::DEFAULT_LIMIT,
        t => match t.parse::<u32>() {
            Ok(n) => n,
            Err(_) => {
                let e = Stage::Knowledge.error(
                    Code::FIELD_INVALID,
                    "limit",
                    format!("an integer in [1, {}]", KbLogRequest::MAX_LIMIT),
                    format!("{t:?}"),
                    "how many changes to show",
                );
                return refused(&session, "Change log", &[e], StatusCode::BAD_REQUEST);
            }
        },
    };
    let lib = q.library.trim();
    let rec = q.record.trim();
    // Each a library's name and a record's id, never a key pattern.
    if !lib.is_empty() {
        let library = match lib_of(&session, lib) {
            Ok(l) => l,
            Err(refusal) => return refusal,
        };
        if !rec.is_empty() {
            if let Err(refusal) = id_of(&session, &library, rec) {
                return refusal;
            }
        }
    }
    let (lib, rec) = (
        (!lib.is_empty()).then_some(lib),
        (!rec.is_empty() && !lib.is_empty()).then_some(rec),
    );
    let changes = match log(&web.bus, lib, rec, limit).await {
        Ok(Ok(c)) => c,
        Ok(Err(errors)) => {
            return refused(&session, "Change log", &errors, StatusCode::BAD_REQUEST)
        }
        Err(e) => return silent(&session, &e),
    };
    let title = match (lib, rec) {
        (Some(l), Some(r)) => format!("Changes of {l} {r}"),
        (Some(l), None) => format!("Changes of {l}"),
        _ => "Changes of the knowledge base".to_string(),
    };
    let body = html! {
        p { a href="/kb" { "← knowledge base" } }
        h1 { (title) }
        form method="get" action="/kb/changes" {
            label { "Library " select name="library" {
                option value="" selected[lib.is_none()] { "every library" }
                @for l in library::LIBRARIES {
                    option value=(l.name) selected[lib == Some(l.name)] { (l.name) }
                }
            } }
            @if let Some(r) = rec { input type="hidden" name="record" value=(r); }
            " " label { "At most " input name="limit" value=(limit) size="5" inputmode="numeric"; }
            " " button type="submit" { "Show" }
        }
        p.count { (changes.len()) " change(s), newest first" }
        table #changes {
            thead { tr { th { "when (UTC)" } th { "who" } th { "what" } th { "library" } th { "record" } th { "old → new" } } }
            tbody {
                @for c in &changes { (change_row(c)) }
            }
        }
    };
    (StatusCode::OK, page(&title, Some(&session), body)).into_response()
}

/// One change as a row of the log.
fn change_row(c: &KbChange) -> Markup {
    let when = gearcam_proto::utc_text(u64::try_from(c.at_ms).unwrap_or(0));
    let known = library::library(&c.library).is_ok();
    html! {
        tr.change data-seq=(c.seq) data-library=(c.library) data-record=(c.record_id) {
            td { (when) }
            td.by { (c.by) }
            td.op { (c.op) }
            td { @if known { a href=(super::library_href(&c.library)) { (c.library) } } @else { (c.library) } }
            td { @if known && c.op != "remove" { a href=(record_href(&c.library, &c.record_id)) { (c.record_id) } } @else { (c.record_id) } }
            td.diff { (diff(c)) }
        }
    }
}

/// What a change changed: for an edit, each field whose value differs,
/// old → new; for an addition or a removal, the record's fields.
fn diff(c: &KbChange) -> Markup {
    let old = c.old.as_ref().map(record_from_wire);
    let new = c.new.as_ref().map(record_from_wire);
    let fields = |r: &Record| flatten(r);
    match (old, new) {
        (Some(old), Some(new)) => {
            let mut lines = Vec::new();
            for (path, v) in fields(&new) {
                let before = value_at(&old, &path).cloned().unwrap_or(Value::Null);
                if before != v {
                    lines.push((path, text_of(&before), text_of(&v)));
                }
            }
            for (path, v) in fields(&old) {
                if value_at(&new, &path).is_none() {
                    lines.push((path, text_of(&v), String::new()));
                }
            }
            html! {
                @if lines.is_empty() { "no field changed" }
                ul.fields { @for (p, a, b) in &lines { li { code { (p) } ": " span.old { (a) } " → " span.new { (b) } } } }
            }
        }
        (None, Some(new)) => html! { "added: " (summary(&new)) },
        (Some(old), None) => html! { "removed: " (summary(&old)) },
        (None, None) => html! {},
    }
}

/// A record in one line: its fields `name = value`, cut.
fn summary(r: &Record) -> String {
    let text: Vec<String> = flatten(r)
        .iter()
        .filter(|(_, v)| !v.is_null())
        .map(|(k, v)| format!("{k} = {}", cell(v)))
        .collect();
    let line = text.join(", ");
    if line.chars().count() > 200 {
        format!("{}…", line.chars().take(200).collect::<String>())
    } else {
        line
    }
}
