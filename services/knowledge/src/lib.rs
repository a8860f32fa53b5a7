//! The knowledge service: the shop's process knowledge in SQLite (GT class
//! tree, workpieces, hobs, machines, machining history as cases, jobs) and the
//! step that turns a job request into a process plan: hob matching, cutting
//! data by case-based reasoning, the job's overrides, every value with its
//! source (docs/knowledge.md#case-based-reasoning).
//!
//! # Layout
//!
//! - [`db`]: schema migrations, seed data of version 1, machine and hob reads.
//! - [`seed`]: seed data of versions 2 (classes, cases, weights, workpieces) and 3 (machine H02), with provenance.
//! - [`library`]: every library as records: list, get, add, edit, remove, validation.
//! - [`csvio`]: CSV import and export of workpieces, hobs, cases and materials.
//! - [`cbr`]: case retrieval (hard constraints, weighted similarity, top-k) and adaptation; pure.
//! - [`hobmatch`]: hob matching with explanations; pure.
//! - [`history`]: reads the libraries into the types of [`cbr`] and [`hobmatch`].
//! - [`plan`]: job request → process plan.
//! - [`learn`]: the learning loop: a confirmed job becomes a case; hob life and shift.
//! - [`service`]: the Zenoh stage (`JobRequest` in, `ProcessPlan` out) and the
//!   library queryable on `gearcam/v1/kb/**`.
#![forbid(unsafe_code)]

pub mod cbr;
pub mod csvio;
pub mod db;
pub mod history;
pub mod hobmatch;
pub mod learn;
pub mod library;
pub mod plan;
pub mod seed;
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
    /// Seed data failed its own validation (a bug in gearcam).
    #[error("seed data: {0}")]
    Seed(String),
    /// A CSV file could not be read or written.
    #[error("CSV: {0}")]
    Csv(#[from] csv::Error),
    /// The bus failed.
    #[error(transparent)]
    Bus(#[from] gearcam_bus::BusError),
}
