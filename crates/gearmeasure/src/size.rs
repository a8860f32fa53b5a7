//! Gear size: the span measurement Wk over k teeth and the dimension over
//! balls (or pins, for spur gears) of external spur and helical gears, and
//! the normal tooth thickness sn at the reference circle each implies.
//! Derivations in docs/measurement.md; in short, with αt the transverse
//! pressure angle (tan αt = tan αn / cos β), db = z·mn·cos αt / cos β the
//! base diameter, βb the base helix angle (sin βb = sin β·cos αn) and
//! inv α = tan α − α:
//!
//! ```text
//! Wk = cos αn·[(k − 1)·π·mn + sn + z·mn·inv αt]
//! inv αMt = inv αt + DM / (z·mn·cos αn) + sn / (z·mn) − π / z
//! dM = db / cos αMt                 (the diameter of the ball centres)
//! Md = dM + DM                      (z even)
//! Md = dM·cos(π / (2z)) + DM        (z odd)
//! ```
//!
//! Both rest on one property: involute helicoids of one gear flank side
//! are parallel surfaces, a distance rb·Δθ·cos βb apart for an angular
//! offset Δθ, so the distance between two flanks (span) or from a ball
//! centre to a flank is an arc of the base circle times cos βb.

use crate::{check_range, Error};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The involute function inv α = tan α − α.
pub fn inv(alpha_rad: f64) -> f64 {
    alpha_rad.tan() - alpha_rad
}

/// The angle α in [0, π/2) whose involute is `value` (≥ 0), by Newton's
/// method on tan α − α − value (derivative tan² α), started from the cube
/// root that inv α ≈ α³/3 gives.
pub fn inv_inverse(value: f64) -> Result<f64, Error> {
    check_range("inv", value, 0.0, 1e6, "an involute value ≥ 0")?;
    let mut a = (3.0 * value).cbrt().min(1.5);
    for _ in 0..60 {
        let t = a.tan();
        let step = (t - a - value) / (t * t).max(1e-300);
        a = (a - step).clamp(1e-12, PI / 2.0 - 1e-12);
        if step.abs() < 1e-15 {
            break;
        }
    }
    Ok(a)
}

/// The involute geometry of an external cylindrical gear, validated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Involute {
    /// Number of teeth z.
    pub teeth: u32,
    /// Normal module mn, mm.
    pub normal_module_mm: f64,
    /// Normal pressure angle αn, degrees.
    pub normal_pressure_angle_deg: f64,
    /// Helix angle β at the reference circle, degrees (its sign, the hand,
    /// does not change the size).
    pub helix_deg: f64,
}

impl Involute {
    /// The gear, or the first input out of its range.
    pub fn new(
        teeth: u32,
        normal_module_mm: f64,
        normal_pressure_angle_deg: f64,
        helix_deg: f64,
    ) -> Result<Self, Error> {
        check_range("teeth", f64::from(teeth), 3.0, 10_000.0, "3 ≤ z ≤ 10 000")?;
        check_range(
            "normal_module_mm",
            normal_module_mm,
            1e-3,
            1e3,
            "0 < mn ≤ 1000 mm",
        )?;
        check_range(
            "normal_pressure_angle_deg",
            normal_pressure_angle_deg,
            1.0,
            45.0,
            "1° ≤ αn ≤ 45°",
        )?;
        check_range("helix_deg", helix_deg, -60.0, 60.0, "|β| ≤ 60°")?;
        Ok(Involute {
            teeth,
            normal_module_mm,
            normal_pressure_angle_deg,
            helix_deg,
        })
    }

    fn z(&self) -> f64 {
        f64::from(self.teeth)
    }

    fn alpha_n(&self) -> f64 {
        self.normal_pressure_angle_deg.to_radians()
    }

    /// The transverse pressure angle αt, rad: tan αt = tan αn / cos β.
    pub fn transverse_pressure_angle_rad(&self) -> f64 {
        (self.alpha_n().tan() / self.helix_deg.to_radians().cos()).atan()
    }

    /// The reference diameter d = z·mn / cos β, mm.
    pub fn reference_diameter_mm(&self) -> f64 {
        self.z() * self.normal_module_mm / self.helix_deg.to_radians().cos()
    }

    /// The base diameter db = d·cos αt, mm.
    pub fn base_diameter_mm(&self) -> f64 {
        self.reference_diameter_mm() * self.transverse_pressure_angle_rad().cos()
    }

    /// The base helix angle βb, rad: sin βb = sin β·cos αn.
    pub fn base_helix_rad(&self) -> f64 {
        (self.helix_deg.to_radians().abs().sin() * self.alpha_n().cos()).asin()
    }

    /// The normal tooth thickness at the reference circle of a gear cut
    /// with profile shift coefficient `x` by a basic rack of tooth thickness
    /// π·mn/2 and no backlash allowance: sn = mn·(π/2 + 2x·tan αn).
    pub fn thickness_from_shift(&self, x: f64) -> f64 {
        self.normal_module_mm * (PI / 2.0 + 2.0 * x * self.alpha_n().tan())
    }

    fn check_k(&self, k: u32) -> Result<(), Error> {
        check_range("k", f64::from(k), 1.0, self.z() - 1.0, "1 ≤ k ≤ z − 1").map(|_| ())
    }

