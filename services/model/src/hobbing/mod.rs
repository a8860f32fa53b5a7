//! The hobbing model of a cylindrical gear (docs/hobbing.md#4-the-cycle-positions-speeds-feeds, patent step 3): hob
//! swivel, approach clearance ΔH′, the five cycle positions A–E, speeds, feed,
//! differential, gearbox coupling and machining time.
//!
//! Everything here assumes a plan that [`crate::validate::validate`] accepted;
//! on other input the results may be non-finite, never a panic.

use std::f64::consts::PI;

use gearcam_proto::class::unit_class;
use gearcam_proto::{
    ConeModel, CouplingFactors, CrowningModel, CrowningShape, Cut, CutMode, GearClass, GearSpec,
    Geometry, HobData, Infeed, Kinematics, MachineProfile, Position, ProcessData, ProcessOverrides,
    ProcessPlan, Ratio, WormInfeed, WormModel,
};
use nalgebra::{Matrix4, Vector4};

use crate::frame;
use crate::geometry::{is_spur, lead_mm};
use crate::path::{self, CutFrame, WormFrame};
use crate::shift;

mod clearance;
mod couplings;
#[cfg(test)]
mod tests;
pub use clearance::*;
pub use couplings::*;

/// Samples of the dense scan for ΔH′ before golden-section refinement.
pub const CLEARANCE_SAMPLES: usize = 128;

/// Hob reference diameter d0 = z0·mn0 / sin γ0, mm (docs/reference.md#check-4-hob-outside-diameter).
pub fn hob_reference_diameter_mm(hob: &HobData) -> f64 {
    f64::from(hob.starts) * hob.module_mm / hob.lead_angle_deg.to_radians().sin()
}

/// The hob's tip and reference radii, as a conical path needs them.
pub fn hob_radii(hob: &HobData) -> path::HobRadii {
    path::HobRadii {
        tip_mm: hob.od_mm / 2.0,
        reference_mm: hob_reference_diameter_mm(hob) / 2.0,
    }
}

/// The blank outside diameter used: the job's `blank_od_mm`, or the theoretical
/// tip diameter da when the job gives none.
pub fn blank_od_mm(gear: &GearSpec, geometry: &Geometry) -> f64 {
    gear.blank_od_mm.unwrap_or(geometry.da_mm)
}

/// Theoretical centre distance of hob and gear (docs/reference.md#check-5-centre-distance), mm:
/// d0/2 + (d·cos αn / cos α0)/2 + x·mn.
pub fn theoretical_centre_distance_mm(gear: &GearSpec, geometry: &Geometry, hob: &HobData) -> f64 {
    let cos_ratio =
        gear.pressure_angle_deg.to_radians().cos() / hob.pressure_angle_deg.to_radians().cos();
    hob_reference_diameter_mm(hob) / 2.0
        + geometry.d_mm * cos_ratio / 2.0
        + gear.profile_shift * gear.module_mm
}

/// The radial set-up of a job: blank, depth and centre distances, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setup {
    /// Blank outside diameter Da1 (see [`blank_od_mm`]).
    pub blank_od_mm: f64,
    /// Radial depth h: `process.depth_mm`, or by default the depth that makes
    /// the final centre distance equal the theoretical one.
    pub depth_mm: f64,
    /// True when the depth came from the plan, false when it is the default.
    pub depth_given: bool,
    /// Final centre distance L = (da0 + Da1)/2 − h.
    pub centre_distance_mm: f64,
    /// Theoretical centre distance (see [`theoretical_centre_distance_mm`]).
    pub theoretical_centre_distance_mm: f64,
    /// Hob reference diameter d0 (see [`hob_reference_diameter_mm`]).
    pub hob_reference_diameter_mm: f64,
}

/// Blank, depth and centre distance of a plan. The default depth is
/// h = (da0 + Da1)/2 − L_theory (docs/reference.md#check-1-blank-outside-diameter).
pub fn setup(plan: &ProcessPlan, geometry: &Geometry) -> Setup {
    setup_unit(&Unit::of_plan(plan), geometry)
}

