//! The five physical checks of the patent (step 2): cutting depth, base pitch,
//! hob diameter and centre distance (the blank's window is in `machine`);
//! and, not among the patent's, a warning when the hob undercuts the
//! involute.

use super::*;
use gearcam_proto::Code;

/// Check 2: 0 < h ≤ whole depth − (da − Da1)/2 + allowance.
pub(super) fn check_depth(r: &mut Report, geo: &Geometry, set: &Setup, cfg: &Config) {
    let h = set.depth_mm;
    let allowance = cfg.depth_allowance_mm;
    let max = geo.whole_depth_mm - (geo.da_mm - set.blank_od_mm) / 2.0 + allowance;
    if h > cfg.length_tolerance_mm && h <= max + cfg.length_tolerance_mm {
        return;
    }
    let what = if set.depth_given {
        "The requested cut depth"
    } else {
        "The default cut depth (final centre distance = theoretical one)"
    };
    let todo = if set.depth_given {
        "correct process.depth_mm or leave it out to use the theoretical depth"
    } else {
        "check the blank OD and the hob OD and lead angle, or give process.depth_mm"
    };
    r.error(
        Code::CUT_DEPTH,
        "process.depth_mm",
        format!(
            "> 0 and ≤ {} mm (whole depth {} mm for the blank, + allowance {} mm)",
            num(max),
            num(max - allowance),
            num(allowance)
        ),
        format!("{} mm", num(h)),
        format!("{what} must be positive and must not cut the root deeper than the whole depth allows; {todo}."),
    );
}

/// Check 3: equal normal base pitch, mn0·cos α0 = mn·cos αn.
pub(super) fn check_base_pitch(r: &mut Report, gear: &GearSpec, hob: &HobData, cfg: &Config) {
    let a0 = hob.pressure_angle_deg.to_radians().cos();
    let gear_pitch = gear.module_mm * gear.pressure_angle_deg.to_radians().cos();
    let hob_pitch = hob.module_mm * a0;
    if (hob_pitch - gear_pitch).abs() <= cfg.base_pitch_tolerance_mm {
        return;
    }
    r.error(
        Code::BASE_PITCH_MISMATCH,
        "hob.module_mm",
        format!(
            "mn0·cos α0 = {} mm ± {} mm (hob module {} mm at α0 {}°)",
            num(gear_pitch),
            num(cfg.base_pitch_tolerance_mm),
            num(gear_pitch / a0),
            num(hob.pressure_angle_deg)
        ),
        format!(
            "mn0·cos α0 = {} mm (hob module {} mm, α0 {}°)",
            num(hob_pitch),
            num(hob.module_mm),
            num(hob.pressure_angle_deg)
        ),
        format!(
            "Hob {} does not fit the gear: hob and gear need the same normal base pitch (module {} mm, pressure angle {}°); choose a matching hob.",
            hob.id,
            num(gear.module_mm),
            num(gear.pressure_angle_deg)
        ),
    );
}

/// Check 4: da0 ≥ d0 + 2·(ha* + c*)·mn0.
pub(super) fn check_hob_od(r: &mut Report, gear: &GearSpec, hob: &HobData, cfg: &Config) {
    let d0 = crate::hobbing::hob_reference_diameter_mm(hob);
    let min = d0 + 2.0 * (gear.addendum_coef + gear.clearance_coef) * hob.module_mm;
    if hob.od_mm >= min - cfg.length_tolerance_mm {
        return;
    }
    r.error(
        Code::HOB_OD_TOO_SMALL,
        "hob.od_mm",
        format!("≥ {} mm (d0 {} mm + 2·(ha* + c*)·mn0)", num(min), num(d0)),
        format!("{} mm", num(hob.od_mm)),
        format!(
            "Hob {}'s outside diameter is too small for its reference diameter d0 = z0·mn0/sin γ0; check the hob's OD and lead angle, or choose another hob.",
            hob.id
        ),
    );
}

/// Check 5: L = (da0 + Da1)/2 − h ≥ d0/2 + (d·cos αn / cos α0)/2 + x·mn.
pub(super) fn check_centre_distance(r: &mut Report, set: &Setup, cfg: &Config) {
    let l = set.centre_distance_mm;
    let theory = set.theoretical_centre_distance_mm;
    if l >= theory - cfg.length_tolerance_mm {
        return;
    }
    r.error(
        Code::CENTRE_DISTANCE_TOO_SMALL,
        "process.depth_mm",
        format!("centre distance ≥ {} mm (depth ≤ {} mm)", num(theory), num(set.depth_mm - (theory - l))),
        format!("centre distance {} mm (depth {} mm)", num(l), num(set.depth_mm)),
        "The final centre distance is below the theoretical one, so the teeth would be cut thin; reduce process.depth_mm or leave it out to use the theoretical depth.",
    );
}

