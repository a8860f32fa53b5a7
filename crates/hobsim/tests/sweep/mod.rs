//! The independent reference the simulation is checked against: for a
//! point of a section it finds, for every gash pass, the instant the gash's
//! half-plane (body angle 2πk/i about the hob axis) passes through the point
//! (a root of the point's angle about the hob axis minus the gash's, by
//! bisection), and asks whether the point lies inside the edge's profile
//! there. The cut outline along a ray is where that first happens, found by
//! bisection on the radius. Nothing of `gearcam_hobsim::cut` is used.
#![allow(dead_code)]

use gearcam_hobsim::hob::Hob;
use gearcam_hobsim::kinematics::Timeline;

const PI: f64 = std::f64::consts::PI;
const TAU: f64 = std::f64::consts::TAU;

/// The edge profile of gash `k` at axial position `a` (mm from the hob's
/// middle): straight flanks of axial pressure angle α_x, tooth centres at
/// p·2πk/i + j·p_x, half a pitch thick at r0, clamped to root and tip.
/// With tip corners of radius r_c (in the normal section, whose lengths
/// along the axis are the axial ones times cos γ0) the tooth is the union
/// of the discs of radius r_c that fit inside the sharp tooth (its opening
/// by a disc): above x the highest point of such a disc, whose centre
/// (u, v) stays r_c below the tip line and r_c inside the flank. The height
/// v(u) + √(r_c² − (x − u)²) is concave in u (a minimum of lines plus a
/// semicircle), so a golden-section search finds its maximum.
pub(crate) fn profile(h: &Hob, k: u32, a: f64) -> f64 {
    if a.abs() > h.length_mm / 2.0 {
        return 0.0;
    }
    let p = h.hand * f64::from(h.starts) * h.axial_pitch_mm / TAU;
    let centre = p * TAU * f64::from(k) / f64::from(h.gashes);
    let px = h.axial_pitch_mm;
    let d = (a - centre - px * ((a - centre) / px).round()).abs();
    let sharp = |x: f64| h.ref_radius_mm + (px / 4.0 - x) / h.tan_alpha_x;
    let rc = h.tip_corner_radius_mm;
    if rc <= 0.0 {
        return sharp(d).clamp(h.root_radius_mm, h.tip_radius_mm);
    }
    // Normal section: x_n = x·cos γ0, flank height (p_n/4 − x_n)/tan α0.
    let (c, tan_a) = (h.cos_lead, h.tan_alpha_x * h.cos_lead);
    let big_h = h.tip_radius_mm - h.ref_radius_mm;
    let pn = px * c;
    let xn = d * c;
    let cos_a = 1.0 / (1.0 + tan_a * tan_a).sqrt();
    let top = |u: f64| {
        let v = (big_h - rc).min((pn / 4.0 - u - rc / cos_a) / tan_a);
        let dx = xn - u;
        v + (rc * rc - dx * dx).max(0.0).sqrt()
    };
    let (mut lo, mut hi) = (xn - rc, xn + rc);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (c1, c2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if top(c1) > top(c2) {
            hi = c2;
        } else {
            lo = c1;
        }
    }
    let best = top(0.5 * (lo + hi));
    let y = best.min(big_h);
    (h.ref_radius_mm + y)
        .min(sharp(d))
        .clamp(h.root_radius_mm, h.tip_radius_mm)
}

/// A workpiece point seen from the hob at time `t`: (ρ, hob angle φ from
/// the direction towards the gear axis, right-handed about u, axial a from
/// the hob's middle) and the hob angle B.
pub(crate) fn in_hob(tl: &Timeline, seg: usize, t: f64, p: [f64; 3]) -> (f64, f64, f64, f64) {
    let pose = tl.pose_in(seg, t);
    let (sc, cc) = pose.c_rad.sin_cos();
    // Workpiece → machine: turn by −C.
    let m = [p[0] * cc + p[1] * sc, -p[0] * sc + p[1] * cc, p[2]];
    let (se, ce) = pose.eta_rad.sin_cos();
    let u = [0.0, ce, -se];
    let w = [0.0, se, ce];
    let mid = [
        pose.axes.x_mm,
        pose.axes.y_mm * u[1],
        pose.axes.z_mm + pose.axes.y_mm * u[2],
    ];
    let v = [m[0] - mid[0], m[1] - mid[1], m[2] - mid[2]];
    let dot = |x: [f64; 3]| v[0] * x[0] + v[1] * x[1] + v[2] * x[2];
    let (s, tt, a) = (-v[0], dot(w), dot(u));
    ((s * s + tt * tt).sqrt(), tt.atan2(s), a, pose.b_rad)
}

