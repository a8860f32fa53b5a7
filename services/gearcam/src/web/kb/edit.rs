//! Changing the knowledge base from the page, for users whose role may
//! (admin, supervisor): a record's form with one input per field (units in
//! the labels), an addition (blank, or a copy of a record), a removal after
//! a page that asks first. The change goes to the knowledge service under
//! the signed-in user's name; its typed errors are shown beside the fields
//! they name, and nothing is changed unless the whole record is valid.
//! Every other role gets no controls and a 403 naming its role.

use std::collections::BTreeMap;

use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Redirect, Response};
use axum::Extension;
use gearcam_knowledge::library::{Kind, Library, Record};
use gearcam_proto::plan::{KbOp, KbRecord, KbRequest};
use gearcam_proto::JobError;
use maud::{html, Markup};
use serde::Deserialize;
use serde_json::Value;

use super::super::auth::{self, CsrfForm, Session};
use super::super::{errors_table, page, Web};
use super::{
    change, flatten, forbidden, id_of, lib_of, library_href, read, record_href, record_list,
    refused, segment, silent, slots, text_of, typed, value_at, wire, Slot,
};

/// A form's fields as sent: name and text, in order.
type Fields = Vec<(String, String)>;

/// The hidden field of an addition naming the record it copies.
const FROM_FIELD: &str = "_from";

/// The record's texts of a sent form: the last text of each name, without
/// the CSRF token and the copied record's id.
fn texts(fields: &Fields) -> BTreeMap<String, String> {
    fields
        .iter()
        .filter(|(k, _)| k != auth::CSRF_FIELD && k != FROM_FIELD)
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect()
}

/// What a record's form shows.
struct FormView<'a> {
    lib: &'a Library,
    title: String,
    /// Where the form is sent.
    action: String,
    /// Where "back" and "cancel" lead.
    back: String,
    slots: Vec<Slot>,
    /// Each field's text.
    values: BTreeMap<String, String>,
    /// The knowledge service's errors (each beside the field it names).
    errors: Vec<JobError>,
    /// The key field cannot change (an edit).
    key_fixed: bool,
    /// The record an addition copies.
    from: Option<String>,
    /// Notes above the form.
    notes: Vec<String>,
    /// The submit button's text.
    submit: &'static str,
}

/// The form: the errors that name no field on top, then one input per
/// field with its label (and unit), meaning, need and its errors.
fn render(session: &Session, v: &FormView<'_>) -> Markup {
    let unplaced: Vec<JobError> = v
        .errors
        .iter()
        .filter(|e| !v.slots.iter().any(|s| s.name == e.field))
        .cloned()
        .collect();
    let body = html! {
        p { a href=(v.back) { "← back" } }
        h1 { (v.title) }
        @for n in &v.notes { p.note role="status" { (n) } }
        @if !v.errors.is_empty() {
            p.refused #summary role="alert" { (v.errors.len()) " error(s) from the knowledge base: nothing was changed." }
        }
        @if !unplaced.is_empty() { (errors_table(&unplaced)) }
        form #record method="post" action=(v.action) {
            (auth::csrf_input(session))
            @if let Some(f) = &v.from { input type="hidden" name=(FROM_FIELD) value=(f); }
            @for s in &v.slots {
                (field(s, v.values.get(&s.name).map_or("", String::as_str), &v.errors,
                       v.key_fixed && s.name == v.lib.key))
            }
            p { button type="submit" #save { (v.submit) } " " a href=(v.back) { "Cancel" } }
        }
    };
    page(&v.title, Some(session), body)
}

