//! Tolerance-bounded arc splines: the fewest circular arcs, each
//! joining the next without a corner (G1), that stay within a tolerance ε of
//! a smooth plane curve. Wire EDM and many controls cut only lines and arcs;
//! a spline of arcs is the exact program of such a path.
//!
//! # Method
//!
//! An arc spline starting at point p0 with tangent angle θ0 is fixed by each
//! arc's curvature κᵢ and length Lᵢ: it is G1 by construction. For k arcs
//! [`fit`] minimises the largest distance between the spline and the curve
//! over (θ0, κ1…κk, L1…Lk) — the start point is the curve's start (or a given
//! point, where the piece before ended); the end
//! point must come within ε of the curve's end, and a given start or end
//! tangent (to join a neighbouring piece without a corner) is kept — by the
//! Nelder–Mead simplex from a start that splits the curve into k pieces of
//! equal turning, restarted until it stalls. It tries k = 1, 2, … and returns
//! the first spline whose deviation, measured again densely and both ways by
//! [`deviation`] (independently of the optimiser's own samples), is within ε.
//! A count that [`impossible`] proves cannot pass that check is skipped
//! (see `bound` for the derivations); the result is unchanged.
//!
//! This is a minimax fit in the spirit of Maier (2014), "Optimal arc spline
//! approximation", and Drysdale, Rote and Sturm (2008), "Approximation of an
//! open polygonal curve with a minimum number of circular arcs and biarcs":
//! the arcs may straddle the curve, the junctions need not lie on it, so
//! fewer arcs suffice than for a biarc fit whose junctions sit on the curve.
//! Not proved optimal: k is the smallest this search finds.
//!
//! # Layout
//!
//! - this file: the curve, the arc, the options and [`fit`];
//! - `measure`: [`deviation`], each arc's constants worked out once and the
//!   arcs too far to be the nearest skipped (the same figure to the bit);
//! - `simplex`: the Nelder–Mead method, its vertices kept in place;
//! - `bound`: [`impossible`], proofs that one arc or two cannot pass the
//!   check (four curve points no circle passes near, and every 2-colouring
//!   of a dozen points leaving such four in one colour), so [`fit`] skips
//!   those counts with the same result as [`fit_exhaustive`].
#![forbid(unsafe_code)]

use std::f64::consts::{PI, TAU};

mod bound;
mod measure;
mod simplex;

pub use bound::impossible;
pub use measure::{deviation, CHECK_SAMPLES};
use simplex::nelder_mead;

/// A plane curve to approximate, over its parameter domain.
pub trait Curve {
    /// The parameter range `(t0, t1)`, t0 < t1.
    fn domain(&self) -> (f64, f64);
    /// The point at parameter `t`.
    fn point(&self, t: f64) -> (f64, f64);
    /// The tangent's angle at `t` (direction of increasing t), radians.
    fn tangent_angle(&self, t: f64) -> f64;
    /// The distance from `q` to the curve over its domain (exact where the
    /// curve allows, else a nearest-point search).
    fn distance(&self, q: (f64, f64)) -> f64;
    /// How a deviation at `t` counts against the fit's tolerance: the
    /// tolerance over the tolerance of this place (1 by default; a curve
    /// joined of pieces with their own tolerances says more).
    fn scale_at(&self, _t: f64) -> f64 {
        1.0
    }
}

/// A curve sampled densely once, for a fast distance: a polyline through
/// `n` + 1 points of it. The distance to the polyline is within
/// [`Sampled::sag`] of the distance to the curve (a chord's sagitta,
/// ≈ chord · turning / 8, at most), so with a few thousand points it is
/// exact to far below a micrometre; it finds the nearest point by a scan of
/// every 16th point and a walk down from the best, then takes its chords.
#[derive(Debug, Clone, PartialEq)]
pub struct Sampled {
    points: Vec<(f64, f64)>,
    angles: Vec<f64>,
    sag: f64,
}

/// Points per coarse step of [`Sampled`]'s search.
const COARSE: usize = 16;

