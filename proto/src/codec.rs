//! The wire codec: MessagePack maps with field names, inside a versioned envelope.
//!
//! Every payload on the bus is the MessagePack encoding (`rmp_serde::to_vec_named`)
//! of the map
//!
//! ```text
//! { "schema": 1, "kind": "job_request", "body": { ...the message's fields... } }
//! ```
//!
//! so a client in any language can read and write it with a plain MessagePack
//! library. A reader first decodes `schema` and `kind` alone and rejects an unknown
//! version or an unexpected kind with a clear error before it looks at the body.

use serde::de::{DeserializeOwned, IgnoredAny};
use serde::{Deserialize, Serialize};

use crate::error::CodecError;

/// The schema version this build reads and writes.
pub const SCHEMA_VERSION: u16 = 1;

/// The largest payload any gearcam reader accepts, in bytes (4 MiB).
pub const MAX_MESSAGE_BYTES: usize = 4 * 1024 * 1024;

/// A message type that travels on the bus.
pub trait Message: Serialize + DeserializeOwned {
    /// The envelope's `kind` for this type, e.g. `job_request`.
    const KIND: &'static str;
}

#[derive(Serialize)]
struct EnvelopeOut<'a, T> {
    schema: u16,
    kind: &'a str,
    body: &'a T,
}

#[derive(Deserialize)]
struct EnvelopeHead {
    schema: u16,
    kind: String,
    #[allow(dead_code)]
    body: IgnoredAny,
}

impl EnvelopeHead {
    /// Reads the head. What [`encode`] writes starts with `schema` and
    /// `kind`, and those are read without walking the body; a map in any
    /// other order is read whole.
    fn read(bytes: &[u8]) -> Result<EnvelopeHead, rmp_serde::decode::Error> {
        match Self::leading(bytes) {
            Some(head) => Ok(head),
            None => rmp_serde::from_slice(bytes),
        }
    }

    /// The head when the map's first two entries are `schema` and `kind`.
    fn leading(bytes: &[u8]) -> Option<EnvelopeHead> {
        use rmp::decode::{read_int, read_map_len, read_str};
        let mut rd = bytes;
        let mut buf = [0u8; 64];
        if read_map_len(&mut rd).ok()? != 3 || read_str(&mut rd, &mut buf).ok()? != "schema" {
            return None;
        }
        let schema: u16 = read_int(&mut rd).ok()?;
        if read_str(&mut rd, &mut buf).ok()? != "kind" {
            return None;
        }
        let kind = read_str(&mut rd, &mut buf).ok()?.to_string();
        Some(EnvelopeHead {
            schema,
            kind,
            body: IgnoredAny,
        })
    }
}

/// The whole envelope, read in one pass.
#[derive(Deserialize)]
struct EnvelopeIn<T> {
    schema: u16,
    kind: String,
    body: T,
}

/// Encodes a message into its envelope.
pub fn encode<T: Message>(msg: &T) -> Result<Vec<u8>, CodecError> {
    rmp_serde::to_vec_named(&EnvelopeOut {
        schema: SCHEMA_VERSION,
        kind: T::KIND,
        body: msg,
    })
    .map_err(|e| CodecError::Encode {
        kind: T::KIND,
        detail: e.to_string(),
    })
}

/// Decodes a message, checking size, schema version and kind first: a
/// message of another version or kind is refused as such, whatever its body.
/// The envelope is read in one pass; only when that fails, or finds another
/// version or kind, is the head read alone to say which.
pub fn decode<T: Message>(bytes: &[u8]) -> Result<T, CodecError> {
    if bytes.len() > MAX_MESSAGE_BYTES {
        return Err(CodecError::TooLarge {
            kind: T::KIND,
            limit: MAX_MESSAGE_BYTES,
            got: bytes.len(),
        });
    }
    let body_error = match rmp_serde::from_slice::<EnvelopeIn<T>>(bytes) {
        Ok(env) if env.schema == SCHEMA_VERSION && env.kind == T::KIND => return Ok(env.body),
        Ok(_) => None,
        Err(e) => Some(e),
    };
    let malformed = |e: rmp_serde::decode::Error| CodecError::Malformed {
        expected_kind: T::KIND,
        detail: e.to_string(),
    };
    let head = EnvelopeHead::read(bytes).map_err(malformed)?;
    if head.schema != SCHEMA_VERSION {
        return Err(CodecError::UnknownVersion {
            kind: head.kind,
            expected: SCHEMA_VERSION,
            got: head.schema,
        });
    }
    if head.kind != T::KIND {
        return Err(CodecError::WrongKind {
            expected: T::KIND,
            got: head.kind,
        });
    }
    Err(match body_error {
        Some(e) => malformed(e),
        None => CodecError::Malformed {
            expected_kind: T::KIND,
            detail: "the envelope's head and body disagree".into(),
        },
    })
}

/// A message type a stage receives: one [`Message`] kind, or one of several
/// (a plan or model of any part family, [`crate::AnyPlan`]).
pub trait Incoming: Sized {
    /// The envelope kinds accepted, for error messages.
    const KINDS: &'static str;
    /// Decodes the bytes, checking size, schema version and kind first.
    fn decode_incoming(bytes: &[u8]) -> Result<Self, CodecError>;
}

