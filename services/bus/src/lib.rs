//! Shared Zenoh plumbing of every gearcam service.
//!
//! # Layout
//!
//! - [`config`]: [`BusConfig`] (mode, listen/connect endpoints, multicast
//!   scouting, JSON5 config file) and the [`BusArgs`] every binary flattens
//!   into its command line.
//! - [`Bus`]: an open session with typed put, event publishing, liveliness
//!   tokens and waiting for other services to be alive.
//! - [`stage`]: the loop every pipeline stage runs: subscribe, decode and
//!   validate, handle, publish, report typed errors; never panic, never silence.
//! - [`query`]: typed request/reply with retries, and a serving loop for queryables.
//! - [`alive`]: the services alive, as a liveliness subscriber follows them.
//! - [`shutdown`]: one future for SIGINT and SIGTERM.
#![forbid(unsafe_code)]

pub mod alive;
pub mod config;
pub mod durable;
pub mod query;
pub mod shutdown;
pub mod stage;

use std::time::Duration;

use gearcam_proto::{encode, keys, now_ms, CodecError, EventKind, JobEvent, JobId, Message, Stage};
use thiserror::Error;
use zenoh::liveliness::LivelinessToken;
use zenoh::qos::CongestionControl;
use zenoh::Session;

pub use config::{BusArgs, BusConfig, Mode};
pub use shutdown::{cancel_on_signal, init_tracing, shutdown_signal};
pub use tokio_util::sync::CancellationToken;

/// Errors of the bus layer.
#[derive(Debug, Error)]
pub enum BusError {
    /// The Zenoh configuration is invalid.
    #[error("invalid Zenoh configuration ({what}): {detail}")]
    Config {
        /// Which setting.
        what: String,
        /// What Zenoh said.
        detail: String,
    },
    /// Zenoh refused an operation.
    #[error("zenoh {op} failed: {detail}")]
    Zenoh {
        /// The operation.
        op: &'static str,
        /// What Zenoh said.
        detail: String,
    },
    /// A message could not be encoded.
    #[error(transparent)]
    Codec(#[from] CodecError),
    /// Services did not become alive in time.
    #[error("services not alive after {waited_ms} ms: {missing:?}; is `gearcam up` (or each service) running and reachable?")]
    NotAlive {
        /// Services that did not answer.
        missing: Vec<String>,
        /// How long we waited.
        waited_ms: u64,
    },
}

fn zerr(op: &'static str) -> impl FnOnce(zenoh::Error) -> BusError {
    move |e| BusError::Zenoh {
        op,
        detail: e.to_string(),
    }
}

/// An open Zenoh session with gearcam's typed helpers. Cheap to clone.
#[derive(Clone, Debug)]
pub struct Bus {
    session: Session,
}

impl Bus {
    /// Opens a session with the given configuration.
    pub async fn open(config: &BusConfig) -> Result<Bus, BusError> {
        let zconfig = config.to_zenoh()?;
        let session = zenoh::open(zconfig).await.map_err(zerr("open"))?;
        Ok(Bus { session })
    }

    /// The underlying Zenoh session.
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// Publishes raw bytes reliably (blocking, not dropping, under congestion).
    pub async fn put_bytes(&self, key: &str, payload: Vec<u8>) -> Result<(), BusError> {
        self.session
            .put(key, payload)
            .congestion_control(CongestionControl::Block)
            .await
            .map_err(zerr("put"))
    }

    /// Encodes and publishes a message.
    pub async fn put<T: Message>(&self, key: &str, msg: &T) -> Result<(), BusError> {
        self.put_bytes(key, encode(msg)?).await
    }

    /// Publishes a job event of a middle service or the station on its own
    /// key (`gearcam/v1/jobs/{job}/events/{stage}`).
    pub async fn event(&self, job: &JobId, stage: Stage, event: EventKind) -> Result<(), BusError> {
        self.event_as(stage.as_str(), job, stage, event).await
    }

    /// Publishes a job event on `reporter`'s key
    /// (`gearcam/v1/jobs/{job}/events/{reporter}`; an agent: `agent-{machine}`).
    pub async fn event_as(
        &self,
        reporter: &str,
        job: &JobId,
        stage: Stage,
        event: EventKind,
    ) -> Result<(), BusError> {
        let msg = JobEvent {
            job_id: job.clone(),
            stage,
            at_ms: now_ms(),
            event,
        };
        self.put(&keys::job_event(job, reporter), &msg).await
    }

    /// Declares the liveliness token `gearcam/v1/alive/{service}`; it lives as
    /// long as the returned token.
    pub async fn alive_token(&self, service: &str) -> Result<LivelinessToken, BusError> {
        self.session
            .liveliness()
            .declare_token(keys::alive(service))
            .await
            .map_err(zerr("liveliness token"))
    }

    /// True when a liveliness token `gearcam/v1/alive/{service}` is visible.
    pub async fn is_alive(&self, service: &str) -> Result<bool, BusError> {
        let replies = self
            .session
            .liveliness()
            .get(keys::alive(service))
            .timeout(Duration::from_millis(500))
            .await
            .map_err(zerr("liveliness get"))?;
        while let Ok(reply) = replies.recv_async().await {
            if reply.result().is_ok() {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// Waits until every named service is alive, polling, up to `timeout`.
    pub async fn wait_alive(&self, services: &[String], timeout: Duration) -> Result<(), BusError> {
        let start = tokio::time::Instant::now();
        loop {
            let mut missing = Vec::new();
            for s in services {
                if !self.is_alive(s).await? {
                    missing.push(s.clone());
                }
            }
            if missing.is_empty() {
                return Ok(());
            }
            if start.elapsed() >= timeout {
                return Err(BusError::NotAlive {
                    missing,
                    waited_ms: timeout.as_millis() as u64,
                });
            }
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }

    /// Closes the session.
    pub async fn close(self) {
        if let Err(e) = self.session.close().await {
            tracing::warn!(error = %e, "closing the Zenoh session failed");
        }
    }
}
