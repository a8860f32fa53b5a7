//! The machines' program stores, read and changed over the bus like
//! `gearcam program history|show|rollback|resolve`: every answer is the
//! machine agent's, never a second copy of its index.
//!
//! # Layout
//!
//! - this module: the routes, the checks of the address's values (machine,
//!   program name, version number), the rights check of a change, and the
//!   pages of a refusal;
//! - [`list`]: the machines whose agents are on the bus, and one machine's
//!   programs;
//! - [`program`]: one program's versions with who and what made each, an
//!   edit at the machine waiting for review, a version's text and its
//!   download;
//! - [`diff`]: the line diff of two versions;
//! - [`change`]: a rollback (after a confirmation page), the adoption or
//!   replacement of an edit at the machine.
//!
//! Everyone signed in reads; only a user who may change the machine's
//! programs (an operator of that machine, a supervisor) rolls back, adopts
//! or replaces, and the agent records the change under the signed-in
//! user's name.

mod change;
mod diff;
mod list;
mod program;

use std::time::Duration;

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::Router;
use gearcam_bus::query::CallError;
use gearcam_proto::{Code, JobState, JobStatus, MachineId, ProgramVersion};
use maud::{html, Markup, PreEscaped};

use super::auth::{self, Role, Session, User};
use super::{errors_table, page, Web};
use crate::store;

/// What a page handler answers: the page, or the page of what went wrong.
type Reply = Result<Response, Response>;

/// The stores' pages.
pub(super) fn routes() -> Router<Web> {
    let program = "/machines/{machine}/programs/{name}";
    Router::new()
        .route("/machines", get(list::machines_page))
        .route("/machines/{machine}", get(list::machine_page))
        .route(program, get(program::program_page))
        .route(&format!("{program}/diff"), get(diff::diff_page))
        .route(
            &format!("{program}/versions/{{seq}}"),
            get(program::version_page),
        )
        .route(
            &format!("{program}/versions/{{seq}}/download"),
            get(program::download),
        )
        .route(
            &format!("{program}/versions/{{seq}}/rollback"),
            get(change::confirm_rollback).post(change::rollback),
        )
        .route(&format!("{program}/adopt"), post(change::adopt))
        .route(&format!("{program}/replace"), post(change::replace))
}

/// The address of program `name` of `machine`'s store.
pub(super) fn program_href(machine: &MachineId, name: &str) -> String {
    format!(
        "/machines/{}/programs/{}",
        segment(machine.as_str()),
        segment(name)
    )
}

/// `s` percent-encoded as one path segment (a `/` too).
fn segment(s: &str) -> String {
    auth::urlencode(s).replace('/', "%2F")
}

/// The page of a bad value in the address or query: the field, what it
/// takes and the value given (shown as text).
fn bad_input(
    session: &Session,
    status: StatusCode,
    field: &str,
    expected: &str,
    given: &str,
) -> Response {
    let body = html! {
        h1 { "Not a valid " (field) }
        table.errors {
            thead { tr { th { "field" } th { "expected" } th { "given" } } }
            tbody { tr { td { code { (field) } } td { (expected) } td { code { (given) } } } }
        }
        p { a href="/machines" { "← machines" } }
    };
    (status, page("Bad address", Some(session), body)).into_response()
}

/// The machine named in the address, or the page saying what a machine id is.
fn machine_of(session: &Session, text: &str) -> Result<MachineId, Response> {
    MachineId::new(text).map_err(|e| {
        bad_input(
            session,
            StatusCode::BAD_REQUEST,
            "machine",
            &format!("a machine id: {}", e.expected),
            text,
        )
    })
}

/// What a program name may hold on any controller: letters, digits, `_`
/// and `-` (no `/`, no `.` but a wire program's `.3b`/`.4b` ending).
const PROGRAM_NAME_RULE: &str =
    "a program name: 1 to 64 letters, digits, _ and -, starting with a letter, digit or _ (a wire program may end in .3b or .4b)";

/// The program name in the address, or the page saying what a name may
/// hold; a name with a path in it (`../x`) never reaches the bus.
fn program_name_of<'a>(session: &Session, text: &'a str) -> Result<&'a str, Response> {
    if valid_program_name(text) {
        Ok(text)
    } else {
        Err(bad_input(
            session,
            StatusCode::BAD_REQUEST,
            "name",
            PROGRAM_NAME_RULE,
            text,
        ))
    }
}

