//! Cutting a section only within angular windows: the coarse run traces
//! profile and helix on a few teeth outside the middle section, as a
//! gear-measuring machine does, so the outline is wanted only about those
//! teeth there (`docs/simulation.md` §3).
//!
//! A step of a pass's curve (the profile points a ∈ [a₀, a₁] along the
//! hob) is traced only when its points can lower the outline within a
//! window. The bound comes from where the hob can be, not from the points.
//!
//! - **The machine point.** A pierce point of the profile point (a, ρ),
//!   and a point of an end chord, posed at hob angle φ lies at (X − s, y),
//!   with t = (z_s − Z)/cos η + (Y + a)·tan η its distance across the hob
//!   and y = (Y + a)·cos η + t·sin η = (Y + a)/cos η + (z_s − Z)·tan η.
//!   Over the hob turn about the pass time (|φ| ≤ π) X, Y and Z are
//!   bounded by their values at the ends of the moves in that time (the
//!   nominal pose is linear within a move), widened by what the what-if
//!   errors can move the hob. With 0 ≤ s ≤ ρ ≤ r_a0 (the tip radius), every
//!   point lies in the box X_min − r_a0 ≤ x ≤ X_max, y_lo(a₀) ≤ y ≤
//!   y_hi(a₁). (An end chord is cut only where x ≤ clip_r, s ≥ X − clip_r;
//!   where that does not keep s positive, x ≤ X_max + r_a0.)
//! - **The table angle.** A pierce point has ρ·sin φ = t, so sin φ lies
//!   between t/r_a0 and t/r_f0 (r_f0 the hob's root radius, ρ ≥ r_f0); a
//!   chord point has tan φ = t/s with X − clip_r ≤ s ≤ ρ. The bounds of t
//!   over the step so bound φ, and C over those hob angles is bounded by
//!   its values at the ends of that stretch and of the moves within it
//!   (C is linear in time within a move).
//! - **The angle.** A point's workpiece angle is its machine angle plus C,
//!   C within [C_mid − δ, C_mid + δ]; turned back by C_mid it stands
//!   within δ·|p| of the box, so every straight piece between two points of
//!   the step (the box widened by δ·|p| is convex) lies in the widened box
//!   turned by C_mid, and where it can lower an outline (within clip_r)
//!   x ≤ clip_r. The angles of that box, plus C_mid, bound the step; a
//!   step whose bound meets no window cannot change the outline in a
//!   window.

use crate::kinematics::{MachineErrors, Timeline};

const TAU: f64 = std::f64::consts::TAU;
const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;
const PI: f64 = std::f64::consts::PI;

/// Slack on a bound of the hob angle, rad: a pierce point's angle is a
/// Newton solution within 10⁻⁸ rad, a chord point's an iteration as close.
const PHI_SLACK: f64 = 1e-6;

/// Bounds of the hob's pose over one hob turn about a pass: the least and
/// greatest X, the ranges of Y and Z, and the table angle C by hob angle
/// φ, as the corners of a broken line (C is linear within a move and may
/// jump where a coupling starts).
#[derive(Debug, Clone)]
pub(super) struct PoseBounds {
    x: (f64, f64),
    y: (f64, f64),
    z: (f64, f64),
    /// (φ, C) in increasing φ.
    c: Vec<(f64, f64)>,
}

impl PoseBounds {
    /// The bounds over the hob angles −π..π about the pass time `t`, the
    /// hob turning at `omega` rad/s, clamped to the timeline, with the
    /// timeline's errors; `se` and `ce` are the sine and cosine of the
    /// pass's swivel.
    pub(super) fn around(timeline: &Timeline, t: f64, omega: f64, (se, ce): (f64, f64)) -> Self {
        let half = std::f64::consts::PI / omega.abs();
        let (lo, hi) = (t - half, t + half);
        let segs = timeline.segments();
        let first = segs
            .partition_point(|s| s.t1_s < lo)
            .min(segs.len().saturating_sub(1));
        let mut poses = vec![(lo, timeline.nominal_pose(lo))];
        for (i, s) in segs.iter().enumerate().skip(first) {
            if s.t0_s > hi {
                break;
            }
            for at in [s.t0_s.max(lo), s.t1_s.min(hi)] {
                poses.push((at, timeline.nominal_pose_in(i, at)));
            }
        }
        poses.push((hi, timeline.nominal_pose(hi)));
        let p = poses[0].1.axes;
        let mut b = PoseBounds {
            x: (p.x_mm, p.x_mm),
            y: (p.y_mm, p.y_mm),
            z: (p.z_mm, p.z_mm),
            c: Vec::with_capacity(poses.len()),
        };
        for (at, q) in &poses {
            let a = &q.axes;
            b.x = (b.x.0.min(a.x_mm), b.x.1.max(a.x_mm));
            b.y = (b.y.0.min(a.y_mm), b.y.1.max(a.y_mm));
            b.z = (b.z.0.min(a.z_mm), b.z.1.max(a.z_mm));
            b.c.push((omega * (at - t), q.c_rad));
        }
        if omega < 0.0 {
            b.c.reverse();
        }
        b.widen(&timeline.errors(), se.abs(), ce)
    }

