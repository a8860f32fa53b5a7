//! Balls, calipers and the tooth thickness on the outline of the middle
//! section.
//!
//! **A ball in the transverse section.** A ball of diameter DM touching
//! two helicoid flanks is, in the transverse plane of its centre, a circle
//! of radius DM/(2·cos βb) touching the two involutes: the flank normal
//! lies in the base tangent plane at βb to the transverse plane, so the
//! normal distance from the centre to a flank is its transverse distance
//! along the base tangent times cos βb (the property [`crate::size`] rests
//! on; exact for design flanks, to first order in the deviations for a cut
//! one). For a spur gear it is the ball (or pin) itself.
//!
//! **Where the ball rests.** The ball is put in the space and sinks towards
//! the axis: along the ray at angle γ it stops where it first meets the
//! outline, at the largest t with dist(t·u(γ), outline) ≤ R. That is exact
//! on the polygonal outline: the set of centres within R of a segment is a
//! capsule (two discs and a rectangle), whose far exit on the ray is found
//! in closed form. The resting place touches both flanks: the γ of least
//! t(γ), found by golden section (t(γ) falls towards one flank and rises
//! towards the other, one minimum). Its radial position gives the runout,
//! two centres the dimension over balls.
//!
//! **Span.** Two parallel jaws at angle ω over k consecutive teeth open to
//! the width W(ω) = max p·u − min p·u over the outline points p of the
//! teeth (u(ω) the jaws' normal; the support of a polygon is at a vertex).
//! Rocking the caliper, one reads the smallest opening, the minimum of W
//! near the symmetric direction. On design involutes W is the same for
//! every ω while both contacts stay on the involutes (the contacts lie on
//! one base tangent, rb times the angle between the flanks' base points
//! apart), the transverse span Wkt; the normal span is Wkt·cos βb. The jaws
//! of a disc micrometer reach only into the tooth spaces: only points at
//! or above the form circle count (the roots of the spaces beyond the outer
//! flanks would stick out past a jaw of unlimited depth), and ω stays where
//! both design contacts lie in the middle half of the room between the
//! form and tip form circles (roll lengths Wkt/2 ± rb·(ω − μ), μ the
//! symmetric direction): near the form circle the outline's points are
//! sparse along the flank, and a jaw resting there would read the chord
//! between them, about 1 µm thin at n = 16 384.

use super::flank::{Section, Tooth};
use super::report::{Runout, SizeResult};
use super::{GearSpec, Geometry};
use crate::pitch::runout_um;
use crate::size::Involute;
use crate::{check_range, Error};
use std::f64::consts::TAU;

type P2 = [f64; 2];

fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The largest t ≥ 0 with the point t·u within `r` of the segment ab, if
/// any: the far exit of the ray from the segment's capsule.
fn capsule_exit(a: P2, b: P2, u: P2, r: f64) -> Option<f64> {
    // The distance to the ray's line is linear along the segment: two ends
    // more than r off on one side keep the whole segment (and its capsule)
    // off the line.
    let (sa, sb) = (cross(u, a), cross(u, b));
    if (sa > r && sb > r) || (sa < -r && sb < -r) {
        return None;
    }
    let mut best: Option<f64> = None;
    let mut take = |t: f64| {
        if t >= 0.0 && best.is_none_or(|b| t > b) {
            best = Some(t);
        }
    };
    for p in [a, b] {
        let c = dot(p, u);
        let off2 = dot(p, p) - c * c;
        if off2 <= r * r {
            take(c + (r * r - off2).sqrt());
        }
    }
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = dot(d, d);
    let den = cross(u, d);
    if len2 > 0.0 && den.abs() > 1e-300 {
        let len = len2.sqrt();
        let nrm = [-d[1] / len, d[0] / len];
        for s in [-1.0, 1.0] {
            let q = [a[0] + s * r * nrm[0], a[1] + s * r * nrm[1]];
            let t = cross(q, d) / den;
            let lambda = dot([t * u[0] - q[0], t * u[1] - q[1]], d) / len2;
            if (0.0..=1.0).contains(&lambda) {
                take(t);
            }
        }
    }
    best
}

/// The outline points (x, y) of the samples from angle `from` to `to`.
fn points(sec: &Section<'_>, from: f64, to: f64) -> Vec<P2> {
    (sec.index_at(from)..=sec.index_at(to) + 1)
        .map(|i| {
            let (r, t) = (sec.at(i), sec.theta(i));
            [r * t.cos(), r * t.sin()]
        })
        .collect()
}

