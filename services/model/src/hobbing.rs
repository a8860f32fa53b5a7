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
    Geometry, Hand, HobData, Infeed, Kinematics, MachineProfile, Position, ProcessData,
    ProcessOverrides, ProcessPlan, Ratio, WormInfeed, WormModel,
};
use nalgebra::{Matrix4, Vector4};

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

/// Swivel angle γ of the hob head, degrees (patent step 3①):
/// γ = −(|β| − |γ0|) for same hands, γ = −(|β| + |γ0|) for opposite hands.
///
/// A spur gear takes the same-hand branch, so γ = +|γ0|: the hob is tilted by
/// its own lead angle so that its thread runs parallel to the gear axis.
pub fn swivel_deg(gear: &GearSpec, hob: &HobData) -> f64 {
    let beta = gear.helix_angle_deg.abs();
    let gamma0 = hob.lead_angle_deg.abs();
    if same_hand(gear, hob) {
        -(beta - gamma0)
    } else {
        -(beta + gamma0)
    }
}

/// Sign s of the differential (patent formula ③): conventional cut with same
/// hands +1, with opposite hands −1; a climb cut reverses both.
pub fn differential_sign(gear: &GearSpec, hob: &HobData, mode: CutMode) -> f64 {
    let same = same_hand(gear, hob);
    match (mode, same) {
        (CutMode::Conventional, true) | (CutMode::Climb, false) => 1.0,
        (CutMode::Conventional, false) | (CutMode::Climb, true) => -1.0,
    }
}

/// The patent's homogeneous transform from the hob frame (Xd, Yd, Zd; Yd the
/// hob axis, tilted by γ against the gear end face) to the gear frame
/// (Xg, Yg, Zg; Zg the gear axis), with the hob centre at (L, 0, Z0):
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

/// The approach-clearance problem: where the tilted hob first touches the blank.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// Blank outside diameter Da1, mm (R = Da1/2).
    pub blank_od_mm: f64,
    /// Hob outside diameter da0, mm (r = da0/2).
    pub hob_od_mm: f64,
    /// Radial depth h, mm (L = R + r − h).
    pub depth_mm: f64,
    /// Hob swivel γ, degrees; only |γ| matters.
    pub swivel_deg: f64,
    /// Usable hob length, mm; contact points beyond ±length/2 from the hob
    /// centre along its axis are not on the hob.
    pub hob_length_mm: f64,
}

