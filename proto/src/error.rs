//! Errors of the protocol crate: invalid ids and undecodable messages.

use thiserror::Error;

/// An id that breaks its rule.
#[derive(Debug, Clone, Error, PartialEq, Eq)]
#[error("invalid {kind} {got:?}: {reason}; expected {expected}")]
pub struct IdError {
    /// Which kind of id (`job id`, `machine id`, ...).
    pub kind: &'static str,
    /// The text given.
    pub got: String,
    /// The rule it had to follow.
    pub expected: String,
    /// What is wrong with it.
    pub reason: String,
}

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
    pub fn code(&self) -> &'static str {
        match self {
            CodecError::Malformed { .. } => "MALFORMED_MESSAGE",
            CodecError::UnknownVersion { .. } => "UNKNOWN_SCHEMA_VERSION",
            CodecError::WrongKind { .. } => "WRONG_MESSAGE_KIND",
            CodecError::TooLarge { .. } => "MESSAGE_TOO_LARGE",
            CodecError::Encode { .. } => "ENCODE_FAILED",
        }
    }
}