    /// Widened by what the errors can move the hob ([`MachineErrors::apply`]:
    /// the centre distance adds to X; the runouts translate the hob by at
    /// most their amplitudes along X, Y and Z as written there; C is not
    /// changed).
    fn widen(mut self, e: &MachineErrors, se: f64, ce: f64) -> Self {
        let (er, ea, et) = (
            e.hob_radial_mm.abs(),
            e.hob_axial_mm.abs(),
            e.table_mm.abs(),
        );
        let dx = er + et;
        let dy = ea + (et + er * se) / ce;
        let dz = (et * se + er) / ce;
        let cd = e.centre_distance_mm;
        self.x = (self.x.0 + cd - dx, self.x.1 + cd + dx);
        self.y = (self.y.0 - dy, self.y.1 + dy);
        self.z = (self.z.0 - dz, self.z.1 + dz);
        self
    }

    /// The least and greatest C over the hob angles `pa..=pb`.
    fn c_range(&self, pa: f64, pb: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for w in self.c.windows(2) {
            let ((p0, c0), (p1, c1)) = (w[0], w[1]);
            if p1 < pa || p0 > pb {
                continue;
            }
            let at = |p: f64| {
                if p1 > p0 {
                    c0 + (c1 - c0) * (p - p0) / (p1 - p0)
                } else {
                    c0.min(c1)
                }
            };
            let (ca, cb) = (at(pa.max(p0)), at(pb.min(p1)));
            lo = lo.min(ca).min(cb);
            hi = hi.max(ca).max(cb);
            if p1 == p0 {
                hi = hi.max(c0.max(c1));
            }
        }
        if lo > hi {
            // Beyond the broken line: all of it.
            return self
                .c
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), &(_, c)| (l.min(c), h.max(c)));
        }
        (lo, hi)
    }
}

/// The bound on the workpiece angles of a pass's points in one section
/// ([`AngleBound::of_step`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct AngleBound {
    /// X at its least and greatest.
    x: (f64, f64),
    /// Y at its least and greatest.
    y: (f64, f64),
    clip_r: f64,
    /// (z_s − Z)/cos η at its least and greatest.
    zt: (f64, f64),
    /// (z_s − Z)·tan η at its least and greatest.
    zy: (f64, f64),
    tan: f64,
    inv_ce: f64,
    /// The middle of the table angles over the pass's points, and how far
    /// a point can be turned from it, radians.
    pub(super) c_mid: f64,
    turn: f64,
    /// Beyond the distance of any point from the gear axis, mm.
    far: f64,
}

/// Where a step of a pass can lower an outline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum StepReach {
    /// No bound on the angle.
    Anywhere,
    /// Within the directions from the gear axis whose slopes y/x, seen
    /// from the direction at [`AngleBound::c_mid`], lie in (lo, hi): within
    /// a quarter turn of it.
    Within(f64, f64),
    /// Nowhere: no point of the step comes within the clip radius.
    Nowhere,
}