/// Tip radius of the hob's basic rack in modules: the hob data carry none,
/// so the standard rack's 0.38 (ISO 53).
const RACK_TIP_RADIUS: f64 = 0.38;

/// How far below the reference circle the hob's straight flank reaches
/// beyond the point where the line of action touches the base circle, mm
/// (positive: the involute is undercut). The flank ends where the rack's
/// tip rounding of radius `rho` starts, (d − df)/2 − ρ·(1 − sin αn) below the
/// reference circle (df already holds the profile shift); a generating
/// line touches the involute on the line of action, at most (d/2)·sin²αt
/// below the reference circle (at the base circle), so a flank reaching
/// deeper cuts into the involute it generated.
///
/// Fed along a cone of `cone_deg` (0: a cylinder), the hob generates each
/// transverse section with its rack's depths stretched by 1/cos δ about the
/// rack's reference line, which stands x·mn out from the reference circle
/// (`crate::path::cone_offsets`): the flank ends (ha0 − ρ·(1 − sin αn))/cos δ
/// below that line, ha0 = (d − df)/2 + x·mn, and its flanks stand at
/// tan αt′ = tan αt·cos δ. These are the large end's figures.
fn undercut_mm(geo: &Geometry, pressure_angle_deg: f64, rho: f64, cone: (f64, f64)) -> f64 {
    let (cone_deg, shift_mm) = cone;
    let stretch = 1.0 / cone_deg.to_radians().cos();
    let an = pressure_angle_deg.to_radians();
    let at = (geo.alpha_t_deg.to_radians().tan() / stretch).atan();
    let addendum = (geo.d_mm - geo.df_mm) / 2.0 + shift_mm;
    let form = (addendum - rho * (1.0 - an.sin())) * stretch - shift_mm;
    form - geo.d_mm / 2.0 * at.sin().powi(2)
}

/// Warns when the hob undercuts the involute (few teeth, or a negative
/// profile shift): the root is weakened and the active profile shortened.
/// Along a cone the hob stands b·tan δ deeper at the small end than at the
/// large one, where the geometry holds.
pub(super) fn check_undercut(r: &mut Report, gear: &GearSpec, geo: &Geometry) {
    let mn = gear.module_mm;
    let over = |cone_deg: f64| {
        undercut_mm(
            geo,
            gear.pressure_angle_deg,
            RACK_TIP_RADIUS * mn,
            (cone_deg, gear.profile_shift * mn),
        )
    };
    let cone_deg = gear.cone.as_ref().map_or(0.0, |c| c.angle_deg);
    let at_large = over(cone_deg);
    let deeper = gear.face_width_mm * cone_deg.to_radians().tan();
    let worst = at_large + deeper;
    if worst <= 1e-6 {
        return;
    }
    let x_min = gear.profile_shift + worst / mn;
    let message = match &gear.cone {
        None => format!(
            "The hob undercuts the involute: with {} teeth and profile shift {} its straight flank reaches {} mm below where the line of action touches the base circle (standard rack tip radius {RACK_TIP_RADIUS}·mn). The root is weakened and the active profile shorter; raise gear.profile_shift to at least {} unless the drawing asks for the undercut gear.",
            gear.teeth,
            num(gear.profile_shift),
            num(worst),
            num(x_min)
        ),
        Some(c) if at_large >= 0.0 => format!(
            "The hob undercuts the involute over the whole face: along the cone the profile shift falls from {} at the large end, already below the {} at which the straight flank of the hob (standard rack tip radius {RACK_TIP_RADIUS}·mn) reaches past where the line of action touches the base circle, to {} at the small end. The root is weakened and the active profile shorter; raise gear.profile_shift to at least {} (at the large end) or use a smaller cone than {}°.",
            num(gear.profile_shift),
            num(gear.profile_shift + at_large / mn),
            num(gear.profile_shift - deeper / mn),
            num(x_min),
            num(c.angle_deg)
        ),
        Some(c) => {
            let tan = c.angle_deg.to_radians().tan();
            let sound = -at_large / tan;
            // The steepest cone sound at the small end: b·tan δ = −(the
            // large end's figure at δ), which changes little with δ.
            let mut steepest = c.angle_deg;
            for _ in 0..20 {
                steepest = (-over(steepest) / gear.face_width_mm).atan().to_degrees();
            }
            format!(
                "The hob undercuts the involute over the {} mm of the face nearest its small end: along the cone the profile shift falls from {} at the large end to {} at the small end, and below {} the straight flank of the hob (standard rack tip radius {RACK_TIP_RADIUS}·mn) reaches past where the line of action touches the base circle. The root is weakened and the active profile shorter there. A cone of at most {}° avoids it; so would a profile shift of at least {} at the large end, if its teeth do not come to a point.",
                num(gear.face_width_mm - sound),
                num(gear.profile_shift),
                num(gear.profile_shift - deeper / mn),
                num(gear.profile_shift + at_large / mn),
                num(steepest),
                num(x_min)
            )
        }
    };
    r.warnings.push(Warning {
        code: Code::FLANK_UNDERCUT,
        field: "gear.profile_shift".into(),
        message,
    });
}