/// True when `text` follows [`PROGRAM_NAME_RULE`].
fn valid_program_name(text: &str) -> bool {
    let base = text
        .strip_suffix(".3b")
        .or_else(|| text.strip_suffix(".4b"))
        .unwrap_or(text);
    !base.is_empty()
        && text.len() <= 64
        && base.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_')
        && base
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The version number `field` of the address, or the page saying it is a
/// number.
fn seq_of(session: &Session, field: &str, text: &str) -> Result<u64, Response> {
    text.parse::<u64>().map_err(|_| {
        bad_input(
            session,
            StatusCode::BAD_REQUEST,
            field,
            "a version number from the program's history, e.g. 3",
            text,
        )
    })
}

/// Refuses, with a 404 page naming the machines that are there, a machine
/// whose agent is not on the bus: its store cannot be asked (and asking
/// would only wait for the query's timeout).
async fn on_the_bus(web: &Web, session: &Session, machine: &MachineId) -> Result<(), Response> {
    let agents = store::agents_on_the_bus(&web.bus).await;
    if agents.iter().any(|m| m == machine.as_str()) {
        return Ok(());
    }
    let expected = if agents.is_empty() {
        "a machine whose agent is on the bus (none is: is `gearcam up` or the machine's agent running?)".to_string()
    } else {
        format!("a machine whose agent is on the bus: {}", agents.join(", "))
    };
    Err(bad_input(
        session,
        StatusCode::NOT_FOUND,
        "machine",
        &expected,
        machine.as_str(),
    ))
}

/// The store's answer, or the page of its refusal (404 for an unknown
/// program or version, 409 for an edit at the machine or none to resolve)
/// or of an agent that does not answer (503).
fn answered<T>(
    session: &Session,
    what: &str,
    answer: Result<store::Answer<T>, CallError>,
) -> Result<T, Response> {
    match answer {
        Ok(Ok(t)) => Ok(t),
        Ok(Err(error)) => {
            let status = match error.code {
                Code::UNKNOWN_PROGRAM | Code::UNKNOWN_VERSION | Code::AGENT_OFFLINE => {
                    StatusCode::NOT_FOUND
                }
                Code::BAD_STORE_REQUEST | Code::BAD_PROGRAM_NAME => StatusCode::BAD_REQUEST,
                Code::PROGRAM_CHANGED_AT_MACHINE | Code::NO_CONFLICT => StatusCode::CONFLICT,
                _ => StatusCode::BAD_GATEWAY,
            };
            let body = html! {
                h1 { (what) }
                p.refused role="alert" { "The machine's agent refused: " (error.message) }
                (errors_table(std::slice::from_ref(&error)))
                p { a href="/machines" { "← machines" } }
            };
            Err((status, page(what, Some(session), body)).into_response())
        }
        Err(e) => {
            let body = html! {
                h1 { (what) }
                p.refused role="alert" { "The machine's agent does not answer: " (e.to_string()) }
            };
            Err((
                StatusCode::SERVICE_UNAVAILABLE,
                page(what, Some(session), body),
            )
                .into_response())
        }
    }
}

/// Refuses a change of `machine`'s programs by a user whose role does not
/// allow it, saying what the role lacks.
fn may_change(session: &Session, machine: &MachineId) -> Result<(), Response> {
    match change_refusal(&session.user, machine) {
        None => Ok(()),
        Some(why) => Err(auth::refuse(StatusCode::FORBIDDEN, &why)),
    }
}

/// Why `user` may not change `machine`'s programs, naming their role; none
/// when they may.
fn change_refusal(user: &User, machine: &MachineId) -> Option<String> {
    if user.may_change_program(machine) {
        return None;
    }
    let who = match user.role {
        Role::Operator if user.machines.is_empty() => "an operator of no machine".to_string(),
        Role::Operator => format!(
            "an operator of {}",
            user.machines
                .iter()
                .map(MachineId::as_str)
                .collect::<Vec<_>>()
                .join(", ")
        ),
        Role::Admin => "an admin".to_string(),
        Role::Planner | Role::Supervisor => format!("a {}", user.role.as_str()),
    };
    Some(format!(
        "{who} may not change the programs of machine {machine} (roll back, adopt or replace): only an operator of {machine} or a supervisor may"
    ))
}

/// The station's jobs, for the edits at the machine they wait on; none
/// when the station does not answer soon (the store's pages do not depend
/// on it).
async fn station_jobs(web: &Web) -> Option<Vec<JobStatus>> {
    match tokio::time::timeout(Duration::from_secs(3), crate::station::jobs(&web.bus)).await {
        Ok(Ok(Ok(jobs))) => Some(jobs),
        _ => None,
    }
}

/// The jobs refused because program file `current.file_name` was changed at
/// `machine` since gearcam stored its current version `current`: each waits
/// (`PROGRAM_CHANGED_AT_MACHINE`) until a person adopts or replaces the
/// edit. A refusal reported before the current version was stored was
/// resolved by it, so it is not a conflict any more.
fn conflicts<'a>(
    jobs: &'a [JobStatus],
    machine: &MachineId,
    current: &ProgramVersion,
) -> Vec<&'a JobStatus> {
    let at = format!("{} at {machine}", current.file_name);
    jobs.iter()
        .filter(|s| {
            s.machine == *machine
                && s.state == JobState::Waiting
                && s.updated_at_ms >= current.stored_at_ms
                && s.waiting_for.as_deref().is_some_and(|w| {
                    w.starts_with(Code::PROGRAM_CHANGED_AT_MACHINE.as_str()) && w.contains(&at)
                })
        })
        .collect()
}

