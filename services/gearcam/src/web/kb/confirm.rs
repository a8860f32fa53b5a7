//! Confirming a delivered job from the page, what `gearcam confirm` does:
//! the values actually used (the plan's proposed) and the outcome go to
//! the knowledge service under the signed-in user's name; the job becomes
//! a case, shown with the hob after its wear, or the service's typed
//! errors are shown beside the fields they name. Every role may confirm.

use std::collections::BTreeMap;

use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Extension;
use gearcam_knowledge::library::record_from_wire;
use gearcam_knowledge::library::{self, Record};
use gearcam_proto::plan::{ConfirmReply, ConfirmRequest};
use gearcam_proto::{Code, JobError, JobId, Stage};
use maud::{html, Markup};
use serde_json::Value;

use super::super::auth::{self, CsrfForm, Session};
use super::super::{errors_table, page, Web};
use super::{confirm_job, read, record_href, record_list, silent, text_of};

/// The outcomes a confirmation takes (the cases' `outcome`).
const OUTCOMES: [&str; 4] = ["ok", "rework", "scrap", "unknown"];

/// The trust a new case gets unless the form says otherwise (as the CLI's).
const CONFIDENCE: &str = "0.8";

/// What the knowledge base knows of the job: its state and family, and
/// the values its plan proposes, as text.
#[derive(Debug, Default)]
struct Planned {
    /// `planned`, `delivered`, `confirmed` or `refused`.
    state: String,
    /// The job's class (`cylindrical`, `spiral-face`, `wire-die`, …).
    class: String,
    /// Proposed values by form field.
    values: BTreeMap<&'static str, String>,
}

impl Planned {
    fn spiral(&self) -> bool {
        self.class.starts_with("spiral")
    }
}

/// The job's record in the jobs library: its state, class, quantity and
/// the plan's cutting speed, feed and cuts (a spiral plan's feed per
/// tooth and depth passes).
fn planned(job: &Record) -> Planned {
    let plan: Value = job
        .get("plan_json")
        .and_then(Value::as_str)
        .and_then(|t| serde_json::from_str(t).ok())
        .unwrap_or(Value::Null);
    // A plan's value is a number, or a sourced one ({value, source}).
    let at = |ptr: &str| {
        plan.pointer(ptr)
            .map(|v| v.get("value").unwrap_or(v))
            .filter(|v| v.is_number())
            .map(text_of)
    };
    let mut values = BTreeMap::new();
    let found = [
        ("quantity", job.get("quantity").map(text_of)),
        ("cutting_speed_m_min", at("/process/cutting_speed_m_min")),
        (
            "feed_mm_per_rev",
            at("/process/feed_mm_per_rev").or_else(|| at("/process/feed_per_tooth_mm")),
        ),
        (
            "cuts",
            at("/process/cuts").or_else(|| at("/process/passes")),
        ),
    ];
    for (k, v) in found {
        if let Some(v) = v.filter(|v| !v.is_empty()) {
            values.insert(k, v);
        }
    }
    Planned {
        state: job.get("state").map(text_of).unwrap_or_default(),
        class: job.get("class").map(text_of).unwrap_or_default(),
        values,
    }
}

/// The job's id from the path, or the page saying it is none.
fn job_of(session: &Session, job: &str) -> Result<JobId, Response> {
    JobId::new(job).map_err(|e| {
        let err = Stage::Knowledge.error(
            Code::BAD_JOB_ID,
            "job",
            "a job id: 1–64 characters A–Z a–z 0–9 _ - starting with a letter or digit",
            job,
            e.to_string(),
        );
        super::refused(session, "No such job", &[err], StatusCode::NOT_FOUND)
    })
}

/// What the knowledge base knows of `job`, or its typed errors (e.g. a job
/// it never planned), or the page of a service that does not answer.
async fn known(
    web: &Web,
    session: &Session,
    job: &JobId,
) -> Result<Result<Planned, Vec<JobError>>, Response> {
    match read(&web.bus, &library::JOBS, Some(job.as_str())).await {
        Ok(Ok(r)) => Ok(r.first().map(planned).ok_or_else(Vec::new)),
        Ok(Err(errors)) => Ok(Err(errors)),
        Err(e) => Err(silent(session, &e)),
    }
}

/// `GET /jobs/{job}/confirm`: the form of `gearcam confirm`, with the job's
/// planned values proposed.
pub(super) async fn form(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(job): Path<String>,
) -> Response {
    let job = match job_of(&session, &job) {
        Ok(j) => j,
        Err(r) => return r,
    };
    let (plan, errors) = match known(&web, &session, &job).await {
        Ok(Ok(p)) => (p, vec![]),
        Ok(Err(errors)) => (Planned::default(), errors),
        Err(r) => return r,
    };
    let mut values: BTreeMap<String, String> = plan
        .values
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    values.insert("outcome".into(), "ok".into());
    values.insert("confidence".into(), CONFIDENCE.into());
    (
        StatusCode::OK,
        render(&session, &job, &plan, &values, &errors),
    )
        .into_response()
}

