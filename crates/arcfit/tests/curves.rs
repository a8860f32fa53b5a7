//! The arc spline fit on curves whose geometry is known: a circle (one arc,
//! exactly), the involute flank of a spur gear (m 2, z 20, α 20°, the
//! reference figure: a greedy biarc fit needs 6 arcs per flank at 1 µm),
//! and random involutes and circles (property tests). Every fit is measured
//! again here by a brute-force nearest-point search, not by the crate's own
//! `deviation`.

use gearcam_arcfit::{fit, Arc, Curve, Options};
use proptest::prelude::*;

/// An involute of the base circle `rb` from roll angle `t0` to `t1`:
/// P(t) = rb·(cos t + t·sin t, sin t − t·cos t), tangent angle t.
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
    /// Closed form: q lies on the involute's normal at the roll angle t'
    /// whose base-circle tangent passes through q, l = √(|q|² − rb²) from
    /// the tangent point; the polar angle of q is t' − atan(l/rb), and the
    /// involute point on that normal is rb·t' from the tangent point.
    fn distance(&self, q: (f64, f64)) -> f64 {
        let r2 = q.0 * q.0 + q.1 * q.1;
        let l = (r2 - self.rb * self.rb).max(0.0).sqrt();
        let t = q.1.atan2(q.0) + (l / self.rb).atan();
        if (self.t0..=self.t1).contains(&t) {
            (l - self.rb * t).abs()
        } else {
            let d = |p: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
            d(self.point(self.t0)).min(d(self.point(self.t1)))
        }
    }
}

/// A circular arc of radius r about the origin from angle a0 to a1 (ccw).
struct Circle {
    r: f64,
    a0: f64,
    a1: f64,
}

impl Curve for Circle {
    fn domain(&self) -> (f64, f64) {
        (self.a0, self.a1)
    }
    fn point(&self, t: f64) -> (f64, f64) {
        (self.r * t.cos(), self.r * t.sin())
    }
    fn tangent_angle(&self, t: f64) -> f64 {
        t + std::f64::consts::FRAC_PI_2
    }
    fn distance(&self, q: (f64, f64)) -> f64 {
        let a = q.1.atan2(q.0);
        if (self.a0..=self.a1).contains(&a) {
            ((q.0 * q.0 + q.1 * q.1).sqrt() - self.r).abs()
        } else {
            let d = |p: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
            d(self.point(self.a0)).min(d(self.point(self.a1)))
        }
    }
}

