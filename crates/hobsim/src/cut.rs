//! The blank as polar outlines on transverse sections, and the material each
//! gash pass removes from it.
//!
//! A gash passes the gear once per hob turn, when its plane points from the
//! hob axis towards the gear axis (body angle + B ≡ 0). While it sweeps the
//! blank its edge at hob angle φ (measured from the direction towards the
//! gear axis, right-handed about u) is there at the pass time plus
//! φ/(2π·n_hob), when the table has turned on. A pass is cut in `sweep_steps`
//! sub-intervals of φ; in each the hob is posed at the sub-interval's middle
//! instant and the edge, turned through the sub-interval, sweeps a sector of
//! the solid of revolution of its profile. A sector meets a section plane in
//! chords of the discs ρ ≤ ρ_out(a) (one per axial sample a); each chord
//! piece is turned into the workpiece frame and lowers the outline r(θ)
//! where it reaches inside it (`docs/simulation.md`).

use crate::hob::Hob;
use crate::kinematics::{Pose, Timeline};
use crate::SimError;

const TAU: f64 = std::f64::consts::TAU;

/// The blank: outlines r(θ) on planes z = `z_mm[j]`, θ counter-clockwise in
/// the workpiece frame, sampled at θ_i = 2π·i/n.
#[derive(Debug, Clone, PartialEq)]
pub struct Blank {
    /// Heights of the sections above the table plane, mm.
    pub z_mm: Vec<f64>,
    /// Outer radius of the uncut blank, mm.
    pub outer_radius_mm: f64,
    /// r(θ_i) per section, mm.
    pub r_mm: Vec<Vec<f64>>,
}

impl Blank {
    /// A cylindrical blank of radius `outer_radius_mm` with sections at
    /// `z_mm` and `n_theta` angles per section.
    pub fn new(z_mm: Vec<f64>, outer_radius_mm: f64, n_theta: usize) -> Result<Blank, SimError> {
        if z_mm.is_empty() || n_theta < 8 || outer_radius_mm <= 0.0 {
            return Err(SimError::Parameter(
                "blank",
                "needs sections, ≥ 8 angles and a radius",
            ));
        }
        let r_mm = vec![vec![outer_radius_mm; n_theta]; z_mm.len()];
        Ok(Blank {
            z_mm,
            outer_radius_mm,
            r_mm,
        })
    }

    /// `n` equally spaced sections over `z_lo..z_hi` (both ends included).
    pub fn planes(z_lo: f64, z_hi: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|j| z_lo + (z_hi - z_lo) * j as f64 / (n.max(2) - 1) as f64)
            .collect()
    }

    /// Angle of sample `i`, radians.
    pub fn theta(&self, i: usize) -> f64 {
        TAU * i as f64 / self.r_mm[0].len() as f64
    }
}

/// Resolution of the material removal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolution {
    /// Axial step along the hob between the discs of a pass, mm.
    pub axial_step_mm: f64,
    /// Sub-intervals of hob angle per gash pass (1: the whole pass cut at
    /// the instant the gash points at the gear axis).
    pub sweep_steps: u32,
}

impl Resolution {
    /// The fine resolution: chords 0.02 mm apart along the hob, pieces of
    /// at most a quarter of the pass's hob-angle span. The strips between
    /// chords are exact for straight flanks and leave Δa²/(8·r_c) on a
    /// rounded tip corner of radius r_c (5·10⁻⁵ mm at r_c = 1 mm); the chord
    /// pieces stay within 10⁻⁵ mm of the swept curve (`docs/simulation.md`
    /// §3). With [`samples_for`] at 1 µm the outline is within 1 µm.
    pub fn fine() -> Resolution {
        Resolution {
            axial_step_mm: 0.02,
            sweep_steps: 8,
        }
    }

    /// A coarse resolution for a quick look: chords 0.1 mm apart (1.3 µm
    /// on a corner of radius 1 mm), with [`samples_for`] at about 10 µm.
    pub fn coarse() -> Resolution {
        Resolution {
            axial_step_mm: 0.1,
            sweep_steps: 2,
        }
    }
}

