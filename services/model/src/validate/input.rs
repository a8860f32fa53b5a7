//! Parameter checks of the job's input: the gear's drawing data, the ball for
//! the measurement over balls, the hob, and the process values.

use super::*;
use gearcam_proto::Code;

pub(super) fn check_gear(r: &mut Report, g: &GearSpec) -> bool {
    if g.teeth < 1 || g.teeth > MAX_TEETH {
        r.error(
            Code::TEETH_RANGE,
            "gear.teeth",
            format!("1 to {MAX_TEETH}"),
            g.teeth.to_string(),
            "The number of teeth is not a gear's; correct the number of teeth in the job.",
        );
    }
    if !(g.module_mm > 0.0 && g.module_mm.is_finite()) {
        r.error(
            Code::MODULE_RANGE,
            "gear.module_mm",
            "> 0 mm",
            format!("{} mm", num(g.module_mm)),
            "The normal module must be a positive length; correct gear.module_mm.",
        );
    }
    if !open(g.pressure_angle_deg, 0.0, 45.0) {
        r.error(
            Code::PRESSURE_ANGLE_RANGE,
            "gear.pressure_angle_deg",
            "(0°, 45°)",
            format!("{}°", num(g.pressure_angle_deg)),
            "The normal pressure angle must lie between 0° and 45° (usually 20°); correct gear.pressure_angle_deg.",
        );
    }
    if !open(g.helix_angle_deg, -90.0, 90.0) {
        r.error(
            Code::HELIX_RANGE,
            "gear.helix_angle_deg",
            "(-90°, 90°)",
            format!("{}°", num(g.helix_angle_deg)),
            "The helix angle must lie strictly between -90° and 90° (0 for a spur gear); correct gear.helix_angle_deg.",
        );
    } else if !is_spur(g) && g.helix_hand.is_none() {
        r.error(
            Code::HELIX_HAND_MISSING,
            "gear.helix_hand",
            "right or left",
            "none",
            "A helical gear needs its helix hand to set the hob swivel and the differential; add helix_hand = \"right\" or \"left\" to [gear].",
        );
    }
    if !(g.face_width_mm > 0.0 && g.face_width_mm.is_finite()) {
        r.error(
            Code::FACE_WIDTH_RANGE,
            "gear.face_width_mm",
            "> 0 mm",
            format!("{} mm", num(g.face_width_mm)),
            "The face width must be a positive length; correct gear.face_width_mm.",
        );
    }
    if !(g.addendum_coef > 0.0 && g.addendum_coef.is_finite()) {
        r.error(
            Code::ADDENDUM_RANGE,
            "gear.addendum_coef",
            "> 0",
            num(g.addendum_coef),
            "The addendum coefficient ha* must be positive (usually 1); correct gear.addendum_coef.",
        );
    }
    if !(g.clearance_coef >= 0.0 && g.clearance_coef.is_finite()) {
        r.error(
            Code::CLEARANCE_COEF_RANGE,
            "gear.clearance_coef",
            "≥ 0",
            num(g.clearance_coef),
            "The tip clearance coefficient c* must not be negative (usually 0.25); correct gear.clearance_coef.",
        );
    }
    for (field, v) in [
        ("gear.profile_shift", g.profile_shift),
        ("gear.od_correction_mm", g.od_correction_mm),
        ("gear.fixture_height_mm", g.fixture_height_mm),
    ] {
        if !v.is_finite() {
            r.error(
                Code::NOT_FINITE,
                field,
                "a finite number",
                num(v),
                format!("{field} is not a number; give a finite value."),
            );
        }
    }
    // The geometry needs these inputs; the face width, hand, OD correction and
    // fixture height only matter to the kinematics, which errors stop anyway.
    g.teeth >= 1
        && g.teeth <= MAX_TEETH
        && g.module_mm > 0.0
        && g.module_mm.is_finite()
        && open(g.pressure_angle_deg, 0.0, 45.0)
        && open(g.helix_angle_deg, -90.0, 90.0)
        && g.addendum_coef > 0.0
        && g.addendum_coef.is_finite()
        && g.clearance_coef >= 0.0
        && g.clearance_coef.is_finite()
        && g.profile_shift.is_finite()
}

/// A job's ball must rest on the involute flanks (the default always does).
pub(super) fn check_ball(r: &mut Report, g: &GearSpec) {
    let Some(dm) = g.ball_diameter_mm.filter(|d| *d > 0.0 && d.is_finite()) else {
        return;
    };
    let min = crate::geometry::min_ball_mm(g);
    if dm <= min {
        r.error(
            Code::BALL_DIAMETER_RANGE,
            "gear.ball_diameter_mm",
            format!("> {} mm (smaller balls drop below the base circle)", num(min)),
            format!("{} mm", num(dm)),
            format!(
                "The ball must rest on the involute flanks; the ball touching at the reference circle is {} mm. Correct gear.ball_diameter_mm.",
                num(crate::geometry::reference_ball_mm(g))
            ),
        );
    }
}

