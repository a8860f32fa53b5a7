//! The machines whose agents are on the bus, and one machine's programs:
//! each program's current version, its state, when it was stored, its job
//! and part, and whether an edit at the machine waits for review.

use std::collections::BTreeMap;

use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::IntoResponse;
use axum::Extension;
use gearcam_proto::{utc_text, ProgramVersion};
use maud::html;

use super::{
    answered, conflicts, machine_of, on_the_bus, program_href, segment, station_jobs, style, Reply,
};
use crate::store;
use crate::web::auth::Session;
use crate::web::{page, Web};

/// `GET /machines`: the machines whose agents are on the bus (their
/// liveliness tokens), each linking to its store.
pub(super) async fn machines_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
) -> Reply {
    let agents = store::agents_on_the_bus(&web.bus).await;
    let body = html! {
        h1 { "Machines" }
        @if agents.is_empty() {
            p.refused { "No machine's agent is on the bus: is " code { "gearcam up" } " (or the machines' agents) running?" }
        } @else {
            p.muted { "The machines whose delivery agents are on the bus now; each keeps the programs delivered to it." }
            ul #machines {
                @for m in &agents {
                    li { a href=(format!("/machines/{}", segment(m))) { (m) } }
                }
            }
        }
    };
    Ok((StatusCode::OK, page("Machines", Some(&session), body)).into_response())
}

/// `GET /machines/{machine}`: the machine's programs, each with its
/// current version.
pub(super) async fn machine_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(machine): Path<String>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    on_the_bus(&web, &session, &machine).await?;
    let what = format!("Programs of {machine}");
    let history = answered(
        &session,
        &what,
        store::history(&web.bus, &machine, None).await,
    )?;
    // Newest first: each program's first version is its current one.
    let mut programs: BTreeMap<&str, Vec<&ProgramVersion>> = BTreeMap::new();
    for v in &history.versions {
        programs.entry(v.name.as_str()).or_default().push(v);
    }
    let jobs = station_jobs(&web).await;
    let body = html! {
        p { a href="/machines" { "← machines" } }
        h1 { (what) }
        (style())
        @if jobs.is_none() {
            p.muted { "The planning station does not answer: edits at the machine that wait for review are not shown." }
        }
        @if programs.is_empty() {
            p { "No program was delivered to " (machine) " yet." }
        } @else {
            table #programs {
                thead { tr { th { "program" } th { "current version" } th { "state" } th { "stored at" } th { "job" } th { "part" } th { "versions" } th { "" } } }
                tbody {
                    @for (name, versions) in &programs {
                        @let cur = versions.iter().copied().find(|v| v.current).unwrap_or(versions[0]);
                        @let conflict = jobs.as_deref().is_some_and(|j| !conflicts(j, &machine, cur).is_empty());
                        tr data-program=(name) {
                            td { a href=(program_href(&machine, name)) { (name) } }
                            td { (cur.seq) }
                            td { (cur.state) }
                            td { (utc_text(cur.stored_at_ms)) }
                            td { a href=(format!("/jobs/{}", segment(&cur.job))) { (cur.job) } }
                            td { (cur.part_number) }
                            td { (versions.len()) }
                            td { @if conflict { strong.refused { "changed at the machine: review" } } }
                        }
                    }
                }
            }
        }
    };
    Ok((StatusCode::OK, page(&what, Some(&session), body)).into_response())
}