    /// The span Wk over `k` teeth, mm, for the normal tooth thickness
    /// `sn_mm`: cos αn·[(k − 1)·π·mn + sn + z·mn·inv αt].
    pub fn span_mm(&self, k: u32, sn_mm: f64) -> Result<f64, Error> {
        self.check_k(k)?;
        let mn = self.normal_module_mm;
        let inv_t = inv(self.transverse_pressure_angle_rad());
        Ok(self.alpha_n().cos() * ((f64::from(k) - 1.0) * PI * mn + sn_mm + self.z() * mn * inv_t))
    }

    /// The normal tooth thickness sn a measured span `span_mm` over `k`
    /// teeth implies (the span formula solved for sn).
    pub fn thickness_from_span(&self, k: u32, span_mm: f64) -> Result<f64, Error> {
        self.check_k(k)?;
        let mn = self.normal_module_mm;
        let inv_t = inv(self.transverse_pressure_angle_rad());
        Ok(span_mm / self.alpha_n().cos() - (f64::from(k) - 1.0) * PI * mn - self.z() * mn * inv_t)
    }

    /// The diameter at which the caliper touches the flanks, mm, in the
    /// transverse section where the tooth group is symmetric about the
    /// caliper's middle: there the jaws' traces are Wk / cos βb apart, the
    /// contacts lie on one tangent of the base circle, half of that either
    /// side of its tangent point, so dc = √(db² + (Wk / cos βb)²). (On a
    /// helical gear the jaws touch along lines, crossing other sections at
    /// other diameters.)
    pub fn span_contact_diameter_mm(&self, k: u32, sn_mm: f64) -> Result<f64, Error> {
        let wt = self.span_mm(k, sn_mm)? / self.base_helix_rad().cos();
        Ok(self.base_diameter_mm().hypot(wt))
    }

    /// The number of teeth to span: the k whose contact diameter is nearest
    /// the middle of the tooth depth, d + 2·x·mn, with x the shift that
    /// gives `sn_mm`.
    pub fn span_teeth(&self, sn_mm: f64) -> Result<u32, Error> {
        let x = (sn_mm / self.normal_module_mm - PI / 2.0) / (2.0 * self.alpha_n().tan());
        let target = self.reference_diameter_mm() + 2.0 * x * self.normal_module_mm;
        let mut best = (1, f64::INFINITY);
        for k in 1..self.teeth {
            let off = (self.span_contact_diameter_mm(k, sn_mm)? - target).abs();
            if off < best.1 {
                best = (k, off);
            }
        }
        Ok(best.0)
    }

    /// The diameter dM of the centres of balls of diameter `ball_mm` lying
    /// in the tooth spaces, mm: inv αMt = inv αt + DM/(z·mn·cos αn)
    /// + sn/(z·mn) − π/z, dM = db / cos αMt.
    pub fn ball_centre_diameter_mm(&self, ball_mm: f64, sn_mm: f64) -> Result<f64, Error> {
        check_range("ball_mm", ball_mm, 1e-9, 1e6, "DM > 0")?;
        let (z, mn) = (self.z(), self.normal_module_mm);
        let inv_m = inv(self.transverse_pressure_angle_rad())
            + ball_mm / (z * mn * self.alpha_n().cos())
            + sn_mm / (z * mn)
            - PI / z;
        let alpha_m = inv_inverse(inv_m).map_err(|_| Error::OutOfRange {
            field: "ball_mm",
            expected: "a ball large enough to reach above the base circle",
            got: ball_mm,
        })?;
        Ok(self.base_diameter_mm() / alpha_m.cos())
    }

    /// The dimension over two balls `ball_mm` in opposite spaces (the most
    /// nearly opposite when z is odd), mm.
    pub fn over_balls_mm(&self, ball_mm: f64, sn_mm: f64) -> Result<f64, Error> {
        let dm = self.ball_centre_diameter_mm(ball_mm, sn_mm)?;
        Ok(dm * self.odd_factor() + ball_mm)
    }

    /// cos(π/(2z)) for odd z (the balls' centres are 180° − 180°/z apart),
    /// 1 for even z.
    fn odd_factor(&self) -> f64 {
        if self.teeth % 2 == 1 {
            (PI / (2.0 * self.z())).cos()
        } else {
            1.0
        }
    }

    /// The normal tooth thickness sn a measured dimension `over_mm` over
    /// balls `ball_mm` implies: dM from the dimension, αMt = acos(db/dM),
    /// and the ball formula solved for sn.
    pub fn thickness_from_over_balls(&self, ball_mm: f64, over_mm: f64) -> Result<f64, Error> {
        check_range("ball_mm", ball_mm, 1e-9, 1e6, "DM > 0")?;
        let dm = (over_mm - ball_mm) / self.odd_factor();
        let db = self.base_diameter_mm();
        check_range(
            "over_mm",
            dm,
            db,
            f64::MAX,
            "ball centres outside the base circle",
        )
        .map_err(|_| Error::OutOfRange {
            field: "over_mm",
            expected: "ball centres outside the base circle",
            got: over_mm,
        })?;
        let (z, mn) = (self.z(), self.normal_module_mm);
        let inv_m = inv((db / dm).acos());
        Ok(z * mn
            * (inv_m
                - inv(self.transverse_pressure_angle_rad())
                - ball_mm / (z * mn * self.alpha_n().cos())
                + PI / z))
    }
}
