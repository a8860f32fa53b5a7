//! The simulation: parameters, axes, gearbox, spindle and switched functions,
//! block by block, and the rules of `DIALECTS.md` applied as it goes.
//!
//! # Tolerances
//!
//! Geometry compares within [`TOL`] (1e-6 mm). A number read from the text is
//! compared with the model's allowing for the rounding the dialect prints:
//! half a unit of the 3rd decimal for lengths, feeds and speeds ([`MM`]), of
//! the 4th for angles ([`DEG`]) and of the 6th for gearbox factors
//! ([`FACTOR`]). FANUC `S` is a whole number and is taken as printed.
//!
//! # The contact zone
//!
//! For each gear unit, the hob (radius r) can touch the blank (radius R, the
//! large end of a cone) only at X below the contact centre distance R + r + Δx
//! and at Z strictly inside the unit's approach band: the face widened on
//! each side by ΔH′ + safety of the cut, which is also the span of the cut's C
//! and D heights (a radial-axial cut enters at the face + safety, so its C
//! lies inside). With several cuts the band widens with depth, so the zone is
//! a staircase: the shallowest cut's band from R + r + Δx down, each deeper
//! cut's band below the previous cut's centre distance. A worm wheel's band is
//! the throat height ± r; for tangential infeed the hob is clear while its
//! shift |Y| is at least the smaller of |start Y| and |end Y|. The zone is
//! open and shrunk by [`MM`] (Y by twice that), so a move along its edge (the
//! model's B→C infeed at the top of the band, D→E retract at the bottom) is
//! outside. A move that only increases X (a radial withdrawal, such as a worm
//! wheel's D→E retract from the throat) leaves the zone and never counts as
//! entering it.

use std::f64::consts::{PI, TAU};

use gearcam_proto::{
    Code, Dialect, GearSpec, HobData, Kinematics, MachineProfile, MachiningModel, MoveKind,
    PathFinding, WormInfeed,
};

use super::expr::{Cond, NcValue, Num, PARAMS};
use super::{
    finding, AxisName, Block, Distance, Interp, Lead, Motion, Op, Trace, TraceArc, TraceCoupling,
    TraceMove,
};
use crate::number::format_fixed;

mod functions;
mod gearbox;
mod motion;
#[cfg(test)]
mod tests;

/// Geometric tolerance, mm.
pub(crate) const TOL: f64 = 1e-6;
/// A length, feed or speed printed with 3 decimals lies within this of the model's.
pub(crate) const MM: f64 = 0.0005 + TOL;
/// An angle printed with 4 decimals lies within this of the model's, degrees.
pub(crate) const DEG: f64 = 0.00005 + 1e-9;
/// A gearbox factor printed with 6 decimals lies within this of the model's.
pub(crate) const FACTOR: f64 = 0.000_000_5 + 1e-9;

/// The shift Y may be reached by an absolute and an incremental word (FANUC),
/// each rounded: the zone's Y limit allows for both.
const Y_MARGIN: f64 = 2.0 * MM;

/// Points an arc is checked at (plus its start).
const ARC_STEPS: usize = 16;

/// The switched functions in the order of [`Sim::function`].
/// The switched functions that must be off when the program stops for the
/// operator (`M0`, a hob change): the fixture stays clamped.
const STOP_OFF: [&str; 4] = [
    "the outer hob support",
    "the coolant",
    "the chip conveyor",
    "the oil mist separator",
];

const FUNCTIONS: [&str; 5] = [
    "the outer hob support",
    "the fixture clamp",
    "the coolant",
    "the chip conveyor",
    "the oil mist separator",
];

fn f3(v: f64) -> String {
    format_fixed(v, 3).unwrap_or_else(|| v.to_string())
}

fn f4(v: f64) -> String {
    format_fixed(v, 4).unwrap_or_else(|| v.to_string())
}

fn f6(v: f64) -> String {
    format_fixed(v, 6).unwrap_or_else(|| v.to_string())
}

/// One gear unit as the check sees it.
#[derive(Debug, Clone, Copy)]
struct Unit<'m> {
    kin: &'m Kinematics,
    gear: &'m GearSpec,
    hob: &'m HobData,
}

fn units(model: &MachiningModel) -> Vec<Unit<'_>> {
    if model.model.units.is_empty() {
        vec![Unit {
            kin: &model.model,
            gear: &model.plan.gear,
            hob: &model.plan.hob,
        }]
    } else {
        model
            .model
            .units
            .iter()
            .map(|u| Unit {
                kin: &u.model,
                gear: &u.gear,
                hob: &u.hob,
            })
            .collect()
    }
}

