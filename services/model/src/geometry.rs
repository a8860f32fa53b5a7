//! Cylindrical gear geometry after ISO 21771 (DIN 3960): transverse module and
//! pressure angle, reference, base, tip and root diameters, base helix angle,
//! lead, normal tooth thickness, span measurement, measurement over balls, and
//! for a pair the working pressure angle, centre distance and contact ratio.
//!
//! All lengths are in millimetres and all angles in degrees at the interface;
//! the functions are pure and total (a nonsensical input gives a non-finite
//! result, which [`crate::validate`] rejects before anything uses it).

use gearcam_geom::involute::{inv, inv_inverse, working_pressure_angle};
use std::f64::consts::PI;

use gearcam_proto::{GearSpec, Geometry, MateSpec, PairGeometry};

/// Helix angles at or below this magnitude, degrees, count as a spur gear.
pub const SPUR_EPS_DEG: f64 = 1e-9;

/// Default ball diameter for the measurement over balls, as a multiple of mn
/// (the ratio of docs/reference.md#reference-values's MESYS example, DM = 1.7 mm for mn = 1).
pub const DEFAULT_BALL_PER_MODULE: f64 = 1.7;

/// True when the gear's helix angle is zero (within [`SPUR_EPS_DEG`]).
pub fn is_spur(gear: &GearSpec) -> bool {
    gear.helix_angle_deg.abs() <= SPUR_EPS_DEG
}

/// Reference diameter d = z·mn / cos β, mm.
pub fn reference_diameter_mm(gear: &GearSpec) -> f64 {
    f64::from(gear.teeth) * gear.module_mm / gear.helix_angle_deg.to_radians().cos()
}

/// Transverse pressure angle αt = atan(tan αn / cos β), radians.
pub fn transverse_pressure_angle(gear: &GearSpec) -> f64 {
    (gear.pressure_angle_deg.to_radians().tan() / gear.helix_angle_deg.to_radians().cos()).atan()
}

/// Base helix angle βb = asin(sin |β|·cos αn), radians.
pub fn base_helix_angle(gear: &GearSpec) -> f64 {
    (gear.helix_angle_deg.abs().to_radians().sin() * gear.pressure_angle_deg.to_radians().cos())
        .asin()
}

/// Lead of the tooth helix Pz = π·mn·z / sin |β|, mm; `None` for a spur gear.
///
/// The lead is a length and therefore positive; the hand travels separately in
/// [`GearSpec::helix_hand`].
pub fn lead_mm(gear: &GearSpec) -> Option<f64> {
    if is_spur(gear) {
        return None;
    }
    let beta = gear.helix_angle_deg.abs().to_radians();
    Some(PI * gear.module_mm * f64::from(gear.teeth) / beta.sin())
}

/// Normal tooth thickness at the reference circle without backlash allowance,
/// sn = mn·(π/2 + 2·x·tan αn), mm (ISO 21771 §5.4).
pub fn normal_tooth_thickness_mm(gear: &GearSpec) -> f64 {
    gear.module_mm
        * (PI / 2.0 + 2.0 * gear.profile_shift * gear.pressure_angle_deg.to_radians().tan())
}

/// Base tangent length over k teeth (ISO 21771 §6.2, DIN 3960):
/// Wk = mn·cos αn·((k − 0.5)·π + z·inv αt) + 2·x·mn·sin αn, mm.
pub fn span_mm(gear: &GearSpec, k: u32) -> f64 {
    let an = gear.pressure_angle_deg.to_radians();
    let alpha_t = transverse_pressure_angle(gear);
    gear.module_mm * an.cos() * ((f64::from(k) - 0.5) * PI + f64::from(gear.teeth) * inv(alpha_t))
        + 2.0 * gear.profile_shift * gear.module_mm * an.sin()
}

