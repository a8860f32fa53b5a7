//! Hob matching (docs/knowledge.md#case-based-reasoning): pick the library hob that can cut the gear, and
//! say why it was chosen and why every other hob was not.
//!
//! Pure functions on the tool library's records ([`HobRecord`]). A hob fits when
//!
//! 1. its normal base pitch equals the gear's: `mn0·cos α0 = mn·cos αn` within
//!    1e-4 mm (docs/reference.md#check-3-base-pitch);
//! 2. the machine takes it: `da0 ≤ max_hob_od_mm`;
//! 3. its accuracy class fits the grade: AA for grade ≤ 7, A for 8, B for 9,
//!    C for 10 and coarser (the usual hob-maker guidance relating DIN 3968
//!    hob classes to the gear grade; a better class always fits);
//! 4. its hand gives a swivel the machine can reach: `|γ| = |β| − γ0` for the
//!    gear's hand, `|β| + γ0` for the opposite hand, `|γ| ≤ max_swivel_deg`;
//! 5. its remaining usable length covers the job's shift plan:
//!    `shift_position + working zone + ⌈quantity / parts_per_shift⌉·shift_step
//!    ≤ usable_length`, where the working zone is the hob length in contact,
//!    `2·√(h·(da0 − h))` with the whole depth `h = 2.25·mn`; and its remaining
//!    life covers the quantity.
//!
//! Among fitting hobs: the gear's hand first (a right-hand hob for a spur
//! gear), then the class closest to the one needed (an AA hob is not spent on
//! grade-9 work when a B hob fits), then fewer starts (better accuracy), then
//! the most remaining life, then the id.

use gearcam_proto::plan::{HobChoice, HobRejection};
use gearcam_proto::Hand;

use crate::records::HobRecord;

/// Normal base pitch tolerance, mm (docs/reference.md#check-3-base-pitch).
pub const BASE_PITCH_TOL_MM: f64 = 1e-4;

/// What the gear and job ask of the hob.
#[derive(Debug, Clone, PartialEq)]
pub struct Need {
    /// Normal module mn, mm.
    pub module_mm: f64,
    /// Normal pressure angle αn, degrees.
    pub pressure_angle_deg: f64,
    /// Helix angle magnitude, degrees.
    pub helix_angle_deg: f64,
    /// Helix hand (None for spur gears).
    pub helix_hand: Option<Hand>,
    /// Accuracy grade.
    pub quality_grade: u8,
    /// Parts to cut.
    pub quantity: u32,
    /// Machine: largest hob OD, mm.
    pub max_hob_od_mm: f64,
    /// Machine: largest swivel, degrees.
    pub max_swivel_deg: f64,
}

/// The class needed for a grade, as a rank (0 = AA … 3 = C).
pub fn required_class(grade: u8) -> usize {
    match grade {
        0..=7 => 0,
        8 => 1,
        9 => 2,
        _ => 3,
    }
}

const CLASSES: [&str; 4] = ["AA", "A", "B", "C"];

fn class_rank(c: &str) -> Option<usize> {
    CLASSES.iter().position(|x| *x == c)
}

/// Shift length a job of `quantity` parts uses on a hob, mm.
pub fn shift_needed_mm(h: &HobRecord, quantity: u32) -> f64 {
    let steps = quantity.div_ceil(h.parts_per_shift.max(1));
    f64::from(steps) * h.shift_step_mm
}

/// Length of the hob in contact with the gear, mm: `2·√(h·(da0 − h))`,
/// whole depth `h = 2.25·mn`.
pub fn working_zone_mm(h: &HobRecord) -> f64 {
    let depth = 2.25 * h.module_mm;
    2.0 * (depth * (h.od_mm - depth)).max(0.0).sqrt()
}

