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
    Dialect, GearSpec, HobData, Kinematics, MachineProfile, MachiningModel, MoveKind, PathFinding,
    WormInfeed,
};

use super::expr::{Cond, Num, Value, PARAMS};
use super::{
    finding, rules, AxisName, Block, Distance, Interp, Lead, Motion, Op, Trace, TraceCoupling,
    TraceMove,
};
use crate::render::format_fixed;

/// Geometric tolerance, mm.
pub const TOL: f64 = 1e-6;
/// A length, feed or speed printed with 3 decimals lies within this of the model's.
pub const MM: f64 = 0.0005 + TOL;
/// An angle printed with 4 decimals lies within this of the model's, degrees.
pub const DEG: f64 = 0.00005 + 1e-9;
/// A gearbox factor printed with 6 decimals lies within this of the model's.
pub const FACTOR: f64 = 0.000_000_5 + 1e-9;

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
            gear: &model.plan.request.spec.gear,
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
}

impl Path {
    fn line(from: [f64; 3], to: [f64; 3]) -> Path {
        let mut points = [[0.0; 3]; ARC_STEPS + 1];
        points[0] = from;
        points[1] = to;
        Path { points, n: 2 }
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
                rules::END_AT_A,
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
    fn push(&mut self, line: u32, rule: &str, message: String) {
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

    fn assign(&mut self, line: u32, param: u16, value: &Value) {
        let (first, last) = self.free_params();
        if !(first..=last).contains(&param) {
            let (name, a, b) = (
                self.param_name(param),
                self.param_name(first),
                self.param_name(last),
            );
            self.push(
                line,
                rules::SETUP,
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
                    rules::PARSE,
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
                    rules::PARSE,
                    format!("the condition cannot be computed: {e}"),
                );
                false
            }
        }
    }

    // ----- motion -----

    fn motion(&mut self, line: u32, m: &Motion) {
        self.setup.merge(m.setup);
        self.check_system(line, m);
        if !self.setup_checked && !m.words().is_empty() {
            self.setup_checked = true;
            self.check_setup(line);
        }
        if let Some(i) = m.interp {
            self.interp = Some(i);
        }
        match m.distance {
            Some(Distance::Incremental) => self.incremental = Some(line),
            Some(Distance::Absolute) => self.incremental = None,
            None => {}
        }
        if let Some(f) = m.feed {
            self.feed = Some(f.value);
        }
        if m.words().is_empty() {
            return;
        }
        let Some(interp) = self.interp else {
            self.push(
                line,
                rules::PARSE,
                "a move without G0 or G1 in effect".into(),
            );
            return;
        };
        let inc = self.incremental.is_some();
        let (mut x, mut z, mut y) = (self.x, self.z, self.y);
        let (mut x_set, mut z_set, mut y_set) = (false, false, false);
        let (mut a, mut c) = (None, None);
        for w in m.words() {
            let v = match w.value.eval(&self.vars) {
                Ok(v) => v,
                Err(e) => {
                    self.push(
                        line,
                        rules::PARSE,
                        format!("the value of {} cannot be computed: {e}", w.axis),
                    );
                    return;
                }
            };
            let role = self.role(&w.axis);
            if let Some(n) = w.value.literal() {
                if n.decimals > 3 && !matches!(role, Role::A | Role::C) {
                    self.push(
                        line,
                        rules::PARSE,
                        format!(
                            "{} has {} decimals; lengths are written with at most 3",
                            w.axis, n.decimals
                        ),
                    );
                    return;
                }
            }
            let base = |old: f64| if inc { old + v } else { v };
            match role {
                Role::X => (x, x_set) = (base(self.x), true),
                Role::Z => (z, z_set) = (base(self.z), true),
                Role::Y => (y, y_set) = (base(self.y), true),
                Role::A => a = Some(base(self.a.unwrap_or(0.0))),
                Role::C if self.dialect == Dialect::Fanuc => c = Some(v),
                _ => {
                    let ax = &self.profile.axes;
                    let msg = format!(
                        "{} is not an axis a motion block moves (this machine's are {} {} {} {})",
                        w.axis, ax.radial, ax.axial, ax.shift, ax.swivel
                    );
                    self.push(line, rules::PARSE, msg);
                    return;
                }
            }
        }
        let shift_form = inc
            && interp == Interp::Linear
            && y_set
            && c.is_some()
            && !x_set
            && !z_set
            && a.is_none();
        if let Some(g91) = self.incremental.filter(|_| !shift_form) {
            let since = if g91 == line {
                String::new()
            } else {
                format!(" (G91 of line {g91} is still in effect; write G90)")
            };
            self.push(
                line,
                rules::PARSE,
                format!("incremental dimensions are used only for the shift move G01 G91 Y.. C..{since}"),
            );
            return;
        }
        if c.is_some() && !inc {
            self.push(
                line,
                rules::PARSE,
                "C is programmed only in the incremental shift move G01 G91 Y.. C..".into(),
            );
            return;
        }
        let kind = match interp {
            Interp::Rapid => MoveKind::Rapid,
            Interp::Linear => MoveKind::Feed,
            _ => MoveKind::Arc,
        };
        let from = [self.x, self.z, self.y];
        let to = [x, z, y];

        // The path: a line, or the arc sampled.
        let path = match interp {
            Interp::Rapid | Interp::Linear => Path::line(from, to),
            Interp::CircleVia => {
                let Some((vx, vz)) = m.via else {
                    self.push(
                        line,
                        rules::PARSE,
                        "CIP is in effect, but the block has no intermediate point I1= K1=".into(),
                    );
                    return;
                };
                self.travel(line, Role::X, vx.value);
                self.travel(line, Role::Z, vz.value);
                match circle_via((from[1], from[0]), (vz.value, vx.value), (to[1], to[0])) {
                    Some((centre, t0, sweep)) => Path::arc(from, to, centre, t0, sweep),
                    None => {
                        self.push(
                            line,
                            rules::PARSE,
                            "the start, intermediate and end point of the CIP lie on one line"
                                .into(),
                        );
                        return;
                    }
                }
            }
            Interp::ArcCw | Interp::ArcCcw => {
                let Some(r) = m.radius.map(|r| r.value) else {
                    self.push(
                        line,
                        rules::PARSE,
                        "G02/G03 is in effect, but the block has no radius R".into(),
                    );
                    return;
                };
                let ccw = interp == Interp::ArcCcw;
                match arc_radius((from[1], from[0]), (to[1], to[0]), r, ccw) {
                    Some((centre, t0, sweep)) => Path::arc(from, to, centre, t0, sweep),
                    None => {
                        self.push(
                            line,
                            rules::PARSE,
                            format!(
                                "the arc radius R{} cannot join its start and end point",
                                f3(r)
                            ),
                        );
                        return;
                    }
                }
            }
        };

        if x_set {
            self.travel(line, Role::X, x);
        }
        if z_set {
            self.travel(line, Role::Z, z);
        }
        if let Some(a) = a {
            let max = self.profile.limits.max_swivel_deg;
            if (a - self.profile.settings.swivel_offset_deg).abs() > max + DEG {
                let name = &self.profile.axes.swivel;
                self.push(
                    line,
                    rules::TRAVEL_LIMIT,
                    format!(
                        "swivel {name}={} is beyond the machine's limit of ±{} degrees about {}",
                        f4(a),
                        f4(max),
                        f4(self.profile.settings.swivel_offset_deg)
                    ),
                );
            }
            self.trace.swivel_deg.push((line, a));
            self.a = Some(a);
        }

        let feed = if kind == MoveKind::Rapid {
            None
        } else {
            self.check_feed(line);
            self.feed
        };

        let coupled = self.coupled.is_some();
        // A move that only increases X is a radial withdrawal: it can leave
        // the zone (a worm wheel's D → E retract from the throat) but never
        // enter it.
        let withdrawal = to[0] > from[0]
            && (to[1] - from[1]).abs() <= TOL
            && (to[2] - from[2]).abs() <= TOL
            && matches!(interp, Interp::Rapid | Interp::Linear);
        let zone = if withdrawal {
            None
        } else {
            self.zone_crossed(&path)
        };
        let why = match (coupled, self.turning()) {
            (true, true) => None,
            (false, true) => Some("the gearbox is not coupled"),
            (true, false) => Some("the hob is not turning"),
            (false, false) => Some("the gearbox is not coupled and the hob is not turning"),
        };
        if let Some(zone) = zone.filter(|_| kind == MoveKind::Rapid || why.is_some()) {
            let what = self.move_text(kind, from, to);
            let zone_text = zone.describe(self.axes(), self.units.len());
            if kind == MoveKind::Rapid {
                self.push(
                    line,
                    rules::RAPID_CLEARANCE,
                    format!("{what} passes through the blank zone ({zone_text})"),
                );
            }
            if let Some(why) = why {
                self.push(
                    line,
                    rules::DEPTH_UNCOUPLED,
                    format!("{what} enters the contact zone ({zone_text}) while {why}"),
                );
            }
        }

        let dy = y - self.y;
        if shift_form {
            self.check_shift_correction(line, dy, c.unwrap_or(0.0));
        } else if dy.abs() > TOL && coupled {
            self.check_coupled_shift(line, from[2], y);
        }

        self.trace.moves.push(TraceMove {
            line,
            kind,
            x_mm: x,
            z_mm: z,
            y_mm: y,
            feed_mm_min: feed,
            dwell_s: None,
            coupled,
            c_correction_deg: c,
        });
        (self.x, self.z, self.y) = (x, z, y);
        self.last_move = Some(line);
    }

    /// The program's G codes mean what the machine's G-code system says:
    /// FANUC M series and T systems B and C take G94 for feed per minute
    /// (G98 is a canned-cycle return level there); T system A takes G98 and
    /// has no G90/G91 (G90 is a turning cycle).
    fn check_system(&mut self, line: u32, m: &Motion) {
        use gearcam_proto::GCodeSystem as S;
        let system = self.profile.gcode_system;
        match (self.dialect, system) {
            (Dialect::Fanuc, S::FanucM | S::FanucTB | S::FanucTC) if m.feed_code == Some(98) => {
                self.push(
                    line,
                    rules::SETUP,
                    format!("G98 is the canned-cycle return level in G-code system {}, not feed per minute: write G94", system.as_str()),
                );
            }
            (Dialect::Fanuc, S::FanucTA) if m.distance.is_some() || m.feed_code == Some(94) => {
                self.push(
                    line,
                    rules::SETUP,
                    "G-code system A (fanuc_t_a) has no G90/G91 or G94: absolute is X/Z, incremental U/W, feed per minute G98".into(),
                );
            }
            (Dialect::Fanuc, S::Sinumerik)
            | (Dialect::Sinumerik840d, S::FanucM | S::FanucTA | S::FanucTB | S::FanucTC) => {
                self.push(
                    line,
                    rules::SETUP,
                    format!(
                        "the machine profile names G-code system {} for a {} control",
                        system.as_str(),
                        self.dialect.as_str()
                    ),
                );
            }
            _ => {}
        }
    }

    /// Before the first move the program states the metric unit, the
    /// machine's work offset (Z0 on the table, X0 on its axis) and, on an
    /// 840D, that X is a radius.
    fn check_setup(&mut self, line: u32) {
        let s = self.setup;
        let (metric, offset) = match self.dialect {
            Dialect::Fanuc => ("G21", "work offset"),
            _ => ("G71", "work offset"),
        };
        let want = self.profile.work_offset.trim().to_ascii_uppercase();
        let want_n = want
            .strip_prefix('G')
            .and_then(|n| n.parse::<u8>().ok())
            .filter(|n| (54..=59).contains(n));
        let mut missing = Vec::new();
        if !s.metric {
            missing.push(format!("{metric} (metric input)"));
        }
        if want_n.is_some() && s.work_offset != want_n {
            missing.push(format!(
                "{want} ({offset}: Z0 on the table plane, X0 on the table axis)"
            ));
        }
        if self.dialect == Dialect::Sinumerik840d && !s.radius_x {
            missing.push("DIAMOF (X is the centre distance, a radius)".into());
        }
        if !missing.is_empty() {
            self.push(
                line,
                rules::SETUP,
                format!("the first move comes before {}", missing.join(", ")),
            );
        }
    }

    fn move_text(&self, kind: MoveKind, from: [f64; 3], to: [f64; 3]) -> String {
        let (xn, zn, _) = self.axes();
        let what = match kind {
            MoveKind::Rapid => "rapid move",
            MoveKind::Feed => "feed move",
            MoveKind::Arc => "arc",
            MoveKind::Dwell => "dwell",
        };
        format!(
            "{what} from {xn}={} {zn}={} to {xn}={} {zn}={}",
            f3(from[0]),
            f3(from[1]),
            f3(to[0]),
            f3(to[1])
        )
    }

    /// The first zone the path passes through.
    fn zone_crossed(&self, path: &Path) -> Option<Zone> {
        path.segments()
            .find_map(|(p, q)| self.zones.iter().find(|z| z.crossed_by(p, q)).copied())
    }

    /// The zone the hob stands in.
    fn zone_here(&self) -> Option<Zone> {
        let p = [self.x, self.z, self.y];
        self.zones.iter().find(|z| z.crossed_by(p, p)).copied()
    }

    fn travel(&mut self, line: u32, role: Role, v: f64) {
        let (name, [lo, hi]) = match role {
            Role::X => (&self.profile.axes.radial, self.profile.limits.x_mm),
            _ => (&self.profile.axes.axial, self.profile.limits.z_mm),
        };
        if !(v >= lo - MM && v <= hi + MM) {
            let msg = format!(
                "{name}={} is outside the machine's travel {} to {} mm",
                f3(v),
                f3(lo),
                f3(hi)
            );
            self.push(line, rules::TRAVEL_LIMIT, msg);
        }
    }

    fn check_feed(&mut self, line: u32) {
        let max = self.profile.limits.max_axial_feed_mm_min;
        match self.feed {
            Some(f) if f > 0.0 && f <= max + MM => {}
            Some(f) if f > 0.0 => self.push(
                line,
                rules::FEED_LIMIT,
                format!(
                    "feed F={} mm/min is above the machine's largest feed {} mm/min",
                    f3(f),
                    f3(max)
                ),
            ),
            Some(_) => self.push(
                line,
                rules::FEED_LIMIT,
                "a feed move with a zero feed F".into(),
            ),
            None => self.push(
                line,
                rules::FEED_LIMIT,
                "a feed move without a feed F in effect".into(),
            ),
        }
    }

    /// FANUC: the C correction of the incremental shift move.
    fn check_shift_correction(&mut self, line: u32, dy: f64, c: f64) {
        if self.coupled.is_none() {
            self.push(
                line,
                rules::COUPLING_RATIO,
                "the shift move G01 G91 Y.. C.. corrects C for a coupled gearbox, but the gearbox is not coupled".into(),
            );
            return;
        }
        let per_y = self.unit().kin.factors.c_per_y_deg_per_mm;
        let want = per_y * dy;
        if (c - want).abs() > DEG + per_y.abs() * MM {
            let (_, _, yn) = self.axes();
            let table = &self.profile.axes.table;
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!(
                    "the correction {table}{} for the shift {yn}{} differs from the model's {} ({} deg/mm)",
                    f4(c),
                    f3(dy),
                    f4(want),
                    f6(per_y)
                ),
            );
        }
    }