#[cfg(test)]
mod undercut_tests {
    use super::*;
    use crate::geometry::geometry;
    use gearcam_proto::ConeSpec;

    /// Brute force, independent of the closed form: a sharp rack (its
    /// straight flank down to `depth` below the rolling line, pressure
    /// angle α) rolled on the pitch circle of radius `r`; true when, at
    /// some roll angle, a point of the involute that flank generates lies
    /// inside the rack's tooth by more than 10⁻⁹ mm. The involute's points
    /// are the contacts on the line of action, turned into the gear's frame.
    fn rack_cuts_its_involute(r: f64, alpha: f64, depth: f64, width: f64) -> bool {
        let (sa, ca) = alpha.sin_cos();
        // Rack coordinates (u, v) from the pitch point, v up. The tooth,
        // `width` wide on the rolling line, points down to v = −depth
        // between its flanks u = −width − v·tan α and u = v·tan α (the one
        // that generates the involute); its part up to half its width above
        // the rolling line is tried. Rolled by φ (the gear turned by φ
        // counter-clockwise) a rack point stands at (u − r·φ, r + v).
        let turn = |(x, y): (f64, f64), phi: f64| {
            let (s, c) = phi.sin_cos();
            (x * c - y * s, x * s + y * c)
        };
        let involute: Vec<(f64, f64)> = (1..200)
            .map(|k| {
                // s along the line of action from the pitch point towards
                // its tangent point on the base circle (s = r·sin α), the
                // points closer together near the base circle, where an
                // undercut starts.
                let s = r * sa * (1.0 - (f64::from(k) / 200.0).powi(2));
                let phi = -s / (r * ca);
                turn((s * ca, r - s * sa), -phi)
            })
            .collect();
        // Contact stays within |φ| ≤ tan α; the flank's end passes a
        // point of the involute near there.
        (-12_000..=12_000).any(|i| {
            let phi = f64::from(i) * 5e-5;
            involute.iter().any(|&q| {
                let (x, y) = turn(q, phi);
                let (u, v) = (x + r * phi, y - r);
                let tan = sa / ca;
                (v * tan - u) * ca > 1e-9 && u > -width - v * tan && v > -depth && v < 0.5 * width
            })
        })
    }

    /// How many of `teeth` × shifts −0.5 to 0.5 the closed form calls
    /// undercut and sound along a cone of `cone_deg` (0: a cylinder),
    /// asserting on each that the brute force agrees, with the rack as the
    /// hob stands in a transverse section: its flanks at
    /// tan α′ = tan αn·cos δ, its depth below its reference line stretched
    /// by 1/cos δ. Cases within 0.005·mn of the limit are left out: the
    /// rack's intrusion grows faster than its overshoot, and is below the
    /// sampling's reach that close.
    fn agreement(cone_deg: f64, teeth: &[u32]) -> (usize, usize) {
        let (mut under, mut sound) = (0, 0);
        for &z in teeth {
            for x in (-5..=5).map(|i| f64::from(i) / 10.0) {
                let mut gear = crate::geometry::tests::gear(2.0, z, 0.0);
                gear.profile_shift = x;
                let geo = geometry(&gear);
                let mn = gear.module_mm;
                let over = undercut_mm(&geo, gear.pressure_angle_deg, 0.0, (cone_deg, x * mn));
                if over.abs() < 0.005 * mn {
                    continue;
                }
                let c = cone_deg.to_radians().cos();
                let a = (20f64.to_radians().tan() * c).atan();
                let addendum = (geo.d_mm - geo.df_mm) / 2.0 + x * mn;
                let depth = addendum / c - x * mn;
                let width = mn * (std::f64::consts::FRAC_PI_2 - 2.0 * x * a.tan());
                let cut = rack_cuts_its_involute(geo.d_mm / 2.0, a, depth, width);
                assert_eq!(
                    cut,
                    over > 0.0,
                    "δ {cone_deg}, z {z}, x {x}: closed form {over} mm"
                );
                if cut {
                    under += 1;
                } else {
                    sound += 1;
                }
            }
        }
        (under, sound)
    }

