//! Validation of a process plan before and after the hobbing computation
//! (SPEC §4.2, patent step 2).
//!
//! [`validate`] runs every parameter check and the five physical checks of the
//! patent and reports all failures together; a check whose inputs already
//! failed a parameter check is skipped rather than reported with nonsense
//! numbers. [`check_limits`] runs after [`crate::hobbing::kinematics`] and
//! checks the computed speeds, feed, swivel and positions against the machine.
//!
//! # Tolerance policy
//!
//! Lengths compare with [`TOLERANCE_MM`] (1e-6 mm) in the job's favour, so a
//! job exactly at a limit passes; the base-pitch equality uses
//! [`BASE_PITCH_TOLERANCE_MM`] (1e-4 mm). Every comparison is written so that
//! a NaN fails it.

// Negated comparisons are deliberate here: written as `!(v <= max)`, a NaN
// fails the check instead of slipping through.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use gearcam_proto::{
    GearSpec, Geometry, HobData, JobError, Kinematics, Position, ProcessPlan, Stage, Warning,
};

use crate::geometry::{geometry, is_spur, lead_mm};
use crate::hobbing::{setup, Setup};

/// Numerical tolerance of length comparisons, mm.
pub const TOLERANCE_MM: f64 = 1e-6;

/// Tolerance of the base-pitch equality mn0·cos α0 = mn·cos αn, mm.
pub const BASE_PITCH_TOLERANCE_MM: f64 = 1e-4;

/// A blank OD that uses more than 1 − this fraction of its allowed deviation
/// from da (on its side of da) gets a [`codes::BLANK_OD_EDGE`] warning.
pub const EDGE_FRACTION: f64 = 0.1;

/// Stable error and warning codes of the model stage.
pub mod codes {
    /// Blank OD outside the window around the tip diameter (check 1).
    pub const BLANK_OD_WINDOW: &str = "BLANK_OD_WINDOW";
    /// Warning: blank OD near the edge of its window.
    pub const BLANK_OD_EDGE: &str = "BLANK_OD_EDGE";
    /// Cut depth not positive or deeper than the whole depth plus allowance (check 2).
    pub const CUT_DEPTH: &str = "CUT_DEPTH";
    /// Hob and gear normal base pitches differ (check 3).
    pub const BASE_PITCH_MISMATCH: &str = "BASE_PITCH_MISMATCH";
    /// Hob OD below d0 + 2·(ha* + c*)·mn0 (check 4).
    pub const HOB_OD_TOO_SMALL: &str = "HOB_OD_TOO_SMALL";
    /// Final centre distance below the theoretical one (check 5).
    pub const CENTRE_DISTANCE_TOO_SMALL: &str = "CENTRE_DISTANCE_TOO_SMALL";
    /// Teeth below 1.
    pub const TEETH_RANGE: &str = "TEETH_RANGE";
    /// Normal module not positive.
    pub const MODULE_RANGE: &str = "MODULE_RANGE";
    /// Gear pressure angle outside (0°, 45°).
    pub const PRESSURE_ANGLE_RANGE: &str = "PRESSURE_ANGLE_RANGE";
    /// Helix angle outside (−90°, 90°).
    pub const HELIX_RANGE: &str = "HELIX_RANGE";
    /// Helical gear without a helix hand.
    pub const HELIX_HAND_MISSING: &str = "HELIX_HAND_MISSING";
    /// Face width not positive.
    pub const FACE_WIDTH_RANGE: &str = "FACE_WIDTH_RANGE";
    /// Addendum coefficient not positive.
    pub const ADDENDUM_RANGE: &str = "ADDENDUM_RANGE";
    /// Tip clearance coefficient negative.
    pub const CLEARANCE_COEF_RANGE: &str = "CLEARANCE_COEF_RANGE";
    /// A value that must be a finite number is not.
    pub const NOT_FINITE: &str = "NOT_FINITE";
    /// Quantity below 1.
    pub const QUANTITY_RANGE: &str = "QUANTITY_RANGE";
    /// Feed per revolution not positive, or not below the helix lead.
    pub const FEED_RANGE: &str = "FEED_RANGE";
    /// Cutting speed not positive.
    pub const CUTTING_SPEED_RANGE: &str = "CUTTING_SPEED_RANGE";
    /// Safety distance negative.
    pub const SAFETY_RANGE: &str = "SAFETY_RANGE";
    /// More than one cut (this release programs one cut).
    pub const CUTS_UNSUPPORTED: &str = "CUTS_UNSUPPORTED";
    /// Hob starts below 1.
    pub const HOB_STARTS_RANGE: &str = "HOB_STARTS_RANGE";
    /// Hob OD not positive.
    pub const HOB_OD_RANGE: &str = "HOB_OD_RANGE";
    /// Hob module not positive.
    pub const HOB_MODULE_RANGE: &str = "HOB_MODULE_RANGE";
    /// Hob pressure angle outside (0°, 45°).
    pub const HOB_PRESSURE_ANGLE_RANGE: &str = "HOB_PRESSURE_ANGLE_RANGE";
    /// Hob lead angle outside (0°, 45°).
    pub const HOB_LEAD_ANGLE_RANGE: &str = "HOB_LEAD_ANGLE_RANGE";
    /// Hob length not positive.
    pub const HOB_LENGTH_RANGE: &str = "HOB_LENGTH_RANGE";
    /// A machine setting outside its range.
    pub const MACHINE_SETTING_RANGE: &str = "MACHINE_SETTING_RANGE";
    /// Gear module outside the machine's module range.
    pub const MACHINE_MODULE_LIMIT: &str = "MACHINE_MODULE_LIMIT";
    /// Blank OD above the machine's largest workpiece.
    pub const WORKPIECE_OD_LIMIT: &str = "WORKPIECE_OD_LIMIT";
    /// Hob OD above the machine's largest hob.
    pub const HOB_OD_LIMIT: &str = "HOB_OD_LIMIT";
    /// Computed hob speed above the machine's limit.
    pub const HOB_RPM_LIMIT: &str = "HOB_RPM_LIMIT";
    /// Computed table speed above the machine's limit.
    pub const TABLE_RPM_LIMIT: &str = "TABLE_RPM_LIMIT";
    /// Computed axial feed above the machine's limit.
    pub const AXIAL_FEED_LIMIT: &str = "AXIAL_FEED_LIMIT";
    /// Computed swivel angle above the machine's limit.
    pub const SWIVEL_LIMIT: &str = "SWIVEL_LIMIT";
    /// A computed position outside the machine's travel.
    pub const POSITION_TRAVEL_LIMIT: &str = "POSITION_TRAVEL_LIMIT";
}