    /// A Y move while coupled, outside the FANUC shift form.
    fn check_coupled_shift(&mut self, line: u32, from: f64, to: f64) {
        let (_, _, yn) = self.axes();
        let table = &self.profile.axes.table;
        let msg = match self.dialect {
            Dialect::Fanuc => format!(
                "{yn} moves from {} to {} while the gearbox is coupled without its {table} correction; write G01 G91 {yn}.. {table}..",
                f3(from),
                f3(to)
            ),
            _ if self.coupled.is_some_and(|c| c.y.is_none()) => format!(
                "{yn} moves from {} to {} while {table} is coupled without the shift compensation ({yn} is not a leading axis of the gearbox)",
                f3(from),
                f3(to)
            ),
            _ => return,
        };
        self.push(line, rules::COUPLING_RATIO, msg);
    }

    // ----- M functions -----

    fn function(&self, code: u16) -> Option<(usize, bool)> {
        let mc = &self.profile.mcodes;
        [
            (mc.outer_support_on, mc.outer_support_off),
            (mc.fixture_clamp, mc.fixture_unclamp),
            (mc.coolant_on, mc.coolant_off),
            (mc.chip_conveyor_on, mc.chip_conveyor_off),
            (mc.mist_on, mc.mist_off),
        ]
        .iter()
        .enumerate()
        .find_map(|(i, (on, off))| {
            if code == *on {
                Some((i, true))
            } else if code == *off {
                Some((i, false))
            } else {
                None
            }
        })
    }

