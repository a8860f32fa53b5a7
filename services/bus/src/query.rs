//! Request/reply on Zenoh queries: a typed client call with retries (a query
//! can find no queryable while its declaration is still travelling), and a
//! serving loop for a stage that answers queries.

use std::time::Duration;

use gearcam_proto::{decode, encode, keys, EventKind, JobId, Message, Stage};
use tokio_util::sync::CancellationToken;

use zenoh::handlers::FifoChannelHandler;
use zenoh::query::{Query, Queryable};

use crate::{Bus, BusError};

/// What a query handler produced.
#[derive(Debug)]
pub struct Answer {
    /// The reply payload, or an error text sent as an error reply.
    pub reply: Result<Vec<u8>, String>,
    /// Events to publish after replying.
    pub events: Vec<(JobId, EventKind)>,
}

impl Answer {
    /// The error reply of a handler that failed unexpectedly (a panic).
    pub fn internal(stage: Stage) -> Answer {
        Answer::error(format!(
            "internal error in the {} stage; please report it",
            stage.as_str()
        ))
    }

    /// A reply with an encoded message and no events.
    pub fn message<T: Message>(msg: &T) -> Answer {
        Answer {
            reply: encode(msg).map_err(|e| e.to_string()),
            events: vec![],
        }
    }

    /// An error reply.
    pub fn error(text: impl Into<String>) -> Answer {
        Answer {
            reply: Err(text.into()),
            events: vec![],
        }
    }
}

/// How a client call is retried.
#[derive(Debug, Clone, Copy)]
pub struct Retry {
    /// Timeout of one attempt.
    pub timeout: Duration,
    /// Attempts in all.
    pub attempts: u32,
    /// Pause between attempts.
    pub pause: Duration,
}

impl Default for Retry {
    fn default() -> Self {
        Retry {
            timeout: Duration::from_secs(5),
            attempts: 3,
            pause: Duration::from_millis(200),
        }
    }
}

/// The outcome of a call.
#[derive(Debug)]
pub enum CallError {
    /// No queryable answered in any attempt.
    NoReply {
        /// The key queried.
        key: String,
        /// Attempts made.
        attempts: u32,
    },
    /// The queryable answered with an error reply.
    Remote(String),
    /// The reply could not be decoded.
    Codec(gearcam_proto::CodecError),
    /// The bus failed.
    Bus(BusError),
}