/// Why a hob cannot cut the job (empty when it can).
pub fn reasons(h: &HobRecord, n: &Need) -> Vec<String> {
    let mut out = Vec::new();
    let pb_gear = n.module_mm * n.pressure_angle_deg.to_radians().cos();
    let pb_hob = h.module_mm * h.pressure_angle_deg.to_radians().cos();
    if (pb_hob - pb_gear).abs() > BASE_PITCH_TOL_MM {
        out.push(format!(
            "normal base pitch mn0·cos α0 = {pb_hob:.4} mm ≠ gear {pb_gear:.4} mm (module {} at {}°)",
            h.module_mm, h.pressure_angle_deg
        ));
    }
    if h.od_mm > n.max_hob_od_mm {
        out.push(format!(
            "outside diameter {} mm > machine limit {} mm",
            h.od_mm, n.max_hob_od_mm
        ));
    }
    let need = required_class(n.quality_grade);
    match class_rank(&h.accuracy_class) {
        Some(r) if r <= need => {}
        Some(_) => out.push(format!(
            "accuracy class {} too coarse for grade {} (needs {} or better)",
            h.accuracy_class, n.quality_grade, CLASSES[need]
        )),
        None => out.push(format!(
            "accuracy class {:?} unknown (expected AA, A, B or C)",
            h.accuracy_class
        )),
    }
    let swivel = swivel_deg(h, n);
    if swivel > n.max_swivel_deg {
        out.push(format!(
            "{} hob on a {} gear needs a swivel of {swivel:.2}° > machine limit {}°",
            hand_str(h.hand),
            n.helix_hand.map(hand_str).unwrap_or("spur"),
            n.max_swivel_deg
        ));
    }
    let need_mm = shift_needed_mm(h, n.quantity);
    let zone = working_zone_mm(h);
    let left = h.usable_length_mm - h.shift_position_mm;
    if h.shift_position_mm + zone + need_mm > h.usable_length_mm {
        out.push(format!(
            "remaining usable length {left:.1} mm (usable {} − shift position {}) < working zone {zone:.1} + shift plan {need_mm:.1} mm for {} parts",
            h.usable_length_mm, h.shift_position_mm, n.quantity
        ));
    }
    if h.remaining_life_parts < u64::from(n.quantity) {
        out.push(format!(
            "remaining life {} parts < quantity {}",
            h.remaining_life_parts, n.quantity
        ));
    }
    out
}

fn hand_str(h: Hand) -> &'static str {
    match h {
        Hand::Right => "right-hand",
        Hand::Left => "left-hand",
    }
}

fn swivel_deg(h: &HobRecord, n: &Need) -> f64 {
    match n.helix_hand {
        Some(gh) if n.helix_angle_deg != 0.0 => {
            if gh == h.hand {
                (n.helix_angle_deg - h.lead_angle_deg).abs()
            } else {
                n.helix_angle_deg + h.lead_angle_deg
            }
        }
        _ => h.lead_angle_deg,
    }
}

