//! The knowledge service: the shop's process knowledge in SQLite (machines,
//! hobs, cutting data) and the step that turns a job request into a process
//! plan, every value with its source.
//!
//! # Layout
//!
//! - [`db`]: schema migrations, seed data with provenance, reads.
//! - [`plan`]: classification, hob resolution and matching, cutting data.
//! - [`service`]: the Zenoh stage: `JobRequest` in, `ProcessPlan` out.
#![forbid(unsafe_code)]

pub mod db;
pub mod plan;
pub mod service;

use thiserror::Error;

/// Errors of the knowledge base.
#[derive(Debug, Error)]
pub enum KnowledgeError {
    /// SQLite failed.
    #[error("knowledge base (SQLite): {0}")]
    Sqlite(#[from] rusqlite::Error),
    /// A stored JSON column is unreadable.
    #[error("knowledge base JSON column: {0}")]
    Json(#[from] serde_json::Error),
    /// A file or directory could not be created.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The error.
        #[source]
        source: std::io::Error,
    },
    /// The bus failed.
    #[error(transparent)]
    Bus(#[from] gearcam_bus::BusError),
}