/// The stores' own look (diff lines, the current version, a conflict).
fn style() -> Markup {
    html! {
        style { (PreEscaped(
            "table.diff td{font-family:ui-monospace,monospace;white-space:pre;padding:0 .5rem;border:0}\
             table.diff td.n{color:#888;text-align:right}tr.add td{background:#e6ffec}tr.del td{background:#ffebe9}\
             tr.hunk td{background:#f0f4ff;color:#555}tr.current td{background:#eaf7ea;font-weight:600}\
             .conflict{border:2px solid #c60;background:#fff4e5;padding:.5rem 1rem;margin:1rem 0}\
             .muted{color:#666;font-size:.9em}form.inline button{margin-right:.5rem}"
        )) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn version(file_name: &str, stored_at_ms: u64) -> ProgramVersion {
        ProgramVersion {
            seq: 2,
            name: "SP_1".into(),
            file_name: file_name.into(),
            job: "J2".into(),
            revision: 1,
            sha256: "ab".into(),
            size_bytes: 3,
            stored_at_ms,
            state: "stored".into(),
            current: true,
            part_number: "P".into(),
            by: String::new(),
        }
    }

    fn waiting(machine: &str, at_ms: u64, reason: &str) -> JobStatus {
        JobStatus {
            job: gearcam_proto::JobId::new("J3").unwrap(),
            machine: MachineId::new(machine).unwrap(),
            part_number: "P".into(),
            state: JobState::Waiting,
            attempts: 1,
            accepted_at_ms: at_ms,
            updated_at_ms: at_ms,
            waiting_for: Some(reason.into()),
            program: None,
            receipt: None,
            errors: vec![],
            warnings: vec![],
            quantity: 1,
        }
    }

    #[test]
    fn a_conflict_is_a_job_refused_for_this_file_since_the_current_version() {
        let h01 = MachineId::new("H01").unwrap();
        let reason = "PROGRAM_CHANGED_AT_MACHINE: _N_SP_1_MPF at H01 was changed at the machine";
        let jobs = vec![
            waiting("H01", 2000, reason),
            waiting("H01", 500, reason),
            waiting("H02", 2000, reason),
            waiting("H01", 2000, "AGENT_OFFLINE: no agent"),
            waiting(
                "H01",
                2000,
                "PROGRAM_CHANGED_AT_MACHINE: _N_SP_10_MPF at H01 was",
            ),
        ];
        let found = conflicts(&jobs, &h01, &version("_N_SP_1_MPF", 1000));
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].updated_at_ms, 2000);
    }

    #[test]
    fn program_names_with_a_path_are_refused() {
        for good in ["SP_1001", "O1234", "groove-1", "PD-2001.4b", "_X1"] {
            assert!(valid_program_name(good), "{good}");
        }
        for bad in [
            "../x",
            "a/b",
            "..",
            ".3b",
            "",
            "x y",
            "<b>",
            &"A".repeat(65),
        ] {
            assert!(!valid_program_name(bad), "{bad}");
        }
    }

    #[test]
    fn a_refused_change_names_the_role_and_the_machines() {
        let (h01, h02) = (
            MachineId::new("H01").unwrap(),
            MachineId::new("H02").unwrap(),
        );
        let user = |role, machines: Vec<MachineId>| User {
            name: "x".into(),
            role,
            machines,
            password: String::new(),
        };
        let planner = change_refusal(&user(Role::Planner, vec![]), &h01).unwrap();
        assert!(planner.starts_with("a planner may not change the programs of machine H01"));
        let operator = change_refusal(&user(Role::Operator, vec![h01.clone()]), &h02).unwrap();
        assert!(
            operator.starts_with("an operator of H01 may not change the programs of machine H02")
        );
        assert!(change_refusal(&user(Role::Operator, vec![h01.clone()]), &h01).is_none());
        assert!(change_refusal(&user(Role::Supervisor, vec![]), &h02).is_none());
    }
}
