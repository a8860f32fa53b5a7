//! The rules of each class of gear (conical, crowned, worm wheel, multi-gear),
//! the hob shift and the units of a multi-gear part.

use super::*;
use gearcam_proto::{Code, ConeSpec, CrowningSpec, ProcessOverrides, WormWheelSpec};

/// Class markers, class-specific data, process options of the class, shift,
/// measurement data, mate and the units of a multi-gear part.
pub(super) fn check_class(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let g = &plan.gear;
    let o = &plan.sections().process;
    check_markers(r, g, o);
    if let Some(cone) = &g.cone {
        check_cone(r, g, cone);
    }
    if let Some(cr) = &g.crowning {
        check_crowning(r, g, cr, cfg);
    }
    if let Some(w) = &g.worm_wheel {
        check_worm_wheel(r, w, o);
    }
    check_process_options(r, g, o);
    check_measurement(r, g);
    check_shift(r, plan, cfg);
    if plan.class == GearClass::MultiGear {
        check_units(r, plan, cfg);
    }
}

/// The class the gear's tables mark: at most one marker, not the curved
/// tooth (classified, not programmable), and radial-axial infeed only for
/// a cylindrical gear.
fn check_markers(r: &mut Report, g: &GearSpec, o: &ProcessOverrides) {
    let markers = unit_markers(g);
    if markers.len() > 1 {
        let names: Vec<&str> = markers.iter().map(|c| c.as_str()).collect();
        r.error(
            Code::CLASS_AMBIGUOUS,
            "gear",
            "at most one of cone, crowning, worm_wheel, curved_tooth",
            names.join(", "),
            "A gear belongs to exactly one class; keep the one table of [gear.cone], [gear.crowning], [gear.worm_wheel] or [gear.curved_tooth] that describes it.",
        );
    }
    if markers.contains(&GearClass::CurvedTooth) {
        r.error(
            Code::CLASS_NOT_PROGRAMMABLE,
            "gear.curved_tooth",
            "a programmable class: cylindrical, conical, crowned, worm_wheel or multi_gear",
            GearClass::CurvedTooth.as_str(),
            "Curved-tooth gears are classified (docs/knowledge.md#group-technology-classes) but not yet programmable: gearcam has no hobbing model for a curved tooth trace. Program this part by hand for now, or remove [gear.curved_tooth] if the trace is in fact straight.",
        );
    }
    let unit = gearcam_proto::class::unit_class(g);
    if o.infeed == Some(Infeed::RadialAxial) && unit != GearClass::Cylindrical {
        r.error(
            Code::CLASS_OPTION_UNSUPPORTED,
            "process.infeed",
            "axial for a conical, crowned or worm-wheel gear",
            "radial_axial",
            format!("Radial-axial infeed is programmed for cylindrical gears only; this gear is {unit}. Leave process.infeed out."),
        );
    }
}

/// A conical gear: a cone angle in (0°, 45°) whose root cone stays a cone
/// over the face width.
fn check_cone(r: &mut Report, g: &GearSpec, cone: &ConeSpec) {
    if !open(cone.angle_deg, 0.0, 45.0) {
        r.error(
            Code::CONE_ANGLE_RANGE,
            "gear.cone.angle_deg",
            "(0°, 45°)",
            format!("{}°", num(cone.angle_deg)),
            "The cone angle of a conical gear lies between 0° and 45° (seed 000's example: 6.5°); correct gear.cone.angle_deg.",
        );
    } else {
        // The root cone must stay a cone over the face width: its
        // diameter at the small end, df − 2·b·tan δ, above zero.
        let df = crate::geometry::geometry(g).df_mm;
        let taper = 2.0 * g.face_width_mm * cone.angle_deg.to_radians().tan();
        if !(df - taper > 0.0) {
            r.error(
                Code::CONE_ANGLE_RANGE,
                "gear.cone.angle_deg",
                format!(
                    "< {}° (the root cone reaches the axis within the face width)",
                    num((df / (2.0 * g.face_width_mm)).atan().to_degrees())
                ),
                format!("{}°", num(cone.angle_deg)),
                format!(
                    "Over the face width of {} mm the cone narrows the root diameter {} mm by {} mm, to nothing at the small end; correct gear.cone.angle_deg or gear.face_width_mm.",
                    num(g.face_width_mm),
                    num(df),
                    num(taper)
                ),
            );
        }
    }
}

