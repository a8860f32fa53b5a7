//! Identifier newtypes that validate when built or deserialised.
//!
//! Every id travels inside Zenoh key expressions, so it must never contain a
//! character with a meaning there (`/`, `*`, `$`, `?`, `#`, `@`) and must be
//! short enough to read on a machine's screen.

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize};
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

/// Checks the common id rule: 1 to `max` characters from `A–Z a–z 0–9 _ -`,
/// starting with a letter or digit.
fn check_id(kind: &'static str, value: &str, max: usize) -> Result<(), IdError> {
    let expected =
        format!("1 to {max} characters from A-Z a-z 0-9 _ -, starting with a letter or digit");
    let bad = |reason: String| IdError {
        kind,
        got: value.to_string(),
        expected: expected.clone(),
        reason,
    };
    if value.is_empty() {
        return Err(bad("it is empty".into()));
    }
    if value.chars().count() > max {
        return Err(bad(format!("it has {} characters", value.chars().count())));
    }
    if let Some(c) = value
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(bad(format!("it contains {c:?}")));
    }
    if !value.starts_with(|c: char| c.is_ascii_alphanumeric()) {
        return Err(bad("it does not start with a letter or digit".into()));
    }
    Ok(())
}

macro_rules! id_type {
    ($(#[$doc:meta])* $name:ident, $kind:literal, $max:literal) => {
        $(#[$doc])*
        #[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
        #[serde(transparent)]
        pub struct $name(String);

        impl $name {
            /// Builds the id, checking the rule for this kind of id.
            pub fn new(value: impl Into<String>) -> Result<Self, IdError> {
                let value = value.into();
                check_id($kind, &value, $max)?;
                Ok(Self(value))
            }

            /// The id as text.
            pub fn as_str(&self) -> &str {
                &self.0
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(&self.0)
            }
        }

        impl FromStr for $name {
            type Err = IdError;
            fn from_str(s: &str) -> Result<Self, Self::Err> {
                Self::new(s)
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let s = String::deserialize(d)?;
                Self::new(s).map_err(serde::de::Error::custom)
            }
        }
    };
}

id_type!(
    /// A job's id: unique per submission, the key of its events.
    JobId, "job id", 64
);
id_type!(
    /// A machine's id in the shop, e.g. `H01`.
    MachineId, "machine id", 32
);
id_type!(
    /// A hob's id in the tool library, e.g. `HOB-M3-80`.
    HobId, "hob id", 32
);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_ordinary_ids() {
        assert_eq!(JobId::new("J-2026_0001").unwrap().as_str(), "J-2026_0001");
        assert_eq!("H01".parse::<MachineId>().unwrap().to_string(), "H01");
    }

    #[test]
    fn rejects_key_expression_characters_and_names_them() {
        for bad in ["a/b", "*", "a$b", "x?", "", "-lead", "a b"] {
            let err = JobId::new(bad).unwrap_err();
            assert_eq!(err.got, bad);
            assert_eq!(err.kind, "job id");
        }
        let err = MachineId::new("H/01").unwrap_err();
        assert!(err.to_string().contains("'/'"), "{err}");
    }

    #[test]
    fn rejects_overlong_ids() {
        let err = MachineId::new("M".repeat(33)).unwrap_err();
        assert!(err.to_string().contains("33 characters"), "{err}");
    }

    #[test]
    fn deserialising_validates() {
        let err = serde_json::from_str::<HobId>("\"bad/hob\"").unwrap_err();
        assert!(err.to_string().contains("hob id"), "{err}");
    }
}
