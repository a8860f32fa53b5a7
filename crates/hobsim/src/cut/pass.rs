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

use super::{raster, raster_between, Blank, Resolution, CLIP_MARGIN_MM};
use crate::hob::Hob;
use crate::kinematics::{Axes, MachineErrors, Pose, Timeline};

/// Deepest halving of a step of the initial grid along the hob.
const MAX_DEPTH: u32 = 18;

/// A gash pass: the pose at hob angle φ is the move's at the pass time plus
/// φ/ω. Within the move the nominal axes, B and C are linear in time, so in
/// φ; outside it they stand (as [`Timeline::nominal_pose_in`] holds them).
pub(super) struct Pass<'a> {
    /// The nominal pose at φ = 0.
    p0: Pose,
    /// X, Y, Z and C per radian of hob turn, nominal.
    d: [f64; 4],
    /// The hob angles at the move's start and end, in order.
    phi_range: (f64, f64),
    errors: MachineErrors,
    /// Half the hob angle over which the gash can be inside the blank.
    phi_max: f64,
    /// sin and cos of the pass's swivel (with the what-if offset).
    se: f64,
    ce: f64,
    hob: &'a Hob,
    k: u32,
    res: Resolution,
}

/// A pierce point: the workpiece point and the hob angle it was posed at.
type Point = [f64; 2];

