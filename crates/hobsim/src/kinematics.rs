//! The hob's pose relative to the workpiece over time, in the machine-neutral
//! frame of `docs/hobbing.md` §1.
//!
//! A [`Timeline`] is a list of [`Segment`]s, one per move of the program. In a
//! segment X, Y (shift along u) and Z move linearly in time, the hob turns at
//! a constant rate, and the table either stands (decoupled) or follows the
//! gearbox: C − C₀ = k_b·(B − B₀) + k_z·(Z − Z₀) + k_y·(Y − Y₀), all in the
//! neutral frame (C clockwise from above, B right-handed about u). The
//! programmed values are mapped back through the machine profile's signs
//! (`docs/hobbing.md` §6; `docs/simulation.md` lists them).

use gearcam_nc::Trace;
use gearcam_proto::{MachiningModel, MoveKind};

use crate::SimError;

mod errors;
mod sync;

pub use errors::MachineErrors;
pub use sync::CouplingPhase;
use sync::{CouplingStart, Phaser};

/// Position of the linear axes in the neutral frame, mm: X centre distance,
/// Y hob shift along u, Z height of the hob centre.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Axes {
    /// Centre distance, mm.
    pub x_mm: f64,
    /// Shift along the hob axis u, mm.
    pub y_mm: f64,
    /// Height of the hob centre above the table plane, mm.
    pub z_mm: f64,
}

/// The gearbox in the neutral frame: table turns per hob turn and the
/// additional table turns per mm of Z and of Y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gearbox {
    /// C per B (turns per turn, signed): s_h·z0/z for a correct program.
    pub c_per_b: f64,
    /// C per Z, radians per mm.
    pub c_per_z_rad_mm: f64,
    /// C per Y, radians per mm of shift along u.
    pub c_per_y_rad_mm: f64,
}

/// One move: linear axes from `from` to `to` over `t0_s..t1_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Program line the move comes from (0 for a segment built by hand).
    pub line: u32,
    /// Start time, s.
    pub t0_s: f64,
    /// End time, s.
    pub t1_s: f64,
    /// Axes at the start.
    pub from: Axes,
    /// Axes at the end.
    pub to: Axes,
    /// Swivel η, radians (neutral frame).
    pub eta_rad: f64,
    /// Hob speed, turns per second, signed right-handed about u.
    pub hob_rev_s: f64,
    /// The gearbox when coupled during the move.
    pub gearbox: Option<Gearbox>,
    /// Extra table turn spread over the move (FANUC C correction), radians.
    pub c_extra_rad: f64,
    /// True for a feed (or arc) move, false for rapids and dwells.
    pub feed: bool,
}

/// The hob's pose at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Linear axes.
    pub axes: Axes,
    /// Swivel η, radians.
    pub eta_rad: f64,
    /// Hob angle B, radians, right-handed about u.
    pub b_rad: f64,
    /// Table angle C, radians, clockwise seen from above.
    pub c_rad: f64,
}

/// Segments with the hob and table angles at each segment's start.
#[derive(Debug, Clone, PartialEq)]
pub struct Timeline {
    segments: Vec<Segment>,
    /// (B, C) at each segment's start, radians.
    start_angles: Vec<(f64, f64)>,
    /// How each coupling's phase was set (empty for a hand-built timeline).
    phases: Vec<CouplingPhase>,
    /// The what-if errors laid over every pose.
    errors: MachineErrors,
}

const TAU: f64 = std::f64::consts::TAU;

impl Segment {
    /// The linear axes at fraction `s` (0..1) of the move.
    pub fn axes_at(&self, s: f64) -> Axes {
        let l = |a: f64, b: f64| a + (b - a) * s;
        Axes {
            x_mm: l(self.from.x_mm, self.to.x_mm),
            y_mm: l(self.from.y_mm, self.to.y_mm),
            z_mm: l(self.from.z_mm, self.to.z_mm),
        }
    }

