//! [`deviation`] against the plain way of taking it: every arc sampled by
//! [`Arc::point_at`], every curve point measured by [`Arc::distance`] from
//! every arc. The crate works each arc's constants out once and skips arcs
//! whose circle is too far to be the nearest; the figure must be the same
//! to the last bit, on random arc splines near and far from random
//! involutes (arcs, lines, nearly flat arcs, turning either way).

use gearcam_arcfit::{deviation, Arc, Curve};
use proptest::prelude::*;

/// An involute of the base circle `rb` from roll angle `t0` to `t1`, with
/// its distance by a dense nearest-point scan (any distance does here: both
/// ways of measuring call it on the same points).
struct Involute {
    rb: f64,
    t0: f64,
    t1: f64,
}

impl Curve for Involute {
    fn domain(&self) -> (f64, f64) {
        (self.t0, self.t1)
    }
    fn point(&self, t: f64) -> (f64, f64) {
        let rb = self.rb;
        (rb * (t.cos() + t * t.sin()), rb * (t.sin() - t * t.cos()))
    }
    fn tangent_angle(&self, t: f64) -> f64 {
        t
    }
    fn distance(&self, q: (f64, f64)) -> f64 {
        (0..=64)
            .map(|i| {
                let p = self.point(self.t0 + (self.t1 - self.t0) * f64::from(i) / 64.0);
                (p.0 - q.0).hypot(p.1 - q.1)
            })
            .fold(f64::INFINITY, f64::min)
    }
    fn scale_at(&self, t: f64) -> f64 {
        // A tolerance that changes along the curve, as a joined curve's.
        1.0 + (t - self.t0)
    }
}

/// The plain deviation: each arc's points by `point_at`, each curve
/// point's distance from every arc by `distance`.
fn plain(curve: &dyn Curve, arcs: &[Arc], samples: usize) -> f64 {
    let (t0, t1) = curve.domain();
    let mut worst: f64 = 0.0;
    for a in arcs {
        for i in 0..=samples {
            let q = a.point_at(a.length * i as f64 / samples as f64);
            worst = worst.max(curve.distance(q));
        }
    }
    let n = samples * arcs.len().max(1);
    for i in 0..=n {
        let t = t0 + (t1 - t0) * i as f64 / n as f64;
        let q = curve.point(t);
        let d = arcs
            .iter()
            .map(|a| a.distance(q))
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d * curve.scale_at(t));
    }
    worst
}

/// A G1 spline from the curve's start (moved by `shift`) along its
/// tangent, of arcs of the given curvatures (a code of 0 makes a line,
/// 1 a nearly flat arc) and lengths.
fn spline(curve: &Involute, shift: (f64, f64), arcs: &[(f64, u8, f64)]) -> Vec<Arc> {
    let p = curve.point(curve.t0);
    let mut start = (p.0 + shift.0, p.1 + shift.1);
    let mut angle = curve.t0;
    arcs.iter()
        .map(|&(k, code, length)| {
            let curvature = match code {
                0 => 0.0,
                1 => k * 1e-10,
                _ => k,
            };
            let a = Arc {
                start,
                start_angle: angle,
                curvature,
                length,
            };
            start = a.end();
            angle = a.end_angle();
            a
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn the_deviation_is_the_plain_deviation_to_the_last_bit(
        rb in 2.0f64..100.0,
        t0 in 0.05f64..0.4,
        span in 0.05f64..0.6,
        shift in (-0.5f64..0.5, -0.5f64..0.5),
        arcs in prop::collection::vec((-2.0f64..2.0, 0u8..5, 0.01f64..5.0), 1..7),
        samples in 1usize..60,
    ) {
        let curve = Involute { rb, t0, t1: t0 + span };
        let arcs = spline(&curve, shift, &arcs);
        prop_assert_eq!(
            deviation(&curve, &arcs, samples).to_bits(),
            plain(&curve, &arcs, samples).to_bits()
        );
    }
}
