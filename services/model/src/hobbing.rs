//! The hobbing model of a cylindrical gear (SPEC §4.3, patent step 3): hob
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

/// Samples of the dense scan for ΔH′ before golden-section refinement.
pub const CLEARANCE_SAMPLES: usize = 128;

/// Hob reference diameter d0 = z0·mn0 / sin γ0, mm (SPEC §4.2 check 4).
pub fn hob_reference_diameter_mm(hob: &HobData) -> f64 {
    f64::from(hob.starts) * hob.module_mm / hob.lead_angle_deg.to_radians().sin()
}

/// The blank outside diameter used: the job's `blank_od_mm`, or the theoretical
/// tip diameter da when the job gives none.
pub fn blank_od_mm(gear: &GearSpec, geometry: &Geometry) -> f64 {
    gear.blank_od_mm.unwrap_or(geometry.da_mm)
}

/// Theoretical centre distance of hob and gear (SPEC §4.2 check 5), mm:
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
/// h = (da0 + Da1)/2 − L_theory (SPEC §4.2 check 1).
pub fn setup(plan: &ProcessPlan, geometry: &Geometry) -> Setup {
    setup_unit(&Unit::of_plan(plan), geometry)
}

/// True when gear helix and hob thread have the same hand. A spur gear (or a
/// gear without a hand, which validation only allows for spur gears) takes the
/// same-hand branch.
pub fn same_hand(gear: &GearSpec, hob: &HobData) -> bool {
    match gear.helix_hand {
        Some(hand) if !is_spur(gear) => hand == hob.hand,
        _ => true,
    }
}

/// The signed setting angle η = s_g·β − s_h·γ0 of the hob axis in the
/// machine-neutral frame, degrees ([`crate::frame`]; `docs/hobbing.md`).
///
/// The patent prints γ = −(|β| ∓ |γ0|): the magnitude of η with one machine's
/// sign, which gives mirror-image set-ups (left-hand gear and hob, or a spur
/// gear cut with a left-hand hob) the same swivel as the right-hand ones.
pub fn swivel_deg(gear: &GearSpec, hob: &HobData) -> f64 {
    frame::setting_angle_deg(gear, hob)
}

/// Sign of the differential speed in the table-speed magnitude
/// Nw = Ni/(1 − s·fa/Pz) (patent formula ③, speeds as magnitudes):
/// conventional cut with same hands +1, with opposite hands −1; a climb cut
/// reverses both. It never enters a signed coupling factor: the differential
/// coupling C per Z is the gear's alone ([`frame::differential_deg_per_mm`]).
pub fn table_speed_sign(gear: &GearSpec, hob: &HobData, mode: CutMode) -> f64 {
    let same = same_hand(gear, hob);
    match (mode, same) {
        (CutMode::Conventional, true) | (CutMode::Climb, false) => 1.0,
        (CutMode::Conventional, false) | (CutMode::Climb, true) => -1.0,
    }
}

/// The homogeneous transform from the hob frame (Xd, Yd, Zd; Yd the hob
/// axis, tilted by γ against the gear end face) to the gear frame (Xg, Yg,
/// Zg; Zg the gear axis), with the hob centre at (L, 0, Z0) (the patent's):
///
/// ```text
/// ⎡Xg⎤   ⎡−1    0      0    L ⎤ ⎡Xd⎤
/// ⎢Yg⎥ = ⎢ 0  cos γ  sin γ  0 ⎥ ⎢Yd⎥
/// ⎢Zg⎥   ⎢ 0 −sin γ  cos γ  Z0⎥ ⎢Zd⎥
/// ⎣1 ⎦   ⎣ 0    0      0    1 ⎦ ⎣1 ⎦
/// ```
pub fn hob_to_gear(swivel_deg: f64, centre_distance_mm: f64, hob_height_mm: f64) -> Matrix4<f64> {
    let (s, c) = swivel_deg.to_radians().sin_cos();
    #[rustfmt::skip]
    let m = Matrix4::new(
        -1.0, 0.0, 0.0, centre_distance_mm,
        0.0, c, s, 0.0,
        0.0, -s, c, hob_height_mm,
        0.0, 0.0, 0.0, 1.0,
    );
    m
}