    fn mcode(&mut self, line: u32, code: u16, speed: Option<Num>) {
        self.trace.mcodes.push((line, code));
        let mc = &self.profile.mcodes;
        if let Some(s) = speed {
            self.speed = Some(s.value);
            self.trace.spindle_rpm.push((line, s.value));
            self.check_hob_speed(line, s.value);
        }
        if code == mc.spindle_on {
            if self.speed.is_none() {
                self.push(
                    line,
                    rules::SPEED_LIMIT,
                    format!("M{code} switches the hob on without a speed S"),
                );
            }
            self.spindle = true;
            self.check_table_speed(line);
        } else if code == mc.spindle_off {
            if let Some(zone) = self.zone_here() {
                let zone_text = zone.describe(self.axes(), self.units.len());
                self.push(
                    line,
                    rules::DEPTH_UNCOUPLED,
                    format!("M{code} stops the hob inside the contact zone ({zone_text})"),
                );
            }
            self.spindle = false;
        } else if code == mc.program_end {
            self.end = Some(line);
        } else if let Some((k, on)) = self.function(code) {
            let name = FUNCTIONS[k];
            match (on, self.functions[k]) {
                (true, Some(since)) => self.push(
                    line,
                    rules::MCODE_PAIR,
                    format!("M{code} switches {name} on, but it has been on since line {since}"),
                ),
                (true, None) => self.functions[k] = Some(line),
                (false, Some(_)) => self.functions[k] = None,
                (false, None) => self.push(
                    line,
                    rules::MCODE_PAIR,
                    format!("M{code} switches {name} off, but it is not on"),
                ),
            }
        } else if code != 0 {
            self.push(
                line,
                rules::PARSE,
                format!("M{code} is not one of the machine's M functions"),
            );
        } else {
            // M0: the operator reaches into the machine (a hob change).
            let on: Vec<String> = FUNCTIONS
                .iter()
                .zip(self.functions)
                .filter(|(name, since)| since.is_some() && STOP_OFF.contains(name))
                .map(|(name, since)| format!("{name} (on since line {})", since.unwrap_or(0)))
                .collect();
            if !on.is_empty() || self.spindle {
                let mut what = on;
                if self.spindle {
                    what.push("the hob spindle".into());
                }
                self.push(
                    line,
                    rules::MCODE_PAIR,
                    format!(
                        "M0 stops for the operator with {} still on; switch it off before the stop",
                        what.join(", ")
                    ),
                );
            }
        }
    }

