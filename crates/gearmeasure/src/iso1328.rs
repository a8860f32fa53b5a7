//! ISO 1328-1:2013 flank tolerance classes: the tolerance of each measured
//! item for a gear and a class, and the best class a measured deviation
//! meets.
//!
//! The tolerances of class 5 (µm; `d` reference diameter, `mn` normal
//! module, `b` face width, all mm) are, by the standard's formulas (5) to
//! (12) and the runout annex:
//!
//! ```text
//! fpT  = 0.001·d + 0.4·mn + 5                    single pitch
//! FpT  = 0.002·d + 0.55·√d + 0.7·mn + 12         cumulative pitch (index)
//! fHαT = 0.4·mn + 0.001·d + 4                    profile slope (±)
//! ffαT = 0.55·mn + 5                             profile form
//! FαT  = √(fHαT² + ffαT²)                        total profile
//! fHβT = 0.05·√d + 0.35·√b + 4                   helix slope (±)
//! ffβT = 0.07·√d + 0.45·√b + 4                   helix form
//! FβT  = √(fHβT² + ffβT²)                        total helix
//! FrT  = 0.9·FpT                                 runout
//! ```
//!
//! Class A multiplies the class-5 value by √2^(A−5) (the step factor √2
//! between consecutive classes); the totals are formed from the unrounded
//! slope and form tolerances; the result is then rounded ([`round_um`]):
//! above 10 µm to the integer micrometre, from 5 to 10 µm to 0.5 µm, below
//! 5 µm to 0.1 µm. The formulas hold only within the scope the standard
//! states (5 ≤ z ≤ 1000, 5 ≤ d ≤ 15 000 mm, 0.5 ≤ mn ≤ 70 mm,
//! 4 ≤ b ≤ 1200 mm, β ≤ 45°) and are not to be extrapolated: outside it
//! [`GearData::new`] refuses. Sources and what was verified:
//! docs/measurement.md.

use crate::{check_range, Error};
use serde::{Deserialize, Serialize};

/// The design data the tolerances depend on, validated against the
/// standard's scope.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GearData {
    /// Reference diameter d = z·mn / cos β, mm.
    pub reference_diameter_mm: f64,
    /// Normal module mn, mm.
    pub normal_module_mm: f64,
    /// Face width b (axial), mm.
    pub face_width_mm: f64,
    /// Number of teeth z.
    pub teeth: u32,
    /// Helix angle β at the reference circle, degrees (sign = hand; only
    /// its magnitude matters here).
    pub helix_deg: f64,
}

impl GearData {
    /// The gear, or the first field outside the standard's scope (its
    /// name, the range, the value).
    pub fn new(
        teeth: u32,
        normal_module_mm: f64,
        helix_deg: f64,
        face_width_mm: f64,
    ) -> Result<Self, Error> {
        check_range("teeth", f64::from(teeth), 5.0, 1000.0, "5 ≤ z ≤ 1000")?;
        check_range(
            "normal_module_mm",
            normal_module_mm,
            0.5,
            70.0,
            "0.5 mm ≤ mn ≤ 70 mm",
        )?;
        check_range("helix_deg", helix_deg.abs(), 0.0, 45.0, "|β| ≤ 45°")
            .map_err(|_| out("helix_deg", "|β| ≤ 45°", helix_deg))?;
        check_range(
            "face_width_mm",
            face_width_mm,
            4.0,
            1200.0,
            "4 mm ≤ b ≤ 1200 mm",
        )?;
        let d = f64::from(teeth) * normal_module_mm / helix_deg.to_radians().cos();
        check_range(
            "reference_diameter_mm",
            d,
            5.0,
            15_000.0,
            "5 mm ≤ d ≤ 15 000 mm",
        )?;
        Ok(GearData {
            reference_diameter_mm: d,
            normal_module_mm,
            face_width_mm,
            teeth,
            helix_deg,
        })
    }
}