/// The distance from q to the curve by brute force: a dense scan of the
/// parameter, then golden-section refinement around the best sample.
fn brute_distance(c: &dyn Curve, q: (f64, f64)) -> f64 {
    let (t0, t1) = c.domain();
    let d = |t: f64| {
        let p = c.point(t);
        ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt()
    };
    let n = 2000;
    let h = (t1 - t0) / n as f64;
    let i = (0..=n)
        .min_by(|&a, &b| d(t0 + h * a as f64).total_cmp(&d(t0 + h * b as f64)))
        .unwrap();
    let (mut lo, mut hi) = (
        (t0 + h * (i as f64 - 1.0)).max(t0),
        (t0 + h * (i as f64 + 1.0)).min(t1),
    );
    for _ in 0..80 {
        let (m1, m2) = (lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo));
        if d(m1) < d(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    d(0.5 * (lo + hi))
}

/// The largest brute-force distance of the arcs from the curve, and of
/// the curve from the arcs; and that the arcs join without gaps or corners.
fn measured(c: &dyn Curve, arcs: &[Arc]) -> f64 {
    for w in arcs.windows(2) {
        let (e, s) = (w[0].end(), w[1].start);
        assert!((e.0 - s.0).abs() + (e.1 - s.1).abs() < 1e-12, "a gap");
        assert!(
            (w[0].end_angle() - w[1].start_angle).abs() < 1e-12,
            "a corner"
        );
    }
    let mut worst: f64 = 0.0;
    for a in arcs {
        for i in 0..=300 {
            worst = worst.max(brute_distance(c, a.point_at(a.length * i as f64 / 300.0)));
        }
    }
    let (t0, t1) = c.domain();
    for i in 0..=600 {
        let q = c.point(t0 + (t1 - t0) * i as f64 / 600.0);
        worst = worst.max(
            arcs.iter()
                .map(|a| a.distance(q))
                .fold(f64::INFINITY, f64::min),
        );
    }
    worst
}

/// The closed-form involute distance is the brute-force one.
#[test]
fn the_involute_distance_in_closed_form_is_the_nearest_point_distance() {
    let inv = Involute {
        rb: 18.79385241571817,
        t0: 0.05,
        t1: 0.61,
    };
    for (i, off) in [(0, 0.01), (37, -0.004), (99, 0.2), (140, -0.05), (199, 0.0)] {
        let t = inv.t0 + (inv.t1 - inv.t0) * f64::from(i) / 200.0;
        let p = inv.point(t);
        // Off the curve along its normal (the tangent turned by −90°).
        let q = (p.0 + off * t.sin(), p.1 - off * t.cos());
        let (a, b) = (inv.distance(q), brute_distance(&inv, q));
        assert!((a - b).abs() < 1e-9, "{i}: closed {a} brute {b}");
        assert!((a - off.abs()).abs() < 1e-9, "{i}: {a} vs {off}");
    }
}

/// A circular arc is one arc of the spline, to rounding.
#[test]
fn a_circle_is_one_arc() {
    let c = Circle {
        r: 12.5,
        a0: 0.2,
        a1: 1.4,
    };
    let f = fit(&c, &Options::tolerance(0.001)).unwrap();
    assert_eq!(f.arcs.len(), 1);
    assert!(
        (1.0 / f.arcs[0].curvature - 12.5).abs() < 0.01,
        "{:?}",
        f.arcs[0]
    );
    assert!(measured(&c, &f.arcs) <= 0.001);
}

/// The reference figure's flank: the involute of m 2, z 20, α 20°, x 0, from
/// the form circle of a rack with ha* = 1 (r_form = √(rb² + (r·sin α −
/// ha*·m/sin α)²) = 18.820 mm) to the tip circle (22 mm), at 1 µm.
#[test]
fn an_involute_flank_of_m2_z20_needs_at_most_four_arcs_at_1_um() {
    let m = 2.0;
    let z = 20.0;
    let alpha = 20f64.to_radians();
    let r = m * z / 2.0;
    let rb = r * alpha.cos();
    let r_form = (rb * rb + (r * alpha.sin() - m / alpha.sin()).powi(2)).sqrt();
    let roll = |radius: f64| (radius * radius - rb * rb).sqrt() / rb;
    let inv = Involute {
        rb,
        t0: roll(r_form),
        t1: roll(r + m),
    };
    let f = fit(&inv, &Options::tolerance(0.001)).unwrap();
    let d = measured(&inv, &f.arcs);
    eprintln!(
        "m2 z20 flank at 1 um: {} arcs, deviation {:.3} um (brute force), radii {:?}",
        f.arcs.len(),
        d * 1000.0,
        f.arcs.iter().map(|a| 1.0 / a.curvature).collect::<Vec<_>>()
    );
    assert!(f.arcs.len() <= 4, "{} arcs", f.arcs.len());
    assert!(d <= 0.001 * 1.001, "{d}");
}

/// Kept tangents: the spline leaves with the given start tangent and
/// arrives with the given end tangent (to join its neighbours without a corner).
#[test]
fn given_end_tangents_are_kept() {
    let inv = Involute {
        rb: 30.0,
        t0: 0.1,
        t1: 0.5,
    };
    let mut o = Options::tolerance(0.002);
    o.start_angle = Some(0.1);
    o.end_angle = Some(0.5);
    let f = fit(&inv, &o).unwrap();
    assert_eq!(f.arcs[0].start_angle, 0.1);
    let end = f.arcs.last().unwrap().end_angle();
    assert!(
        (end - 0.5).abs() * f.arcs.last().unwrap().length <= 0.002,
        "{end}"
    );
    assert!(measured(&inv, &f.arcs) <= 0.002 * 1.001);
}

/// A closing biarc: asked to end on a point and tangent of its own (here
/// the involute's end moved 1 µm along its normal, as a neighbouring
/// piece's start would be), the spline ends exactly there with exactly that
/// tangent, starts on the given point and tangent, and stays within the
/// tolerance (brute force).
#[test]
fn a_closing_biarc_ends_exactly_on_the_given_point_and_tangent() {
    let inv = Involute {
        rb: 20.0,
        t0: 0.15,
        t1: 0.55,
    };
    let end = inv.point(0.55);
    let goal = (end.0 + 0.001 * 0.55f64.sin(), end.1 - 0.001 * 0.55f64.cos());
    let mut o = Options::tolerance(0.003);
    o.start_point = Some(inv.point(0.15));
    o.start_angle = Some(0.15);
    o.end_point = Some(goal);
    o.end_angle = Some(0.55 + 1e-4);
    let f = fit(&inv, &o).unwrap();
    assert!(f.arcs.len() >= 2, "{} arcs", f.arcs.len());
    let last = f.arcs.last().unwrap();
    let e = last.end();
    assert!(
        (e.0 - goal.0).hypot(e.1 - goal.1) < 1e-9,
        "{e:?} vs {goal:?}"
    );
    assert!((last.end_angle() - (0.55 + 1e-4)).abs() < 1e-9);
    assert_eq!(f.arcs[0].start_angle, 0.15);
    for w in f.arcs.windows(2) {
        let gap = (w[0].end().0 - w[1].start.0).hypot(w[0].end().1 - w[1].start.1);
        assert!(gap < 1e-12 && (w[0].end_angle() - w[1].start_angle).abs() < 1e-12);
    }
    assert!(measured(&inv, &f.arcs) <= 0.003 * 1.001);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    /// Random involute flanks (base radius 2–100 mm, a roll range away from
    /// the cusp) at 1–10 µm: every fit is within the tolerance, measured by
    /// brute force, and G1.
    #[test]
    fn random_involutes_are_fitted_within_the_tolerance(
        rb in 2.0f64..100.0,
        t0 in 0.05f64..0.4,
        span in 0.05f64..0.6,
        tol in 0.001f64..0.01,
    ) {
        let inv = Involute { rb, t0, t1: t0 + span };
        let f = fit(&inv, &Options::tolerance(tol)).unwrap();
        prop_assert!(measured(&inv, &f.arcs) <= tol * 1.001);
    }

    /// Random circular arcs need one arc.
    #[test]
    fn random_circles_are_one_arc(r in 0.5f64..200.0, a0 in -3.0f64..0.0, span in 0.05f64..3.0) {
        let c = Circle { r, a0, a1: a0 + span };
        let f = fit(&c, &Options::tolerance(0.001)).unwrap();
        prop_assert_eq!(f.arcs.len(), 1);
    }
}
