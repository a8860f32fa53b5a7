//! Helix traces: the deviation of a flank along the face width, at a
//! constant diameter (usually the reference circle), evaluated over the
//! helix evaluation range Lβ ([`crate::trace`] for the definitions of Fβ,
//! fHβ and ffβ).
//!
//! The abscissa is the axial position z (mm) from the reference face into
//! the gear. fHβ is the mean helix line's rise from the start of Lβ to its
//! end, in the direction of increasing z.
//!
//! Whether a positive fHβ means a larger or a smaller helix angle depends
//! on the flank and the hand ([`helix_angle_sign`]). Derivation (the
//! coordinates of docs/measurement.md): the axis z runs from the reference
//! face into the gear, the angle θ counter-clockwise seen from +z. A
//! right-hand helix turns +θ as z grows: its flank lies at
//! θ(z) = θ0 + z·tan βb / rb (left hand: −). A material deviation e moves a
//! flank along its normal, which turns it by e/rb towards the space it
//! faces: +θ for the flank facing +θ, which seen from the reference face
//! with the tip up is the right flank (n = +1), −θ for the left flank
//! (n = −1). The measured flank is then at θ0 + (h·z·tan βb + n·e(z))/rb
//! with h = +1 for right hand, −1 for left, and its helix is steeper than
//! the design when h·n·de/dz > 0.

use crate::trace::{evaluate, FlankDeviations};
use crate::Error;
use serde::{Deserialize, Serialize};

/// The flank of a tooth, seen from the reference face with the tooth tip
/// up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Flank {
    /// The flank on the right (facing +θ in the crate's coordinates).
    Right,
    /// The flank on the left (facing −θ).
    Left,
}

/// The hand of a helical gear.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Hand {
    /// Right hand: the helix turns like a right-hand screw.
    Right,
    /// Left hand.
    Left,
}

/// +1 when a positive helix slope deviation fHβ on `flank` of a gear of
/// `hand` means a helix angle larger (in magnitude) than the design, −1
/// when it means a smaller one: h·n in the derivation above.
pub fn helix_angle_sign(flank: Flank, hand: Hand) -> f64 {
    let n = match flank {
        Flank::Right => 1.0,
        Flank::Left => -1.0,
    };
    let h = match hand {
        Hand::Right => 1.0,
        Hand::Left => -1.0,
    };
    h * n
}

/// The helix evaluation range Lβ, axial positions mm from the reference
/// face.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EvaluationRange {
    /// Start of Lβ, mm (nearer the reference face).
    pub start_mm: f64,
    /// End of Lβ, mm.
    pub end_mm: f64,
}

impl EvaluationRange {
    /// The usual range: the face width less, at each end, the smaller of
    /// 5 % of it and one module (ISO 1328-1:2013 takes this as the default
    /// when the drawing gives none; see docs/measurement.md).
    pub fn default_for(face_width_mm: f64, normal_module_mm: f64) -> Self {
        let cut = (0.05 * face_width_mm).min(normal_module_mm);
        EvaluationRange {
            start_mm: cut,
            end_mm: face_width_mm - cut,
        }
    }
}

/// The helix deviations of one flank.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HelixDeviations {
    /// Total helix deviation Fβ, µm.
    pub total_um: f64,
    /// Helix slope deviation fHβ, µm, signed: the rise towards +z.
    pub slope_um: f64,
    /// Helix form deviation ffβ, µm.
    pub form_um: f64,
}

impl From<FlankDeviations> for HelixDeviations {
    fn from(d: FlankDeviations) -> Self {
        HelixDeviations {
            total_um: d.total_um,
            slope_um: d.slope_um,
            form_um: d.form_um,
        }
    }
}

/// Evaluates a helix trace: deviations `deviation_um` (+material) at axial
/// positions `axial_mm`, over `range`.
pub fn evaluate_helix(
    axial_mm: &[f64],
    deviation_um: &[f64],
    range: EvaluationRange,
) -> Result<HelixDeviations, Error> {
    evaluate(axial_mm, deviation_um, range.start_mm, range.end_mm).map(Into::into)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flank built at a helix angle 0.05° steeper than the design, its
    /// material deviation taken as the distance (µm, along the base
    /// tangent) by which it lies further into the space it faces: the
    /// slope's sign times `helix_angle_sign` must say "steeper".
    #[test]
    fn a_steeper_helix_reads_as_steeper_on_every_flank_and_hand() {
        let (rb, beta_b) = (40.0_f64, 15.0_f64.to_radians());
        let steeper = beta_b + 0.05_f64.to_radians();
        let z: Vec<f64> = (0..=40).map(|i| f64::from(i) * 0.5).collect();
        for hand in [Hand::Right, Hand::Left] {
            let h = if hand == Hand::Right { 1.0 } else { -1.0 };
            for flank in [Flank::Right, Flank::Left] {
                // The flank facing +θ is the right flank.
                let faces = if flank == Flank::Right { 1.0 } else { -1.0 };
                let e: Vec<f64> = z
                    .iter()
                    .map(|z| {
                        let design = h * z * beta_b.tan() / rb;
                        let actual = h * z * steeper.tan() / rb;
                        faces * rb * (actual - design) * 1000.0
                    })
                    .collect();
                let range = EvaluationRange {
                    start_mm: 0.0,
                    end_mm: 20.0,
                };
                let d = evaluate_helix(&z, &e, range).unwrap();
                assert!(d.slope_um.abs() > 1.0, "{d:?}");
                assert!(
                    d.slope_um * helix_angle_sign(flank, hand) > 0.0,
                    "{hand:?} {flank:?}"
                );
            }
        }
        let r = EvaluationRange::default_for(40.0, 3.0);
        assert_eq!((r.start_mm, r.end_mm), (2.0, 38.0));
    }
}