impl Sampled {
    /// `curve` sampled at `n` + 1 equally spaced parameters (n ≥ 2).
    pub fn new(curve: &dyn Curve, n: usize) -> Sampled {
        let n = n.max(2);
        let (t0, t1) = curve.domain();
        let ts = (0..=n).map(|i| t0 + (t1 - t0) * i as f64 / n as f64);
        let points: Vec<(f64, f64)> = ts.clone().map(|t| curve.point(t)).collect();
        let angles: Vec<f64> = ts.map(|t| curve.tangent_angle(t)).collect();
        let sag = points
            .windows(2)
            .zip(angles.windows(2))
            .map(|(p, a)| {
                let chord = ((p[1].0 - p[0].0).powi(2) + (p[1].1 - p[0].1).powi(2)).sqrt();
                chord * (a[1] - a[0]).abs() / 8.0
            })
            .fold(0.0, f64::max);
        Sampled {
            points,
            angles,
            sag,
        }
    }

    /// The largest sagitta of a chord: how far the polyline may lie from
    /// the curve, mm.
    pub fn sag(&self) -> f64 {
        self.sag
    }

    /// The polyline's points, as sampled.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The coarse step of the nearest-point search: every this many points,
    /// and the last one, are scanned first.
    pub const COARSE: usize = COARSE;

    /// The distance from `q` to the polyline, from the point `start` (the
    /// nearest coarse point): walks down to the nearest point, then takes
    /// the two chords beside it. On a dense polyline of a smooth curve the
    /// nearest point of the polyline lies on a chord beside it (and were it
    /// not, the chords give more, not less, than the distance: a check stays
    /// on the safe side).
    pub fn distance_from(&self, start: usize, q: (f64, f64)) -> f64 {
        let n = self.points.len() - 1;
        let d2 = |p: (f64, f64)| (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2);
        let mut i = start;
        // The current point's square kept, not taken again each step.
        let mut here = d2(self.points[i]);
        while i > 0 {
            let next = d2(self.points[i - 1]);
            if next >= here {
                break;
            }
            (i, here) = (i - 1, next);
        }
        while i < n {
            let next = d2(self.points[i + 1]);
            if next >= here {
                break;
            }
            (i, here) = (i + 1, next);
        }
        let before = if i > 0 {
            self.chord_distance2(i - 1, q)
        } else {
            f64::INFINITY
        };
        let after = if i < n {
            self.chord_distance2(i, q)
        } else {
            f64::INFINITY
        };
        // One square root: it keeps order and rounds correctly, so the
        // root of the smaller square is the smaller root.
        before.min(after).sqrt()
    }