/// The approach-clearance problem: how far the tilted hob reaches below its
/// centre over the blank when it stands at its final centre distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// Blank outside diameter Da1 at the face the hob approaches, mm (R = Da1/2).
    pub blank_od_mm: f64,
    /// Hob outside diameter da0, mm (r = da0/2).
    pub hob_od_mm: f64,
    /// Radial depth h, mm (L = R + r − h).
    pub depth_mm: f64,
    /// Hob swivel, degrees; only its magnitude γ = |η| matters (a tilt either
    /// way is the mirror image: the reach moves to the other side of the blank).
    pub swivel_deg: f64,
    /// Hob length, mm: hob points lie within ±length/2 of the centre along
    /// its axis.
    pub hob_length_mm: f64,
}

/// The solution of a [`Clearance`] problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceSolution {
    /// ΔH′, the largest reach below the hob centre over the blank disc, mm
    /// (no safety distance).
    pub clearance_mm: f64,
    /// The hob-frame x of the lowest point, mm.
    pub x_mm: f64,
    /// The hob-axial coordinate y of the lowest point, mm.
    pub hob_axial_mm: f64,
    /// True when no point of the hob's tip cylinder lies over the blank disc,
    /// so the unbounded maximum was taken (the larger, safe value).
    pub length_bound_ignored: bool,
}

impl Clearance {
    fn radii(&self) -> (f64, f64, f64) {
        let big_r = self.blank_od_mm / 2.0;
        let r = self.hob_od_mm / 2.0;
        (big_r, r, big_r + r - self.depth_mm)
    }

    /// Final centre distance L = R + r − h, mm.
    pub fn centre_distance_mm(&self) -> f64 {
        self.radii().2
    }

    /// The interval (L − R, r) of x, clipped to where both roots are real.
    pub fn domain(&self) -> (f64, f64) {
        let (big_r, r, l) = self.radii();
        ((l - big_r).max(-r), r.min(l + big_r))
    }

    /// (√(r² − x²), √(R² − (L − x)²)): the depth of the hob's tip cylinder
    /// below its axis at x, and the half chord of the blank disc there.
    fn roots(&self, x: f64) -> (f64, f64) {
        let (big_r, r, l) = self.radii();
        (
            (r * r - x * x).max(0.0).sqrt(),
            (big_r * big_r - (l - x) * (l - x)).max(0.0).sqrt(),
        )
    }

    /// ΔH(x) = √(r² − x²)/cos γ + √(R² − (L − x)²)·tan γ, mm: the reach of an
    /// unbounded hob at x. (The patent prints the factor cos γ − tan γ·sin γ
    /// = cos 2γ/cos γ instead of 1/cos γ, too small for every γ > 0.)
    ///
    /// Derivation: a tip-cylinder point (x, y, −s), s = √(r² − x²), lies
    /// s·cos γ + y·sin γ below the hob centre and over the blank at gear
    /// Yg = y·cos γ − s·sin γ; the reach grows with y, so the lowest point
    /// over the disc (|Yg| ≤ w) has Yg = w.
    pub fn delta_h(&self, x: f64) -> f64 {
        let g = self.swivel_deg.abs().to_radians();
        let (s, w) = self.roots(x);
        s / g.cos() + w * g.tan()
    }

    /// Hob-axial coordinate y = (√(R² − (L − x)²) + √(r² − x²)·sin γ)/cos γ of
    /// the unbounded hob's lowest point at x, mm.
    pub fn hob_axial_mm(&self, x: f64) -> f64 {
        let g = self.swivel_deg.abs().to_radians();
        let (s, w) = self.roots(x);
        (w + s * g.sin()) / g.cos()
    }

    /// The reach at x of the hob of finite length, with the hob-axial y of
    /// its lowest point over the disc; `None` when no point of the hob at x
    /// lies over the blank disc.
    pub fn reach_at(&self, x: f64) -> Option<(f64, f64)> {
        let (big_r, _, l) = self.radii();
        if (l - x).abs() > big_r {
            return None;
        }
        let g = self.swivel_deg.abs().to_radians();
        let (sin_g, cos_g) = g.sin_cos();
        let (s, w) = self.roots(x);
        let half = self.hob_length_mm / 2.0;
        let y_hi = ((w + s * sin_g) / cos_g).min(half);
        let y_lo = ((-w + s * sin_g) / cos_g).max(-half);
        (y_hi >= y_lo).then_some((y_hi * sin_g + s * cos_g, y_hi))
    }

    /// The contact point at x in gear coordinates (hob centre at height 0).
    pub fn contact_in_gear_frame(&self, x: f64) -> Vector4<f64> {
        let (_, r, l) = self.radii();
        let z = -(r * r - x * x).max(0.0).sqrt();
        let y = self.hob_axial_mm(x);
        hob_to_gear(self.swivel_deg.abs(), l, 0.0) * Vector4::new(x, y, z, 1.0)
    }