/// The solution of a [`Clearance`] problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearanceSolution {
    /// ΔH′ = max ΔH(x), mm (no safety distance).
    pub clearance_mm: f64,
    /// The hob-frame x of the first contact point, mm.
    pub x_mm: f64,
    /// The hob-axial coordinate y of the first contact point, mm.
    pub hob_axial_mm: f64,
    /// True when no contact point lay within the hob length, so the maximum
    /// was taken without the length bound (the larger, safe value).
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

    /// The open interval (L − R, r) of x, clipped to where both roots are real.
    pub fn domain(&self) -> (f64, f64) {
        let (big_r, r, l) = self.radii();
        ((l - big_r).max(-r), r.min(l + big_r))
    }

    /// ΔH(x) = √(r² − x²)·(cos γ − tan γ·sin γ) + √(R² − (L − x)²)·tan γ, mm,
    /// exactly as SPEC §4.3 (the patent's formula), with γ taken as |γ|: a tilt
    /// either way is physically symmetric, the contact simply moves to the
    /// other side of the blank (y′ changes sign).
    pub fn delta_h(&self, x: f64) -> f64 {
        let (big_r, r, l) = self.radii();
        let g = self.swivel_deg.abs().to_radians();
        let (s, c) = g.sin_cos();
        let t = g.tan();
        let hob_root = (r * r - x * x).max(0.0).sqrt();
        let blank_root = (big_r * big_r - (l - x) * (l - x)).max(0.0).sqrt();
        hob_root * (c - t * s) + blank_root * t
    }

    /// Hob-axial coordinate y of the contact point at x, mm.
    ///
    /// The contact point has hob coordinates (x, y, z) with z = √(r² − x²) and
    /// lies on the blank cylinder at gear coordinates Xg = L − x,
    /// Yg = √(R² − (L − x)²). The Yg row of [`hob_to_gear`] is linear in y;
    /// solving it gives y (the convention under which the patent's ΔH follows).
    pub fn hob_axial_mm(&self, x: f64) -> f64 {
        let (big_r, r, l) = self.radii();
        let m = hob_to_gear(self.swivel_deg.abs(), l, 0.0);
        let z = (r * r - x * x).max(0.0).sqrt();
        let y_gear = (big_r * big_r - (l - x) * (l - x)).max(0.0).sqrt();
        (y_gear - m[(1, 0)] * x - m[(1, 2)] * z - m[(1, 3)]) / m[(1, 1)]
    }

    /// The contact point at x in gear coordinates (hob centre at height 0).
    pub fn contact_in_gear_frame(&self, x: f64) -> Vector4<f64> {
        let (_, r, l) = self.radii();
        let z = (r * r - x * x).max(0.0).sqrt();
        let y = self.hob_axial_mm(x);
        hob_to_gear(self.swivel_deg.abs(), l, 0.0) * Vector4::new(x, y, z, 1.0)
    }

    /// ΔH′ = max ΔH(x) over the domain: a dense scan of
    /// [`CLEARANCE_SAMPLES`] points (end points included: ΔH is continuous,
    /// so the supremum over the open interval is the maximum over the closed
    /// one), then golden-section refinement on the bracket around the best
    /// sample. Points whose contact lies beyond the hob length are skipped;
    /// when every point does, the bound is dropped (the unbounded maximum is
    /// never smaller, so this errs on the safe side).
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
        let half = self.hob_length_mm / 2.0;
        // ΔH and the hob-axial y at x with the trigonometry hoisted out of
        // the scan: the same expressions as `delta_h` and `hob_axial_mm`
        // (y = (Yg − sin γ·z)/cos γ from the Yg row of `hob_to_gear`), which
        // the tests compare against each other.
        let (big_r, r, l) = self.radii();
        let g = self.swivel_deg.abs().to_radians();
        let (sin_g, cos_g) = g.sin_cos();
        let tan_g = g.tan();
        let hob_factor = cos_g - tan_g * sin_g;
        let roots = move |x: f64| {
            let z = (r * r - x * x).max(0.0).sqrt();
            let yg = (big_r * big_r - (l - x) * (l - x)).max(0.0).sqrt();
            (z, yg)
        };
        let free = |x: f64| {
            let (z, yg) = roots(x);
            z * hob_factor + yg * tan_g
        };
        let bounded = |x: f64| {
            let (z, yg) = roots(x);
            if ((yg - sin_g * z) / cos_g).abs() <= half {
                z * hob_factor + yg * tan_g
            } else {
                f64::NEG_INFINITY
            }
        };
        let mut best = self.maximise(lo, hi, &bounded);
        let mut ignored = false;
        if best.1 == f64::NEG_INFINITY {
            best = self.maximise(lo, hi, &free);
            ignored = true;
        } else {
            // Where the length bound is active the maximum sits on an edge of
            // the window of contact, which may lie between two samples away
            // from the best one: find every edge by bisection and take ΔH
            // there too.
            let inside = |x: f64| {
                let (z, yg) = roots(x);
                ((yg - sin_g * z) / cos_g).abs() <= half
            };
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
                    let v = free(a);
                    if v > best.1 {
                        best = (a, v);
                    }
                }
                was = now;
            }
        }
        ClearanceSolution {
            clearance_mm: best.1,
            x_mm: best.0,
            hob_axial_mm: self.hob_axial_mm(best.0),
            length_bound_ignored: ignored,
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

fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The gearbox coupling z0 : z, reduced by the greatest common divisor and kept
/// as exact integers.
pub fn coupling(hob_starts: u32, teeth: u32) -> Ratio {
    let g = gcd(hob_starts, teeth).max(1);
    Ratio {
        num: hob_starts / g,
        den: teeth / g,
    }
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

/// Shift compensation C per Y = ±360·cos γ0 / (π·mn0·z) degrees of table per
/// mm of hob shift: shifting the hob by one axial pitch π·mn0/cos γ0 moves its
/// thread by one gear pitch, 360°/z (SPEC §4.3 writes mn, which equals mn0
/// when the pressure angles are equal). Positive for a right-hand hob,
/// negative for a left-hand one.
pub fn shift_compensation_deg_per_mm(hob: &HobData, teeth: u32) -> f64 {
    let sign = match hob.hand {
        Hand::Right => 1.0,
        Hand::Left => -1.0,
    };
    sign * 360.0 * hob.lead_angle_deg.to_radians().cos() / (PI * hob.module_mm * f64::from(teeth))
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

    let gamma = swivel_deg(gear, hob);
    let safety = process.safety_mm;
    let z = f64::from(gear.teeth);
    let z0 = f64::from(hob.starts);
    let hob_rpm = 1000.0 * process.cutting_speed_m_min / (PI * hob.od_mm);
    let index_rpm = z0 * hob_rpm / z;
    let (sign, differential, lead) = match lead_mm(gear) {
        None => (0.0, 0.0, None),
        Some(pz) => {
            let s = differential_sign(gear, hob, process.cut_mode);
            let beta = gear.helix_angle_deg.abs().to_radians();
            (
                s,
                s * 360.0 * beta.sin() / (PI * gear.module_mm * z),
                Some(pz),
            )
        }
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
        let clearance = Clearance {
            blank_od_mm: set.blank_od_mm,
            hob_od_mm: hob.od_mm,
            depth_mm: depth + crown,
            swivel_deg: gamma,
            hob_length_mm: hob.length_mm,
        }
        .solve()
        .clearance_mm;
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
            overtravel_mm: clearance + safety,
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
    let coupling = coupling(hob.starts, gear.teeth);
    Kinematics {
        swivel_deg: gamma,
        swivel_axis_deg: machine.settings.swivel_sign * gamma,
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
        differential_deg_per_mm: if axial { differential } else { 0.0 },
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
            c_per_b: coupling,
            c_per_z_deg_per_mm: if axial { differential } else { 0.0 },
            c_per_y_deg_per_mm: c_per_y,
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
    fn differential_sign_follows_hands_and_cut_mode() {
        // Independent Python values: opposite hands or climb cut give s = −1.
        let opposite = kin(&fixtures::helical_plan(15.0, Hand::Left));
        assert_relative_eq!(
            opposite.differential_deg_per_mm,
            -0.395_446_371_786,
            epsilon = 1e-9
        );
        assert_relative_eq!(opposite.table_rpm, 15.880_605_820_559, epsilon = 1e-9);
        let mut climb = fixtures::helical_plan(15.0, Hand::Right);
        climb.process.cut_mode = CutMode::Climb;
        let k = kin(&climb);
        assert_relative_eq!(
            k.differential_deg_per_mm,
            -0.395_446_371_786,
            epsilon = 1e-9
        );
        assert_relative_eq!(k.axial_feed_mm_min, 31.761_211_641_118, epsilon = 1e-9);
        let mut climb_opposite = fixtures::helical_plan(15.0, Hand::Left);
        climb_opposite.process.cut_mode = CutMode::Climb;
        assert_relative_eq!(
            kin(&climb_opposite).differential_deg_per_mm,
            0.395_446_371_786,
            epsilon = 1e-9
        );
    }

    #[test]
    fn swivel_by_hands_and_spur() {
        let hob = fixtures::hob();
        let mut g = fixtures::gear();
        // Spur: same-hand branch, γ = +γ0.
        assert_relative_eq!(swivel_deg(&g, &hob), 2.3716, epsilon = 1e-12);
        g.helix_angle_deg = 15.0;
        g.helix_hand = Some(Hand::Right);
        assert_relative_eq!(swivel_deg(&g, &hob), -12.6284, epsilon = 1e-12);
        g.helix_hand = Some(Hand::Left);
        assert_relative_eq!(swivel_deg(&g, &hob), -17.3716, epsilon = 1e-12);
        let mut plan = fixtures::helical_plan(15.0, Hand::Left);
        plan.machine.settings.swivel_sign = -1.0;
        let k = kin(&plan);
        assert_relative_eq!(k.swivel_deg, -17.3716, epsilon = 1e-12);
        assert_relative_eq!(k.swivel_axis_deg, 17.3716, epsilon = 1e-12);
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
    fn clearance_matches_brute_force_for_helical_gears() {
        // Independent Python brute force over 10⁶ points of the SPEC formula.
        let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
        assert_relative_eq!(k.clearance_mm, 21.344_570_651_702, epsilon = 1e-7);
        let k = kin(&fixtures::helical_plan(15.0, Hand::Left));
        assert_relative_eq!(k.clearance_mm, 20.635_723_184_063, epsilon = 1e-7);
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
        // β 20° same hands, γ = −17.6284°: the free maximum lies at y = 3.25 mm
        // on the hob; a 4 mm hob reaches only y = 2 mm (Python brute force).
        let mut plan = fixtures::helical_plan(20.0, Hand::Right);
        let free = kin(&plan).clearance_mm;
        assert_relative_eq!(free, 20.631_935_817_636, epsilon = 1e-7);
        plan.hob.length_mm = 4.0;
        let k = kin(&plan);
        assert_relative_eq!(k.clearance_mm, 20.607_335_285_218, epsilon = 1e-6);
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
        assert!(s.hob_axial_mm.abs() <= 2.0, "{s:?}");
        assert!(!s.length_bound_ignored);
    }

    #[test]
    fn hob_too_short_for_any_contact_falls_back_to_the_free_maximum() {
        let c = Clearance {
            blank_od_mm: 85.0,
            hob_od_mm: 80.0,
            depth_mm: 6.75,
            swivel_deg: 30.0,
            hob_length_mm: 1e-9,
        };
        let bounded = c.solve();
        let free = Clearance {
            hob_length_mm: 1e9,
            ..c
        }
        .solve();
        assert!(bounded.length_bound_ignored);
        assert_eq!(bounded.clearance_mm, free.clearance_mm);
    }

    #[test]
    fn contact_point_lies_on_the_blank_cylinder() {
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
            // ΔH = y·sin γ + z·cos γ, the patent's definition, equals the closed form.
            let g = 12f64.to_radians();
            let z = (40.0f64 * 40.0 - x * x).sqrt();
            let y = c.hob_axial_mm(x);
            assert_relative_eq!(y * g.sin() + z * g.cos(), c.delta_h(x), epsilon = 1e-9);
        }
    }

    #[test]
    fn positions_conventional_and_climb() {
        // Python reference: L 73.749037, ΔH′ 22.203502, top = 50 + 30 + ΔH′ + 2.
        let plan = fixtures::plan();
        let p = kin(&plan).positions;
        let (xc, top, bottom) = (73.749_036_780_371, 104.203_501_681_800, 25.796_498_318_200);
        assert_eq!((p.A.x_mm, p.A.z_mm), (300.0, 350.0));
        assert_relative_eq!(p.B.x_mm, xc + 100.0, epsilon = 1e-9);
        assert_relative_eq!(p.B.z_mm, top, epsilon = 1e-7);
        assert_relative_eq!(p.C.x_mm, xc, epsilon = 1e-9);
        assert_relative_eq!(p.C.z_mm, top, epsilon = 1e-7);
        assert_relative_eq!(p.D.x_mm, xc, epsilon = 1e-9);
        assert_relative_eq!(p.D.z_mm, bottom, epsilon = 1e-7);
        assert_relative_eq!(p.E.x_mm, xc + 5.0, epsilon = 1e-9);
        assert_relative_eq!(p.E.z_mm, bottom, epsilon = 1e-7);

        let mut climb = fixtures::plan();
        climb.process.cut_mode = CutMode::Climb;
        climb.request.spec.gear.od_correction_mm = 0.1;
        let q = kin(&climb).positions;
        assert_relative_eq!(q.B.x_mm, xc + 100.1, epsilon = 1e-9);
        assert_relative_eq!(q.B.z_mm, bottom, epsilon = 1e-7);
        assert_relative_eq!(q.C.z_mm, bottom, epsilon = 1e-7);
        assert_relative_eq!(q.D.z_mm, top, epsilon = 1e-7);
        assert_relative_eq!(q.E.x_mm, xc + 5.1, epsilon = 1e-9);
        assert_relative_eq!(q.E.z_mm, top, epsilon = 1e-7);
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
        assert_eq!(coupling(1, 25), Ratio { num: 1, den: 25 });
        assert_eq!(coupling(2, 40), Ratio { num: 1, den: 20 });
        assert_eq!(coupling(3, 40), Ratio { num: 3, den: 40 });
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
        // C per Y = 360·cos γ0/(π·mn0·z): a shift by px0 = π·mn0/cos γ0 turns
        // the table by 360°/z.
        let hob = fixtures::hob();
        let c = shift_compensation_deg_per_mm(&hob, 25);
        let px0 = PI * 3.0 / 2.3716f64.to_radians().cos();
        assert_relative_eq!(c * px0, 360.0 / 25.0, epsilon = 1e-12);
        let left = HobData {
            hand: Hand::Left,
            ..hob
        };
        assert_relative_eq!(
            shift_compensation_deg_per_mm(&left, 25),
            -c,
            epsilon = 1e-15
        );
    }

    #[test]
    fn cut_time_is_axial_travel_over_feed_rate() {
        // (b + 2ΔH′)·z/(Nt·z0·fa) with the Python reference values.
        let k = kin(&fixtures::plan());
        assert_relative_eq!(k.cut_time_min, 2.337_564_951_427, epsilon = 1e-7);
    }
}