    /// S printed with 3 decimals on 840D, a whole number on FANUC.
    fn speed_tolerance(&self) -> f64 {
        if self.dialect == Dialect::Fanuc {
            1e-9
        } else {
            MM
        }
    }

    fn check_hob_speed(&mut self, line: u32, s: f64) {
        let max = self.profile.limits.max_hob_rpm;
        if s > max + self.speed_tolerance() {
            self.push(
                line,
                rules::SPEED_LIMIT,
                format!(
                    "hob speed S={} rpm is above the machine's largest hob speed {} rpm",
                    f3(s),
                    f3(max)
                ),
            );
        }
    }

    /// The table speed S·z0/z, with the coupling in effect (or the model's).
    fn check_table_speed(&mut self, line: u32) {
        let (true, Some(s)) = (self.spindle, self.speed) else {
            return;
        };
        let (num, den) = match self.coupled {
            Some(c) if c.den != 0 => (c.num.unsigned_abs() as f64, c.den.unsigned_abs() as f64),
            _ => {
                let r = self.unit().kin.coupling;
                (f64::from(r.num.unsigned_abs()), f64::from(r.den.max(1)))
            }
        };
        let ratio = num / den;
        let table = s * ratio;
        let max = self.profile.limits.max_table_rpm;
        if table > max + self.speed_tolerance() * ratio.max(1.0) {
            self.push(
                line,
                rules::SPEED_LIMIT,
                format!(
                    "hob speed S={} rpm turns the table at S*{num}/{den} = {} rpm, above the machine's largest table speed {} rpm",
                    f3(s),
                    f3(table),
                    f3(max)
                ),
            );
        }
    }

