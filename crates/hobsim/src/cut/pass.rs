//! One gash pass through the sections.
//!
//! While the gash sweeps the blank, every point of its edge's outer profile
//! (axial position a, radius ρ(a)) pierces a section plane once, on the
//! gear's side of the hob axis, at the hob angle φ where it meets the plane:
//! ρ·sin φ = t(φ), t the plane's distance from the hob centre's disc at a
//! along w. The points where the profile pierces the plane, each posed at
//! its own instant, form the curve that bounds what the pass removes from
//! the section on the gear's side; the rest of the swept region lies
//! further out. So a pass lowers the outline to that curve (sampled along a
//! and refined until its straight pieces stay within the tolerance) and to
//! the chords of the profile's first and last points where the curve ends
//! inside the blank (the hob's end faces). `docs/simulation.md` §3 derives
//! this.

use super::plane::{off_line, polar_angle, s_range, Point};
use super::window::{meets_slopes, window_slopes, AngleBound, PoseBounds, StepReach};
use super::{clear_of, raster, Resolution};
use crate::hob::{Edge, Hob};
use crate::kinematics::{Axes, MachineErrors, Pose, Timeline};

/// 1/6, a multiplication where a division would be slower.
const SIX: f64 = 1.0 / 6.0;

/// The tolerance on the rounded tip corners, in times the resolution's:
/// they cut only the root fillet, below the range over which the profile is
/// evaluated, and most of a fine run's points were spent on them.
const CORNER_TOLERANCE: f64 = 10.0;

/// Deepest halving of a step of the initial grid along the hob.
const MAX_DEPTH: u32 = 18;

/// A gash pass: the pose at hob angle φ is the timeline's at the pass time
/// plus φ/ω. Within the move the nominal axes, B and C are linear in time,
/// so in φ; beyond its ends the pose is the neighbouring move's (a pass
/// near the end of a short move, such as a piece of an arc, sweeps the
/// blank partly during the next), found at the pass time plus φ/ω: right
/// while the hob's speed does not change between the moves.
pub(super) struct Pass<'t> {
    timeline: &'t Timeline,
    /// The pass time, s, and the hob's angular speed, rad/s.
    t: f64,
    omega: f64,
    /// The nominal pose at φ = 0.
    p0: Pose,
    /// X, Y, Z and C per radian of hob turn, nominal.
    d: [f64; 4],
    /// The hob angles at the move's start and end, in order.
    phi_range: (f64, f64),
    /// The what-if errors, when there are any.
    errors: Option<MachineErrors>,
    /// The pose at φ = 0 (errors applied).
    q0: Pose,
    /// dt/dφ of the nominal pose: how the section's distance from a disc's
    /// centre moves as the hob turns.
    dt: f64,
    /// Half the hob angle over which the gash can be inside the blank.
    phi_max: f64,
    /// sin and cos of the table angle at φ = 0.
    sc0: (f64, f64),
    /// sin and cos of the pass's swivel (with the what-if offset).
    se: f64,
    ce: f64,
    /// The hob's tip and root radii, mm.
    tip: f64,
    root: f64,
    edge: Edge,
    /// 1/cos η.
    inv_ce: f64,
    res: Resolution,
    /// Where the hob can be over the pass's hob turn, when the pass cuts
    /// sections within windows ([`Pass::windowed`]).
    bounds: Option<PoseBounds>,
}

/// What a pierce point was solved from: the profile point (a, ρ), the hob
/// angle φ, the distance t of the section from the disc's centre and the
/// chord parameter s = √(ρ² − t²), the sine and cosine of the table angle,
/// and the point.
#[derive(Clone, Copy)]
struct Pierced {
    a: f64,
    rho: f64,
    phi: f64,
    tt: f64,
    s: f64,
    /// sin and cos of the table angle the point was posed at.
    table: (f64, f64),
    point: Point,
}

/// Added to the tangent bound of a step before it is left out, mm: the
/// rounding of the tangents and the pose's second-order terms, far below
/// any tolerance.
const BULGE_SLACK_MM: f64 = 1e-7;

