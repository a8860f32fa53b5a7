//! Errors: the typed [`JobError`] every stage reports (with the [`Stage`] that
//! found it), invalid ids and undecodable messages.

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::codes::Code;
pub use crate::ids::IdError;
use crate::ids::{JobId, MachineId};

/// A message that could not be encoded or decoded.
#[derive(Debug, Error)]
pub enum CodecError {
    /// The bytes are not a MessagePack gearcam envelope.
    #[error("malformed {expected_kind} message: {detail}")]
    Malformed {
        /// The message kind the reader expected.
        expected_kind: &'static str,
        /// What the decoder said.
        detail: String,
    },
    /// The envelope carries a schema version this reader does not know.
    #[error("unsupported schema version {got} in {kind} message; this reader understands version {expected}")]
    UnknownVersion {
        /// The message kind named in the envelope.
        kind: String,
        /// The version this reader speaks.
        expected: u16,
        /// The version in the envelope.
        got: u16,
    },
    /// The envelope holds a different kind of message than the key promises.
    #[error("wrong message kind: expected {expected}, got {got}")]
    WrongKind {
        /// The kind this reader expected.
        expected: &'static str,
        /// The kind named in the envelope.
        got: String,
    },
    /// The message is larger than the reader accepts.
    #[error("{kind} message of {got} bytes exceeds the limit of {limit} bytes")]
    TooLarge {
        /// The message kind the reader expected.
        kind: &'static str,
        /// The size limit in bytes.
        limit: usize,
        /// The size received.
        got: usize,
    },
    /// Encoding failed (a bug: every message type is encodable).
    #[error("cannot encode {kind} message: {detail}")]
    Encode {
        /// The message kind.
        kind: &'static str,
        /// What the encoder said.
        detail: String,
    },
}

impl CodecError {
    /// A stable code for typed error events.
    pub fn code(&self) -> Code {
        match self {
            CodecError::Malformed { .. } => Code::MALFORMED_MESSAGE,
            CodecError::UnknownVersion { .. } => Code::UNKNOWN_SCHEMA_VERSION,
            CodecError::WrongKind { .. } => Code::WRONG_MESSAGE_KIND,
            CodecError::TooLarge { .. } => Code::MESSAGE_TOO_LARGE,
            CodecError::Encode { .. } => Code::ENCODE_FAILED,
        }
    }
}

/// The stage of the pipeline an event or error comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Stage {
    /// Planning station (job file, submission).
    Station,
    /// Knowledge service.
    Knowledge,
    /// Model service.
    Model,
    /// Template service.
    Template,
    /// Delivery agent.
    Agent,
}

impl Stage {
    /// The stage's name.
    pub fn as_str(self) -> &'static str {
        match self {
            Stage::Station => "station",
            Stage::Knowledge => "knowledge",
            Stage::Model => "model",
            Stage::Template => "template",
            Stage::Agent => "agent",
        }
    }
}

/// A typed error: what was wrong, where, what was expected and what was given.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobError {
    /// Stage that found it.
    pub stage: Stage,
    /// Stable code, e.g. `BASE_PITCH_MISMATCH`.
    pub code: Code,
    /// Field concerned, e.g. `hob.module_mm`.
    pub field: String,
    /// The expected value or range, as text.
    pub expected: String,
    /// The given value, as text.
    pub got: String,
    /// A sentence saying what is wrong and what to do.
    pub message: String,
}

/// A typed problem found by code that belongs to no stage — a shared
/// crate's validation, a replay that several stages run — for the stage that
/// runs it to raise as its own [`JobError`] ([`Problem::raise`]). The same
/// five parts as a [`JobError`]: what was wrong (`code`, `field`), what was
/// expected, what was given, and what to do.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Stable code.
    pub code: Code,
    /// Field concerned, e.g. `die.teeth`.
    pub field: String,
    /// The expected value or range, as text.
    pub expected: String,
    /// The given value, as text.
    pub got: String,
    /// A sentence saying what is wrong and what to do.
    pub message: String,
}