impl<'a> Pass<'a> {
    /// The pass of gash `k` at time `t` of segment `seg`.
    pub(super) fn new(
        timeline: &Timeline,
        seg: usize,
        t: f64,
        hob: &'a Hob,
        k: u32,
        outer_radius_mm: f64,
        res: Resolution,
    ) -> Pass<'a> {
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
        let cos_lim = ((posed.axes.x_mm - outer_radius_mm) / hob.tip_radius_mm).clamp(-1.0, 1.0);
        let (se, ce) = posed.eta_rad.sin_cos();
        Pass {
            p0,
            d,
            phi_range: (f0.min(f1), f0.max(f1)),
            errors,
            phi_max: (cos_lim.acos() + 0.02).min(std::f64::consts::PI),
            se,
            ce,
            hob,
            k,
            res,
        }
    }

    /// The pose at hob angle `phi`.
    fn pose(&self, phi: f64) -> Pose {
        let f = phi.clamp(self.phi_range.0, self.phi_range.1);
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
        self.errors.apply(nominal)
    }

    /// t: the distance along w of the section `zs` from the centre of the
    /// hob's disc at axial position `a`, with the hob at pose `q`.
    fn across(&self, q: &Pose, a: f64, zs: f64) -> f64 {
        (zs - q.axes.z_mm + (q.axes.y_mm + a) * self.se) / self.ce
    }

    /// The machine point at chord parameter `s` (along e1, towards the gear
    /// axis) and height `tt` of the disc at `a`, turned into the workpiece.
    fn to_workpiece(&self, q: &Pose, a: f64, s: f64, tt: f64) -> Point {
        let (x, y) = (q.axes.x_mm - s, (q.axes.y_mm + a) * self.ce + tt * self.se);
        let (sc, cc) = q.c_rad.sin_cos();
        [x * cc - y * sc, x * sc + y * cc]
    }

    /// Where the profile point (a, ρ) pierces the section `zs` on the
    /// gear's side, or None when the plane misses its circle. The hob angle
    /// solves ρ·sin φ = t(φ) by Newton's method from asin(t(0)/ρ) (t moves
    /// with Z and Y by micrometres per radian, so two steps leave far less
    /// than 10⁻¹² rad); the point is then placed exactly on the plane and on
    /// the profile with the pose at that angle.
    fn pierce(&self, a: f64, rho: f64, zs: f64) -> Option<Point> {
        if rho <= 0.0 {
            return None;
        }
        let dt = (self.d[1] * self.se - self.d[2]) / self.ce;
        let tt0 = self.across(&self.pose(0.0), a, zs);
        if tt0.abs() >= rho {
            return None;
        }
        let mut phi = (tt0 / rho).asin();
        for _ in 0..3 {
            let tt = self.across(&self.pose(phi), a, zs);
            let (sn, cs) = phi.sin_cos();
            let step = (rho * sn - tt) / (rho * cs - dt);
            if !step.is_finite() {
                return None;
            }
            phi -= step;
            if step.abs() < 1e-13 {
                break;
            }
        }
        let q = self.pose(phi);
        let tt = self.across(&q, a, zs);
        if tt.abs() >= rho {
            return None;
        }
        let s = (rho * rho - tt * tt).sqrt();
        Some(self.to_workpiece(&q, a, s, tt))
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
        self.to_workpiece(&q, a, s, tt)
    }

    /// Cuts every section of `blank` the pass can reach.
    pub(super) fn cut(&self, blank: &mut Blank, dirs: &[(f64, f64)], buf: &mut Vec<Point>) {
        let big_r = blank.outer_radius_mm;
        let clip_r = big_r + CLIP_MARGIN_MM;
        for j in 0..blank.z_mm.len() {
            let zs = blank.z_mm[j];
            let Some((a_min, a_max)) = self.reach(clip_r, zs) else {
                continue;
            };
            let knots = self.hob.knots(self.k, a_min, a_max);
            let r = &mut blank.r_mm[j];
            let mut grid = Vec::with_capacity(64);
            for w in knots.windows(2) {
                let n = ((w[1] - w[0]) / self.res.axial_step_mm).ceil().max(1.0) as usize;
                grid.extend((0..n).map(|q| w[0] + (w[1] - w[0]) * q as f64 / n as f64));
            }
            grid.extend(knots.last());
            let mut run = false;
            let mut last = (0.0, [0.0; 2]);
            buf.clear();
            for a in grid {
                let rho = self.hob.outer_radius(self.k, a);
                match (self.pierce(a, rho, zs), run) {
                    (Some(p), false) => {
                        self.end_chord(a, rho, zs, clip_r, r, dirs, big_r);
                        buf.push(p);
                        run = true;
                        last = (a, p);
                    }
                    (Some(p), true) => {
                        self.refine(last, (a, p), zs, big_r, MAX_DEPTH, buf);
                        last = (a, p);
                    }
                    (None, true) => {
                        self.close(last.0, zs, clip_r, r, dirs, big_r, buf);
                        run = false;
                    }
                    (None, false) => {}
                }
            }
            if run {
                self.close(last.0, zs, clip_r, r, dirs, big_r, buf);
            }
        }
    }

    /// Ends a run of pierce points at `a`: cuts the curve and the chord of
    /// the run's last disc.
    #[allow(clippy::too_many_arguments)]
    fn close(
        &self,
        a: f64,
        zs: f64,
        clip_r: f64,
        r: &mut [f64],
        dirs: &[(f64, f64)],
        big_r: f64,
        buf: &mut Vec<Point>,
    ) {
        raster_polyline(r, dirs, buf, big_r);
        buf.clear();
        let rho = self.hob.outer_radius(self.k, a);
        self.end_chord(a, rho, zs, clip_r, r, dirs, big_r);
    }

    /// Adds the pierce points between `from` and `to` (which is added) to
    /// `out`, halving each step until the curve's midpoint lies within four
    /// times the tolerance of the straight piece (the two halves then stay
    /// within about the tolerance), or the piece stays outside the blank by
    /// more than that.
    fn refine(
        &self,
        (a0, p0): (f64, Point),
        (a1, p1): (f64, Point),
        zs: f64,
        big_r: f64,
        depth: u32,
        out: &mut Vec<Point>,
    ) {
        let am = 0.5 * (a0 + a1);
        let Some(pm) = self.pierce(am, self.hob.outer_radius(self.k, am), zs) else {
            out.push(p1);
            return;
        };
        let dev = off_line(p0, p1, pm);
        let outside = near(p0, pm).min(near(pm, p1)) >= big_r + dev;
        if depth == 0 || outside || dev <= 4.0 * self.res.tolerance_mm {
            out.push(pm);
            out.push(p1);
            return;
        }
        self.refine((a0, p0), (am, pm), zs, big_r, depth - 1, out);
        self.refine((am, pm), (a1, p1), zs, big_r, depth - 1, out);
    }

    /// Cuts the chord of the disc at `a` (radius `rho`) in the section `zs`
    /// over the hob angles the pass sweeps inside the blank, as points posed
    /// at their own instants, pieces within the tolerance of the swept curve.
    #[allow(clippy::too_many_arguments)]
    fn end_chord(
        &self,
        a: f64,
        rho: f64,
        zs: f64,
        clip_r: f64,
        r: &mut [f64],
        dirs: &[(f64, f64)],
        big_r: f64,
    ) {
        let q = self.pose(0.0);
        let tt = self.across(&q, a, zs);
        if rho <= 0.0 || tt.abs() >= rho {
            return;
        }
        let big_s = (rho * rho - tt * tt).sqrt();
        let Some((s_lo, s_hi)) = s_range(tt, -self.phi_max, self.phi_max, big_s) else {
            return;
        };
        // Machine points (X − s, y): within clip_r of the gear axis.
        let y = (q.axes.y_mm + a) * self.ce + tt * self.se;
        let h2 = clip_r * clip_r - y * y;
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
        let mut prev = self.chord_point(a, s_hi, zs);
        for i in 1..=m {
            let s = s_hi + (s_lo - s_hi) * i as f64 / m as f64;
            let p = self.chord_point(a, s, zs);
            raster(r, dirs, prev, p, big_r);
            prev = p;
        }
    }

    /// The axial positions a (from the hob's middle) whose disc of radius
    /// tip can meet the disc of radius `clip_r` about the gear axis in the
    /// section `zs`, as an interval (widened by 0.1 mm), or None.
    ///
    /// A section point (x, y, z_s) lies at a = y·cos η − (z_s − Z)·sin η − Y
    /// along the hob and t = y·sin η + (z_s − Z)·cos η across it (along w),
    /// at distance √((x − X)² + t²) from the hob axis. At a given y the
    /// point within `tip` of the hob axis nearest the gear axis has
    /// x = max(X − √(tip² − t²), 0), so the y that reach the blank are where
    /// h(y) = y² + max(X − √(tip² − t²), 0)² − clip_r² ≤ 0 (h = ∞ where
    /// |t| ≥ tip). h is convex (a nonnegative convex function squared plus
    /// y²), so its minimum is found by a golden-section search and the
    /// interval's ends by bisection on either side, to well within the
    /// widening. The pose is the pass's at φ = 0; the hob moves by far less
    /// than the widening while it sweeps.
    fn reach(&self, clip_r: f64, zs: f64) -> Option<(f64, f64)> {
        let p0 = self.pose(0.0);
        let tip = self.hob.tip_radius_mm;
        let (se, ce) = (self.se, self.ce);
        let dz = zs - p0.axes.z_mm;
        let big_x = p0.axes.x_mm;
        let h = |y: f64| {
            let t = y * se + dz * ce;
            if t.abs() >= tip {
                return f64::INFINITY;
            }
            let near_x = (big_x - (tip * tip - t * t).sqrt()).max(0.0);
            y * y + near_x * near_x - clip_r * clip_r
        };
        // Where |t| < tip: y within (±tip − dz·cos η)/sin η, and |y| < clip_r.
        let (mut lo, mut hi) = (-clip_r, clip_r);
        if se.abs() > 1e-12 {
            let (y1, y2) = ((-tip - dz * ce) / se, (tip - dz * ce) / se);
            lo = lo.max(y1.min(y2));
            hi = hi.min(y1.max(y2));
        } else if (dz * ce).abs() >= tip {
            return None;
        }
        if lo >= hi {
            return None;
        }
        let g = (5f64.sqrt() - 1.0) / 2.0;
        let (mut a, mut b) = (lo, hi);
        // 0.618⁴⁰ of a few hundred mm: below 10⁻⁶ mm.
        for _ in 0..40 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if h(c) < h(d) {
                b = d;
            } else {
                a = c;
            }
        }
        let y_min = 0.5 * (a + b);
        if h(y_min) > 0.0 {
            return None;
        }
        let edge = |inside: f64, outside: f64| {
            let (mut a, mut b) = (inside, outside);
            // 2⁻³⁰ of a few hundred mm: below 10⁻⁶ mm.
            for _ in 0..30 {
                let m = 0.5 * (a + b);
                if h(m) <= 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            b
        };
        let (y_lo, y_hi) = (edge(y_min, lo), edge(y_min, hi));
        let a = |y: f64| y * ce - dz * se - p0.axes.y_mm;
        let (a0, a1) = (a(y_lo), a(y_hi));
        Some((a0.min(a1) - 0.1, a0.max(a1) + 0.1))
    }
}

