//! Proofs that one arc, or two, cannot pass [`fit`](crate::fit)'s check,
//! so the search skips those counts (each count's attempt starts afresh:
//! skipping one proven to fail changes nothing in the result).
//!
//! # The rule proved against
//!
//! A k-arc spline is accepted only if [`deviation`](crate::deviation) is at
//! most ε; among its terms, for each of the n + 1 curve points
//! pᵢ = curve.point(tᵢ), tᵢ = t0 + (t1 − t0)·i/n, n = 500·k, the distance
//! from pᵢ to the nearest arc times `scale_at(tᵢ)`. A point of an arc lies
//! on the arc's circle (or line), so the distance from pᵢ to the arc is at
//! least |‖pᵢ − c‖ − r| (to a line, its distance from the line). Hence an
//! accepted spline has, for each tested point, a circle or line of one of
//! its arcs within eᵢ = ε / scale_at(tᵢ) of pᵢ. The tests below use only
//! such points, at exactly those parameters, with eᵢ enlarged by a relative
//! 10⁻⁹ and 10⁻¹² mm for the rounding of the check's own arithmetic.
//!
//! # Four points no circle passes near
//!
//! Let pᵢ, i = 1…4, lie within eᵢ of a circle (c, r): ‖pᵢ − c‖ = r + dᵢ,
//! |dᵢ| ≤ eᵢ.
//!
//! *A lower bound on r.* The affine dependence of four plane points,
//! λ1 = X(p2, p3, p4), λ2 = −X(p1, p3, p4), λ3 = X(p1, p2, p4),
//! λ4 = −X(p1, p2, p3), with X(a, b, c) = (b − a) × (c − a), has Σλᵢ = 0 and
//! Σλᵢpᵢ = 0 (a 4 × 4 determinant with a repeated column). So
//! Σλᵢ(‖pᵢ − c‖² − r²) = Σλᵢ‖pᵢ‖² − 2c·Σλᵢpᵢ + (‖c‖² − r²)Σλᵢ = K, with
//! K = Σλᵢ‖pᵢ‖², for every circle. As ‖pᵢ − c‖² − r² = 2r·dᵢ + dᵢ²,
//! |K| ≤ 2r·Σ|λᵢ|eᵢ + Σ|λᵢ|eᵢ²: r ≥ (|K| − Σ|λᵢ|eᵢ²) / (2Σ|λᵢ|eᵢ).
//! (K = 0 exactly when the four points lie on one circle or line.)
//!
//! *An upper bound on r.* Take three of the points, A, B, C, and their
//! nearest points on the circle qA, qB, qC (‖A − qA‖ = |dA| ≤ eA).
//! Three points of a circle of radius r have r = |qA qB|·|qB qC|·|qC qA| /
//! (2|u′ × v′|), u′ = qB − qA, v′ = qC − qA (the circumradius abc / 4·area).
//! With u = B − A, v = C − A, u′ = u + δu, v′ = v + δv, |δu| ≤ eA + eB,
//! |δv| ≤ eA + eC, so |u′ × v′| ≥ |u × v| − |δu||v| − |u||δv| − |δu||δv|
//! =: a. If a > 0, r ≤ (|u| + eA + eB)(|C − B| + eB + eC)(|v| + eA + eC) /
//! (2a); and no line passes within the eᵢ of the three (three points of a
//! line have u′ × v′ = 0).
//!
//! So when some three of the four give a > 0 and the smallest such upper
//! bound is below the lower bound, no circle and no line lies within eᵢ of
//! all four points, and a single arc cannot pass the check. This is a
//! cheaper stand-in for the narrowest annulus of the points (exact only at
//! the optimum's own four points, sound everywhere).
//!
//! # Two arcs
//!
//! An accepted two-arc spline puts each tested point within its eᵢ of one
//! of two circles (or lines). The check measures each point against the
//! nearest arc, so the points near the first arc need not be the ones
//! before some split point: the test allows any assignment. With m points,
//! every 2-colouring of them must leave some four points of one colour that
//! no circle passes near (as above); if every colouring does, two arcs
//! cannot pass. The colourings are all subsets M of the points: M is
//! "ruled out" when it contains such a four; a subset DP (a set is ruled
//! out when it is such a four or one of its one-smaller subsets is) marks
//! them all in 2^m·m steps, and two arcs are impossible when for every M
//! containing the first point, M or its complement is ruled out. This
//! covers every split of the curve into a part before and a part after (a
//! split is one of the colourings), and more.