/// The form with its values and the errors beside the fields they name.
fn render(
    session: &Session,
    job: &JobId,
    plan: &Planned,
    values: &BTreeMap<String, String>,
    errors: &[JobError],
) -> Markup {
    let spiral = plan.spiral();
    let fields: [(&str, String, &str); 7] = [
        ("quantity", "parts cut".into(), "the job's quantity"),
        (
            "cutting_speed_m_min",
            "cutting speed (m/min)".into(),
            "the plan's",
        ),
        (
            "feed_mm_per_rev",
            if spiral {
                "feed per tooth (mm)"
            } else {
                "feed (mm/rev)"
            }
            .into(),
            "the plan's",
        ),
        (
            "cuts",
            if spiral { "depth passes" } else { "cuts" }.into(),
            "the plan's",
        ),
        (
            "quality_achieved",
            "accuracy grade measured".into(),
            "optional, 1–12",
        ),
        ("notes", "remarks".into(), "optional"),
        (
            "confidence",
            "trust in the new case (0–1)".into(),
            "default 0.8",
        ),
    ];
    let names = ["outcome", "undelivered"];
    let unplaced: Vec<JobError> = errors
        .iter()
        .filter(|e| !fields.iter().any(|f| f.0 == e.field) && !names.contains(&e.field.as_str()))
        .cloned()
        .collect();
    let value = |n: &str| values.get(n).cloned().unwrap_or_default();
    let outcome = value("outcome");
    let title = format!("Confirm job {job}");
    let body = html! {
        p { a href=(format!("/jobs/{job}")) { "← job " (job) } }
        h1 { (title) }
        p { "What actually ran, and how it came out: the job becomes a case of the knowledge base, "
            "recorded as " (session.user.name) "'s, and the hob's shift and life move on. "
            @if !plan.state.is_empty() { "The knowledge base has the job " strong #job-state { (plan.state) } "." } }
        @if !errors.is_empty() {
            p.refused #summary role="alert" { (errors.len()) " error(s): the job was not confirmed." }
        }
        @if !unplaced.is_empty() { (errors_table(&unplaced)) }
        form #confirm-form method="post" action=(format!("/jobs/{job}/confirm")) {
            (auth::csrf_input(session))
            p.field data-field="outcome" {
                label { span.label { "outcome" } " "
                    select name="outcome" {
                        @for o in OUTCOMES { option value=(o) selected[outcome == o] { (o) } }
                    }
                }
                " " (field_errors(errors, "outcome"))
            }
            @for (name, label, help) in &fields {
                p.field data-field=(name) {
                    label { span.label { (label) } " "
                        input name=(name) value=(value(name)) placeholder=(help); }
                    " "
                    @if let Some(p) = plan.values.get(name) { span.proposal { "planned " (p) } " " }
                    (field_errors(errors, name))
                }
            }
            p.field data-field="undelivered" {
                label { input type="checkbox" name="undelivered" value="true" checked[value("undelivered") == "true"];
                    " its delivery was not heard (cut from a program delivered another way): give the speed and feed that ran" }
                " " (field_errors(errors, "undelivered"))
            }
            p { button type="submit" #confirm { "Confirm" } }
        }
    };
    page(&title, Some(session), body)
}

/// The errors that name `field`, as one line.
fn field_errors(errors: &[JobError], field: &str) -> Markup {
    html! {
        span.field-error role="alert" {
            @for e in errors.iter().filter(|e| e.field == field) {
                code { (e.code) } ": expected " (e.expected) ", got " (e.got) ". " (e.message) " "
            }
        }
    }
}

/// A field's text read as a `T`, or the error naming it; no text, or the
/// planned value, is `None` (the plan's value, which the case then says it
/// kept).
fn given<T: std::str::FromStr>(
    values: &BTreeMap<String, String>,
    plan: &Planned,
    name: &str,
    expected: &str,
    errors: &mut Vec<JobError>,
) -> Option<T> {
    let text = values.get(name).map_or("", |t| t.trim());
    let planned = plan.values.get(name).map(String::as_str);
    let same = match (text.parse::<f64>(), planned.map(str::parse::<f64>)) {
        (Ok(a), Some(Ok(b))) => a == b,
        _ => Some(text) == planned,
    };
    if text.is_empty() || same {
        return None;
    }
    match text.parse::<T>() {
        Ok(v) => Some(v),
        Err(_) => {
            errors.push(Stage::Knowledge.error(
                Code::FIELD_INVALID,
                name,
                expected,
                format!("{text:?}"),
                format!("{name}: {expected}"),
            ));
            None
        }
    }
}

/// The confirmation a sent form asks for, or the errors of its fields
/// that do not read as their type.
fn request_of(
    values: &BTreeMap<String, String>,
    plan: &Planned,
) -> Result<ConfirmRequest, Vec<JobError>> {
    let mut errors = Vec::new();
    let none = Planned::default();
    let quantity = given(
        values,
        plan,
        "quantity",
        "a whole number of parts",
        &mut errors,
    );
    let cutting_speed_m_min = given::<f64>(
        values,
        plan,
        "cutting_speed_m_min",
        "a number, m/min",
        &mut errors,
    );
    let feed_mm_per_rev = given::<f64>(values, plan, "feed_mm_per_rev", "a number", &mut errors);
    let cuts = given(values, plan, "cuts", "a whole number", &mut errors);
    let quality_achieved = given(
        values,
        &none,
        "quality_achieved",
        "an integer in [1, 12]",
        &mut errors,
    );
    let confidence = given::<f64>(
        values,
        &none,
        "confidence",
        "a number in [0, 1]",
        &mut errors,
    );
    let finite = |name: &str, v: Option<f64>, errors: &mut Vec<JobError>| match v {
        Some(x) if !x.is_finite() => {
            errors.push(Stage::Knowledge.error(
                Code::FIELD_INVALID,
                name,
                "a finite number",
                x.to_string(),
                format!("{name}: a finite number"),
            ));
            None
        }
        other => other,
    };
    let cutting_speed_m_min = finite("cutting_speed_m_min", cutting_speed_m_min, &mut errors);
    let feed_mm_per_rev = finite("feed_mm_per_rev", feed_mm_per_rev, &mut errors);
    let confidence = finite("confidence", confidence, &mut errors).unwrap_or(0.8);
    if !errors.is_empty() {
        return Err(errors);
    }
    let text = |n: &str| {
        values
            .get(n)
            .map(|t| t.trim().to_string())
            .unwrap_or_default()
    };
    Ok(ConfirmRequest {
        quantity,
        cutting_speed_m_min,
        feed_mm_per_rev,
        cuts,
        outcome: text("outcome"),
        quality_achieved,
        notes: text("notes"),
        confidence,
        undelivered: matches!(text("undelivered").as_str(), "true" | "on"),
    })
}

/// `POST /jobs/{job}/confirm`: the confirmation sent as the signed-in
/// user; the case the job became, or the form again with the errors.
pub(super) async fn confirm(
    State(web): State<Web>,
    Path(job): Path<String>,
    CsrfForm { session, form }: CsrfForm<Vec<(String, String)>>,
) -> Response {
    let job = match job_of(&session, &job) {
        Ok(j) => j,
        Err(r) => return r,
    };
    let plan = match known(&web, &session, &job).await {
        Ok(p) => p.unwrap_or_default(),
        Err(r) => return r,
    };
    let values: BTreeMap<String, String> = form
        .into_iter()
        .filter(|(k, _)| k != auth::CSRF_FIELD)
        .collect();
    let req = match request_of(&values, &plan) {
        Ok(r) => r,
        Err(errors) => {
            let page = render(&session, &job, &plan, &values, &errors);
            return (StatusCode::UNPROCESSABLE_ENTITY, page).into_response();
        }
    };
    match confirm_job(&web.bus, &session.user.name, &job, &req).await {
        Ok(reply) if reply.errors.is_empty() => {
            (StatusCode::OK, confirmed(&session, &job, &reply)).into_response()
        }
        Ok(reply) => {
            let page = render(&session, &job, &plan, &values, &reply.errors);
            (StatusCode::UNPROCESSABLE_ENTITY, page).into_response()
        }
        Err(e) => silent(&session, &e),
    }
}

/// The page of a confirmed job: the case it became, the hob after.
fn confirmed(session: &Session, job: &JobId, reply: &ConfirmReply) -> Markup {
    let case = reply
        .case
        .as_ref()
        .map(record_from_wire)
        .unwrap_or_default();
    let case_id = case.get("id").map(text_of).unwrap_or_default();
    let case_lib = library::library(&reply.case_library).unwrap_or(library::CASES);
    let hob = reply.hob.as_ref().map(record_from_wire);
    let title = format!("Job {job} confirmed");
    let body = html! {
        p { a href=(format!("/jobs/{job}")) { "← job " (job) } }
        h1 { (title) }
        p.ok #done role="status" {
            "Confirmed by " (session.user.name) ": the job became case "
            a #case href=(record_href(case_lib.name, &case_id)) { (case_id) }
            " of " a href=(super::library_href(case_lib.name)) { (case_lib.name) } "."
        }
        h2 { "The case" }
        (record_list(&case_lib, &case))
        @if let Some(h) = &hob {
            h2 { "The hob after" }
            (record_list(&library::HOBS, h))
        }
    };
    page(&title, Some(session), body)
}