    fn fraction(&self, t: f64) -> f64 {
        let d = self.t1_s - self.t0_s;
        if d > 0.0 {
            ((t - self.t0_s) / d).clamp(0.0, 1.0)
        } else {
            1.0
        }
    }

    /// Hob and table turn from the segment's start to time `t`, radians.
    fn turns(&self, t: f64) -> (f64, f64) {
        let s = self.fraction(t);
        let db = TAU * self.hob_rev_s * (t.clamp(self.t0_s, self.t1_s) - self.t0_s);
        let mut dc = self.c_extra_rad * s;
        if let Some(g) = self.gearbox {
            let a = self.axes_at(s);
            dc += g.c_per_b * db
                + g.c_per_z_rad_mm * (a.z_mm - self.from.z_mm)
                + g.c_per_y_rad_mm * (a.y_mm - self.from.y_mm);
        }
        (db, dc)
    }
}

impl Timeline {
    /// A timeline from segments in time order (each starting where the last
    /// ended), with B = C = 0 at the start.
    pub fn from_segments(segments: Vec<Segment>) -> Result<Timeline, SimError> {
        Timeline::build(segments, &[])
    }

    /// A timeline whose segment `i` starts coupling `starts[i]` (when
    /// `Some`): the table jumps to the phase [`Phaser`] gives it.
    fn build(
        segments: Vec<Segment>,
        starts: &[Option<CouplingStart>],
    ) -> Result<Timeline, SimError> {
        if segments.is_empty() {
            return Err(SimError::Empty);
        }
        let mut start_angles = Vec::with_capacity(segments.len());
        let mut phaser = Phaser::default();
        let (mut b, mut c) = (0.0, 0.0);
        for (i, s) in segments.iter().enumerate() {
            if let (Some(Some(start)), Some(g)) = (starts.get(i), s.gearbox) {
                let residual = c
                    - g.c_per_b * b
                    - g.c_per_z_rad_mm * s.from.z_mm
                    - g.c_per_y_rad_mm * s.from.y_mm;
                c += phaser.couple(i, *start, residual);
            }
            if s.gearbox.is_some() && s.feed && s.hob_rev_s != 0.0 && s.t1_s > s.t0_s {
                phaser.cutting();
            }
            start_angles.push((b, c));
            let (db, dc) = s.turns(s.t1_s);
            b += db;
            c += dc;
        }
        Ok(Timeline {
            segments,
            start_angles,
            phases: phaser.phases,
            errors: MachineErrors::default(),
        })
    }

    /// The same timeline on a machine with `errors` (every pose carries them).
    pub fn with_errors(mut self, errors: MachineErrors) -> Timeline {
        self.errors = errors;
        self
    }

    /// The what-if errors the poses carry.
    pub fn errors(&self) -> MachineErrors {
        self.errors
    }

    /// How each coupling of the program set the table's phase, in order.
    pub fn couplings(&self) -> &[CouplingPhase] {
        &self.phases
    }

    /// The segments.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }

    /// The pose at time `t` in segment `i`, with the timeline's errors.
    pub fn pose_in(&self, i: usize, t: f64) -> Pose {
        self.errors.apply(self.nominal_pose_in(i, t))
    }

    /// The pose at time `t` in segment `i` on the ideal machine.
    pub fn nominal_pose_in(&self, i: usize, t: f64) -> Pose {
        let s = &self.segments[i];
        let (b0, c0) = self.start_angles[i];
        let (db, dc) = s.turns(t);
        Pose {
            axes: s.axes_at(s.fraction(t)),
            eta_rad: s.eta_rad,
            b_rad: b0 + db,
            c_rad: c0 + dc,
        }
    }

    /// The pose at time `t` (clamped to the timeline).
    pub fn pose(&self, t: f64) -> Pose {
        self.errors.apply(self.nominal_pose(t))
    }

    /// The pose at time `t` (clamped to the timeline) on the ideal machine.
    pub fn nominal_pose(&self, t: f64) -> Pose {
        let i = self
            .segments
            .partition_point(|s| s.t1_s < t)
            .min(self.segments.len() - 1);
        self.nominal_pose_in(i, t)
    }