/// One box of the contact zone (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Zone {
    unit: usize,
    x_hi: f64,
    z_lo: f64,
    z_hi: f64,
    y_half: Option<f64>,
}

impl Zone {
    /// True when the straight segment `p0` → `p1` ((X, Z, Y)) has a piece
    /// strictly inside the zone shrunk by [`MM`] (Liang–Barsky clipping).
    fn crossed_by(&self, p0: [f64; 3], p1: [f64; 3]) -> bool {
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        // Keeps the t where a + b·t < bound.
        let mut clip = |a: f64, b: f64, bound: f64| -> bool {
            if b.abs() < 1e-12 {
                return a < bound;
            }
            let t = (bound - a) / b;
            if b > 0.0 {
                t1 = t1.min(t);
            } else {
                t0 = t0.max(t);
            }
            true
        };
        let d = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
        let inside = clip(p0[0], d[0], self.x_hi - MM)
            && clip(-p0[1], -d[1], -(self.z_lo + MM))
            && clip(p0[1], d[1], self.z_hi - MM)
            && self.y_half.is_none_or(|h| {
                clip(p0[2], d[2], h - Y_MARGIN) && clip(-p0[2], -d[2], h - Y_MARGIN)
            });
        inside && t0 < t1
    }

    fn describe(&self, axes: (&str, &str, &str), units: usize) -> String {
        let (x, z, y) = axes;
        let mut s = format!(
            "{x} < {}, {} < {z} < {}",
            f3(self.x_hi),
            f3(self.z_lo),
            f3(self.z_hi)
        );
        if let Some(h) = self.y_half {
            s.push_str(&format!(", |{y}| < {}", f3(h)));
        }
        if units > 1 {
            s.push_str(&format!(", unit {}", self.unit + 1));
        }
        s
    }
}

/// The contact zone of every unit.
fn zones(units: &[Unit<'_>]) -> Vec<Zone> {
    let mut out = Vec::new();
    for (i, u) in units.iter().enumerate() {
        let k = u.kin;
        let r = u.hob.od_mm / 2.0;
        let contact = k.blank_od_mm / 2.0 + r + u.gear.od_correction_mm;
        if let Some(w) = &k.worm {
            out.push(Zone {
                unit: i,
                x_hi: contact,
                z_lo: w.throat_z_mm - r,
                z_hi: w.throat_z_mm + r,
                y_half: (w.infeed == WormInfeed::Tangential)
                    .then(|| w.start_y_mm.abs().min(w.end_y_mm.abs())),
            });
            continue;
        }
        let face_lo = u.gear.fixture_height_mm;
        let face_hi = face_lo + u.gear.face_width_mm;
        // C and D stand beyond the faces by each face's own overtravel (a
        // cone's small end needs less); a radial-axial cut enters at the face
        // + safety, so its band is widened by the approach's.
        let band = |c: &gearcam_proto::Positions, over: f64| {
            let (lo, hi) = (c.C.z_mm.min(c.D.z_mm), c.C.z_mm.max(c.D.z_mm));
            if lo <= face_lo - MM && hi >= face_hi + MM {
                (lo, hi)
            } else {
                (lo.min(face_lo - over), hi.max(face_hi + over))
            }
        };
        if k.cuts.is_empty() {
            let (z_lo, z_hi) = band(&k.positions, k.clearance_mm + k.safety_mm);
            out.push(Zone {
                unit: i,
                x_hi: contact,
                z_lo,
                z_hi,
                y_half: None,
            });
            continue;
        }
        let mut cuts: Vec<_> = k.cuts.iter().collect();
        cuts.sort_by(|a, b| a.depth_mm.total_cmp(&b.depth_mm));
        // Below the X a previous cut reached, the hob runs in the gaps it cut:
        // its nominal centre distance, and for a crowned cut, deeper towards
        // the faces by the crowning, the deepest X of its cutting moves. (A
        // cone's X follows the cone; its nominal X at the large end stays the
        // bound, which errs on the safe side.)
        let mut reached_x = contact;
        for c in cuts {
            let (z_lo, z_hi) = band(&c.positions, c.clearance_mm + k.safety_mm);
            out.push(Zone {
                unit: i,
                x_hi: reached_x,
                z_lo,
                z_hi,
                y_half: None,
            });
            let mut deepest = contact - c.depth_mm;
            if k.crowning.is_some() {
                deepest = c
                    .moves
                    .iter()
                    .filter(|m| matches!(m.kind, MoveKind::Feed | MoveKind::Arc))
                    .filter_map(|m| m.x_mm)
                    .fold(deepest, f64::min);
            }
            reached_x = reached_x.min(deepest);
        }
    }
    out
}

/// What an axis name means on this machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    X,
    Z,
    Y,
    A,
    B,
    C,
    Other,
}

