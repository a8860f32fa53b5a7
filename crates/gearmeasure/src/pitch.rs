//! Pitch deviations of one flank (left and right flanks are evaluated
//! separately), and the runout.
//!
//! The machine probes the same flank of every tooth, in order, at the
//! measuring circle and records each flank's position as a deviation from
//! its nominal position (µm of arc on that circle, +: the flank is further
//! along the direction of measurement; the zero is arbitrary). With
//! P0, …, P(z−1) these positions:
//!
//! - the individual single pitch deviation of pitch i, from tooth i−1 to
//!   tooth i, is fpi = Pi − P(i−1), the pitch from the last tooth back to
//!   the first closing the circle (so Σ fpi = 0);
//! - the single pitch deviation is fp = max |fpi|;
//! - the individual cumulative pitch deviation of tooth i, relative to
//!   tooth 0, is Fpi = fp1 + … + fpi = Pi − P0;
//! - the total cumulative pitch deviation Fp is the largest algebraic
//!   difference between the Fpi of any two teeth: max Fpi − min Fpi, which
//!   is also the largest |sum of consecutive fpi| over any sector.
//!
//! A machine that reports angles instead gives positions through
//! [`positions_from_angles`]; one that reports the pitches themselves
//! through [`positions_from_pitches`].
//!
//! Runout Fr: a ball (or the probe) is put in every tooth space, touching
//! both flanks, and its radial position recorded; Fr is the difference
//! between the largest and the smallest ([`runout_um`]).

use crate::Error;
use serde::{Deserialize, Serialize};

/// The pitch deviations of one flank.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PitchDeviations {
    /// fpi, µm: element i is the pitch from tooth i−1 to tooth i (element 0
    /// the pitch from the last tooth to tooth 0).
    pub single_um: Vec<f64>,
    /// Fpi, µm: element i is tooth i's cumulative deviation from tooth 0.
    pub cumulative_um: Vec<f64>,
    /// Single pitch deviation fp = max |fpi|, µm.
    pub single_max_um: f64,
    /// Total cumulative pitch deviation Fp = max Fpi − min Fpi, µm.
    pub cumulative_total_um: f64,
}

/// Both flanks' pitch deviations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlankPair {
    /// The left flanks.
    pub left: PitchDeviations,
    /// The right flanks.
    pub right: PitchDeviations,
}

/// Evaluates the flank positions `position_um` (one per tooth, in order
/// round the gear, at least 3 teeth).
pub fn evaluate_pitch(position_um: &[f64]) -> Result<PitchDeviations, Error> {
    let z = position_um.len();
    if z < 3 {
        return Err(Error::TooFewSamples {
            what: "teeth",
            needed: 3,
            got: z,
        });
    }
    if let Some(bad) = position_um.iter().find(|v| !v.is_finite()) {
        return Err(Error::OutOfRange {
            field: "position_um",
            expected: "finite positions",
            got: *bad,
        });
    }
    let single_um: Vec<f64> = (0..z)
        .map(|i| position_um[i] - position_um[(i + z - 1) % z])
        .collect();
    let cumulative_um: Vec<f64> = position_um.iter().map(|p| p - position_um[0]).collect();
    let single_max_um = single_um.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    let (lo, hi) = cumulative_um
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), f| {
            (a.min(*f), b.max(*f))
        });
    Ok(PitchDeviations {
        single_um,
        cumulative_um,
        single_max_um,
        cumulative_total_um: hi - lo,
    })
}

/// Evaluates both flanks.
pub fn evaluate_flanks(left_um: &[f64], right_um: &[f64]) -> Result<FlankPair, Error> {
    if left_um.len() != right_um.len() {
        return Err(Error::TooFewSamples {
            what: "right-flank positions for as many left-flank positions",
            needed: left_um.len(),
            got: right_um.len(),
        });
    }
    Ok(FlankPair {
        left: evaluate_pitch(left_um)?,
        right: evaluate_pitch(right_um)?,
    })
}

/// Flank positions (µm of arc) from measured flank angles (degrees, one per
/// tooth, in order, any zero) on a measuring circle of diameter
/// `measuring_diameter_mm`: tooth i's nominal angle is i·360°/z, and its
/// deviation (angle − nominal − the first tooth's) times the radius.
pub fn positions_from_angles(angle_deg: &[f64], measuring_diameter_mm: f64) -> Vec<f64> {
    let z = angle_deg.len() as f64;
    let r_um = measuring_diameter_mm / 2.0 * 1000.0;
    angle_deg
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let mut dev = a - angle_deg[0] - 360.0 * i as f64 / z;
            // Angles may be given modulo 360°.
            dev -= 360.0 * (dev / 360.0).round();
            dev.to_radians() * r_um
        })
        .collect()
}

/// Flank positions from measured single pitch deviations (µm, element i the
/// pitch from tooth i−1 to tooth i, element 0 closing the circle): their
/// mean is taken off first, since the z pitches of a real gear close the
/// circle and sum to zero (a non-zero sum is a scale error of the
/// instrument), then position i = fp1 + … + fpi.
pub fn positions_from_pitches(single_um: &[f64]) -> Vec<f64> {
    let mean = single_um.iter().sum::<f64>() / single_um.len().max(1) as f64;
    let mut at = 0.0;
    let mut out = Vec::with_capacity(single_um.len());
    for (i, f) in single_um.iter().enumerate() {
        if i > 0 {
            at += f - mean;
        }
        out.push(at);
    }
    out
}

/// Runout Fr, µm: the range of the radial positions `radial_um` of a ball
/// or probe in each tooth space (at least 3 spaces).
pub fn runout_um(radial_um: &[f64]) -> Result<f64, Error> {
    if radial_um.len() < 3 {
        return Err(Error::TooFewSamples {
            what: "tooth spaces",
            needed: 3,
            got: radial_um.len(),
        });
    }
    if let Some(bad) = radial_um.iter().find(|v| !v.is_finite()) {
        return Err(Error::OutOfRange {
            field: "radial_um",
            expected: "finite radial positions",
            got: *bad,
        });
    }
    let (lo, hi) = radial_um
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(*r), b.max(*r))
        });
    Ok(hi - lo)
}

#[cfg(test)]
mod tests;
