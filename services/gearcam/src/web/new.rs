//! A new job: one form per family (the `form` module) with the knowledge
//! base's proposal beside each field (its value and source, and the cases
//! behind the plan), the typed errors beside the fields they name, import
//! and export of the TOML job file, and submit.
//!
//! The check while typing is `gearcam check` run here, on the page's data
//! directory (the knowledge base and template library `gearcam up` serves):
//! no round trip over the bus per keystroke. The job itself goes to the
//! station over the bus, and the services decide.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use axum::extract::{Multipart, Path, State};
use axum::http::{header, StatusCode};
use axum::response::{IntoResponse, Redirect, Response};
use axum::routing::{get, post};
use axum::{Extension, Json, Router};
use gearcam_proto::{Code, JobError, JobRequest, Stage};
use gearcam_template::Templates;
use maud::{html, Markup};
use serde::Serialize;

use super::auth::{self, CsrfForm, Session};
use super::form::{self, Field, Form, Kind};
use super::{errors_table, page, Web};
use crate::check::CheckReport;
use crate::jobfile;
use crate::station::{self, Outcome, SubmitOptions};

/// The local check: the data directory's knowledge base and templates.
#[derive(Debug)]
pub struct LocalCheck {
    /// The data directory.
    pub data: PathBuf,
    /// Its template library, compiled once.
    pub templates: Templates,
}

impl LocalCheck {
    /// The local check on the data directory `data` with its template
    /// library `templates`.
    pub fn new(data: &std::path::Path, templates: Templates) -> LocalCheck {
        LocalCheck {
            data: data.to_path_buf(),
            templates,
        }
    }

    /// `gearcam check` of `req`.
    fn check(&self, req: &JobRequest) -> CheckReport {
        if let Err(e) = jobfile::check_size(req) {
            return CheckReport::failed(vec![e]);
        }
        match gearcam_knowledge::db::open(&self.data.join("knowledge.db")) {
            Ok(conn) => crate::check::check(&conn, &self.templates, req, None).0,
            Err(e) => CheckReport::failed(vec![Stage::Knowledge.error(
                Code::DATA_DIR_NOT_WRITABLE,
                "data",
                "a readable knowledge base (knowledge.db)",
                self.data.display().to_string(),
                format!("the page cannot open its knowledge base: {e}"),
            )]),
        }
    }
}

/// The new job's pages.
pub(super) fn routes() -> Router<Web> {
    Router::new()
        .route("/new", get(choose))
        .route("/new/import", post(import))
        .route("/new/{form}", get(blank).post(act))
        .route("/check/{form}", post(check_json))
}

/// `GET /new`: the forms, and the import of a job file.
async fn choose(Extension(session): Extension<Session>) -> Markup {
    let body = html! {
        h1 { "New job" }
        ul.forms {
            @for f in form::forms() {
                li { a href=(format!("/new/{}", f.name)) { (f.title) } }
            }
        }
        h2 { "Import a job file" }
        form method="post" action="/new/import" enctype="multipart/form-data" {
            (auth::csrf_input(&session))
            input type="file" name="file" accept=".toml,text/plain" required;
            " " button type="submit" id="import" { "Import" }
        }
        p.help { "A TOML job file as " code { "gearcam submit" } " reads it (at most 64 KiB)." }
    };
    page("New job", Some(&session), body)
}

/// `GET /new/{form}`: the form with the example's values.
async fn blank(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(name): Path<String>,
) -> Response {
    let Some(f) = form::form(&name) else {
        return no_form(&name);
    };
    let values: Vec<(String, String)> = f
        .fields
        .iter()
        .filter(|x| !x.optional)
        .map(|x| (x.name(), x.example.clone()))
        .collect();
    let checked = check_values(&web, &f, &values, &session).await;
    (StatusCode::OK, render(&session, &f, &values, &checked, &[])).into_response()
}

fn no_form(name: &str) -> Response {
    let names: Vec<&str> = form::forms().iter().map(|f| f.name).collect();
    auth::refuse(
        StatusCode::NOT_FOUND,
        &format!("form: expected one of {}, got {name:?}", names.join(", ")),
    )
}

/// What a check of the form's values gave.
#[derive(Debug, Default, Serialize)]
struct Checked {
    /// Every error: the form's own (a wrong type) or the check's.
    errors: Vec<JobError>,
    /// The knowledge base's proposals by form field: value and source.
    proposals: Vec<Proposal>,
    /// The cases behind the plan.
    cases: Vec<crate::check::CaseSummary>,
    /// The check's warnings.
    warnings: Vec<gearcam_proto::Warning>,
    /// True when the job passed every check.
    ok: bool,
}