    /// The square of the distance from `q` to the chord from point `i`.
    fn chord_distance2(&self, i: usize, q: (f64, f64)) -> f64 {
        let (a, b) = (self.points[i], self.points[i + 1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let l2 = dx * dx + dy * dy;
        let u = if l2 > 0.0 {
            (((q.0 - a.0) * dx + (q.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a.0 + u * dx - q.0).powi(2) + (a.1 + u * dy - q.1).powi(2)
    }
}

impl Curve for Sampled {
    fn domain(&self) -> (f64, f64) {
        (0.0, (self.points.len() - 1) as f64)
    }
    fn point(&self, t: f64) -> (f64, f64) {
        let n = self.points.len() - 1;
        let i = (t.floor().max(0.0) as usize).min(n - 1);
        let u = t - i as f64;
        let (a, b) = (self.points[i], self.points[i + 1]);
        (a.0 + u * (b.0 - a.0), a.1 + u * (b.1 - a.1))
    }
    fn tangent_angle(&self, t: f64) -> f64 {
        let n = self.points.len() - 1;
        let i = (t.floor().max(0.0) as usize).min(n - 1);
        let u = t - i as f64;
        self.angles[i] + u * (self.angles[i + 1] - self.angles[i])
    }
    fn distance(&self, q: (f64, f64)) -> f64 {
        let n = self.points.len() - 1;
        let d2 = |p: (f64, f64)| (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2);
        let best = (0..=n)
            .step_by(COARSE)
            .chain(std::iter::once(n))
            .min_by(|&a, &b| d2(self.points[a]).total_cmp(&d2(self.points[b])))
            .expect("points");
        self.distance_from(best, q)
    }
}

/// One arc of a spline (a line when the curvature is 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// Start point.
    pub start: (f64, f64),
    /// Tangent angle at the start, radians.
    pub start_angle: f64,
    /// Signed curvature, 1/mm: positive turns left (counter-clockwise).
    pub curvature: f64,
    /// Length along the arc, mm (≥ 0).
    pub length: f64,
}

impl Arc {
    /// The point `s` along the arc.
    pub fn point_at(&self, s: f64) -> (f64, f64) {
        let a = self.start_angle;
        self.point_with(a.sin(), a.cos(), s)
    }

    /// [`Arc::point_at`] with the start angle's sine and cosine given (a
    /// caller taking many points of one arc works them out once): the same
    /// operations on the same values, so the same point to the last bit.
    pub(crate) fn point_with(&self, sin_a: f64, cos_a: f64, s: f64) -> (f64, f64) {
        let (x, y) = self.start;
        let a = self.start_angle;
        let k = self.curvature;
        if (k * s).abs() < 1e-9 {
            // A line, or an arc so flat that the series is exact to 1e-18 mm.
            let h = 0.5 * k * s * s;
            return (x + s * cos_a - h * sin_a, y + s * sin_a + h * cos_a);
        }
        (
            x + ((a + k * s).sin() - sin_a) / k,
            y - ((a + k * s).cos() - cos_a) / k,
        )
    }

    /// The end point.
    pub fn end(&self) -> (f64, f64) {
        self.point_at(self.length)
    }

    /// The tangent angle at the end.
    pub fn end_angle(&self) -> f64 {
        self.start_angle + self.curvature * self.length
    }

    /// The centre and radius, or `None` for a line.
    pub fn circle(&self) -> Option<((f64, f64), f64)> {
        if self.curvature.abs() < 1e-12 {
            return None;
        }
        let r = 1.0 / self.curvature;
        let a = self.start_angle;
        Some((
            (self.start.0 - r * a.sin(), self.start.1 + r * a.cos()),
            r.abs(),
        ))
    }

    /// The distance from `q` to the arc (exact).
    pub fn distance(&self, q: (f64, f64)) -> f64 {
        let d = |p: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
        let ends = d(self.start).min(d(self.end()));
        match self.circle() {
            None => {
                // Project on the segment.
                let (c, s) = (self.start_angle.cos(), self.start_angle.sin());
                let u =
                    ((q.0 - self.start.0) * c + (q.1 - self.start.1) * s).clamp(0.0, self.length);
                d((self.start.0 + u * c, self.start.1 + u * s))
            }
            Some((centre, r)) => {
                // The angle from the start, in the arc's sense, of q's direction.
                let sense = self.curvature.signum();
                let a0 = (self.start.1 - centre.1).atan2(self.start.0 - centre.0);
                let aq = (q.1 - centre.1).atan2(q.0 - centre.0);
                let rel = (sense * (aq - a0)).rem_euclid(TAU);
                if rel <= self.curvature.abs() * self.length {
                    (d(centre) - r).abs()
                } else {
                    ends
                }
            }
        }
    }
}

/// What [`fit`] is asked for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// The tolerance ε, mm.
    pub tolerance: f64,
    /// The start point, when the spline must begin where the piece before
    /// it ended (within the tolerance of the curve's start); else the
    /// curve's start.
    pub start_point: Option<(f64, f64)>,
    /// The start tangent's angle the spline must keep (to join the piece
    /// before it without a corner), or free.
    pub start_angle: Option<f64>,
    /// The end tangent's angle the spline must keep, or free.
    pub end_angle: Option<f64>,
    /// The end point the spline must reach exactly, with `end_angle` (to
    /// join the piece after it without a gap or corner): the last two arcs
    /// are then the biarc from the arcs before them to this point and
    /// tangent, and the fit starts at two arcs.
    pub end_point: Option<(f64, f64)>,
    /// How close the end must come to the curve's end, mm, when closer
    /// than the tolerance (where a piece of a finer tolerance follows).
    pub end_tolerance: Option<f64>,
    /// The smallest arc radius allowed (e.g. what a wire can cut), mm.
    pub min_radius: f64,
    /// The most arcs tried.
    pub max_arcs: usize,
}

impl Options {
    /// A tolerance, both tangents free, no radius limit, up to 12 arcs.
    pub fn tolerance(tolerance: f64) -> Options {
        Options {
            tolerance,
            start_point: None,
            start_angle: None,
            end_angle: None,
            end_point: None,
            end_tolerance: None,
            min_radius: 0.0,
            max_arcs: 12,
        }
    }
}

/// An arc spline within the tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Fit {
    /// The arcs, in order along the curve.
    pub arcs: Vec<Arc>,
    /// The deviation measured by [`deviation`], mm.
    pub max_deviation: f64,
}

/// Why no spline was found.
#[derive(Debug, Clone, PartialEq)]
pub struct FitError {
    /// The arcs tried at the most.
    pub max_arcs: usize,
    /// The smallest deviation reached with that many, mm.
    pub best_deviation: f64,
}

impl std::fmt::Display for FitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "no arc spline of at most {} arcs within the tolerance; the best came within {:.6} mm",
            self.max_arcs, self.best_deviation
        )
    }
}