fn out(field: &'static str, expected: &'static str, got: f64) -> Error {
    Error::OutOfRange {
        field,
        expected,
        got,
    }
}

/// A flank tolerance class, 1 (finest) to 11 (coarsest).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Class(u8);

impl Class {
    /// The finest class, 1.
    pub const FINEST: Class = Class(1);
    /// The coarsest class, 11.
    pub const COARSEST: Class = Class(11);

    /// The class `a`, or an error when it is not 1 to 11.
    pub fn new(a: u8) -> Result<Class, Error> {
        if (1..=11).contains(&a) {
            Ok(Class(a))
        } else {
            Err(out("class", "1 ≤ A ≤ 11", f64::from(a)))
        }
    }

    /// Its number A.
    pub fn number(self) -> u8 {
        self.0
    }

    /// The factor √2^(A−5) that takes a class-5 tolerance to this class.
    pub fn step_factor(self) -> f64 {
        std::f64::consts::SQRT_2.powi(i32::from(self.0) - 5)
    }

    /// All eleven classes, finest first.
    pub fn all() -> impl Iterator<Item = Class> {
        (1..=11).map(Class)
    }
}

/// A measured item with a tolerance in ISO 1328-1:2013.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Item {
    /// Single pitch deviation fp (largest |fpi|), tolerance fpT.
    SinglePitch,
    /// Total cumulative pitch (index) deviation Fp, tolerance FpT.
    CumulativePitch,
    /// Profile slope deviation fHα (±), tolerance fHαT.
    ProfileSlope,
    /// Profile form deviation ffα, tolerance ffαT.
    ProfileForm,
    /// Total profile deviation Fα, tolerance FαT.
    ProfileTotal,
    /// Helix slope deviation fHβ (±), tolerance fHβT.
    HelixSlope,
    /// Helix form deviation ffβ, tolerance ffβT.
    HelixForm,
    /// Total helix deviation Fβ, tolerance FβT.
    HelixTotal,
    /// Runout Fr, tolerance FrT.
    Runout,
}

impl Item {
    /// Every item, in the order of the standard's formulas.
    pub const ALL: [Item; 9] = [
        Item::SinglePitch,
        Item::CumulativePitch,
        Item::ProfileSlope,
        Item::ProfileForm,
        Item::ProfileTotal,
        Item::HelixSlope,
        Item::HelixForm,
        Item::HelixTotal,
        Item::Runout,
    ];
}

/// The unrounded class-5 tolerance of `item`, µm (the formulas above).
pub fn class5_um(gear: &GearData, item: Item) -> f64 {
    let d = gear.reference_diameter_mm;
    let mn = gear.normal_module_mm;
    let b = gear.face_width_mm;
    let fpt = 0.001 * d + 0.4 * mn + 5.0;
    let fpt_cum = 0.002 * d + 0.55 * d.sqrt() + 0.7 * mn + 12.0;
    let fha = 0.4 * mn + 0.001 * d + 4.0;
    let ffa = 0.55 * mn + 5.0;
    let fhb = 0.05 * d.sqrt() + 0.35 * b.sqrt() + 4.0;
    let ffb = 0.07 * d.sqrt() + 0.45 * b.sqrt() + 4.0;
    match item {
        Item::SinglePitch => fpt,
        Item::CumulativePitch => fpt_cum,
        Item::ProfileSlope => fha,
        Item::ProfileForm => ffa,
        Item::ProfileTotal => fha.hypot(ffa),
        Item::HelixSlope => fhb,
        Item::HelixForm => ffb,
        Item::HelixTotal => fhb.hypot(ffb),
        Item::Runout => 0.9 * fpt_cum,
    }
}

/// The unrounded tolerance of `item` in `class`, µm: the class-5 value
/// times √2^(A−5). The totals are the root sum of squares of the
/// unrounded slope and form tolerances, the same scaled either way.
pub fn unrounded_um(gear: &GearData, item: Item, class: Class) -> f64 {
    class5_um(gear, item) * class.step_factor()
}

