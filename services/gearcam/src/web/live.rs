//! Live progress: the jobs' events from the bus, forwarded to the open
//! page as server-sent events (`text/event-stream`). Each message is JSON
//! `{job, stage, state, text, at_ms}`: the job, the stage that reported,
//! the state the event puts the job in, the line `gearcam submit` prints
//! for it, and when. The pages work without it; the script uses it to
//! update a job's state and progress, and the queue's rows, as they happen.

use std::convert::Infallible;
use std::time::Duration;

use axum::extract::{Path, State};
use axum::http::StatusCode;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::Router;
use gearcam_proto::{decode, keys, EventKind, JobEvent, JobId, JobState};
use serde::Serialize;
use tokio_stream::wrappers::ReceiverStream;
use tokio_stream::StreamExt;

use super::Web;
use crate::station;

/// The live pages' event streams.
pub(super) fn routes() -> Router<Web> {
    Router::new()
        .route("/events", get(all_jobs))
        .route("/jobs/{job}/events", get(one_job))
}

/// One event as the page reads it.
#[derive(Debug, Serialize)]
struct Live {
    job: String,
    stage: &'static str,
    state: &'static str,
    text: String,
    at_ms: u64,
}

/// The state a job is in after `event`.
pub(super) fn state_after(event: &EventKind) -> JobState {
    match event {
        EventKind::Accepted { .. } => JobState::Accepted,
        EventKind::Planned { .. } => JobState::Planned,
        EventKind::Modelled { .. } => JobState::Modelled,
        EventKind::Programmed { .. } => JobState::Programmed,
        EventKind::Delivered { .. } => JobState::Delivered,
        EventKind::Waiting { .. } => JobState::Waiting,
        EventKind::Failed { .. } => JobState::Failed,
        EventKind::Superseded { .. } => JobState::Superseded,
        EventKind::Cancelled { .. } => JobState::Cancelled,
    }
}

/// `GET /events`: every job's events.
async fn all_jobs(State(web): State<Web>) -> Response {
    stream(&web, keys::ALL_JOB_EVENTS.to_string(), None).await
}

/// `GET /jobs/{job}/events`: one job's events.
async fn one_job(State(web): State<Web>, Path(job): Path<String>) -> Response {
    match JobId::new(job.clone()) {
        Ok(id) => stream(&web, keys::job_events(&id), Some(id)).await,
        Err(e) => (
            StatusCode::NOT_FOUND,
            format!("job: expected a job id, got {job:?}: {e}"),
        )
            .into_response(),
    }
}

/// The events published on `key`, as server-sent events, until the page
/// closes the stream; for one `job`, its state in the journal first (read
/// after subscribing, so nothing between the page and the stream is missed).
async fn stream(web: &Web, key: String, job: Option<JobId>) -> Response {
    let subscriber = match web.bus.session().declare_subscriber(key).await {
        Ok(s) => s,
        Err(e) => {
            return (
                StatusCode::SERVICE_UNAVAILABLE,
                format!("cannot follow the jobs' events on the bus: {e}"),
            )
                .into_response()
        }
    };
    let (tx, rx) = tokio::sync::mpsc::channel::<Live>(64);
    if let Some(job) = job {
        if let Ok(Ok(s)) = station::status(&web.bus, &job).await {
            let _ = tx
                .send(Live {
                    job: s.job.to_string(),
                    stage: "station",
                    state: s.state.as_str(),
                    text: format!("journal: {}", s.state.as_str()),
                    at_ms: s.updated_at_ms,
                })
                .await;
        }
    }
    tokio::spawn(async move {
        loop {
            // Until the page goes away, even when no event comes.
            let sample = tokio::select! {
                () = tx.closed() => break,
                s = subscriber.recv_async() => match s {
                    Ok(s) => s,
                    Err(_) => break,
                },
            };
            let Ok(ev) = decode::<JobEvent>(&sample.payload().to_bytes()) else {
                continue;
            };
            let live = Live {
                job: ev.job_id.to_string(),
                stage: ev.stage.as_str(),
                state: state_after(&ev.event).as_str(),
                text: station::describe(&ev),
                at_ms: ev.at_ms,
            };
            // The page went away: stop following.
            if tx.send(live).await.is_err() {
                break;
            }
        }
    });
    let events = ReceiverStream::new(rx).map(|live| {
        Ok::<Event, Infallible>(
            Event::default()
                .event("job")
                .json_data(&live)
                .unwrap_or_else(|_| Event::default().comment("unencodable event")),
        )
    });
    Sse::new(events)
        .keep_alive(KeepAlive::new().interval(Duration::from_secs(15)))
        .into_response()
}