/// One proposal of the knowledge base, for a form field.
#[derive(Debug, Serialize)]
struct Proposal {
    field: String,
    value: f64,
    source: String,
}

/// The request of the form's values, by `session`'s user, or the typed
/// errors of the form and the job file.
fn request_of(
    f: &Form,
    values: &[(String, String)],
    session: &Session,
) -> Result<JobRequest, Vec<JobError>> {
    let text = form::job_file(f, values)?;
    let spec = jobfile::parse(&text, "the form").map_err(|e| vec![e])?;
    Ok(JobRequest {
        job_id: jobfile::job_id(&spec),
        submitted_at_ms: gearcam_proto::now_ms(),
        submitted_by: session.user.name.clone(),
        spec,
    })
}

async fn check_values(
    web: &Web,
    f: &Form,
    values: &[(String, String)],
    session: &Session,
) -> Checked {
    let req = match request_of(f, values, session) {
        Ok(r) => r,
        Err(errors) => {
            return Checked {
                errors,
                ..Checked::default()
            }
        }
    };
    let Some(local) = web.local.clone() else {
        return Checked {
            ok: true,
            ..Checked::default()
        };
    };
    let report = tokio::task::spawn_blocking(move || local.check(&req))
        .await
        .unwrap_or_else(|e| {
            CheckReport::failed(vec![Stage::Station.error(
                Code::JOB_FILE_INVALID,
                "-",
                "a check that ends",
                "a failed check",
                format!("the check stopped: {e}"),
            )])
        });
    checked_of(f, report)
}

fn checked_of(f: &Form, report: CheckReport) -> Checked {
    let mut proposals = Vec::new();
    let mut cases = Vec::new();
    if let Some(plan) = &report.plan {
        for (key, value) in &plan.values {
            // The knowledge base's own proposal, also where the job overrides it.
            let sourced = plan.proposed.get(key).unwrap_or(value);
            if sourced.source == gearcam_proto::Source::Job {
                continue;
            }
            if let Some(field) = field_for(f, key) {
                let source = serde_json::to_value(sourced.source)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_default();
                proposals.push(Proposal {
                    field: field.name(),
                    value: sourced.value,
                    source,
                });
            }
        }
        cases = plan.cases.clone();
    }
    Checked {
        ok: report.ok,
        errors: report.errors,
        warnings: report.warnings,
        proposals,
        cases,
    }
}

/// The form field a plan value or an error names: the same name, or the
/// only field with that key.
fn field_for<'a>(f: &'a Form, name: &str) -> Option<&'a Field> {
    if let Some(x) = f.fields.iter().find(|x| x.name() == name) {
        return Some(x);
    }
    // A name in a section the form has, but not a field of it (e.g. the
    // library hob's `hob.module_mm`), belongs to no field.
    if let Some((section, _)) = name.split_once('.') {
        if f.fields.iter().any(|x| x.section == section) {
            return None;
        }
    }
    let key = name.rsplit('.').next().unwrap_or(name);
    let mut same = f.fields.iter().filter(|x| x.key == key);
    match (same.next(), same.next()) {
        (Some(x), None) => Some(x),
        _ => None,
    }
}

/// The form, its values, and what the check said beside each field.
fn render(
    session: &Session,
    f: &Form,
    values: &[(String, String)],
    checked: &Checked,
    notes: &[String],
) -> Markup {
    let value_of = |name: &str| {
        values
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.clone())
            .unwrap_or_default()
    };
    let unplaced: Vec<JobError> = checked
        .errors
        .iter()
        .filter(|e| field_for(f, &e.field).is_none())
        .cloned()
        .collect();
    let mut sections: Vec<&str> = Vec::new();
    for x in &f.fields {
        if !sections.contains(&x.section.as_str()) {
            sections.push(&x.section);
        }
    }
    let body = html! {
        p { a href="/new" { "← forms" } }
        h1 { (f.title) }
        @for n in notes { p.refused role="alert" { (n) } }
        div #summary role="status" {
            (summary(checked, &unplaced))
        }
        form #job method="post" action=(format!("/new/{}", f.name)) data-check=(format!("/check/{}", f.name)) {
            (auth::csrf_input(session))
            @for s in &sections {
                fieldset {
                    legend { "[" (s) "]" }
                    @for x in f.fields.iter().filter(|x| x.section == *s) {
                        (field(x, &value_of(&x.name()), checked))
                    }
                }
            }
            p {
                button type="submit" name="action" value="check" id="check" { "Check" } " "
                button type="submit" name="action" value="submit" id="submit" { "Submit" } " "
                button type="submit" name="action" value="export" id="export" { "Export TOML" }
            }
        }
    };
    page(f.title, Some(session), body)
}