/// One field of the form: its input (a choice where the library lists the
/// values), meaning and need, and the errors that name it.
fn field(s: &Slot, value: &str, errors: &[JobError], fixed: bool) -> Markup {
    let mine: Vec<&JobError> = errors.iter().filter(|e| e.field == s.name).collect();
    let numeric = matches!(s.kind, Some(Kind::Real | Kind::Int));
    html! {
        p.field data-field=(s.name) {
            label {
                span.label { (s.label) } " "
                @if fixed {
                    input name=(s.name) value=(value) readonly;
                } @else if s.kind == Some(Kind::Bool) {
                    select name=(s.name) {
                        option value="" selected[value.is_empty()] { "—" }
                        option value="true" selected[value == "true"] { "true" }
                        option value="false" selected[value == "false"] { "false" }
                    }
                } @else if !s.choices.is_empty() {
                    select name=(s.name) {
                        option value="" selected[value.is_empty()] { "—" }
                        @for c in s.choices { option value=(c) selected[value == *c] { (c) } }
                        @if !value.is_empty() && !s.choices.contains(&value) {
                            option value=(value) selected { (value) }
                        }
                    }
                } @else {
                    input name=(s.name) value=(value) placeholder=(s.need)
                        inputmode=[numeric.then_some("decimal")];
                }
            }
            " "
            small.help { (s.doc) @if !s.doc.is_empty() { "; " } (s.need) }
            " "
            span.field-error role="alert" {
                @for e in &mine {
                    code { (e.code) } ": expected " (e.expected) ", got " (e.got) ". " (e.message) " "
                }
            }
        }
    }
}

/// The record `id` of `lib`, or the page saying why there is none.
async fn current(
    web: &Web,
    session: &Session,
    lib: &Library,
    id: &str,
) -> Result<Record, Response> {
    match read(&web.bus, lib, Some(id)).await {
        Ok(Ok(mut r)) if !r.is_empty() => Ok(r.swap_remove(0)),
        Ok(Ok(_)) => Err(refused(
            session,
            "No such record",
            &[],
            StatusCode::NOT_FOUND,
        )),
        Ok(Err(errors)) => Err(refused(
            session,
            &format!("{} {id}", lib.name),
            &errors,
            StatusCode::BAD_GATEWAY,
        )),
        Err(e) => Err(silent(session, &e)),
    }
}

/// Each field's text in a record.
fn texts_of(rec: &Record) -> BTreeMap<String, String> {
    flatten(rec)
        .into_iter()
        .map(|(k, v)| (k, text_of(&v)))
        .collect()
}

/// The library and record id of a path, with the record, for a change by
/// a user who may make it; else the page that refuses.
async fn editable(
    web: &Web,
    session: &Session,
    name: &str,
    id: &str,
) -> Result<(Library, String, Record), Response> {
    if !session.user.may_edit_kb() {
        return Err(forbidden(session));
    }
    let lib = lib_of(session, name)?;
    let id = id_of(session, &lib, id)?;
    let rec = current(web, session, &lib, &id).await?;
    Ok((lib, id, rec))
}

/// The edit form of `rec` with `values` and the service's `errors`.
fn edit_view<'a>(
    lib: &'a Library,
    id: &str,
    rec: &Record,
    values: BTreeMap<String, String>,
    errors: Vec<JobError>,
    notes: Vec<String>,
) -> FormView<'a> {
    let here = record_href(lib.name, id);
    FormView {
        lib,
        title: format!("Edit {} {id}", lib.name),
        action: format!("{here}/edit"),
        back: here,
        slots: slots(lib, Some(rec)),
        values,
        errors,
        key_fixed: true,
        from: None,
        notes,
        submit: "Save",
    }
}

/// `GET /kb/{library}/{id}/edit`: the record's form.
pub(super) async fn edit_form(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((name, id)): Path<(String, String)>,
) -> Response {
    let (lib, id, rec) = match editable(&web, &session, &name, &id).await {
        Ok(x) => x,
        Err(r) => return r,
    };
    let view = edit_view(&lib, &id, &rec, texts_of(&rec), vec![], vec![]);
    (StatusCode::OK, render(&session, &view)).into_response()
}