impl<T: Message> Incoming for T {
    const KINDS: &'static str = T::KIND;
    fn decode_incoming(bytes: &[u8]) -> Result<Self, CodecError> {
        decode(bytes)
    }
}

/// The envelope's kind of `bytes` (checking size and schema version), for a
/// reader that accepts several kinds (`expected` names them in errors).
pub fn kind_of(bytes: &[u8], expected: &'static str) -> Result<String, CodecError> {
    if bytes.len() > MAX_MESSAGE_BYTES {
        return Err(CodecError::TooLarge {
            kind: expected,
            limit: MAX_MESSAGE_BYTES,
            got: bytes.len(),
        });
    }
    let head = EnvelopeHead::read(bytes).map_err(|e| CodecError::Malformed {
        expected_kind: expected,
        detail: e.to_string(),
    })?;
    if head.schema != SCHEMA_VERSION {
        return Err(CodecError::UnknownVersion {
            kind: head.kind,
            expected: SCHEMA_VERSION,
            got: head.schema,
        });
    }
    Ok(head.kind)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Ping {
        n: u32,
        label: String,
    }
    impl Message for Ping {
        const KIND: &'static str = "ping";
    }

    #[test]
    fn round_trips_and_keeps_field_names() {
        let msg = Ping {
            n: 7,
            label: "x".into(),
        };
        let bytes = encode(&msg).unwrap();
        assert_eq!(decode::<Ping>(&bytes).unwrap(), msg);
        // Field names are on the wire, so other languages can read the map.
        let generic: serde_json::Value = rmp_serde::from_slice(&bytes).unwrap();
        assert_eq!(
            generic,
            serde_json::json!({"schema": 1, "kind": "ping", "body": {"n": 7, "label": "x"}})
        );
    }

    #[test]
    fn rejects_unknown_version_with_both_versions() {
        let bytes = rmp_serde::to_vec_named(&serde_json::json!(
            {"schema": 9, "kind": "ping", "body": {"n": 1, "label": ""}}
        ))
        .unwrap();
        let err = decode::<Ping>(&bytes).unwrap_err();
        assert_eq!(err.code(), "UNKNOWN_SCHEMA_VERSION");
        assert!(err.to_string().contains("version 9"), "{err}");
        assert!(err.to_string().contains("version 1"), "{err}");
    }

    #[test]
    fn rejects_random_bytes_and_wrong_kind() {
        let err = decode::<Ping>(&[0xc1, 0x00, 0xff, 0x13]).unwrap_err();
        assert_eq!(err.code(), "MALFORMED_MESSAGE");
        let other = rmp_serde::to_vec_named(&serde_json::json!(
            {"schema": 1, "kind": "pong", "body": {}}
        ))
        .unwrap();
        assert_eq!(
            decode::<Ping>(&other).unwrap_err().code(),
            "WRONG_MESSAGE_KIND"
        );
    }

    #[test]
    fn rejects_a_body_with_a_missing_field() {
        let bytes = rmp_serde::to_vec_named(&serde_json::json!(
            {"schema": 1, "kind": "ping", "body": {"n": 1}}
        ))
        .unwrap();
        let err = decode::<Ping>(&bytes).unwrap_err();
        assert!(err.to_string().contains("label"), "{err}");
    }

    #[test]
    fn a_body_that_fits_does_not_hide_another_kind() {
        let other = rmp_serde::to_vec_named(&serde_json::json!(
            {"schema": 1, "kind": "pong", "body": {"n": 1, "label": "x"}}
        ))
        .unwrap();
        let err = decode::<Ping>(&other).unwrap_err();
        assert_eq!(err.code(), "WRONG_MESSAGE_KIND", "{err}");
        assert!(err.to_string().contains("pong"), "{err}");
    }

    #[test]
    fn the_head_is_read_without_the_body() {
        let mut bytes = encode(&Ping {
            n: 7,
            label: "a label long enough to cut".into(),
        })
        .unwrap();
        bytes.truncate(bytes.len() - 5);
        assert_eq!(kind_of(&bytes, "ping").unwrap(), "ping");
        assert_eq!(
            decode::<Ping>(&bytes).unwrap_err().code(),
            "MALFORMED_MESSAGE"
        );
        // The head's fields in another order, after the body.
        let reordered = rmp_serde::to_vec_named(&serde_json::json!(
            {"body": {"n": 1, "label": ""}, "kind": "ping", "schema": 1}
        ))
        .unwrap();
        assert_eq!(kind_of(&reordered, "ping").unwrap(), "ping");
        assert_eq!(decode::<Ping>(&reordered).unwrap().n, 1);
        let headless = rmp_serde::to_vec_named(&serde_json::json!({"kind": "ping"})).unwrap();
        let err = kind_of(&headless, "ping").unwrap_err();
        assert!(err.to_string().contains("schema"), "{err}");
    }

    #[test]
    fn rejects_oversize_payloads() {
        let err = decode::<Ping>(&vec![0u8; MAX_MESSAGE_BYTES + 1]).unwrap_err();
        assert_eq!(err.code(), "MESSAGE_TOO_LARGE");
    }
}
