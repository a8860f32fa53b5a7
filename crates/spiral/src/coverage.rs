//! Whether the tool covers the face: proved from the spiral in closed form
//! ([`prove_coverage`], what the model runs) and checked by sampling
//! ([`coverage`], the independent reference the tests hold the proof to).
//!
//! # The proof
//!
//! The tool's centre runs along the path the program cuts (chords or arcs),
//! which strays at most δ from the spiral: every point of the spiral has a
//! point of the path within δ. A point within w = R − δ of the spiral is
//! then within R (the tool's radius) of the path, and under the tool. So it
//! is enough that every point of the annulus Ri ≤ ρ ≤ Ro lies within w of
//! the spiral.
//!
//! **Crossings.** The spiral r(φ) = R1 + b·φ, polar angle a(φ) = θ0 +
//! sense·φ, φ ∈ [0, 2πn], crosses the ray at polar angle ψ wherever
//! a(φ) ≡ ψ (mod 2π): at φψ + 2πj, so at radii L apart, L = |R2 − R1| / n
//! the step-over (the Archimedean spiral's pitch). With n whole turns the
//! crossings on every ray run from an innermost ρin(ψ) ∈ [Rin, Rin + L) to
//! an outermost ρout(ψ) ∈ (Rout − L, Rout], Rin = min(R1, R2),
//! Rout = max(R1, R2); as ψ goes round, ρin(ψ) takes every value of
//! [Rin, Rin + L) and ρout(ψ) every value of (Rout − L, Rout].
//!
//! **The band along a ray.** The tool's disc about a crossing at radius ρk
//! covers the ray from ρk − w to ρk + w: the disc's centre is on the ray.
//! So the band a turn sweeps is at least w wide either side of the turn
//! along any ray — not less: the band is 2w wide across the path, and the
//! path crosses the ray at an angle β from the ray's normal
//! (tan β = L / (2π·ρk)), so along the ray the band is about 2w / cos β
//! wide, wider than 2w. The discs of the path's points off the ray only
//! add to that; the proof takes w, a proven lower bound.
//!
//! **The conditions.** The ray's part Ri ≤ ρ ≤ Ro is covered when the
//! segments [ρk − w, ρk + w] of its crossings chain without a gap from
//! below Ri to above Ro:
//!
//! 1. *Between turns*: neighbouring crossings, L apart, overlap:
//!    **L ≤ 2w**. (Needed only where a gap between turns could meet the
//!    face: the gaps lie within (Rin + w, Rout − w).)
//! 2. *Inner edge*: the innermost turn reaches past Ri on every ray,
//!    ρin(ψ) − w ≤ Ri for all ψ: **Rin + L − w ≤ Ri** (the planner's end
//!    radius R2 = Ri + R − L − inner overtravel meets it with the inner
//!    overtravel's margin less δ). A spiral through the centre (Rin = 0)
//!    has a crossing at the centre on every ray and meets it always.
//! 3. *Outer edge*: the outermost turn reaches past Ro on every ray:
//!    **Rout − L + w ≥ Ro** (the start R1 = Ro + R + outer overtravel
//!    meets it with L ≤ 2R − δ + the overtravel).
//!
//! The three together cover every ray, so the annulus. The edge conditions
//! are the supremum over the rays: the crossing Rin + L is approached only
//! on the rays just beside the spiral's inner end, where the end point's own
//! disc helps. So an edge whose condition fails, by s, is also proved when
//! the end point's disc (radius w about the end E, |E| = Rin) covers what
//! the rays near it leave: on the ray at the angle u from the end's ray the
//! innermost crossing is Rin + L − L·u/2π, so the uncovered radii lie
//! within [Ri, Ri + s − L·u/2π], on the rays up to u = 2π·s/L. The squared
//! distance from E, ρ² + Rin² − 2ρ·Rin·cos u, is convex in ρ, so the
//! range's two ends decide on each ray; the rays are taken in 64 pieces of
//! angle, each with its widest range and its smallest cos u, which bounds
//! every ray of the piece. Likewise at the outer edge with the outer end
//! (Rout) and the radii [Ro − s + L·u/2π, Ro].
//!
//! **What is left when it fails.** Each failed condition bounds the gap
//! from above along the rays: a point between turns lies at most L/2 from
//! a crossing, a point inside the innermost turn at most Rin + L − Ri, one
//! outside the outermost at most Ro − (Rout − L). The proof reports the
//! largest shortfall, L/2 − w, Rin + L − w − Ri or Ro − (Rout − L + w):
//! an upper bound of how far a point of the face lies beyond the tool's
//! edge. It is close between turns (the true gap is (L/2)·cos β − R at the
//! face's largest radius there, β small) and at most about L/2 too high at
//! an edge (the end point's disc covers the crescent near the end).
//!
//! **Iff.** The conditions are sufficient. They are necessary up to two
//! margins: the band along a ray is w / cos β, not w, so a face with
//! 2w < L ≤ 2w / cos β is covered and not proved; and an edge condition
//! can fail where the end disc and the off-ray discs still cover. The
//! property test (`tests/coverage_proof.rs`) holds the proof to the
//! sampled check outside those margins and the sampling's resolution.