/// The gearbox definition (840D `EGDEF`).
#[derive(Debug, Clone, Copy)]
struct Definition {
    /// Hob, axial and shift axis are leading axes.
    leads: [bool; 3],
}

/// The coupling in effect.
#[derive(Debug, Clone, Copy)]
struct Active {
    num: i64,
    den: i64,
    z: Option<f64>,
    y: Option<f64>,
}

/// A path to check: its points, the first being the start.
#[derive(Debug, Clone, Copy)]
struct Path {
    points: [[f64; 3]; ARC_STEPS + 1],
    n: usize,
    /// The circle, for an arc.
    arc: Option<TraceArc>,
}

impl Path {
    fn line(from: [f64; 3], to: [f64; 3]) -> Path {
        let mut points = [[0.0; 3]; ARC_STEPS + 1];
        points[0] = from;
        points[1] = to;
        Path {
            points,
            n: 2,
            arc: None,
        }
    }

    /// An arc in the Z–X plane around `centre` (Z, X), from angle `t0` through
    /// `sweep` radians (positive from +Z towards +X), Y moving linearly.
    fn arc(from: [f64; 3], to: [f64; 3], centre: (f64, f64), t0: f64, sweep: f64) -> Path {
        let r = (from[1] - centre.0).hypot(from[0] - centre.1);
        let mut points = [[0.0; 3]; ARC_STEPS + 1];
        points[0] = from;
        for (i, p) in points.iter_mut().enumerate().skip(1) {
            let s = i as f64 / ARC_STEPS as f64;
            let t = t0 + sweep * s;
            *p = [
                centre.1 + r * t.sin(),
                centre.0 + r * t.cos(),
                from[2] + (to[2] - from[2]) * s,
            ];
        }
        points[ARC_STEPS] = to;
        Path {
            points,
            n: ARC_STEPS + 1,
            arc: Some(TraceArc {
                centre_z_mm: centre.0,
                centre_x_mm: centre.1,
                sweep_rad: sweep,
            }),
        }
    }

    fn segments(&self) -> impl Iterator<Item = ([f64; 3], [f64; 3])> + '_ {
        self.points[..self.n].windows(2).map(|w| (w[0], w[1]))
    }
}

/// The circle through `a`, `via`, `b` ((Z, X) points): centre, start angle
/// and signed sweep from `a` to `b` passing `via`. `None` when collinear.
fn circle_via(a: (f64, f64), via: (f64, f64), b: (f64, f64)) -> Option<((f64, f64), f64, f64)> {
    let (bx, by) = (via.0 - a.0, via.1 - a.1);
    let (cx, cy) = (b.0 - a.0, b.1 - a.1);
    let d = 2.0 * (bx * cy - by * cx);
    let scale = (bx * bx + by * by).max(cx * cx + cy * cy);
    if d.is_nan() || d.abs() <= 1e-12 * scale.max(1e-12) {
        return None;
    }
    let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
    let ux = (cy * b2 - by * c2) / d;
    let uy = (bx * c2 - cx * b2) / d;
    let centre = (a.0 + ux, a.1 + uy);
    let angle = |p: (f64, f64)| (p.1 - centre.1).atan2(p.0 - centre.0);
    let t0 = angle(a);
    let to_end = (angle(b) - t0).rem_euclid(TAU);
    let to_via = (angle(via) - t0).rem_euclid(TAU);
    let sweep = if to_via < to_end {
        to_end
    } else {
        to_end - TAU
    };
    Some((centre, t0, sweep))
}

/// The arc of radius `r` from `a` to `b` ((Z, X) points) in the G18 plane:
/// counter-clockwise (`G03`) turns from +Z towards +X seen from +Y; `r < 0`
/// takes the arc over 180°. `None` when the radius cannot span the chord.
fn arc_radius(a: (f64, f64), b: (f64, f64), r: f64, ccw: bool) -> Option<((f64, f64), f64, f64)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l = dx.hypot(dy);
    if l.is_nan() || l <= 1e-9 || !r.is_finite() {
        return None;
    }
    let h2 = r * r - l * l / 4.0;
    if h2 < -(MM * r.abs().max(1.0)) {
        return None;
    }
    let h = h2.max(0.0).sqrt();
    let side = if ccw == (r > 0.0) { 1.0 } else { -1.0 };
    let centre = (
        (a.0 + b.0) / 2.0 - dy / l * h * side,
        (a.1 + b.1) / 2.0 + dx / l * h * side,
    );
    let angle = |p: (f64, f64)| (p.1 - centre.1).atan2(p.0 - centre.0);
    let t0 = angle(a);
    let sweep = if ccw {
        (angle(b) - t0).rem_euclid(TAU)
    } else {
        -(t0 - angle(b)).rem_euclid(TAU)
    };
    Some((centre, t0, sweep))
}

