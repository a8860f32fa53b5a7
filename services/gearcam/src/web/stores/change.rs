//! Changes of a machine's current program: a rollback to a stored version,
//! first shown on a confirmation page (what is replaced by what, and the
//! diff), then posted; the adoption or replacement of an edit at the
//! machine. Each goes to the machine's agent under the signed-in user's
//! name, and only for a user who may change the machine's programs.

use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Redirect};
use axum::Extension;
use gearcam_proto::{utc_text, ProgramVersion, StoreRequest};
use maud::{html, Markup};

use super::diff::diff_table;
use super::program::made_by;
use super::{
    answered, machine_of, may_change, on_the_bus, program_href, program_name_of, seq_of, style,
    Reply,
};
use crate::store;
use crate::web::auth::{self, CsrfForm, Empty, Session};
use crate::web::{page, Web};

/// A version in one line of the confirmation: its number, who and what
/// made it, its job, when, and its hash.
fn version_cells(v: &ProgramVersion, versions: &[ProgramVersion]) -> Markup {
    html! {
        td { (v.seq) } td { (made_by(v, versions)) } td { (v.job) } td { (utc_text(v.stored_at_ms)) }
        td { code { (v.sha256.chars().take(12).collect::<String>()) } }
    }
}

/// `GET …/versions/{seq}/rollback`: what the rollback replaces by what,
/// the diff, and the button that does it.
pub(super) async fn confirm_rollback(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((machine, name, seq)): Path<(String, String, String)>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let seq = seq_of(&session, "seq", &seq)?;
    may_change(&session, &machine)?;
    on_the_bus(&web, &session, &machine).await?;
    let what = format!("Roll back {name} at {machine} to version {seq}?");
    let history = answered(
        &session,
        &what,
        store::history(&web.bus, &machine, Some(name)).await,
    )?;
    let target = answered(
        &session,
        &what,
        store::version(&web.bus, &machine, name, seq).await,
    )?;
    let versions = &history.versions;
    let href = program_href(&machine, name);
    let Some(current) = versions.iter().find(|v| v.current) else {
        return Err(StatusCode::NOT_FOUND.into_response());
    };
    if current.seq == seq {
        let body = html! {
            h1 { "Version " (seq) " is the current version" }
            p { "There is nothing to roll back: " a href=(href) { (name) " at " (machine) } }
        };
        return Err((StatusCode::CONFLICT, page(&what, Some(&session), body)).into_response());
    }
    let now = answered(
        &session,
        &what,
        store::version(&web.bus, &machine, name, current.seq).await,
    )?;
    let body = html! {
        p { a href=(href) { "← " (name) " at " (machine) } }
        h1 { (what) }
        (style())
        p {
            "The program at the machine, version " (current.seq) ", will be replaced by the text of version " (seq)
            "; the rollback is recorded as a new version made by " strong { (session.user.name) } "."
        }
        table #replace {
            thead { tr { th { "" } th { "version" } th { "made by" } th { "job" } th { "stored at" } th { "sha256" } } }
            tbody {
                tr { th { "replaced" } (version_cells(current, versions)) }
                tr { th { "by" } (version_cells(&target.version, versions)) }
            }
        }
        form method="post" action=(format!("{href}/versions/{seq}/rollback")) {
            (auth::csrf_input(&session))
            button type="submit" #confirm { "Roll back to version " (seq) }
            " " a href=(href) { "Cancel" }
        }
        h2 { "What changes at the machine" }
        (diff_table(current.seq, &now.text, seq, &target.text))
    };
    Ok((StatusCode::OK, page(&what, Some(&session), body)).into_response())
}

/// `POST …/versions/{seq}/rollback`: makes version `seq` current again.
pub(super) async fn rollback(
    State(web): State<Web>,
    Path((machine, name, seq)): Path<(String, String, String)>,
    CsrfForm { session, form: _ }: CsrfForm<Empty>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let seq = seq_of(&session, "seq", &seq)?;
    let by = session.user.name.clone();
    change(
        &web,
        &session,
        &machine,
        name,
        StoreRequest::Rollback { seq, by },
    )
    .await
}

/// `POST …/adopt`: the edit at the machine becomes the current version.
pub(super) async fn adopt(
    State(web): State<Web>,
    Path((machine, name)): Path<(String, String)>,
    CsrfForm { session, form: _ }: CsrfForm<Empty>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let by = session.user.name.clone();
    change(&web, &session, &machine, name, StoreRequest::Adopt { by }).await
}

/// `POST …/replace`: gearcam's current version is written back over the
/// edit at the machine, which stays in the history.
pub(super) async fn replace(
    State(web): State<Web>,
    Path((machine, name)): Path<(String, String)>,
    CsrfForm { session, form: _ }: CsrfForm<Empty>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let by = session.user.name.clone();
    change(&web, &session, &machine, name, StoreRequest::Replace { by }).await
}

/// Sends `request` to the store of `machine` (its key names the signed-in
/// user, whom the agent records) once the user's role allows it; back to
/// the program's page when done, else the page of the refusal.
async fn change(
    web: &Web,
    session: &Session,
    machine: &gearcam_proto::MachineId,
    name: &str,
    request: StoreRequest,
) -> Reply {
    may_change(session, machine)?;
    on_the_bus(web, session, machine).await?;
    let what = match &request {
        StoreRequest::Rollback { seq, .. } => {
            format!("Roll back {name} at {machine} to version {seq}")
        }
        StoreRequest::Adopt { .. } => format!("Adopt the edit of {name} at {machine}"),
        StoreRequest::Replace { .. } => format!("Replace the edit of {name} at {machine}"),
    };
    answered(
        session,
        &what,
        store::change(&web.bus, machine, name, &request).await,
    )?;
    tracing::info!(%machine, program = name, user = session.user.name, ?request, "program changed from the page");
    Ok(Redirect::to(&program_href(machine, name)).into_response())
}