impl std::error::Error for FitError {}

/// The arc from `p` with the tangent angle `a` through `q`.
fn arc_to(p: (f64, f64), a: f64, q: (f64, f64)) -> Arc {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let chord = (dx * dx + dy * dy).sqrt();
    // The angle from the tangent to the chord: the arc turns twice that.
    let psi = (dy.atan2(dx) - a + PI).rem_euclid(TAU) - PI;
    let (curvature, length) = if psi.abs() < 1e-12 {
        (0.0, chord)
    } else {
        (2.0 * psi.sin() / chord, chord * psi / psi.sin())
    };
    Arc {
        start: p,
        start_angle: a,
        curvature,
        length,
    }
}

/// The biarc from `p0` with the tangent angle `a0` to `p1` with `a1`: two
/// arcs through the junction J = (d2·q1 + d1·q2)/(d1 + d2), q1 = p0 + d1·t0,
/// q2 = p1 − d2·t1, where the tangent legs d1, d2 satisfy
/// |q2 − q1| = d1 + d2, i.e. d2 = (v·v/2 − d1·v·t0)/(v·t1 + d1·(1 − t0·t1)),
/// v = p1 − p0. `scale` is d1 over the equal-legs d1 = d2; `None` when a
/// leg would not be positive.
fn biarc(p0: (f64, f64), a0: f64, p1: (f64, f64), a1: f64, scale: f64) -> Option<[Arc; 2]> {
    let dot = |a: (f64, f64), b: (f64, f64)| a.0 * b.0 + a.1 * b.1;
    let (t0, t1) = ((a0.cos(), a0.sin()), (a1.cos(), a1.sin()));
    let v = (p1.0 - p0.0, p1.1 - p0.1);
    let (vv, t01) = (dot(v, v), dot(t0, t1));
    // Equal legs: 2(1 − t0·t1)·d² + 2·v·(t0 + t1)·d − v·v = 0.
    let (qa, qb) = (2.0 * (1.0 - t01), 2.0 * dot(v, (t0.0 + t1.0, t0.1 + t1.1)));
    let equal = if qa.abs() < 1e-12 {
        vv / qb
    } else {
        (-qb + (qb * qb + 4.0 * qa * vv).sqrt()) / (2.0 * qa)
    };
    let d1 = equal * scale;
    let den = dot(v, t1) + d1 * (1.0 - t01);
    let d2 = (vv / 2.0 - d1 * dot(v, t0)) / den;
    if !(d1 > 0.0 && d2 > 0.0 && d1.is_finite() && d2.is_finite()) {
        return None;
    }
    let (q1, q2) = (
        (p0.0 + d1 * t0.0, p0.1 + d1 * t0.1),
        (p1.0 - d2 * t1.0, p1.1 - d2 * t1.1),
    );
    let j = (
        (d2 * q1.0 + d1 * q2.0) / (d1 + d2),
        (d2 * q1.1 + d1 * q2.1) / (d1 + d2),
    );
    let first = arc_to(p0, a0, j);
    let second = arc_to(j, first.end_angle(), p1);
    Some([first, second])
}