impl Problem {
    /// A problem on `field`.
    pub fn new(
        code: Code,
        field: &str,
        expected: impl Into<String>,
        got: impl Into<String>,
        message: impl Into<String>,
    ) -> Problem {
        Problem {
            code,
            field: field.into(),
            expected: expected.into(),
            got: got.into(),
            message: message.into(),
        }
    }

    /// The problem as the typed error of `stage`.
    pub fn raise(self, stage: Stage) -> JobError {
        JobError {
            stage,
            code: self.code,
            field: self.field,
            expected: self.expected,
            got: self.got,
            message: self.message,
        }
    }
}

impl Stage {
    /// A typed error found by this stage: what was wrong (`code`, `field`),
    /// what was expected, what was given, and what to do (`message`).
    pub fn error(
        self,
        code: Code,
        field: &str,
        expected: impl Into<String>,
        got: impl Into<String>,
        message: impl Into<String>,
    ) -> JobError {
        JobError::new(self, code, field, expected, got, message)
    }
}

impl JobError {
    /// A typed error of `stage`.
    pub fn new(
        stage: Stage,
        code: Code,
        field: &str,
        expected: impl Into<String>,
        got: impl Into<String>,
        message: impl Into<String>,
    ) -> JobError {
        JobError {
            stage,
            code,
            field: field.into(),
            expected: expected.into(),
            got: got.into(),
            message: message.into(),
        }
    }

    /// `JOB_ID_MISMATCH`: the `what` (request, plan, model, program) received
    /// on `key` carries the job id `got`, not the key's.
    pub fn job_id_mismatch(stage: Stage, key: &str, got: &JobId, what: &str) -> JobError {
        JobError::new(
            stage,
            Code::JOB_ID_MISMATCH,
            "job_id",
            key,
            got.to_string(),
            format!("the {what}'s job id differs from the job id in its key"),
        )
    }
}

impl JobError {
    /// `JOB_SUPERSEDED`: an operator adopted the edit at `machine` of program
    /// `name` (now its version `seq`) that the job waited to replace; the
    /// job ends and is never delivered over it.
    pub fn superseded(machine: &MachineId, name: &str, seq: u64, by: &str) -> JobError {
        JobError::new(
            Stage::Agent,
            Code::JOB_SUPERSEDED,
            "job",
            "a job no operator's decision has ended",
            format!("version {seq} of {name} at {machine}, adopted by {by}"),
            format!(
                "{by} adopted the edit of {name} at {machine} that this job waited to replace; the job is not delivered over it (submit it again for gearcam's program)"
            ),
        )
    }

    /// `JOB_CANCELLED`: `by` cancelled the job before it was delivered.
    pub fn cancelled(by: &str) -> JobError {
        JobError::new(
            Stage::Station,
            Code::JOB_CANCELLED,
            "job",
            "a job not cancelled",
            format!("cancelled by {by}"),
            format!("{by} cancelled the job; it is never delivered"),
        )
    }

    /// `BAD_JOB_ID`, `BAD_MACHINE_ID` or `BAD_HOB_ID`: the id in `field` breaks
    /// the id rule; `got` is the id as given.
    pub fn bad_id(stage: Stage, field: &str, err: &IdError) -> JobError {
        let code = match err.kind {
            "job id" => Code::BAD_JOB_ID,
            "machine id" => Code::BAD_MACHINE_ID,
            _ => Code::BAD_HOB_ID,
        };
        JobError::new(
            stage,
            code,
            field,
            err.expected.clone(),
            err.got.clone(),
            format!("the {} is not valid: {}", err.kind, err.reason),
        )
    }
}

impl std::fmt::Display for JobError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "[{}] {} {}: {} (expected {}, got {})",
            self.stage.as_str(),
            self.code,
            self.field,
            self.message,
            self.expected,
            self.got
        )
    }
}
