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

use gearcam_proto::class::unit_markers;
use gearcam_proto::{
    classify, CrowningShape, GearClass, GearSpec, Geometry, HobData, Infeed, JobError, Kinematics,
    MachineProfile, Move, Position, ProcessPlan, Stage, Warning, WormInfeed,
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

/// Most cuts a job may ask for.
pub const MAX_CUTS: u32 = 6;

/// Tolerances and windows of validation for one machine (SPEC §4.2).
///
/// The windows come from the machine profile's settings
/// ([`Config::for_machine`]); the tolerances default to [`TOLERANCE_MM`],
/// [`BASE_PITCH_TOLERANCE_MM`] and [`EDGE_FRACTION`]; [`Config::default`] is
/// the documented default machine: blank OD 2 mm under to 0.5 mm over da
/// (the patent allows 1–2 mm under), depth allowance 0.5 mm, at most
/// [`MAX_CUTS`] cuts and [`crate::path::MAX_CHORDS`] chords.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// Tolerance of length comparisons, in the job's favour, mm.
    pub length_tolerance_mm: f64,
    /// Tolerance of the base-pitch equality, mm.
    pub base_pitch_tolerance_mm: f64,
    /// A blank using more than 1 − this fraction of its window is warned about.
    pub edge_fraction: f64,
    /// The blank OD may lie this far under da, mm.
    pub blank_od_below_mm: f64,
    /// The blank OD may lie this far over da, mm.
    pub blank_od_above_mm: f64,
    /// The depth may exceed the whole depth by this much, mm.
    pub depth_allowance_mm: f64,
    /// Most cuts.
    pub max_cuts: u32,
    /// Most chords of a parabolic crowning.
    pub max_chords: u32,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            length_tolerance_mm: TOLERANCE_MM,
            base_pitch_tolerance_mm: BASE_PITCH_TOLERANCE_MM,
            edge_fraction: EDGE_FRACTION,
            blank_od_below_mm: 2.0,
            blank_od_above_mm: 0.5,
            depth_allowance_mm: 0.5,
            max_cuts: MAX_CUTS,
            max_chords: crate::path::MAX_CHORDS,
        }
    }
}

impl Config {
    /// The defaults with the machine profile's windows (blank OD and depth
    /// allowance).
    pub fn for_machine(machine: &MachineProfile) -> Config {
        let s = &machine.settings;
        Config {
            blank_od_below_mm: s.blank_od_below_mm,
            blank_od_above_mm: s.blank_od_above_mm,
            depth_allowance_mm: s.depth_allowance_mm,
            ..Config::default()
        }
    }
}

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
    /// Number of cuts outside 1 to the most cuts.
    pub const CUTS_RANGE: &str = "CUTS_RANGE";
    /// Finish allowance not positive or not below the depth.
    pub const FINISH_ALLOWANCE_RANGE: &str = "FINISH_ALLOWANCE_RANGE";
    /// Radial, tangential or finishing feed not positive.
    pub const FEED_RATE_RANGE: &str = "FEED_RATE_RANGE";
    /// The gear is classified into a class that cannot be programmed yet.
    pub const CLASS_NOT_PROGRAMMABLE: &str = "CLASS_NOT_PROGRAMMABLE";
    /// The gear carries the markers of more than one class.
    pub const CLASS_AMBIGUOUS: &str = "CLASS_AMBIGUOUS";
    /// An option that the gear's class does not support.
    pub const CLASS_OPTION_UNSUPPORTED: &str = "CLASS_OPTION_UNSUPPORTED";
    /// Cone angle outside (0°, 45°) or a cone that ends below the root.
    pub const CONE_ANGLE_RANGE: &str = "CONE_ANGLE_RANGE";
    /// Crowning amount outside (0, b/2).
    pub const CROWNING_RANGE: &str = "CROWNING_RANGE";
    /// Chord tolerance not positive or needing too many chords.
    pub const CHORD_TOLERANCE_RANGE: &str = "CHORD_TOLERANCE_RANGE";
    /// Worm wheel dwell negative.
    pub const DWELL_RANGE: &str = "DWELL_RANGE";
    /// Shift settings outside the usable hob length or not positive.
    pub const SHIFT_RANGE: &str = "SHIFT_RANGE";
    /// The hob is too short to shift at all.
    pub const HOB_TOO_SHORT_FOR_SHIFT: &str = "HOB_TOO_SHORT_FOR_SHIFT";
    /// Ball diameter not positive.
    pub const BALL_DIAMETER_RANGE: &str = "BALL_DIAMETER_RANGE";
    /// Mating gear data out of range.
    pub const MATE_RANGE: &str = "MATE_RANGE";
    /// A unit of a multi-gear part is out of range.
    pub const UNIT_RANGE: &str = "UNIT_RANGE";
    /// The hob would cut into another unit of a multi-gear part.
    pub const UNIT_COLLISION: &str = "UNIT_COLLISION";
    /// Computed radial or tangential feed above the machine's feed limit.
    pub const FEED_RATE_LIMIT: &str = "FEED_RATE_LIMIT";
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
    /// The hob's run-out below the gear reaches the table or the fixture.
    pub const ENVELOPE_COLLISION: &str = "ENVELOPE_COLLISION";
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
    JobError::new(Stage::Model, code, field, expected, got, message)
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
    validate_with(plan, &Config::for_machine(&plan.machine))
}