/// Whether the spline must end on a given point and tangent (its last two
/// arcs a biarc).
fn ends_fixed(o: &Options) -> bool {
    o.end_point.is_some() && o.end_angle.is_some()
}

/// The free arcs of a k-arc spline (the biarc's two are not).
fn free_arcs(o: &Options, k: usize) -> usize {
    if ends_fixed(o) {
        k - 2
    } else {
        k
    }
}

/// The spline of the parameters x = (θ0 offset, κ…, L…[, biarc scale]);
/// `None` when the closing biarc does not exist.
fn spline(curve: &dyn Curve, o: &Options, x: &[f64], k: usize) -> Option<Vec<Arc>> {
    let (t0, _) = curve.domain();
    let mut angle = match o.start_angle {
        Some(a) => a,
        None => curve.tangent_angle(t0) + x[0],
    };
    let mut p = o.start_point.unwrap_or_else(|| curve.point(t0));
    let n = free_arcs(o, k);
    let mut arcs = Vec::with_capacity(k);
    for i in 0..n {
        let a = Arc {
            start: p,
            start_angle: angle,
            curvature: x[1 + i],
            length: x[1 + n + i].abs(),
        };
        p = a.end();
        angle = a.end_angle();
        arcs.push(a);
    }
    if let (Some(q), Some(b)) = (o.end_point, o.end_angle) {
        arcs.extend(biarc(p, angle, q, b, x[1 + 2 * n].exp())?);
    }
    Some(arcs)
}

/// Samples per arc of the optimiser's cost.
const COST_SAMPLES: usize = 12;

/// The [`COST_SAMPLES`] points of the optimiser's cost along `a`, at
/// s = L·i/n, i = 1…n, with one sine and cosine per arc.
///
/// A point of the arc is p0 + ((sin(a + κs) − sin a), −(cos(a + κs) −
/// cos a))/κ = p0 + (2/κ)·sin(κs/2)·(cos(a + κs/2), sin(a + κs/2)) (sum
/// to product), a chord of length (2/κ)·sin(κs/2) along the mean angle.
/// At s = L·i/n both κs/2 = i·h and a + κs/2 = a + i·h with h = κL/(2n),
/// so the two unit vectors (cos ih, sin ih) and (cos(a + ih), sin(a + ih))
/// are turned by h from one sample to the next (a rotation by the one
/// sin h, cos h): no cancellation, a rounding of a few units in the last
/// place after n turns (the test holds the points to [`Arc::point_at`]
/// within 10⁻¹² mm). A line, or an arc so flat that [`Arc::point_at`]
/// takes its series, takes [`Arc::point_at`]'s own points.
fn cost_samples(a: &Arc) -> impl Iterator<Item = (f64, f64)> + '_ {
    let n = COST_SAMPLES as f64;
    let k = a.curvature;
    let flat = (k * a.length).abs() < 1e-9;
    let (sin_a, cos_a) = a.start_angle.sin_cos();
    let (sh, ch) = (0.5 * k * a.length / n).sin_cos();
    // (cos ih, sin ih) and (cos(a + ih), sin(a + ih)), from i = 0.
    let mut half = (1.0, 0.0);
    let mut mean = (cos_a, sin_a);
    (1..=COST_SAMPLES).map(move |i| {
        if flat {
            return a.point_with(sin_a, cos_a, a.length * i as f64 / n);
        }
        let turn = |v: (f64, f64)| (v.0 * ch - v.1 * sh, v.1 * ch + v.0 * sh);
        half = turn(half);
        mean = turn(mean);
        let chord = 2.0 / k * half.1;
        (a.start.0 + chord * mean.0, a.start.1 + chord * mean.1)
    })
}

