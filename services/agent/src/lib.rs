//! The delivery agent beside a machine: receives its machine's NC programs,
//! stores them durably in the controller's program directory under the
//! controller's naming rule with an SQLite index row, and sends a receipt.
//!
//! # Layout
//!
//! - [`store`]: the part-program store (atomic file write, index, idempotency,
//!   conflict detection).
//! - [`guard`]: only programs of journaled jobs, checked again against the
//!   model service's model.
//! - [`service`]: the Zenoh stage: `NcProgram` in, `delivered` event with the
//!   receipt out.
#![forbid(unsafe_code)]

pub mod guard;
pub mod service;
pub mod store;

use thiserror::Error;

/// Errors of the agent.
#[derive(Debug, Error)]
pub enum AgentError {
    /// The index database failed.
    #[error("program index (SQLite): {0}")]
    Sqlite(#[from] rusqlite::Error),
    /// A file or directory failed.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The error.
        #[source]
        source: std::io::Error,
    },
    /// The index held data before and is now missing or empty: the agent
    /// refuses to start rather than forget every version (the message says
    /// how to recover).
    #[error("{0}")]
    Lost(String),
    /// Another agent already serves this machine: this one does not.
    #[error("{0}")]
    Duplicate(String),
    /// The bus failed.
    #[error(transparent)]
    Bus(#[from] gearcam_bus::BusError),
}
