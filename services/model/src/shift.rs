//! Hob shifting (docs/reference.md#hob-shifting; the patent's shift start, end, per step and
//! parts per step): which section of the hob cuts which part and which cut,
//! inside the usable hob length.
//!
//! The hob engages the blank over its *active length*, taken as
//! La = 2·h·cot α0 + px0 (the generating zone of a rack of depth h on both
//! flanks, plus one axial pitch px0 = π·mn0 / cos γ0). Shift positions are
//! measured along the hob axis from the hob centre; a position p uses the hob
//! from p − La/2 to p + La/2, so the usable positions are
//! |p| ≤ (U − La)/2, with U the usable length the tool library gives (the
//! part of the hob whose teeth may cut, centred; the overall length for a hob
//! given inline).

use std::f64::consts::PI;

use gearcam_proto::{HobData, PartShift, ShiftMode, ShiftPlan, ShiftSpec};

/// At most this many runs of parts are listed in a [`ShiftPlan`]; the pattern
/// repeats with the number of positions, so longer lists say nothing new.
pub const MAX_LISTED_RUNS: usize = 1000;

/// Axial pitch of the hob px0 = π·mn0 / cos γ0, mm.
pub fn hob_axial_pitch_mm(hob: &HobData) -> f64 {
    PI * hob.module_mm / hob.lead_angle_deg.to_radians().cos()
}

/// Active length of the hob at depth h, La = 2·h·cot α0 + px0, mm.
pub fn active_length_mm(hob: &HobData, depth_mm: f64) -> f64 {
    2.0 * depth_mm / hob.pressure_angle_deg.to_radians().tan() + hob_axial_pitch_mm(hob)
}

/// Usable shift range [−u, u] with u = (U − La)/2, mm, U the hob's usable
/// length ([`HobData::usable_mm`]); u < 0 means the hob is too short to shift
/// at all.
pub fn usable_range_mm(hob: &HobData, depth_mm: f64) -> [f64; 2] {
    let u = (hob.usable_mm() - active_length_mm(hob, depth_mm)) / 2.0;
    [-u, u]
}

/// The resolved shift settings before the per-part list: start, end, step,
/// parts per step, with the defaults filled in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolved {
    /// Per part or per cut.
    pub mode: ShiftMode,
    /// First position, mm.
    pub start_mm: f64,
    /// Last position, mm.
    pub end_mm: f64,
    /// Shift per step (positive), mm.
    pub step_mm: f64,
    /// Parts per step.
    pub parts_per_step: u32,
    /// Usable range, mm.
    pub usable_mm: [f64; 2],
    /// Active length, mm.
    pub active_length_mm: f64,
}

impl Resolved {
    /// Fills the defaults: start and end at the ends of the usable range, one
    /// axial pitch per step, one part per step.
    pub fn new(spec: &ShiftSpec, hob: &HobData, depth_mm: f64) -> Resolved {
        let usable = usable_range_mm(hob, depth_mm);
        Resolved {
            mode: spec.mode,
            start_mm: spec.start_mm.unwrap_or(usable[0]),
            end_mm: spec.end_mm.unwrap_or(usable[1]),
            step_mm: spec.step_mm.unwrap_or_else(|| hob_axial_pitch_mm(hob)),
            parts_per_step: spec.parts_per_step.unwrap_or(1),
            usable_mm: usable,
            active_length_mm: active_length_mm(hob, depth_mm),
        }
    }

    /// Number of distinct positions from start to end in steps of `step_mm`.
    pub fn positions(&self) -> u32 {
        let span = (self.end_mm - self.start_mm).abs();
        let n = (span / self.step_mm + 1e-9).floor() + 1.0;
        if n.is_finite() && n >= 1.0 {
            n.min(f64::from(u32::MAX)) as u32
        } else {
            1
        }
    }

    /// The k-th step's position, cycling back to the start after the end.
    pub fn position_mm(&self, k: u64) -> f64 {
        let n = u64::from(self.positions());
        let dir = if self.end_mm >= self.start_mm {
            1.0
        } else {
            -1.0
        };
        self.start_mm + dir * (k % n) as f64 * self.step_mm
    }

    /// Shift of cut `cut` (0-based) of part `part` (0-based) when each part
    /// has `cuts` cuts: per part, all cuts of a part share the part's step;
    /// per cut, every cut moves on by one step.
    pub fn shift_mm(&self, part: u64, cut: u64, cuts: u64) -> f64 {
        let step = part / u64::from(self.parts_per_step.max(1));
        match self.mode {
            ShiftMode::Part => self.position_mm(step),
            ShiftMode::Cut => self.position_mm(step * cuts.max(1) + cut),
        }
    }