/// The optimiser's cost: the largest sampled distance of the spline from
/// the curve, the end point's gap, the end tangent's miss (as a distance
/// over the last arc), and a penalty below the radius limit.
///
/// Once the largest distance so far reaches `bound` the rest is not
/// measured: the cost is then at least that (every later term is a max),
/// and the simplex asks for no more (see `simplex`).
fn cost(curve: &dyn Curve, o: &Options, x: &[f64], k: usize, bound: f64) -> f64 {
    let Some(arcs) = spline(curve, o, x, k) else {
        // No closing biarc: far worse than any spline.
        return 1e3 * o.tolerance.max(1.0);
    };
    let (_, t1) = curve.domain();
    let mut worst: f64 = 0.0;
    for a in &arcs {
        for q in cost_samples(a) {
            worst = worst.max(curve.distance(q));
            if worst >= bound {
                return worst;
            }
        }
        if o.min_radius > 0.0 && a.curvature.abs() * o.min_radius > 1.0 {
            worst = worst.max(o.tolerance * (1.0 + a.curvature.abs() * o.min_radius));
        }
    }
    if ends_fixed(o) {
        return worst;
    }
    let last = arcs.last().expect("k ≥ 1");
    let e = last.end();
    let goal = curve.point(t1);
    let gap = ((e.0 - goal.0).powi(2) + (e.1 - goal.1).powi(2)).sqrt();
    // The end gap counts against its own limit, scaled to the tolerance.
    let end_limit = o.end_tolerance.unwrap_or(o.tolerance).min(o.tolerance);
    worst = worst.max(gap * o.tolerance / end_limit);
    if let Some(want) = o.end_angle {
        let miss =
            (last.end_angle() - want + std::f64::consts::PI).rem_euclid(TAU) - std::f64::consts::PI;
        worst = worst.max(miss.abs() * last.length.max(o.tolerance));
    }
    worst
}

/// A start for k arcs: the curve cut into k pieces of equal turning (by a
/// dense walk; turning either way counts), each of the first `free` arcs
/// with its piece's mean curvature and length (and a closing biarc of equal
/// legs when `biarc`).
fn start(curve: &dyn Curve, k: usize, free: usize, biarc: bool) -> Vec<f64> {
    let (t0, t1) = curve.domain();
    const N: usize = 400;
    let ts: Vec<f64> = (0..=N)
        .map(|i| t0 + (t1 - t0) * i as f64 / N as f64)
        .collect();
    let angle: Vec<f64> = ts.iter().map(|&t| curve.tangent_angle(t)).collect();
    let mut len = vec![0.0; N + 1];
    for i in 1..=N {
        let (a, b) = (curve.point(ts[i - 1]), curve.point(ts[i]));
        len[i] = len[i - 1] + ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
    }
    // The turning so far, counted both ways (a curve may turn back: an
    // S between two pieces).
    let mut turned = vec![0.0; N + 1];
    for i in 1..=N {
        turned[i] = turned[i - 1] + (angle[i] - angle[i - 1]).abs();
    }
    let turn = |i: usize| turned[i];
    let total = turn(N).max(1e-12);
    let mut cuts = vec![0usize];
    for j in 1..k {
        let goal = total * j as f64 / k as f64;
        let i = (1..N).find(|&i| turn(i) >= goal).unwrap_or(N * j / k);
        cuts.push(i.max(cuts[j - 1] + 1).min(N - (k - j)));
    }
    cuts.push(N);
    let mut x = vec![0.0; 1 + 2 * free + usize::from(biarc)];
    for j in 0..free {
        let (a, b) = (cuts[j], cuts[j + 1]);
        let l = (len[b] - len[a]).max(1e-9);
        x[1 + j] = (angle[b] - angle[a]) / l;
        x[1 + free + j] = l;
    }
    x
}