/// A gash pass: the segment, the instant the gash points at the gear axis,
/// the gash, and the hob's turn rate ω, rad/s.
#[derive(Clone, Copy)]
struct Pass {
    seg: usize,
    t: f64,
    k: u32,
    omega: f64,
}

/// How far inside the gash's edge the point is when the gash's half-plane
/// passes it (negative: outside). The pose is the move's own, held at its
/// ends, as the simulation models a pass reaching past a move.
fn pass_depth(tl: &Timeline, h: &Hob, ps: Pass, p: [f64; 3]) -> f64 {
    // At t the gash points at the gear axis (hob angle 0); it stands at
    // ω·(τ − t) after. The point's hob angle stays near 0 while the gash
    // can reach it, so the difference has one root within half a turn.
    let f = |tau: f64| {
        let (_, phi, _, _) = in_hob(tl, ps.seg, tau, p);
        phi - ps.omega * (tau - ps.t)
    };
    let half = PI / ps.omega.abs();
    let (mut lo, mut hi) = (ps.t - 0.999 * half, ps.t + 0.999 * half);
    let mut flo = f(lo);
    for _ in 0..60 {
        let m = 0.5 * (lo + hi);
        let fm = f(m);
        if fm.signum() == flo.signum() {
            lo = m;
            flo = fm;
        } else {
            hi = m;
        }
    }
    let (rho, _, a, _) = in_hob(tl, ps.seg, 0.5 * (lo + hi), p);
    profile(h, ps.k, a) - rho
}

/// The passes of every move in which the hob turns (at B = 2πn/i, gash
/// −n mod i) whose gash stands within `reach` of the point at its instant.
fn passes(tl: &Timeline, h: &Hob, p: [f64; 3], reach: f64) -> Vec<Pass> {
    let mut out = vec![];
    let step = TAU / f64::from(h.gashes);
    for (seg, s) in tl.segments().iter().enumerate() {
        if s.hob_rev_s == 0.0 || s.t1_s <= s.t0_s {
            continue;
        }
        let omega = TAU * s.hob_rev_s;
        let b0 = tl.pose_in(seg, s.t0_s).b_rad;
        let b1 = tl.pose_in(seg, s.t1_s).b_rad;
        let mut n = (b0.min(b1) / step).ceil() as i64;
        while n as f64 * step <= b0.max(b1) {
            let t = s.t0_s + (n as f64 * step - b0) / omega;
            let (rho, _, a, _) = in_hob(tl, seg, t, p);
            if rho < h.tip_radius_mm + reach && a.abs() < h.length_mm / 2.0 + reach {
                let k = (-n).rem_euclid(i64::from(h.gashes)) as u32;
                out.push(Pass { seg, t, k, omega });
            }
            n += 1;
        }
    }
    out
}

/// The exact outline radius on the ray at `theta` in the section `z`: the
/// smallest radius in `r_lo..r_hi` a gash edge passes through (the cut part
/// of the ray taken as one interval reaching out to `r_hi`).
pub(crate) fn reference_radius(
    tl: &Timeline,
    h: &Hob,
    z: f64,
    theta: f64,
    r_lo: f64,
    r_hi: f64,
) -> f64 {
    let (st, ct) = theta.sin_cos();
    let at = |r: f64| [r * ct, r * st, z];
    // The table turns ≤ π·|C/B| (plus the differential) in half a hob turn:
    // points farther from the gash at a pass's instant cannot be reached in it.
    let ratio = tl
        .segments()
        .iter()
        .filter_map(|s| s.gearbox.map(|g| g.c_per_b.abs()))
        .fold(0.0, f64::max);
    let reach = r_hi * PI * ratio * 1.5 + 2.0 + (r_hi - r_lo);
    let mid = at(0.5 * (r_lo + r_hi));
    // A pass whose gash misses the bracket's middle by more than the
    // bracket (times the flank's slope) cannot reach into it.
    let cand: Vec<Pass> = passes(tl, h, mid, reach)
        .into_iter()
        .filter(|&ps| pass_depth(tl, h, ps, mid) > -8.0 * (r_hi - r_lo))
        .collect();
    let cut_at = |r: f64| {
        let p = at(r);
        cand.iter().any(|&ps| pass_depth(tl, h, ps, p) >= 0.0)
    };
    let (mut lo, mut hi) = (r_lo, r_hi);
    for _ in 0..40 {
        let m = 0.5 * (lo + hi);
        if cut_at(m) {
            hi = m;
        } else {
            lo = m;
        }
    }
    0.5 * (lo + hi)
}