/// Number of teeth k for the span measurement.
///
/// The ideal (real) k puts the anvils' contact on a chosen measuring circle dM:
/// k = z/π·(tan αMt / cos² βb − 2·x·tan αn / z − inv αt) + 0.5 with
/// cos αMt = db/dM (ISO 21771 / DIN 3960). Published calculators differ in dM
/// and in the rounding; we take dM in the middle of the tooth depth,
/// (da + df)/2, and round to the nearest integer, clamped to 1..z. This
/// reproduces both MESYS (docs/reference.md#reference-values: z 20, x 0 → k 2) and KHK (z 24, x 0.4 →
/// k 4), where dM = d + 2·x·mn with rounding would give 3 for the MESYS gear.
pub fn span_teeth(gear: &GearSpec) -> u32 {
    let alpha_t = transverse_pressure_angle(gear);
    let beta_b = base_helix_angle(gear);
    let d = reference_diameter_mm(gear);
    let db = d * alpha_t.cos();
    let mn = gear.module_mm;
    let da = d + 2.0 * mn * (gear.addendum_coef + gear.profile_shift);
    let df = d - 2.0 * mn * (gear.addendum_coef + gear.clearance_coef - gear.profile_shift);
    let dm = ((da + df) / 2.0).max(db);
    let alpha_m = (db / dm).min(1.0).acos();
    let z = f64::from(gear.teeth);
    let ideal = z / PI
        * (alpha_m.tan() / beta_b.cos().powi(2)
            - 2.0 * gear.profile_shift * gear.pressure_angle_deg.to_radians().tan() / z
            - inv(alpha_t))
        + 0.5;
    if !ideal.is_finite() {
        return 1;
    }
    (ideal.round().max(1.0) as u32).min(gear.teeth.max(1))
}

/// Ball diameter of the measurement over balls: the job's, or
/// [`DEFAULT_BALL_PER_MODULE`]·mn when that ball rests on the flanks above the
/// base circle, else [`reference_ball_mm`] (a strongly negative profile shift
/// on few teeth widens the space so much that 1.7·mn falls through it).
pub fn ball_diameter_mm(gear: &GearSpec) -> f64 {
    if let Some(dm) = gear.ball_diameter_mm {
        return dm;
    }
    let default = DEFAULT_BALL_PER_MODULE * gear.module_mm;
    if default > min_ball_mm(gear) {
        default
    } else {
        reference_ball_mm(gear)
    }
}

/// The ball that touches the flanks at the reference circle (αKt = αt):
/// DM = mn·cos αn·(π/2 − 2·x·tan αn), the normal space width at the
/// reference circle times cos αn, mm.
pub fn reference_ball_mm(gear: &GearSpec) -> f64 {
    let an = gear.pressure_angle_deg.to_radians();
    gear.module_mm * an.cos() * (PI / 2.0 - 2.0 * gear.profile_shift * an.tan())
}

/// The smallest ball that still rests on the involute flanks (inv αKt > 0,
/// contact above the base circle): DM > mn·z·cos αn·(π/(2z) − 2·x·tan αn/z −
/// inv αt), mm. A smaller ball drops into the space below the base circle,
/// where the measurement over balls is undefined.
pub fn min_ball_mm(gear: &GearSpec) -> f64 {
    let an = gear.pressure_angle_deg.to_radians();
    let z = f64::from(gear.teeth);
    gear.module_mm
        * z
        * an.cos()
        * (PI / (2.0 * z)
            - 2.0 * gear.profile_shift * an.tan() / z
            - inv(transverse_pressure_angle(gear)))
}