/// Runs the blocks; returns the findings (unsorted) and the trace.
pub(super) fn run(
    dialect: Dialect,
    blocks: &[Block],
    model: &MachiningModel,
    last_line: u32,
) -> (Vec<PathFinding>, Trace) {
    let units = units(model);
    let zones = zones(&units);
    let profile = &model.plan.machine;
    let ax = &profile.axes;
    // An axis name the profile spells invalidly matches nothing (the default
    // name is empty and no parsed name is).
    let name = |s: &str| AxisName::new(s.as_bytes()).unwrap_or_default();
    let mut sim = Sim {
        dialect,
        profile,
        roles: [
            (name(&ax.radial), Role::X),
            (name(&ax.axial), Role::Z),
            (name(&ax.shift), Role::Y),
            (name(&ax.swivel), Role::A),
            (name(&ax.hob), Role::B),
            (name(&ax.table), Role::C),
        ],
        units,
        zones,
        vars: [0.0; PARAMS],
        x: profile.home_x_mm,
        z: profile.home_z_mm,
        y: 0.0,
        a: None,
        interp: None,
        incremental: None,
        feed: None,
        spindle: false,
        speed: None,
        definition: None,
        coupled: None,
        unit: 0,
        started: false,
        defined: false,
        reference: None,
        setup: super::Setup::default(),
        setup_checked: false,
        functions: [None; 5],
        end: None,
        last_move: None,
        findings: Vec::new(),
        trace: Trace {
            moves: Vec::with_capacity(blocks.len() / 2 + 1),
            ..Trace::default()
        },
    };
    let mut branches = Branches::default();
    for b in blocks {
        if let Some(end) = sim.end {
            let code = sim.profile.mcodes.program_end;
            sim.push(
                b.line,
                Code::END_AT_A,
                format!("this block comes after the end of program M{code} of line {end} and is never executed"),
            );
            break;
        }
        if branches.control(&mut sim, b) {
            continue;
        }
        if branches.active() {
            sim.block(b);
        }
    }
    sim.finish(last_line);
    (sim.findings, sim.trace)
}

/// The open `IF`s of an 840D program, innermost last ([`super::structure`]
/// has checked that they pair up before the simulation starts).
#[derive(Default)]
struct Branches {
    open: Vec<Branch>,
}

struct Branch {
    /// The enclosing blocks run.
    outer: bool,
    /// The condition held.
    holds: bool,
    /// Past the `ELSE`.
    otherwise: bool,
}

impl Branches {
    /// True when the current block runs.
    fn active(&self) -> bool {
        self.open
            .last()
            .is_none_or(|b| b.outer && (b.holds != b.otherwise))
    }

    /// Handles `IF`, `ELSE`, `ENDIF` and the FANUC conditional assignment;
    /// false for any other block.
    fn control(&mut self, sim: &mut Sim<'_>, b: &Block) -> bool {
        let line = b.line;
        match &b.op {
            Op::If(cond) => {
                let outer = self.active();
                let holds = outer && sim.condition(line, cond);
                self.open.push(Branch {
                    outer,
                    holds,
                    otherwise: false,
                });
            }
            Op::Else => {
                if let Some(open) = self.open.last_mut() {
                    open.otherwise = true;
                }
            }
            Op::EndIf => {
                self.open.pop();
            }
            Op::AssignIf { cond, param, value } => {
                if self.active() && sim.condition(line, cond) {
                    sim.assign(line, *param, value);
                }
            }
            _ => return false,
        }
        true
    }
}

struct Sim<'m> {
    dialect: Dialect,
    profile: &'m MachineProfile,
    /// The machine's axis names with their meaning.
    roles: [(AxisName, Role); 6],
    units: Vec<Unit<'m>>,
    zones: Vec<Zone>,
    vars: [f64; PARAMS],
    x: f64,
    z: f64,
    y: f64,
    a: Option<f64>,
    interp: Option<Interp>,
    /// Line of the `G91` in effect.
    incremental: Option<u32>,
    feed: Option<f64>,
    spindle: bool,
    speed: Option<f64>,
    definition: Option<Definition>,
    coupled: Option<Active>,
    unit: usize,
    started: bool,
    /// An `EGDEF` since the last coupling: the next coupling starts a unit.
    defined: bool,
    /// The first coupling of the current unit: its line, and the synchronised
    /// positions (following axis first) when it was an `EGONSYNE`.
    reference: Option<(u32, Option<Vec<f64>>)>,
    /// Set-up codes stated so far.
    setup: super::Setup,
    /// True once the set-up has been checked (at the first move).
    setup_checked: bool,
    /// Line where each switched function was switched on, while it is on.
    functions: [Option<u32>; 5],
    end: Option<u32>,
    last_move: Option<u32>,
    findings: Vec<PathFinding>,
    trace: Trace,
}

