//! Gear measurement, the pure model: what a gear-measuring machine reports
//! from the traces it takes on a cylindrical involute gear, and the
//! ISO 1328-1:2013 flank tolerance class those deviations meet
//! (docs/measurement.md).
//!
//! The crate knows nothing of where the traces come from (a probe on a real
//! gear, or a simulated hobbing of a virtual blank): it takes numbers and
//! the gear's design data and returns deviations and classes. Deviations
//! are micrometres, positive where the flank has more material than the
//! design ("+material"); lengths are millimetres, angles degrees at the
//! interface.
//!
//! # Layout
//!
//! - [`iso1328`]: the tolerance formulas of ISO 1328-1:2013 for classes 1
//!   to 11, the rounding rule, the scope, and the class a deviation meets;
//! - [`trace`]: the evaluation shared by profile and helix traces (total,
//!   slope and form deviations from the least-squares mean line);
//! - [`profile`]: profile traces over the roll length (Fα, fHα, ffα);
//! - [`helix`]: helix traces over the face width (Fβ, fHβ, ffβ) and the
//!   sign of the slope for each flank and helix hand;
//! - [`pitch`]: single and cumulative pitch deviations (fp, Fp) per flank
//!   and the runout Fr;
//! - [`size`]: span measurement Wk and dimension over balls or pins, and
//!   the tooth thickness each implies;
//! - [`outline`]: a gear given as transverse outlines r(θ) (a simulated
//!   cut) measured like a gear-measuring machine: every item above, and
//!   its ISO 1328 class.
#![forbid(unsafe_code)]

pub mod helix;
pub mod iso1328;
pub mod outline;
pub mod pitch;
pub mod profile;
pub mod size;
pub mod trace;

use std::fmt;

/// What was wrong with an input: which field, what was expected, what it
/// was. Every function of the crate validates its inputs and returns this
/// instead of a meaningless number.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A value outside its range (or not finite).
    OutOfRange {
        /// The input's name, e.g. `normal_module_mm`.
        field: &'static str,
        /// The range it must lie in, as the standard or the formula states it.
        expected: &'static str,
        /// The value given.
        got: f64,
    },
    /// Too few samples (or teeth) to evaluate.
    TooFewSamples {
        /// What was counted.
        what: &'static str,
        /// How many are needed at least.
        needed: usize,
        /// How many there were.
        got: usize,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::OutOfRange {
                field,
                expected,
                got,
            } => write!(f, "{field} = {got} is outside {expected}"),
            Error::TooFewSamples { what, needed, got } => {
                write!(f, "{got} {what}, at least {needed} needed")
            }
        }
    }
}

impl std::error::Error for Error {}

/// `Ok(value)` when `value` is finite and within `lo..=hi`, else the error
/// naming `field` and `expected`.
pub(crate) fn check_range(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<f64, Error> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(value)
    } else {
        Err(Error::OutOfRange {
            field,
            expected,
            got: value,
        })
    }
}