pub(super) fn check_hob(r: &mut Report, h: &HobData) -> bool {
    let before = r.errors.len();
    if h.starts < 1 {
        r.error(
            Code::HOB_STARTS_RANGE,
            "hob.starts",
            "≥ 1",
            h.starts.to_string(),
            "A hob has at least one start; correct the hob's number of starts.",
        );
    }
    if !(h.od_mm > 0.0 && h.od_mm.is_finite()) {
        r.error(
            Code::HOB_OD_RANGE,
            "hob.od_mm",
            "> 0 mm",
            format!("{} mm", num(h.od_mm)),
            "The hob outside diameter must be a positive length; correct the hob data.",
        );
    }
    if !(h.module_mm > 0.0 && h.module_mm.is_finite()) {
        r.error(
            Code::HOB_MODULE_RANGE,
            "hob.module_mm",
            "> 0 mm",
            format!("{} mm", num(h.module_mm)),
            "The hob module must be a positive length; correct the hob data.",
        );
    }
    if !open(h.pressure_angle_deg, 0.0, 45.0) {
        r.error(
            Code::HOB_PRESSURE_ANGLE_RANGE,
            "hob.pressure_angle_deg",
            "(0°, 45°)",
            format!("{}°", num(h.pressure_angle_deg)),
            "The hob pressure angle must lie between 0° and 45°; correct the hob data.",
        );
    }
    if !open(h.lead_angle_deg, 0.0, 45.0) {
        r.error(
            Code::HOB_LEAD_ANGLE_RANGE,
            "hob.lead_angle_deg",
            "(0°, 45°)",
            format!("{}°", num(h.lead_angle_deg)),
            "The hob lead angle must lie between 0° and 45° (a few degrees for a usual hob); correct the hob data.",
        );
    }
    if !(h.length_mm > 0.0 && h.length_mm.is_finite()) {
        r.error(
            Code::HOB_LENGTH_RANGE,
            "hob.length_mm",
            "> 0 mm",
            format!("{} mm", num(h.length_mm)),
            "The hob length must be a positive length; correct the hob data.",
        );
    }
    r.errors.len() == before
}

pub(super) fn check_process(r: &mut Report, plan: &ProcessPlan, gear_ok: bool, cfg: &Config) {
    let p = &plan.process;
    let quantity = plan.request.spec.job.quantity;
    if quantity < 1 {
        r.error(
            Code::QUANTITY_RANGE,
            "job.quantity",
            "≥ 1",
            quantity.to_string(),
            "A job makes at least one part; correct job.quantity.",
        );
    }
    if !(1..=cfg.max_cuts).contains(&p.cuts) {
        r.error(
            Code::CUTS_RANGE,
            "process.cuts",
            format!("1 to {}", cfg.max_cuts),
            p.cuts.to_string(),
            format!("A job has one to {} cuts (rough cuts, then one finishing cut); correct process.cuts.", cfg.max_cuts),
        );
    }
    if !(p.cutting_speed_m_min > 0.0 && p.cutting_speed_m_min.is_finite()) {
        r.error(
            Code::CUTTING_SPEED_RANGE,
            "process.cutting_speed_m_min",
            "> 0 m/min",
            format!("{} m/min", num(p.cutting_speed_m_min)),
            "The cutting speed must be positive; set process.cutting_speed_m_min or let the knowledge base propose it.",
        );
    }
    if !(p.feed_mm_per_rev > 0.0 && p.feed_mm_per_rev.is_finite()) {
        r.error(
            Code::FEED_RANGE,
            "process.feed_mm_per_rev",
            "> 0 mm/rev",
            format!("{} mm/rev", num(p.feed_mm_per_rev)),
            "The axial feed per workpiece revolution must be positive; set process.feed_mm_per_rev or let the knowledge base propose it.",
        );
    } else if gear_ok {
        if let Some(pz) = lead_mm(&plan.gear) {
            if !(p.feed_mm_per_rev < pz) {
                r.error(
                    Code::FEED_RANGE,
                    "process.feed_mm_per_rev",
                    format!("< {} mm/rev (the helix lead)", num(pz)),
                    format!("{} mm/rev", num(p.feed_mm_per_rev)),
                    "The feed per revolution must be far below the helix lead, or the differential has no meaning; reduce process.feed_mm_per_rev.",
                );
            }
        }
    }
    if !(p.safety_mm >= 0.0 && p.safety_mm.is_finite()) {
        r.error(
            Code::SAFETY_RANGE,
            "process.safety_mm",
            "≥ 0 mm",
            format!("{} mm", num(p.safety_mm)),
            "The safety distance must not be negative; correct process.safety_mm.",
        );
    }
}