    /// The timeline's end time, s.
    pub fn end_s(&self) -> f64 {
        self.segments.last().map_or(0.0, |s| s.t1_s)
    }
}

/// What the trace does not say: the rapid rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MachineRates {
    /// Rapid traverse rate, mm/min (default 10 000).
    pub rapid_mm_min: f64,
}

impl Default for MachineRates {
    fn default() -> Self {
        MachineRates {
            rapid_mm_min: 10_000.0,
        }
    }
}

/// The program state a move sees: the last of each event before its line.
struct State {
    rpm: f64,
    /// +1 (M3), −1 (M4) or 0 (M5, or not started).
    dir: f64,
    swivel_prog_deg: f64,
    coupling: Option<gearcam_nc::TraceCoupling>,
}

fn state_at(trace: &Trace, model: &MachiningModel, line: u32) -> State {
    let before = |l: u32| l <= line;
    let rpm = trace
        .spindle_rpm
        .iter()
        .rfind(|(l, _)| before(*l))
        .map_or(0.0, |&(_, r)| r);
    let dir = trace
        .mcodes
        .iter()
        .rfind(|(l, c)| before(*l) && matches!(c, 3..=5))
        .map_or(0.0, |&(_, c)| match c {
            3 => 1.0,
            4 => -1.0,
            _ => 0.0,
        });
    let settings = &model.plan.machine.settings;
    let swivel_prog_deg = trace
        .swivel_deg
        .iter()
        .rfind(|(l, _)| before(*l))
        .map_or(settings.swivel_offset_deg, |&(_, a)| a);
    let coupling = trace.couplings.iter().rfind(|c| c.line < line).cloned();
    State {
        rpm,
        dir,
        swivel_prog_deg,
        coupling,
    }
}

/// The timeline of a whole program on the ideal machine: [`from_trace_with`]
/// with [`MachineErrors::default`].
pub fn from_trace(
    trace: &Trace,
    model: &MachiningModel,
    rates: MachineRates,
) -> Result<Timeline, SimError> {
    from_trace_with(trace, model, rates, MachineErrors::default())
}

/// Half a pitch of each gear unit's gear in table angle, π/z, radians.
fn half_pitches(model: &MachiningModel) -> Vec<f64> {
    let teeth: Vec<u32> = if model.model.units.is_empty() {
        vec![model.plan.gear.teeth]
    } else {
        model.model.units.iter().map(|u| u.gear.teeth).collect()
    };
    teeth
        .iter()
        .map(|&z| std::f64::consts::PI / f64::from(z.max(1)))
        .collect()
}

/// The gear unit of every coupling of the trace: the check's rule (a unit
/// starts at the program's first coupling, after a new `EGDEF`, at a `G81`
/// after a `G80`), the last unit kept when the model has no more.
fn coupling_units(trace: &Trace, units: usize) -> Vec<usize> {
    let mut n = 0usize;
    trace
        .couplings
        .iter()
        .map(|c| {
            if c.unit_start {
                n += 1;
            }
            n.saturating_sub(1).min(units.saturating_sub(1))
        })
        .collect()
}