/// [`validate`] with explicit tolerances and windows.
pub fn validate_with(plan: &ProcessPlan, cfg: &Config) -> Report {
    let mut report = Report::default();
    let gear = &plan.request.spec.gear;
    let gear_ok = check_gear(&mut report, gear);
    let hob_ok = check_hob(&mut report, &plan.hob);
    check_process(&mut report, plan, gear_ok, cfg);
    check_class(&mut report, plan, cfg);
    let settings_ok = check_machine_settings(&mut report, plan);

    let mut geo = None;
    if gear_ok {
        let g = geometry(gear);
        check_machine_limits(&mut report, plan, &g, cfg);
        check_ball(&mut report, gear);
        geo = Some(g);
    } else {
        check_hob_od_limit(&mut report, plan, cfg);
    }

    if let (Some(g), true) = (&geo, settings_ok) {
        check_blank_window(&mut report, plan, g, cfg);
    }
    if hob_ok && gear_ok {
        check_base_pitch(&mut report, gear, &plan.hob, cfg);
        check_hob_od(&mut report, gear, &plan.hob, cfg);
    }
    if let (Some(g), true, true) = (&geo, hob_ok, settings_ok) {
        let set = setup(plan, g);
        check_depth(&mut report, g, &set, cfg);
        check_centre_distance(&mut report, &set, cfg);
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

/// A job's ball must rest on the involute flanks (the default always does).
fn check_ball(r: &mut Report, g: &GearSpec) {
    let Some(dm) = g.ball_diameter_mm.filter(|d| *d > 0.0 && d.is_finite()) else {
        return;
    };
    let min = crate::geometry::min_ball_mm(g);
    if dm <= min {
        r.error(
            codes::BALL_DIAMETER_RANGE,
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

fn check_process(r: &mut Report, plan: &ProcessPlan, gear_ok: bool, cfg: &Config) {
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
    if !(1..=cfg.max_cuts).contains(&p.cuts) {
        r.error(
            codes::CUTS_RANGE,
            "process.cuts",
            format!("1 to {}", cfg.max_cuts),
            p.cuts.to_string(),
            format!("A job has one to {} cuts (rough cuts, then one finishing cut); correct process.cuts.", cfg.max_cuts),
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

/// Class markers, class-specific data, process options of the class, shift,
/// measurement data, mate and the units of a multi-gear part.
fn check_class(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let spec = &plan.request.spec;
    let g = &spec.gear;
    let o = &spec.process;
    let markers = unit_markers(g);
    if markers.len() > 1 {
        let names: Vec<&str> = markers.iter().map(|c| c.as_str()).collect();
        r.error(
            codes::CLASS_AMBIGUOUS,
            "gear",
            "at most one of cone, crowning, worm_wheel, curved_tooth",
            names.join(", "),
            "A gear belongs to exactly one class; keep the one table of [gear.cone], [gear.crowning], [gear.worm_wheel] or [gear.curved_tooth] that describes it.",
        );
    }
    let class = classify(spec);
    if markers.contains(&GearClass::CurvedTooth) {
        r.error(
            codes::CLASS_NOT_PROGRAMMABLE,
            "gear.curved_tooth",
            "a programmable class: cylindrical, conical, crowned, worm_wheel or multi_gear",
            GearClass::CurvedTooth.as_str(),
            "Curved-tooth gears are classified (SPEC §3) but not yet programmable: gearcam has no hobbing model for a curved tooth trace. Program this part by hand for now, or remove [gear.curved_tooth] if the trace is in fact straight.",
        );
    }
    let unit = gearcam_proto::class::unit_class(g);
    if o.infeed == Some(Infeed::RadialAxial) && unit != GearClass::Cylindrical {
        r.error(
            codes::CLASS_OPTION_UNSUPPORTED,
            "process.infeed",
            "axial for a conical, crowned or worm-wheel gear",
            "radial_axial",
            format!("Radial-axial infeed is programmed for cylindrical gears only; this gear is {unit}. Leave process.infeed out."),
        );
    }
    if let Some(cone) = &g.cone {
        if !open(cone.angle_deg, 0.0, 45.0) {
            r.error(
                codes::CONE_ANGLE_RANGE,
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
                    codes::CONE_ANGLE_RANGE,
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
    if let Some(cr) = &g.crowning {
        let half = g.face_width_mm / 2.0;
        if !(cr.amount_mm > 0.0 && cr.amount_mm < half) {
            r.error(
                codes::CROWNING_RANGE,
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
                    codes::CHORD_TOLERANCE_RANGE,
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
    let positive = |r: &mut Report, field: &str, v: Option<f64>, unit: &str, what: &str| {
        if let Some(v) = v {
            if !(v > 0.0 && v.is_finite()) {
                r.error(
                    codes::FEED_RATE_RANGE,
                    field,
                    format!("> 0 {unit}"),
                    format!("{} {unit}", num(v)),
                    format!("The {what} must be positive; correct {field}."),
                );
            }
        }
    };
    if let Some(w) = &g.worm_wheel {
        positive(
            r,
            "gear.worm_wheel.radial_feed_mm_per_rev",
            w.radial_feed_mm_per_rev,
            "mm/rev",
            "radial feed",
        );
        positive(
            r,
            "gear.worm_wheel.tangential_feed_mm_per_rev",
            w.tangential_feed_mm_per_rev,
            "mm/rev",
            "tangential feed",
        );
        if let Some(d) = w.dwell_rev {
            if !(d >= 0.0 && d.is_finite()) {
                r.error(
                    codes::DWELL_RANGE,
                    "gear.worm_wheel.dwell_rev",
                    "≥ 0 revolutions",
                    num(d),
                    "The dwell at the final centre distance is a number of wheel revolutions, 0 or more; correct gear.worm_wheel.dwell_rev.",
                );
            }
        }
        if w.infeed == WormInfeed::Tangential && o.shift.is_some() {
            r.error(
                codes::CLASS_OPTION_UNSUPPORTED,
                "process.shift",
                "no hob shifting with tangential infeed",
                "shift",
                "Tangential infeed already moves the hob along its axis; leave [process.shift] out.",
            );
        }
    }
    positive(
        r,
        "process.finish_feed_mm_per_rev",
        o.finish_feed_mm_per_rev,
        "mm/rev",
        "finishing feed",
    );
    positive(
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
                codes::FINISH_ALLOWANCE_RANGE,
                "process.finish_allowance_mm",
                format!("> 0 and < {} mm (the whole depth)", num(whole)),
                format!("{} mm", num(a)),
                "The finish allowance is the radial stock the rough cuts leave (typically 0.1–0.5 mm); correct process.finish_allowance_mm.",
            );
        }
    }
    if let Some(dm) = g.ball_diameter_mm {
        if !(dm > 0.0 && dm.is_finite()) {
            r.error(
                codes::BALL_DIAMETER_RANGE,
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
                codes::MATE_RANGE,
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
    check_shift(r, plan, cfg);
    if class == GearClass::MultiGear {
        check_units(r, plan, cfg);
    }
}

/// Hob shifting: positive step and parts per step, positions inside the
/// usable hob length.
fn check_shift(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let Some(spec) = &plan.request.spec.process.shift else {
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
    let g = &plan.request.spec.gear;
    let depth = plan
        .process
        .depth_mm
        .unwrap_or((2.0 * g.addendum_coef + g.clearance_coef) * g.module_mm);
    let res = crate::shift::Resolved::new(spec, hob, depth);
    let [lo, hi] = res.usable_mm;
    if hi < 0.0 {
        r.error(
            codes::HOB_TOO_SHORT_FOR_SHIFT,
            "hob.length_mm",
            format!("≥ {} mm (the active length)", num(res.active_length_mm)),
            format!("{} mm", num(hob.length_mm)),
            format!("Hob {} is shorter than its active length, so it cannot shift; leave [process.shift] out or use a longer hob.", hob.id),
        );
        return;
    }
    if !(res.step_mm > 0.0 && res.step_mm.is_finite()) {
        r.error(
            codes::SHIFT_RANGE,
            "process.shift.step_mm",
            "> 0 mm",
            format!("{} mm", num(res.step_mm)),
            "The shift per step must be positive; correct process.shift.step_mm.",
        );
    }
    if spec.parts_per_step == Some(0) {
        r.error(
            codes::SHIFT_RANGE,
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
                codes::SHIFT_RANGE,
                field,
                format!("{} to {} mm (usable hob length)", num(lo), num(hi)),
                format!("{} mm", num(v)),
                format!(
                    "Shift positions must keep the active length {} mm on the hob's {} mm; correct {field} or leave it out.",
                    num(res.active_length_mm),
                    num(hob.length_mm)
                ),
            );
        }
    }
}

/// The units of a multi-gear part: ascending, non-overlapping Z offsets, a
/// resolvable hob, and every check of a job for each unit (errors with the
/// unit's field names).
fn check_units(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let spec = &plan.request.spec;
    let mut top = spec.gear.face_width_mm;
    for (i, u) in spec.units.iter().enumerate() {
        let field = format!("units[{i}].z_offset_mm");
        if !(u.z_offset_mm.is_finite() && u.z_offset_mm >= top - cfg.length_tolerance_mm) {
            r.error(
                codes::UNIT_RANGE,
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
    for (name, v) in [
        ("swivel_sign", s.swivel_sign),
        ("table_sign", s.table_sign),
        ("hob_sign", s.hob_sign),
        ("shift_sign", s.shift_sign),
    ] {
        if v != 1.0 && v != -1.0 {
            r.error(
                codes::MACHINE_SETTING_RANGE,
                &format!("machine.settings.{name}"),
                "1 or -1",
                num(v),
                format!(
                    "Machine {}'s {name} is the sense of that axis against the neutral frame (docs/hobbing.md), 1 or -1; correct the machine profile in the knowledge base.",
                    plan.machine.id
                ),
            );
        }
    }
    if !s.swivel_offset_deg.is_finite() {
        r.error(
            codes::MACHINE_SETTING_RANGE,
            "machine.settings.swivel_offset_deg",
            "a finite angle",
            num(s.swivel_offset_deg),
            "The swivel offset is the swivel axis reading with the hob parallel to the gear's end face; correct the machine profile.".to_string(),
        );
    }
    let env = &plan.machine.envelope;
    for (name, v) in [
        ("table_radius_mm", env.table_radius_mm),
        ("fixture_radius_mm", env.fixture_radius_mm),
        ("tailstock_radius_mm", env.tailstock_radius_mm),
        ("tailstock_gap_mm", env.tailstock_gap_mm),
    ] {
        if !(v >= 0.0 && v.is_finite()) {
            r.error(
                codes::MACHINE_SETTING_RANGE,
                &format!("machine.envelope.{name}"),
                "≥ 0 mm",
                format!("{} mm", num(v)),
                format!(
                    "Machine {}'s envelope (table, fixture, tailstock) keeps the hob off them; correct the machine profile.",
                    plan.machine.id
                ),
            );
        }
    }
    if let Some(d) = plan.request.spec.gear.fixture_diameter_mm {
        if !(d >= 0.0 && d.is_finite()) {
            r.error(
                codes::MACHINE_SETTING_RANGE,
                "gear.fixture_diameter_mm",
                "≥ 0 mm",
                format!("{} mm", num(d)),
                "The fixture diameter is the support under the gear's lower face; give it in mm or leave it out for the machine's.".to_string(),
            );
        }
    }
    let p = plan.machine.parameters;
    let slots = gearcam_proto::ParameterBlock::SLOTS;
    let (field, first, lo, hi) = match plan.machine.dialect {
        gearcam_proto::Dialect::Fanuc => {
            ("machine.parameters.macro_first", p.macro_first, 500, 999)
        }
        _ => ("machine.parameters.r_first", p.r_first, 0, 999),
    };
    if first < lo || first + slots - 1 > hi {
        r.error(
            codes::MACHINE_SETTING_RANGE,
            field,
            format!("{lo} to {}", hi + 1 - slots),
            first.to_string(),
            format!(
                "gearcam's programs use {slots} consecutive parameters from this one (the hob-shift part counter among them, which the control must keep between runs); name a free block of the machine's retained parameters in the profile."
            ),
        );
    }
    r.errors.len() == before
}

fn check_machine_limits(r: &mut Report, plan: &ProcessPlan, geo: &Geometry, cfg: &Config) {
    let gear = &plan.request.spec.gear;
    let lim = &plan.machine.limits;
    let id = &plan.machine.id;
    let [lo, hi] = lim.module_mm;
    let mn = gear.module_mm;
    if !(mn >= lo - cfg.length_tolerance_mm && mn <= hi + cfg.length_tolerance_mm) {
        r.error(
            codes::MACHINE_MODULE_LIMIT,
            "gear.module_mm",
            format!("{} to {} mm", num(lo), num(hi)),
            format!("{} mm", num(mn)),
            format!("Machine {id} cuts modules from {} to {} mm only; choose another machine for this gear.", num(lo), num(hi)),
        );
    }
    let blank = gear.blank_od_mm.unwrap_or(geo.da_mm);
    if !(blank <= lim.max_workpiece_od_mm + cfg.length_tolerance_mm) {
        r.error(
            codes::WORKPIECE_OD_LIMIT,
            "gear.blank_od_mm",
            format!("≤ {} mm", num(lim.max_workpiece_od_mm)),
            format!("{} mm", num(blank)),
            format!("The blank is larger than machine {id} takes; choose a larger machine."),
        );
    }
    check_hob_od_limit(r, plan, cfg);
}

fn check_hob_od_limit(r: &mut Report, plan: &ProcessPlan, cfg: &Config) {
    let lim = &plan.machine.limits;
    let od = plan.hob.od_mm;
    if od.is_finite() && !(od <= lim.max_hob_od_mm + cfg.length_tolerance_mm) {
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
fn check_blank_window(r: &mut Report, plan: &ProcessPlan, geo: &Geometry, cfg: &Config) {
    let s = cfg;
    let da = geo.da_mm;
    let blank = blank_od(plan, geo);
    let (lo, hi) = (da - s.blank_od_below_mm, da + s.blank_od_above_mm);
    if !(blank >= lo - cfg.length_tolerance_mm && blank <= hi + cfg.length_tolerance_mm) {
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
    if allowed > 0.0 && dev.abs() > (1.0 - cfg.edge_fraction) * allowed {
        r.warnings.push(Warning {
            code: codes::BLANK_OD_EDGE.into(),
            field: "gear.blank_od_mm".into(),
            message: format!(
                "The blank OD {} mm is within {} % of the edge of its window {} to {} mm; check the blank before cutting.",
                num(blank),
                num(cfg.edge_fraction * 100.0),
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
fn check_depth(r: &mut Report, geo: &Geometry, set: &Setup, cfg: &Config) {
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
fn check_base_pitch(r: &mut Report, gear: &GearSpec, hob: &HobData, cfg: &Config) {
    let a0 = hob.pressure_angle_deg.to_radians().cos();
    let gear_pitch = gear.module_mm * gear.pressure_angle_deg.to_radians().cos();
    let hob_pitch = hob.module_mm * a0;
    if (hob_pitch - gear_pitch).abs() <= cfg.base_pitch_tolerance_mm {
        return;
    }
    r.error(
        codes::BASE_PITCH_MISMATCH,
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
fn check_hob_od(r: &mut Report, gear: &GearSpec, hob: &HobData, cfg: &Config) {
    let d0 = crate::hobbing::hob_reference_diameter_mm(hob);
    let min = d0 + 2.0 * (gear.addendum_coef + gear.clearance_coef) * hob.module_mm;
    if hob.od_mm >= min - cfg.length_tolerance_mm {
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
fn check_centre_distance(r: &mut Report, set: &Setup, cfg: &Config) {
    let l = set.centre_distance_mm;
    let theory = set.theoretical_centre_distance_mm;
    if l >= theory - cfg.length_tolerance_mm {
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

/// Checks computed kinematics against the machine's limits: hob speed and
/// swivel; table speed, axial and radial feed of every cut; the travel of
/// every position A–E and of every move's end point; and the same for each
/// further unit of a multi-gear part. Duplicate findings are reported once.
pub fn check_limits(plan: &ProcessPlan, k: &Kinematics) -> Vec<JobError> {
    check_limits_with(plan, k, &Config::for_machine(&plan.machine))
}

/// [`check_limits`] with explicit tolerances.
pub fn check_limits_with(plan: &ProcessPlan, k: &Kinematics, cfg: &Config) -> Vec<JobError> {
    let mut errors = Vec::new();
    unit_limits(&mut errors, plan, k, cfg, "");
    for (i, unit) in k.units.iter().enumerate().skip(1) {
        let spec = &plan.request.spec.units[i - 1];
        let unit_plan = crate::units::unit_plan(plan, i - 1, spec, unit.hob.clone());
        unit_limits(
            &mut errors,
            &unit_plan,
            &unit.model,
            cfg,
            &format!("units[{}].", i - 1),
        );
    }
    check_unit_collisions(&mut errors, k, cfg);
    let mut seen = std::collections::BTreeSet::new();
    errors.retain(|e| seen.insert((e.code.clone(), e.field.clone(), e.got.clone())));
    errors
}

/// The hob's run-out below the gear must stay clear of the table and the
/// fixture: at the lowest hob centre Zl of the stroke, the tilted tip
/// cylinder reaches r·cos η + (length/2 + |shift|)·|sin η| below it (the
/// largest shift of any part), which must stay
/// above the table plane where the hob stands over the table; and the hob
/// comes as near as X − r to the table axis (the swivel turns it about X),
/// so a fixture at least that wide under the gear is hit. (The template
/// service's path check sweeps the sampled hob solid independently.)
fn run_out(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    k: &Kinematics,
    cfg: &Config,
    prefix: &str,
) {
    let gear = &plan.request.spec.gear;
    let env = &plan.machine.envelope;
    let r = plan.hob.od_mm / 2.0;
    let half = plan.hob.length_mm / 2.0;
    let eta = k.swivel_deg.to_radians();
    // A shifted hob stands off-centre along its own axis: its far end reaches
    // lower by the shift times sin η. Every part may be cut at any shift
    // position, so the largest one counts.
    let shift = k
        .shift
        .as_ref()
        .map_or(0.0, |s| s.start_mm.abs().max(s.end_mm.abs()))
        .max(
            k.cuts
                .iter()
                .flat_map(|c| c.moves.iter().filter_map(|m| m.y_mm))
                .fold(0.0, |a: f64, y| a.max(y.abs())),
        );
    let below = r * eta.cos() + (half + shift) * eta.sin().abs();
    let (mut low, mut x_low) = (f64::INFINITY, f64::INFINITY);
    for c in &k.cuts {
        for p in [c.positions.C, c.positions.D] {
            if p.z_mm < low {
                (low, x_low) = (p.z_mm, p.x_mm);
            }
        }
        for m in &c.moves {
            if let (Some(z), Some(x)) = (m.z_mm, m.x_mm) {
                if z < low {
                    (low, x_low) = (z, x);
                }
            }
        }
    }
    if !low.is_finite() {
        return;
    }
    let id = &plan.machine.id;
    let lowest = low - below;
    if lowest < -cfg.length_tolerance_mm && x_low - r < env.table_radius_mm {
        let need = gear.fixture_height_mm - lowest;
        errors.push(job_error(
            codes::ENVELOPE_COLLISION,
            &format!("{prefix}gear.fixture_height_mm"),
            format!("≥ {} mm", num(need)),
            format!("{} mm", num(gear.fixture_height_mm)),
            format!(
                "Below the gear the hob runs out {} mm below its centre (tip radius {} mm, half its length {} mm, shifted up to {} mm, tilted {}°) and would reach {} mm into machine {id}'s table; raise the gear on a taller fixture or use a shorter hob.",
                num(below),
                num(r),
                num(half),
                num(shift),
                num(k.swivel_deg.abs()),
                num(-lowest)
            ),
        ));
    }
    let fixture_r = gear
        .fixture_diameter_mm
        .map_or(env.fixture_radius_mm, |d| d / 2.0);
    let nearest = x_low - r;
    // The fixture stands under the lowest unit only (a unit above runs out
    // over the unit below it, which `check_unit_collisions` covers).
    if prefix.is_empty()
        && low < gear.fixture_height_mm
        && fixture_r >= nearest - cfg.length_tolerance_mm
    {
        errors.push(job_error(
            codes::ENVELOPE_COLLISION,
            &format!("{prefix}gear.fixture_diameter_mm"),
            format!("< {} mm", num(2.0 * nearest)),
            format!(
                "{} mm{}",
                num(2.0 * fixture_r),
                if gear.fixture_diameter_mm.is_none() {
                    format!(" (machine {id}'s default)")
                } else {
                    String::new()
                }
            ),
            format!(
                "Below the gear the hob comes within {} mm of the table axis; a fixture that wide under the gear is cut. Give gear.fixture_diameter_mm of the support actually used, narrower than the gear's root.",
                num(nearest)
            ),
        ));
    }
}

/// Multi-gear parts: while cutting one unit, the hob must stay clear of the
/// other units. For a neighbour of radius Rn, the hob (radius r, swivel γ) at
/// the unit's centre distance L overlaps it radially by hn = Rn + r − L; when
/// hn > 0 the hob centre must stay ΔH′(Rn, r, hn, γ) away from the
/// neighbour's face (the same clearance as the approach, SPEC §4.3), over the
/// unit's whole feed stroke.
fn check_unit_collisions(errors: &mut Vec<JobError>, k: &Kinematics, cfg: &Config) {
    for (i, u) in k.units.iter().enumerate() {
        let stroke: Vec<f64> = u
            .model
            .cuts
            .iter()
            .flat_map(|c| [c.positions.C.z_mm, c.positions.D.z_mm])
            .collect();
        let lowest = stroke.iter().copied().fold(f64::INFINITY, f64::min);
        let highest = stroke.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let bottom = u.gear.fixture_height_mm;
        let top = bottom + u.gear.face_width_mm;
        for (_, n) in k.units.iter().enumerate().filter(|(j, _)| *j != i) {
            let r_n = n.model.blank_od_mm / 2.0;
            let overlap = r_n + u.hob.od_mm / 2.0 - u.model.centre_distance_mm;
            if !(overlap > 0.0) {
                continue;
            }
            let clear = crate::hobbing::Clearance {
                blank_od_mm: n.model.blank_od_mm,
                hob_od_mm: u.hob.od_mm,
                depth_mm: overlap,
                swivel_deg: u.model.swivel_deg,
                hob_length_mm: u.hob.length_mm,
            }
            .solve()
            .clearance_mm;
            let n_bottom = n.gear.fixture_height_mm;
            let n_top = n_bottom + n.gear.face_width_mm;
            let (bad, limit, got) = if n_top <= bottom + cfg.length_tolerance_mm {
                let min = n_top + clear;
                (
                    lowest < min - cfg.length_tolerance_mm,
                    format!("hob centre ≥ {} mm", num(min)),
                    lowest,
                )
            } else if n_bottom >= top - cfg.length_tolerance_mm {
                let max = n_bottom - clear;
                (
                    highest > max + cfg.length_tolerance_mm,
                    format!("hob centre ≤ {} mm", num(max)),
                    highest,
                )
            } else {
                continue; // overlapping units are reported by validation
            };
            if bad {
                errors.push(job_error(
                    codes::UNIT_COLLISION,
                    &format!("units[{i}].model.positions"),
                    limit,
                    format!("hob centre at {} mm", num(got)),
                    format!(
                        "While cutting {} the hob would cut into {} (it needs {} mm of clearance from that unit's face); move the units apart with z_offset_mm or plan a run-out groove.",
                        u.name,
                        n.name,
                        num(clear)
                    ),
                ));
            }
        }
    }
}

fn unit_limits(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    k: &Kinematics,
    cfg: &Config,
    prefix: &str,
) {
    let lim = &plan.machine.limits;
    let id = &plan.machine.id;
    let mut over = |code: &str, field: &str, v: f64, max: f64, unit: &str, todo: &str| {
        if !(v.abs() <= max + cfg.length_tolerance_mm) {
            errors.push(job_error(
                code,
                &format!("{prefix}{field}"),
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
        "model.swivel_deg",
        k.swivel_deg,
        lim.max_swivel_deg,
        "°",
        "use a hob of the same hand as the gear helix or another machine",
    );
    for (i, c) in k.cuts.iter().enumerate().filter(|(_, c)| !c.finish) {
        over(
            codes::TABLE_RPM_LIMIT,
            &format!("model.cuts[{i}].table_rpm"),
            c.table_rpm,
            lim.max_table_rpm,
            "rpm",
            "lower process.cutting_speed_m_min or use a hob with fewer starts",
        );
        over(
            codes::AXIAL_FEED_LIMIT,
            &format!("model.cuts[{i}].axial_feed_mm_min"),
            c.axial_feed_mm_min,
            lim.max_axial_feed_mm_min,
            "mm/min",
            "lower process.feed_mm_per_rev or the cutting speed",
        );
    }
    for (i, c) in k.cuts.iter().enumerate() {
        for (j, m) in c
            .moves
            .iter()
            .enumerate()
            .filter(|(_, m)| m.kind != gearcam_proto::MoveKind::Rapid)
        {
            if !(m.x_mm.is_some() && m.z_mm.is_none()) {
                continue;
            }
            let rate = m.feed_mm_min;
            over(
                codes::FEED_RATE_LIMIT,
                &format!("model.cuts[{i}].moves[{j}].feed_mm_min"),
                rate,
                lim.max_axial_feed_mm_min,
                "mm/min",
                "lower the radial feed per revolution or the cutting speed",
            );
        }
    }
    let p = &k.positions;
    for (name, pos) in [("A", p.A), ("B", p.B), ("C", p.C), ("D", p.D), ("E", p.E)] {
        check_travel(
            errors,
            plan,
            &|| format!("{prefix}model.positions.{name}"),
            name,
            pos,
            cfg,
        );
    }
    for (i, c) in k.cuts.iter().enumerate() {
        let q = &c.positions;
        for (name, pos) in [("B", q.B), ("C", q.C), ("D", q.D), ("E", q.E)] {
            check_travel(
                errors,
                plan,
                &|| format!("{prefix}model.cuts[{i}].positions.{name}"),
                name,
                pos,
                cfg,
            );
        }
        let mut at = q.B;
        for (j, m) in c.moves.iter().enumerate() {
            at = move_end(at, m);
            check_travel(
                errors,
                plan,
                &|| format!("{prefix}model.cuts[{i}].moves[{j}]"),
                "move",
                at,
                cfg,
            );
        }
    }
    run_out(errors, plan, k, cfg, prefix);
}

fn move_end(from: Position, m: &Move) -> Position {
    Position {
        x_mm: m.x_mm.unwrap_or(from.x_mm),
        z_mm: m.z_mm.unwrap_or(from.z_mm),
    }
}

fn check_travel(
    errors: &mut Vec<JobError>,
    plan: &ProcessPlan,
    field: &dyn Fn() -> String,
    name: &str,
    pos: Position,
    cfg: &Config,
) {
    let lim = &plan.machine.limits;
    for (axis, v, [lo, hi]) in [("x", pos.x_mm, lim.x_mm), ("z", pos.z_mm, lim.z_mm)] {
        if v >= lo - cfg.length_tolerance_mm && v <= hi + cfg.length_tolerance_mm {
            continue;
        }
        let todo = if name == "A" {
            "correct the machine's home position in its profile"
        } else if axis == "x" {
            "check the blank and hob diameters, gear.od_correction_mm and the retract and exit distances"
        } else {
            "check gear.fixture_height_mm, the face width and the safety distance"
        };
        // A duplicate of an already reported value (same axis and value) is noise.
        let got = format!("{} mm", num(v));
        // Cut positions and moves repeat the top-level positions; report a
        // value outside the travel once.
        let field = field();
        if field.contains("cuts[")
            && errors.iter().any(|e| {
                e.code == codes::POSITION_TRAVEL_LIMIT
                    && e.got == got
                    && e.field.ends_with(&format!(".{axis}_mm"))
            })
        {
            continue;
        }
        errors.push(job_error(
            codes::POSITION_TRAVEL_LIMIT,
            &format!("{field}.{axis}_mm"),
            format!("{} to {} mm", num(lo), num(hi)),
            got,
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
    fn a_ball_below_the_base_circle_is_refused_with_the_smallest_that_rests() {
        let mut plan = fixtures::plan();
        let g = &mut plan.request.spec.gear;
        g.ball_diameter_mm = Some(0.5);
        let min = crate::geometry::min_ball_mm(g);
        let e = validate(&plan)
            .errors
            .into_iter()
            .find(|e| e.code == "BALL_DIAMETER_RANGE")
            .expect("a ball of 0.5 mm on module 3 falls through the space");
        assert_eq!(e.field, "gear.ball_diameter_mm");
        assert_eq!(
            e.expected,
            format!(
                "> {} mm (smaller balls drop below the base circle)",
                num(min)
            )
        );
        assert_eq!(e.got, "0.5 mm");
        plan.request.spec.gear.ball_diameter_mm = Some(min * 1.01);
        assert!(validate(&plan)
            .errors
            .iter()
            .all(|e| e.code != "BALL_DIAMETER_RANGE"));
    }

    #[test]
    fn reports_several_failures_together() {
        let mut plan = fixtures::plan();
        plan.hob.module_mm = 2.5;
        plan.process.cuts = 7;
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
                "CUTS_RANGE",
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
                "CUTS_RANGE",
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
        // β 44° left-hand, right-hand hob: η = −44 − 2.3716 = −46.3716°,
        // |η| > 45°; H01 programs A = −η.
        let plan = fixtures::helical_plan(44.0, Hand::Left);
        assert!(validate(&plan).is_ok());
        let errors: Vec<_> = crate::compute(&plan)
            .unwrap_err()
            .into_iter()
            .filter(|e| e.code != "ENVELOPE_COLLISION")
            .collect();
        assert_eq!(errors.len(), 1, "{errors:?}");
        assert_eq!(errors[0].code, "SWIVEL_LIMIT");
        assert_eq!(errors[0].got, "-46.3716 °");
    }

    #[test]
    fn the_machine_profile_new_fields_are_checked_with_their_names() {
        let mut plan = fixtures::plan();
        plan.machine.settings.table_sign = 0.5;
        plan.machine.envelope.table_radius_mm = -1.0;
        plan.machine.parameters.r_first = 980;
        plan.request.spec.gear.fixture_diameter_mm = Some(f64::NAN);
        let fields: Vec<String> = validate(&plan)
            .errors
            .into_iter()
            .map(|e| e.field)
            .collect();
        for want in [
            "machine.settings.table_sign",
            "machine.envelope.table_radius_mm",
            "machine.parameters.r_first",
            "gear.fixture_diameter_mm",
        ] {
            assert!(fields.iter().any(|f| f == want), "{want} in {fields:?}");
        }
    }

    #[test]
    fn numbers_print_plainly() {
        assert_eq!(num(80.0), "80");
        assert_eq!(num(2.5), "2.5");
        assert_eq!(num(-0.0000001), "0");
        assert_eq!(num(1.0 / 3.0), "0.333333");
        assert_eq!(num(f64::NAN), "NaN");
    }

    #[test]
    fn tolerances_and_windows_come_from_the_config() {
        // A blank 1 mm over da fails H01's +0.5 mm window but passes a
        // machine configured for +1.5 mm; the defaults are documented.
        let mut plan = fixtures::plan();
        plan.request.spec.gear.blank_od_mm = Some(82.0);
        assert_eq!(codes_of(&plan), vec![codes::BLANK_OD_WINDOW]);
        let cfg = Config {
            blank_od_above_mm: 1.5,
            ..Config::for_machine(&plan.machine)
        };
        let report = validate_with(&plan, &cfg);
        assert!(report.is_ok(), "{:?}", report.errors);
        let d = Config::default();
        assert_eq!(
            (d.length_tolerance_mm, d.base_pitch_tolerance_mm),
            (1e-6, 1e-4)
        );
        assert_eq!(
            (
                d.blank_od_below_mm,
                d.blank_od_above_mm,
                d.depth_allowance_mm
            ),
            (2.0, 0.5, 0.5)
        );
        // A base-pitch tolerance is a per-machine choice too.
        let mut off = fixtures::plan();
        off.hob.module_mm = 2.9995;
        assert_eq!(codes_of(&off), vec![codes::BASE_PITCH_MISMATCH]);
        let loose = Config {
            base_pitch_tolerance_mm: 1e-3,
            ..Config::default()
        };
        assert!(validate_with(&off, &loose).is_ok());
    }

    #[test]
    fn class_options_and_cut_settings_are_checked() {
        let mut plan = fixtures::plan();
        plan.request.spec.gear.cone = Some(gearcam_proto::ConeSpec {
            angle_deg: 6.5,
            large_end: gearcam_proto::LargeEnd::Bottom,
        });
        plan.request.spec.process.infeed = Some(Infeed::RadialAxial);
        plan.process.cuts = 2;
        plan.request.spec.process.finish_allowance_mm = Some(9.0);
        plan.request.spec.process.radial_feed_mm_per_rev = Some(0.0);
        assert_eq!(
            codes_of(&plan),
            vec![
                codes::CLASS_OPTION_UNSUPPORTED,
                codes::FEED_RATE_RANGE,
                codes::FINISH_ALLOWANCE_RANGE
            ]
        );
    }

    #[test]
    fn unit_errors_name_the_unit() {
        let mut plan = fixtures::plan();
        let mut g = fixtures::gear();
        g.module_mm = 2.0;
        plan.request.spec.units.push(gearcam_proto::UnitSpec {
            name: None,
            z_offset_mm: 10.0,
            gear: g,
            hob: Default::default(),
        });
        let report = validate(&plan);
        // The unit overlaps unit 1 (30 mm face) and a module-2 gear does not fit
        // the job's module-3 hob.
        let fields: Vec<(&str, &str)> = report
            .errors
            .iter()
            .map(|e| (e.code.as_str(), e.field.as_str()))
            .collect();
        assert!(
            fields.contains(&(codes::UNIT_RANGE, "units[0].z_offset_mm")),
            "{fields:?}"
        );
        assert!(
            fields.contains(&(codes::BASE_PITCH_MISMATCH, "units[0].hob.module_mm")),
            "{fields:?}"
        );
    }
}