/// One gear unit to model: the job's gear (or a multi-gear unit) with its hob,
/// process, machine and class.
#[derive(Debug, Clone, Copy)]
pub struct Unit<'a> {
    /// Drawing data.
    pub gear: &'a GearSpec,
    /// Hob.
    pub hob: &'a HobData,
    /// Decided process data.
    pub process: &'a ProcessData,
    /// The job's process overrides (infeed, allowance, shift, ...).
    pub overrides: &'a ProcessOverrides,
    /// Machine.
    pub machine: &'a MachineProfile,
    /// Parts to cut.
    pub quantity: u32,
    /// Unit class (never multi-gear).
    pub class: GearClass,
    /// Finish allowance the knowledge base proposed (plan value `allowance_mm`).
    pub proposed_allowance_mm: Option<f64>,
    /// Finishing feed the knowledge base proposed for the drawing's class
    /// (plan value `finish_feed_mm_per_rev`).
    pub proposed_finish_feed_mm_per_rev: Option<f64>,
}

/// The plan's finishing feed for several cuts, when the knowledge base
/// gave one.
pub fn proposed_finish_feed(plan: &ProcessPlan) -> Option<f64> {
    plan.values.get("finish_feed_mm_per_rev").map(|v| v.value)
}

impl<'a> Unit<'a> {
    /// The job's own gear as a unit (for a multi-gear job: its first unit).
    pub fn of_plan(plan: &'a ProcessPlan) -> Unit<'a> {
        let spec = &plan.request.spec;
        Unit {
            gear: &plan.gear,
            hob: &plan.hob,
            process: &plan.process,
            overrides: &plan.sections().process,
            machine: &plan.machine,
            quantity: spec.job.quantity,
            class: unit_class(&plan.gear),
            proposed_allowance_mm: plan.values.get("allowance_mm").map(|v| v.value),
            proposed_finish_feed_mm_per_rev: proposed_finish_feed(plan),
        }
    }

    /// Radial stock the rough cuts leave: 0 for one cut, else the job's
    /// `finish_allowance_mm`, the knowledge base's proposal, or
    /// [`DEFAULT_FINISH_ALLOWANCE_PER_MODULE`]·mn.
    pub fn finish_allowance_mm(&self) -> f64 {
        if self.process.cuts <= 1 {
            0.0
        } else {
            self.overrides
                .finish_allowance_mm
                .or(self.proposed_allowance_mm.filter(|a| *a > 0.0))
                .unwrap_or(DEFAULT_FINISH_ALLOWANCE_PER_MODULE * self.gear.module_mm)
        }
    }

    /// Feed per revolution of the finishing cut: when there are several
    /// cuts the job's `finish_feed_mm_per_rev`, else the knowledge base's
    /// for the drawing's class, else the feed; for one cut the feed.
    pub fn finish_feed_mm_per_rev(&self) -> f64 {
        match (self.process.cuts > 1, self.overrides.finish_feed_mm_per_rev) {
            (true, Some(f)) => f,
            (true, None) => self
                .proposed_finish_feed_mm_per_rev
                .unwrap_or(self.process.feed_mm_per_rev),
            (false, _) => self.process.feed_mm_per_rev,
        }
    }

    /// Radial feed per workpiece revolution of a plunge: the worm wheel's or
    /// the job's, or by default [`DEFAULT_RADIAL_FEED_FRACTION`] of the axial feed.
    pub fn radial_feed_mm_per_rev(&self) -> f64 {
        self.gear
            .worm_wheel
            .as_ref()
            .and_then(|w| w.radial_feed_mm_per_rev)
            .or(self.overrides.radial_feed_mm_per_rev)
            .unwrap_or(DEFAULT_RADIAL_FEED_FRACTION * self.process.feed_mm_per_rev)
    }

    /// Infeed mode: the job's, axial by default.
    pub fn infeed(&self) -> Infeed {
        self.overrides.infeed.unwrap_or_default()
    }
}

/// Default radial finish allowance of rough cuts, as a multiple of mn.
pub const DEFAULT_FINISH_ALLOWANCE_PER_MODULE: f64 = 0.1;

/// Default radial feed of a plunge as a fraction of the axial feed per
/// revolution (seed 000's case: radial 36 mm/min against axial 105 mm/min).
pub const DEFAULT_RADIAL_FEED_FRACTION: f64 = 1.0 / 3.0;

/// Default dwell of a worm wheel at the final centre distance, wheel revolutions.
pub const DEFAULT_WORM_DWELL_REV: f64 = 2.0;

/// Blank, depth and centre distance of a unit (see [`setup`]).
pub fn setup_unit(u: &Unit, geometry: &Geometry) -> Setup {
    let blank = blank_od_mm(u.gear, geometry);
    let theory = theoretical_centre_distance_mm(u.gear, geometry, u.hob);
    let outer = (u.hob.od_mm + blank) / 2.0;
    let (depth, given) = match u.process.depth_mm {
        Some(h) => (h, true),
        None => (outer - theory, false),
    };
    Setup {
        blank_od_mm: blank,
        depth_mm: depth,
        depth_given: given,
        centre_distance_mm: outer - depth,
        theoretical_centre_distance_mm: theory,
        hob_reference_diameter_mm: hob_reference_diameter_mm(u.hob),
    }
}

/// Radial depth of cut `i` (1-based) of `n`: rough cuts share h − allowance
/// evenly, the last cut goes to h.
pub fn cut_depth_mm(depth_mm: f64, allowance_mm: f64, i: u32, n: u32) -> f64 {
    if i >= n || n <= 1 {
        depth_mm
    } else {
        (depth_mm - allowance_mm) * f64::from(i) / f64::from(n - 1)
    }
}

/// The hobbing kinematics of a validated plan's own gear (docs/reference.md#class-models), see
/// [`unit_kinematics`].
pub fn kinematics(plan: &ProcessPlan, geometry: &Geometry) -> Kinematics {
    unit_kinematics(&Unit::of_plan(plan), geometry)
}

/// The hobbing kinematics of one validated unit (docs/reference.md#class-models):
///
/// - swivel γ ([`swivel_deg`]), programmed as `machine.settings.swivel_sign · γ`;
/// - cuts: rough cuts to (h − allowance)·i/(n − 1), the last to h, each with
///   its own centre distance, ΔH′ ([`Clearance::solve`]) and path
///   ([`crate::path`]): axial or radial-axial (cylindrical), along the cone
///   (conical), on the crowning (crowned), radial or tangential (worm wheel);
///   cuts after the first re-synchronise into the existing gaps;
/// - Nt = 1000·vc/(π·da0), Ni = z0·Nt/z; helical Nw = Ni/(1 − s·fa/Pz),
///   differential s·360·sin|β|/(π·mn·z) °/mm; spur Nw = Ni; Vf = fa·Nw;
/// - coupling factors C/B = z0/z exact, C per Z, C per Y
///   ([`shift_compensation_deg_per_mm`]);
/// - hob shifting per part or per cut ([`crate::shift`]);
/// - reported cut time (b + 2·ΔH′)·z/(Nt·z0·fa) for the finishing cut
///   (docs/reference.md#speeds-feeds-and-times), the time of every cut from
///   its feed moves and dwells, per part and per job.
///
/// The top-level positions, depth, centre distance, ΔH′, table speed and feed
/// are those of the finishing cut.
pub fn unit_kinematics(u: &Unit, geometry: &Geometry) -> Kinematics {
    let gear = u.gear;
    let hob = u.hob;
    let process = u.process;
    let machine = u.machine;
    let set = setup_unit(u, geometry);

    let eta = swivel_deg(gear, hob);
    let safety = process.safety_mm;
    let z = f64::from(gear.teeth);
    let z0 = f64::from(hob.starts);
    let hob_rpm = 1000.0 * process.cutting_speed_m_min / (PI * hob.od_mm);
    let index_rpm = z0 * hob_rpm / z;
    // The differential coupling is the gear's helix alone; the patent's
    // sign rule only decides whether the table turns faster or slower than
    // the indexing speed during the cut (Nw, a magnitude).
    let (sign, differential, lead) = match lead_mm(gear) {
        None => (0.0, 0.0, None),
        Some(pz) => (
            table_speed_sign(gear, hob, process.cut_mode),
            frame::differential_deg_per_mm(gear),
            Some(pz),
        ),
    };
    // Worm wheels are fed radially or tangentially, never along Z.
    let axial = u.class != GearClass::WormWheel;
    let table_rpm_for = |fa: f64| match lead {
        Some(pz) if axial => index_rpm / (1.0 - sign * fa / pz),
        _ => index_rpm,
    };

    let n = process.cuts.max(1);
    let allowance = u.finish_allowance_mm();
    let outer = (hob.od_mm + set.blank_od_mm) / 2.0;
    let shift = u
        .overrides
        .shift
        .as_ref()
        .map(|spec| shift::Resolved::new(spec, hob, set.depth_mm));
    let c_per_y = shift_compensation_deg_per_mm(hob, gear.teeth);
    let clear_x = outer + gear.od_correction_mm + safety;
    let worm = gear.worm_wheel.as_ref();
    let throat_z = gear.fixture_height_mm + gear.face_width_mm / 2.0;

    let mut cuts = Vec::with_capacity(n as usize);
    let mut crowning_info = None;
    let mut worm_info = None;
    for i in 1..=n {
        let depth = cut_depth_mm(set.depth_mm, allowance, i, n);
        let finish = i == n;
        let fa = if finish {
            u.finish_feed_mm_per_rev()
        } else {
            process.feed_mm_per_rev
        };
        let table_rpm = table_rpm_for(fa);
        let axial_feed = if axial { fa * table_rpm } else { 0.0 };
        let radial_feed = u.radial_feed_mm_per_rev() * table_rpm;
        // A crowned cut goes deeper towards the faces by the crowning, and
        // the approach must clear the blank at that deepest depth.
        let crown = match (u.class, gear.crowning.as_ref()) {
            (GearClass::Crowned, Some(cr)) => cr.amount_mm.max(0.0),
            _ => 0.0,
        };
        let clear_top = face_clearance(u, eta, set.blank_od_mm, depth + crown, true);
        // Only a cone's blank and depth differ at its other face.
        let clear_bottom = if u.class == GearClass::Conical {
            face_clearance(u, eta, set.blank_od_mm, depth + crown, false)
        } else {
            clear_top
        };
        // The cut's ΔH′ is the one at the face the hob approaches.
        let clearance = if process.cut_mode == CutMode::Conventional {
            clear_top
        } else {
            clear_bottom
        };
        let shift_mm = shift
            .as_ref()
            .map(|r| r.shift_mm(0, u64::from(i - 1), u64::from(n)));
        let frame = CutFrame {
            home: Position {
                x_mm: machine.home_x_mm,
                z_mm: machine.home_z_mm,
            },
            xc_mm: outer - depth + gear.od_correction_mm,
            bottom_face_mm: gear.fixture_height_mm,
            face_width_mm: gear.face_width_mm,
            over_top_mm: clear_top + safety,
            over_bottom_mm: clear_bottom + safety,
            safety_mm: safety,
            retract_mm: machine.settings.retract_mm,
            exit_mm: machine.settings.exit_mm,
            down: process.cut_mode == CutMode::Conventional,
            axial_feed_mm_min: axial_feed,
            radial_feed_mm_min: radial_feed,
            shift_mm,
            clear_x_mm: clear_x,
        };
        let cut_path = match u.class {
            GearClass::Conical => {
                let cone = gear.cone.as_ref().expect("conical class has a cone");
                path::conical(&frame, cone.angle_deg, cone.large_end, hob_radii(u.hob))
            }
            GearClass::Crowned => {
                let cr = gear
                    .crowning
                    .as_ref()
                    .expect("crowned class has a crowning");
                let tol = cr
                    .chord_tolerance_mm
                    .unwrap_or(path::DEFAULT_CHORD_TOLERANCE_MM);
                let chords = match cr.shape {
                    CrowningShape::Circular => 0,
                    CrowningShape::Parabolic => path::parabolic_chords(cr.amount_mm, tol),
                };
                let (cp, deviation) = path::crowned(&frame, cr.shape, cr.amount_mm, chords);
                crowning_info = Some(CrowningModel {
                    shape: cr.shape,
                    amount_mm: cr.amount_mm,
                    radius_mm: (cr.shape == CrowningShape::Circular)
                        .then(|| path::crowning_radius_mm(gear.face_width_mm, cr.amount_mm)),
                    chords,
                    tolerance_mm: tol,
                    max_deviation_mm: deviation,
                });
                cp
            }
            GearClass::WormWheel => {
                let w = worm.expect("worm wheel class has worm data");
                let ra2 = set.blank_od_mm / 2.0;
                let a = outer - depth;
                let half_chord = (ra2 * ra2 - (a - hob.od_mm / 2.0).powi(2)).max(0.0).sqrt();
                let y_start = -(hob.length_mm / 2.0 + half_chord + safety);
                let y_end = hob.length_mm / 2.0 + half_chord;
                let dwell_rev = w.dwell_rev.unwrap_or(DEFAULT_WORM_DWELL_REV);
                let tangential = w
                    .tangential_feed_mm_per_rev
                    .unwrap_or(process.feed_mm_per_rev)
                    * table_rpm;
                let wf = WormFrame {
                    infeed: w.infeed,
                    throat_z_mm: throat_z,
                    dwell_s: 60.0 * dwell_rev / table_rpm,
                    tangential_feed_mm_min: tangential,
                    y_mm: [y_start, y_end],
                };
                worm_info = Some(WormModel {
                    infeed: w.infeed,
                    centre_distance_mm: a,
                    throat_z_mm: throat_z,
                    start_x_mm: clear_x,
                    radial_feed_mm_min: radial_feed,
                    dwell_s: wf.dwell_s,
                    start_y_mm: y_start,
                    end_y_mm: y_end,
                    tangential_feed_mm_min: tangential,
                });
                path::worm_wheel(&frame, &wf)
            }
            _ => match u.infeed() {
                Infeed::Axial => path::axial(&frame),
                Infeed::RadialAxial => path::radial_axial(&frame),
            },
        };
        let time = path::time_min(
            cut_path.positions.B,
            shift_mm.unwrap_or(0.0),
            &cut_path.moves,
        );
        cuts.push(Cut {
            number: i,
            finish,
            depth_mm: depth,
            allowance_mm: set.depth_mm - depth,
            centre_distance_mm: outer - depth,
            clearance_mm: clearance,
            positions: cut_path.positions,
            feed_mm_per_rev: fa,
            table_rpm,
            axial_feed_mm_min: axial_feed,
            radial_feed_mm_min: if u.infeed() == Infeed::RadialAxial
                || (u.class == GearClass::WormWheel
                    && worm.map(|w| w.infeed) == Some(WormInfeed::Radial))
            {
                radial_feed
            } else {
                0.0
            },
            shift_mm: shift_mm.unwrap_or(0.0),
            resync: i > 1,
            moves: cut_path.moves,
            time_min: time,
        });
    }

    let last = cuts.last().expect("at least one cut").clone();
    let fa = last.feed_mm_per_rev;
    let part_time: f64 = cuts.iter().map(|c| c.time_min).sum();
    let cone = gear
        .cone
        .as_ref()
        .filter(|_| u.class == GearClass::Conical)
        .map(|c| {
            let slope = path::cone_slope(c.angle_deg, c.large_end);
            let xc = last.centre_distance_mm + gear.od_correction_mm;
            let (lift, _) = path::cone_offsets(c.angle_deg, hob_radii(u.hob));
            ConeModel {
                angle_deg: c.angle_deg,
                large_end: c.large_end,
                x_per_z: slope,
                x_large_mm: xc + lift,
                x_small_mm: xc + lift - c.angle_deg.to_radians().tan() * gear.face_width_mm,
            }
        });
    let coupling = coupling(hob, gear.teeth);
    let c_per_z = if axial { differential } else { 0.0 };
    let on_machine = frame::to_machine(&machine.settings, eta, coupling, c_per_z, c_per_y);
    Kinematics {
        swivel_deg: eta,
        swivel_axis_deg: on_machine.swivel_axis_deg,
        clearance_mm: last.clearance_mm,
        safety_mm: safety,
        centre_distance_mm: last.centre_distance_mm,
        depth_mm: set.depth_mm,
        blank_od_mm: set.blank_od_mm,
        positions: last.positions,
        hob_rpm,
        index_rpm,
        table_rpm: last.table_rpm,
        axial_feed_mm_min: last.axial_feed_mm_min,
        differential_deg_per_mm: c_per_z,
        coupling,
        // The reported cut time of the axial stroke, (b + 2·ΔH′)·z/(Nt·z0·fa);
        // a worm wheel has no axial stroke, so its cut time is the finishing
        // cut's radial or tangential feed time.
        cut_time_min: if axial {
            (gear.face_width_mm + 2.0 * last.clearance_mm) * z / (hob_rpm * z0 * fa)
        } else {
            last.time_min
        },
        cut_mode: process.cut_mode,
        cuts,
        class: u.class,
        infeed: u.infeed(),
        factors: CouplingFactors {
            c_per_b: on_machine.c_per_b,
            c_per_z_deg_per_mm: on_machine.c_per_z_deg_per_mm,
            c_per_y_deg_per_mm: on_machine.c_per_y_deg_per_mm,
        },
        part_time_min: part_time,
        job_time_min: part_time * f64::from(u.quantity),
        shift: shift.map(|r| r.plan(u.quantity, n)),
        cone,
        crowning: crowning_info,
        worm: worm_info,
        units: Vec::new(),
        explain: Vec::new(),
    }
}
