//! How deep the hob enters an obstacle along a move, from the geometry.
//!
//! # What is measured
//!
//! For one pose of the hob H and an obstacle O, the depth is
//!
//! ```text
//! D = max( max_{p ∈ H} φ_O(p),  max_{q ∈ O} φ_H(q) )
//! ```
//!
//! with φ the signed depth of `super::shapes` (distance to the boundary
//! inside, minus the distance outside): the deepest point of either solid in
//! the other. When the solids are apart, both terms are −dist(H, O); when
//! they overlap, D > 0 is how far inside the other solid the deepest point
//! of the overlap lies, measured from its nearest face. Along a move,
//! D* = max over the poses. A finding is D* > `PEN_TOL`.
//!
//! # Straight moves
//!
//! With a constant tilt, every pose is a translate of one cylinder and the
//! union of the poses is the swept solid S (`shapes::Sweep`), convex. Then
//!
//! - **apart**: D* = −dist(S, O), one distance query;
//! - **A* = max_{p ∈ S} φ_O(p) ≥ s ⇔ S meets O_s = {φ_O ≥ s}** (a
//!   continuous function on a compact set reaches its maximum), and O_s is a
//!   frustum again; so A* is the largest level whose set still meets S;
//! - **B* = max over the poses and q ∈ O of φ_H(q) ≥ s ⇔ S_s meets O**,
//!   with S_s the sweep of the hob's level set H_s (a cylinder again).
//!
//! The largest such level is found by bisection on s, each step one distance
//! query (`gjk::gap`) whose bounds decide it: a positive lower bound
//! certifies that the level is too deep (the maximum is below s), and an
//! upper bound δ certifies that the maximum is at least s − δ (φ is
//! 1-Lipschitz: the point of S within δ of a point of O_s, where φ_O ≥ s,
//! has φ_O ≥ s − δ). That second bound also holds when the sets are apart,
//! and is then usually the answer itself (φ grows at unit rate along the
//! inward normal), so each separated step is followed by a test just above
//! it; the bisection keeps what is certified either way and stops when the
//! bounds are [`TAU`] apart.
//!
//! # Moves that swivel the hob
//!
//! When A changes within a move, the poses are no translates of one solid.
//! Every hob point then moves at most L·|Δt| between the move's parameters t
//! and t + Δt, with L = |Δ(X, Z)| + |ΔY| + (max |Y| + reach)·|Δη| (the
//! centre's travel, the shift's travel along an axis turning by Δη, and the
//! turn of a point at most `reach` = √(r² + h²) from the centre). So D(t) is
//! L-Lipschitz (a deepest point of H in O moves that far; a point of O
//! inside H at t has body coordinates that move that far), and a branch and
//! bound over t, each interval bounded by D at its middle plus L times its
//! half width (and by the largest depth any point can have, min(r, h) in
//! the hob and the obstacle's own bound), brackets D* to [`SWIVEL_TOL`].
//! Swivel moves are the one or two per unit made far from the work, where
//! the first interval is clear.

use super::gjk::{gap, Gap, Stop};
use super::shapes::{depth_bound, Solid, Sweep};
use super::P3;
use std::collections::BinaryHeap;

/// Width of the bracket of a depth along a straight move, mm. The distance
/// iteration resolves a gap of about √(ε·size·error) near contact, 10 nm
/// for solids of 500 mm; this leaves it a margin.
pub(crate) const TAU: f64 = 1e-4;
/// Width of the bracket of a depth along a swivel move, mm.
pub(crate) const SWIVEL_TOL: f64 = 1e-3;
/// Most bisection steps for one level.
const MAX_LEVEL_STEPS: usize = 100;
/// Most intervals the branch and bound of a swivel move splits.
const MAX_SWIVEL_SPLITS: usize = 80_000;

/// Certified bounds of the depth D* of a move into an obstacle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Depth {
    /// D* is at least this.
    pub(crate) lo: f64,
    /// D* is at most this.
    pub(crate) hi: f64,
    /// Upper bounds of the two terms of D*: the hob's points in the
    /// obstacle, and the obstacle's points in the hob.
    pub(crate) hi_terms: [f64; 2],
    /// A point where the depth `lo` is reached: a point of the hob in the
    /// obstacle, or of the obstacle in the hob (`hob_point`).
    pub(crate) at: P3,
    /// The move's parameter t ∈ [0, 1] of the pose where it is reached.
    pub(crate) t: f64,
    /// True when `at` is a point of the hob.
    pub(crate) hob_point: bool,
}