use serde::{Deserialize, Serialize};

use crate::{Region, Spiral};

/// The 5 × 5 cells around a sample's, the nearest first.
const NEIGHBOURS: [(i64, i64); 25] = {
    let mut out = [(0, 0); 25];
    let mut n = 0;
    let mut ring: i64 = 0;
    while ring <= 2 {
        let mut ox: i64 = -2;
        while ox <= 2 {
            let mut oy: i64 = -2;
            while oy <= 2 {
                let cheb = if ox.abs() > oy.abs() {
                    ox.abs()
                } else {
                    oy.abs()
                };
                if cheb == ring {
                    out[n] = (ox, oy);
                    n += 1;
                }
                oy += 1;
            }
            ox += 1;
        }
        ring += 1;
    }
    out
};

/// What the coverage check found.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Coverage {
    /// True when every sampled point of the region lies under the tool.
    pub ok: bool,
    /// The largest distance of a region point beyond the tool's edge
    /// (0 when covered), mm.
    pub max_gap_mm: f64,
    /// Where that point is (x, y), mm.
    pub worst_point: (f64, f64),
    /// Points of the region sampled.
    pub samples: usize,
}

/// Checks that every point of `region` lies within `tool_radius_mm` of the
/// tool-centre path `points` (a polyline): the region is sampled on a polar
/// grid no coarser than `resolution_mm`, and each sample's distance to the
/// path is the exact distance to the nearest segment (a grid of buckets keeps
/// it fast). Independent of the spiral's formula: it sees only the points.
pub fn coverage(
    region: &Region,
    tool_radius_mm: f64,
    points: &[(f64, f64)],
    resolution_mm: f64,
) -> Coverage {
    let cell = tool_radius_mm.max(resolution_mm);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    let key = |x: f64, y: f64| ((x / cell).floor() as i64, (y / cell).floor() as i64);
    for (i, w) in points.windows(2).enumerate() {
        let (a, b) = (key(w[0].0, w[0].1), key(w[1].0, w[1].1));
        for gx in a.0.min(b.0)..=a.0.max(b.0) {
            for gy in a.1.min(b.1)..=a.1.max(b.1) {
                grid.entry((gx, gy)).or_default().push(i);
            }
        }
    }
    let seg_dist = |i: usize, x: f64, y: f64| {
        let (a, b) = (points[i], points[i + 1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (((x - a.0) * dx + (y - a.1) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        ((a.0 + t * dx - x).powi(2) + (a.1 + t * dy - y).powi(2)).sqrt()
    };
    let mut result = Coverage {
        ok: true,
        max_gap_mm: 0.0,
        worst_point: (0.0, 0.0),
        samples: 0,
    };
    let (ri, ro) = (region.inner_radius_mm, region.outer_radius_mm);
    let rings = ((ro - ri) / resolution_mm).ceil().max(1.0) as usize;
    for k in 0..=rings {
        let r = ri + (ro - ri) * k as f64 / rings as f64;
        let around = ((std::f64::consts::TAU * r / resolution_mm).ceil() as usize).max(1);
        for j in 0..around {
            let a = std::f64::consts::TAU * j as f64 / around as f64;
            let (x, y) = (r * a.cos(), r * a.sin());
            result.samples += 1;
            let (gx, gy) = key(x, y);
            // Segments within two cells: anything farther is more than the
            // tool's radius away and counts as that far (a lower bound).
            // Nearest cells first; a segment within the tool's radius ends
            // the search (the point is covered, its gap is not the worst).
            let mut best = 2.0 * cell;
            'search: for (ox, oy) in NEIGHBOURS {
                if let Some(segs) = grid.get(&(gx + ox, gy + oy)) {
                    for &i in segs {
                        best = best.min(seg_dist(i, x, y));
                        if best <= tool_radius_mm {
                            break 'search;
                        }
                    }
                }
            }
            let gap = best - tool_radius_mm;
            if gap > result.max_gap_mm {
                result.max_gap_mm = gap;
                result.worst_point = (x, y);
            }
        }
    }
    result.ok = result.max_gap_mm <= 1e-9;
    result
}

/// Which condition of the proof a shortfall is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Zone {
    /// Neighbouring turns overlap: L ≤ 2w.
    BetweenTurns,
    /// The innermost turn reaches past the inner edge: Rin + L − w ≤ Ri.
    InnerEdge,
    /// The outermost turn reaches past the outer edge: Rout − L + w ≥ Ro.
    OuterEdge,
}

/// What [`prove_coverage`] found: each condition's margin and, when one
/// fails, the largest shortfall.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoverageProof {
    /// Proved: every point of the face lies under the tool.
    pub ok: bool,
    /// w = R − δ: how far the tool reaches from the spiral wherever the
    /// path is, mm.
    pub reach_mm: f64,
    /// 2w − L, mm (∞ where no gap between turns can meet the face).
    pub between_turns_mm: f64,
    /// Ri − (Rin + L − w), mm (∞ for a spiral through the centre).
    pub inner_edge_mm: f64,
    /// (Rout − L + w) − Ro, mm.
    pub outer_edge_mm: f64,
    /// The inner edge's margin is negative and the inner end's disc
    /// covers what its rays leave.
    pub inner_by_end: bool,
    /// The same at the outer edge.
    pub outer_by_end: bool,
    /// The largest shortfall of a failed condition (0 when proved), mm: an
    /// upper bound of how far a point of the face lies beyond the tool's
    /// edge.
    pub max_gap_mm: f64,
    /// The condition of that shortfall.
    pub worst: Option<Zone>,
    /// A point of the face where it is (near it, for an edge), mm.
    pub worst_point: (f64, f64),
}

impl CoverageProof {
    /// The proof as a [`Coverage`] (no points sampled).
    pub fn coverage(&self) -> Coverage {
        Coverage {
            ok: self.ok,
            max_gap_mm: self.max_gap_mm,
            worst_point: self.worst_point,
            samples: 0,
        }
    }
}

/// Proves that the tool of radius `tool_radius_mm` covers `region` when
/// its centre follows a path within `stray_mm` of `spiral` (every point of
/// the spiral within that of the path), in closed form (the module's
/// documentation derives it): neighbouring turns overlap (L ≤ 2w), the
/// innermost turn reaches past Ri (Rin + L − w ≤ Ri, or the inner end's
/// disc covers the rest) and the outermost past Ro (Rout − L + w ≥ Ro, or
/// the outer end's disc), w = R − δ.
pub fn prove_coverage(
    region: &Region,
    spiral: &Spiral,
    tool_radius_mm: f64,
    stray_mm: f64,
) -> CoverageProof {
    let w = tool_radius_mm - stray_mm;
    let (ri, ro) = (region.inner_radius_mm, region.outer_radius_mm);
    let (r1, r2) = (spiral.start_radius_mm, spiral.end_radius_mm);
    let (r_in, r_out) = (r1.min(r2), r1.max(r2));
    let l = spiral.step_over_mm();
    let between = if ri < r_out - w && ro > r_in + w {
        2.0 * w - l
    } else {
        f64::INFINITY
    };
    let inner = if r_in == 0.0 {
        f64::INFINITY
    } else {
        ri - (r_in + l - w)
    };
    let outer = (r_out - l + w) - ro;
    let inner_by_end = inner < 0.0 && end_disc_covers(r_in, ri, -inner, l, true, w);
    let outer_by_end = outer < 0.0 && end_disc_covers(r_out, ro, -outer, l, false, w);
    let mut shortfalls = Vec::new();
    if between < 0.0 {
        shortfalls.push((-0.5 * between, Zone::BetweenTurns));
    }
    if inner < 0.0 && !inner_by_end {
        shortfalls.push((-inner, Zone::InnerEdge));
    }
    if outer < 0.0 && !outer_by_end {
        shortfalls.push((-outer, Zone::OuterEdge));
    }
    let worst = shortfalls
        .iter()
        .copied()
        .max_by(|a, b| a.0.total_cmp(&b.0));
    CoverageProof {
        ok: worst.is_none(),
        reach_mm: w,
        between_turns_mm: between,
        inner_edge_mm: inner,
        outer_edge_mm: outer,
        inner_by_end,
        outer_by_end,
        max_gap_mm: worst.map_or(0.0, |(g, _)| g),
        worst: worst.map(|(_, z)| z),
        worst_point: worst.map_or((0.0, 0.0), |(_, z)| worst_point(z, region, spiral)),
    }
}

/// Pieces of the rays near an end that [`end_disc_covers`] takes in turn.
const END_PIECES: usize = 64;

/// Whether the disc of radius `w` about an end E of the spiral (|E| =
/// `end`) covers what the rays near it leave uncovered at an edge (radius
/// `edge`), the edge's condition failing by `short` (> 0); `l` the
/// step-over, `inward` for the inner edge.
///
/// On the ray at the angle u from the end's ray the crossings leave
/// uncovered at most the radii between the edge and `short` − l·u/2π
/// beyond it (inwards from the innermost crossing less w, or outwards from
/// the outermost plus w): the rays up to u = 2π·short/l. The squared
/// distance from E, ρ² + end² − 2ρ·end·cos u, is convex in ρ, so on a ray
/// the range's two ends decide. The angles are taken in [`END_PIECES`]
/// pieces, each with its widest range (at its first angle) and its
/// smallest cos u: a bound for every ray of the piece.
fn end_disc_covers(end: f64, edge: f64, short: f64, l: f64, inward: bool, w: f64) -> bool {
    use std::f64::consts::{PI, TAU};
    if w <= 0.0 {
        return false;
    }
    let gamma = (TAU * short / l).min(TAU);
    let within = |rho: f64, c: f64| {
        let rho = rho.max(0.0);
        rho * rho + end * end - 2.0 * rho * end * c <= w * w
    };
    (0..END_PIECES).all(|k| {
        let ua = gamma * k as f64 / END_PIECES as f64;
        let ub = gamma * (k + 1) as f64 / END_PIECES as f64;
        let c = if ua <= PI && PI <= ub {
            -1.0
        } else {
            ua.cos().min(ub.cos())
        };
        let reach = short - l * ua / TAU;
        let other = if inward { edge + reach } else { edge - reach };
        within(edge, c) && within(other, c)
    })
}

/// A point of the face where a condition's shortfall lies: between turns,
/// midway between two crossings at the largest radius the face allows
/// there; at an edge, on the edge on the ray of the spiral's end there
/// (the shortfall's supremum is approached beside it).
fn worst_point(zone: Zone, region: &Region, spiral: &Spiral) -> (f64, f64) {
    let (r1, r2) = (spiral.start_radius_mm, spiral.end_radius_mm);
    let total = std::f64::consts::TAU * f64::from(spiral.turns);
    let at = |phi: f64, rho: f64| {
        let a = spiral.start_angle_deg.to_radians() + f64::from(spiral.sense) * phi;
        (rho * a.cos(), rho * a.sin())
    };
    let (inner_end, outer_end) = if r1 <= r2 { (0.0, total) } else { (total, 0.0) };
    match zone {
        Zone::InnerEdge => at(inner_end, region.inner_radius_mm),
        Zone::OuterEdge => at(outer_end, region.outer_radius_mm),
        Zone::BetweenTurns => {
            let l = spiral.step_over_mm();
            let (r_in, r_out) = (r1.min(r2), r1.max(r2));
            let rho = (r_out - 0.5 * l)
                .min(region.outer_radius_mm)
                .max(region.inner_radius_mm.max(r_in + 0.5 * l));
            // The crossing half a step-over inside, on the ray through it.
            let b = (r2 - r1) / total;
            let phi = if b == 0.0 {
                0.0
            } else {
                ((rho - 0.5 * l - r1) / b).clamp(0.0, total)
            };
            at(phi, rho)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// Whether the end's disc covers, by brute force: every ray near the
    /// end 1/1000 of its angle apart, 100 points along each ray's range;
    /// the largest distance from the end, over `w`.
    fn brute_force(end: f64, edge: f64, short: f64, l: f64, inward: bool, w: f64) -> f64 {
        let gamma = (TAU * short / l).min(TAU);
        let mut worst: f64 = 0.0;
        for i in 0..=1000 {
            let u = gamma * f64::from(i) / 1000.0;
            let reach = short - l * u / TAU;
            for k in 0..=100 {
                let t = reach * f64::from(k) / 100.0;
                let rho = if inward { edge + t } else { edge - t }.max(0.0);
                let d2 = rho * rho + end * end - 2.0 * rho * end * u.cos();
                worst = worst.max(d2.max(0.0).sqrt() / w);
            }
        }
        worst
    }

    /// The end disc's pieces against brute force, on random ends, edges,
    /// shortfalls, step-overs and reaches round the threshold: where the
    /// pieces say covered, every ray's every point is within the disc (the
    /// bound is sound), and where every point is within 0.95 of the disc's
    /// radius the pieces say covered too (they lose little).
    #[test]
    fn the_end_disc_bound_is_sound_and_close() {
        let mut seed: u64 = 17;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut proved, mut refused) = (0, 0);
        for i in 0..1500 {
            let w = 1.0 + 20.0 * rnd();
            let l = w * (0.2 + 1.8 * rnd());
            let short = l * 1.2 * rnd();
            let inward = i % 2 == 0;
            let edge = if inward {
                40.0 * rnd() * rnd()
            } else {
                5.0 + 80.0 * rnd()
            };
            // The end near the edge: where its disc can matter.
            let end = (edge
                + (if inward { 1.0 } else { -1.0 }) * (short - l) * rnd()
                + w * (rnd() - 0.5))
                .max(0.0);
            let pieces = end_disc_covers(end, edge, short, l, inward, w);
            let brute = brute_force(end, edge, short, l, inward, w);
            if pieces {
                assert!(brute <= 1.0 + 1e-12, "{i}: proved, yet {brute}");
                proved += 1;
            } else {
                refused += 1;
            }
            if brute <= 0.95 {
                assert!(pieces, "{i}: {brute} but refused");
            }
        }
        assert!(
            proved > 150 && refused > 150,
            "{proved} proved, {refused} refused"
        );
    }
}