/// Dimension over two balls of diameter DM (ISO 21771 §6.3, DIN 3960):
/// inv αKt = inv αt + DM/(mn·z·cos αn) − π/(2z) + 2·x·tan αn / z,
/// dK = db / cos αKt, MdK = dK + DM for even z and dK·cos(90°/z) + DM for odd z.
pub fn over_balls_mm(gear: &GearSpec, ball_mm: f64) -> f64 {
    let an = gear.pressure_angle_deg.to_radians();
    let alpha_t = transverse_pressure_angle(gear);
    let z = f64::from(gear.teeth);
    let mn = gear.module_mm;
    let db = reference_diameter_mm(gear) * alpha_t.cos();
    let inv_k = inv(alpha_t) + ball_mm / (mn * z * an.cos()) - PI / (2.0 * z)
        + 2.0 * gear.profile_shift * an.tan() / z;
    let dk = db / inv_inverse(inv_k).cos();
    if gear.teeth % 2 == 0 {
        dk + ball_mm
    } else {
        dk * (PI / (2.0 * z)).cos() + ball_mm
    }
}

/// Transverse contact ratio εα = (√(ra1² − rb1²) + √(ra2² − rb2²) − a·sin αwt) / pbt,
/// with the transverse base pitch pbt = π·mt·cos αt (ISO 21771 §7).
pub fn contact_ratio(
    da1_mm: f64,
    db1_mm: f64,
    da2_mm: f64,
    db2_mm: f64,
    centre_distance_mm: f64,
    alpha_wt: f64,
    base_pitch_mm: f64,
) -> f64 {
    let leg = |da: f64, db: f64| ((da * da - db * db) / 4.0).max(0.0).sqrt();
    (leg(da1_mm, db1_mm) + leg(da2_mm, db2_mm) - centre_distance_mm * alpha_wt.sin())
        / base_pitch_mm
}

/// The pair geometry of a gear with its mate (external gears, same module,
/// pressure angle and helix angle with opposite hand). The working pressure
/// angle comes from the mate's centre distance when given, otherwise from the
/// sum of the profile shifts (zero backlash); the mate's tip diameter defaults
/// to d2 + 2·mn·(ha* + x2).
pub fn pair(gear: &GearSpec, mate: &MateSpec) -> PairGeometry {
    let mn = gear.module_mm;
    let an = gear.pressure_angle_deg.to_radians();
    let alpha_t = transverse_pressure_angle(gear);
    let cos_b = gear.helix_angle_deg.to_radians().cos();
    let (z1, z2) = (f64::from(gear.teeth), f64::from(mate.teeth));
    let d1 = z1 * mn / cos_b;
    let d2 = z2 * mn / cos_b;
    let a0 = (d1 + d2) / 2.0;
    let (alpha_wt, a) = match mate.centre_distance_mm {
        Some(a) => ((a0 * alpha_t.cos() / a).clamp(-1.0, 1.0).acos(), a),
        None => {
            let awt = working_pressure_angle(
                an,
                alpha_t,
                gear.profile_shift + mate.profile_shift,
                z1 + z2,
            );
            (awt, a0 * alpha_t.cos() / awt.cos())
        }
    };
    let da1 = d1 + 2.0 * mn * (gear.addendum_coef + gear.profile_shift);
    let da2 = mate
        .tip_diameter_mm
        .unwrap_or(d2 + 2.0 * mn * (gear.addendum_coef + mate.profile_shift));
    let pbt = PI * mn / cos_b * alpha_t.cos();
    let eps_a = contact_ratio(
        da1,
        d1 * alpha_t.cos(),
        da2,
        d2 * alpha_t.cos(),
        a,
        alpha_wt,
        pbt,
    );
    let eps_b = gear.face_width_mm * gear.helix_angle_deg.abs().to_radians().sin() / (PI * mn);
    PairGeometry {
        mate_teeth: mate.teeth,
        mate_profile_shift: mate.profile_shift,
        reference_centre_distance_mm: a0,
        working_pressure_angle_deg: alpha_wt.to_degrees(),
        centre_distance_mm: a,
        contact_ratio: eps_a,
        overlap_ratio: eps_b,
        total_contact_ratio: eps_a + eps_b,
    }
}

