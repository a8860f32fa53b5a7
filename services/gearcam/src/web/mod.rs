//! `gearcam web`: the planning office's page, served from the bus like the
//! CLI (a Zenoh client of the station; no second path to the data).
//!
//! Pages are rendered on the server with `maud`, which escapes every value it
//! prints: a part number or an error message is text, never HTML. They work
//! without JavaScript.
//!
//! - `/`: the station's journal as a shared queue, newest first, with a
//!   filter by state and a search over job ids and part numbers;
//! - `/jobs/{job}`: one job: its state, what it waits for, its errors
//!   (stage, code, field, expected, given, message), its warnings and the
//!   program delivered.

use std::net::SocketAddr;

use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use axum::routing::get;
use axum::Router;
use gearcam_bus::Bus;
use gearcam_proto::{JobId, JobState, JobStatus};
use maud::{html, Markup, DOCTYPE};
use serde::Deserialize;

use crate::station;

/// What the page's handlers share: the bus session.
#[derive(Debug, Clone)]
struct Web {
    bus: Bus,
}

/// The page's routes on `bus`.
pub fn router(bus: Bus) -> Router {
    Router::new()
        .route("/", get(jobs_page))
        .route("/jobs/{job}", get(job_page))
        .with_state(Web { bus })
}

/// Serves the page on `listen` until `shutdown` is cancelled; prints the
/// address it listens on (`gearcam web: http://…`) once it does.
pub async fn serve(
    bus: Bus,
    listen: SocketAddr,
    shutdown: tokio_util::sync::CancellationToken,
) -> anyhow::Result<()> {
    let listener = tokio::net::TcpListener::bind(listen).await?;
    let addr = listener.local_addr()?;
    crate::outln!("gearcam web: http://{addr}/");
    axum::serve(listener, router(bus))
        .with_graceful_shutdown(async move { shutdown.cancelled().await })
        .await?;
    Ok(())
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

/// A page answered with `status`.
type Page = (StatusCode, Markup);

async fn jobs_page(State(web): State<Web>, Query(filter): Query<Filter>) -> Page {
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
        p.count { (shown.len()) " of " (jobs.len()) " job(s)" }
        table {
            thead { tr { th { "job" } th { "part number" } th { "machine" } th { "state" } th { "updated" } } }
            tbody {
                @for s in &shown {
                    tr class=(s.state.as_str()) {
                        td { a href=(format!("/jobs/{}", s.job)) { (s.job) } }
                        td { (s.part_number) }
                        td { (s.machine) }
                        td { (s.state.as_str()) }
                        td { (gearcam_proto::utc_text(s.updated_at_ms)) }
                    }
                }
            }
        }
    };
    (StatusCode::OK, page("Jobs", body))
}

async fn job_page(State(web): State<Web>, Path(job): Path<String>) -> Page {
    let Ok(id) = JobId::new(job.clone()) else {
        return (
            StatusCode::NOT_FOUND,
            page(
                "No such job",
                html! { h1 { "No such job" } p { "Not a job id: " code { (job) } } },
            ),
        );
    };
    let s = match station::status(&web.bus, &id).await {
        Ok(Ok(s)) => s,
        Ok(Err(errors)) => {
            let status = if errors
                .iter()
                .all(|e| e.code == gearcam_proto::Code::UNKNOWN_JOB)
            {
                StatusCode::NOT_FOUND
            } else {
                StatusCode::BAD_GATEWAY
            };
            return trouble(status, &format!("job {id}"), &errors);
        }
        Err(e) => return unreachable(&e.to_string()),
    };
    let body = html! {
        p { a href="/" { "← jobs" } }
        h1 { "Job " (s.job) }
        dl {
            dt { "part number" } dd { (s.part_number) }
            dt { "machine" } dd { (s.machine) }
            dt { "state" } dd.state { (s.state.as_str()) }
            @if let Some(w) = &s.waiting_for { dt { "waiting for" } dd { (w) } }
            dt { "accepted" } dd { (gearcam_proto::utc_text(s.accepted_at_ms)) }
            dt { "updated" } dd { (gearcam_proto::utc_text(s.updated_at_ms)) }
            dt { "sent" } dd { (s.attempts) " time(s)" }
            @if let Some(p) = &s.program {
                dt { "program" } dd { code { (p.name) } " at " (s.machine) " (sha256 " code { (p.sha256) } ")" }
            }
        }
        @if !s.errors.is_empty() { h2 { "Errors" } (errors_table(&s.errors)) }
        @if !s.warnings.is_empty() {
            h2 { "Warnings" }
            ul { @for w in &s.warnings { li { code { (w.code) } " " (w.field) ": " (w.message) } } }
        }
    };
    (StatusCode::OK, page(&format!("Job {}", s.job), body))
}

/// Typed errors as a table: stage, code, field, expected, given, message.
fn errors_table(errors: &[gearcam_proto::JobError]) -> Markup {
    html! {
        table.errors {
            thead { tr { th { "stage" } th { "code" } th { "field" } th { "expected" } th { "given" } th { "message" } } }
            tbody {
                @for e in errors {
                    tr {
                        td { (e.stage.as_str()) } td { code { (e.code) } } td { code { (e.field) } }
                        td { (e.expected) } td { (e.got) } td { (e.message) }
                    }
                }
            }
        }
    }
}

/// A page for a refusal: what was asked and the typed errors.
fn trouble(status: StatusCode, what: &str, errors: &[gearcam_proto::JobError]) -> Page {
    (
        status,
        page(what, html! { h1 { (what) } (errors_table(errors)) }),
    )
}

/// A page for a station that does not answer.
fn unreachable(detail: &str) -> Page {
    (
        StatusCode::SERVICE_UNAVAILABLE,
        page(
            "Station unreachable",
            html! {
                h1 { "The planning station does not answer" }
                p { "Is " code { "gearcam up" } " (or the station) running? " (detail) }
            },
        ),
    )
}

/// Every page's frame.
fn page(title: &str, body: Markup) -> Markup {
    html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                meta name="viewport" content="width=device-width, initial-scale=1";
                title { (title) " · gearcam" }
                style { (maud::PreEscaped(STYLE)) }
            }
            body { main { (body) } }
        }
    }
}

/// The page's look: plain tables a planner reads at a glance.
const STYLE: &str = "body{font-family:system-ui,sans-serif;margin:1.5rem;color:#222}\
table{border-collapse:collapse;margin-top:.5rem}th,td{border-bottom:1px solid #ddd;padding:.3rem .6rem;text-align:left}\
tr.failed td{background:#fde8e8}tr.delivered td{background:#eaf7ea}tr.waiting td{background:#fff6dc}\
dt{font-weight:600;float:left;clear:left;width:10rem}dd{margin-left:10.5rem}code{font-size:.95em}";