impl<'m> Sim<'m> {
    fn push(&mut self, line: u32, rule: Code, message: String) {
        self.findings
            .push(finding(line, rule, format!("line {line}: {message}")));
    }

    fn unit(&self) -> Unit<'m> {
        self.units[self.unit.min(self.units.len() - 1)]
    }

    fn role(&self, a: &AxisName) -> Role {
        self.roles
            .iter()
            .find(|(name, _)| name == a)
            .map_or(Role::Other, |(_, role)| *role)
    }

    fn axes(&self) -> (&'m str, &'m str, &'m str) {
        let ax = &self.profile.axes;
        (&ax.radial, &ax.axial, &ax.shift)
    }

    fn param_name(&self, param: u16) -> String {
        match self.dialect {
            Dialect::Fanuc => format!("#{param}"),
            _ => format!("R{param}"),
        }
    }

    /// The parameters the machine leaves free for gearcam (first, last).
    fn free_params(&self) -> (u16, u16) {
        let p = self.profile.parameters;
        let first = match self.dialect {
            Dialect::Fanuc => p.macro_first,
            _ => p.r_first,
        };
        (
            first,
            first.saturating_add(gearcam_proto::ParameterBlock::SLOTS - 1),
        )
    }

    fn turning(&self) -> bool {
        self.spindle && self.speed.is_some_and(|s| s > 0.0)
    }

    fn block(&mut self, b: &Block) {
        let line = b.line;
        match &b.op {
            Op::Assign { param, value } => self.assign(line, *param, value),
            Op::Motion(m) => self.motion(line, m),
            Op::Dwell { seconds } => self.trace.moves.push(TraceMove {
                line,
                kind: MoveKind::Dwell,
                x_mm: self.x,
                z_mm: self.z,
                y_mm: self.y,
                feed_mm_min: None,
                dwell_s: Some(seconds.value),
                coupled: self.coupled.is_some(),
                c_correction_deg: None,
                arc: None,
            }),
            Op::MCode { code, speed } => self.mcode(line, *code, *speed),
            Op::GearDefine { following, leading } => self.egdef(line, *following, leading),
            Op::GearOn {
                sync,
                position,
                following,
                leading,
            } => self.egon(line, *sync, *position, *following, leading),
            Op::FanucGearOn {
                teeth,
                starts,
                module,
                helix,
            } => self.g81(line, *teeth, *starts, *module, *helix),
            Op::GearOff { following } => self.gear_off(line, *following),
            Op::GearDelete { following } => self.egdel(line, *following),
            Op::Message | Op::If(_) | Op::Else | Op::EndIf | Op::AssignIf { .. } => {}
        }
    }

    fn assign(&mut self, line: u32, param: u16, value: &NcValue) {
        let (first, last) = self.free_params();
        if !(first..=last).contains(&param) {
            let (name, a, b) = (
                self.param_name(param),
                self.param_name(first),
                self.param_name(last),
            );
            self.push(
                line,
                Code::SETUP,
                format!(
                    "{name} is not among the parameters machine {} leaves free for gearcam ({a} to {b}, the profile's parameters)",
                    self.profile.id
                ),
            );
        }
        match value.eval(&self.vars) {
            Ok(v) => {
                if let Some(slot) = self.vars.get_mut(usize::from(param)) {
                    *slot = v;
                }
            }
            Err(e) => {
                let name = self.param_name(param);
                self.push(
                    line,
                    Code::PARSE,
                    format!("the value of {name} cannot be computed: {e}"),
                );
            }
        }
    }

    /// The condition's truth with the parameters as simulated; a condition
    /// that cannot be computed is a `PARSE` finding and counts as false.
    fn condition(&mut self, line: u32, cond: &Cond) -> bool {
        match cond.eval(&self.vars) {
            Ok(holds) => holds,
            Err(e) => {
                self.push(
                    line,
                    Code::PARSE,
                    format!("the condition cannot be computed: {e}"),
                );
                false
            }
        }
    }

    // ----- motion -----
}
