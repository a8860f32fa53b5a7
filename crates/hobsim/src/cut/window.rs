//! Cutting a section only within angular windows: the coarse run traces
//! profile and helix on a few teeth outside the middle section, as a
//! gear-measuring machine does, so the outline is wanted only about those
//! teeth there (`docs/simulation.md` §3).
//!
//! A step of a pass's curve (the profile points a ∈ [a₀, a₁] along the
//! hob) is traced only when its pierce points can lower the outline within
//! a window. The bound comes from where the hob can be, not from the
//! points: a pierce point of the profile point (a, ρ) posed at hob angle φ
//! lies at the machine point (X − s, y) with 0 ≤ s ≤ ρ ≤ r_a0 (the tip
//! radius) and, t = (z_s − Z + (Y + a)·sin η)/cos η being its distance
//! across the hob, y = (Y + a)·cos η + t·sin η = (Y + a)/cos η +
//! (z_s − Z)·tan η; the workpiece angle is atan2(y, x) + C. Over the hob
//! turn about the pass time (|φ| ≤ π, every pierce point's and every end
//! chord's angle) X, Y, Z and C are bounded by their values at the ends of
//! the moves in that time (the nominal pose is linear within a move), and
//! the what-if errors move the hob by at most their amplitudes. A point
//! that can lower an outline inside the clip radius has x ≤ clip_r, so it
//! lies in the box X_min − r_a0 ≤ x ≤ clip_r, y_lo(a₀) ≤ y ≤ y_hi(a₁), and
//! so does every straight piece between two such points there (the box is
//! convex). Its angles, turned by C's range, bound the step; a step whose
//! bound meets no window cannot change the outline in a window.

use crate::kinematics::{MachineErrors, Timeline};

const TAU: f64 = std::f64::consts::TAU;

/// Bounds of the hob's pose over one hob turn about a pass: the least X,
/// the ranges of Y, Z and C.
#[derive(Debug, Clone, Copy)]
pub(super) struct PoseBounds {
    x_min: f64,
    y: (f64, f64),
    z: (f64, f64),
    c: (f64, f64),
}

impl PoseBounds {
    /// The bounds over the times `t ± 1/(2·|n|)` (half a hob turn either
    /// side, `n` the hob's turns per second), clamped to the timeline, with
    /// the timeline's errors; `ce` and `se` are the cosine and sine of the
    /// pass's swivel.
    pub(super) fn around(timeline: &Timeline, t: f64, rev_s: f64, (se, ce): (f64, f64)) -> Self {
        let half = 0.5 / rev_s.abs();
        let (lo, hi) = (t - half, t + half);
        let segs = timeline.segments();
        let first = segs
            .partition_point(|s| s.t1_s < lo)
            .min(segs.len().saturating_sub(1));
        let p = timeline.nominal_pose(lo);
        let mut b = PoseBounds {
            x_min: p.axes.x_mm,
            y: (p.axes.y_mm, p.axes.y_mm),
            z: (p.axes.z_mm, p.axes.z_mm),
            c: (p.c_rad, p.c_rad),
        };
        for (i, s) in segs.iter().enumerate().skip(first) {
            if s.t0_s > hi {
                break;
            }
            for at in [s.t0_s.max(lo), s.t1_s.min(hi)] {
                let q = timeline.nominal_pose_in(i, at);
                b.x_min = b.x_min.min(q.axes.x_mm);
                b.y = (b.y.0.min(q.axes.y_mm), b.y.1.max(q.axes.y_mm));
                b.z = (b.z.0.min(q.axes.z_mm), b.z.1.max(q.axes.z_mm));
                b.c = (b.c.0.min(q.c_rad), b.c.1.max(q.c_rad));
            }
        }
        let q = timeline.nominal_pose(hi);
        b.x_min = b.x_min.min(q.axes.x_mm);
        b.y = (b.y.0.min(q.axes.y_mm), b.y.1.max(q.axes.y_mm));
        b.z = (b.z.0.min(q.axes.z_mm), b.z.1.max(q.axes.z_mm));
        b.c = (b.c.0.min(q.c_rad), b.c.1.max(q.c_rad));
        b.widen(&timeline.errors(), se.abs(), ce)
    }

    /// Widened by what the errors can move the hob ([`MachineErrors::apply`]:
    /// the centre distance adds to X; the runouts translate the hob by at
    /// most their amplitudes along X, Y and Z as written there).
    fn widen(mut self, e: &MachineErrors, se: f64, ce: f64) -> Self {
        let (er, ea, et) = (
            e.hob_radial_mm.abs(),
            e.hob_axial_mm.abs(),
            e.table_mm.abs(),
        );
        let dx = er + et;
        let dy = ea + (et + er * se) / ce;
        let dz = (et * se + er) / ce;
        self.x_min += e.centre_distance_mm - dx;
        self.y = (self.y.0 - dy, self.y.1 + dy);
        self.z = (self.z.0 - dz, self.z.1 + dz);
        self
    }
}