impl AngleBound {
    /// The bound in the section `zs` for the profile points `reach` of a
    /// hob of root and tip radii `root`, `tip` whose pose is within `pose`,
    /// at X `x0` at the pass time, swivelled by η (`se`, `ce`), cutting
    /// within `clip_r` of the gear axis; `None` when cos η ≤ 0 or the root
    /// radius is not positive.
    pub(super) fn new(
        pose: &PoseBounds,
        (zs, clip_r): (f64, f64),
        (root, tip): (f64, f64),
        (x0, reach): (f64, (f64, f64)),
        (se, ce): (f64, f64),
    ) -> Option<Self> {
        if !(ce > 0.0 && root > 0.0) {
            return None;
        }
        let tan = se / ce;
        let (za, zb) = (zs - pose.z.1, zs - pose.z.0);
        let (ya, yb) = (za * tan, zb * tan);
        let mut b = AngleBound {
            x: pose.x,
            y: pose.y,
            clip_r,
            zt: (za / ce, zb / ce),
            zy: (ya.min(yb), ya.max(yb)),
            tan,
            inv_ce: 1.0 / ce,
            c_mid: 0.0,
            turn: 0.0,
            far: 0.0,
        };
        // The hob angles of the points: a pierce point's sin φ = t/ρ with
        // root ≤ ρ ≤ tip; an end chord's tan φ = t/s with X − clip_r ≤ s ≤
        // ρ (any angle where that is not positive).
        let (t0, t1) = b.across(reach.0, reach.1);
        let sin_lo = t0 / if t0 >= 0.0 { tip } else { root };
        let sin_hi = t1 / if t1 >= 0.0 { root } else { tip };
        let mut phi = (
            sin_lo.clamp(-1.0, 1.0).asin(),
            sin_hi.clamp(-1.0, 1.0).asin(),
        );
        let s_min = x0 - clip_r;
        if s_min > 0.0 {
            let lo = (t0 / if t0 >= 0.0 { tip } else { s_min }).atan();
            let hi = (t1 / if t1 >= 0.0 { s_min } else { tip }).atan();
            phi = (phi.0.min(lo), phi.1.max(hi));
        } else {
            // A chord may then reach behind the hob's centre: any angle.
            phi = (-PI, PI);
        }
        let (c_lo, c_hi) = pose.c_range(phi.0 - PHI_SLACK, phi.1 + PHI_SLACK);
        b.c_mid = 0.5 * (c_lo + c_hi);
        b.turn = 0.5 * (c_hi - c_lo);
        let (y0, y1) = b.machine_y(reach.0, reach.1);
        b.far = (pose.x.1.abs() + tip).hypot(y0.abs().max(y1.abs()));
        Some(b)
    }

    /// t, the distance across the hob, at its least and greatest over the
    /// profile points a0..=a1: (z_s − Z)/cos η + (Y + a)·tan η.
    fn across(&self, a0: f64, a1: f64) -> (f64, f64) {
        let (u0, u1) = (self.y.0 + a0, self.y.1 + a1);
        let (v0, v1) = if self.tan >= 0.0 {
            (u0 * self.tan, u1 * self.tan)
        } else {
            (u1 * self.tan, u0 * self.tan)
        };
        (self.zt.0 + v0, self.zt.1 + v1)
    }

    /// The machine y at its least and greatest over the profile points
    /// a0..=a1: (Y + a)/cos η + (z_s − Z)·tan η.
    fn machine_y(&self, a0: f64, a1: f64) -> (f64, f64) {
        (
            (self.y.0 + a0) * self.inv_ce + self.zy.0,
            (self.y.1 + a1) * self.inv_ce + self.zy.1,
        )
    }

    /// True when the plane may miss the disc of radius `rho` at `a` (or the
    /// point is beyond the hob's end): a run of the pass's curve may end
    /// next to it, so its neighbours may cut end chords.
    pub(super) fn may_miss(&self, a: f64, rho: f64) -> bool {
        let (t0, t1) = self.across(a, a);
        rho <= 0.0 || t0.abs().max(t1.abs()) >= 0.999 * rho
    }