/// The minimum of `f` on [lo, hi] by golden section: (argument, value).
fn golden_min(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut fa, mut fb) = (f(a), f(b));
    for _ in 0..60 {
        if fa <= fb {
            hi = b;
            (b, fb) = (a, fa);
            a = hi - g * (hi - lo);
            fa = f(a);
        } else {
            lo = a;
            (a, fa) = (b, fb);
            b = lo + g * (hi - lo);
            fb = f(b);
        }
    }
    if fa <= fb {
        (a, fa)
    } else {
        (b, fb)
    }
}

/// The centre (radius, angle) of a circle of radius `r` resting in the
/// space whose middle is at `gap` (rad), the pitch angle being `pitch`.
fn ball_in_space(sec: &Section<'_>, gap: f64, pitch: f64, r: f64) -> Option<(f64, f64)> {
    let pts = points(sec, gap - pitch, gap + pitch);
    let height = |g: f64| {
        let u = [g.cos(), g.sin()];
        pts.windows(2)
            .filter_map(|w| capsule_exit(w[0], w[1], u, r))
            .fold(f64::NAN, f64::max)
    };
    let (g, t) = golden_min(gap - pitch / 4.0, gap + pitch / 4.0, |g| {
        let h = height(g);
        if h.is_nan() {
            f64::INFINITY
        } else {
            h
        }
    });
    t.is_finite().then_some((t, g))
}

