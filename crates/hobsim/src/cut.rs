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

impl Default for Resolution {
    fn default() -> Self {
        Resolution {
            axial_step_mm: 0.02,
            sweep_steps: 8,
        }
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
            pass(timeline, i, t, hob, k, blank, res);
            passes += 1;
            n += 1;
        }
    }
    Ok(passes)
}

/// One gash pass at time `t` (the gash pointing at the gear axis).
fn pass(
    timeline: &Timeline,
    seg: usize,
    t: f64,
    hob: &Hob,
    k: u32,
    blank: &mut Blank,
    res: Resolution,
) {
    let s = &timeline.segments()[seg];
    let p0 = timeline.pose_in(seg, t);
    // Half the hob angle over which a gash can be inside the blank.
    let cos_lim = ((p0.axes.x_mm - blank.outer_radius_mm) / hob.tip_radius_mm).clamp(-1.0, 1.0);
    let phi_max = (cos_lim.acos() + 0.02).min(std::f64::consts::PI);
    let n = res.sweep_steps;
    let w = 2.0 * phi_max / f64::from(n);
    let omega = TAU * s.hob_rev_s;
    for m in 0..n {
        let (pa, pb) = (-phi_max + w * f64::from(m), -phi_max + w * f64::from(m + 1));
        let mid = if n == 1 { 0.0 } else { 0.5 * (pa + pb) };
        let pose = timeline.pose_in(seg, t + mid / omega);
        // The table keeps turning with the hob inside the segment; a pass
        // reaching past the segment's end is posed at its end.
        sector(&pose, hob, k, pa, pb, blank, res);
    }
}

/// The sector φ ∈ [pa, pb] of gash `k`'s solid of revolution at `pose`,
/// cut from every section.
fn sector(pose: &Pose, hob: &Hob, k: u32, pa: f64, pb: f64, blank: &mut Blank, res: Resolution) {
    let (se, ce) = pose.eta_rad.sin_cos();
    let u = [0.0, ce, -se];
    let w = [0.0, se, ce];
    let big_r = blank.outer_radius_mm;
    let hx = pose.axes.x_mm;
    let reach_y = ((big_r + hob.tip_radius_mm).powi(2) - hx * hx)
        .max(0.0)
        .sqrt();
    let half = hob.length_mm / 2.0;
    let (a_lo, a_hi) = if ce.abs() > 1e-9 {
        let c0 = -pose.axes.y_mm;
        let d = reach_y / ce.abs();
        ((c0 - d).max(-half), (c0 + d).min(half))
    } else {
        (-half, half)
    };
    let (sc, cc) = pose.c_rad.sin_cos();
    let na = ((a_hi - a_lo) / res.axial_step_mm).ceil().max(0.0) as usize;
    // The last chord piece of each section: consecutive pieces bound a strip
    // of the section, whose edges are cut too, so a ray nearly parallel to
    // the chords still meets the strip where it enters it.
    let mut prev: Vec<Option<([f64; 2], [f64; 2])>> = vec![None; blank.z_mm.len()];
    for ia in 0..=na {
        let a = a_lo + (a_hi - a_lo) * ia as f64 / na.max(1) as f64;
        let rho = hob.outer_radius(k, a);
        if rho <= 0.0 {
            prev.iter_mut().for_each(|p| *p = None);
            continue;
        }
        let along = pose.axes.y_mm + a;
        let c = [hx, along * u[1], pose.axes.z_mm + along * u[2]];
        for (j, &zs) in blank.z_mm.iter().enumerate() {
            let tt = (zs - c[2]) / w[2];
            if tt.abs() >= rho {
                prev[j] = None;
                continue;
            }
            let big_s = (rho * rho - tt * tt).sqrt();
            let Some((s_lo, s_hi)) = s_range(tt, pa, pb, big_s) else {
                prev[j] = None;
                continue;
            };
            // Points c + tt·w + s·e1, e1 = (−1, 0, 0); then into the
            // workpiece frame: θ_w = θ_m + C.
            let base = [c[0], c[1] + tt * w[1]];
            let to_w = |s: f64| {
                let (x, y) = (base[0] - s, base[1]);
                [x * cc - y * sc, x * sc + y * cc]
            };
            let (inner, outer) = (to_w(s_hi), to_w(s_lo));
            raster(&mut blank.r_mm[j], inner, outer, big_r);
            if let Some((pi, po)) = prev[j] {
                raster(&mut blank.r_mm[j], pi, inner, big_r);
                raster(&mut blank.r_mm[j], po, outer, big_r);
            }
            prev[j] = Some((inner, outer));
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
fn raster(r: &mut [f64], p: [f64; 2], q: [f64; 2], big_r: f64) {
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
        let th = i as f64 / scale;
        let (sn, cs) = th.sin_cos();
        let den = cs * d[1] - sn * d[0];
        let rr = if den.abs() > 1e-15 {
            cross_pd / den
        } else {
            near
        };
        let idx = i.rem_euclid(n as i64) as usize;
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
        // The line x = 5 from y = −1 to y = 1.
        raster(&mut r, [5.0, -1.0], [5.0, 1.0], 10.0);
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