/// The fewest-arcs spline within `o.tolerance` of `curve` (see the module).
/// Counts proven unable to pass the check ([`impossible`]) are skipped:
/// each count's attempt starts afresh, so the result is [`fit_exhaustive`]'s
/// (when every count fails, the skipped ones are tried after all, for the
/// error's best deviation).
pub fn fit(curve: &dyn Curve, o: &Options) -> Result<Fit, FitError> {
    search(curve, o, true)
}

/// [`fit`] trying every count from the first, proofs or not: the reference
/// the proofs are checked against.
pub fn fit_exhaustive(curve: &dyn Curve, o: &Options) -> Result<Fit, FitError> {
    search(curve, o, false)
}

fn search(curve: &dyn Curve, o: &Options, prove: bool) -> Result<Fit, FitError> {
    let mut best_dev = f64::INFINITY;
    let first_k = if ends_fixed(o) { 2 } else { 1 };
    let mut skipped = Vec::new();
    for k in first_k..=o.max_arcs {
        if prove && impossible(curve, o, k) {
            skipped.push(k);
            continue;
        }
        match attempt(curve, o, k) {
            Ok(fit) => return Ok(fit),
            Err(d) => best_dev = best_dev.min(d),
        }
    }
    // Every count tried failed. The skipped ones in order: the first that
    // passed would have been the answer (it cannot, if the proofs hold).
    for k in skipped {
        match attempt(curve, o, k) {
            Ok(fit) => return Ok(fit),
            Err(d) => best_dev = best_dev.min(d),
        }
    }
    Err(FitError {
        max_arcs: o.max_arcs,
        best_deviation: best_dev,
    })
}

