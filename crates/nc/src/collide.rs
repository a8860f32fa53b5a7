//! The independent clearance check: the hob as a finite solid moved along
//! every move of the parsed program, against the blank of every gear unit
//! (rapid moves) and against the table, the fixture and the tailstock (every
//! move).
//!
//! It shares nothing with the model's clearance ΔH′ but the machine-neutral
//! frame (`docs/hobbing.md`): the programmed swivel value gives the hob's
//! tilt η = (A − offset)/swivel_sign, the programmed X, Z and shift Y its
//! centre, and the hob is its tip cylinder (radius da0/2, the hob's length)
//! around the axis u = (0, cos η, −sin η). The obstacles are solids of
//! revolution about the table axis: each blank a cylinder or a frustum, the
//! table a cylinder reaching down without end, the fixture a cylinder, the
//! tailstock a cylinder reaching up without end.
//!
//! All of them are convex, and within a move that keeps the tilt the hob is
//! a translate of one cylinder, so the solid it sweeps is convex too. How
//! deep the hob enters an obstacle along the move is then found from the
//! geometry, with certified bounds rather than samples (`depth`): one
//! distance query between the swept solid and the obstacle (`gjk`, on the
//! support functions of `shapes`) shows most moves clear; where it does not,
//! the deepest point of either solid in the other is bracketed to 1 nm by a
//! bisection on level sets. A move that swivels the hob is bounded by a
//! Lipschitz branch and bound over its poses. A finding names the line, the
//! obstacle, how deep the hob enters it and near which radius and height.
//!
//! # Tolerance
//!
//! A penetration up to [`PEN_TOL`] is ignored: the printed coordinates are
//! rounded to 0.0005 mm.
//!
//! # Layout
//!
//! - `shapes`: the hob's sweep and the obstacles as support functions, and
//!   their level sets.
//! - `gjk`: the distance between two of them, with its certified bounds.
//! - `depth`: the depth along a straight move and along a swivel move.
//! - [`hook`]: the same for the crate's tests and benchmark.

use gearcam_geom::Vector3;
use gearcam_proto::{GearSpec, HobData, MachiningModel, MoveKind, PathFinding};

use super::{finding, Trace};
use depth::{Depth, Need};
use gearcam_proto::Code;
use shapes::{depth_bound, Solid, Sweep};

mod depth;
mod gjk;
mod shapes;
#[cfg(test)]
mod tests;

/// Penetration ignored, mm.
pub(crate) const PEN_TOL: f64 = 0.002;

/// A point or direction in the machine-neutral frame (x radial, y
/// tangential, z axial), mm.
type P3 = Vector3<f64>;

/// What the hob must not enter.
#[derive(Debug, Clone)]
struct Obstacle {
    what: String,
    solid: Solid,
    /// Checked on rapid moves only (the blank, which feed moves cut).
    rapid_only: bool,
}

/// The hob along one move: its tip cylinder, and the machine-neutral
/// position (X, Z, shift along the hob axis) and tilt η at both ends, each
/// varying linearly along the move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HobMove {
    /// X, Z and the shift along the hob's axis at the start, mm.
    pub from: [f64; 3],
    /// The same at the end.
    pub to: [f64; 3],
    /// Tilt η at the start, degrees.
    pub eta_from_deg: f64,
    /// Tilt η at the end, degrees.
    pub eta_to_deg: f64,
    /// Tip radius da0/2, mm.
    pub radius: f64,
    /// Half the hob's length, mm.
    pub half_length: f64,
}

impl HobMove {
    /// The hob's axis at tilt η.
    fn axis(eta_deg: f64) -> P3 {
        let (sin, cos) = eta_deg.to_radians().sin_cos();
        P3::new(0.0, cos, -sin)
    }

    /// The hob's centre at a position with the given axis.
    fn centre(at: [f64; 3], axis: P3) -> P3 {
        P3::new(at[0], 0.0, at[1]) + axis * at[2]
    }

    /// True when the tilt stays (within 1e-9 degrees).
    fn keeps_tilt(&self) -> bool {
        (self.eta_to_deg - self.eta_from_deg).abs() <= 1e-9
    }

    /// The pose at the move's parameter t, as a sweep that does not travel.
    fn pose_at(&self, t: f64) -> Sweep {
        let at = [0, 1, 2].map(|k| self.from[k] + (self.to[k] - self.from[k]) * t);
        let axis = Self::axis(self.eta_from_deg + (self.eta_to_deg - self.eta_from_deg) * t);
        Sweep {
            start: Self::centre(at, axis),
            travel: P3::zeros(),
            axis,
            r: self.radius,
            half: self.half_length,
        }
    }

