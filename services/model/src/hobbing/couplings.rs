//! The signs and ratios of the set-up in the machine-neutral frame: the hands,
//! the swivel η, the table's sense, the indexing ratio and the shift
//! compensation (docs/hobbing.md).

use super::*;

/// True when gear helix and hob thread have the same hand. A spur gear (or a
/// gear without a hand, which validation only allows for spur gears) takes the
/// same-hand branch.
pub fn same_hand(gear: &GearSpec, hob: &HobData) -> bool {
    match gear.helix_hand {
        Some(hand) if !is_spur(gear) => hand == hob.hand,
        _ => true,
    }
}

/// The signed setting angle η = s_g·β − s_h·γ0 of the hob axis in the
/// machine-neutral frame, degrees ([`crate::frame`]; `docs/hobbing.md`).
///
/// The patent prints γ = −(|β| ∓ |γ0|): the magnitude of η with one machine's
/// sign, which gives mirror-image set-ups (left-hand gear and hob, or a spur
/// gear cut with a left-hand hob) the same swivel as the right-hand ones.
pub fn swivel_deg(gear: &GearSpec, hob: &HobData) -> f64 {
    frame::setting_angle_deg(gear, hob)
}

/// Sign of the differential speed in the table-speed magnitude
/// Nw = Ni/(1 − s·fa/Pz) (patent formula ③, speeds as magnitudes):
/// conventional cut with same hands +1, with opposite hands −1; a climb cut
/// reverses both. It never enters a signed coupling factor: the differential
/// coupling C per Z is the gear's alone ([`frame::differential_deg_per_mm`]).
pub fn table_speed_sign(gear: &GearSpec, hob: &HobData, mode: CutMode) -> f64 {
    let same = same_hand(gear, hob);
    match (mode, same) {
        (CutMode::Conventional, true) | (CutMode::Climb, false) => 1.0,
        (CutMode::Conventional, false) | (CutMode::Climb, true) => -1.0,
    }
}

/// The indexing ratio s_h·z0 : z in the machine-neutral frame, reduced and
/// kept as exact integers ([`frame::indexing`]).
pub fn coupling(hob: &HobData, teeth: u32) -> Ratio {
    frame::indexing(hob, teeth)
}

/// Shift compensation C per Y = −360·cos γ0/(π·mn0·z) degrees of table per
/// mm of hob shift along the hob axis, in the machine-neutral frame
/// ([`frame::shift_compensation_deg_per_mm`]): a shift by one axial pitch
/// π·mn0/cos γ0 turns the table by one gear pitch, 360°/z, for either hand.
pub fn shift_compensation_deg_per_mm(hob: &HobData, teeth: u32) -> f64 {
    frame::shift_compensation_deg_per_mm(hob, teeth)
}