/// The timeline of a whole program: every move of the trace, first to last,
/// starting at the machine's home position (`home_x_mm`, `home_z_mm`, Y 0),
/// on a machine with `errors` (see [`MachineErrors::apply`]).
///
/// Programmed values become neutral ones through the machine profile's
/// settings: η = (A − swivel_offset)/swivel_sign, Y = shift_sign·Y_prog,
/// B = hob_sign·B_prog (B_prog turning positive under M3, negative under M4),
/// and the gearbox C_prog = (num/den)·B_prog + f_z·Z + f_y·Y_prog becomes
/// C = table_sign·C_prog. At the first move of every coupling the table
/// takes the phase `sync` gives it: a unit coupled again after it cut keeps
/// its first coupling's phase when both are synchronised (`EGONSYNE`), and is
/// put half a pitch off it otherwise (the worst case of an unknown phase).
pub fn from_trace_with(
    trace: &Trace,
    model: &MachiningModel,
    rates: MachineRates,
    errors: MachineErrors,
) -> Result<Timeline, SimError> {
    if trace.moves.is_empty() {
        return Err(SimError::Empty);
    }
    let machine = &model.plan.machine;
    let st = &machine.settings;
    let half = half_pitches(model);
    let units = coupling_units(trace, half.len());
    let mut pos = Axes {
        x_mm: machine.home_x_mm,
        y_mm: 0.0,
        z_mm: machine.home_z_mm,
    };
    let mut t = 0.0;
    let mut segments = Vec::with_capacity(trace.moves.len());
    let mut starts = Vec::with_capacity(trace.moves.len());
    let mut last_coupling: Option<u32> = None;
    for m in &trace.moves {
        let state = state_at(trace, model, m.line);
        let to = Axes {
            x_mm: m.x_mm,
            y_mm: st.shift_sign * m.y_mm,
            z_mm: m.z_mm,
        };
        let pieces = arc_pieces(pos, to, m.arc.as_ref());
        let dist = match &m.arc {
            Some(a) => {
                let r = (pos.z_mm - a.centre_z_mm).hypot(pos.x_mm - a.centre_x_mm);
                (r * a.sweep_rad).hypot(to.y_mm - pos.y_mm)
            }
            None => ((to.x_mm - pos.x_mm).powi(2)
                + (to.y_mm - pos.y_mm).powi(2)
                + (to.z_mm - pos.z_mm).powi(2))
            .sqrt(),
        };
        let (dt, feed) = match m.kind {
            MoveKind::Rapid => (dist / rates.rapid_mm_min * 60.0, false),
            MoveKind::Dwell => (m.dwell_s.unwrap_or(0.0), false),
            MoveKind::Feed | MoveKind::Arc => match m.feed_mm_min {
                Some(f) if f > 0.0 => (dist / f * 60.0, true),
                _ if dist == 0.0 => (0.0, true),
                _ => return Err(SimError::NoFeed(m.line)),
            },
        };
        let coupling = state.coupling.as_ref().filter(|_| m.coupled);
        let gearbox = coupling.map(|c| gearbox_of(c, st)).transpose()?;
        let mut start = coupling.filter(|c| last_coupling != Some(c.line)).map(|c| {
            let k = trace
                .couplings
                .iter()
                .position(|d| d.line == c.line)
                .unwrap_or(0);
            let unit = units.get(k).copied().unwrap_or(0);
            CouplingStart {
                line: c.line,
                synchronised: c.synchronised,
                unit,
                half_pitch_rad: half.get(unit).copied().unwrap_or(0.0),
            }
        });
        if let Some(c) = coupling {
            last_coupling = Some(c.line);
        }
        let n = pieces.len() as f64;
        for piece in pieces {
            // A coupling starts at the move's first piece only.
            starts.push(start.take());
            segments.push(Segment {
                line: m.line,
                t0_s: t,
                t1_s: t + dt / n,
                from: pos,
                to: piece,
                eta_rad: ((state.swivel_prog_deg - st.swivel_offset_deg) / st.swivel_sign)
                    .to_radians(),
                hob_rev_s: st.hob_sign * state.dir * state.rpm / 60.0,
                gearbox,
                c_extra_rad: st.table_sign * m.c_correction_deg.unwrap_or(0.0).to_radians() / n,
                feed,
            });
            t += dt / n;
            pos = piece;
        }
    }
    Ok(Timeline::build(segments, &starts)?.with_errors(errors))
}

/// How far the chords an arc is followed by may stand off it, mm.
pub const ARC_SAGITTA_MM: f64 = 1e-5;