    // ----- gearbox -----

    fn is_table(&mut self, line: u32, call: &str, following: AxisName) -> bool {
        if self.role(&following) == Role::C {
            return true;
        }
        let table = &self.profile.axes.table;
        let msg = format!(
            "{call} names {following} as the following axis; this machine's table axis is {table}"
        );
        self.push(line, rules::COUPLING_RATIO, msg);
        false
    }

    fn lead_index(role: Role) -> Option<usize> {
        match role {
            Role::B => Some(0),
            Role::Z => Some(1),
            Role::Y => Some(2),
            _ => None,
        }
    }

    fn bad_lead(&mut self, line: u32, call: &str, axis: AxisName, first: bool) {
        let ax = &self.profile.axes;
        let msg = if first {
            format!(
                "the first leading axis of {call} is {axis}, not the hob axis {}",
                ax.hob
            )
        } else {
            format!(
                "{axis} is not a leading axis of the hobbing gearbox (hob {}, axial {}, shift {})",
                ax.hob, ax.axial, ax.shift
            )
        };
        self.push(line, rules::COUPLING_RATIO, msg);
    }

    fn egdef(&mut self, line: u32, following: AxisName, leading: &[(AxisName, i64)]) {
        self.is_table(line, "EGDEF", following);
        if self.coupled.is_some() {
            self.push(
                line,
                rules::COUPLING_RATIO,
                "EGDEF redefines the gearbox while it is coupled; EGOFS first".into(),
            );
        }
        let mut leads = [false; 3];
        for (i, (axis, _)) in leading.iter().enumerate() {
            let role = self.role(axis);
            match Self::lead_index(role) {
                Some(k) if (k == 0) == (i == 0) => leads[k] = true,
                _ => self.bad_lead(line, "EGDEF", *axis, i == 0),
            }
        }
        self.definition = Some(Definition { leads });
        self.defined = true;
    }