    /// Where the points of the profile points a0..=a1 (radii `rho` at the
    /// two ends: the profile is a line or one arc between them), and every
    /// straight piece between two of them, can lower an outline; `chord`
    /// when an end chord may be cut at either end.
    ///
    /// A pierce point's s = √(ρ² − t²) lies between √(ρ_lo² − t_max²) and
    /// √(ρ_hi² − t_min²) (t_min, t_max the least and greatest |t|), so its
    /// x between X_min − s_hi and X_max − s_lo; a chord's point lies
    /// between X − s and the clip radius.
    pub(super) fn of_step(&self, (a0, a1): (f64, f64), rho: (f64, f64), chord: bool) -> StepReach {
        let (t0, t1) = self.across(a0, a1);
        let t_max = t0.abs().max(t1.abs());
        let t_min = if t0 <= 0.0 && t1 >= 0.0 {
            0.0
        } else {
            t0.abs().min(t1.abs())
        };
        let (r_lo, r_hi) = (rho.0.min(rho.1).max(0.0), rho.0.max(rho.1));
        let s_lo = (r_lo * r_lo - t_max * t_max).max(0.0).sqrt();
        let s_hi = (r_hi * r_hi - t_min * t_min).max(0.0).sqrt();
        let moved = self.turn * self.far;
        let x_lo = self.x.0 - s_hi - moved;
        if x_lo.is_nan() || x_lo <= 0.0 {
            return StepReach::Anywhere;
        }
        let x_top = if chord {
            self.clip_r
        } else {
            self.x.1 - s_lo + moved
        };
        let (y_lo, y_hi) = self.machine_y(a0, a1);
        let (y_lo, y_hi) = (y_lo - moved, y_hi + moved);
        // Within the clip radius: x ≤ √(clip_r² − y²) at the least |y|.
        let y_near = if y_lo > 0.0 {
            y_lo
        } else if y_hi < 0.0 {
            y_hi
        } else {
            0.0
        };
        let x_hi = x_top.min(
            (self.clip_r * self.clip_r - y_near * y_near)
                .max(0.0)
                .sqrt(),
        );
        if x_hi < x_lo {
            return StepReach::Nowhere;
        }
        StepReach::Within(
            y_lo / if y_lo >= 0.0 { x_hi } else { x_lo },
            y_hi / if y_hi >= 0.0 { x_lo } else { x_hi },
        )
    }
}

/// The windows `(from, to)` (from ≤ to, rad, workpiece angles) seen from
/// the direction at angle `c_mid`, as ranges of the slope y/x of the
/// points within a quarter turn of it (x > 0), into `out`: the angle
/// relative to `c_mid` is atan(y/x) there, and tan is increasing on
/// (−π/2, π/2), so an angle range there meets a window where its slopes
/// meet the window's.
pub(super) fn window_slopes(windows: &[(f64, f64)], c_mid: f64, out: &mut Vec<(f64, f64)>) {
    out.clear();
    for &(from, to) in windows {
        let width = to - from;
        if width >= TAU {
            out.push((f64::NEG_INFINITY, f64::INFINITY));
            continue;
        }
        // The window's start relative to c_mid in [−π, π), and the same a
        // turn earlier.
        let rel = from - c_mid;
        let rel = rel - TAU * ((rel + std::f64::consts::PI) / TAU).floor();
        for start in [rel, rel - TAU] {
            let (a, b) = (start.max(-HALF_PI), (start + width).min(HALF_PI));
            if a <= b {
                let slope = |x: f64| {
                    if x >= HALF_PI {
                        f64::INFINITY
                    } else if x <= -HALF_PI {
                        f64::NEG_INFINITY
                    } else {
                        x.tan()
                    }
                };
                out.push((slope(a), slope(b)));
            }
        }
    }
}