    /// The closed form agrees with the brute force on sharp racks: spur
    /// gears of 8 to 40 teeth, shifts −0.5 to 0.5.
    #[test]
    fn the_undercut_limit_is_where_the_rack_starts_cutting_its_involute() {
        let (under, sound) = agreement(0.0, &[8, 12, 14, 16, 17, 18, 20, 25, 40]);
        assert!(under >= 5 && sound >= 5, "{under} undercut, {sound} sound");
    }

    /// Along a cone the same brute force, with the rack as the hob stands in
    /// a transverse section.
    #[test]
    fn along_a_cone_the_limit_is_where_the_stretched_rack_cuts_its_involute() {
        let teeth = [12, 16, 20, 30];
        let (u10, s10) = agreement(10.0, &teeth);
        let (u25, s25) = agreement(25.0, &teeth);
        let (under, sound) = (u10 + u25, s10 + s25);
        assert!(under >= 5 && sound >= 5, "{under} undercut, {sound} sound");
    }

    /// With the standard rack's tip radius: 14 teeth unshifted are undercut
    /// and warned, 18 are not; a conical gear is warned over the part of its
    /// face nearest the small end, with the shift where the undercut starts.
    #[test]
    fn few_teeth_and_a_steep_cone_are_warned() {
        let warned = |gear: &GearSpec| {
            let mut r = Report::default();
            check_undercut(&mut r, gear, &geometry(gear));
            r.warnings
        };
        let mut gear = crate::geometry::tests::gear(2.0, 14, 0.0);
        let w = warned(&gear);
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].code, Code::FLANK_UNDERCUT);
        assert_eq!(w[0].field, "gear.profile_shift");
        gear.teeth = 18;
        assert!(warned(&gear).is_empty());
        // Helical, β 30°: z_min = 2·cos β·(1.25 − 0.38·(1 − sin αn))/sin²αt
        // = 11.5 (αt from tan αn / cos β).
        let mut helical = crate::geometry::tests::gear(2.0, 11, 30.0);
        helical.helix_hand = Some(gearcam_proto::Hand::Right);
        assert_eq!(warned(&helical).len(), 1);
        helical.teeth = 12;
        assert!(warned(&helical).is_empty());
        // The conical example: z 19, 6.5° over 20 mm, sound at the large end.
        gear.teeth = 19;
        gear.face_width_mm = 20.0;
        assert!(warned(&gear).is_empty());
        gear.cone = Some(ConeSpec {
            angle_deg: 6.5,
            large_end: Default::default(),
        });
        let w = warned(&gear);
        assert_eq!(w.len(), 1, "{w:?}");
        // Sound over (d/2·sin²α′ − (2.5 − 0.76·(1 − sin α))/cos δ)/tan δ,
        // tan α′ = tan α·cos δ.
        let (a, d) = (20f64.to_radians(), 6.5f64.to_radians());
        let a_cone = (a.tan() * d.cos()).atan();
        let sound =
            (19.0 * a_cone.sin().powi(2) - (2.5 - 0.76 * (1.0 - a.sin())) / d.cos()) / d.tan();
        let over = format!("over the {} mm of the face", num(20.0 - sound));
        assert!(w[0].message.contains(&over), "{over}: {}", w[0].message);
        // Undercut at its large end already (14 teeth): the whole face.
        gear.teeth = 14;
        let w = warned(&gear);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].message.contains("over the whole face"),
            "{}",
            w[0].message
        );
    }
}