    fn egon(
        &mut self,
        line: u32,
        sync: bool,
        position: Option<Num>,
        following: AxisName,
        leading: &[Lead],
    ) {
        let call = if sync { "EGONSYNE" } else { "EGON" };
        self.is_table(line, call, following);
        if self.coupled.is_some() {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!("{call} while the gearbox is already coupled; EGOFS first"),
            );
        }
        let unit_start = !self.started || self.defined;
        if unit_start && self.started {
            self.unit = (self.unit + 1).min(self.units.len() - 1);
        }
        self.defined = false;
        // Every coupling of one unit must share one reference: couple at the
        // same synchronised positions, or stay coupled. A plain EGON takes
        // wherever the axes stand as its reference.
        let positions: Option<Vec<f64>> = sync.then(|| {
            std::iter::once(position.map_or(0.0, |p| p.value))
                .chain(leading.iter().map(|l| l.position.map_or(0.0, |p| p.value)))
                .collect()
        });
        if unit_start {
            self.reference = Some((line, positions));
        } else if let Some((first, reference)) = self.reference.clone() {
            let same = match (&reference, &positions) {
                (Some(a), Some(b)) => {
                    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= TOL)
                }
                _ => false,
            };
            if !same {
                let why = match (&reference, &positions) {
                    (None, _) => format!("the coupling of line {first} was a plain EGON, whose reference is wherever the axes stood"),
                    (_, None) => "a plain EGON takes wherever the axes stand as its reference".to_string(),
                    _ => format!("its synchronised positions differ from those of line {first}"),
                };
                self.push(
                    line,
                    rules::COUPLING_RATIO,
                    format!("{call} couples this unit again, but {why}: the cut lands in new gaps (couple every cut at the same EGONSYNE positions, or stay coupled)"),
                );
            }
        }
        self.started = true;
        let mut leads = [false; 3];
        for l in leading {
            if let Some(k) = Self::lead_index(self.role(&l.axis)) {
                leads[k] = true;
            }
        }
        match self.definition {
            None => self.push(
                line,
                rules::COUPLING_RATIO,
                format!("{call} switches on a gearbox that EGDEF has not defined"),
            ),
            Some(def) if def.leads != leads => self.push(
                line,
                rules::COUPLING_RATIO,
                format!("the leading axes of {call} differ from those of the EGDEF"),
            ),
            Some(_) => {}
        }
        let active = self.check_leads(line, call, leading);
        self.trace.couplings.push(TraceCoupling {
            line,
            num: active.num,
            den: active.den,
            c_per_z_deg_per_mm: active.z,
            c_per_y_deg_per_mm: active.y,
            unit_start,
        });
        self.coupled = Some(active);
        self.check_table_speed(line);
    }

    /// The 840D coupling against the unit's model.
    fn check_leads(&mut self, line: u32, call: &str, leading: &[Lead]) -> Active {
        let k = self.unit().kin;
        // The programmed ratio: the hob's hand in the machine's directions.
        let (z0, z) = (k.factors.c_per_b.num, k.factors.c_per_b.den);
        let mut active = Active {
            num: 0,
            den: 1,
            z: None,
            y: None,
        };
        let (_, zn, yn) = self.axes();
        for (i, l) in leading.iter().enumerate() {
            let role = self.role(&l.axis);
            if i == 0 {
                if role != Role::B {
                    self.bad_lead(line, call, l.axis, true);
                }
                let (num, den) = (l.num.integer().unwrap_or(0), l.den.integer().unwrap_or(0));
                (active.num, active.den) = (num, den);
                let lhs = i128::from(num) * i128::from(z);
                let rhs = i128::from(den) * i128::from(z0);
                if lhs != rhs || den == 0 {
                    let table = &self.profile.axes.table;
                    let hob = &self.profile.axes.hob;
                    self.push(
                        line,
                        rules::COUPLING_RATIO,
                        format!("{call} couples {table} to {hob} by {num}/{den}; the model's ratio is {z0}/{z} (z0/z signed by the hob's hand in the machine's axis directions)"),
                    );
                }
                continue;
            }
            if l.den.integer() != Some(1) {
                self.push(
                    line,
                    rules::COUPLING_RATIO,
                    format!(
                        "the factor of {} is written as numerator with denominator 1",
                        l.axis
                    ),
                );
            }
            let f = l.num.value;
            let (slot, want, what, axis) = match role {
                Role::Z => (
                    &mut active.z,
                    k.factors.c_per_z_deg_per_mm,
                    "differential",
                    zn,
                ),
                Role::Y => (
                    &mut active.y,
                    k.factors.c_per_y_deg_per_mm,
                    "shift compensation",
                    yn,
                ),
                _ => {
                    self.bad_lead(line, call, l.axis, false);
                    continue;
                }
            };
            *slot = Some(f);
            if (f - want).abs() > FACTOR {
                self.push(
                    line,
                    rules::COUPLING_RATIO,
                    format!(
                        "the {axis} factor {} deg/mm of {call} differs from the model's {what} {} deg/mm",
                        f6(f),
                        f6(want)
                    ),
                );
            }
        }
        let diff = k.factors.c_per_z_deg_per_mm;
        if active.z.is_none() && diff.abs() > FACTOR {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!(
                    "{call} has no {zn} factor, but the model's differential is {} deg/mm",
                    f6(diff)
                ),
            );
        }
        active
    }

    fn g81(&mut self, line: u32, teeth: Num, starts: Num, module: Option<Num>, helix: Option<Num>) {
        let unit_start = self.coupled.is_none();
        if unit_start {
            if self.started {
                self.unit = (self.unit + 1).min(self.units.len() - 1);
            }
            self.started = true;
        }
        let u = self.unit();
        let k = u.kin;
        // T and L are the teeth and hob starts themselves (the model keeps z0/z reduced).
        let (z0, z) = (u.hob.starts, u.gear.teeth);
        let t = teeth.integer().unwrap_or(0);
        let l = starts.integer().unwrap_or(0);
        if !(1..=1000).contains(&t) {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!("G81 T{t}: T is 1 to 1000"),
            );
        } else if t != i64::from(z) {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!("G81 T{t}: T must be the gear's {z} teeth"),
            );
        }
        if l == 0 || l.abs() > 21 {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!("G81 L{l}: L is 1 to 21 with the sign of the direction"),
            );
        } else if l.unsigned_abs() != u64::from(z0) {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!("G81 L{l}: |L| must be the hob's {z0} starts"),
            );
        } else if (l < 0) != (k.factors.c_per_b.num < 0) {
            self.push(
                line,
                rules::COUPLING_RATIO,
                format!(
                    "G81 L{l}: the sign of L is the table's direction against the hob, which the hob's hand ({}) fixes on this machine: L{}",
                    match u.hob.hand {
                        gearcam_proto::Hand::Right => "right",
                        gearcam_proto::Hand::Left => "left",
                    },
                    if k.factors.c_per_b.num < 0 { -l.abs() } else { l.abs() }
                ),
            );
        }
        let diff = k.factors.c_per_z_deg_per_mm;
        let mut implied = None;
        match (module, helix) {
            (Some(q), Some(p)) => {
                let (q, p) = (q.value, p.value);
                if q * t as f64 != 0.0 {
                    implied = Some(360.0 * p.to_radians().sin() / (PI * q * t as f64));
                }
                let mn = u.gear.module_mm;
                let beta = u.gear.helix_angle_deg.abs();
                let msg = if !(0.1..=25.0).contains(&q) || p.abs() > 90.0 {
                    Some(format!(
                        "G81 Q{} P{}: Q is 0.1 to 25 mm and |P| at most 90 degrees",
                        f3(q),
                        f4(p)
                    ))
                } else if diff.abs() <= FACTOR {
                    Some(format!(
                        "G81 Q{} P{} adds a helical compensation, but the model has no differential",
                        f3(q),
                        f4(p)
                    ))
                } else if (q - mn).abs() > MM {
                    Some(format!(
                        "G81 Q{}: Q must be the gear's normal module {} mm",
                        f3(q),
                        f3(mn)
                    ))
                } else if (p.abs() - beta).abs() > DEG {
                    Some(format!(
                        "G81 P{}: |P| must be the gear's helix angle {} degrees",
                        f4(p),
                        f4(beta)
                    ))
                } else if (p > 0.0) != (diff > 0.0) {
                    Some(format!(
                        "G81 P{} compensates {} deg/mm of C per Z; the model's differential is {} deg/mm, so P is {}",
                        f4(p),
                        f6(implied.unwrap_or(0.0)),
                        f6(diff),
                        f4(beta.copysign(diff))
                    ))
                } else {
                    None
                };
                if let Some(msg) = msg {
                    self.push(line, rules::COUPLING_RATIO, msg);
                }
            }
            (None, None) if diff.abs() > FACTOR => self.push(
                line,
                rules::COUPLING_RATIO,
                format!(
                    "G81 without Q and P: the model's differential of {} deg/mm needs the helical compensation (Q the module, P the helix angle)",
                    f6(diff)
                ),
            ),
            (None, None) => {}
            _ => self.push(
                line,
                rules::COUPLING_RATIO,
                "G81 takes Q and P together (alarm PS0594 otherwise)".into(),
            ),
        }
        let active = Active {
            num: l,
            den: t,
            z: implied,
            y: None,
        };
        self.trace.couplings.push(TraceCoupling {
            line,
            num: l,
            den: t,
            c_per_z_deg_per_mm: implied,
            c_per_y_deg_per_mm: None,
            unit_start,
        });
        self.coupled = Some(active);
        self.check_table_speed(line);
    }

    fn gear_off(&mut self, line: u32, following: Option<AxisName>) {
        let call = match following {
            Some(f) => {
                self.is_table(line, "EGOFS", f);
                format!("EGOFS({f})")
            }
            None => "G80".to_string(),
        };
        if self.coupled.is_some() {
            if let Some(zone) = self.zone_here() {
                let zone_text = zone.describe(self.axes(), self.units.len());
                self.push(
                    line,
                    rules::DEPTH_UNCOUPLED,
                    format!("{call} uncouples the gearbox with the hob inside the contact zone ({zone_text})"),
                );
            }
        }
        self.coupled = None;
    }

    fn egdel(&mut self, line: u32, following: AxisName) {
        self.is_table(line, "EGDEL", following);
        if self.coupled.is_some() {
            self.push(
                line,
                rules::COUPLING_RATIO,
                "EGDEL deletes the gearbox definition while it is coupled; EGOFS first".into(),
            );
        }
        self.definition = None;
    }

    // ----- end -----

    fn finish(&mut self, last_line: u32) {
        let end_code = self.profile.mcodes.program_end;
        let end_line = match self.end {
            Some(l) => l,
            None => {
                self.push(
                    last_line,
                    rules::END_AT_A,
                    format!(
                        "the program does not end with M{end_code}, the machine's end of program"
                    ),
                );
                last_line
            }
        };
        for (name, on) in FUNCTIONS.iter().zip(self.functions) {
            if let Some(since) = on {
                self.push(
                    end_line,
                    rules::MCODE_PAIR,
                    format!("{name} is still on at the end of the program (switched on at line {since})"),
                );
            }
        }
        if let Some(line) = self.last_move {
            let (hx, hz) = (self.profile.home_x_mm, self.profile.home_z_mm);
            if (self.x - hx).abs() > MM || (self.z - hz).abs() > MM {
                let (xn, zn, _) = self.axes();
                let msg = format!(
                    "the last move ends at {xn}={} {zn}={}, not at the start point A ({xn}={} {zn}={})",
                    f3(self.x),
                    f3(self.z),
                    f3(hx),
                    f3(hz)
                );
                self.push(line, rules::END_AT_A, msg);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zone() -> Zone {
        Zone {
            unit: 0,
            x_hi: 80.5,
            z_lo: 25.798,
            z_hi: 104.202,
            y_half: None,
        }
    }

    #[test]
    fn segments_along_the_zone_edge_are_outside() {
        let z = zone();
        // B → C at the top of the band, D → E at the bottom.
        assert!(!z.crossed_by([173.75, 104.202, 0.0], [73.75, 104.202, 0.0]));
        assert!(!z.crossed_by([73.75, 25.798, 0.0], [78.75, 25.798, 0.0]));
        // C → D through the band, and a rapid into it.
        assert!(z.crossed_by([73.75, 104.202, 0.0], [73.75, 25.798, 0.0]));
        assert!(z.crossed_by([174.05, 82.0, 0.0], [75.0, 40.0, 0.0]));
        // E → A diagonally: X is below 80.5 while Z climbs into the band.
        assert!(z.crossed_by([78.75, 25.798, 0.0], [300.0, 350.0, 0.0]));
        // A point.
        assert!(z.crossed_by([70.0, 50.0, 0.0], [70.0, 50.0, 0.0]));
        assert!(!z.crossed_by([90.0, 50.0, 0.0], [90.0, 50.0, 0.0]));
    }

    #[test]
    fn tangential_zone_is_clear_while_the_hob_is_shifted_out() {
        // The worm wheel example: R + r = 63.05 + 40, throat 82.5 ± 40.
        let z = Zone {
            unit: 0,
            x_hi: 103.05,
            z_lo: 42.5,
            z_hi: 122.5,
            y_half: Some(78.384),
        };
        assert!(!z.crossed_by([205.0, 82.5, -80.384], [96.301, 82.5, -80.384]));
        assert!(z.crossed_by([96.301, 82.5, -80.384], [96.301, 82.5, 78.384]));
    }

    #[test]
    fn circle_through_three_points_and_radius_arcs() {
        // A quarter circle of radius 10 around (Z 0, X 0): from (10, 0) via 45° to (0, 10).
        let s = 10.0 / 2f64.sqrt();
        let (c, t0, sweep) = circle_via((10.0, 0.0), (s, s), (0.0, 10.0)).unwrap();
        assert!(c.0.abs() < 1e-9 && c.1.abs() < 1e-9);
        assert!(t0.abs() < 1e-12);
        assert!((sweep - PI / 2.0).abs() < 1e-12);
        // The same arc the other way round through the far side.
        let (_, _, sweep) = circle_via((10.0, 0.0), (-10.0, 0.0), (0.0, 10.0)).unwrap();
        assert!((sweep + 1.5 * PI).abs() < 1e-12);
        assert!(circle_via((0.0, 0.0), (1.0, 1.0), (2.0, 2.0)).is_none());
        // G03 (counter-clockwise) R10 from (10, 0) to (0, 10): centre at the origin.
        let (c, _, sweep) = arc_radius((10.0, 0.0), (0.0, 10.0), 10.0, true).unwrap();
        assert!(c.0.abs() < 1e-9 && c.1.abs() < 1e-9);
        assert!((sweep - PI / 2.0).abs() < 1e-12);
        // G02 (clockwise) R10 between the same points: centre at (10, 10).
        let (c, _, sweep) = arc_radius((10.0, 0.0), (0.0, 10.0), 10.0, false).unwrap();
        assert!((c.0 - 10.0).abs() < 1e-9 && (c.1 - 10.0).abs() < 1e-9);
        assert!((sweep + PI / 2.0).abs() < 1e-12);
        assert!(arc_radius((0.0, 0.0), (30.0, 0.0), 10.0, true).is_none());
    }
}