    /// The farthest any hob point gets from the line of its centre's X and
    /// Z: the shift along the axis, then the hob's reach √(r² + h²).
    fn lever(&self) -> f64 {
        self.from[2].abs().max(self.to[2].abs()) + self.radius.hypot(self.half_length)
    }

    /// How far any hob point moves per unit of the move's parameter, at
    /// most (`depth`'s derivation): a point is (X, 0, Z) + Y·u(η) plus its
    /// offset from the centre turned with η, so its speed is at most
    /// |Δ(X, Z)| + |ΔY| + |Y|·|Δη| + |offset|·|Δη|.
    fn lipschitz(&self) -> f64 {
        let travel = (self.to[0] - self.from[0]).hypot(self.to[1] - self.from[1]);
        let shift = (self.to[2] - self.from[2]).abs();
        let turn = (self.eta_to_deg - self.eta_from_deg).to_radians().abs();
        travel + shift + self.lever() * turn
    }

    /// The depth D* of the move into a solid (`depth`).
    fn depth(&self, solid: &Solid, need: Need) -> Depth {
        if self.keeps_tilt() {
            let axis = Self::axis(self.eta_to_deg);
            let start = Self::centre(self.from, axis);
            let sweep = Sweep {
                start,
                travel: Self::centre(self.to, axis) - start,
                axis,
                r: self.radius,
                half: self.half_length,
            };
            depth::straight(&sweep, solid, need)
        } else {
            let lever = self.lever();
            let pose_at = |t: f64| self.pose_at(t);
            // Every pose lies within `lever` of the line of centres' heights.
            let (z0, z1) = (self.from[1].min(self.to[1]), self.from[1].max(self.to[1]));
            let frustum = solid.finite_for(z0 - lever, z1 + lever);
            let caps = [
                depth_bound(&frustum, z0 - lever, z1 + lever),
                self.radius.min(self.half_length),
            ];
            depth::swivel(&pose_at, self.lipschitz(), caps, solid, need)
        }
    }
}

/// The blanks of every unit, and the table, fixture and tailstock.
fn obstacles(model: &MachiningModel) -> Vec<Obstacle> {
    let m = &model.model;
    // A unit's gear carries its own lower face: the model replaced its
    // fixture height by the first unit's plus the unit's offset.
    let units: Vec<(&GearSpec, f64)> = if m.units.is_empty() {
        vec![(&model.plan.gear, m.blank_od_mm)]
    } else {
        m.units
            .iter()
            .map(|u| (&u.gear, u.model.blank_od_mm))
            .collect()
    };
    let mut out = Vec::new();
    let base = model.plan.gear.fixture_height_mm;
    let mut top = f64::NEG_INFINITY;
    let mut bottom = f64::INFINITY;
    for (i, (gear, od)) in units.iter().enumerate() {
        let z_lo = gear.fixture_height_mm;
        let z_hi = z_lo + gear.face_width_mm;
        let r = od / 2.0;
        let (r_lo, r_hi) = match &gear.cone {
            Some(cone) => {
                let taper = gear.face_width_mm * cone.angle_deg.to_radians().tan();
                match cone.large_end {
                    gearcam_proto::LargeEnd::Bottom => (r, r - taper),
                    gearcam_proto::LargeEnd::Top => (r - taper, r),
                }
            }
            None => (r, r),
        };
        let what = if units.len() > 1 {
            format!("the blank of unit {}", i + 1)
        } else {
            "the blank".to_string()
        };
        out.push(Obstacle {
            what,
            solid: Solid {
                z_lo,
                z_hi,
                r_lo,
                r_hi,
            },
            rapid_only: true,
        });
        top = top.max(z_hi);
        bottom = bottom.min(z_lo);
    }
    let env = &model.plan.machine.envelope;
    out.push(Obstacle {
        what: "the table".into(),
        solid: Solid {
            z_lo: f64::NEG_INFINITY,
            z_hi: 0.0,
            r_lo: env.table_radius_mm,
            r_hi: env.table_radius_mm,
        },
        rapid_only: false,
    });
    let fixture_r = model
        .plan
        .gear
        .fixture_diameter_mm
        .map_or(env.fixture_radius_mm, |d| d / 2.0);
    let fixture_top = bottom.min(base);
    if fixture_r > 0.0 && fixture_top > 0.0 {
        out.push(Obstacle {
            what: "the fixture".into(),
            solid: Solid {
                z_lo: 0.0,
                z_hi: fixture_top,
                r_lo: fixture_r,
                r_hi: fixture_r,
            },
            rapid_only: false,
        });
    }
    if env.tailstock_radius_mm > 0.0 && top.is_finite() {
        out.push(Obstacle {
            what: "the tailstock".into(),
            solid: Solid {
                z_lo: top + env.tailstock_gap_mm,
                z_hi: f64::INFINITY,
                r_lo: env.tailstock_radius_mm,
                r_hi: env.tailstock_radius_mm,
            },
            rapid_only: false,
        });
    }
    out
}