/// The check's verdict, its errors that name no field of the form, and
/// the cases behind the proposals.
fn summary(checked: &Checked, unplaced: &[JobError]) -> Markup {
    html! {
        @if checked.ok && checked.errors.is_empty() {
            p.ok { "The job passes every check here." }
        } @else {
            p.refused { (checked.errors.len()) " error(s): the job would be refused." }
        }
        @if !unplaced.is_empty() { (errors_table(unplaced)) }
        @if !checked.warnings.is_empty() {
            ul.warnings { @for w in &checked.warnings { li { code { (w.code) } " " (w.field) ": " (w.message) } } }
        }
        @if !checked.cases.is_empty() {
            p.cases { "Proposals from the cases: "
                @for c in &checked.cases { span.case { (c.id) " (similarity " (format!("{:.2}", c.similarity)) ", " (c.provenance) ") " } }
            }
        }
    }
}

/// One field: label with unit, input, proposal and errors.
fn field(x: &Field, value: &str, checked: &Checked) -> Markup {
    let name = x.name();
    let proposal = checked.proposals.iter().find(|p| p.field == name);
    let errors: Vec<&JobError> = checked
        .errors
        .iter()
        .filter(|e| e.field == name || e.field.ends_with(&format!(".{name}")))
        .collect();
    html! {
        p.field data-field=(name) {
            label {
                span.label { (x.label()) @if x.optional { " (optional)" } } " "
                @match x.kind {
                    Kind::Bool => select name=(name) {
                        @if x.optional { option value="" selected[value.is_empty()] { "—" } }
                        option value="true" selected[value == "true"] { "true" }
                        option value="false" selected[value == "false"] { "false" }
                    },
                    _ => input name=(name) value=(value) placeholder=(x.example)
                        inputmode=[matches!(x.kind, Kind::Int | Kind::Float).then_some("decimal")];,
                }
            }
            " "
            span.proposal {
                @if let Some(p) = proposal { "proposed " (num(p.value)) " from " (p.source) }
            }
            span.field-error role="alert" {
                @for e in &errors { (e.code) ": expected " (e.expected) ", got " (e.got) ". " }
            }
            @if !x.help.is_empty() { br; small.help { (x.help) } }
        }
    }
}

/// A number as the report prints it: at most 4 decimals, no trailing zeros.
fn num(v: f64) -> String {
    let s = format!("{v:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The form's fields and which button was pressed.
type Fields = Vec<(String, String)>;

/// `POST /new/{form}`: check, submit or export the form's job.
async fn act(
    State(web): State<Web>,
    Path(name): Path<String>,
    CsrfForm { session, form: all }: CsrfForm<Fields>,
) -> Response {
    let Some(f) = form::form(&name) else {
        return no_form(&name);
    };
    let action = all
        .iter()
        .find(|(k, _)| k == "action")
        .map_or("check", |(_, v)| v.as_str())
        .to_string();
    let values: Fields = all
        .into_iter()
        .filter(|(k, _)| k != "action" && k != auth::CSRF_FIELD)
        .collect();
    match action.as_str() {
        "export" => export(&f, &values, &session),
        "submit" => submit(&web, &f, &values, &session).await,
        _ => {
            let checked = check_values(&web, &f, &values, &session).await;
            (StatusCode::OK, render(&session, &f, &values, &checked, &[])).into_response()
        }
    }
}

/// The form's job file as a download, or the form with its typed errors.
fn export(f: &Form, values: &[(String, String)], session: &Session) -> Response {
    match form::job_file(f, values) {
        Ok(text) => {
            let part = values
                .iter()
                .find(|(k, _)| k == "job.part_number")
                .map_or("job", |(_, v)| v.as_str());
            let file: String = part
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '-' {
                        c
                    } else {
                        '_'
                    }
                })
                .take(40)
                .collect();
            let header_text = format!(
                "# gearcam job file, exported from the web page by {}\n",
                session.user.name
            );
            (
                [
                    (
                        header::CONTENT_TYPE,
                        "application/toml; charset=utf-8".to_string(),
                    ),
                    (
                        header::CONTENT_DISPOSITION,
                        format!("attachment; filename=\"{file}.toml\""),
                    ),
                ],
                format!("{header_text}{text}"),
            )
                .into_response()
        }
        Err(errors) => {
            let checked = Checked {
                errors,
                ..Checked::default()
            };
            (
                StatusCode::UNPROCESSABLE_ENTITY,
                render(session, f, values, &checked, &[]),
            )
                .into_response()
        }
    }
}