use crate::{Curve, Options, CHECK_SAMPLES};

/// A tested point of the curve and how far a circle may lie from it, mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pt {
    pub(crate) p: (f64, f64),
    pub(crate) e: f64,
}

/// Points tested for one arc and for two.
const POINTS: [usize; 2] = [12, 12];

/// `m` points among the n + 1 the check measures for `k` arcs, spread
/// evenly, each with its allowance eᵢ (infinite where the curve's
/// tolerance is unbounded).
pub(crate) fn points(curve: &dyn Curve, o: &Options, k: usize, m: usize) -> Vec<Pt> {
    let (t0, t1) = curve.domain();
    let n = CHECK_SAMPLES * k.max(1);
    (0..m)
        .map(|j| {
            let i = (j * n + (m - 1) / 2) / (m - 1);
            // The check's own parameter, to the bit.
            let t = t0 + (t1 - t0) * i as f64 / n as f64;
            let s = curve.scale_at(t);
            let e = if s > 0.0 {
                o.tolerance / s * (1.0 + 1e-9) + 1e-12
            } else {
                f64::INFINITY
            };
            Pt {
                p: curve.point(t),
                e,
            }
        })
        .collect()
}

fn cross(a: (f64, f64), b: (f64, f64), c: (f64, f64)) -> f64 {
    (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
}

fn len(a: (f64, f64), b: (f64, f64)) -> f64 {
    ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt()
}

/// The upper bound on the radius of a circle within the allowances of
/// three points (see the module), or `None` when they do not bound it.
pub(crate) fn radius_above(a: Pt, b: Pt, c: Pt) -> Option<f64> {
    let (u, v, w) = (len(a.p, b.p), len(a.p, c.p), len(b.p, c.p));
    let (du, dv, dw) = (a.e + b.e, a.e + c.e, b.e + c.e);
    let area = cross(a.p, b.p, c.p).abs() - du * v - u * dv - du * dv;
    // A margin for the rounding of the cross product of mm-sized vectors.
    let area = area - 1e-12 * (u * v + 1e-12);
    (area > 0.0).then(|| (u + du) * (w + dw) * (v + dv) / (2.0 * area) * (1.0 + 1e-9))
}

/// Whether no circle and no line lies within the allowances of the four
/// points (see the module).
pub(crate) fn four_impossible(q: [Pt; 4]) -> bool {
    if q.iter().any(|x| !x.e.is_finite()) {
        return false;
    }
    let r_hi = [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
        .iter()
        .filter_map(|&[i, j, l]| radius_above(q[i], q[j], q[l]))
        .fold(f64::INFINITY, f64::min);
    if !r_hi.is_finite() {
        return false;
    }
    // Relative to the first point: K is the same (Σλ = 0, Σλp = 0) with
    // less cancellation.
    let o = q[0].p;
    let p: Vec<(f64, f64)> = q.iter().map(|x| (x.p.0 - o.0, x.p.1 - o.1)).collect();
    let lambda = [
        cross(p[1], p[2], p[3]),
        -cross(p[0], p[2], p[3]),
        cross(p[0], p[1], p[3]),
        -cross(p[0], p[1], p[2]),
    ];
    let norm2: Vec<f64> = p.iter().map(|x| x.0 * x.0 + x.1 * x.1).collect();
    let k: f64 = (0..4).map(|i| lambda[i] * norm2[i]).sum();
    let sum_abs: f64 = lambda.iter().map(|l| l.abs()).sum();
    let sum_e: f64 = (0..4).map(|i| lambda[i].abs() * q[i].e).sum();
    let sum_e2: f64 = (0..4).map(|i| lambda[i].abs() * q[i].e * q[i].e).sum();
    // Rounding: the λ sum to 0 and Σλp to 0 only to the last bits, which
    // the identity multiplies by ‖c‖² ≤ (r + span)²; a generous 10⁻¹².
    let span = norm2.iter().fold(0.0_f64, |m, &x| m.max(x)).sqrt();
    let slack = 1e-12 * sum_abs * (r_hi + span + 1.0).powi(2);
    k.abs() - sum_e2 - slack > 2.0 * r_hi * sum_e
}

/// The four-point subsets of `pts` (as bit masks) that no circle passes
/// near.
fn impossible_fours(pts: &[Pt]) -> Vec<u32> {
    let m = pts.len();
    let mut out = Vec::new();
    for a in 0..m {
        for b in a + 1..m {
            for c in b + 1..m {
                for d in c + 1..m {
                    if four_impossible([pts[a], pts[b], pts[c], pts[d]]) {
                        out.push(1 << a | 1 << b | 1 << c | 1 << d);
                    }
                }
            }
        }
    }
    out
}

/// Whether no two circles (or lines) between them pass within the
/// allowances of all of `pts` (m ≤ 20): every 2-colouring leaves a colour
/// holding four points no circle passes near.
pub(crate) fn two_impossible(pts: &[Pt]) -> bool {
    let m = pts.len();
    assert!(m <= 20, "a colouring per subset");
    let fours = impossible_fours(pts);
    // A split into the points before and after is one of the colourings:
    // when some split leaves both parts without such a four, so does a
    // colouring, and the DP is not needed to say "not proven". Parts grow
    // harder to fit as they grow, so the splits are covered when the
    // shortest refuted prefix and the shortest refuted suffix overlap.
    let prefix = fours.iter().map(|&f| 32 - f.leading_zeros()).min();
    let suffix = fours.iter().map(|&f| f.trailing_zeros()).max();
    match (prefix, suffix) {
        // Points 0..p hold a four, and so do the points from q on: a split
        // before point s leaves one when s ≥ p or s ≤ q.
        (Some(p), Some(q)) if p <= q + 1 => {}
        _ => return false,
    }
    let full = (1u32 << m) - 1;
    let mut ruled_out = vec![false; 1 << m];
    for &f in &fours {
        ruled_out[f as usize] = true;
    }
    // Supersets of a ruled-out set are ruled out: in increasing order, a
    // set's one-smaller subsets come before it.
    for set in 1..=full {
        if !ruled_out[set as usize] {
            let mut bits = set;
            while bits != 0 {
                let low = bits & bits.wrapping_neg();
                if ruled_out[(set & !low) as usize] {
                    ruled_out[set as usize] = true;
                    break;
                }
                bits &= !low;
            }
        }
    }
    (0..=full)
        .filter(|set| set & 1 == 1)
        .all(|set| ruled_out[set as usize] || ruled_out[(full & !set) as usize])
}

/// Whether `k` arcs are proven unable to pass the fit's check for `curve`
/// and `o` (only k = 1 and 2 are tried; `false` says nothing).
pub fn impossible(curve: &dyn Curve, o: &Options, k: usize) -> bool {
    match k {
        1 => {
            let pts = points(curve, o, 1, POINTS[0]);
            !impossible_fours(&pts).is_empty()
        }
        2 => two_impossible(&points(curve, o, 2, POINTS[1])),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    //! Against brute force: points placed within their allowances of a
    //! random circle or line (or of two) are never declared impossible.
    use super::*;
    use proptest::prelude::*;

    /// A point at angle `a` of the circle (c, r), moved radially by `d`.
    fn on_circle(c: (f64, f64), r: f64, a: f64, d: f64) -> (f64, f64) {
        (c.0 + (r + d) * a.cos(), c.1 + (r + d) * a.sin())
    }

    /// Points near a circle of centre `c` and radius `r` (or the line
    /// through `c` along `a0` when `r` is 0): at the angles (or distances)
    /// `at`, each moved by its own fraction (±1 at the extremes) of its
    /// allowance.
    fn near(c: (f64, f64), r: f64, a0: f64, at: &[(f64, f64, f64)]) -> Vec<Pt> {
        at.iter()
            .map(|&(t, e, frac)| {
                let p = if r == 0.0 {
                    let (s, k) = a0.sin_cos();
                    (c.0 + t * k - frac * e * s, c.1 + t * s + frac * e * k)
                } else {
                    on_circle(c, r, a0 + t, frac * e)
                };
                // The point's allowance, less the rounding margin the
                // fit's points get.
                Pt { p, e }
            })
            .collect()
    }

    fn sample() -> impl Strategy<Value = (f64, f64, f64)> {
        (
            -1.0..1.0f64,
            -5.0..-2.0f64,
            prop_oneof![Just(1.0), Just(-1.0), -1.0..1.0f64],
        )
            .prop_map(|(t, le, frac)| (t, 10f64.powf(le), frac))
    }

    fn circle() -> impl Strategy<Value = ((f64, f64), f64, f64, f64)> {
        (
            (-60.0..60.0f64, -60.0..60.0f64),
            prop_oneof![Just(0.0), (-0.5..5.0f64).prop_map(|l| 10f64.powf(l))],
            -3.2..3.2f64,
            // The span of the points: angle for a circle (× its own scale
            // below), length for a line.
            0.001..2.0f64,
        )
    }

    fn scaled(r: f64, span: f64, at: &[(f64, f64, f64)]) -> Vec<(f64, f64, f64)> {
        // On a circle, `span` radians at most (a short arc of a huge one
        // too); on a line, `span` · 20 mm.
        let s = if r == 0.0 {
            20.0 * span
        } else {
            span.min(40.0 / r)
        };
        at.iter().map(|&(t, e, f)| (t * s, e, f)).collect()
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn four_near_a_circle_are_possible(
            (c, r, a0, span) in circle(),
            at in prop::collection::vec(sample(), 4),
        ) {
            let pts = near(c, r, a0, &scaled(r, span, &at));
            prop_assert!(!four_impossible([pts[0], pts[1], pts[2], pts[3]]), "{pts:?}");
        }

        #[test]
        fn points_near_two_circles_are_possible(
            (c1, r1, a1, span1) in circle(),
            (c2, r2, a2, span2) in circle(),
            at in prop::collection::vec((sample(), any::<bool>()), 6..12),
        ) {
            // In the order drawn: the two circles' points interleave.
            let pts: Vec<Pt> = at
                .iter()
                .map(|&(x, first)| {
                    let (c, r, a, span) = if first {
                        (c1, r1, a1, span1)
                    } else {
                        (c2, r2, a2, span2)
                    };
                    near(c, r, a, &scaled(r, span, &[x]))[0]
                })
                .collect();
            prop_assert!(!two_impossible(&pts), "{pts:?}");
        }

        #[test]
        fn the_affine_dependence_holds(
            p in prop::collection::vec((-50.0..50.0f64, -50.0..50.0f64), 4),
        ) {
            let l = [
                cross(p[1], p[2], p[3]),
                -cross(p[0], p[2], p[3]),
                cross(p[0], p[1], p[3]),
                -cross(p[0], p[1], p[2]),
            ];
            let size: f64 = l.iter().map(|x| x.abs()).sum::<f64>() + 1.0;
            prop_assert!(l.iter().sum::<f64>().abs() < 1e-12 * size);
            let sx: f64 = (0..4).map(|i| l[i] * p[i].0).sum();
            let sy: f64 = (0..4).map(|i| l[i] * p[i].1).sum();
            prop_assert!(sx.abs() < 1e-10 * size && sy.abs() < 1e-10 * size);
        }
    }

    /// Not vacuous: four points of a parabola y = x² over a millimetre, at
    /// 1 µm, fit no circle (the narrowest annulus is some 20 µm each side, by a random search); at 0.1 mm one
    /// does.
    #[test]
    fn a_parabola_fits_no_circle_at_a_micrometre() {
        let at = |e: f64| {
            let p: Vec<Pt> = [0.0, 0.3, 0.7, 1.0]
                .iter()
                .map(|&x| Pt { p: (x, x * x), e })
                .collect();
            [p[0], p[1], p[2], p[3]]
        };
        assert!(four_impossible(at(1e-3 * 1.0)));
        assert!(!four_impossible(at(0.1)));
    }

    /// Not vacuous: a dozen points of y = x³ over [−2, 2] at 1 µm fit no
    /// two circles; at 10 mm, points fit one (any).
    #[test]
    fn a_cubic_fits_no_two_circles_at_a_micrometre() {
        let at = |e: f64| -> Vec<Pt> {
            (0..12)
                .map(|i| {
                    let x = -2.0 + 4.0 * i as f64 / 11.0;
                    Pt {
                        p: (x, x * x * x),
                        e,
                    }
                })
                .collect()
        };
        assert!(two_impossible(&at(1e-3)));
        assert!(!two_impossible(&at(10.0)));
    }
}