/// The number of polar samples per section for an outline within
/// `tolerance_um` of the true one on a blank of radius `outer_radius_mm`.
///
/// The outline between two neighbouring rays is read as the straight line
/// through their samples; a curve of radius of curvature ρ leaves
/// L²/(8·ρ) between points L apart along it. Neighbouring samples at radius
/// r are r·Δθ apart across the rays, L = r·Δθ/sin ψ along a curve crossing
/// the rays at angle ψ. Taken here: ρ ≥ 1 mm (a hob tip radius of 0.38·mn
/// for mn ≥ 2.6 mm; a finer module wants a smaller tolerance) and ψ ≥ 10°
/// (an involute crosses its radius at 90° − α_r, the fillet of a gear with
/// at least 10 teeth more steeply), at the outer radius (the largest r).
/// So Δθ = sin 10°·√(8·ρ·tol)/R.
pub fn samples_for(outer_radius_mm: f64, tolerance_um: f64) -> usize {
    let rho_mm = 1.0;
    let psi = 10f64.to_radians();
    let step = psi.sin() * (8.0 * rho_mm * tolerance_um * 1e-3).sqrt() / outer_radius_mm;
    ((TAU / step).ceil() as usize).max(8)
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution::fine()
    }
}

/// Cuts `blank` with `hob` along the whole `timeline`; returns the number of
/// gash passes that were posed near the blank.
pub fn cut(
    timeline: &Timeline,
    hob: &Hob,
    blank: &mut Blank,
    res: Resolution,
) -> Result<u64, SimError> {
    if res.axial_step_mm <= 0.0 || res.sweep_steps == 0 {
        return Err(SimError::Parameter("resolution", "steps must be positive"));
    }
    let (z_lo, z_hi) = blank
        .z_mm
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &z| (a.min(z), b.max(z)));
    let reach = hob.tip_radius_mm + hob.length_mm / 2.0;
    // The rays' directions (cos θ_i, sin θ_i), once.
    let n_theta = blank.r_mm[0].len();
    let dirs: Vec<(f64, f64)> = (0..n_theta)
        .map(|i| {
            let (sn, cs) = (TAU * i as f64 / n_theta as f64).sin_cos();
            (cs, sn)
        })
        .collect();
    let mut passes = 0;
    for (i, s) in timeline.segments().iter().enumerate() {
        if s.hob_rev_s == 0.0 || s.t1_s <= s.t0_s {
            continue;
        }
        let x_min = s.from.x_mm.min(s.to.x_mm);
        let near_z =
            s.from.z_mm.min(s.to.z_mm) - reach < z_hi && s.from.z_mm.max(s.to.z_mm) + reach > z_lo;
        if x_min - hob.tip_radius_mm >= blank.outer_radius_mm || !near_z {
            continue;
        }
        let b0 = timeline.pose_in(i, s.t0_s).b_rad;
        let b1 = timeline.pose_in(i, s.t1_s).b_rad;
        let step = TAU / f64::from(hob.gashes);
        let (lo, hi) = (b0.min(b1), b0.max(b1));
        let mut n = (lo / step).ceil() as i64;
        while (n as f64) * step <= hi {
            let b = n as f64 * step;
            let t = s.t0_s + (b - b0) / (TAU * s.hob_rev_s);
            let k = (-n).rem_euclid(i64::from(hob.gashes)) as u32;
            pass(timeline, i, t, hob, k, blank, &dirs, res);
            passes += 1;
            n += 1;
        }
    }
    Ok(passes)
}

/// Estimated chord error below which a chord piece is not split, mm, at
/// least: the straight piece between two exactly posed points departs from
/// the swept curve by about δ·L/4 (δ the table turn across the piece, L its
/// length). A resolution's own bound is the strips' error across a rounded
/// corner of 1 mm, Δa²/8 (5·10⁻⁵ mm at Δa 0.02 mm), when that is larger.
const PIECE_TOL_MM: f64 = 1e-5;

/// Margin outside the blank's radius to which chords are clipped, mm: the
/// strip edges joining clipped ends stay outside the blank.
const CLIP_MARGIN_MM: f64 = 1.0;