/// The end points of the straight pieces a move from `from` to `to` is
/// followed by: `to` alone for a line, and for an arc the points at equal
/// steps of its angle, each chord within [`ARC_SAGITTA_MM`] of the circle
/// (a chord over the angle δ of a circle of radius r stands r·(1 − cos δ/2)
/// off it at its middle), Y moving linearly with the angle, the last point
/// `to` exactly.
fn arc_pieces(from: Axes, to: Axes, arc: Option<&gearcam_nc::TraceArc>) -> Vec<Axes> {
    let Some(a) = arc else {
        return vec![to];
    };
    let r = (from.z_mm - a.centre_z_mm).hypot(from.x_mm - a.centre_x_mm);
    if r <= ARC_SAGITTA_MM || a.sweep_rad == 0.0 {
        return vec![to];
    }
    let step = 2.0 * (1.0 - ARC_SAGITTA_MM / r).acos();
    let n = (a.sweep_rad.abs() / step).ceil().clamp(1.0, 1e6) as usize;
    let t0 = (from.x_mm - a.centre_x_mm).atan2(from.z_mm - a.centre_z_mm);
    let mut out: Vec<Axes> = (1..n)
        .map(|i| {
            let f = i as f64 / n as f64;
            let t = t0 + a.sweep_rad * f;
            Axes {
                x_mm: a.centre_x_mm + r * t.sin(),
                y_mm: from.y_mm + (to.y_mm - from.y_mm) * f,
                z_mm: a.centre_z_mm + r * t.cos(),
            }
        })
        .collect();
    out.push(to);
    out
}

/// A coupling of the trace as the neutral-frame gearbox.
fn gearbox_of(
    c: &gearcam_nc::TraceCoupling,
    st: &gearcam_proto::MachineSettings,
) -> Result<Gearbox, SimError> {
    if c.den == 0 {
        return Err(SimError::BadRatio(c.line));
    }
    let ratio = c.num as f64 / c.den as f64;
    Ok(Gearbox {
        c_per_b: st.table_sign * st.hob_sign * ratio,
        c_per_z_rad_mm: st.table_sign * c.c_per_z_deg_per_mm.unwrap_or(0.0).to_radians(),
        c_per_y_rad_mm: st.table_sign
            * st.shift_sign
            * c.c_per_y_deg_per_mm.unwrap_or(0.0).to_radians(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(t0: f64, t1: f64, z0: f64, z1: f64, g: Option<Gearbox>) -> Segment {
        Segment {
            line: 0,
            t0_s: t0,
            t1_s: t1,
            from: Axes {
                x_mm: 50.0,
                y_mm: 0.0,
                z_mm: z0,
            },
            to: Axes {
                x_mm: 50.0,
                y_mm: 0.0,
                z_mm: z1,
            },
            eta_rad: 0.0,
            hob_rev_s: 2.0,
            gearbox: g,
            c_extra_rad: 0.0,
            feed: true,
        }
    }

    #[test]
    fn a_coupled_move_turns_the_table_by_the_ratio_and_the_differential() {
        let g = Gearbox {
            c_per_b: 0.04,
            c_per_z_rad_mm: 0.01,
            c_per_y_rad_mm: 0.0,
        };
        let tl = Timeline::from_segments(vec![
            seg(0.0, 1.0, 10.0, 10.0, None),
            seg(1.0, 3.0, 10.0, 6.0, Some(g)),
        ])
        .unwrap();
        let end = tl.pose(3.0);
        // Decoupled first second: the hob turns 2 turns, the table stands.
        let mid = tl.pose(1.0);
        assert!((mid.b_rad - 2.0 * TAU).abs() < 1e-12 && mid.c_rad.abs() < 1e-12);
        // Coupled: 4 more hob turns give 0.16 table turns; Z falls 4 mm.
        let want_c = 0.04 * 4.0 * TAU + 0.01 * -4.0;
        assert!(
            (end.c_rad - want_c).abs() < 1e-12,
            "{} vs {want_c}",
            end.c_rad
        );
        assert!((end.axes.z_mm - 6.0).abs() < 1e-12);
    }
}