/// The tolerance of `item` in `class`, µm, rounded by the standard's rule.
pub fn tolerance_um(gear: &GearData, item: Item, class: Class) -> f64 {
    round_um(unrounded_um(gear, item, class))
}

/// The rounding rule of ISO 1328-1:2013 for computed tolerances: above
/// 10 µm to the nearest integer micrometre; from 5 µm to 10 µm to the
/// nearest 0.5 µm; below 5 µm to the nearest 0.1 µm. Halves round up (the
/// standard's tie rule was not found; see docs/measurement.md).
pub fn round_um(value_um: f64) -> f64 {
    // Steps per micrometre (1, 2, 10): exact in binary, unlike 0.1.
    let per_um = if value_um > 10.0 {
        1.0
    } else if value_um >= 5.0 {
        2.0
    } else {
        10.0
    };
    (value_um * per_um + 0.5).floor() / per_um
}

/// Every tolerance of one class, µm, rounded.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Tolerances {
    /// The class.
    pub class: Class,
    /// fpT.
    pub single_pitch_um: f64,
    /// FpT.
    pub cumulative_pitch_um: f64,
    /// fHαT (the slope deviation may be ± this).
    pub profile_slope_um: f64,
    /// ffαT.
    pub profile_form_um: f64,
    /// FαT.
    pub profile_total_um: f64,
    /// fHβT (the slope deviation may be ± this).
    pub helix_slope_um: f64,
    /// ffβT.
    pub helix_form_um: f64,
    /// FβT.
    pub helix_total_um: f64,
    /// FrT.
    pub runout_um: f64,
}

/// The tolerances of `gear` in `class`.
pub fn tolerances(gear: &GearData, class: Class) -> Tolerances {
    let t = |item| tolerance_um(gear, item, class);
    Tolerances {
        class,
        single_pitch_um: t(Item::SinglePitch),
        cumulative_pitch_um: t(Item::CumulativePitch),
        profile_slope_um: t(Item::ProfileSlope),
        profile_form_um: t(Item::ProfileForm),
        profile_total_um: t(Item::ProfileTotal),
        helix_slope_um: t(Item::HelixSlope),
        helix_form_um: t(Item::HelixForm),
        helix_total_um: t(Item::HelixTotal),
        runout_um: t(Item::Runout),
    }
}

/// The class a deviation meets: a class 1 to 11, or worse than 11. Ordered
/// from best to worst, so the grade of a gear is the largest of its
/// items' grades.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub enum Grade {
    /// The finest class whose tolerance the deviation does not exceed.
    Class(Class),
    /// The deviation exceeds the class-11 tolerance.
    WorseThan11,
}

/// The finest class whose (rounded) tolerance of `item` the measured
/// deviation does not exceed. Slope deviations are signed and compared by
/// their magnitude, as their tolerance is ±; the others are magnitudes
/// already. A deviation equal to the tolerance meets it.
pub fn grade(gear: &GearData, item: Item, deviation_um: f64) -> Result<Grade, Error> {
    if !deviation_um.is_finite() {
        return Err(out("deviation_um", "a finite number of µm", deviation_um));
    }
    let dev = deviation_um.abs();
    Ok(Class::all()
        .find(|&c| dev <= tolerance_um(gear, item, c))
        .map_or(Grade::WorseThan11, Grade::Class))
}

/// The gear's overall grade: the worst of its items' grades (an empty
/// list is an error: no item, no grade).
pub fn overall_grade(gear: &GearData, deviations: &[(Item, f64)]) -> Result<Grade, Error> {
    if deviations.is_empty() {
        return Err(Error::TooFewSamples {
            what: "measured items",
            needed: 1,
            got: 0,
        });
    }
    let mut worst = Grade::Class(Class::FINEST);
    for &(item, dev) in deviations {
        worst = worst.max(grade(gear, item, dev)?);
    }
    Ok(worst)
}

#[cfg(test)]
mod tests;
