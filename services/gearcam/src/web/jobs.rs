//! The jobs: the station's journal as a shared queue, newest first, with a
//! filter by state and a search over job ids and part numbers; one job with
//! its state, what it waits for, its typed errors, warnings and program.

use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use axum::routing::get;
use axum::Extension;
use axum::Router;
use gearcam_proto::{JobId, JobState, JobStatus};
use maud::html;
use serde::Deserialize;

use super::auth::Session;
use super::{errors_table, page, trouble, unreachable, Page, Web};
use crate::station;

/// The jobs' pages.
pub(super) fn routes() -> Router<Web> {
    Router::new()
        .route("/", get(jobs_page))
        .route("/jobs/{job}", get(job_page))
        .route("/jobs/{job}/resubmit", axum::routing::post(resubmit))
}

/// The job list's filter: a state and a search text.
#[derive(Debug, Default, Deserialize)]
struct Filter {
    /// Only jobs in this state (`delivered`, `failed`, …); empty for all.
    #[serde(default)]
    state: String,
    /// Only jobs whose id or part number contains this text.
    #[serde(default)]
    q: String,
}

impl Filter {
    fn keeps(&self, s: &JobStatus) -> bool {
        let state_ok = self.state.is_empty() || s.state.as_str() == self.state;
        let q = self.q.trim().to_lowercase();
        let text_ok = q.is_empty()
            || s.job.as_str().to_lowercase().contains(&q)
            || s.part_number.to_lowercase().contains(&q);
        state_ok && text_ok
    }
}

async fn jobs_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Query(filter): Query<Filter>,
) -> Page {
    let jobs = match station::jobs(&web.bus).await {
        Ok(Ok(jobs)) => jobs,
        Ok(Err(errors)) => return trouble(StatusCode::BAD_GATEWAY, "the station refused", &errors),
        Err(e) => return unreachable(&e.to_string()),
    };
    let shown: Vec<&JobStatus> = jobs.iter().rev().filter(|s| filter.keeps(s)).collect();
    let body = html! {
        h1 { "Jobs" }
        form method="get" action="/" {
            label { "State " select name="state" {
                option value="" selected[filter.state.is_empty()] { "any" }
                @for s in JobState::ALL.map(JobState::as_str) {
                    option value=(s) selected[filter.state == s] { (s) }
                }
            } }
            " "
            label { "Search " input type="search" name="q" value=(filter.q) placeholder="job id or part number"; }
            " " button type="submit" { "Filter" }
        }
        p.count {
            (shown.len()) " of " (jobs.len()) " job(s), "
            (shown.iter().map(|s| u64::from(s.quantity)).sum::<u64>()) " part(s)"
        }
        table {
            thead { tr { th { "job" } th { "part number" } th { "parts" } th { "machine" } th { "state" } th { "updated" } } }
            tbody #jobs data-events="/events" {
                @for s in &shown {
                    tr class=(s.state.as_str()) data-job=(s.job) {
                        td { a href=(format!("/jobs/{}", s.job)) { (s.job) } }
                        td { (s.part_number) }
                        td.parts { (s.quantity) }
                        td { (s.machine) }
                        td.state { (s.state.as_str()) }
                        td { (gearcam_proto::utc_text(s.updated_at_ms)) }
                    }
                }
            }
        }
    };
    (StatusCode::OK, page("Jobs", Some(&session), body))
}