/// Submits the form's job to the station; its page follows it live.
async fn submit(web: &Web, f: &Form, values: &[(String, String)], session: &Session) -> Response {
    let req = match request_of(f, values, session) {
        Ok(r) => r,
        Err(errors) => {
            let checked = Checked {
                errors,
                ..Checked::default()
            };
            return (
                StatusCode::UNPROCESSABLE_ENTITY,
                render(session, f, values, &checked, &[]),
            )
                .into_response();
        }
    };
    if let Err(e) = jobfile::check_size(&req) {
        let checked = Checked {
            errors: vec![e],
            ..Checked::default()
        };
        return (
            StatusCode::PAYLOAD_TOO_LARGE,
            render(session, f, values, &checked, &[]),
        )
            .into_response();
    }
    let opts = SubmitOptions {
        wait: false,
        alive_timeout: Duration::from_secs(5),
        timeout: Duration::from_secs(10),
    };
    match station::submit(&web.bus, &req, &opts, |_| {}).await {
        Ok(Outcome::Failed(errors)) => {
            let checked = Checked {
                errors,
                ..Checked::default()
            };
            (
                StatusCode::UNPROCESSABLE_ENTITY,
                render(
                    session,
                    f,
                    values,
                    &checked,
                    &["The station refused the job.".into()],
                ),
            )
                .into_response()
        }
        Ok(_) => Redirect::to(&format!("/jobs/{}", req.job_id)).into_response(),
        Err(e) => {
            let note = format!("Not submitted: {e}");
            (
                StatusCode::SERVICE_UNAVAILABLE,
                render(session, f, values, &Checked::default(), &[note]),
            )
                .into_response()
        }
    }
}

/// `POST /check/{form}`: the check of the form's values as JSON, for the
/// page's script (errors beside fields while typing).
async fn check_json(
    State(web): State<Web>,
    Path(name): Path<String>,
    CsrfForm { session, form: all }: CsrfForm<Fields>,
) -> Response {
    let Some(f) = form::form(&name) else {
        return no_form(&name);
    };
    let values: Fields = all
        .into_iter()
        .filter(|(k, _)| k != "action" && k != auth::CSRF_FIELD)
        .collect();
    let mut checked = check_values(&web, &f, &values, &session).await;
    // Each error as the page places it: under its form field when one has its name.
    for e in &mut checked.errors {
        if let Some(x) = field_for(&f, &e.field) {
            e.field = x.name();
        }
    }
    Json(checked).into_response()
}

/// `POST /new/import`: a TOML job file uploaded into its family's form.
async fn import(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    mut multipart: Multipart,
) -> Response {
    let mut csrf = String::new();
    let mut text = None;
    while let Ok(Some(part)) = multipart.next_field().await {
        match part.name() {
            Some(auth::CSRF_FIELD) => csrf = part.text().await.unwrap_or_default(),
            Some("file") => match part.bytes().await {
                Ok(b) => text = Some(b),
                Err(e) => {
                    return auth::refuse(
                        StatusCode::PAYLOAD_TOO_LARGE,
                        &format!("file: expected a job file of at most 64 KiB: {e}"),
                    )
                }
            },
            _ => {}
        }
    }
    if let Err(refused) = auth::csrf_matches(&session, &csrf) {
        return refused;
    }
    let Some(bytes) = text else {
        return auth::refuse(
            StatusCode::BAD_REQUEST,
            "file: expected a TOML job file, got none",
        );
    };
    let Ok(text) = String::from_utf8(bytes.to_vec()) else {
        return auth::refuse(
            StatusCode::UNPROCESSABLE_ENTITY,
            "file: expected a TOML job file in UTF-8, got bytes that are not UTF-8",
        );
    };
    let Some(f) = form::form_for(&text) else {
        let why = match text.parse::<toml::Table>() {
            Err(e) => format!("file: expected a TOML job file, got one that does not parse: {e}"),
            Ok(_) => "file: [job] family: expected hobbing, spiral-face or wire-edm".to_string(),
        };
        return auth::refuse(StatusCode::UNPROCESSABLE_ENTITY, &why);
    };
    match form::values_of(&f, &text) {
        Ok(values) => {
            let checked = check_values(&web, &f, &values, &session).await;
            (StatusCode::OK, render(&session, &f, &values, &checked, &[])).into_response()
        }
        Err(lost) => auth::refuse(
            StatusCode::UNPROCESSABLE_ENTITY,
            &format!(
                "file: this form holds one gear and no other keys; the file also has {} — submit it with `gearcam submit`",
                lost.join(", ")
            ),
        ),
    }
}

/// The local check, shared by the page's handlers.
pub type Local = Option<Arc<LocalCheck>>;