/// Distance of `m` from the line through `p` and `q`.
fn off_line(p: Point, q: Point, m: Point) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let v = [m[0] - p[0], m[1] - p[1]];
    if len == 0.0 {
        return (v[0] * v[0] + v[1] * v[1]).sqrt();
    }
    (v[0] * d[1] - v[1] * d[0]).abs() / len
}

/// Distance from the gear axis of the segment's nearest point.
fn near(p: Point, q: Point) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let tc = if len2 > 0.0 {
        (-(p[0] * d[0] + p[1] * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] + tc * d[0]).hypot(p[1] + tc * d[1])
}

/// Lowers the outline to the polyline `pts`, each point's polar angle
/// computed once.
fn raster_polyline(r: &mut [f64], dirs: &[(f64, f64)], pts: &[Point], big_r: f64) {
    let mut prev: Option<(Point, f64)> = None;
    for &p in pts {
        let ta = p[1].atan2(p[0]);
        if let Some((q, tq)) = prev {
            raster_between(r, dirs, (q, tq), (p, ta), big_r);
        }
        prev = Some((p, ta));
    }
}

/// The chord parameters s (along e1) whose hob angle atan2(t, s) lies in
/// [pa, pb], within [−S, S].
pub(super) fn s_range(t: f64, pa: f64, pb: f64, big_s: f64) -> Option<(f64, f64)> {
    let cot = |p: f64| p.cos() / p.sin();
    let (lo, hi) = if t > 0.0 {
        let (a, b) = (pa.max(1e-12), pb.min(std::f64::consts::PI - 1e-12));
        if a >= b {
            return None;
        }
        (t * cot(b), t * cot(a))
    } else if t < 0.0 {
        let (a, b) = (pa.max(-std::f64::consts::PI + 1e-12), pb.min(-1e-12));
        if a >= b {
            return None;
        }
        (t * cot(a), t * cot(b))
    } else if pa <= 0.0 && 0.0 < pb {
        (0.0, big_s)
    } else {
        return None;
    };
    let (lo, hi) = (lo.max(-big_s), hi.min(big_s));
    (lo < hi).then_some((lo, hi))
}