/// A crowned gear: an amount between 0 and half the face width, and for a
/// parabolic crowning a chord tolerance that keeps the chords countable.
fn check_crowning(r: &mut Report, g: &GearSpec, cr: &CrowningSpec, cfg: &Config) {
    let half = g.face_width_mm / 2.0;
    if !(cr.amount_mm > 0.0 && cr.amount_mm < half) {
        r.error(
            Code::CROWNING_RANGE,
            "gear.crowning.amount_mm",
            format!("> 0 and < {} mm (half the face width)", num(half)),
            format!("{} mm", num(cr.amount_mm)),
            "The crowning amount is the small extra radial depth at each face against the middle (typically 0.01–0.05 mm); correct gear.crowning.amount_mm.",
        );
    } else if cr.shape == CrowningShape::Parabolic {
        let tol = cr
            .chord_tolerance_mm
            .unwrap_or(crate::path::DEFAULT_CHORD_TOLERANCE_MM);
        let chords = crate::path::parabolic_chords(cr.amount_mm, tol);
        if !(tol > 0.0) || chords > cfg.max_chords {
            r.error(
                Code::CHORD_TOLERANCE_RANGE,
                "gear.crowning.chord_tolerance_mm",
                format!(
                    "> 0 mm and at least {} mm (at most {} chords)",
                    num(cr.amount_mm / f64::from(cfg.max_chords).powi(2)),
                    cfg.max_chords
                ),
                format!("{} mm", num(tol)),
                "The chord tolerance of a parabolic crowning must be positive and not so fine that the program needs thousands of chords; correct gear.crowning.chord_tolerance_mm.",
            );
        }
    }
}

/// A worm wheel: positive radial and tangential feeds, a dwell of 0 or more
/// revolutions, and no hob shifting with tangential infeed.
fn check_worm_wheel(r: &mut Report, w: &WormWheelSpec, o: &ProcessOverrides) {
    check_positive(
        r,
        "gear.worm_wheel.radial_feed_mm_per_rev",
        w.radial_feed_mm_per_rev,
        "mm/rev",
        "radial feed",
    );
    check_positive(
        r,
        "gear.worm_wheel.tangential_feed_mm_per_rev",
        w.tangential_feed_mm_per_rev,
        "mm/rev",
        "tangential feed",
    );
    if let Some(d) = w.dwell_rev {
        if !(d >= 0.0 && d.is_finite()) {
            r.error(
                Code::DWELL_RANGE,
                "gear.worm_wheel.dwell_rev",
                "≥ 0 revolutions",
                num(d),
                "The dwell at the final centre distance is a number of wheel revolutions, 0 or more; correct gear.worm_wheel.dwell_rev.",
            );
        }
    }
    if w.infeed == WormInfeed::Tangential && o.shift.is_some() {
        r.error(
            Code::CLASS_OPTION_UNSUPPORTED,
            "process.shift",
            "no hob shifting with tangential infeed",
            "shift",
            "Tangential infeed already moves the hob along its axis; leave [process.shift] out.",
        );
    }
}

/// The process options of the class: positive finishing and radial feeds,
/// and a finish allowance within the whole depth.
fn check_process_options(r: &mut Report, g: &GearSpec, o: &ProcessOverrides) {
    check_positive(
        r,
        "process.finish_feed_mm_per_rev",
        o.finish_feed_mm_per_rev,
        "mm/rev",
        "finishing feed",
    );
    check_positive(
        r,
        "process.radial_feed_mm_per_rev",
        o.radial_feed_mm_per_rev,
        "mm/rev",
        "radial feed",
    );
    if let Some(a) = o.finish_allowance_mm {
        let whole = (2.0 * g.addendum_coef + g.clearance_coef) * g.module_mm;
        if !(a > 0.0 && a < whole) {
            r.error(
                Code::FINISH_ALLOWANCE_RANGE,
                "process.finish_allowance_mm",
                format!("> 0 and < {} mm (the whole depth)", num(whole)),
                format!("{} mm", num(a)),
                "The finish allowance is the radial stock the rough cuts leave (typically 0.1–0.5 mm); correct process.finish_allowance_mm.",
            );
        }
    }
}

/// The measurement data: a positive ball diameter, and a mating gear with
/// teeth, a finite profile shift and a positive centre distance.
fn check_measurement(r: &mut Report, g: &GearSpec) {
    if let Some(dm) = g.ball_diameter_mm {
        if !(dm > 0.0 && dm.is_finite()) {
            r.error(
                Code::BALL_DIAMETER_RANGE,
                "gear.ball_diameter_mm",
                "> 0 mm",
                format!("{} mm", num(dm)),
                "The ball diameter of the measurement over balls must be positive (about 1.7·mn); correct gear.ball_diameter_mm.",
            );
        }
    }
    if let Some(m) = &g.mate {
        let bad_a = m
            .centre_distance_mm
            .is_some_and(|a| !(a > 0.0 && a.is_finite()));
        if m.teeth < 1 || !m.profile_shift.is_finite() || bad_a {
            r.error(
                Code::MATE_RANGE,
                "gear.mate",
                "teeth ≥ 1, a finite profile shift and a positive centre distance",
                format!(
                    "teeth {}, profile shift {}, centre distance {}",
                    m.teeth,
                    num(m.profile_shift),
                    m.centre_distance_mm
                        .map(num)
                        .unwrap_or_else(|| "none".into())
                ),
                "Correct the mating gear's data in [gear.mate].",
            );
        }
    }
}