/// Chooses a hob; `Err` carries the explanation with every rejection when
/// none fits.
pub fn choose(hobs: &[HobRecord], n: &Need) -> Result<(HobRecord, HobChoice), HobChoice> {
    let want = n.helix_hand.unwrap_or(Hand::Right);
    let need = required_class(n.quality_grade);
    let mut fit = Vec::new();
    let mut rejected = Vec::new();
    for h in hobs {
        let r = reasons(h, n);
        if r.is_empty() {
            fit.push(h);
        } else {
            rejected.push(HobRejection {
                id: h.id.clone(),
                reasons: r,
            });
        }
    }
    fit.sort_by(|a, b| {
        let key = |h: &HobRecord| {
            (
                h.hand != want,
                need - class_rank(&h.accuracy_class).unwrap_or(0).min(need),
                h.starts,
            )
        };
        key(a)
            .cmp(&key(b))
            .then(b.remaining_life_parts.cmp(&a.remaining_life_parts))
            .then(a.id.cmp(&b.id))
    });
    let Some(best) = fit.first() else {
        return Err(HobChoice {
            chosen: String::new(),
            reason: format!(
                "no library hob fits module {} at {}°, grade {}, {} parts",
                n.module_mm, n.pressure_angle_deg, n.quality_grade, n.quantity
            ),
            alternatives: vec![],
            rejected,
        });
    };
    let pb = best.module_mm * best.pressure_angle_deg.to_radians().cos();
    let need_mm = shift_needed_mm(best, n.quantity);
    let reason = format!(
        "{}: normal base pitch {pb:.4} mm equals the gear's; {} ({}); class {} fits grade {} (needs {}); \
         swivel {:.2}° within {}°; remaining usable length {:.1} mm covers working zone {:.1} + shift plan {need_mm:.1} mm; \
         remaining life {} ≥ {} parts",
        best.id,
        hand_str(best.hand),
        if best.hand == want {
            "the gear's hand"
        } else {
            "opposite hand: none of the gear's hand fits"
        },
        best.accuracy_class,
        n.quality_grade,
        CLASSES[need],
        swivel_deg(best, n),
        n.max_swivel_deg,
        best.usable_length_mm - best.shift_position_mm,
        working_zone_mm(best),
        best.remaining_life_parts,
        n.quantity
    );
    let alternatives = fit[1..].iter().map(|h| h.id.clone()).collect();
    Ok((
        (*best).clone(),
        HobChoice {
            chosen: best.id.clone(),
            reason,
            alternatives,
            rejected,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hob(id: &str, module: f64, hand: Hand, class: &str) -> HobRecord {
        HobRecord {
            id: id.into(),
            module_mm: module,
            pressure_angle_deg: 20.0,
            starts: 1,
            hand,
            lead_angle_deg: 2.37,
            od_mm: 80.0,
            length_mm: 100.0,
            usable_length_mm: 90.0,
            accuracy_class: class.into(),
            material: "HSS".into(),
            coating: "TiN".into(),
            shift_position_mm: 0.0,
            shift_step_mm: 0.5,
            parts_per_shift: 2,
            remaining_life_parts: 400,
            source: "test".into(),
        }
    }

    fn need(grade: u8, hand: Option<Hand>, quantity: u32) -> Need {
        Need {
            module_mm: 3.0,
            pressure_angle_deg: 20.0,
            helix_angle_deg: if hand.is_some() { 15.0 } else { 0.0 },
            helix_hand: hand,
            quality_grade: grade,
            quantity,
            max_hob_od_mm: 130.0,
            max_swivel_deg: 45.0,
        }
    }

    #[test]
    fn picks_the_gears_hand_and_explains_every_rejection() {
        let hobs = [
            hob("M2", 2.0, Hand::Right, "AA"),
            hob("M3R", 3.0, Hand::Right, "AA"),
            hob("M3L", 3.0, Hand::Left, "AA"),
            hob("M3B", 3.0, Hand::Left, "B"),
        ];
        let (h, why) = choose(&hobs, &need(7, Some(Hand::Left), 20)).unwrap();
        assert_eq!(h.id, "M3L");
        assert_eq!(why.alternatives, ["M3R"]);
        let rej: Vec<&str> = why.rejected.iter().map(|r| r.id.as_str()).collect();
        assert_eq!(rej, ["M2", "M3B"]);
        assert!(why.rejected[0].reasons[0].contains("base pitch"));
        assert!(why.rejected[1].reasons[0].contains("class B too coarse for grade 7"));
    }

    #[test]
    fn a_coarser_grade_spends_the_closest_class_not_the_best() {
        let hobs = [
            hob("AA", 3.0, Hand::Right, "AA"),
            hob("B", 3.0, Hand::Right, "B"),
        ];
        let (h, _) = choose(&hobs, &need(9, None, 1)).unwrap();
        assert_eq!(h.id, "B");
    }

    #[test]
    fn the_shift_plan_must_fit_the_remaining_usable_length() {
        // Working zone 2·√(6.75·73.25) = 44.47 mm; 20 parts at 2 per 0.5 mm step = 5 mm.
        let mut h = hob("H", 3.0, Hand::Right, "AA");
        approx::assert_abs_diff_eq!(working_zone_mm(&h), 2.0 * (6.75f64 * 73.25).sqrt());
        h.shift_position_mm = 90.0 - 44.47 - 5.0 + 0.01; // just short
        assert!(reasons(&h, &need(7, None, 20))[0].contains("shift plan 5.0 mm"));
        h.shift_position_mm -= 0.02;
        assert!(reasons(&h, &need(7, None, 20)).is_empty());
        h.remaining_life_parts = 19;
        assert!(reasons(&h, &need(7, None, 20))[0].contains("remaining life 19"));
        let err = choose(&[h], &need(7, None, 20)).unwrap_err();
        assert_eq!(err.rejected.len(), 1);
    }
}