/// The units' hobs in program order, and the lines of the couplings that
/// start each unit (the first, then every one after a new definition or an
/// uncoupling): a line's hob is the one of the last unit started before it.
struct Hobs<'m> {
    hobs: Vec<&'m HobData>,
    starts: Vec<u32>,
}

impl<'m> Hobs<'m> {
    fn new(model: &'m MachiningModel, trace: &Trace) -> Hobs<'m> {
        let hobs = if model.model.units.is_empty() {
            vec![&model.plan.hob]
        } else {
            model.model.units.iter().map(|u| &u.hob).collect()
        };
        let starts = trace
            .couplings
            .iter()
            .filter(|c| c.unit_start)
            .map(|c| c.line)
            .collect();
        Hobs { hobs, starts }
    }

    /// The hob mounted at `line` (before the first coupling, the first unit's).
    fn at(&self, line: u32) -> &'m HobData {
        let idx = self
            .starts
            .iter()
            .filter(|&&l| l <= line)
            .count()
            .saturating_sub(1);
        self.hobs[idx.min(self.hobs.len() - 1)]
    }
}

/// One move to check: where the hob goes, and what it may not enter.
struct Planned<'m> {
    line: u32,
    kind: MoveKind,
    a_to: f64,
    hob: &'m HobData,
    path: HobMove,
    /// A rapid that only withdraws the hob radially (see `plan`).
    withdrawal: bool,
}

/// The hob's moves of a simulated program, with the mounted hob and the
/// swivel at both ends of each.
fn plan<'m>(model: &'m MachiningModel, trace: &Trace) -> Vec<Planned<'m>> {
    let settings = &model.plan.machine.settings;
    let hobs = Hobs::new(model, trace);
    let mut out = Vec::with_capacity(trace.moves.len());
    let mut from = [
        model.plan.machine.home_x_mm,
        model.plan.machine.home_z_mm,
        0.0,
    ];
    // Before the first programmed swivel the head stands where the program
    // will put it first (the program sets it before any move near the work).
    let first_a = trace.swivel_deg.first().map_or(0.0, |s| s.1);
    let mut a_from = first_a;
    let eta = |a: f64| (a - settings.swivel_offset_deg) * settings.swivel_sign;
    for mv in &trace.moves {
        if mv.kind == MoveKind::Dwell {
            continue;
        }
        let to = [mv.x_mm, mv.z_mm, mv.y_mm];
        let a_to = trace
            .swivel_deg
            .iter()
            .rev()
            .find(|s| s.0 <= mv.line)
            .map_or(first_a, |s| s.1);
        let hob = hobs.at(mv.line);
        let r = hob.od_mm / 2.0;
        // A rapid that only moves X outwards withdraws the hob from the gaps
        // it stands in (a worm wheel's retract from the throat): while the
        // whole hob stays on its side of the table axis (X > r), every hob
        // point moves away from the axis and cannot enter a blank.
        let withdrawal = to[0] > from[0]
            && (to[1] - from[1]).abs() <= 1e-9
            && (to[2] - from[2]).abs() <= 1e-9
            && (a_to - a_from).abs() <= 1e-9
            && from[0] > r;
        let shift = settings.shift_sign;
        out.push(Planned {
            line: mv.line,
            kind: mv.kind,
            a_to,
            hob,
            path: HobMove {
                from: [from[0], from[1], from[2] * shift],
                to: [to[0], to[1], to[2] * shift],
                eta_from_deg: eta(a_from),
                eta_to_deg: eta(a_to),
                radius: r,
                half_length: hob.length_mm / 2.0,
            },
            withdrawal,
        });
        from = to;
        a_from = a_to;
    }
    out
}