/// True when the slopes `lo..=hi` meet one of `slopes`.
pub(super) fn meets_slopes(slopes: &[(f64, f64)], lo: f64, hi: f64) -> bool {
    slopes.iter().any(|&(a, b)| lo <= b && hi >= a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::{Axes, Gearbox, Segment};

    /// A plunge, a feed along Z and a rapid away, coupled, 20 hob turns a
    /// second.
    fn timeline(errors: MachineErrors) -> Timeline {
        let at = |x_mm, y_mm, z_mm| Axes { x_mm, y_mm, z_mm };
        let seg = |t0_s, t1_s, from, to, feed| Segment {
            line: 0,
            t0_s,
            t1_s,
            from,
            to,
            eta_rad: 0.3,
            hob_rev_s: 20.0,
            gearbox: Some(Gearbox {
                c_per_b: 1.0 / 31.0,
                c_per_z_rad_mm: 0.01,
                c_per_y_rad_mm: 0.0,
            }),
            c_extra_rad: 0.0,
            feed,
        };
        let (a, b, c, d) = (
            at(95.0, 3.0, 40.0),
            at(88.0, 3.0, 40.0),
            at(88.0, 3.5, 30.0),
            at(120.0, 3.5, 30.0),
        );
        Timeline::from_segments(vec![
            seg(0.0, 0.02, a, b, true),
            seg(0.02, 0.05, b, c, true),
            seg(0.05, 0.052, c, d, false),
        ])
        .expect("timeline")
        .with_errors(errors)
    }

    #[test]
    fn every_pose_of_the_hob_turn_is_within_its_bounds() {
        let errors = MachineErrors {
            centre_distance_mm: 0.1,
            hob_radial_mm: 0.3,
            hob_radial_phase_deg: 70.0,
            hob_axial_mm: 0.2,
            hob_axial_phase_deg: 10.0,
            table_mm: 0.25,
            table_phase_deg: 250.0,
            ..Default::default()
        };
        for errors in [MachineErrors::default(), errors] {
            let tl = timeline(errors);
            let (se, ce) = (0.3f64.sin(), 0.3f64.cos());
            let omega = std::f64::consts::TAU * 20.0;
            for t in [0.0, 0.013, 0.02, 0.031, 0.049, 0.051, 0.06] {
                let b = PoseBounds::around(&tl, t, omega, (se, ce));
                let mut close = [f64::MAX; 3];
                for k in 0..=2000 {
                    let phi = -std::f64::consts::PI + TAU * f64::from(k) / 2000.0;
                    let q = tl.pose(t + phi / omega);
                    let a = &q.axes;
                    let gaps = [
                        (a.x_mm - b.x.0).min(b.x.1 - a.x_mm),
                        (a.y_mm - b.y.0).min(b.y.1 - a.y_mm),
                        (a.z_mm - b.z.0).min(b.z.1 - a.z_mm),
                    ];
                    for (c, g) in close.iter_mut().zip(gaps) {
                        assert!(g >= -1e-12, "{t} s, φ {phi}: {gaps:?} outside {b:?}");
                        *c = c.min(g);
                    }
                    // The table angle within its bounds over a small
                    // stretch of hob angles about it.
                    let (lo, hi) = b.c_range(phi - 1e-3, phi + 1e-3);
                    assert!(
                        q.c_rad >= lo - 1e-12 && q.c_rad <= hi + 1e-12,
                        "{t} s, φ {phi}: C {} outside {lo}..{hi}",
                        q.c_rad
                    );
                    // Not much wider than C moves over that stretch.
                    assert!(hi - lo <= 1.5e-4, "{lo}..{hi}");
                }
                // Not wider than the errors make it: within their sum.
                let slack = 2.0 * (0.3 + 0.2 + 0.25) / ce + 0.1 + 1e-9;
                assert!(close.iter().all(|&c| c <= slack), "{t} s: {close:?}");
            }
        }
    }

    /// Whether the angles lo..=hi meet a window, counted round the circle.
    fn meets_angles(windows: &[(f64, f64)], lo: f64, hi: f64) -> bool {
        windows.iter().any(|&(from, to)| {
            let start = (from - lo).rem_euclid(TAU);
            start <= hi - lo || start + (to - from) >= TAU
        })
    }

    #[test]
    fn windows_are_met_as_their_slopes() {
        // Windows (one across 2π, one wider than a half turn) against
        // angle ranges within a quarter turn of the direction seen from.
        let windows = [(1.0, 1.2), (TAU - 0.1, TAU + 0.1), (3.0, 5.0)];
        let mut slopes = Vec::new();
        for c_mid in [0.0, 1.1, -2.0, 3.1, 9.0] {
            window_slopes(&windows, c_mid, &mut slopes);
            for k in 0..400 {
                let lo = -1.5 + 2.9 * f64::from(k) / 400.0;
                let hi = (lo + 0.02 * f64::from(k % 7)).min(1.55);
                assert_eq!(
                    meets_slopes(&slopes, lo.tan(), hi.tan()),
                    meets_angles(&windows, c_mid + lo, c_mid + hi),
                    "seen from {c_mid}: {lo}..{hi}"
                );
            }
        }
        window_slopes(&[(0.0, 7.0)], 2.0, &mut slopes);
        assert!(meets_slopes(&slopes, 0.1, 0.2));
        window_slopes(&[(2.0, 2.1)], 2.0 + std::f64::consts::PI, &mut slopes);
        assert!(slopes.is_empty());
    }
}
