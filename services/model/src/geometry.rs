//! Cylindrical gear geometry after ISO 21771 (DIN 3960): reference, base, tip and
//! root diameters, transverse module and pressure angle, whole depth and lead.
//!
//! All lengths are in millimetres and all angles in degrees at the interface;
//! the functions are pure and total (a nonsensical input gives a non-finite
//! result, which [`crate::validate`] rejects before anything uses it).

use gearcam_proto::{GearSpec, Geometry};

/// Helix angles at or below this magnitude, degrees, count as a spur gear.
pub const SPUR_EPS_DEG: f64 = 1e-9;

/// True when the gear's helix angle is zero (within [`SPUR_EPS_DEG`]).
pub fn is_spur(gear: &GearSpec) -> bool {
    gear.helix_angle_deg.abs() <= SPUR_EPS_DEG
}

/// Reference diameter d = z·mn / cos β, mm.
pub fn reference_diameter_mm(gear: &GearSpec) -> f64 {
    f64::from(gear.teeth) * gear.module_mm / gear.helix_angle_deg.to_radians().cos()
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
    Some(std::f64::consts::PI * gear.module_mm * f64::from(gear.teeth) / beta.sin())
}

/// The ISO 21771 geometry of a cylindrical gear:
///
/// - d = z·mn / cos β, mt = mn / cos β, αt = atan(tan αn / cos β), db = d·cos αt,
/// - da = d + 2·mn·(ha* + x), df = d − 2·mn·(ha* + c* − x),
/// - whole depth (2·ha* + c*)·mn, lead Pz = π·mn·z / sin β (none for spur gears).
pub fn geometry(gear: &GearSpec) -> Geometry {
    let mn = gear.module_mm;
    let beta = gear.helix_angle_deg.to_radians();
    let alpha_n = gear.pressure_angle_deg.to_radians();
    let ha = gear.addendum_coef;
    let c = gear.clearance_coef;
    let x = gear.profile_shift;

    let d = reference_diameter_mm(gear);
    let mt = mn / beta.cos();
    let alpha_t = (alpha_n.tan() / beta.cos()).atan();
    Geometry {
        d_mm: d,
        db_mm: d * alpha_t.cos(),
        da_mm: d + 2.0 * mn * (ha + x),
        df_mm: d - 2.0 * mn * (ha + c - x),
        mt_mm: mt,
        alpha_t_deg: alpha_t.to_degrees(),
        whole_depth_mm: (2.0 * ha + c) * mn,
        lead_mm: lead_mm(gear),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use gearcam_proto::Hand;

    /// A gear with the given module, teeth and helix angle and standard defaults otherwise.
    pub(crate) fn gear(module_mm: f64, teeth: u32, helix_angle_deg: f64) -> GearSpec {
        GearSpec {
            module_mm,
            teeth,
            pressure_angle_deg: 20.0,
            helix_angle_deg,
            helix_hand: (helix_angle_deg != 0.0).then_some(Hand::Right),
            face_width_mm: 30.0,
            profile_shift: 0.0,
            addendum_coef: 1.0,
            clearance_coef: 0.25,
            blank_od_mm: None,
            od_correction_mm: 0.0,
            material: "42CrMo4".into(),
            quality_grade: 8,
            fixture_height_mm: 50.0,
        }
    }

    #[test]
    fn spur_gear_matches_mesys_reference() {
        // SPEC §10: ISO 21771 reference values published by the MESYS online
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