/// One count's fit from its own start: the spline if it passes the check,
/// else the deviation it came to (measured, or the optimiser's cost).
fn attempt(curve: &dyn Curve, o: &Options, k: usize) -> Result<Fit, f64> {
    let target = 0.97 * o.tolerance;
    let x0 = start(curve, k, free_arcs(o, k), ends_fixed(o));
    let f = |y: &[f64], bound: f64| cost(curve, o, y, k, bound);
    // Two simplex sizes for the start tangent (the optimiser stalls in
    // different places); the better result is kept.
    let mut runs = [1e-2, 1e-3].into_iter().map(|step| {
        let scale: Vec<f64> = x0
            .iter()
            .enumerate()
            .map(|(i, v)| {
                if i == 0 {
                    step
                } else if i == x0.len() - 1 && ends_fixed(o) {
                    0.2 // the biarc's scale, a logarithm
                } else {
                    0.05 * v.abs().max(1e-6)
                }
            })
            .collect();
        let mut x = x0.clone();
        let mut fx = f(&x, f64::INFINITY);
        // Restart from the best point until a restart gains under 0.1 %.
        for round in 0..30 {
            let (y, fy) = nelder_mead(&f, &x, &scale, 600 * (1 + 2 * k), target);
            let gain = fx - fy;
            x = y;
            fx = fy;
            // Far off after a round: more arcs are needed, not more rounds.
            if fx <= target || gain < 1e-3 * fx || (round == 0 && fx > 4.0 * target) {
                break;
            }
        }
        (x, fx)
    });
    // The second size only when the first did not reach the target.
    let first = runs.next().expect("two starts");
    let (x, fx) = if first.1 <= target {
        first
    } else {
        let second = runs.next().expect("two starts");
        if second.1 < first.1 {
            second
        } else {
            first
        }
    };
    if let (true, Some(arcs)) = (fx <= target, spline(curve, o, &x, k)) {
        let d = deviation(curve, &arcs, CHECK_SAMPLES);
        let (_, t1) = curve.domain();
        let goal = o.end_point.unwrap_or_else(|| curve.point(t1));
        let e = arcs.last().expect("k ≥ 1").end();
        let gap = ((e.0 - goal.0).powi(2) + (e.1 - goal.1).powi(2)).sqrt();
        if d <= o.tolerance && gap <= o.end_tolerance.unwrap_or(o.tolerance) {
            return Ok(Fit {
                arcs,
                max_deviation: d,
            });
        }
        Err(d)
    } else {
        Err(fx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Part of an ellipse, x = 3 cos t, y = 2 sin t, t from 0 to 2.
    struct Ellipse;

    impl Curve for Ellipse {
        fn domain(&self) -> (f64, f64) {
            (0.0, 2.0)
        }
        fn point(&self, t: f64) -> (f64, f64) {
            (3.0 * t.cos(), 2.0 * t.sin())
        }
        fn tangent_angle(&self, t: f64) -> f64 {
            (2.0 * t.cos()).atan2(-3.0 * t.sin())
        }
        /// A finer polyline's (the test asks only the coarser one).
        fn distance(&self, q: (f64, f64)) -> f64 {
            Sampled::new(self, 1 << 14).distance(q)
        }
    }

    /// The polyline's distance against every chord's, by brute force: at
    /// points near the curve (within 0.2 mm either side, and beyond its
    /// ends) the nearest chord is one beside the nearest point, so the two
    /// agree to the bit; anywhere, the walk's is never less.
    #[test]
    fn the_polyline_distance_is_the_nearest_chords() {
        let s = Sampled::new(&Ellipse, 1024);
        let p = s.points();
        let brute = |q: (f64, f64)| -> f64 {
            p.windows(2)
                .map(|w| {
                    let (a, b) = (w[0], w[1]);
                    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                    let l2 = dx * dx + dy * dy;
                    let u = (((q.0 - a.0) * dx + (q.1 - a.1) * dy) / l2).clamp(0.0, 1.0);
                    ((a.0 + u * dx - q.0).powi(2) + (a.1 + u * dy - q.1).powi(2)).sqrt()
                })
                .fold(f64::INFINITY, f64::min)
        };
        let mut near = 0;
        for i in 0..=2000 {
            let t = -0.1 + 2.2 * f64::from(i) / 2000.0;
            let (c, n) = (Ellipse.point(t), (2.0 * t.cos(), 3.0 * t.sin()));
            let len = n.0.hypot(n.1);
            for off in [-0.2, -0.01, 0.0, 1e-4, 0.05, 0.2, 1.5, 4.0] {
                let q = (c.0 + off * n.0 / len, c.1 + off * n.1 / len);
                let (fast, sure) = (s.distance(q), brute(q));
                if f64::abs(off) <= 0.2 {
                    assert_eq!(fast.to_bits(), sure.to_bits(), "{q:?}: {fast} vs {sure}");
                    near += 1;
                } else {
                    assert!(fast >= sure, "{q:?}: {fast} vs {sure}");
                }
            }
        }
        assert!(near > 10_000);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]

        /// The cost's turned samples against [`Arc::point_at`] at the same
        /// lengths: arcs both ways, tight and nearly straight, short and
        /// up to most of a turn, lines, within 10⁻¹² mm.
        #[test]
        fn the_cost_samples_are_the_arcs_points(
            start in (-50.0..50.0f64, -50.0..50.0f64),
            start_angle in -7.0..7.0f64,
            radius_exp in -2.5..7.0f64,
            sense in prop_oneof![Just(1.0), Just(-1.0), Just(0.0)],
            turn in 0.0..6.0f64,
            flat_len in 0.0..20.0f64,
        ) {
            let curvature = sense / 10f64.powf(radius_exp);
            // Up to `turn` radians of the circle, or a length on a line.
            let length = if curvature == 0.0 { flat_len } else { turn / curvature.abs() };
            let a = Arc { start, start_angle, curvature, length };
            let mut n = 0;
            for (i, p) in cost_samples(&a).enumerate() {
                let q = a.point_at(a.length * (i + 1) as f64 / COST_SAMPLES as f64);
                let scale = 1.0 + a.length;
                prop_assert!(
                    (p.0 - q.0).hypot(p.1 - q.1) < 1e-12 * scale,
                    "{a:?} {i}: {p:?} vs {q:?}"
                );
                n += 1;
            }
            prop_assert_eq!(n, COST_SAMPLES);
        }
    }
}