async fn job_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(job): Path<String>,
) -> Page {
    let Ok(id) = JobId::new(job.clone()) else {
        return (
            StatusCode::NOT_FOUND,
            page(
                "No such job",
                Some(&session),
                html! { h1 { "No such job" } p { "Not a job id: " code { (job) } } },
            ),
        );
    };
    let s = match station::status(&web.bus, &id).await {
        Ok(Ok(s)) => s,
        Ok(Err(errors)) => {
            let status = super::refusal_status(&errors);
            return trouble(status, &format!("job {id}"), &errors);
        }
        Err(e) => return unreachable(&e.to_string()),
    };
    let body = html! {
        p { a href="/" { "← jobs" } }
        h1 { "Job " (s.job) }
        @if s.state == JobState::Delivered { p { a #confirm-link href=(format!("/jobs/{}/confirm", s.job)) { "Confirm what ran: the job becomes a case" } } }
        dl #status data-job=(s.job) data-events=(format!("/jobs/{}/events", s.job)) data-final=[s.state.is_final().then_some("1")] {
            dt { "part number" } dd { (s.part_number) }
            dt { "machine" } dd { (s.machine) }
            dt { "state" } dd #state .state { (s.state.as_str()) }
            @if let Some(w) = &s.waiting_for { dt { "waiting for" } dd { (w) } }
            dt { "accepted" } dd { (gearcam_proto::utc_text(s.accepted_at_ms)) }
            dt { "updated" } dd { (gearcam_proto::utc_text(s.updated_at_ms)) }
            dt { "sent" } dd { (s.attempts) " time(s)" }
            @if let Some(p) = &s.program {
                dt { "program" } dd { a href=(super::stores::program_href(&s.machine, &p.name)) { code { (p.name) } } " at " (s.machine) " (sha256 " code { (p.sha256) } ")" }
            }
        }
        form method="post" action=(format!("/jobs/{}/resubmit", s.job)) {
            (super::auth::csrf_input(&session))
            button type="submit" id="resubmit" { "Submit again" }
            " " small { "the same job under a new job id, as you" }
        }
        (super::pictures::section(&s))
        h2 { "Progress" }
        ol #progress { li { (gearcam_proto::utc_text(s.updated_at_ms)) " " (s.state.as_str()) } }
        @if !s.errors.is_empty() { h2 { "Errors" } (errors_table(&s.errors)) }
        @if !s.warnings.is_empty() {
            h2 { "Warnings" }
            ul { @for w in &s.warnings { li { code { (w.code) } " " (w.field) ": " (w.message) } } }
        }
    };
    (
        StatusCode::OK,
        page(&format!("Job {}", s.job), Some(&session), body),
    )
}

/// `POST /jobs/{job}/resubmit`: the job as the station journaled it,
/// submitted again under a new id by the signed-in user; its page follows.
async fn resubmit(
    State(web): State<Web>,
    Path(job): Path<String>,
    form: super::auth::CsrfForm<super::auth::Empty>,
) -> axum::response::Response {
    use axum::response::IntoResponse;
    let session = form.session;
    let Ok(id) = JobId::new(job.clone()) else {
        return super::auth::refuse(
            StatusCode::NOT_FOUND,
            &format!("job: expected a job id, got {job:?}"),
        );
    };
    let old = match station::request(&web.bus, &id).await {
        Ok(Ok(r)) => r,
        Ok(Err(errors)) => {
            let status = super::refusal_status(&errors);
            return trouble(status, &format!("job {id}"), &errors).into_response();
        }
        Err(e) => return unreachable(&e.to_string()).into_response(),
    };
    let mut spec = old.spec;
    spec.job.id = None;
    let req = gearcam_proto::JobRequest {
        job_id: crate::jobfile::job_id(&spec),
        submitted_at_ms: gearcam_proto::now_ms(),
        submitted_by: session.user.name.clone(),
        spec,
    };
    let opts = station::SubmitOptions {
        wait: false,
        alive_timeout: std::time::Duration::from_secs(5),
        timeout: std::time::Duration::from_secs(10),
    };
    match station::submit(&web.bus, &req, &opts, |_| {}).await {
        Ok(station::Outcome::Failed(errors)) => trouble(
            StatusCode::UNPROCESSABLE_ENTITY,
            "The station refused the job",
            &errors,
        )
        .into_response(),
        Ok(_) => axum::response::Redirect::to(&format!("/jobs/{}", req.job_id)).into_response(),
        Err(e) => unreachable(&e.to_string()).into_response(),
    }
}
