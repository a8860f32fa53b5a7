//! The proofs against the fit itself: a count declared impossible is never
//! one the fit passes with, and the fit with the proofs is the fit without
//! them to the bit, on random involutes (a gear's flank) with random
//! tolerances, some of them varying along the curve.

use gearcam_arcfit::{fit, fit_exhaustive, impossible, Curve, Options};
use proptest::prelude::*;

/// An involute of the base circle `rb` from roll angle `t0` to `t1`,
/// P(t) = rb·(cos t + t·sin t, sin t − t·cos t), its tolerance `scale`
/// times finer past the middle of the domain.
#[derive(Debug)]
struct Involute {
    rb: f64,
    t0: f64,
    t1: f64,
    scale: f64,
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
    /// By a dense scan and a golden-section refinement (slow and plain).
    fn distance(&self, q: (f64, f64)) -> f64 {
        let d = |t: f64| {
            let p = self.point(t);
            ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt()
        };
        let n = 200;
        let h = (self.t1 - self.t0) / n as f64;
        let i = (0..=n)
            .min_by(|&a, &b| d(self.t0 + a as f64 * h).total_cmp(&d(self.t0 + b as f64 * h)))
            .expect("points");
        let (mut a, mut b) = (
            (self.t0 + (i as f64 - 1.0) * h).max(self.t0),
            (self.t0 + (i as f64 + 1.0) * h).min(self.t1),
        );
        for _ in 0..60 {
            let (m1, m2) = (a + 0.382 * (b - a), b - 0.382 * (b - a));
            if d(m1) < d(m2) {
                b = m2;
            } else {
                a = m1;
            }
        }
        d(0.5 * (a + b))
    }
    fn scale_at(&self, t: f64) -> f64 {
        if t > 0.5 * (self.t0 + self.t1) {
            self.scale
        } else {
            1.0
        }
    }
}

fn involute() -> impl Strategy<Value = Involute> {
    (
        5.0..40.0f64,
        0.0..0.4f64,
        0.05..0.8f64,
        prop_oneof![Just(1.0), 1.0..4.0f64],
    )
        .prop_map(|(rb, t0, dt, scale)| Involute {
            rb,
            t0,
            t1: t0 + dt,
            scale,
        })
}

fn tolerance() -> impl Strategy<Value = f64> {
    (-4.0..-1.5f64).prop_map(|l| 10f64.powf(l))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// Where one or two arcs pass, the proofs do not say they cannot.
    #[test]
    fn a_passing_count_is_never_declared_impossible(c in involute(), tol in tolerance()) {
        let mut o = Options::tolerance(tol);
        o.max_arcs = 2;
        if let Ok(f) = fit_exhaustive(&c, &o) {
            let k = f.arcs.len();
            prop_assert!(!impossible(&c, &o, k), "{k} arcs pass, declared impossible: {c:?} at {tol}");
        }
    }

    /// The same fit to the bit, or the same error (few arcs allowed, so
    /// some searches fail and try the skipped counts after all).
    #[test]
    fn the_proofs_change_nothing(c in involute(), tol in tolerance(), max_arcs in 1usize..5) {
        let mut o = Options::tolerance(tol);
        o.max_arcs = max_arcs;
        prop_assert_eq!(fit(&c, &o), fit_exhaustive(&c, &o));
    }
}

/// The proofs cut something: a long involute at a micrometre fits no
/// single arc, and they say so.
#[test]
fn a_long_involute_at_a_micrometre_fits_no_single_arc() {
    let c = Involute {
        rb: 18.8,
        t0: 0.1,
        t1: 0.6,
        scale: 1.0,
    };
    let o = Options::tolerance(1e-3);
    assert!(impossible(&c, &o, 1));
    assert!(fit_exhaustive(&c, &o).expect("fits").arcs.len() > 1);
}