impl<'t> Pass<'t> {
    /// The pass of gash `k` at time `t` of segment `seg`.
    pub(super) fn new(
        timeline: &'t Timeline,
        seg: usize,
        t: f64,
        hob: &Hob,
        k: u32,
        outer_radius_mm: f64,
        res: Resolution,
    ) -> Pass<'t> {
        let s = &timeline.segments()[seg];
        let omega = std::f64::consts::TAU * s.hob_rev_s;
        let p0 = timeline.nominal_pose_in(seg, t);
        let dt = s.t1_s - s.t0_s;
        let c0 = timeline.nominal_pose_in(seg, s.t0_s).c_rad;
        let c1 = timeline.nominal_pose_in(seg, s.t1_s).c_rad;
        let per_phi = |a: f64, b: f64| (b - a) / (dt * omega);
        let d = [
            per_phi(s.from.x_mm, s.to.x_mm),
            per_phi(s.from.y_mm, s.to.y_mm),
            per_phi(s.from.z_mm, s.to.z_mm),
            per_phi(c0, c1),
        ];
        let (f0, f1) = (omega * (s.t0_s - t), omega * (s.t1_s - t));
        let errors = timeline.errors();
        let posed = errors.apply(p0);
        let errors = (!errors.is_zero()).then_some(errors);
        let cos_lim = ((posed.axes.x_mm - outer_radius_mm) / hob.tip_radius_mm).clamp(-1.0, 1.0);
        let (se, ce) = posed.eta_rad.sin_cos();
        Pass {
            timeline,
            t,
            omega,
            p0,
            d,
            phi_range: (f0.min(f1), f0.max(f1)),
            errors,
            q0: posed,
            sc0: posed.c_rad.sin_cos(),
            dt: (d[1] * se - d[2]) / ce,
            phi_max: (cos_lim.acos() + 0.02).min(std::f64::consts::PI),
            se,
            ce,
            tip: hob.tip_radius_mm,
            root: hob.root_radius_mm,
            edge: hob.edge(k),
            inv_ce: 1.0 / ce,
            res,
            bounds: None,
        }
    }

    /// The pass made ready to cut sections within angular windows: the
    /// bounds of its pose over its hob turn ([`PoseBounds::around`]).
    pub(super) fn windowed(mut self) -> Self {
        self.bounds = Some(PoseBounds::around(
            self.timeline,
            self.t,
            self.omega,
            (self.se, self.ce),
        ));
        self
    }

    /// The pose at hob angle `phi`.
    #[inline]
    fn pose(&self, phi: f64) -> Pose {
        if phi < self.phi_range.0 || phi > self.phi_range.1 {
            let nominal = self.timeline.nominal_pose(self.t + phi / self.omega);
            return match &self.errors {
                Some(e) => e.apply(nominal),
                None => nominal,
            };
        }
        let f = phi;
        let p = &self.p0;
        let nominal = Pose {
            axes: Axes {
                x_mm: p.axes.x_mm + self.d[0] * f,
                y_mm: p.axes.y_mm + self.d[1] * f,
                z_mm: p.axes.z_mm + self.d[2] * f,
            },
            eta_rad: p.eta_rad,
            b_rad: p.b_rad + f,
            c_rad: p.c_rad + self.d[3] * f,
        };
        match &self.errors {
            Some(e) => e.apply(nominal),
            None => nominal,
        }
    }

    /// t: the distance along w of the section `zs` from the centre of the
    /// hob's disc at axial position `a`, with the hob at pose `q`.
    fn across(&self, q: &Pose, a: f64, zs: f64) -> f64 {
        (zs - q.axes.z_mm + (q.axes.y_mm + a) * self.se) * self.inv_ce
    }

    /// The machine point at chord parameter `s` (along e1, towards the gear
    /// axis) and height `tt` of the disc at `a`, turned into the workpiece.
    /// Its polar angle is found from `near`'s, a point close by, when
    /// there is one ([`polar_angle`]).
    fn to_workpiece(&self, q: &Pose, a: f64, s: f64, tt: f64, near: Option<&Point>) -> Point {
        self.turned(q, a, s, tt, near).0
    }

    /// [`Pass::to_workpiece`] with the sine and cosine of the table angle
    /// it was turned by.
    #[inline]
    fn turned(
        &self,
        q: &Pose,
        a: f64,
        s: f64,
        tt: f64,
        near: Option<&Point>,
    ) -> (Point, (f64, f64)) {
        let (x, y) = (q.axes.x_mm - s, (q.axes.y_mm + a) * self.ce + tt * self.se);
        let (sc, cc) = self.table_sin_cos(q.c_rad);
        let (u, v) = (x * cc - y * sc, x * sc + y * cc);
        ([u, v, polar_angle(u, v, near)], (sc, cc))
    }

    /// sin and cos of the table angle `c`: the angle at φ = 0 turned on by
    /// the small difference (Taylor's series to the ninth power leaves
    /// below 10⁻¹³ rad within 0.3 rad), or directly beyond.
    #[inline]
    fn table_sin_cos(&self, c: f64) -> (f64, f64) {
        let d = c - self.q0.c_rad;
        if d.abs() > 0.3 {
            return c.sin_cos();
        }
        let d2 = d * d;
        let sd = d
            * (1.0
                - d2 * SIX
                    * (1.0
                        - d2 * (1.0 / 20.0)
                            * (1.0 - d2 * (1.0 / 42.0) * (1.0 - d2 * (1.0 / 72.0)))));
        let cd = 1.0
            - d2 * 0.5
                * (1.0
                    - d2 * (1.0 / 12.0)
                        * (1.0
                            - d2 * (1.0 / 30.0)
                                * (1.0 - d2 * (1.0 / 56.0) * (1.0 - d2 * (1.0 / 90.0)))));
        let (s0, c0) = self.sc0;
        (s0 * cd + c0 * sd, c0 * cd - s0 * sd)
    }

    /// Where the profile point (a, ρ) pierces the section `zs` on the
    /// gear's side, or None when the plane misses its circle. The hob angle
    /// solves ρ·sin φ = t(φ) by Newton's method from asin(t(0)/ρ) (t moves
    /// with Z and Y by micrometres per radian, so two steps leave far less
    /// than 10⁻¹² rad); the point is then placed exactly on the plane and on
    /// the profile with the pose at that angle.
    fn pierce(&self, a: f64, rho: f64, zs: f64, near: Option<&Point>) -> Option<Point> {
        self.pierce_at(a, rho, zs, near).map(|p| p.point)
    }

    /// [`Pass::pierce`] with the geometry of the solution, for its tangent.
    fn pierce_at(&self, a: f64, rho: f64, zs: f64, near: Option<&Point>) -> Option<Pierced> {
        if rho <= 0.0 {
            return None;
        }
        let tt0 = self.across(&self.q0, a, zs);
        if tt0.abs() >= rho {
            return None;
        }
        let mut sn = tt0 / rho;
        let mut cs = (1.0 - sn * sn).sqrt();
        let mut phi = sn.asin();
        // Within the move on the ideal machine t is linear in φ,
        // t(φ) = t(0) + ∂t/∂φ·φ, so the first Newton step needs no pose.
        // After a step below 10⁻⁴ rad the angle is within tan φ/2 times its
        // square, 10⁻⁸ rad; the point is then placed exactly on the plane
        // and the profile with the pose at that angle, so the angle's error
        // only poses it that much early, r·(C/B)·10⁻⁸: 10⁻⁸ mm.
        if self.errors.is_none() {
            let step = (rho * sn - tt0 - self.dt * phi) / (rho * cs - self.dt);
            let next = phi - step;
            if step.abs() < 1e-4 && next >= self.phi_range.0 && next <= self.phi_range.1 {
                return self.placed(a, rho, zs, next, near);
            }
        }
        for _ in 0..3 {
            let tt = self.across(&self.pose(phi), a, zs);
            let step = (rho * sn - tt) / (rho * cs - self.dt);
            if !step.is_finite() {
                return None;
            }
            phi -= step;
            // sin and cos of φ − step, by a rotation (Taylor's series for
            // the small steps Newton takes here).
            let (sd, cd) = if step.abs() < 1e-3 {
                let s2 = step * step;
                (
                    step * (1.0 - s2 * SIX),
                    1.0 - s2 * 0.5 + s2 * s2 * (1.0 / 24.0),
                )
            } else {
                step.sin_cos()
            };
            (sn, cs) = (sn * cd - cs * sd, cs * cd + sn * sd);
            // Newton's error squares each step (times tan φ/2): after a
            // step below 10⁻⁷ rad the next would be below 10⁻¹⁴.
            if step.abs() < 1e-7 {
                break;
            }
        }
        self.placed(a, rho, zs, phi, near)
    }

    /// The profile point (a, ρ) placed exactly on the section `zs` and on
    /// its disc with the pose at hob angle `phi`, or None when the plane
    /// misses the disc there.
    fn placed(&self, a: f64, rho: f64, zs: f64, phi: f64, near: Option<&Point>) -> Option<Pierced> {
        // The pierce point on the gear's side has |φ| < π/2; Newton's
        // steps from near a grazing start can run on towards the far root.
        if phi.abs() >= std::f64::consts::FRAC_PI_2 {
            return None;
        }
        let q = self.pose(phi);
        let tt = self.across(&q, a, zs);
        if tt.abs() >= rho {
            return None;
        }
        let s = (rho * rho - tt * tt).sqrt();
        let turned = self.turned(&q, a, s, tt, near);
        Some(Pierced {
            a,
            rho,
            phi,
            tt,
            s,
            table: turned.1,
            point: turned.0,
        })
    }

    /// The direction d(u, v)/da in which the pierce point `p` moves as the
    /// profile point moves along the hob on the side `dir` (+1 or −1; the
    /// profile's slope is that side's), by differentiating ρ(a)·sin φ =
    /// t(a, φ) (dφ/da = (∂t/∂a − ρ′·sin φ)/(ρ·cos φ − ∂t/∂φ)), the chord
    /// parameter s = √(ρ² − t²), the machine point (X − s, (Y + a)·cos η +
    /// t·sin η) and the table's turn. None where the pose is not linear in
    /// φ (what-if errors, beyond the move) or the point grazes its disc.
    fn tangent(&self, p: &Pierced, dir: f64) -> Option<[f64; 2]> {
        if self.errors.is_some()
            || p.phi < self.phi_range.0
            || p.phi > self.phi_range.1
            || p.s <= 1e-6 * p.rho
        {
            return None;
        }
        let drho = self.edge.slope(p.a, dir);
        let (sn, cs) = (p.tt / p.rho, p.s / p.rho);
        let t_a = self.se * self.inv_ce;
        let dphi = (t_a - drho * sn) / (p.rho * cs - self.dt);
        let dt = t_a + self.dt * dphi;
        let ds = (p.rho * drho - p.tt * dt) / p.s;
        let dx = self.d[0] * dphi - ds;
        let dy = (self.d[1] * dphi + 1.0) * self.ce + self.se * dt;
        let dc = self.d[3] * dphi;
        let (sc, cc) = p.table;
        let [u, v, _] = p.point;
        let out = [dx * cc - dy * sc - dc * v, dx * sc + dy * cc + dc * u];
        out.iter().all(|x| x.is_finite()).then_some(out)
    }

    /// How far the curve between the pierce points `p0` and `p1` can stand
    /// off their chord, from the tangents at both ends: a curve that turns
    /// one way by less than half a turn lies in the triangle of its chord
    /// and its end tangents, within the triangle's height of the chord.
    /// None when the tangents do not make such a triangle (the curve may
    /// turn both ways, or the pose is not linear): then only a midpoint
    /// tells.
    fn bulge(&self, p0: &Pierced, p1: &Pierced) -> Option<f64> {
        let t0 = self.tangent(p0, 1.0)?;
        let t1 = self.tangent(p1, -1.0)?;
        let chord = [p1.point[0] - p0.point[0], p1.point[1] - p0.point[1]];
        let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
        let den = cross(t0, t1);
        let len = (chord[0] * chord[0] + chord[1] * chord[1]).sqrt();
        if den == 0.0 || len == 0.0 {
            return None;
        }
        // Where the tangents meet: p0 + λ·t0 = p1 − μ·t1.
        let lambda = cross(chord, t1) / den;
        let mu = cross(t0, chord) / den;
        if !(lambda > 0.0 && mu > 0.0) {
            return None;
        }
        Some(lambda * cross(chord, t0).abs() / len)
    }

    /// The point at chord parameter `s` of the disc at `a` in the section
    /// `zs`, posed at its own hob angle atan2(t, s).
    fn chord_point(&self, a: f64, s: f64, zs: f64) -> Point {
        let mut phi = 0.0;
        for _ in 0..3 {
            phi = self.across(&self.pose(phi), a, zs).atan2(s);
        }
        let q = self.pose(phi);
        let tt = self.across(&q, a, zs);
        self.to_workpiece(&q, a, s, tt, None)
    }

    /// How deep the hob's tip cylinder reaches towards the gear axis in the
    /// section `zs` at φ = 0, along the machine's x axis: X less the half
    /// chord of the tip circle whose plane (across the hob axis) meets the
    /// section there, t = (z_s − Z)·cos η from the hob axis (infinite where
    /// it misses). Only an order for the passes.
    pub(super) fn depth_in(&self, zs: f64) -> f64 {
        let t = (zs - self.q0.axes.z_mm) * self.ce;
        let h2 = self.tip * self.tip - t * t;
        if h2 <= 0.0 {
            return f64::INFINITY;
        }
        self.q0.axes.x_mm - h2.sqrt()
    }

    /// Cuts the outline `r` of the section `zs` where the pass can reach it
    /// (within `clip_r` of the gear axis), only where it can change the
    /// outline within `windows` when there are any (the pass made
    /// [`Pass::windowed`]). `skip_clear`: leave out the pieces that stand
    /// clear of the outline ([`Pass::refine`]).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn cut(
        &self,
        zs: f64,
        clip_r: f64,
        (r, blocks): (&mut [f64], &[f64]),
        dirs: &[(f64, f64)],
        (skip_clear, windows): (bool, Option<&[(f64, f64)]>),
        scratch: &mut Scratch,
    ) {
        let Some((a_min, a_max)) = self.reach(clip_r, zs) else {
            return;
        };
        let bound = match (windows, &self.bounds) {
            (Some(w), Some(pose)) => AngleBound::new(
                pose,
                (zs, clip_r),
                (self.root, self.tip),
                (self.q0.axes.x_mm, (a_min, a_max)),
                (self.se, self.ce),
            )
            .map(|b| (w, b)),
            _ => None,
        };
        let Scratch {
            knots,
            grid,
            wanted,
            rho,
            miss,
            slopes,
        } = scratch;
        if let Some((w, b)) = &bound {
            window_slopes(w, b.c_mid, slopes);
        }
        let meets_windows = |reach: StepReach| match reach {
            StepReach::Anywhere => true,
            StepReach::Nowhere => false,
            StepReach::Within(lo, hi) => meets_slopes(slopes, lo, hi),
        };
        if let Some((_, b)) = &bound {
            if !meets_windows(b.of_step((a_min, a_max), (0.0, self.tip), true)) {
                return;
            }
        }
        self.edge.knots_into(a_min, a_max, knots);
        grid.clear();
        for w in knots.windows(2) {
            let n = ((w[1] - w[0]) / self.res.axial_step_mm).ceil().max(1.0) as usize;
            grid.extend((0..n).map(|q| w[0] + (w[1] - w[0]) * q as f64 / n as f64));
        }
        grid.extend(knots.last());
        wanted.clear();
        if let Some((_, b)) = &bound {
            // Whether each step can change the outline within the windows;
            // a step may cut an end chord at a grid point next to one where
            // the plane may miss the profile, or at the grid's ends.
            rho.clear();
            rho.extend(grid.iter().map(|&a| self.edge.radius(a)));
            miss.clear();
            // (A Newton step that cannot be taken misses too: the hob moving
            // across the section as fast as a point of it turns.)
            let creep = self.dt.abs() * 100.0;
            miss.extend(
                grid.iter()
                    .zip(rho.iter())
                    .map(|(&a, &r)| b.may_miss(a, r) || creep >= r),
            );
            let n = grid.len();
            let chord_at =
                |k: usize| k == 0 || k + 1 == n || miss[k - 1] || miss.get(k + 1) == Some(&true);
            wanted.extend((0..n.saturating_sub(1)).map(|j| {
                let chord = chord_at(j) || chord_at(j + 1);
                let reach = b.of_step((grid[j], grid[j + 1]), (rho[j], rho[j + 1]), chord);
                meets_windows(reach)
            }));
        }
        let section = Section {
            zs,
            clip_r,
            r,
            blocks,
            dirs,
            skip_clear,
        };
        let wanted = bound
            .is_some()
            .then_some((wanted.as_slice(), miss.as_slice()));
        self.trace(grid, wanted, section);
    }

    /// The pass's curve in one section from the pierce points of the
    /// profile points at `grid` (refined between them), in runs where the
    /// plane meets the profile; each run's first and last discs also cut
    /// their chords (the hob's end faces where it ends inside the blank).
    /// A step between two grid points is left out, without its midpoint,
    /// when the curve stands clear of the outline by its chord and the
    /// bound [`Pass::bulge`] gives.
    ///
    /// `wanted`, when given, holds per step (grid point j to j + 1) whether
    /// it can change the outline within the section's windows, and per
    /// grid point whether the plane may miss the profile there; steps not
    /// wanted are not traced. A grid point is pierced when a step from it
    /// is wanted, or when the plane may miss it and a wanted step starts or
    /// ends next to it: then whether a run of the curve ends there (an end
    /// chord next to a wanted step, which may fall in a window) is known.
    /// A grid point left untraced where the plane surely meets the profile
    /// ends no run, so no end chord is cut next to it; one where it may
    /// miss is left untraced only with no wanted step within two, so no
    /// chord it would end can fall in a window.
    fn trace(&self, grid: &[f64], wanted: Option<(&[bool], &[bool])>, mut sec: Section) {
        let want = |k: usize| wanted.is_none_or(|(w, _)| w.get(k).copied().unwrap_or(false));
        let miss = |j: usize| wanted.is_some_and(|(_, m)| m[j]);
        let needed = |j: usize| {
            wanted.is_none()
                || (j >= 1 && want(j - 1))
                || want(j)
                || (miss(j) && ((j >= 2 && want(j - 2)) || want(j + 1)))
        };
        let mut last: Option<Pierced> = None;
        // Whether the grid point before was pierced (not left untraced).
        let mut traced = false;
        for (j, &a) in grid.iter().enumerate() {
            if !needed(j) {
                (last, traced) = (None, false);
                continue;
            }
            let rho = self.edge.radius(a);
            match (
                self.pierce_at(a, rho, sec.zs, last.as_ref().map(|l| &l.point)),
                last,
            ) {
                (Some(p), None) => {
                    if j == 0 || traced {
                        self.end_chord(a, rho, &mut sec);
                    }
                    last = Some(p);
                }
                (Some(p), Some(from)) => {
                    let clear = !want(j - 1)
                        || sec.skip_clear
                            && self.bulge(&from, &p).is_some_and(|b| {
                                clear_of(
                                    (sec.r, sec.blocks),
                                    sec.dirs,
                                    from.point,
                                    p.point,
                                    b + BULGE_SLACK_MM,
                                )
                            });
                    if !clear {
                        self.refine(
                            (from.a, from.point),
                            (a, p.point),
                            &mut sec,
                            MAX_DEPTH,
                            None,
                        );
                    }
                    last = Some(p);
                }
                (None, Some(from)) => {
                    self.end_chord(from.a, from.rho, &mut sec);
                    last = None;
                }
                (None, None) => {}
            }
            traced = true;
        }
        if let Some(from) = last {
            self.end_chord(from.a, from.rho, &mut sec);
        }
    }

    /// Cuts the curve between the pierce points `from` and `to`: halves the
    /// step until the curve's midpoint lies within four times the tolerance
    /// of the straight piece (the two halves, which are cut, then stay
    /// within about the tolerance). A half is left out when it stands
    /// further out than the outline, on every ray it crosses, by more than
    /// its parent's midpoint offset `margin` (its own curve stands off it by
    /// about a quarter of that): the pass cannot cut there.
    fn refine(
        &self,
        (a0, p0): (f64, Point),
        (a1, p1): (f64, Point),
        sec: &mut Section,
        depth: u32,
        margin: Option<f64>,
    ) {
        if sec.skip_clear
            && margin.is_some_and(|m| clear_of((sec.r, sec.blocks), sec.dirs, p0, p1, m))
        {
            return;
        }
        let am = 0.5 * (a0 + a1);
        let Some(pm) = self.pierce(am, self.edge.radius(am), sec.zs, Some(&p0)) else {
            raster(sec.r, sec.dirs, p0, p1);
            return;
        };
        let dev = off_line(p0, p1, pm);
        let tol = if self.edge.on_corner(am) {
            CORNER_TOLERANCE * self.res.tolerance_mm
        } else {
            self.res.tolerance_mm
        };
        if depth == 0 || dev <= 4.0 * tol {
            raster(sec.r, sec.dirs, p0, pm);
            raster(sec.r, sec.dirs, pm, p1);
            return;
        }
        self.refine((a0, p0), (am, pm), sec, depth - 1, Some(dev));
        self.refine((am, pm), (a1, p1), sec, depth - 1, Some(dev));
    }

    /// Cuts the chord of the disc at `a` (radius `rho`) in the section over
    /// the hob angles the pass sweeps inside the blank, as points posed at
    /// their own instants, pieces within the tolerance of the swept curve.
    fn end_chord(&self, a: f64, rho: f64, sec: &mut Section) {
        let q = &self.q0;
        let tt = self.across(q, a, sec.zs);
        if rho <= 0.0 || tt.abs() >= rho {
            return;
        }
        let big_s = (rho * rho - tt * tt).sqrt();
        let Some((s_lo, s_hi)) = s_range(tt, -self.phi_max, self.phi_max, big_s) else {
            return;
        };
        // Machine points (X − s, y): within clip_r of the gear axis.
        let y = (q.axes.y_mm + a) * self.ce + tt * self.se;
        let h2 = sec.clip_r * sec.clip_r - y * y;
        if h2 <= 0.0 {
            return;
        }
        let h = h2.sqrt();
        let (s_lo, s_hi) = (s_lo.max(q.axes.x_mm - h), s_hi.min(q.axes.x_mm + h));
        if s_lo >= s_hi {
            return;
        }
        // A straight piece between two exactly posed points departs from the
        // swept curve by about δ·L/4 (δ the table's turn across it, L its
        // length); at least eight pieces over the pass.
        let dphi = (tt.atan2(s_hi) - tt.atan2(s_lo)).abs();
        let err = (self.d[3] * dphi).abs() * (s_hi - s_lo) / 4.0;
        let m = ((dphi / (self.phi_max / 4.0)).ceil())
            .max((err / self.res.tolerance_mm).sqrt().ceil())
            .clamp(1.0, 4096.0) as usize;
        let mut prev = self.chord_point(a, s_hi, sec.zs);
        for i in 1..=m {
            let s = s_hi + (s_lo - s_hi) * i as f64 / m as f64;
            let p = self.chord_point(a, s, sec.zs);
            raster(sec.r, sec.dirs, prev, p);
            prev = p;
        }
    }
}

/// Buffers a pass's cut of a section fills, kept between passes: the knots
/// along the hob, the grid of profile points, whether each step of the grid
/// is wanted and what decides it.
#[derive(Default)]
pub(super) struct Scratch {
    knots: Vec<f64>,
    grid: Vec<f64>,
    wanted: Vec<bool>,
    /// The profile's radius at each grid point, and whether the section's
    /// plane may miss its disc there.
    rho: Vec<f64>,
    miss: Vec<bool>,
    /// The windows as slopes seen from the pass's table angle.
    slopes: Vec<(f64, f64)>,
}

/// One section as a pass cuts it.
struct Section<'r> {
    zs: f64,
    clip_r: f64,
    r: &'r mut [f64],
    /// Upper bounds of r over its blocks of rays (`clear_of`).
    blocks: &'r [f64],
    dirs: &'r [(f64, f64)],
    skip_clear: bool,
}

mod reach;
#[cfg(test)]
mod tests;