    /// The plan: the settings and the first cut's position for each run of
    /// `parts_per_step` parts of the quantity (at most [`MAX_LISTED_RUNS`]).
    pub fn plan(&self, quantity: u32, cuts: u32) -> ShiftPlan {
        let pps = self.parts_per_step.max(1);
        let mut parts = Vec::new();
        let mut from = 1u32;
        while from <= quantity && parts.len() < MAX_LISTED_RUNS {
            let to = from.saturating_add(pps - 1).min(quantity);
            parts.push(PartShift {
                from_part: from,
                to_part: to,
                shift_mm: self.shift_mm(u64::from(from - 1), 0, u64::from(cuts)),
            });
            if to == u32::MAX {
                break;
            }
            from = to + 1;
        }
        ShiftPlan {
            mode: self.mode,
            usable_mm: self.usable_mm,
            active_length_mm: self.active_length_mm,
            start_mm: self.start_mm,
            end_mm: self.end_mm,
            step_mm: self.step_mm,
            parts_per_step: pps,
            positions: self.positions(),
            parts,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use gearcam_proto::{Hand, Source};

    fn hob() -> HobData {
        HobData {
            id: "H".into(),
            starts: 1,
            od_mm: 80.0,
            module_mm: 3.0,
            pressure_angle_deg: 20.0,
            lead_angle_deg: 2.3716,
            hand: Hand::Right,
            length_mm: 100.0,
            usable_length_mm: None,
            source: Source::Library,
        }
    }

    #[test]
    fn usable_range_is_the_hob_length_minus_the_active_length() {
        // La = 2·6.75·cot 20° + π·3/cos 2.3716° = 37.0909 + 9.4329 (closed form).
        let la = 2.0 * 6.75 / 20f64.to_radians().tan() + PI * 3.0 / 2.3716f64.to_radians().cos();
        assert_relative_eq!(active_length_mm(&hob(), 6.75), la, epsilon = 1e-12);
        let [lo, hi] = usable_range_mm(&hob(), 6.75);
        assert_relative_eq!(hi, (100.0 - la) / 2.0, epsilon = 1e-12);
        assert_relative_eq!(lo, -hi, epsilon = 1e-12);
    }

    #[test]
    fn per_part_shifting_steps_every_parts_per_step_and_wraps() {
        let spec = ShiftSpec {
            mode: ShiftMode::Part,
            start_mm: Some(-20.0),
            end_mm: Some(20.0),
            step_mm: Some(10.0),
            parts_per_step: Some(2),
        };
        let r = Resolved::new(&spec, &hob(), 6.75);
        assert_eq!(r.positions(), 5);
        let shifts: Vec<f64> = (0..12).map(|p| r.shift_mm(p, 0, 1)).collect();
        assert_eq!(
            shifts,
            vec![-20.0, -20.0, -10.0, -10.0, 0.0, 0.0, 10.0, 10.0, 20.0, 20.0, -20.0, -20.0]
        );
        let plan = r.plan(5, 1);
        assert_eq!(plan.parts.len(), 3);
        assert_eq!(
            plan.parts[2],
            PartShift {
                from_part: 5,
                to_part: 5,
                shift_mm: 0.0
            }
        );
    }

    #[test]
    fn per_cut_shifting_moves_every_cut() {
        let spec = ShiftSpec {
            mode: ShiftMode::Cut,
            start_mm: Some(10.0),
            end_mm: Some(-10.0),
            step_mm: Some(5.0),
            parts_per_step: None,
        };
        let r = Resolved::new(&spec, &hob(), 6.75);
        // Start above end: the positions run downwards, 10, 5, 0, −5, −10.
        assert_eq!(r.positions(), 5);
        assert_eq!(r.shift_mm(0, 0, 2), 10.0);
        assert_eq!(r.shift_mm(0, 1, 2), 5.0);
        assert_eq!(r.shift_mm(1, 0, 2), 0.0);
        assert_eq!(r.shift_mm(1, 1, 2), -5.0);
        assert_eq!(r.shift_mm(2, 0, 2), -10.0);
        // The sixth position wraps back to the start.
        assert_eq!(r.shift_mm(2, 1, 2), 10.0);
        assert_eq!(r.shift_mm(3, 0, 2), 5.0);
    }

    #[test]
    fn defaults_span_the_usable_range_in_axial_pitches() {
        let r = Resolved::new(&ShiftSpec::default(), &hob(), 6.75);
        let [lo, hi] = usable_range_mm(&hob(), 6.75);
        assert_eq!((r.start_mm, r.end_mm), (lo, hi));
        assert_relative_eq!(r.step_mm, hob_axial_pitch_mm(&hob()), epsilon = 1e-12);
        assert_eq!(r.parts_per_step, 1);
        for k in 0..50 {
            let p = r.position_mm(k);
            assert!(p >= lo - 1e-9 && p <= hi + 1e-9, "{p}");
        }
    }
}
