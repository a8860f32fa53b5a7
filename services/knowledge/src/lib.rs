//! The knowledge service: the shop's process knowledge in SQLite (GT class
//! tree, workpieces, hobs, machines, machining history as cases, jobs) and the
//! step that turns a job request into a process plan: hob matching, cutting
//! data by case-based reasoning, the job's overrides, every value with its
//! source (docs/knowledge.md#case-based-reasoning).
//!
//! # Layout
//!
//! - [`db`]: opening the database and its schema migrations.
//! - [`seed`]: the seed data of every schema version (machines, hobs, materials,
//!   classes, cases, weights, workpieces), with provenance.
//! - [`library`]: every library as generic records: list, get, add, edit,
//!   remove, validation (the `kb` queryable, CLI and CSV).
//! - [`records`]: one typed record per library, read by one reader per
//!   table; what planning, retrieval, hob matching and learning read.
//! - [`csvio`]: CSV import and export of workpieces, hobs, cases and materials.
//! - [`cbr`]: case retrieval (hard constraints, weighted similarity, top-k) and adaptation; pure.
//! - [`hobmatch`]: hob matching with explanations; pure.
//! - [`history`]: the case and workpiece records as the types of [`cbr`] and of a job.
//! - [`plan`]: job request → process plan.
//! - [`learn`]: the learning loop: a confirmed job becomes a case; hob life and shift.
//! - [`audit`]: every change of the libraries recorded (who, when, old, new).
//! - [`service`]: the Zenoh stage (`JobRequest` in, `ProcessPlan` out) and the
//!   library queryable on `gearcam/v1/kb/**`.
//! - [`answers`]: the change log (`gearcam/v1/kb-log/**`) and the
//!   confirmation of delivered jobs (`gearcam/v1/kb-confirm/**`) on the bus.
#![forbid(unsafe_code)]

pub mod answers;
pub mod audit;
pub mod cbr;
pub mod csvio;
pub mod db;
mod family;
pub mod history;
pub mod hobmatch;
pub mod learn;
pub mod library;
pub mod plan;
pub mod records;
mod sections;
pub mod seed;
pub mod service;
pub mod spiral;
pub mod wire;

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
    /// A stored record does not fit its library's type: a required field
    /// is NULL, or a value is of another type, out of the type's range or
    /// not one of the field's choices ([`records`]).
    #[error("{library} record {id:?}, field {field}: {detail}")]
    Record {
        /// The library, e.g. `hobs`.
        library: &'static str,
        /// The record's key.
        id: String,
        /// The field (for a machine, the path into its profile).
        field: String,
        /// What is wrong with the value.
        detail: String,
    },
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
