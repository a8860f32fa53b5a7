//! Profile traces: the deviation of a flank along its involute, sampled
//! over the roll length, evaluated over the profile evaluation range Lα
//! ([`crate::trace`] for the definitions of Fα, fHα and ffα).
//!
//! The abscissa is the roll length L (mm), the length of the base-circle
//! tangent from its tangent point to the profile point: L = √(r² − rb²)
//! = rb·tan α = rb·ξ, with r the radius, rb the base radius, α the
//! transverse pressure angle and ξ the roll angle (rad) at the point.
//! Traces sampled by diameter or by roll angle are converted with
//! [`roll_length_from_diameter`] and [`roll_length_from_roll_angle`].
//!
//! Sign: fHα is the mean profile line's rise from the start of Lα (root
//! side, smaller roll length) to its end (tip side); positive means more
//! material towards the tip than the design.

use crate::trace::{evaluate, FlankDeviations};
use crate::Error;
use serde::{Deserialize, Serialize};

/// The roll length (mm) of the profile point at `diameter_mm` on an
/// involute of base diameter `base_diameter_mm`: √(d² − db²)/2.
pub fn roll_length_from_diameter(diameter_mm: f64, base_diameter_mm: f64) -> Result<f64, Error> {
    crate::check_range(
        "base_diameter_mm",
        base_diameter_mm,
        f64::MIN_POSITIVE,
        f64::MAX,
        "db > 0",
    )?;
    crate::check_range(
        "diameter_mm",
        diameter_mm,
        base_diameter_mm,
        f64::MAX,
        "d ≥ db (the involute starts on the base circle)",
    )?;
    Ok((diameter_mm * diameter_mm - base_diameter_mm * base_diameter_mm).sqrt() / 2.0)
}

/// The roll length (mm) at roll angle `roll_deg`: rb·ξ.
pub fn roll_length_from_roll_angle(roll_deg: f64, base_diameter_mm: f64) -> f64 {
    base_diameter_mm / 2.0 * roll_deg.to_radians()
}

/// The profile evaluation range Lα: from the roll length `start_mm` (root
/// side) to `end_mm` (tip side).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EvaluationRange {
    /// Start of Lα, roll length mm (root side).
    pub start_mm: f64,
    /// End of Lα, roll length mm (tip side).
    pub end_mm: f64,
}

/// The profile deviations of one flank.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfileDeviations {
    /// Total profile deviation Fα, µm.
    pub total_um: f64,
    /// Profile slope deviation fHα, µm, signed (+: more material at the tip).
    pub slope_um: f64,
    /// Profile form deviation ffα, µm.
    pub form_um: f64,
}

impl From<FlankDeviations> for ProfileDeviations {
    fn from(d: FlankDeviations) -> Self {
        ProfileDeviations {
            total_um: d.total_um,
            slope_um: d.slope_um,
            form_um: d.form_um,
        }
    }
}

/// Evaluates a profile trace: deviations `deviation_um` (+material) at
/// roll lengths `roll_length_mm`, over `range`.
pub fn evaluate_profile(
    roll_length_mm: &[f64],
    deviation_um: &[f64],
    range: EvaluationRange,
) -> Result<ProfileDeviations, Error> {
    evaluate(roll_length_mm, deviation_um, range.start_mm, range.end_mm).map(Into::into)
}