/// A feed given must be positive and finite (`FEED_RATE_RANGE`); `what`
/// names it in the message.
fn check_positive(r: &mut Report, field: &str, v: Option<f64>, unit: &str, what: &str) {
    if let Some(v) = v {
        if !(v > 0.0 && v.is_finite()) {
            r.error(
                Code::FEED_RATE_RANGE,
                field,
                format!("> 0 {unit}"),
                format!("{} {unit}", num(v)),
                format!("The {what} must be positive; correct {field}."),
            );
        }
    }
}

/// Hob shifting: positive step and parts per step, positions inside the
/// usable hob length.
pub(super) fn check_shift(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let Some(spec) = &plan.sections().process.shift else {
        return;
    };
    let hob = &plan.hob;
    if !(hob.length_mm > 0.0
        && open(hob.pressure_angle_deg, 0.0, 45.0)
        && open(hob.lead_angle_deg, 0.0, 45.0)
        && hob.module_mm > 0.0)
    {
        return; // the hob checks report this
    }
    let g = &plan.gear;
    let depth = plan
        .process
        .depth_mm
        .unwrap_or((2.0 * g.addendum_coef + g.clearance_coef) * g.module_mm);
    let res = crate::shift::Resolved::new(spec, hob, depth);
    let [lo, hi] = res.usable_mm;
    if hi < 0.0 {
        r.error(
            Code::HOB_TOO_SHORT_FOR_SHIFT,
            if hob.usable_length_mm.is_some() {
                "hob.usable_length_mm"
            } else {
                "hob.length_mm"
            },
            format!("≥ {} mm (the active length)", num(res.active_length_mm)),
            format!("{} mm", num(hob.usable_mm())),
            format!("Hob {} is shorter than its active length, so it cannot shift; leave [process.shift] out or use a longer hob.", hob.id),
        );
        return;
    }
    if !(res.step_mm > 0.0 && res.step_mm.is_finite()) {
        r.error(
            Code::SHIFT_RANGE,
            "process.shift.step_mm",
            "> 0 mm",
            format!("{} mm", num(res.step_mm)),
            "The shift per step must be positive; correct process.shift.step_mm.",
        );
    }
    if spec.parts_per_step == Some(0) {
        r.error(
            Code::SHIFT_RANGE,
            "process.shift.parts_per_step",
            "≥ 1",
            "0",
            "At least one part is cut per shift step; correct process.shift.parts_per_step.",
        );
    }
    let tol = cfg.length_tolerance_mm;
    for (field, v) in [
        ("process.shift.start_mm", res.start_mm),
        ("process.shift.end_mm", res.end_mm),
    ] {
        if !(v >= lo - tol && v <= hi + tol) {
            r.error(
                Code::SHIFT_RANGE,
                field,
                format!("{} to {} mm (usable hob length)", num(lo), num(hi)),
                format!("{} mm", num(v)),
                format!(
                    "Shift positions must keep the active length {} mm within the hob's usable {} mm (overall {} mm); correct {field} or leave it out.",
                    num(res.active_length_mm),
                    num(hob.usable_mm()),
                    num(hob.length_mm)
                ),
            );
        }
    }
}

/// The units of a multi-gear part: ascending, non-overlapping Z offsets, a
/// resolvable hob, and every check of a job for each unit (errors with the
/// unit's field names).
pub(super) fn check_units(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let mut top = plan.gear.face_width_mm;
    for (i, u) in plan.sections().units.iter().enumerate() {
        let field = format!("units[{i}].z_offset_mm");
        if !(u.z_offset_mm.is_finite() && u.z_offset_mm >= top - cfg.length_tolerance_mm) {
            r.error(
                Code::UNIT_RANGE,
                &field,
                format!("≥ {} mm (above the previous unit's upper face)", num(top)),
                format!("{} mm", num(u.z_offset_mm)),
                "Units are listed from the bottom up and must not overlap; correct the unit's z_offset_mm.",
            );
        }
        top = u.z_offset_mm + u.gear.face_width_mm;
        let hob = match crate::units::unit_hob(plan, i, u) {
            Ok(h) => h,
            Err(errors) => {
                r.errors.extend(errors);
                continue;
            }
        };
        let unit_plan = crate::units::unit_plan(plan, i, u, hob);
        let sub = validate_with(&unit_plan, cfg);
        let prefix = format!("units[{i}].");
        for mut e in sub.errors {
            if e.field.starts_with("gear") || e.field.starts_with("hob") {
                e.field = format!("{prefix}{}", e.field);
                e.message = format!("Unit {}: {}", i + 2, e.message);
                r.errors.push(e);
            }
        }
        for mut w in sub.warnings {
            w.field = format!("{prefix}{}", w.field);
            r.warnings.push(w);
        }
    }
}