/// `POST /kb/{library}/{id}/edit`: the fields whose text differs from the
/// record's, sent as an edit; the record after it, or the form again with
/// the service's errors beside their fields.
pub(super) async fn edit(
    State(web): State<Web>,
    Path((name, id)): Path<(String, String)>,
    CsrfForm { session, form }: CsrfForm<Fields>,
) -> Response {
    let (lib, id, rec) = match editable(&web, &session, &name, &id).await {
        Ok(x) => x,
        Err(r) => return r,
    };
    let values = texts(&form);
    let mut set = Record::new();
    for s in slots(&lib, Some(&rec)) {
        let Some(text) = values.get(&s.name) else {
            continue;
        };
        let now = value_at(&rec, &s.name);
        if s.name != lib.key && text.trim() != now.map(text_of).unwrap_or_default().trim() {
            set.insert(s.name.clone(), typed(&s, now, text));
        }
    }
    if set.is_empty() {
        let note = "Nothing changed: every field holds the record's value.".to_string();
        let view = edit_view(&lib, &id, &rec, values, vec![], vec![note]);
        return (StatusCode::OK, render(&session, &view)).into_response();
    }
    let req = KbRequest {
        op: KbOp::Edit,
        record: None,
        set: wire(&set),
        by: session.user.name.clone(),
    };
    match change(&web.bus, &session.user.name, &lib, Some(&id), &req).await {
        Ok(Ok(_)) => {
            Redirect::to(&format!("{}?done=edited", record_href(lib.name, &id))).into_response()
        }
        Ok(Err(errors)) => {
            let view = edit_view(&lib, &id, &rec, values, errors, vec![]);
            (StatusCode::UNPROCESSABLE_ENTITY, render(&session, &view)).into_response()
        }
        Err(e) => silent(&session, &e),
    }
}

/// The record an addition starts from.
#[derive(Debug, Default, Deserialize)]
pub(super) struct FromQuery {
    /// The id of a record to copy (empty: none).
    #[serde(default)]
    from: String,
}

/// The record an addition to `lib` copies: `from`'s, or, for a library of
/// nested records (machines) whose form needs one, its first record.
async fn template(
    web: &Web,
    session: &Session,
    lib: &Library,
    from: &str,
) -> Result<Option<Record>, Response> {
    if !from.trim().is_empty() {
        let id = id_of(session, lib, from.trim())?;
        return current(web, session, lib, &id).await.map(Some);
    }
    if !lib.fields.is_empty() {
        return Ok(None);
    }
    match read(&web.bus, lib, None).await {
        Ok(Ok(mut all)) if !all.is_empty() => Ok(Some(all.swap_remove(0))),
        Ok(Ok(_)) => Ok(None),
        Ok(Err(errors)) => Err(refused(session, lib.name, &errors, StatusCode::BAD_GATEWAY)),
        Err(e) => Err(silent(session, &e)),
    }
}

/// The addition form of `lib` (copying `from`, when given).
fn add_view<'a>(
    lib: &'a Library,
    template: Option<&Record>,
    from: Option<String>,
    values: BTreeMap<String, String>,
    errors: Vec<JobError>,
) -> FormView<'a> {
    FormView {
        lib,
        title: format!("Add to {}", lib.name),
        action: format!("/kb/new/{}", segment(lib.name)),
        back: library_href(lib.name),
        slots: slots(lib, template),
        values,
        errors,
        key_fixed: false,
        from,
        notes: vec![],
        submit: "Add",
    }
}

/// `GET /kb/new/{library}`: a blank record's form (defaults as
/// placeholders), or a copy of `?from=ID` with its key left to give.
pub(super) async fn add_form(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(name): Path<String>,
    Query(q): Query<FromQuery>,
) -> Response {
    if !session.user.may_edit_kb() {
        return forbidden(&session);
    }
    let lib = match lib_of(&session, &name) {
        Ok(l) => l,
        Err(r) => return r,
    };
    let template = match template(&web, &session, &lib, &q.from).await {
        Ok(t) => t,
        Err(r) => return r,
    };
    let mut values = template.as_ref().map(texts_of).unwrap_or_default();
    values.remove(lib.key);
    let from = (!q.from.trim().is_empty()).then(|| q.from.trim().to_string());
    let view = add_view(&lib, template.as_ref(), from, values, vec![]);
    (StatusCode::OK, render(&session, &view)).into_response()
}

/// Puts `v` at a dotted path of `rec`, making the nested maps on the way.
fn put_path(rec: &mut Record, path: &str, v: Value) {
    match path.split_once('.') {
        None => {
            rec.insert(path.to_string(), v);
        }
        Some((head, rest)) => {
            let inner = rec
                .entry(head.to_string())
                .or_insert_with(|| Value::Object(Record::new()));
            if !inner.is_object() {
                *inner = Value::Object(Record::new());
            }
            if let Value::Object(m) = inner {
                put_path(m, rest, v);
            }
        }
    }
}

