//! Validation of a process plan before and after the hobbing computation
//! (docs/reference.md#validation-checks, patent step 2).
//!
//! [`validate`] runs every parameter check and the five physical checks of the
//! patent and reports all failures together; a check whose inputs already
//! failed a parameter check is skipped rather than reported with nonsense
//! numbers. [`check_limits`] runs after [`crate::hobbing::kinematics`] and
//! checks the computed speeds, feed, swivel and positions against the machine.
//!
//! # Layout, by phase
//!
//! - `input`: the job's own values (gear, ball, hob, process).
//! - `class`: the rules of each gear class, the shift and the units.
//! - `physics`: the patent's physical checks (depth, base pitch, hob
//!   diameter, centre distance).
//! - `machine`: the machine profile before the computation (settings,
//!   limits, blank window).
//! - `limits`: after the computation (run-out envelope, colliding units,
//!   travel and speeds of every move).
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
    Code, CrowningShape, GearClass, GearSpec, Geometry, HobData, Infeed, JobError, Kinematics,
    MachineProfile, Move, Position, ProcessPlan, Stage, Warning, WormInfeed,
};

use crate::geometry::{geometry, is_spur, lead_mm};
use crate::hobbing::{setup, Setup};

mod class;
mod input;
mod limits;
mod machine;
mod physics;
#[cfg(test)]
mod tests;
use class::*;
use input::*;
use limits::*;
use machine::*;
use physics::*;

/// Numerical tolerance of length comparisons, mm.
pub const TOLERANCE_MM: f64 = 1e-6;

/// Tolerance of the base-pitch equality mn0·cos α0 = mn·cos αn, mm.
pub const BASE_PITCH_TOLERANCE_MM: f64 = 1e-4;

/// A blank OD that uses more than 1 − this fraction of its allowed deviation
/// from da (on its side of da) gets a [`Code::BLANK_OD_EDGE`] warning.
pub const EDGE_FRACTION: f64 = 0.1;

/// Most cuts a job may ask for.
pub const MAX_CUTS: u32 = 6;

/// Most teeth a gear may have: far beyond any hobbed gear (10,000 teeth of
/// module 0.5 make a 5 m wheel), so that an absurd count is refused on
/// `gear.teeth` itself, not later on the blank or the depth it throws off.
pub const MAX_TEETH: u32 = 10_000;

/// Tolerances and windows of validation for one machine (docs/reference.md#validation-checks).
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
        code: Code,
        field: &str,
        expected: impl Into<String>,
        got: impl Into<String>,
        message: impl Into<String>,
    ) {
        self.errors
            .push(Stage::Model.error(code, field, expected, got, message));
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
/// together (docs/reference.md#validation-checks).
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
    let gear = &plan.gear;
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
        check_undercut(&mut report, gear, &g);
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
        let spec = &plan.sections().units[i - 1];
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
    errors.retain(|e| seen.insert((e.code, e.field.clone(), e.got.clone())));
    errors
}