    /// ΔH′ = the largest [`Self::reach_at`] over the domain: a dense scan of
    /// [`CLEARANCE_SAMPLES`] points (end points included), golden-section
    /// refinement around the best sample, and the edges of the window where
    /// the hob lies over the disc found by bisection (the maximum may sit
    /// on one). When no point of the hob lies over the disc, the unbounded
    /// maximum of [`Self::delta_h`] is taken (never smaller, so safe).
    pub fn solve(&self) -> ClearanceSolution {
        let (lo, hi) = self.domain();
        if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
            // No overlap of hob and blank (h ≤ 0): nothing to clear.
            return ClearanceSolution {
                clearance_mm: 0.0,
                x_mm: hi,
                hob_axial_mm: 0.0,
                length_bound_ignored: false,
            };
        }
        let bounded = |x: f64| self.reach_at(x).map_or(f64::NEG_INFINITY, |v| v.0);
        let mut best = self.maximise(lo, hi, &bounded);
        if best.1 == f64::NEG_INFINITY {
            let free = |x: f64| self.delta_h(x);
            let best = self.maximise(lo, hi, &free);
            return ClearanceSolution {
                clearance_mm: best.1,
                x_mm: best.0,
                hob_axial_mm: self.hob_axial_mm(best.0),
                length_bound_ignored: true,
            };
        }
        let inside = |x: f64| self.reach_at(x).is_some();
        let n = CLEARANCE_SAMPLES;
        let step = (hi - lo) / (n - 1) as f64;
        let at = |i: usize| if i == n - 1 { hi } else { lo + step * i as f64 };
        let mut was = inside(lo);
        for i in 1..n {
            let now = inside(at(i));
            if now != was {
                let (mut a, mut b) = if was {
                    (at(i - 1), at(i))
                } else {
                    (at(i), at(i - 1))
                };
                // a is inside, b outside.
                for _ in 0..60 {
                    let m = (a + b) / 2.0;
                    if inside(m) {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                let v = bounded(a);
                if v > best.1 {
                    best = (a, v);
                }
            }
            was = now;
        }
        ClearanceSolution {
            clearance_mm: best.1,
            x_mm: best.0,
            hob_axial_mm: self.reach_at(best.0).map_or(0.0, |v| v.1),
            length_bound_ignored: false,
        }
    }

    /// Dense scan then golden section; returns (argmax, max).
    fn maximise(&self, lo: f64, hi: f64, f: &dyn Fn(f64) -> f64) -> (f64, f64) {
        let n = CLEARANCE_SAMPLES;
        let step = (hi - lo) / (n - 1) as f64;
        let at = |i: usize| if i == n - 1 { hi } else { lo + step * i as f64 };
        let (mut best_i, mut best) = (0, f(lo));
        for i in 1..n {
            let v = f(at(i));
            if v > best {
                best_i = i;
                best = v;
            }
        }
        if best == f64::NEG_INFINITY {
            return (lo, best);
        }
        let mut a = at(best_i.saturating_sub(1));
        let mut b = at((best_i + 1).min(n - 1));
        let inv_phi = (5f64.sqrt() - 1.0) / 2.0;
        let mut c = b - inv_phi * (b - a);
        let mut d = a + inv_phi * (b - a);
        let (mut fc, mut fd) = (f(c), f(d));
        for _ in 0..80 {
            if b - a <= 1e-12 * (1.0 + hi.abs()) {
                break;
            }
            if fc >= fd {
                b = d;
                d = c;
                fd = fc;
                c = b - inv_phi * (b - a);
                fc = f(c);
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + inv_phi * (b - a);
                fd = f(d);
            }
        }
        let x_mid = (a + b) / 2.0;
        let (x_best, v_best) =
            [(x_mid, f(x_mid)), (c, fc), (d, fd)]
                .into_iter()
                .fold(
                    (at(best_i), best),
                    |acc, p| if p.1 > acc.1 { p } else { acc },
                );
        (x_best, v_best)
    }
}

/// The indexing ratio s_h·z0 : z in the machine-neutral frame, reduced and
/// kept as exact integers ([`frame::indexing`]).
pub fn coupling(hob: &HobData, teeth: u32) -> Ratio {
    frame::indexing(hob, teeth)
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
}

impl<'a> Unit<'a> {
    /// The job's own gear as a unit (for a multi-gear job: its first unit).
    pub fn of_plan(plan: &'a ProcessPlan) -> Unit<'a> {
        let spec = &plan.request.spec;
        Unit {
            gear: &spec.gear,
            hob: &plan.hob,
            process: &plan.process,
            overrides: &spec.process,
            machine: &plan.machine,
            quantity: spec.job.quantity,
            class: unit_class(&spec.gear),
            proposed_allowance_mm: plan.values.get("allowance_mm").map(|v| v.value),
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

    /// Feed per revolution of the finishing cut: the job's
    /// `finish_feed_mm_per_rev` when there are several cuts, else the feed.
    pub fn finish_feed_mm_per_rev(&self) -> f64 {
        match (self.process.cuts > 1, self.overrides.finish_feed_mm_per_rev) {
            (true, Some(f)) => f,
            _ => self.process.feed_mm_per_rev,
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

/// Shift compensation C per Y = −360·cos γ0/(π·mn0·z) degrees of table per
/// mm of hob shift along the hob axis, in the machine-neutral frame
/// ([`frame::shift_compensation_deg_per_mm`]): a shift by one axial pitch
/// π·mn0/cos γ0 turns the table by one gear pitch, 360°/z, for either hand.
pub fn shift_compensation_deg_per_mm(hob: &HobData, teeth: u32) -> f64 {
    frame::shift_compensation_deg_per_mm(hob, teeth)
}

/// The blank diameter the hob meets at one face (top or bottom): a
/// cylinder's everywhere; a cone's is smaller by 2·b·tan δ at its small end.
/// The depth there is the cut's (the hob's X holds the face's value beyond
/// the face, [`crate::path::conical`]).
fn end_blank_od(u: &Unit, blank_od_mm: f64, top: bool) -> f64 {
    match (u.class, u.gear.cone.as_ref()) {
        (GearClass::Conical, Some(cone)) => {
            let large_on_top = cone.large_end == gearcam_proto::LargeEnd::Top;
            if large_on_top == top {
                blank_od_mm
            } else {
                blank_od_mm - 2.0 * u.gear.face_width_mm * cone.angle_deg.to_radians().tan()
            }
        }
        _ => blank_od_mm,
    }
}

/// ΔH′ at one face (top or bottom) of a unit's blank: a cone's at that
/// face's own blank radius (the end the hob approaches may be the small one).
fn face_clearance(u: &Unit, eta: f64, blank: f64, depth: f64, top: bool) -> f64 {
    Clearance {
        blank_od_mm: end_blank_od(u, blank, top),
        hob_od_mm: u.hob.od_mm,
        depth_mm: depth,
        swivel_deg: eta,
        hob_length_mm: u.hob.length_mm,
    }
    .solve()
    .clearance_mm
}

/// The hobbing kinematics of a validated plan's own gear (SPEC §4.3–4.4), see
/// [`unit_kinematics`].
pub fn kinematics(plan: &ProcessPlan, geometry: &Geometry) -> Kinematics {
    unit_kinematics(&Unit::of_plan(plan), geometry)
}

/// The hobbing kinematics of one validated unit (SPEC §4.3–4.4):
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
/// - cut time of the SPEC, (b + 2·ΔH′)·z/(Nt·z0·fa) for the finishing cut, the
///   time of every cut from its feed moves and dwells, per part and per job.
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
        // Only a cone's blank differs at its other face.
        let clear_bottom =
            if end_blank_od(u, set.blank_od_mm, false) == end_blank_od(u, set.blank_od_mm, true) {
                clear_top
            } else {
                face_clearance(u, eta, set.blank_od_mm, depth + crown, false)
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
                path::conical(&frame, cone.angle_deg, cone.large_end)
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
            ConeModel {
                angle_deg: c.angle_deg,
                large_end: c.large_end,
                x_per_z: slope,
                x_large_mm: xc,
                x_small_mm: xc - c.angle_deg.to_radians().tan() * gear.face_width_mm,
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
        // The SPEC's axial-feed formula; a worm wheel has no axial stroke, so
        // its cut time is the finishing cut's radial or tangential feed time.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures;
    use crate::geometry::geometry;
    use approx::assert_relative_eq;
    use gearcam_proto::Hand;

    fn kin(plan: &ProcessPlan) -> Kinematics {
        kinematics(plan, &geometry(&plan.request.spec.gear))
    }

    #[test]
    fn spec_worked_self_check_helical() {
        // SPEC §4.3 worked self-check: da0 80, vc 100, z0 1, z 25, fa 2, mn 3, β 15°
        // → Nt 397.887 rpm, Ni 15.9155 rpm, differential 0.395446 °/mm.
        let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
        assert_relative_eq!(k.hob_rpm, 397.887, epsilon = 5e-4);
        assert_relative_eq!(k.index_rpm, 15.9155, epsilon = 5e-5);
        assert_relative_eq!(k.differential_deg_per_mm, 0.395446, epsilon = 5e-7);
        // Same hands, conventional: s = +1, Pz = π·3·25/sin 15° = 910.3657 mm,
        // Nw = Ni/(1 − 2/Pz) (independent Python computation).
        assert_relative_eq!(k.table_rpm, 15.950_536_430_075, epsilon = 1e-9);
        assert_relative_eq!(k.axial_feed_mm_min, 31.901_072_860_149, epsilon = 1e-9);
    }

    #[test]
    fn spur_feed_is_fa_times_index_speed() {
        // SPEC §4.3: spur Vf = fa·z0·Nt/z = 2·15.9155 = 31.831 mm/min, no differential.
        let k = kin(&fixtures::plan());
        assert_relative_eq!(k.axial_feed_mm_min, 31.831, epsilon = 5e-4);
        assert_eq!(k.table_rpm, k.index_rpm);
        assert_eq!(k.differential_deg_per_mm, 0.0);
    }

    #[test]
    fn differential_flips_with_cut_mode_and_hob_hand() {
        // Issue 10 defect 1: the C-per-Z coupling belongs to the gear's helix
        // alone. Before the fix a climb cut or a left-hand hob gave −0.395446.
        let right = kin(&fixtures::helical_plan(15.0, Hand::Right));
        for (hob_hand, mode) in [
            (Hand::Right, CutMode::Climb),
            (Hand::Left, CutMode::Conventional),
            (Hand::Left, CutMode::Climb),
        ] {
            let mut plan = fixtures::helical_plan(15.0, Hand::Right);
            plan.hob.hand = hob_hand;
            plan.process.cut_mode = mode;
            let k = kin(&plan);
            assert_relative_eq!(k.differential_deg_per_mm, 0.395446, epsilon = 5e-7);
            assert_eq!(k.differential_deg_per_mm, right.differential_deg_per_mm);
            assert_eq!(
                k.factors.c_per_z_deg_per_mm,
                right.factors.c_per_z_deg_per_mm
            );
        }
        // The gear's hand alone turns it.
        let left = kin(&fixtures::helical_plan(15.0, Hand::Left));
        assert_relative_eq!(left.differential_deg_per_mm, -0.395446, epsilon = 5e-7);
        // The table speed during the cut is the patent's magnitude rule
        // Nw = Ni/(1 ∓ fa/Pz): opposite hands (or climb) turn slower
        // (independent Python values).
        assert_relative_eq!(left.table_rpm, 15.880_605_820_559, epsilon = 1e-9);
        let mut climb = fixtures::helical_plan(15.0, Hand::Right);
        climb.process.cut_mode = CutMode::Climb;
        assert_relative_eq!(
            kin(&climb).axial_feed_mm_min,
            31.761_211_641_118,
            epsilon = 1e-9
        );
    }

    #[test]
    fn swivel_ignores_the_hands() {
        // Issue 10 defect 2: η = s_g·β − s_h·γ0 (γ0 = 2.3716°). Before the fix
        // a spur gear got +2.3716 for both hob hands and the left-hand mirror
        // image of a right-hand set-up got the same swivel.
        let mut g = fixtures::gear();
        let right = fixtures::hob();
        let left = HobData {
            hand: Hand::Left,
            ..fixtures::hob()
        };
        assert_relative_eq!(swivel_deg(&g, &right), -2.3716, epsilon = 1e-12);
        assert_relative_eq!(swivel_deg(&g, &left), 2.3716, epsilon = 1e-12);
        g.helix_angle_deg = 15.0;
        g.helix_hand = Some(Hand::Right);
        assert_relative_eq!(swivel_deg(&g, &right), 12.6284, epsilon = 1e-12);
        assert_relative_eq!(swivel_deg(&g, &left), 17.3716, epsilon = 1e-12);
        g.helix_hand = Some(Hand::Left);
        assert_relative_eq!(swivel_deg(&g, &right), -17.3716, epsilon = 1e-12);
        assert_relative_eq!(swivel_deg(&g, &left), -12.6284, epsilon = 1e-12);
        // H01 maps A = −η: the right-hand set-up keeps the patent's A = −12.6284.
        let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
        assert_relative_eq!(k.swivel_axis_deg, -12.6284, epsilon = 1e-12);
        let mut mirrored = fixtures::helical_plan(15.0, Hand::Left);
        mirrored.hob.hand = Hand::Left;
        let m = kin(&mirrored);
        assert_relative_eq!(m.swivel_axis_deg, 12.6284, epsilon = 1e-12);
        // A profile's offset and sign map η to its axis.
        mirrored.machine.settings.swivel_sign = 1.0;
        mirrored.machine.settings.swivel_offset_deg = 90.0;
        assert_relative_eq!(
            kin(&mirrored).swivel_axis_deg,
            90.0 - 12.6284,
            epsilon = 1e-12
        );
    }

    #[test]
    fn indexing_840d_ignores_the_hob_hand() {
        // Issue 10 defect 3: the C-per-B ratio's sign is the hob's hand.
        let mut plan = fixtures::plan();
        let k = kin(&plan);
        assert_eq!(k.coupling, Ratio { num: 1, den: 25 });
        assert_eq!(k.factors.c_per_b, Ratio { num: 1, den: 25 });
        plan.hob.hand = Hand::Left;
        let k = kin(&plan);
        assert_eq!(k.coupling, Ratio { num: -1, den: 25 });
        assert_eq!(k.factors.c_per_b, Ratio { num: -1, den: 25 });
        // A machine whose table turns the other way flips the programmed sign.
        plan.machine.settings.table_sign = -1.0;
        assert_eq!(kin(&plan).factors.c_per_b, Ratio { num: 1, den: 25 });
    }

    #[test]
    fn clearance_without_swivel_is_the_approach_length() {
        // SPEC §4.3: for γ = 0, ΔH′ = √(h·(da0 − h)).
        let c = Clearance {
            blank_od_mm: 81.0,
            hob_od_mm: 80.0,
            depth_mm: 6.75,
            swivel_deg: 0.0,
            hob_length_mm: 100.0,
        };
        let s = c.solve();
        assert_relative_eq!(
            s.clearance_mm,
            (6.75f64 * (80.0 - 6.75)).sqrt(),
            epsilon = 1e-9
        );
        assert_relative_eq!(s.clearance_mm, 22.235_950_620_560, epsilon = 1e-9);
        assert!(!s.length_bound_ignored);
    }

    #[test]
    fn delta_h_prime_too_small() {
        // Issue 10 defect 4: the patent's factor cos γ − tan γ·sin γ made ΔH′
        // 2.1 mm short at γ 12.6°, 3.8 mm at 17° and 6.1 mm at 22° for this
        // blank. References: an independent Python sweep of the hob's tip
        // cylinder (2·10⁶ angles around the hob, the lowest point over the
        // blank disc for each), not the ΔH formula.
        for (gamma, want) in [
            (0.0, 22.235_950_620),
            (17.0, 24.466_873_472),
            (22.0, 25.988_919_048),
        ] {
            let c = Clearance {
                blank_od_mm: 85.0,
                hob_od_mm: 80.0,
                depth_mm: 6.75,
                swivel_deg: gamma,
                hob_length_mm: 100.0,
            };
            assert_relative_eq!(c.solve().clearance_mm, want, epsilon = 1e-6);
        }
        // The fixture gears (hob 80 × 100, h 6.750963).
        let k = kin(&fixtures::plan());
        assert_relative_eq!(k.clearance_mm, 22.279_643_304, epsilon = 1e-6);
        let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
        assert_relative_eq!(k.clearance_mm, 23.456_419_441, epsilon = 1e-6);
        let k = kin(&fixtures::helical_plan(15.0, Hand::Left));
        assert_relative_eq!(k.clearance_mm, 24.548_048_363, epsilon = 1e-6);
        // A tilt either way gives the same clearance.
        let mut c = Clearance {
            blank_od_mm: 85.0,
            hob_od_mm: 80.0,
            depth_mm: 6.75,
            swivel_deg: 17.0,
            hob_length_mm: 100.0,
        };
        let plus = c.solve().clearance_mm;
        c.swivel_deg = -17.0;
        assert_eq!(c.solve().clearance_mm, plus);
    }

    #[test]
    fn short_hob_bounds_the_contact_point() {
        // β 20° same hands, η = 17.6284°: a 4 mm hob reaches less far than a
        // 100 mm one (Python sweep of the hob's tip cylinder).
        let mut plan = fixtures::helical_plan(20.0, Hand::Right);
        let free = kin(&plan).clearance_mm;
        assert_relative_eq!(free, 24.649_370_772, epsilon = 1e-6);
        plan.hob.length_mm = 4.0;
        let k = kin(&plan);
        assert_relative_eq!(k.clearance_mm, 21.424_671_864, epsilon = 1e-6);
        let geo = geometry(&plan.request.spec.gear);
        let set = setup(&plan, &geo);
        let s = Clearance {
            blank_od_mm: set.blank_od_mm,
            hob_od_mm: 80.0,
            depth_mm: set.depth_mm,
            swivel_deg: k.swivel_deg,
            hob_length_mm: 4.0,
        }
        .solve();
        assert!(s.hob_axial_mm.abs() <= 2.0 + 1e-12, "{s:?}");
        assert!(!s.length_bound_ignored);
    }

    #[test]
    fn hob_too_short_for_any_contact_falls_back_to_the_free_maximum() {
        let c = Clearance {
            blank_od_mm: 85.0,
            hob_od_mm: 80.0,
            depth_mm: 6.75,
            swivel_deg: 80.0,
            hob_length_mm: 1e-9,
        };
        let bounded = c.solve();
        let free = Clearance {
            hob_length_mm: 1e9,
            ..c
        }
        .solve();
        if bounded.length_bound_ignored {
            assert_eq!(bounded.clearance_mm, free.clearance_mm);
        } else {
            assert!(bounded.clearance_mm <= free.clearance_mm + 1e-9);
        }
    }

    #[test]
    fn contact_point_lies_on_the_blank_cylinder_below_the_hob_centre() {
        let c = Clearance {
            blank_od_mm: 85.0,
            hob_od_mm: 80.0,
            depth_mm: 6.75,
            swivel_deg: -12.0,
            hob_length_mm: 100.0,
        };
        let (lo, hi) = c.domain();
        let l = c.centre_distance_mm();
        for i in 1..10 {
            let x = lo + (hi - lo) * f64::from(i) / 10.0;
            let p = c.contact_in_gear_frame(x);
            assert_relative_eq!(p.x, l - x, epsilon = 1e-12);
            assert_relative_eq!(p.x * p.x + p.y * p.y, 42.5 * 42.5, epsilon = 1e-9);
            // The point lies ΔH(x) below the hob centre.
            assert_relative_eq!(-p.z, c.delta_h(x), epsilon = 1e-9);
            // And on the hob's tip cylinder: distance r from the hob axis.
            let g = 12f64.to_radians();
            let axis = [0.0, g.cos(), -g.sin()];
            let v = [p.x - l, p.y, p.z];
            let along = v[1] * axis[1] + v[2] * axis[2];
            let d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - along * along;
            assert_relative_eq!(d2.sqrt(), 40.0, epsilon = 1e-9);
        }
    }

    #[test]
    fn positions_conventional_and_climb() {
        // L 73.749037, ΔH′ 22.279643 (Python sweep), top = 100 + 30 + ΔH′ + 2.
        let plan = fixtures::plan();
        let p = kin(&plan).positions;
        let (xc, top, bottom) = (73.749_036_780_371, 154.279_643_304, 75.720_356_696);
        assert_eq!((p.A.x_mm, p.A.z_mm), (300.0, 350.0));
        assert_relative_eq!(p.B.x_mm, xc + 100.0, epsilon = 1e-9);
        assert_relative_eq!(p.B.z_mm, top, epsilon = 1e-6);
        assert_relative_eq!(p.C.x_mm, xc, epsilon = 1e-9);
        assert_relative_eq!(p.C.z_mm, top, epsilon = 1e-6);
        assert_relative_eq!(p.D.x_mm, xc, epsilon = 1e-9);
        assert_relative_eq!(p.D.z_mm, bottom, epsilon = 1e-6);
        assert_relative_eq!(p.E.x_mm, xc + 5.0, epsilon = 1e-9);
        assert_relative_eq!(p.E.z_mm, bottom, epsilon = 1e-6);

        let mut climb = fixtures::plan();
        climb.process.cut_mode = CutMode::Climb;
        climb.request.spec.gear.od_correction_mm = 0.1;
        let q = kin(&climb).positions;
        assert_relative_eq!(q.B.x_mm, xc + 100.1, epsilon = 1e-9);
        assert_relative_eq!(q.B.z_mm, bottom, epsilon = 1e-6);
        assert_relative_eq!(q.C.z_mm, bottom, epsilon = 1e-6);
        assert_relative_eq!(q.D.z_mm, top, epsilon = 1e-6);
        assert_relative_eq!(q.E.x_mm, xc + 5.1, epsilon = 1e-9);
        assert_relative_eq!(q.E.z_mm, top, epsilon = 1e-6);
    }

    #[test]
    fn given_depth_sets_the_centre_distance() {
        let mut plan = fixtures::plan();
        plan.process.depth_mm = Some(6.0);
        let k = kin(&plan);
        // L = (80 + 81)/2 − 6 = 74.5.
        assert_relative_eq!(k.centre_distance_mm, 74.5, epsilon = 1e-12);
        assert_eq!(k.depth_mm, 6.0);
    }

    #[test]
    fn coupling_is_reduced_and_exact() {
        let hob = |starts, hand| HobData {
            starts,
            hand,
            ..fixtures::hob()
        };
        assert_eq!(
            coupling(&hob(1, Hand::Right), 25),
            Ratio { num: 1, den: 25 }
        );
        assert_eq!(
            coupling(&hob(2, Hand::Right), 40),
            Ratio { num: 1, den: 20 }
        );
        assert_eq!(
            coupling(&hob(3, Hand::Left), 40),
            Ratio { num: -3, den: 40 }
        );
    }

    #[test]
    fn rough_cuts_leave_the_allowance_from_job_case_or_default() {
        use gearcam_proto::{Source, Sourced};
        let mut plan = fixtures::plan();
        plan.process.cuts = 3;
        // Default 0.1·mn = 0.3 mm; rough cuts share h − 0.3 evenly.
        let k = kin(&plan);
        let h = k.depth_mm;
        let depths: Vec<f64> = k.cuts.iter().map(|c| c.depth_mm).collect();
        assert_relative_eq!(depths[0], (h - 0.3) / 2.0, epsilon = 1e-12);
        assert_relative_eq!(depths[1], h - 0.3, epsilon = 1e-12);
        assert_relative_eq!(depths[2], h, epsilon = 1e-12);
        assert!(k.cuts[1].resync && k.cuts[2].resync && !k.cuts[0].resync);
        // A case's proposal replaces the default; the job's value wins over both.
        plan.values.insert(
            "allowance_mm".into(),
            Sourced {
                value: 0.4,
                source: Source::Case,
            },
        );
        assert_relative_eq!(kin(&plan).cuts[1].allowance_mm, 0.4, epsilon = 1e-12);
        plan.request.spec.process.finish_allowance_mm = Some(0.25);
        assert_relative_eq!(kin(&plan).cuts[1].allowance_mm, 0.25, epsilon = 1e-12);
        // Each cut is timed from its own feed stroke; the part time is their sum.
        let k = kin(&plan);
        let sum: f64 = k.cuts.iter().map(|c| c.time_min).sum();
        assert_relative_eq!(k.part_time_min, sum, epsilon = 1e-12);
        assert_relative_eq!(k.job_time_min, sum * 10.0, epsilon = 1e-9);
    }

    #[test]
    fn shift_compensation_is_one_gear_pitch_per_hob_axial_pitch() {
        // |C per Y| = 360·cos γ0/(π·mn0·z): a shift by px0 = π·mn0/cos γ0
        // turns the table by 360°/z, the same way for both hands (the frame
        // module's tests derive the sign from the tooth phase).
        let hob = fixtures::hob();
        let c = shift_compensation_deg_per_mm(&hob, 25);
        let px0 = PI * 3.0 / 2.3716f64.to_radians().cos();
        assert_relative_eq!(c * px0, -360.0 / 25.0, epsilon = 1e-12);
        let left = HobData {
            hand: Hand::Left,
            ..hob
        };
        assert_eq!(shift_compensation_deg_per_mm(&left, 25), c);
    }

    #[test]
    fn cut_time_is_axial_travel_over_feed_rate() {
        // (b + 2ΔH′)·z/(Nt·z0·fa) with the Python reference values.
        let k = kin(&fixtures::plan());
        // (30 + 2·22.279643)·25/(397.887·1·2) (Python).
        let want = (30.0 + 2.0 * 22.279_643_304) * 25.0 / (1000.0 * 100.0 / (PI * 80.0) * 2.0);
        assert_relative_eq!(k.cut_time_min, want, epsilon = 1e-6);
    }
}