/// `POST /kb/new/{library}`: the fields given, sent as an addition; the new
/// record, or the form again with the service's errors beside their fields.
pub(super) async fn add(
    State(web): State<Web>,
    Path(name): Path<String>,
    CsrfForm { session, form }: CsrfForm<Fields>,
) -> Response {
    if !session.user.may_edit_kb() {
        return forbidden(&session);
    }
    let lib = match lib_of(&session, &name) {
        Ok(l) => l,
        Err(r) => return r,
    };
    let from = form
        .iter()
        .rev()
        .find(|(k, _)| k == FROM_FIELD)
        .map(|(_, v)| v.clone())
        .unwrap_or_default();
    let template = match template(&web, &session, &lib, &from).await {
        Ok(t) => t,
        Err(r) => return r,
    };
    let values = texts(&form);
    let mut rec = Record::new();
    for s in slots(&lib, template.as_ref()) {
        match values.get(&s.name) {
            Some(text) if !text.trim().is_empty() => {
                let like = template.as_ref().and_then(|t| value_at(t, &s.name));
                put_path(&mut rec, &s.name, typed(&s, like, text));
            }
            _ => {}
        }
    }
    let req = KbRequest {
        op: KbOp::Add,
        record: Some(wire(&rec)),
        set: KbRecord::new(),
        by: session.user.name.clone(),
    };
    match change(&web.bus, &session.user.name, &lib, None, &req).await {
        Ok(Ok(added)) => {
            let id = added
                .first()
                .and_then(|r| r.get(lib.key))
                .map(text_of)
                .unwrap_or_default();
            Redirect::to(&format!("{}?done=added", record_href(lib.name, &id))).into_response()
        }
        Ok(Err(errors)) => {
            let from = (!from.trim().is_empty()).then(|| from.trim().to_string());
            let view = add_view(&lib, template.as_ref(), from, values, errors);
            (StatusCode::UNPROCESSABLE_ENTITY, render(&session, &view)).into_response()
        }
        Err(e) => silent(&session, &e),
    }
}

/// `GET /kb/{library}/{id}/remove`: the record, and a form that asks
/// whether to remove it.
pub(super) async fn remove_form(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((name, id)): Path<(String, String)>,
) -> Response {
    let (lib, id, rec) = match editable(&web, &session, &name, &id).await {
        Ok(x) => x,
        Err(r) => return r,
    };
    let here = record_href(lib.name, &id);
    let title = format!("Remove {} {id}?", lib.name);
    let body = html! {
        p { a href=(here) { "← back" } }
        h1 { (title) }
        p { "The record leaves the knowledge base; the change log keeps it, with your name." }
        form #remove-form method="post" action=(format!("{here}/remove")) {
            (auth::csrf_input(&session))
            button type="submit" #confirm-remove { "Remove " (id) } " "
            a href=(here) { "Cancel" }
        }
        (record_list(&lib, &rec))
    };
    (StatusCode::OK, page(&title, Some(&session), body)).into_response()
}

/// `POST /kb/{library}/{id}/remove`: the removal; the removed record, or the
/// service's errors.
pub(super) async fn remove(
    State(web): State<Web>,
    Path((name, id)): Path<(String, String)>,
    CsrfForm { session, form }: CsrfForm<Fields>,
) -> Response {
    let _ = form;
    let (lib, id, _) = match editable(&web, &session, &name, &id).await {
        Ok(x) => x,
        Err(r) => return r,
    };
    let req = KbRequest {
        op: KbOp::Remove,
        record: None,
        set: KbRecord::new(),
        by: session.user.name.clone(),
    };
    match change(&web.bus, &session.user.name, &lib, Some(&id), &req).await {
        Ok(Ok(removed)) => {
            let title = format!("Removed {} {id}", lib.name);
            let body = html! {
                p { a href=(library_href(lib.name)) { "← " (lib.name) } }
                h1 { (title) }
                p.ok #done role="status" { "Removed by " (session.user.name) ". The record as it was:" }
                @if let Some(r) = removed.first() { (record_list(&lib, r)) }
            };
            (StatusCode::OK, page(&title, Some(&session), body)).into_response()
        }
        Ok(Err(errors)) => refused(
            &session,
            &format!("{} {id} not removed", lib.name),
            &errors,
            StatusCode::UNPROCESSABLE_ENTITY,
        ),
        Err(e) => silent(&session, &e),
    }
}