/// What the caller needs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Need {
    /// Only whether D* exceeds this, and D* when it does.
    Above(f64),
    /// D* in every case (also the distance when apart).
    Exact,
    /// D* and both its terms bracketed (a swivel move's branch and bound
    /// bounds each term on its own).
    Terms,
}

/// The depth along a straight move.
pub(crate) fn straight(sweep: &Sweep, ob: &Solid, need: Need) -> Depth {
    let (z_min, z_max) = sweep.z_range();
    let frustum = ob.finite_for(z_min, z_max);
    let first = match need {
        // Apart is all the check needs to know.
        Need::Above(_) => Stop {
            apart: 0.0,
            close: TAU / 4.0,
            tol: 0.0,
        },
        Need::Exact | Need::Terms => level_stop(),
    };
    let g = gap(sweep, &frustum, first);
    if g.lb > 0.0 {
        // Apart: A* = B* = −dist(S, O).
        return Depth {
            lo: -g.ub,
            hi: -g.lb,
            hi_terms: [-g.lb; 2],
            at: g.on_b,
            t: g.tau_a,
            hob_point: false,
        };
    }
    // A*: the hob's points in the obstacle's level sets; a witness p of the
    // sweep has φ_O(p) ≤ A*.
    let hob_in = |g: &Gap| Bracket {
        lo: frustum.depth_of(&g.on_a),
        hi: f64::INFINITY,
        at: g.on_a,
        t: g.tau_a,
        hob_point: true,
    };
    let a = largest_level(
        |s| frustum.level(s).map(|f| gap(sweep, &f, level_stop())),
        &hob_in,
        Bracket {
            hi: depth_bound(&frustum, z_min, z_max),
            ..hob_in(&g)
        },
    );
    // B*: the obstacle's points in the hob's level sets; a witness q of the
    // obstacle, near the pose τ of the sweep's witness, has φ_H(τ)(q) ≤ B*.
    // Needed only where B* may exceed A* (unless both terms are asked for):
    // does H_s, s = A*, still meet O?
    let in_hob = |g: &Gap| Bracket {
        lo: sweep.depth_at(g.tau_a, &g.on_b),
        hi: f64::INFINITY,
        at: g.on_b,
        t: g.tau_a,
        hob_point: false,
    };
    let s = if need == Need::Terms {
        0.0
    } else {
        a.lo.max(0.0)
    };
    let b = match sweep.level(s).map(|h| gap(&h, &frustum, level_stop())) {
        Some(g) if g.lb <= 0.0 => largest_level(
            |s| sweep.level(s).map(|h| gap(&h, &frustum, level_stop())),
            &in_hob,
            Bracket {
                hi: sweep.r.min(sweep.half),
                ..in_hob(&g)
            },
        ),
        // H_s misses O (or is empty): B* < s.
        _ => Bracket { hi: s, ..a },
    };
    let deeper = if b.lo > a.lo { b } else { a };
    Depth {
        lo: deeper.lo,
        hi: a.hi.max(b.hi),
        hi_terms: [a.hi, b.hi],
        at: deeper.at,
        t: deeper.t,
        hob_point: deeper.hob_point,
    }
}

/// A distance query precise enough to decide a level.
fn level_stop() -> Stop {
    Stop {
        apart: f64::INFINITY,
        close: TAU / 4.0,
        tol: TAU / 4.0,
    }
}

/// Certified bounds of the largest level, with the witness of the lower.
#[derive(Debug, Clone, Copy)]
struct Bracket {
    lo: f64,
    hi: f64,
    at: P3,
    t: f64,
    hob_point: bool,
}