/// The outcome of [`validate`]: every error and warning found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Failures; the plan must not be computed when there is any.
    pub errors: Vec<JobError>,
    /// Non-fatal findings, carried into the model.
    pub warnings: Vec<Warning>,
}

impl Report {
    /// True when there are no errors.
    pub fn is_ok(&self) -> bool {
        self.errors.is_empty()
    }

    /// The error codes in the order found (handy in tests and logs).
    pub fn codes(&self) -> Vec<&str> {
        self.errors.iter().map(|e| e.code.as_str()).collect()
    }

    fn error(
        &mut self,
        code: &str,
        field: &str,
        expected: impl Into<String>,
        got: impl Into<String>,
        message: impl Into<String>,
    ) {
        self.errors
            .push(job_error(code, field, expected, got, message));
    }
}

fn job_error(
    code: &str,
    field: &str,
    expected: impl Into<String>,
    got: impl Into<String>,
    message: impl Into<String>,
) -> JobError {
    JobError {
        stage: Stage::Model,
        code: code.into(),
        field: field.into(),
        expected: expected.into(),
        got: got.into(),
        message: message.into(),
    }
}

/// A number as text: up to six decimals, trailing zeros removed.
pub fn num(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// True when `v` lies in the open interval (lo, hi); false for NaN.
fn open(v: f64, lo: f64, hi: f64) -> bool {
    v > lo && v < hi
}

/// Runs every pre-computation check of a plan and reports all failures
/// together (SPEC §4.2).
///
/// Parameter checks: teeth, module, pressure angles, helix angle and hand,
/// face width, coefficients, quantity, feed, cutting speed, safety, cuts (one
/// in this release), hob starts, OD, module, lead angle and length, machine
/// settings and machine limits (module, workpiece OD, hob OD).
///
/// Physical checks (patent step 2, in standard form), each skipped when its
/// inputs failed a parameter check:
///
/// 1. `BLANK_OD_WINDOW`: da − below ≤ Da1 ≤ da + above (`machine.settings`).
/// 2. `CUT_DEPTH`: 0 < h ≤ (2·ha* + c*)·mn − (da − Da1)/2 + allowance, i.e. the
///    whole depth for a blank at da, and in general a cut root D − 2h no more
///    than 2·allowance under df.
/// 3. `BASE_PITCH_MISMATCH`: |mn0·cos α0 − mn·cos αn| ≤ 1e-4 mm.
/// 4. `HOB_OD_TOO_SMALL`: da0 ≥ d0 + 2·(ha* + c*)·mn0, d0 = z0·mn0 / sin γ0.
/// 5. `CENTRE_DISTANCE_TOO_SMALL`: (da0 + Da1)/2 − h ≥ d0/2 + (d·cos αn / cos α0)/2 + x·mn.
///
/// Warning `BLANK_OD_EDGE` when the blank uses more than 90 % of its allowed
/// deviation from da.
pub fn validate(plan: &ProcessPlan) -> Report {
    let mut report = Report::default();
    let gear = &plan.request.spec.gear;
    let gear_ok = check_gear(&mut report, gear);
    let hob_ok = check_hob(&mut report, &plan.hob);
    check_process(&mut report, plan, gear_ok);
    let settings_ok = check_machine_settings(&mut report, plan);

    let mut geo = None;
    if gear_ok {
        let g = geometry(gear);
        check_machine_limits(&mut report, plan, &g);
        geo = Some(g);
    } else {
        check_hob_od_limit(&mut report, plan);
    }

    if let (Some(g), true) = (&geo, settings_ok) {
        check_blank_window(&mut report, plan, g);
    }
    if hob_ok && gear_ok {
        check_base_pitch(&mut report, gear, &plan.hob);
        check_hob_od(&mut report, gear, &plan.hob);
    }
    if let (Some(g), true, true) = (&geo, hob_ok, settings_ok) {
        let set = setup(plan, g);
        check_depth(&mut report, plan, g, &set);
        check_centre_distance(&mut report, &set);
    }
    report
}

fn check_gear(r: &mut Report, g: &GearSpec) -> bool {
    if g.teeth < 1 {
        r.error(
            codes::TEETH_RANGE,
            "gear.teeth",
            "≥ 1",
            g.teeth.to_string(),
            "The gear needs at least one tooth; correct the number of teeth in the job.",
        );
    }
    if !(g.module_mm > 0.0 && g.module_mm.is_finite()) {
        r.error(
            codes::MODULE_RANGE,
            "gear.module_mm",
            "> 0 mm",
            format!("{} mm", num(g.module_mm)),
            "The normal module must be a positive length; correct gear.module_mm.",
        );
    }
    if !open(g.pressure_angle_deg, 0.0, 45.0) {
        r.error(
            codes::PRESSURE_ANGLE_RANGE,
            "gear.pressure_angle_deg",
            "(0°, 45°)",
            format!("{}°", num(g.pressure_angle_deg)),
            "The normal pressure angle must lie between 0° and 45° (usually 20°); correct gear.pressure_angle_deg.",
        );
    }
    if !open(g.helix_angle_deg, -90.0, 90.0) {
        r.error(
            codes::HELIX_RANGE,
            "gear.helix_angle_deg",
            "(-90°, 90°)",
            format!("{}°", num(g.helix_angle_deg)),
            "The helix angle must lie strictly between -90° and 90° (0 for a spur gear); correct gear.helix_angle_deg.",
        );
    } else if !is_spur(g) && g.helix_hand.is_none() {
        r.error(
            codes::HELIX_HAND_MISSING,
            "gear.helix_hand",
            "right or left",
            "none",
            "A helical gear needs its helix hand to set the hob swivel and the differential; add helix_hand = \"right\" or \"left\" to [gear].",
        );
    }
    if !(g.face_width_mm > 0.0 && g.face_width_mm.is_finite()) {
        r.error(
            codes::FACE_WIDTH_RANGE,
            "gear.face_width_mm",
            "> 0 mm",
            format!("{} mm", num(g.face_width_mm)),
            "The face width must be a positive length; correct gear.face_width_mm.",
        );
    }
    if !(g.addendum_coef > 0.0 && g.addendum_coef.is_finite()) {
        r.error(
            codes::ADDENDUM_RANGE,
            "gear.addendum_coef",
            "> 0",
            num(g.addendum_coef),
            "The addendum coefficient ha* must be positive (usually 1); correct gear.addendum_coef.",
        );
    }
    if !(g.clearance_coef >= 0.0 && g.clearance_coef.is_finite()) {
        r.error(
            codes::CLEARANCE_COEF_RANGE,
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
                codes::NOT_FINITE,
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

fn check_hob(r: &mut Report, h: &HobData) -> bool {
    let before = r.errors.len();
    if h.starts < 1 {
        r.error(
            codes::HOB_STARTS_RANGE,
            "hob.starts",
            "≥ 1",
            h.starts.to_string(),
            "A hob has at least one start; correct the hob's number of starts.",
        );
    }
    if !(h.od_mm > 0.0 && h.od_mm.is_finite()) {
        r.error(
            codes::HOB_OD_RANGE,
            "hob.od_mm",
            "> 0 mm",
            format!("{} mm", num(h.od_mm)),
            "The hob outside diameter must be a positive length; correct the hob data.",
        );
    }
    if !(h.module_mm > 0.0 && h.module_mm.is_finite()) {
        r.error(
            codes::HOB_MODULE_RANGE,
            "hob.module_mm",
            "> 0 mm",
            format!("{} mm", num(h.module_mm)),
            "The hob module must be a positive length; correct the hob data.",
        );
    }
    if !open(h.pressure_angle_deg, 0.0, 45.0) {
        r.error(
            codes::HOB_PRESSURE_ANGLE_RANGE,
            "hob.pressure_angle_deg",
            "(0°, 45°)",
            format!("{}°", num(h.pressure_angle_deg)),
            "The hob pressure angle must lie between 0° and 45°; correct the hob data.",
        );
    }
    if !open(h.lead_angle_deg, 0.0, 45.0) {
        r.error(
            codes::HOB_LEAD_ANGLE_RANGE,
            "hob.lead_angle_deg",
            "(0°, 45°)",
            format!("{}°", num(h.lead_angle_deg)),
            "The hob lead angle must lie between 0° and 45° (a few degrees for a usual hob); correct the hob data.",
        );
    }
    if !(h.length_mm > 0.0 && h.length_mm.is_finite()) {
        r.error(
            codes::HOB_LENGTH_RANGE,
            "hob.length_mm",
            "> 0 mm",
            format!("{} mm", num(h.length_mm)),
            "The hob length must be a positive length; correct the hob data.",
        );
    }
    r.errors.len() == before
}

fn check_process(r: &mut Report, plan: &ProcessPlan, gear_ok: bool) {
    let p = &plan.process;
    let quantity = plan.request.spec.job.quantity;
    if quantity < 1 {
        r.error(
            codes::QUANTITY_RANGE,
            "job.quantity",
            "≥ 1",
            quantity.to_string(),
            "A job makes at least one part; correct job.quantity.",
        );
    }
    if p.cuts != 1 {
        r.error(
            codes::CUTS_UNSUPPORTED,
            "process.cuts",
            "1",
            p.cuts.to_string(),
            "This release programs exactly one cut; set process.cuts = 1 (several cuts come later).",
        );
    }
    if !(p.cutting_speed_m_min > 0.0 && p.cutting_speed_m_min.is_finite()) {
        r.error(
            codes::CUTTING_SPEED_RANGE,
            "process.cutting_speed_m_min",
            "> 0 m/min",
            format!("{} m/min", num(p.cutting_speed_m_min)),
            "The cutting speed must be positive; set process.cutting_speed_m_min or let the knowledge base propose it.",
        );
    }
    if !(p.feed_mm_per_rev > 0.0 && p.feed_mm_per_rev.is_finite()) {
        r.error(
            codes::FEED_RANGE,
            "process.feed_mm_per_rev",
            "> 0 mm/rev",
            format!("{} mm/rev", num(p.feed_mm_per_rev)),
            "The axial feed per workpiece revolution must be positive; set process.feed_mm_per_rev or let the knowledge base propose it.",
        );
    } else if gear_ok {
        if let Some(pz) = lead_mm(&plan.request.spec.gear) {
            if !(p.feed_mm_per_rev < pz) {
                r.error(
                    codes::FEED_RANGE,
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
            codes::SAFETY_RANGE,
            "process.safety_mm",
            "≥ 0 mm",
            format!("{} mm", num(p.safety_mm)),
            "The safety distance must not be negative; correct process.safety_mm.",
        );
    }
}

fn check_machine_settings(r: &mut Report, plan: &ProcessPlan) -> bool {
    let before = r.errors.len();
    let s = &plan.machine.settings;
    for (name, v) in [
        ("blank_od_below_mm", s.blank_od_below_mm),
        ("blank_od_above_mm", s.blank_od_above_mm),
        ("depth_allowance_mm", s.depth_allowance_mm),
        ("retract_mm", s.retract_mm),
        ("exit_mm", s.exit_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            r.error(
                codes::MACHINE_SETTING_RANGE,
                &format!("machine.settings.{name}"),
                "≥ 0 mm",
                format!("{} mm", num(v)),
                format!(
                    "Machine {}'s setting {name} must not be negative; correct the machine profile in the knowledge base.",
                    plan.machine.id
                ),
            );
        }
    }
    if s.swivel_sign != 1.0 && s.swivel_sign != -1.0 {
        r.error(
            codes::MACHINE_SETTING_RANGE,
            "machine.settings.swivel_sign",
            "1 or -1",
            num(s.swivel_sign),
            format!(
                "Machine {}'s swivel sign must be 1 or -1; correct the machine profile in the knowledge base.",
                plan.machine.id
            ),
        );
    }
    r.errors.len() == before
}

fn check_machine_limits(r: &mut Report, plan: &ProcessPlan, geo: &Geometry) {
    let gear = &plan.request.spec.gear;
    let lim = &plan.machine.limits;
    let id = &plan.machine.id;
    let [lo, hi] = lim.module_mm;
    let mn = gear.module_mm;
    if !(mn >= lo - TOLERANCE_MM && mn <= hi + TOLERANCE_MM) {
        r.error(
            codes::MACHINE_MODULE_LIMIT,
            "gear.module_mm",
            format!("{} to {} mm", num(lo), num(hi)),
            format!("{} mm", num(mn)),
            format!("Machine {id} cuts modules from {} to {} mm only; choose another machine for this gear.", num(lo), num(hi)),
        );
    }
    let blank = gear.blank_od_mm.unwrap_or(geo.da_mm);
    if !(blank <= lim.max_workpiece_od_mm + TOLERANCE_MM) {
        r.error(
            codes::WORKPIECE_OD_LIMIT,
            "gear.blank_od_mm",
            format!("≤ {} mm", num(lim.max_workpiece_od_mm)),
            format!("{} mm", num(blank)),
            format!("The blank is larger than machine {id} takes; choose a larger machine."),
        );
    }
    check_hob_od_limit(r, plan);
}

fn check_hob_od_limit(r: &mut Report, plan: &ProcessPlan) {
    let lim = &plan.machine.limits;
    let od = plan.hob.od_mm;
    if od.is_finite() && !(od <= lim.max_hob_od_mm + TOLERANCE_MM) {
        r.error(
            codes::HOB_OD_LIMIT,
            "hob.od_mm",
            format!("≤ {} mm", num(lim.max_hob_od_mm)),
            format!("{} mm", num(od)),
            format!(
                "Hob {} is larger than machine {}'s hob head takes; choose a smaller hob or another machine.",
                plan.hob.id, plan.machine.id
            ),
        );
    }
}

/// Check 1: the blank OD lies in [da − below, da + above]; warns near an edge.
fn check_blank_window(r: &mut Report, plan: &ProcessPlan, geo: &Geometry) {
    let s = &plan.machine.settings;
    let da = geo.da_mm;
    let blank = blank_od(plan, geo);
    let (lo, hi) = (da - s.blank_od_below_mm, da + s.blank_od_above_mm);
    if !(blank >= lo - TOLERANCE_MM && blank <= hi + TOLERANCE_MM) {
        r.error(
            codes::BLANK_OD_WINDOW,
            "gear.blank_od_mm",
            format!("{} to {} mm (tip diameter da {} mm)", num(lo), num(hi), num(da)),
            format!("{} mm", num(blank)),
            format!(
                "The blank OD must lie between {} mm under and {} mm over the tip diameter; turn the blank to size or correct gear.blank_od_mm.",
                num(s.blank_od_below_mm),
                num(s.blank_od_above_mm)
            ),
        );
        return;
    }
    let dev = blank - da;
    let allowed = if dev < 0.0 {
        s.blank_od_below_mm
    } else {
        s.blank_od_above_mm
    };
    if allowed > 0.0 && dev.abs() > (1.0 - EDGE_FRACTION) * allowed {
        r.warnings.push(Warning {
            code: codes::BLANK_OD_EDGE.into(),
            field: "gear.blank_od_mm".into(),
            message: format!(
                "The blank OD {} mm is within {} % of the edge of its window {} to {} mm; check the blank before cutting.",
                num(blank),
                num(EDGE_FRACTION * 100.0),
                num(lo),
                num(hi)
            ),
        });
    }
}

fn blank_od(plan: &ProcessPlan, geo: &Geometry) -> f64 {
    plan.request.spec.gear.blank_od_mm.unwrap_or(geo.da_mm)
}

/// Check 2: 0 < h ≤ whole depth − (da − Da1)/2 + allowance.
fn check_depth(r: &mut Report, plan: &ProcessPlan, geo: &Geometry, set: &Setup) {
    let h = set.depth_mm;
    let allowance = plan.machine.settings.depth_allowance_mm;
    let max = geo.whole_depth_mm - (geo.da_mm - set.blank_od_mm) / 2.0 + allowance;
    if h > TOLERANCE_MM && h <= max + TOLERANCE_MM {
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
        codes::CUT_DEPTH,
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
fn check_base_pitch(r: &mut Report, gear: &GearSpec, hob: &HobData) {
    let a0 = hob.pressure_angle_deg.to_radians().cos();
    let gear_pitch = gear.module_mm * gear.pressure_angle_deg.to_radians().cos();
    let hob_pitch = hob.module_mm * a0;
    if (hob_pitch - gear_pitch).abs() <= BASE_PITCH_TOLERANCE_MM {
        return;
    }
    r.error(
        codes::BASE_PITCH_MISMATCH,
        "hob.module_mm",
        format!(
            "mn0·cos α0 = {} mm ± {} mm (hob module {} mm at α0 {}°)",
            num(gear_pitch),
            num(BASE_PITCH_TOLERANCE_MM),
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
fn check_hob_od(r: &mut Report, gear: &GearSpec, hob: &HobData) {
    let d0 = crate::hobbing::hob_reference_diameter_mm(hob);
    let min = d0 + 2.0 * (gear.addendum_coef + gear.clearance_coef) * hob.module_mm;
    if hob.od_mm >= min - TOLERANCE_MM {
        return;
    }
    r.error(
        codes::HOB_OD_TOO_SMALL,
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
fn check_centre_distance(r: &mut Report, set: &Setup) {
    let l = set.centre_distance_mm;
    let theory = set.theoretical_centre_distance_mm;
    if l >= theory - TOLERANCE_MM {
        return;
    }
    r.error(
        codes::CENTRE_DISTANCE_TOO_SMALL,
        "process.depth_mm",
        format!("centre distance ≥ {} mm (depth ≤ {} mm)", num(theory), num(set.depth_mm - (theory - l))),
        format!("centre distance {} mm (depth {} mm)", num(l), num(set.depth_mm)),
        "The final centre distance is below the theoretical one, so the teeth would be cut thin; reduce process.depth_mm or leave it out to use the theoretical depth.",
    );
}

/// Checks computed kinematics against the machine's limits: hob and table
/// speed, axial feed, swivel and the travel of every position A–E.
pub fn check_limits(plan: &ProcessPlan, k: &Kinematics) -> Vec<JobError> {
    let lim = &plan.machine.limits;
    let id = &plan.machine.id;
    let mut errors = Vec::new();
    let mut over = |code: &str, field: &str, v: f64, max: f64, unit: &str, todo: &str| {
        if !(v.abs() <= max + TOLERANCE_MM) {
            errors.push(job_error(
                code,
                field,
                format!("≤ {} {unit}", num(max)),
                format!("{} {unit}", num(v)),
                format!(
                    "Machine {id} allows at most {} {unit} here; {todo}.",
                    num(max)
                ),
            ));
        }
    };
    over(
        codes::HOB_RPM_LIMIT,
        "model.hob_rpm",
        k.hob_rpm,
        lim.max_hob_rpm,
        "rpm",
        "lower process.cutting_speed_m_min or use a hob of larger diameter",
    );
    over(
        codes::TABLE_RPM_LIMIT,
        "model.table_rpm",
        k.table_rpm,
        lim.max_table_rpm,
        "rpm",
        "lower process.cutting_speed_m_min or use a hob with fewer starts",
    );
    over(
        codes::AXIAL_FEED_LIMIT,
        "model.axial_feed_mm_min",
        k.axial_feed_mm_min,
        lim.max_axial_feed_mm_min,
        "mm/min",
        "lower process.feed_mm_per_rev or the cutting speed",
    );
    over(
        codes::SWIVEL_LIMIT,
        "model.swivel_axis_deg",
        k.swivel_axis_deg,
        lim.max_swivel_deg,
        "°",
        "use a hob of the same hand as the gear helix or another machine",
    );
    let p = &k.positions;
    for (name, pos) in [("A", p.A), ("B", p.B), ("C", p.C), ("D", p.D), ("E", p.E)] {
        check_travel(&mut errors, plan, name, pos);
    }
    errors
}

fn check_travel(errors: &mut Vec<JobError>, plan: &ProcessPlan, name: &str, pos: Position) {
    let lim = &plan.machine.limits;
    for (axis, v, [lo, hi]) in [("x", pos.x_mm, lim.x_mm), ("z", pos.z_mm, lim.z_mm)] {
        if v >= lo - TOLERANCE_MM && v <= hi + TOLERANCE_MM {
            continue;
        }
        let todo = if name == "A" {
            "correct the machine's home position in its profile"
        } else if axis == "x" {
            "check the blank and hob diameters, gear.od_correction_mm and the retract and exit distances"
        } else {
            "check gear.fixture_height_mm, the face width and the safety distance"
        };
        errors.push(job_error(
            codes::POSITION_TRAVEL_LIMIT,
            &format!("model.positions.{name}.{axis}_mm"),
            format!("{} to {} mm", num(lo), num(hi)),
            format!("{} mm", num(v)),
            format!(
                "Position {name} lies outside machine {}'s {} travel; {todo}.",
                plan.machine.id,
                axis.to_uppercase()
            ),
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures;
    use crate::hobbing::{hob_reference_diameter_mm, kinematics};
    use gearcam_proto::Hand;

    fn codes_of(plan: &ProcessPlan) -> Vec<String> {
        validate(plan).errors.into_iter().map(|e| e.code).collect()
    }

    #[test]
    fn fixture_plan_passes_without_warnings() {
        let report = validate(&fixtures::plan());
        assert!(report.is_ok(), "{:?}", report.errors);
        assert!(report.warnings.is_empty(), "{:?}", report.warnings);
        let report = validate(&fixtures::helical_plan(15.0, Hand::Left));
        assert!(report.is_ok(), "{:?}", report.errors);
    }

    #[test]
    fn hob_module_2_5_for_module_3_gear_is_a_base_pitch_mismatch() {
        let mut plan = fixtures::plan();
        plan.hob.module_mm = 2.5;
        let report = validate(&plan);
        let e = report
            .errors
            .iter()
            .find(|e| e.code == codes::BASE_PITCH_MISMATCH)
            .expect("BASE_PITCH_MISMATCH reported");
        assert_eq!(e.stage, Stage::Model);
        assert_eq!(e.field, "hob.module_mm");
        // 3·cos 20° = 2.819078 mm, 2.5·cos 20° = 2.349232 mm.
        assert_eq!(
            e.expected,
            "mn0·cos α0 = 2.819078 mm ± 0.0001 mm (hob module 3 mm at α0 20°)"
        );
        assert_eq!(
            e.got,
            "mn0·cos α0 = 2.349232 mm (hob module 2.5 mm, α0 20°)"
        );
        assert!(e.message.contains("choose a matching hob"), "{}", e.message);
        // d0 = 2.5/sin 2.3716° = 60.4151 mm, so the default depth
        // (80 + 81)/2 − (d0/2 + 37.5) = 12.7925 mm is too deep as well.
        assert_eq!(report.codes(), vec!["BASE_PITCH_MISMATCH", "CUT_DEPTH"]);
    }

    #[test]
    fn reports_several_failures_together() {
        let mut plan = fixtures::plan();
        plan.hob.module_mm = 2.5;
        plan.process.cuts = 2;
        plan.process.feed_mm_per_rev = 0.0;
        plan.process.cutting_speed_m_min = f64::NAN;
        plan.request.spec.job.quantity = 0;
        plan.request.spec.gear.blank_od_mm = Some(70.0);
        plan.hob.lead_angle_deg = 50.0;
        assert_eq!(
            codes_of(&plan),
            vec![
                "HOB_LEAD_ANGLE_RANGE",
                "QUANTITY_RANGE",
                "CUTS_UNSUPPORTED",
                "CUTTING_SPEED_RANGE",
                "FEED_RANGE",
                "BLANK_OD_WINDOW",
            ]
        );
        // With a valid lead angle the hob checks run too.
        plan.hob.lead_angle_deg = 2.3716;
        assert_eq!(
            codes_of(&plan),
            vec![
                "QUANTITY_RANGE",
                "CUTS_UNSUPPORTED",
                "CUTTING_SPEED_RANGE",
                "FEED_RANGE",
                "BLANK_OD_WINDOW",
                "BASE_PITCH_MISMATCH",
                "CUT_DEPTH",
            ]
        );
    }

    #[test]
    fn blank_od_exactly_at_the_window_edges_passes_with_a_warning() {
        // da = 81 mm; window 79 to 81.5 mm.
        for blank in [79.0, 81.5] {
            let mut g = fixtures::gear();
            g.blank_od_mm = Some(blank);
            let report = validate(&fixtures::plan_with(g));
            assert!(report.is_ok(), "{blank}: {:?}", report.errors);
            assert_eq!(report.warnings.len(), 1);
            assert_eq!(report.warnings[0].code, "BLANK_OD_EDGE");
            assert_eq!(report.warnings[0].field, "gear.blank_od_mm");
        }
        // 1.7 mm under uses 85 % of the 2 mm allowance: no warning.
        let mut g = fixtures::gear();
        g.blank_od_mm = Some(79.3);
        let report = validate(&fixtures::plan_with(g));
        assert!(report.is_ok() && report.warnings.is_empty(), "{report:?}");
    }

    #[test]
    fn blank_od_outside_the_window_fails() {
        let mut g = fixtures::gear();
        g.blank_od_mm = Some(78.99);
        let report = validate(&fixtures::plan_with(g));
        assert_eq!(report.codes(), vec!["BLANK_OD_WINDOW"]);
        let e = &report.errors[0];
        assert_eq!(e.field, "gear.blank_od_mm");
        assert_eq!(e.expected, "79 to 81.5 mm (tip diameter da 81 mm)");
        assert_eq!(e.got, "78.99 mm");
    }

    #[test]
    fn default_depth_sits_exactly_at_the_theoretical_centre_distance() {
        let plan = fixtures::plan();
        let geo = geometry(&plan.request.spec.gear);
        let set = setup(&plan, &geo);
        assert!(!set.depth_given);
        assert_eq!(set.centre_distance_mm, set.theoretical_centre_distance_mm);
        // Giving that depth explicitly passes too.
        let mut given = fixtures::plan();
        given.process.depth_mm = Some(set.depth_mm);
        assert!(validate(&given).is_ok());
    }

    #[test]
    fn deeper_depth_cuts_thin_teeth_and_too_deep_depth_cuts_the_root() {
        // Whole depth 6.75 + allowance 0.5 = 7.25 mm passes check 2 exactly,
        // but any depth beyond 6.750963 mm makes L smaller than the theory.
        let mut plan = fixtures::plan();
        plan.process.depth_mm = Some(7.25);
        assert_eq!(codes_of(&plan), vec!["CENTRE_DISTANCE_TOO_SMALL"]);
        plan.process.depth_mm = Some(7.26);
        assert_eq!(
            codes_of(&plan),
            vec!["CUT_DEPTH", "CENTRE_DISTANCE_TOO_SMALL"]
        );
        let report = validate(&plan);
        assert_eq!(report.errors[0].field, "process.depth_mm");
        assert_eq!(
            report.errors[0].expected,
            "> 0 and ≤ 7.25 mm (whole depth 6.75 mm for the blank, + allowance 0.5 mm)"
        );
        plan.process.depth_mm = Some(0.0);
        assert_eq!(codes_of(&plan), vec!["CUT_DEPTH"]);
    }

    #[test]
    fn hob_od_exactly_at_its_minimum_passes() {
        let mut plan = fixtures::plan();
        let min = hob_reference_diameter_mm(&plan.hob) + 2.0 * 1.25 * 3.0;
        plan.hob.od_mm = min;
        assert!(validate(&plan).is_ok(), "{:?}", validate(&plan).errors);
        plan.hob.od_mm = min - 0.01;
        let report = validate(&plan);
        assert_eq!(report.codes(), vec!["HOB_OD_TOO_SMALL"]);
        assert_eq!(report.errors[0].field, "hob.od_mm");
    }

    #[test]
    fn helical_gear_needs_a_hand_and_a_sane_angle() {
        let mut g = fixtures::gear();
        g.helix_angle_deg = 15.0;
        assert_eq!(
            codes_of(&fixtures::plan_with(g.clone())),
            vec!["HELIX_HAND_MISSING"]
        );
        g.helix_angle_deg = 90.0;
        assert_eq!(codes_of(&fixtures::plan_with(g)), vec!["HELIX_RANGE"]);
    }

    #[test]
    fn broken_gear_parameters_skip_the_physical_checks() {
        let mut g = fixtures::gear();
        g.teeth = 0;
        g.module_mm = -3.0;
        g.face_width_mm = 0.0;
        assert_eq!(
            codes_of(&fixtures::plan_with(g)),
            vec!["TEETH_RANGE", "MODULE_RANGE", "FACE_WIDTH_RANGE"]
        );
    }

    #[test]
    fn machine_limits_before_computation() {
        let mut plan = fixtures::plan();
        plan.machine.limits.module_mm = [0.5, 2.0];
        plan.machine.limits.max_workpiece_od_mm = 80.0;
        plan.machine.limits.max_hob_od_mm = 70.0;
        let report = validate(&plan);
        assert_eq!(
            report.codes(),
            vec!["MACHINE_MODULE_LIMIT", "WORKPIECE_OD_LIMIT", "HOB_OD_LIMIT"]
        );
        assert_eq!(report.errors[0].expected, "0.5 to 2 mm");
        assert_eq!(report.errors[0].got, "3 mm");
    }

    #[test]
    fn limits_after_computation() {
        let mut plan = fixtures::plan();
        plan.machine.home_x_mm = 500.0;
        plan.request.spec.gear.fixture_height_mm = 380.0;
        let k = kinematics(&plan, &geometry(&plan.request.spec.gear));
        let errors = check_limits(&plan, &k);
        let fields: Vec<_> = errors.iter().map(|e| e.field.as_str()).collect();
        // Top = 380 + 30 + 22.2035 + 2 = 434.2 mm > 400 at B and C.
        assert_eq!(
            fields,
            vec![
                "model.positions.A.x_mm",
                "model.positions.B.z_mm",
                "model.positions.C.z_mm"
            ]
        );
        assert!(errors.iter().all(|e| e.code == "POSITION_TRAVEL_LIMIT"));
        assert_eq!(errors[0].expected, "0 to 400 mm");
        assert_eq!(errors[0].got, "500 mm");
    }

    #[test]
    fn swivel_beyond_the_machine_is_reported_after_computation() {
        // β 44° opposite to the hob: γ = −(44 + 2.3716) = −46.3716°, |γ| > 45°.
        let plan = fixtures::helical_plan(44.0, Hand::Left);
        assert!(validate(&plan).is_ok());
        let errors = crate::compute(&plan).unwrap_err();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!(errors[0].code, "SWIVEL_LIMIT");
        assert_eq!(errors[0].got, "-46.3716 °");
    }

    #[test]
    fn numbers_print_plainly() {
        assert_eq!(num(80.0), "80");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(-0.0000001), "0");
        assert_eq!(num(1.0 / 3.0), "0.333333");
        assert_eq!(num(f64::NAN), "NaN");
    }
}