impl std::fmt::Display for CallError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CallError::NoReply { key, attempts } => {
                write!(f, "no reply on {key} after {attempts} attempt(s): is the service running and reachable?")
            }
            CallError::Remote(e) => write!(f, "the service answered with an error: {e}"),
            CallError::Codec(e) => write!(f, "undecodable reply: {e}"),
            CallError::Bus(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for CallError {}

impl Bus {
    /// Sends a query with an optional payload and returns the first reply's
    /// bytes, retrying when no queryable answers.
    pub async fn call_bytes(
        &self,
        key: &str,
        payload: Option<Vec<u8>>,
        retry: Retry,
    ) -> Result<Vec<u8>, CallError> {
        for attempt in 1..=retry.attempts.max(1) {
            let mut get = self.session().get(key).timeout(retry.timeout);
            if let Some(p) = &payload {
                get = get.payload(p.clone());
            }
            let replies = get.await.map_err(|e| {
                CallError::Bus(BusError::Zenoh {
                    op: "get",
                    detail: e.to_string(),
                })
            })?;
            if let Ok(reply) = replies.recv_async().await {
                return match reply.result() {
                    Ok(sample) => Ok(sample.payload().to_bytes().into_owned()),
                    Err(err) => Err(CallError::Remote(
                        String::from_utf8_lossy(&err.payload().to_bytes()).into_owned(),
                    )),
                };
            }
            if attempt < retry.attempts {
                tokio::time::sleep(retry.pause).await;
            }
        }
        Err(CallError::NoReply {
            key: key.to_string(),
            attempts: retry.attempts.max(1),
        })
    }

    /// A typed call: encodes `req` (if any), decodes the reply as `R`.
    pub async fn call<Q: Message, R: Message>(
        &self,
        key: &str,
        req: Option<&Q>,
        retry: Retry,
    ) -> Result<R, CallError> {
        let payload = match req {
            Some(q) => Some(encode(q).map_err(CallError::Codec)?),
            None => None,
        };
        let bytes = self.call_bytes(key, payload, retry).await?;
        decode(&bytes).map_err(CallError::Codec)
    }
}

/// Serves queries on `pattern` until `shutdown`; the liveliness token of
/// `service` (if given) is declared once the queryable is in place. `handle`
/// gets the query's key and payload (empty when none) and answers.
pub async fn run_queryable<F>(
    bus: &Bus,
    pattern: &str,
    service: Option<&str>,
    stage: Stage,
    shutdown: CancellationToken,
    mut handle: F,
) -> Result<(), BusError>
where
    F: FnMut(&str, &[u8]) -> Answer,
{
    run_queryable_batched(bus, pattern, service, stage, shutdown, 1, |batch| {
        batch.iter().map(|(k, p)| handle(k, p)).collect()
    })
    .await
}

/// The next queries to answer: the first to arrive and every other already
/// waiting, up to `max_batch`; `None` once `shutdown` is cancelled or the
/// queryable is closed.
pub async fn next_batch(
    queryable: &Queryable<FifoChannelHandler<Query>>,
    shutdown: &CancellationToken,
    max_batch: usize,
) -> Option<Vec<Query>> {
    let first = tokio::select! {
        _ = shutdown.cancelled() => return None,
        q = queryable.recv_async() => q.ok()?,
    };
    let mut queries = vec![first];
    while queries.len() < max_batch.max(1) {
        match queryable.try_recv() {
            Ok(Some(q)) => queries.push(q),
            _ => break,
        }
    }
    Some(queries)
}

/// Each query's key and payload (empty when it has none).
pub fn keyed(queries: &[Query]) -> Vec<(String, Vec<u8>)> {
    queries
        .iter()
        .map(|q| {
            (
                q.key_expr().as_str().to_string(),
                q.payload()
                    .map(|p| p.to_bytes().into_owned())
                    .unwrap_or_default(),
            )
        })
        .collect()
}

/// Sends each query its answer, in order, then publishes the answers' events
/// as `reporter` (a client that has its reply may ask about the job at once;
/// the events follow).
pub async fn send_answers(
    bus: &Bus,
    reporter: &str,
    stage: Stage,
    queries: Vec<Query>,
    answers: Vec<Answer>,
) {
    let mut events = Vec::new();
    for (query, answer) in queries.into_iter().zip(answers) {
        let sent = match answer.reply {
            Ok(bytes) => query.reply(query.key_expr().clone(), bytes).await,
            Err(text) => query.reply_err(text.into_bytes()).await,
        };
        if let Err(e) = sent {
            tracing::warn!(key = %query.key_expr(), error = %e, "cannot send reply");
        }
        events.extend(answer.events);
    }
    for (job, ev) in events {
        if let Err(e) = bus.event_as(reporter, &job, stage, ev).await {
            tracing::warn!(%job, error = %e, "cannot publish event");
        }
    }
}

/// Like [`run_queryable`], but hands `handle` every query already waiting (up
/// to `max_batch`) at once, so a durable store can commit them as a group.
/// `handle` returns one answer per query, in order.
pub async fn run_queryable_batched<F>(
    bus: &Bus,
    pattern: &str,
    service: Option<&str>,
    stage: Stage,
    shutdown: CancellationToken,
    max_batch: usize,
    mut handle: F,
) -> Result<(), BusError>
where
    F: FnMut(&[(String, Vec<u8>)]) -> Vec<Answer>,
{
    let queryable = bus
        .session()
        .declare_queryable(pattern)
        .await
        .map_err(|e| BusError::Zenoh {
            op: "declare queryable",
            detail: e.to_string(),
        })?;
    let _token = match service {
        Some(s) => Some(bus.alive_token(s).await?),
        None => None,
    };
    // Events go out on the service's own key (an agent: `agent-{machine}`).
    let reporter = keys::reporter(service.unwrap_or(stage.as_str()));
    tracing::info!(stage = stage.as_str(), pattern, "serving queries");
    while let Some(queries) = next_batch(&queryable, &shutdown, max_batch).await {
        let batch = keyed(&queries);
        let answers = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| handle(&batch)))
            .unwrap_or_else(|_| batch.iter().map(|_| Answer::internal(stage)).collect());
        send_answers(bus, &reporter, stage, queries, answers).await;
    }
    Ok(())
}