/// One gash pass at time `t` (the gash pointing at the gear axis).
#[allow(clippy::too_many_arguments)]
fn pass(
    timeline: &Timeline,
    seg: usize,
    t: f64,
    hob: &Hob,
    k: u32,
    blank: &mut Blank,
    dirs: &[(f64, f64)],
    res: Resolution,
) {
    let s = &timeline.segments()[seg];
    let p0 = timeline.pose_in(seg, t);
    // Half the hob angle over which a gash can be inside the blank.
    let cos_lim = ((p0.axes.x_mm - blank.outer_radius_mm) / hob.tip_radius_mm).clamp(-1.0, 1.0);
    let phi_max = (cos_lim.acos() + 0.02).min(std::f64::consts::PI);
    let omega = TAU * s.hob_rev_s;
    let sweep = Sweep {
        timeline,
        seg,
        t,
        omega,
        phi_max,
        max_piece_rad: 2.0 * phi_max / f64::from(res.sweep_steps),
        piece_tol_mm: (res.axial_step_mm * res.axial_step_mm / 8.0).max(PIECE_TOL_MM),
        eta_sin_cos: p0.eta_rad.sin_cos(),
        // Table turn per radian of hob turn (ratio, differential, correction):
        // C is linear in time within a move.
        c_per_phi: (timeline.pose_in(seg, s.t1_s).c_rad - timeline.pose_in(seg, s.t0_s).c_rad)
            / ((s.t1_s - s.t0_s) * omega),
    };
    sweep.cut(&p0, hob, k, blank, dirs, res);
}

/// A gash pass: the pose at hob angle φ is the timeline's at t + φ/ω.
struct Sweep<'a> {
    timeline: &'a Timeline,
    seg: usize,
    t: f64,
    omega: f64,
    phi_max: f64,
    max_piece_rad: f64,
    piece_tol_mm: f64,
    c_per_phi: f64,
    eta_sin_cos: (f64, f64),
}

/// A point of a gash edge in a section: axial position `a` along the hob,
/// chord parameter `s` along e1, or on the edge's outer profile when `rho`.
#[derive(Clone, Copy)]
struct EdgePoint {
    a: f64,
    s: f64,
    rho: Option<f64>,
}