/// The smallest opening of two parallel jaws over the outline points
/// `pts`, the jaws' normal near the angle `mu` + π/2 (mu the middle of the
/// tooth group), searched over ±`spread`.
fn caliper(pts: &[P2], mu: f64, spread: f64) -> f64 {
    let width = |w: f64| {
        let u = [-w.sin(), w.cos()];
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let s = dot(*p, u);
                (lo.min(s), hi.max(s))
            });
        hi - lo
    };
    // W(ω) is flat over a range on design flanks and may have more than one
    // dip on cut ones: a grid first, then golden section around its best.
    let steps = 32;
    let h = 2.0 * spread / f64::from(steps);
    let best = (0..=steps)
        .map(|i| mu - spread + h * f64::from(i))
        .map(|w| (w, width(w)))
        .fold((mu, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
    golden_min(best.0 - h, best.0 + h, width).1.min(best.1)
}

/// The ball touching the design flanks at the measuring diameter: its
/// centre lies on the base tangent through the contact, DM/(2·cos βb)
/// further out in roll length, and on the space's middle
/// ([`Involute::ball_centre_diameter_mm`]); bisection on DM for
/// √(rM² − rb²) − DM/(2·cos βb) = the contact's roll length.
fn default_ball(inv: &Involute, geo: &Geometry) -> Result<f64, Error> {
    let rb = geo.rb();
    let cos_bb = geo.base_helix_deg.to_radians().cos();
    let contact = ((geo.measuring_diameter_mm / 2.0).powi(2) - rb * rb).sqrt();
    let g = |dm: f64| match inv.ball_centre_diameter_mm(dm, geo.design_thickness_mm) {
        Ok(d) => ((d / 2.0).powi(2) - rb * rb).max(0.0).sqrt() - dm / (2.0 * cos_bb) - contact,
        Err(_) => f64::NEG_INFINITY,
    };
    let mn = inv.normal_module_mm;
    let (mut lo, mut hi) = (0.05 * mn, 5.0 * mn);
    if !(g(lo) < 0.0 && g(hi) > 0.0) {
        return Err(Error::OutOfRange {
            field: "ball_diameter_mm",
            expected: "a ball given in the spec (none between 0.05·mn and 5·mn touches at the measuring diameter)",
            got: f64::NAN,
        });
    }
    for _ in 0..100 {
        let m = (lo + hi) / 2.0;
        if g(m) < 0.0 {
            lo = m;
        } else {
            hi = m;
        }
    }
    Ok((lo + hi) / 2.0)
}

/// Mean and spread (max − min) of `v`.
fn mean_spread(v: &[f64]) -> (f64, f64) {
    let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    (mean, hi - lo)
}

/// Runout and size of the middle section `mid` whose teeth at the
/// measuring circle are `teeth`.
pub(super) fn size_and_runout(
    mid: &Section<'_>,
    teeth: &[Tooth],
    geo: &Geometry,
    spec: &GearSpec,
) -> Result<(Runout, SizeResult), Error> {
    let inv = spec.involute()?;
    let z = teeth.len();
    let pitch = TAU / z as f64;
    let cos_bb = geo.base_helix_deg.to_radians().cos();
    let ball = match spec.ball_diameter_mm {
        Some(b) => check_range("ball_diameter_mm", b, 1e-6, 1e6, "DM > 0")?,
        None => default_ball(&inv, geo)?,
    };
    let mut centres = Vec::with_capacity(z);
    for j in 0..z {
        let next = teeth[(j + 1) % z].left + if j + 1 == z { TAU } else { 0.0 };
        let gap = (teeth[j].right + next) / 2.0;
        let c = ball_in_space(mid, gap, pitch, ball / (2.0 * cos_bb)).ok_or(Error::OutOfRange {
            field: "ball_diameter_mm",
            expected: "a ball that rests on the flanks of every space",
            got: ball,
        })?;
        centres.push(c);
    }
    let radial: Vec<f64> = centres.iter().map(|c| c.0 * 1000.0).collect();
    let runout = Runout {
        ball_diameter_mm: ball,
        runout_um: runout_um(&radial)?,
        radial_um: radial,
    };
    let xy = |c: (f64, f64)| [c.0 * c.1.cos(), c.0 * c.1.sin()];
    let pairs: Vec<(usize, usize)> = if z % 2 == 0 {
        (0..z / 2).map(|i| (i, i + z / 2)).collect()
    } else {
        (0..z).map(|i| (i, (i + (z - 1) / 2) % z)).collect()
    };
    let over: Vec<f64> = pairs
        .iter()
        .map(|&(i, j)| {
            let (a, b) = (xy(centres[i]), xy(centres[j]));
            (a[0] - b[0]).hypot(a[1] - b[1]) + ball
        })
        .collect();
    let sn = geo.design_thickness_mm;
    let k = match spec.span_teeth {
        Some(k) => k,
        None => inv.span_teeth(sn)?,
    };
    check_range(
        "span_teeth",
        f64::from(k),
        1.0,
        z as f64 - 1.0,
        "1 ≤ k ≤ z − 1",
    )?;
    // The jaws may tilt while both contacts stay between the form and the
    // tip form circle: the contacts' roll lengths are Wkt/2 ± rb·Δω.
    let rb = geo.rb();
    let half = inv.span_mm(k, sn)? / cos_bb / 2.0;
    let roll = |d: f64| ((d / 2.0).powi(2) - rb * rb).max(0.0).sqrt();
    let room = (half - roll(geo.form_diameter_mm)).min(roll(geo.tip_form_diameter_mm) - half);
    if room <= 0.0 {
        return Err(Error::OutOfRange {
            field: "span_teeth",
            expected: "k teeth whose caliper contacts lie between the form and the tip form circle",
            got: f64::from(k),
        });
    }
    let form_r = geo.form_diameter_mm / 2.0;
    let spans: Vec<f64> = (0..z)
        .map(|j| {
            let first = teeth[j].centre();
            let last = first + pitch * f64::from(k - 1);
            let mut pts = points(mid, first - pitch / 2.0, last + pitch / 2.0);
            pts.retain(|p| p[0].hypot(p[1]) >= form_r);
            caliper(&pts, (first + last) / 2.0, 0.5 * room / rb) * cos_bb
        })
        .collect();
    let r_ref = geo.reference_diameter_mm / 2.0;
    let cos_b = spec.helix_deg.to_radians().cos();
    let mut thick = Vec::with_capacity(z);
    for t in teeth {
        let l = mid.crossing(t.centre(), r_ref, -1, pitch);
        let r = mid.crossing(t.centre(), r_ref, 1, pitch);
        let (Some(l), Some(r)) = (l, r) else {
            return Err(Error::OutOfRange {
                field: "sections",
                expected: "every tooth reaching the reference circle",
                got: r_ref,
            });
        };
        thick.push(r_ref * (r - l) * cos_b);
    }
    let (thickness, thickness_spread) = mean_spread(&thick);
    let (span, span_spread) = mean_spread(&spans);
    let (over_mean, over_spread) = mean_spread(&over);
    let size = SizeResult {
        design_thickness_mm: sn,
        thickness_mm: thickness,
        thickness_spread_um: thickness_spread * 1000.0,
        span_teeth: k,
        span_design_mm: inv.span_mm(k, sn)?,
        span_mm: span,
        span_spread_um: span_spread * 1000.0,
        span_thickness_mm: inv.thickness_from_span(k, span)?,
        ball_diameter_mm: ball,
        over_balls_design_mm: inv.over_balls_mm(ball, sn)?,
        over_balls_mm: over_mean,
        over_balls_spread_um: over_spread * 1000.0,
        over_balls_thickness_mm: inv.thickness_from_over_balls(ball, over_mean)?,
    };
    Ok((runout, size))
}