/// The largest level s whose level set still meets the other solid, from a
/// bracket of it. `query(s)` is the distance between the level set and the
/// other solid, `None` when the level set is empty (the level is too
/// deep); `witness` turns a query's points into a lower bound (the exact
/// depth of a point of one solid in the other).
///
/// A query with a positive lower bound certifies that s is too deep; every
/// query's witness raises the lower bound, and one near the level set
/// usually lands on the answer (φ grows at unit rate along the inward
/// normal). So each step tries just above the lower bound, further (four
/// times) while that is not too deep, and never beyond the middle of the
/// bracket. A query that neither separates nor finds the sets meeting (the
/// distance is below what the iteration resolves) is not asked again: the
/// next level lies between it and the upper bound.
fn largest_level(
    mut query: impl FnMut(f64) -> Option<Gap>,
    witness: &dyn Fn(&Gap) -> Bracket,
    start: Bracket,
) -> Bracket {
    let mut b = start;
    let mut step = TAU / 2.0;
    let mut floor = f64::NEG_INFINITY;
    for _ in 0..MAX_LEVEL_STEPS {
        if b.hi - b.lo <= TAU {
            break;
        }
        let mut s = (b.lo + step).min(0.5 * (b.lo + b.hi));
        if s <= floor {
            s = 0.5 * (floor + b.hi);
        }
        match query(s) {
            None => {
                b.hi = s;
                step = TAU / 2.0;
            }
            Some(g) => {
                let w = witness(&g);
                if w.lo > b.lo {
                    b = Bracket { hi: b.hi, ..w };
                }
                if g.lb > 0.0 {
                    b.hi = s;
                    step = TAU / 2.0;
                } else {
                    floor = s;
                    step *= 4.0;
                }
            }
        }
    }
    b
}

/// The hob's pose along a swivel move, as a sweep that does not travel.
pub(crate) type PoseAt<'a> = &'a dyn Fn(f64) -> Sweep;

/// The depth along a move whose tilt changes, by branch and bound over the
/// move's parameter with the Lipschitz constant `lipschitz` (mm per unit of
/// the parameter; see the module's derivation). `caps` bound the two terms
/// of D at every pose: no point of the obstacle is deeper in the hob than
/// min(r, h), nor a point of the hob deeper in the obstacle than the
/// obstacle's own bound over the heights the hob reaches. Where the hob's
/// axis passes through an obstacle, its term stays at min(r, h) over a
/// whole stretch of the move, and only the cap settles that stretch.
pub(crate) fn swivel(
    pose_at: PoseAt<'_>,
    lipschitz: f64,
    caps: [f64; 2],
    ob: &Solid,
    need: Need,
) -> Depth {
    #[derive(PartialEq)]
    struct Interval {
        upper: f64,
        t0: f64,
        t1: f64,
    }
    impl Eq for Interval {}
    impl PartialOrd for Interval {
        fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(other))
        }
    }
    impl Ord for Interval {
        fn cmp(&self, other: &Self) -> std::cmp::Ordering {
            self.upper.total_cmp(&other.upper)
        }
    }
    let mut best: Option<Depth> = None;
    let eval = |t0: f64, t1: f64, best: &mut Option<Depth>| {
        let t = 0.5 * (t0 + t1);
        let d = straight(&pose_at(t), ob, Need::Terms);
        if best.is_none_or(|b| d.lo > b.lo) {
            *best = Some(Depth { t, ..d });
        }
        let reach = lipschitz * 0.5 * (t1 - t0);
        let term = |k: usize| (d.hi_terms[k] + reach).min(caps[k]);
        Interval {
            upper: term(0).max(term(1)).max(d.hi),
            t0,
            t1,
        }
    };
    let mut heap = BinaryHeap::new();
    heap.push(eval(0.0, 1.0, &mut best));
    for _ in 0..MAX_SWIVEL_SPLITS {
        let Some(top) = heap.peek() else { break };
        let lo = best.map_or(f64::NEG_INFINITY, |b| b.lo);
        let settled = match need {
            Need::Above(limit) => {
                top.upper <= limit || (lo > limit && top.upper - lo <= SWIVEL_TOL)
            }
            Need::Exact | Need::Terms => top.upper - lo <= SWIVEL_TOL,
        };
        if settled {
            break;
        }
        let Some(top) = heap.pop() else { break };
        let mid = 0.5 * (top.t0 + top.t1);
        heap.push(eval(top.t0, mid, &mut best));
        heap.push(eval(mid, top.t1, &mut best));
    }
    let hi = heap.peek().map_or(f64::NEG_INFINITY, |i| i.upper);
    let b = best.unwrap_or(Depth {
        lo: f64::NEG_INFINITY,
        hi,
        hi_terms: [hi; 2],
        at: P3::zeros(),
        t: 0.0,
        hob_point: false,
    });
    Depth {
        hi: hi.max(b.lo),
        ..b
    }
}