/// The bound on the workpiece angles of a pass's pierce points in one
/// section: [`AngleBound::lo`] of a step's first profile point and
/// [`AngleBound::hi`] of its last enclose every point of the step that can
/// lower the outline.
#[derive(Debug, Clone, Copy)]
pub(super) struct AngleBound {
    x_lo: f64,
    x_hi: f64,
    inv_ce: f64,
    /// y less a/cos η at its least and greatest.
    y_lo: f64,
    y_hi: f64,
    c: (f64, f64),
}

impl AngleBound {
    /// The bound in the section `zs` for a hob of tip radius `tip` whose
    /// pose is within `pose`, swivelled by η (`se`, `ce`), cutting within
    /// `clip_r` of the gear axis; `None` when the box reaches the gear axis
    /// (no bound on the angle) or cos η ≤ 0.
    pub(super) fn new(
        pose: &PoseBounds,
        zs: f64,
        clip_r: f64,
        tip: f64,
        (se, ce): (f64, f64),
    ) -> Option<Self> {
        let x_lo = pose.x_min - tip;
        if !(x_lo > 0.0 && ce > 0.0) {
            return None;
        }
        let tan = se / ce;
        let (za, zb) = ((zs - pose.z.1) * tan, (zs - pose.z.0) * tan);
        Some(AngleBound {
            x_lo,
            x_hi: clip_r.max(x_lo),
            inv_ce: 1.0 / ce,
            y_lo: pose.y.0 / ce + za.min(zb),
            y_hi: pose.y.1 / ce + za.max(zb),
            c: pose.c,
        })
    }

    /// The least angle a point of the profile point `a` (or of any later
    /// one) can have.
    pub(super) fn lo(&self, a: f64) -> f64 {
        let y = self.y_lo + a * self.inv_ce;
        let x = if y >= 0.0 { self.x_hi } else { self.x_lo };
        (y / x).atan() + self.c.0
    }

    /// The greatest angle a point of the profile point `a` (or of any
    /// earlier one) can have.
    pub(super) fn hi(&self, a: f64) -> f64 {
        let y = self.y_hi + a * self.inv_ce;
        let x = if y >= 0.0 { self.x_lo } else { self.x_hi };
        (y / x).atan() + self.c.1
    }
}

/// True when the angles `lo..=hi` meet one of `windows` (each `(from, to)`,
/// from ≤ to, rad), counting round the circle.
pub(super) fn meets(windows: &[(f64, f64)], lo: f64, hi: f64) -> bool {
    let span = hi - lo;
    span >= TAU
        || windows.iter().any(|&(from, to)| {
            let start = (from - lo).rem_euclid(TAU);
            start <= span || start + (to - from) >= TAU
        })
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
            for t in [0.0, 0.013, 0.02, 0.031, 0.049, 0.051, 0.06] {
                let b = PoseBounds::around(&tl, t, 20.0, (se, ce));
                let mut close = [f64::MAX; 4];
                for k in 0..=2000 {
                    let q = tl.pose(t - 0.025 + 0.05 * f64::from(k) / 2000.0);
                    let a = &q.axes;
                    let gaps = [
                        a.x_mm - b.x_min,
                        (a.y_mm - b.y.0).min(b.y.1 - a.y_mm),
                        (a.z_mm - b.z.0).min(b.z.1 - a.z_mm),
                        (q.c_rad - b.c.0).min(b.c.1 - q.c_rad),
                    ];
                    for (c, g) in close.iter_mut().zip(gaps) {
                        assert!(g >= -1e-12, "{t} s: {gaps:?} outside {b:?}");
                        *c = c.min(g);
                    }
                }
                // Not wider than the errors make it: within their sum.
                let slack = 2.0 * (0.3 + 0.2 + 0.25) / ce + 1e-9;
                assert!(close.iter().all(|&c| c <= slack), "{t} s: {close:?}");
            }
        }
    }

    #[test]
    fn windows_are_met_round_the_circle() {
        let w = [(1.0, 1.2)];
        assert!(meets(&w, 0.9, 1.05));
        assert!(meets(&w, 1.1, 1.15));
        assert!(meets(&w, 1.15, 2.0));
        assert!(!meets(&w, 1.25, 2.0));
        assert!(!meets(&w, 0.5, 0.95));
        // The same angles a turn away.
        assert!(meets(&w, 0.9 + TAU, 1.05 + TAU));
        assert!(meets(&w, 0.9 - TAU, 1.05 - TAU));
        assert!(!meets(&w, 1.25 - TAU, 2.0 - TAU));
        // A window across 2π.
        let across = [(TAU - 0.1, TAU + 0.1)];
        assert!(meets(&across, 0.05, 0.2));
        assert!(meets(&across, -0.3, -0.05));
        assert!(!meets(&across, 0.2, 0.3));
        assert!(meets(&[], 0.0, TAU));
        assert!(!meets(&[], 0.0, 1.0));
    }
}