/// The ISO 21771 geometry of a cylindrical gear:
///
/// - d = z·mn / cos β, mt = mn / cos β, αt = atan(tan αn / cos β), db = d·cos αt,
/// - da = d + 2·mn·(ha* + x), df = d − 2·mn·(ha* + c* − x),
/// - whole depth (2·ha* + c*)·mn, lead Pz = π·mn·z / sin β (none for spur gears),
/// - βb, sn, span k and Wk, MdK over balls ([`ball_diameter_mm`]), and the
///   pair with the mate when the job names one.
pub fn geometry(gear: &GearSpec) -> Geometry {
    let mn = gear.module_mm;
    let ha = gear.addendum_coef;
    let c = gear.clearance_coef;
    let x = gear.profile_shift;

    let d = reference_diameter_mm(gear);
    let mt = mn / gear.helix_angle_deg.to_radians().cos();
    let alpha_t = transverse_pressure_angle(gear);
    let k = span_teeth(gear);
    let ball = ball_diameter_mm(gear);
    Geometry {
        d_mm: d,
        db_mm: d * alpha_t.cos(),
        da_mm: d + 2.0 * mn * (ha + x),
        df_mm: d - 2.0 * mn * (ha + c - x),
        mt_mm: mt,
        alpha_t_deg: alpha_t.to_degrees(),
        whole_depth_mm: (2.0 * ha + c) * mn,
        lead_mm: lead_mm(gear),
        base_helix_deg: base_helix_angle(gear).to_degrees(),
        sn_mm: normal_tooth_thickness_mm(gear),
        span_teeth: k,
        span_mm: span_mm(gear, k),
        ball_mm: ball,
        over_balls_mm: over_balls_mm(gear, ball),
        pair: gear.mate.as_ref().map(|m| pair(gear, m)),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// A gear with the given module, teeth and helix angle and standard defaults otherwise.
    pub(crate) fn gear(module_mm: f64, teeth: u32, helix_angle_deg: f64) -> GearSpec {
        gearcam_testkit::pipeline::gear(module_mm, teeth, helix_angle_deg)
    }

    #[test]
    fn spur_gear_matches_mesys_reference() {
        // docs/reference.md#reference-values: ISO 21771 reference values published by the MESYS online
        // calculator for mn 1, αn 20°, β 0, z 20, x 0, ha* 1, tool addendum 1.25.
        let g = geometry(&gear(1.0, 20, 0.0));
        assert_relative_eq!(g.d_mm, 20.0, epsilon = 1e-12);
        assert_relative_eq!(g.db_mm, 18.7939, epsilon = 5e-5);
        assert_relative_eq!(g.da_mm, 22.0, epsilon = 1e-12);
        assert_relative_eq!(g.df_mm, 17.5, epsilon = 1e-12);
        assert_relative_eq!(g.mt_mm, 1.0, epsilon = 1e-12);
        assert_relative_eq!(g.alpha_t_deg, 20.0, epsilon = 1e-12);
        assert_relative_eq!(g.whole_depth_mm, 2.25, epsilon = 1e-12);
        assert_eq!(g.lead_mm, None);
    }

    #[test]
    fn helical_gear_matches_independent_computation() {
        // mn 3, αn 20°, β 30°, z 12, x 0: values computed independently in Python
        // (math module) from the ISO 21771 §5 formulas, not with this code.
        let g = geometry(&gear(3.0, 12, 30.0));
        assert_relative_eq!(g.d_mm, 41.569_219_381_653, epsilon = 1e-9);
        assert_relative_eq!(g.mt_mm, 3.464_101_615_138, epsilon = 1e-9);
        assert_relative_eq!(g.alpha_t_deg, 22.795_877_258_858, epsilon = 1e-9);
        assert_relative_eq!(g.db_mm, 38.322_290_598_575, epsilon = 1e-9);
        assert_relative_eq!(g.da_mm, 47.569_219_381_653, epsilon = 1e-9);
        assert_relative_eq!(g.df_mm, 34.069_219_381_653, epsilon = 1e-9);
        assert_relative_eq!(g.whole_depth_mm, 6.75, epsilon = 1e-12);
        assert_relative_eq!(g.lead_mm.unwrap(), 226.194_671_058_465, epsilon = 1e-9);
    }

    #[test]
    fn profile_shift_moves_tip_and_root_by_two_x_mn() {
        let mut spec = gear(2.0, 30, 0.0);
        spec.profile_shift = 0.5;
        let g = geometry(&spec);
        // d = 60; da = 60 + 2·2·(1 + 0.5) = 66; df = 60 − 2·2·(1.25 − 0.5) = 57.
        assert_relative_eq!(g.da_mm, 66.0, epsilon = 1e-12);
        assert_relative_eq!(g.df_mm, 57.0, epsilon = 1e-12);
    }

    #[test]
    fn left_hand_sign_does_not_change_the_lead() {
        let g = geometry(&gear(3.0, 12, -30.0));
        assert_relative_eq!(g.lead_mm.unwrap(), 226.194_671_058_465, epsilon = 1e-9);
    }
}

#[cfg(test)]
mod published {
    //! Geometry against published worked examples; each test names its source
    //! and compares to the printed precision.
    use super::tests::gear;
    use super::*;
    use approx::assert_abs_diff_eq;
    use gearcam_proto::MateSpec;

    #[test]
    // MESYS prints sn = 1.5708, which for x = 0 is π/2 to four decimals; the
    // printed value is the oracle, so it stays as printed.
    #[allow(clippy::approx_constant)]
    fn mesys_spur_gear_thickness_span_and_balls() {
        // docs/reference.md#reference-values, MESYS online calculator (ISO 21771): mn 1, αn 20°, β 0, z 20,
        // x 0, ha* 1 → sn 1.5708, k 2, Wk 4.7083, MdK 22.2941 over 1.7 mm balls.
        let mut g = gear(1.0, 20, 0.0);
        g.ball_diameter_mm = Some(1.7);
        let geo = geometry(&g);
        assert_abs_diff_eq!(geo.sn_mm, 1.5708, epsilon = 5e-5);
        assert_eq!(geo.span_teeth, 2);
        assert_abs_diff_eq!(geo.span_mm, 4.7083, epsilon = 5e-5);
        assert_abs_diff_eq!(geo.ball_mm, 1.7, epsilon = 1e-12);
        assert_abs_diff_eq!(geo.over_balls_mm, 22.2941, epsilon = 5e-5);
        assert_abs_diff_eq!(geo.db_mm, 18.7939, epsilon = 5e-5);
        assert_abs_diff_eq!(geo.base_helix_deg, 0.0, epsilon = 1e-12);
    }

    #[test]
    fn default_ball_is_the_mesys_ratio() {
        // DM defaults to 1.7·mn, so the MESYS gear needs no ball diameter.
        let geo = geometry(&gear(1.0, 20, 0.0));
        assert_abs_diff_eq!(geo.ball_mm, 1.7, epsilon = 1e-12);
        assert_abs_diff_eq!(geo.over_balls_mm, 22.2941, epsilon = 5e-5);
    }

    #[test]
    fn khk_span_measurement_of_a_profile_shifted_spur_gear() {
        // KHK Gear Technical Reference, span measurement example: m 3, α 20°,
        // z 24, x +0.4 → zm 4 teeth, W 32.8266 mm.
        let mut g = gear(3.0, 24, 0.0);
        g.profile_shift = 0.4;
        let geo = geometry(&g);
        assert_eq!(geo.span_teeth, 4);
        assert_abs_diff_eq!(geo.span_mm, 32.8266, epsilon = 5e-5);
    }

    #[test]
    fn machinecalcs_span_over_three_teeth() {
        // machinecalcs.com span measurement worked example: m 2, z 20, α 20°,
        // x 0, k 3 → W 15.321 mm, base pitch 5.904 mm.
        let g = gear(2.0, 20, 0.0);
        assert_abs_diff_eq!(span_mm(&g, 3), 15.321, epsilon = 5e-4);
        assert_abs_diff_eq!(span_mm(&g, 4) - span_mm(&g, 3), 5.904, epsilon = 5e-4);
    }

    #[test]
    fn khk_positive_shifted_pair_from_profile_shifts() {
        // KHK Gear Technical Reference, calculation of positive shifted spur
        // gears: m 3, α 20°, z 12/24, x +0.6/+0.36 → inv αw 0.034316,
        // αw 26.0886°, centre distance a 56.4999 mm.
        let mut g = gear(3.0, 12, 0.0);
        g.profile_shift = 0.6;
        let mate = MateSpec {
            teeth: 24,
            profile_shift: 0.36,
            tip_diameter_mm: None,
            centre_distance_mm: None,
        };
        let p = pair(&g, &mate);
        assert_abs_diff_eq!(
            inv(p.working_pressure_angle_deg.to_radians()),
            0.034316,
            epsilon = 5e-7
        );
        assert_abs_diff_eq!(p.working_pressure_angle_deg, 26.0886, epsilon = 5e-5);
        assert_abs_diff_eq!(p.centre_distance_mm, 56.4999, epsilon = 5e-5);
        assert_abs_diff_eq!(p.reference_centre_distance_mm, 54.0, epsilon = 1e-12);
    }

    #[test]
    fn khk_pair_at_a_given_centre_distance_with_its_contact_ratio() {
        // The same KHK pair worked from the centre distance, as reproduced by
        // bolsover.com ("Profile Shifted External Spur Gears"): a 56.500 →
        // working involute 0.034317, αw 26.0888°, with tip diameters 44.840 /
        // 79.400 the radial contact ratio 1.202.
        let mut g = gear(3.0, 12, 0.0);
        g.profile_shift = 0.6;
        let mate = MateSpec {
            teeth: 24,
            profile_shift: 0.36,
            tip_diameter_mm: Some(79.4),
            centre_distance_mm: Some(56.5),
        };
        let p = pair(&g, &mate);
        assert_abs_diff_eq!(
            inv(p.working_pressure_angle_deg.to_radians()),
            0.034317,
            epsilon = 5e-7
        );
        assert_abs_diff_eq!(p.working_pressure_angle_deg, 26.0888, epsilon = 5e-5);
        // The published contact ratio uses the shortened tip 44.840 of the pinion.
        let alpha_w = p.working_pressure_angle_deg.to_radians();
        let (db1, db2) = (
            36.0 * 20f64.to_radians().cos(),
            72.0 * 20f64.to_radians().cos(),
        );
        let pb = PI * 3.0 * 20f64.to_radians().cos();
        let eps = contact_ratio(44.84, db1, 79.4, db2, 56.5, alpha_w, pb);
        assert_abs_diff_eq!(eps, 1.202, epsilon = 5e-4);
        assert_abs_diff_eq!(p.overlap_ratio, 0.0, epsilon = 1e-12);
    }

    #[test]
    fn helical_angles_lead_and_balls_match_independent_computation() {
        // mn 3, αn 20°, β 15°, z 25, x 0, DM 5: independent Python (math module)
        // from the ISO 21771 formulas: βb 14.076095°, αt 20.646896°, k 3,
        // Wk 23.300570, MdK 84.056637, Pz 910.363644.
        let mut g = gear(3.0, 25, 15.0);
        g.ball_diameter_mm = Some(5.0);
        let geo = geometry(&g);
        assert_abs_diff_eq!(geo.base_helix_deg, 14.076_095_421_662, epsilon = 1e-9);
        assert_abs_diff_eq!(geo.alpha_t_deg, 20.646_896_487_046, epsilon = 1e-9);
        assert_eq!(geo.span_teeth, 3);
        assert_abs_diff_eq!(geo.span_mm, 23.300_570_436_162, epsilon = 1e-9);
        assert_abs_diff_eq!(geo.over_balls_mm, 84.056_636_701_238, epsilon = 1e-8);
        assert_abs_diff_eq!(geo.lead_mm.unwrap(), 910.363_643_934_716, epsilon = 1e-8);
        assert_abs_diff_eq!(geo.sn_mm, 3.0 * PI / 2.0, epsilon = 1e-12);
    }

    #[test]
    fn odd_teeth_over_balls_use_the_cosine_of_a_quarter_pitch() {
        // mn 1, z 21, DM 1.7: independent Python, dK·cos(90°/z) + DM = 23.235939.
        let mut g = gear(1.0, 21, 0.0);
        g.ball_diameter_mm = Some(1.7);
        assert_abs_diff_eq!(over_balls_mm(&g, 1.7), 23.235_939_338_551, epsilon = 1e-8);
    }

    #[test]
    fn a_ball_that_falls_through_the_space_gives_way_to_the_reference_ball() {
        // mn 1, z 6, x −0.5: 1.7 mm sinks below the base circle (the smallest
        // ball that rests on the flanks is 6·cos20°·(π/12 + tan20°/6 − inv20°)
        // = 1.7340 mm), so the default is the ball touching at the reference
        // circle, DM = cos20°·(π/2 + tan20°) = 1.8181 mm; it touches where
        // αKt = αt, so its centre lies on d and MdK = d + DM (even z).
        let g = gear(1.0, 6, 0.0);
        let mut g = GearSpec {
            profile_shift: -0.5,
            ..g
        };
        assert_abs_diff_eq!(min_ball_mm(&g), 1.734_0, epsilon = 1e-4);
        let dm = ball_diameter_mm(&g);
        assert_abs_diff_eq!(dm, 1.818_1, epsilon = 1e-4);
        assert_abs_diff_eq!(over_balls_mm(&g, dm), 6.0 + dm, epsilon = 1e-9);
        // A gear where 1.7·mn rests on the flanks keeps it.
        g.profile_shift = 0.0;
        assert_eq!(ball_diameter_mm(&g), 1.7);
    }

    #[test]
    fn inverse_involute_inverts_the_involute() {
        for deg in [0.5, 5.0, 14.5, 20.0, 26.0886, 40.0, 60.0, 80.0] {
            let a = f64::to_radians(deg);
            assert_abs_diff_eq!(inv_inverse(inv(a)), a, epsilon = 1e-12);
        }
        assert_eq!(inv_inverse(0.0), 0.0);
        assert!(inv_inverse(-1.0).is_nan());
    }

    #[test]
    fn helical_pair_adds_the_overlap_ratio() {
        // εβ = b·sin β / (π·mn): b 30, β 15°, mn 3 → 0.823864 (closed form).
        let g = gear(3.0, 25, 15.0);
        let mate = MateSpec {
            teeth: 50,
            profile_shift: 0.0,
            tip_diameter_mm: None,
            centre_distance_mm: None,
        };
        let p = pair(&g, &mate);
        assert_abs_diff_eq!(
            p.overlap_ratio,
            30.0 * 15f64.to_radians().sin() / (PI * 3.0),
            epsilon = 1e-12
        );
        // Zero shift sum: the working angle is αt and a is the reference distance.
        assert_abs_diff_eq!(
            p.working_pressure_angle_deg,
            geometry(&g).alpha_t_deg,
            epsilon = 1e-9
        );
        assert_abs_diff_eq!(
            p.centre_distance_mm,
            p.reference_centre_distance_mm,
            epsilon = 1e-9
        );
        assert_abs_diff_eq!(
            p.total_contact_ratio,
            p.contact_ratio + p.overlap_ratio,
            epsilon = 1e-12
        );
    }
}