impl Sweep<'_> {
    fn pose(&self, phi: f64) -> Pose {
        self.timeline.pose_in(self.seg, self.t + phi / self.omega)
    }

    /// Where the edge point `e` crosses the section `zs` in the workpiece
    /// frame, posed at its own instant. The hob angle of the point,
    /// atan2(t, s), is found from the pose at `phi0` and once more from the
    /// pose at that angle (the hob moves along Z by a few µm per radian at
    /// most, so one correction leaves an error far below a nanometre).
    fn place(&self, e: EdgePoint, zs: f64, phi0: f64) -> [f64; 2] {
        let mut phi = phi0;
        let mut out = [0.0; 2];
        // η stands within a move: its sine and cosine are the pass's.
        let (se, ce) = self.eta_sin_cos;
        for _ in 0..2 {
            let pose = self.pose(phi);
            let along = pose.axes.y_mm + e.a;
            let (cx, cy, cz) = (pose.axes.x_mm, along * ce, pose.axes.z_mm - along * se);
            let tt = (zs - cz) / ce;
            let s = match e.rho {
                Some(r) => (r * r - tt * tt).max(0.0).sqrt(),
                None => e.s,
            };
            phi = tt.atan2(s);
            let (x, y) = (cx - s, cy + tt * se);
            let (sc, cc) = pose.c_rad.sin_cos();
            out = [x * cc - y * sc, x * sc + y * cc];
        }
        out
    }

    /// Cuts gash `k`'s edge over the whole pass from every section.
    fn cut(
        &self,
        p0: &Pose,
        hob: &Hob,
        k: u32,
        blank: &mut Blank,
        dirs: &[(f64, f64)],
        res: Resolution,
    ) {
        let (se, ce) = p0.eta_rad.sin_cos();
        let big_r = blank.outer_radius_mm;
        let clip_r = big_r + CLIP_MARGIN_MM;
        let hx = p0.axes.x_mm;
        let reach_y = ((big_r + hob.tip_radius_mm).powi(2) - hx * hx)
            .max(0.0)
            .sqrt();
        let half = hob.length_mm / 2.0;
        let (a_lo, a_hi) = if ce.abs() > 1e-9 {
            let c0 = -p0.axes.y_mm;
            let d = reach_y / ce.abs();
            ((c0 - d).max(-half), (c0 + d).min(half))
        } else {
            (-half, half)
        };
        let na = ((a_hi - a_lo) / res.axial_step_mm).ceil().max(0.0) as usize;
        // The ends of the last chord of each section: consecutive chords
        // bound a strip of the section, whose edges are cut too, so a ray
        // nearly parallel to the chords still meets the strip where it
        // enters it.
        let step = (a_hi - a_lo) / na.max(1) as f64;
        let profile: Vec<f64> = (0..=na)
            .map(|ia| hob.outer_radius(k, a_lo + step * ia as f64))
            .collect();
        let mut nodes = Vec::new();
        for (j, &zs) in blank.z_mm.iter().enumerate() {
            // Only the axial samples whose chord can reach the blank.
            let Some((a_min, a_max)) = self.reach(p0, hob.tip_radius_mm, clip_r, zs) else {
                continue;
            };
            let ia0 = ((a_min - a_lo) / step).floor().max(0.0) as usize;
            let ia1 = (((a_max - a_lo) / step).ceil().max(0.0) as usize).min(na);
            // The ends of the last chord: consecutive chords bound a strip
            // of the section, whose edges are cut too, so a ray nearly
            // parallel to the chords still meets the strip where it enters
            // it.
            let mut prev: Option<([f64; 2], [f64; 2])> = None;
            for (ia, &rho) in profile.iter().enumerate().take(ia1 + 1).skip(ia0) {
                let a = a_lo + (a_hi - a_lo) * ia as f64 / na.max(1) as f64;
                let along = p0.axes.y_mm + a;
                let c = [hx, along * ce, p0.axes.z_mm - along * se];
                let tt = (zs - c[2]) / ce;
                let chord = if rho > 0.0 {
                    self.chord(tt, rho, c, se, clip_r)
                } else {
                    None
                };
                let Some((s_lo, s_hi)) = chord else {
                    prev = None;
                    continue;
                };
                let big_s = (rho * rho - tt * tt).sqrt();
                self.nodes(a, tt, (s_lo, s_hi), big_s, rho, zs, &mut nodes);
                let (inner, outer) = (nodes[0], nodes[nodes.len() - 1]);
                let r = &mut blank.r_mm[j];
                for w in nodes.windows(2) {
                    raster(r, dirs, w[0], w[1], big_r);
                }
                if let Some((pi, po)) = prev {
                    raster(r, dirs, pi, inner, big_r);
                    raster(r, dirs, po, outer, big_r);
                }
                prev = Some((inner, outer));
            }
        }
    }

    /// The axial positions a (from the hob's middle) whose disc of radius
    /// `tip` can meet the disc of radius `clip_r` about the gear axis in
    /// the section `zs`, as an interval (widened by 0.1 mm), or None.
    ///
    /// A section point (x, y, z_s) lies at a = y·cos η − (z_s − Z)·sin η − Y
    /// along the hob and t = y·sin η + (z_s − Z)·cos η across it (along w),
    /// at distance √((x − X)² + t²) from the hob axis. At a given y the
    /// point within `tip` of the hob axis nearest the gear axis has
    /// x = max(X − √(tip² − t²), 0), so the y that reach the blank are where
    /// h(y) = y² + max(X − √(tip² − t²), 0)² − clip_r² ≤ 0 (h = ∞ where
    /// |t| ≥ tip). h is convex (a nonnegative convex function squared plus
    /// y²), so its minimum is found by a golden-section search and the
    /// interval's ends by bisection on either side.
    fn reach(&self, p0: &Pose, tip: f64, clip_r: f64, zs: f64) -> Option<(f64, f64)> {
        let (se, ce) = p0.eta_rad.sin_cos();
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
        for _ in 0..100 {
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
            for _ in 0..60 {
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

    /// The part of the chord at height `tt` of the disc of radius `rho`
    /// centred at `c` (hob swivelled by η, `se` = sin η) that the pass sweeps (hob angles within ±φ_max) and
    /// that lies within `clip_r` of the gear axis, as s_lo..s_hi.
    fn chord(&self, tt: f64, rho: f64, c: [f64; 3], se: f64, clip_r: f64) -> Option<(f64, f64)> {
        if tt.abs() >= rho {
            return None;
        }
        let big_s = (rho * rho - tt * tt).sqrt();
        let (s_lo, s_hi) = s_range(tt, -self.phi_max, self.phi_max, big_s)?;
        // Machine points (c_x − s, c_y + tt·sin η): within clip_r of the axis.
        let y = c[1] + tt * se;
        let h2 = clip_r * clip_r - y * y;
        if h2 <= 0.0 {
            return None;
        }
        let h = h2.sqrt();
        let (lo, hi) = (s_lo.max(c[0] - h), s_hi.min(c[0] + h));
        (lo < hi).then_some((lo, hi))
    }

    /// The chord s_lo..s_hi as exactly posed points from s_hi (towards the
    /// gear) to s_lo, split so that each piece turns the hob by at most the
    /// resolution's sweep step and leaves a chord error below the piece
    /// tolerance ([`PIECE_TOL_MM`] or the strips' own).
    #[allow(clippy::too_many_arguments)]
    fn nodes(
        &self,
        a: f64,
        tt: f64,
        (s_lo, s_hi): (f64, f64),
        big_s: f64,
        rho: f64,
        zs: f64,
        out: &mut Vec<[f64; 2]>,
    ) {
        out.clear();
        let (f_hi, f_lo) = (tt.atan2(s_hi), tt.atan2(s_lo));
        let dphi = (f_hi - f_lo).abs();
        let err = (self.c_per_phi * dphi).abs() * (s_hi - s_lo) / 4.0;
        let m = ((dphi / self.max_piece_rad).ceil())
            .max((err / self.piece_tol_mm).sqrt().ceil())
            .clamp(1.0, 4096.0) as usize;
        for q in 0..=m {
            let s = s_hi + (s_lo - s_hi) * q as f64 / m as f64;
            let on_edge = q == 0 && s_hi >= big_s;
            let e = EdgePoint {
                a,
                s,
                rho: on_edge.then_some(rho),
            };
            out.push(self.place(e, zs, tt.atan2(s)));
        }
    }
}

/// The chord parameters s (along e1) whose hob angle atan2(t, s) lies in
/// [pa, pb], within [−S, S].
fn s_range(t: f64, pa: f64, pb: f64, big_s: f64) -> Option<(f64, f64)> {
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

/// Lowers r(θ_i) to where the segment p→q crosses each sample ray it spans.
/// `dirs` holds (cos θ_i, sin θ_i) of every ray.
fn raster(r: &mut [f64], dirs: &[(f64, f64)], p: [f64; 2], q: [f64; 2], big_r: f64) {
    let n = r.len();
    let d = [q[0] - p[0], q[1] - p[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    // Nearest point of the segment to the gear axis: skip what stays outside.
    let tc = if len2 > 0.0 {
        (-(p[0] * d[0] + p[1] * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let near = ((p[0] + tc * d[0]).powi(2) + (p[1] + tc * d[1]).powi(2)).sqrt();
    if near >= big_r {
        return;
    }
    let (ta, tb) = (p[1].atan2(p[0]), q[1].atan2(q[0]));
    let mut span = tb - ta;
    if span > std::f64::consts::PI {
        span -= TAU;
    } else if span < -std::f64::consts::PI {
        span += TAU;
    }
    let (start, end) = if span >= 0.0 {
        (ta, ta + span)
    } else {
        (ta + span, ta)
    };
    let scale = n as f64 / TAU;
    let i0 = (start * scale).ceil() as i64;
    let i1 = (end * scale).floor() as i64;
    let cross_pd = p[0] * d[1] - p[1] * d[0];
    for i in i0..=i1 {
        let idx = i.rem_euclid(n as i64) as usize;
        let (cs, sn) = dirs[idx];
        let den = cs * d[1] - sn * d[0];
        let rr = if den.abs() > 1e-15 {
            cross_pd / den
        } else {
            near
        };
        if rr > 0.0 && rr < r[idx] {
            r[idx] = rr;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_lowers_the_rays_it_crosses_to_its_own_radius() {
        let mut r = vec![10.0; 360];
        let dirs: Vec<(f64, f64)> = (0..360)
            .map(|i| {
                let (s, c) = (TAU * f64::from(i) / 360.0).sin_cos();
                (c, s)
            })
            .collect();
        // The line x = 5 from y = −1 to y = 1.
        raster(&mut r, &dirs, [5.0, -1.0], [5.0, 1.0], 10.0);
        assert!((r[0] - 5.0).abs() < 1e-12);
        let th = TAU * 5.0 / 360.0;
        assert!((r[5] - 5.0 / th.cos()).abs() < 1e-12);
        assert_eq!(r[20], 10.0);
        assert_eq!(r[180], 10.0);
    }

    #[test]
    fn the_chord_pieces_of_the_sweep_cover_the_chord_once() {
        // φ from −π to π in 7 pieces cover s ∈ [−S, S] for t ≠ 0.
        let (t, big_s) = (0.3, 2.0);
        let mut total = 0.0;
        for m in 0..7 {
            let w = TAU / 7.0;
            let pa = -std::f64::consts::PI + w * f64::from(m);
            if let Some((lo, hi)) = s_range(t, pa, pa + w, big_s) {
                total += hi - lo;
            }
        }
        assert!((total - 2.0 * big_s).abs() < 1e-9, "{total}");
    }
}
