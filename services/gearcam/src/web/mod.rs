//! `gearcam web`: the planning office's page, served from the bus like the
//! CLI (a Zenoh client of the station, the knowledge service and the
//! machines' agents; no second path to the data).
//!
//! Pages are rendered on the server with `maud`, which escapes every value it
//! prints: a part number or an error message is text, never HTML. Every
//! page that reads works without JavaScript; a little script of our own
//! (`/static/gearcam.js`) adds live progress and inline checks where it helps.
//!
//! Every page needs a signed-in user ([`auth`]); each module adds its pages:
//! `jobs` the shared queue and each job, [`new`] a job's form per family
//! (checked while typed, imported and exported as TOML, submitted), `live`
//! the jobs' events as they happen.

pub mod auth;
mod form;
mod jobs;
mod kb;
mod live;
pub mod new;
mod pictures;
mod stores;

use std::net::SocketAddr;

use axum::extract::DefaultBodyLimit;
use axum::http::{header, StatusCode};
use axum::routing::{get, post};
use axum::Router;
use gearcam_bus::Bus;
use maud::{html, Markup, DOCTYPE};

use auth::{Auth, Session};

/// What the page's handlers share: the bus session and the users.
#[derive(Debug, Clone)]
pub struct Web {
    /// The bus: the page's one path to the data.
    pub bus: Bus,
    /// Who may sign in, and the sessions of those who did.
    pub auth: Auth,
    /// The check of a job while it is typed (`gearcam check` on the data
    /// directory), when the page has one.
    pub local: new::Local,
}

/// The largest request body accepted (a job file is about 1 KB).
pub const MAX_BODY_BYTES: usize = 64 * 1024;

/// The page's routes.
pub fn router(web: Web) -> Router {
    let signed_in = Router::new()
        .merge(jobs::routes())
        .merge(kb::routes())
        .merge(new::routes())
        .merge(live::routes())
        .merge(pictures::routes())
        .merge(stores::routes())
        .route("/signout", post(auth::signout))
        .route_layer(axum::middleware::from_fn_with_state(
            web.clone(),
            auth::require_session,
        ));
    Router::new()
        .route("/signin", get(auth::signin_page).post(auth::signin))
        .route("/static/gearcam.js", get(script))
        .route("/static/zoom.js", get(pictures::zoom_script))
        .merge(signed_in)
        .layer(DefaultBodyLimit::max(MAX_BODY_BYTES))
        .with_state(web)
}

/// Serves the page on `listen` until `shutdown` is cancelled; prints the
/// address it listens on (`gearcam web: http://…`) once it does.
pub async fn serve(
    web: Web,
    listen: SocketAddr,
    shutdown: tokio_util::sync::CancellationToken,
) -> anyhow::Result<()> {
    let listener = tokio::net::TcpListener::bind(listen).await?;
    serve_on(listener, web, shutdown).await
}

/// Serves the page on `listener` until `shutdown` is cancelled; prints the
/// address first (`gearcam web: http://…`).
pub async fn serve_on(
    listener: tokio::net::TcpListener,
    web: Web,
    shutdown: tokio_util::sync::CancellationToken,
) -> anyhow::Result<()> {
    let addr = listener.local_addr()?;
    crate::outln!("gearcam web: http://{addr}/");
    axum::serve(listener, router(web))
        .with_graceful_shutdown(async move { shutdown.cancelled().await })
        .await?;
    Ok(())
}

/// `GET /static/gearcam.js`: the page's own script.
async fn script() -> impl axum::response::IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        SCRIPT,
    )
}

/// The page's script: progressive additions only (every page works without).
const SCRIPT: &str = include_str!("gearcam.js");

/// A page answered with `status`.
pub type Page = (StatusCode, Markup);

/// The status of a page for a station's refusal: 404 when every error
/// says the station has no such job (or no model of it), else 502.
pub fn refusal_status(errors: &[gearcam_proto::JobError]) -> StatusCode {
    use gearcam_proto::Code;
    if errors
        .iter()
        .all(|e| matches!(e.code, Code::UNKNOWN_JOB | Code::MODEL_NOT_JOURNALED))
    {
        StatusCode::NOT_FOUND
    } else {
        StatusCode::BAD_GATEWAY
    }
}

/// Typed errors as a table: stage, code, field, expected, given, message.
pub fn errors_table(errors: &[gearcam_proto::JobError]) -> Markup {
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
pub fn trouble(status: StatusCode, what: &str, errors: &[gearcam_proto::JobError]) -> Page {
    (
        status,
        page(what, None, html! { h1 { (what) } (errors_table(errors)) }),
    )
}

/// A page for a station that does not answer.
pub fn unreachable(detail: &str) -> Page {
    (
        StatusCode::SERVICE_UNAVAILABLE,
        page(
            "Station unreachable",
            None,
            html! {
                h1 { "The planning station does not answer" }
                p { "Is " code { "gearcam up" } " (or the station) running? " (detail) }
            },
        ),
    )
}

/// Every page's frame: the navigation and who is signed in (with a
/// session), the body.
pub fn page(title: &str, session: Option<&Session>, body: Markup) -> Markup {
    html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                meta name="viewport" content="width=device-width, initial-scale=1";
                title { (title) " · gearcam" }
                style { (maud::PreEscaped(STYLE)) }
                script src="/static/gearcam.js" defer {}
                script src="/static/zoom.js" defer {}
            }
            body {
                @if let Some(s) = session {
                    nav {
                        a href="/" { "Jobs" } " "
                        a href="/new" { "New job" } " "
                        a href="/kb" { "Knowledge base" } " "
                        a href="/machines" { "Programs" } " "
                        span.who { (s.user.name) " (" (s.user.role.as_str()) ") " }
                        form.inline method="post" action="/signout" {
                            (auth::csrf_input(s))
                            button type="submit" id="signout" { "Sign out" }
                        }
                    }
                }
                main { (body) }
            }
        }
    }
}

/// The page's look: plain tables a planner reads at a glance.
const STYLE: &str = "body{font-family:system-ui,sans-serif;margin:1.5rem;color:#222}\
table{border-collapse:collapse;margin-top:.5rem}th,td{border-bottom:1px solid #ddd;padding:.3rem .6rem;text-align:left}\
tr.failed td{background:#fde8e8}tr.delivered td{background:#eaf7ea}tr.waiting td{background:#fff6dc}\
dt{font-weight:600;float:left;clear:left;width:10rem}dd{margin-left:10.5rem}code{font-size:.95em}\
nav{display:flex;gap:1rem;align-items:center;border-bottom:1px solid #ccc;padding-bottom:.5rem;margin-bottom:1rem}\
nav .who{margin-left:auto;color:#555}form.inline{display:inline}.refused{color:#a00;font-weight:600}\
.field-error{color:#a00;font-size:.9em}.proposal{color:#555;font-size:.9em}pre.program{background:#f6f6f6;padding:.6rem;overflow:auto}";
