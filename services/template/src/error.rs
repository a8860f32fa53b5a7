//! Errors of the template library: templates that cannot be loaded or compiled.
//!
//! Errors of a single job's rendering are not here: they travel to the planning
//! station as typed [`JobError`](gearcam_proto::JobError)s.

use std::path::PathBuf;

use thiserror::Error;

/// A template that cannot be taken into the library.
#[derive(Debug, Error)]
pub enum TemplateError {
    /// A template source is not in the standard-code format.
    #[error("{0}")]
    Format(#[from] crate::stdcode::StdCodeError),
    /// A template's expressions do not compile (unknown parameter, syntax, scope).
    #[error("{0}")]
    Compile(#[from] crate::engine::CompileError),
    /// The template library (SQLite) cannot be opened, imported into or read.
    #[error("template library: {0}")]
    Library(String),
    /// The template id does not name a class and a supported dialect.
    #[error("template id {id:?} is not usable: {reason}")]
    BadId {
        /// The id (file name up to the first `.`).
        id: String,
        /// What is wrong and what is expected.
        reason: String,
    },
    /// Two templates in the directory have the same id.
    #[error("template id {id} appears twice in the template directory: {first} and {second}")]
    DuplicateId {
        /// The id.
        id: String,
        /// The first file.
        first: PathBuf,
        /// The second file.
        second: PathBuf,
    },
    /// A template file or directory cannot be read.
    #[error("cannot read template {path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}