/// True when the move is checked against the obstacle: the blanks on rapid
/// moves that do not withdraw the hob, the rest on every move.
fn checked(mv: &Planned<'_>, ob: &Obstacle) -> bool {
    !ob.rapid_only || (mv.kind == MoveKind::Rapid && !mv.withdrawal)
}

/// The independent clearance and envelope check of a simulated program.
pub(crate) fn check(model: &MachiningModel, trace: &Trace) -> Vec<PathFinding> {
    let axes = &model.plan.machine.axes;
    let obstacles = obstacles(model);
    let mut findings = Vec::new();
    for mv in plan(model, trace) {
        for ob in obstacles.iter().filter(|ob| checked(&mv, ob)) {
            let d = mv.path.depth(&ob.solid, Need::Above(PEN_TOL));
            // The bounds are 1 nm apart (0.1 µm on a swivel move) whenever
            // the hob enters; the middle is the depth.
            let depth = 0.5 * (d.lo + d.hi);
            if depth <= PEN_TOL {
                continue;
            }
            let what = match mv.kind {
                MoveKind::Rapid => "rapid move",
                MoveKind::Feed => "feed move",
                _ => "arc",
            };
            let rule = if ob.rapid_only {
                Code::HOB_CLEARANCE
            } else {
                Code::ENVELOPE
            };
            findings.push(finding(
                mv.line,
                rule,
                format!(
                    "the {what} to {}={:.3} {}={:.3} takes the hob (tip cylinder {:.3} x {:.3} mm, {}={:.4}) {:.3} mm into {} near radius {:.3} mm, height {:.3} mm",
                    axes.radial,
                    mv.path.to[0],
                    axes.axial,
                    mv.path.to[1],
                    mv.hob.od_mm,
                    mv.hob.length_mm,
                    axes.swivel,
                    mv.a_to,
                    depth,
                    ob.what,
                    d.at[0].hypot(d.at[1]),
                    d.at[2]
                ),
            ));
        }
    }
    findings
}

/// The clearance check's pieces for the crate's tests and benchmark: not
/// part of the crate's interface.
#[doc(hidden)]
pub mod hook {
    use super::{checked, obstacles, plan, Need};
    use gearcam_proto::{MachiningModel, PathFinding};

    pub use super::shapes::Solid;
    pub use super::HobMove;

    /// Certified bounds of the depth D* of a move into a solid (the
    /// deepest point of either in the other; minus the distance when apart).
    #[derive(Debug, Clone, Copy)]
    pub struct Depth {
        /// D* is at least this.
        pub lo: f64,
        /// D* is at most this.
        pub hi: f64,
        /// Where `lo` is reached.
        pub at: [f64; 3],
        /// The move's parameter of the pose where it is reached.
        pub t: f64,
        /// True when `at` is a point of the hob (else of the solid).
        pub hob_point: bool,
    }

    /// D* of a move into a solid, bracketed in every case.
    pub fn depth(path: &HobMove, solid: &Solid) -> Depth {
        let d = path.depth(solid, Need::Exact);
        Depth {
            lo: d.lo,
            hi: d.hi,
            at: [d.at[0], d.at[1], d.at[2]],
            t: d.t,
            hob_point: d.hob_point,
        }
    }

    /// One move of a simulated program and the solids it is checked
    /// against.
    #[derive(Debug, Clone)]
    pub struct Checked {
        /// The move's line.
        pub line: u32,
        /// The hob along it.
        pub hob: HobMove,
        /// The solids, each with its name in findings.
        pub solids: Vec<(String, Solid)>,
    }

    /// Every move of a simulated program with the solids it is checked
    /// against.
    pub fn moves(model: &MachiningModel, trace: &super::Trace) -> Vec<Checked> {
        let obstacles = obstacles(model);
        plan(model, trace)
            .iter()
            .map(|mv| Checked {
                line: mv.line,
                hob: mv.path,
                solids: obstacles
                    .iter()
                    .filter(|ob| checked(mv, ob))
                    .map(|ob| (ob.what.clone(), ob.solid))
                    .collect(),
            })
            .collect()
    }

    /// The clearance and envelope findings of a simulated program (what
    /// [`crate::check`] adds to the simulation's).
    pub fn clearance(model: &MachiningModel, trace: &super::Trace) -> Vec<PathFinding> {
        super::check(model, trace)
    }
}
