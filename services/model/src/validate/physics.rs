//! The five physical checks of the patent (step 2): cutting depth, base pitch,
//! hob diameter and centre distance (the blank's window is in `machine`).

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
