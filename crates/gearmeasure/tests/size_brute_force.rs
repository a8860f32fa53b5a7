//! Span and dimension over balls against a brute-force measurement of
//! numerically built involute flanks: the flanks are sampled from their
//! polar form alone (radius rb·√(1 + t²), angle ±(ψb − (t − atan t)) about
//! the tooth's centre, turned by z·tan β / r along the face), the caliper
//! is found by maximising over the flank points and minimising over its
//! tilt, the ball by bisection on its radius until its distance to the
//! flank, minimised over the flank, is its radius. None of the size
//! formulas is used.

use approx::assert_relative_eq;
use gearcam_gearmeasure::size::{inv, inv_inverse, Involute};
use proptest::prelude::*;
use std::f64::consts::PI;

/// A gear built point by point.
struct Flanks {
    z: usize,
    rb: f64,
    psi_b: f64,
    /// Turn per mm of face, rad (right hand +).
    twist: f64,
    t_tip: f64,
}

impl Flanks {
    fn new(g: &Involute, sn: f64, tip_diameter: f64) -> Flanks {
        let d = g.reference_diameter_mm();
        let beta = g.helix_deg.to_radians();
        let alpha_t = (g.normal_pressure_angle_deg.to_radians().tan() / beta.cos()).atan();
        let rb = d / 2.0 * alpha_t.cos();
        // Transverse thickness on the reference cylinder: sn / cos β; its
        // half angle there, carried down the involute to the base circle.
        let psi_b = sn / beta.cos() / d + (alpha_t.tan() - alpha_t);
        Flanks {
            z: g.teeth as usize,
            rb,
            psi_b,
            twist: beta.tan() / (d / 2.0),
            t_tip: ((tip_diameter / 2.0 / rb).powi(2) - 1.0).sqrt(),
        }
    }

    /// The point at roll t and face position w of tooth `j`'s flank facing
    /// +θ (`side` = 1) or −θ (`side` = −1).
    fn point(&self, j: usize, side: f64, t: f64, w: f64) -> [f64; 3] {
        let r = self.rb * (1.0 + t * t).sqrt();
        let centre = 2.0 * PI * j as f64 / self.z as f64;
        let a = centre + side * (self.psi_b - (t - t.atan())) + self.twist * w;
        [r * a.cos(), r * a.sin(), w]
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The minimum of `f` on [lo, hi] by golden section (f unimodal there).
fn golden_min(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    for _ in 0..120 {
        let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if f(a) < f(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let x = (lo + hi) / 2.0;
    (x, f(x))
}

/// The largest p·u over a flank (roll by golden section, face on a grid):
/// the support of the flank in direction u, and the roll it is reached at.
fn support(fl: &Flanks, j: usize, side: f64, u: [f64; 3], face: f64) -> (f64, f64) {
    let mut best = (f64::MIN, 0.0);
    for i in 0..=100 {
        let w = -face / 2.0 + face * i as f64 / 100.0;
        let (t, v) = golden_min(0.0, fl.t_tip, |t| -dot(fl.point(j, side, t, w), u));
        if -v > best.0 {
            best = (-v, t);
        }
    }
    best
}

/// The caliper over k teeth: jaws on the −θ flank of tooth 0 and the +θ
/// flank of tooth k−1, their normal u in the plane of the group's middle
/// tangent and the axis, tilted by τ; the caliper settles where its jaws
/// lie flat on the flanks, the tilt of locally least width (tilted off it,
/// a jaw rests on an end of the face and opens). That local minimum lies
/// within ±0.6 rad for these gears; further out the width falls again as
/// cos τ, which is the jaw slipping off the gear, not a measurement.
/// Returns the width and the rolls of the two contacts in the section
/// w = 0, where the group is symmetric about its middle.
fn brute_span(fl: &Flanks, k: usize, face: f64) -> (f64, f64, f64) {
    let mid = (k as f64 - 1.0) * PI / fl.z as f64;
    let dir = |tau: f64| [-mid.sin() * tau.cos(), mid.cos() * tau.cos(), tau.sin()];
    let width = |tau: f64| {
        let u = dir(tau);
        let minus = [-u[0], -u[1], -u[2]];
        support(fl, k - 1, 1.0, u, face).0 + support(fl, 0, -1.0, minus, face).0
    };
    let (tau, w) = golden_min(-0.6, 0.6, width);
    let u = dir(tau);
    let t_b = support(fl, k - 1, 1.0, u, 0.0).1;
    let t_a = support(fl, 0, -1.0, [-u[0], -u[1], -u[2]], 0.0).1;
    (w, t_a, t_b)
}

/// The distance from `c` to tooth j's flank, minimised over the flank.
fn distance(fl: &Flanks, j: usize, side: f64, c: [f64; 3], reach: f64) -> f64 {
    golden_min(-reach, reach, |w| {
        golden_min(0.0, fl.t_tip, |t| {
            let p = fl.point(j, side, t, w);
            ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2) + (p[2] - c[2]).powi(2)).sqrt()
        })
        .1
    })
    .1
}

/// The ball in the space between teeth 0 and 1, centred on the space's
/// middle line in the plane w = 0, pushed in until it touches: its centre
/// radius by bisection. Also returns the distance to the other flank.
fn brute_ball(fl: &Flanks, ball: f64) -> (f64, f64) {
    let a = PI / fl.z as f64;
    let at = |r: f64| [r * a.cos(), r * a.sin(), 0.0];
    // From the base circle (too deep: the ball cuts the flanks) to beyond
    // the tip (loose).
    let (mut lo, mut hi) = (fl.rb, fl.rb * (1.0 + fl.t_tip * fl.t_tip).sqrt() + ball);
    for _ in 0..80 {
        let r = (lo + hi) / 2.0;
        if distance(fl, 0, 1.0, at(r), 3.0 * ball) < ball / 2.0 {
            lo = r;
        } else {
            hi = r;
        }
    }
    let r = (lo + hi) / 2.0;
    (r, distance(fl, 1, -1.0, at(r), 3.0 * ball))
}

/// The dimension over two such balls in the most nearly opposite spaces,
/// both in the plane w = 0: the distance of their centres plus a ball.
fn brute_over_balls(fl: &Flanks, ball: f64) -> f64 {
    let (r, _) = brute_ball(fl, ball);
    let m = fl.z / 2; // z/2 spaces on (odd z: (z−1)/2)
    let a1 = PI / fl.z as f64;
    let a2 = a1 + 2.0 * PI * m as f64 / fl.z as f64;
    r * ((a1.cos() - a2.cos()).powi(2) + (a1.sin() - a2.sin()).powi(2)).sqrt() + ball
}

struct Case {
    g: Involute,
    x: f64,
    k: u32,
    ball: f64,
    face: f64,
}

fn cases() -> Vec<Case> {
    let c = |z, mn, an, b, x, k, ball, face| Case {
        g: Involute::new(z, mn, an, b).unwrap(),
        x,
        k,
        ball,
        face,
    };
    vec![
        c(24, 3.0, 20.0, 0.0, 0.4, 4, 5.25, 20.0),
        c(17, 2.0, 20.0, 0.0, 0.0, 2, 3.5, 20.0),
        c(31, 2.5, 20.0, 18.0, 0.2, 4, 4.5, 30.0),
        c(40, 1.5, 25.0, -25.0, -0.1, 6, 2.5, 30.0),
    ]
}

#[test]
fn the_span_formula_matches_a_caliper_on_built_flanks() {
    for case in cases() {
        let g = case.g;
        let sn = g.thickness_from_shift(case.x);
        let tip = g.reference_diameter_mm() + 2.0 * g.normal_module_mm * (1.0 + case.x);
        let fl = Flanks::new(&g, sn, tip);
        let (w, t_a, t_b) = brute_span(&fl, case.k as usize, case.face);
        let want = g.span_mm(case.k, sn).unwrap();
        assert_relative_eq!(w, want, epsilon = 2e-6);
        // The jaws touch inside the flanks, not on their ends, and where the
        // contact-diameter formula says.
        assert!(t_a > 0.01 && t_a < fl.t_tip - 0.01, "contact at t = {t_a}");
        let dc = 2.0 * fl.rb * (1.0 + t_b * t_b).sqrt();
        let want_dc = g.span_contact_diameter_mm(case.k, sn).unwrap();
        assert_relative_eq!(dc, want_dc, epsilon = 1e-3);
        assert_relative_eq!(
            g.thickness_from_span(case.k, w).unwrap(),
            sn,
            epsilon = 2e-6
        );
    }
}

#[test]
fn the_ball_formula_matches_a_ball_pushed_into_built_flanks() {
    for case in cases() {
        let g = case.g;
        let sn = g.thickness_from_shift(case.x);
        let tip = g.reference_diameter_mm() + 2.0 * g.normal_module_mm * (1.0 + case.x);
        let fl = Flanks::new(&g, sn, tip);
        let (r, other) = brute_ball(&fl, case.ball);
        assert_relative_eq!(other, case.ball / 2.0, epsilon = 1e-7);
        assert_relative_eq!(
            2.0 * r,
            g.ball_centre_diameter_mm(case.ball, sn).unwrap(),
            epsilon = 1e-6
        );
        let over = brute_over_balls(&fl, case.ball);
        assert_relative_eq!(
            over,
            g.over_balls_mm(case.ball, sn).unwrap(),
            epsilon = 2e-6
        );
        assert_relative_eq!(
            g.thickness_from_over_balls(case.ball, over).unwrap(),
            sn,
            epsilon = 1e-5
        );
    }
}

#[test]
fn the_span_of_the_hand_worked_spur_gear() {
    // z = 24, m = 3, αn = 20°, x = +0.4, k = 4, by hand:
    // m·cos α = 2.8190779; (k − 0.5)·π = 10.9955743; z·inv 20° = 24 ·
    // 0.0149044 = 0.3577052; 2.8190779 · 11.3532795 = 32.0057789;
    // + 2·x·m·sin α = 2.4 · 0.3420201 = 0.8208483: Wk = 32.8266272.
    let g = Involute::new(24, 3.0, 20.0, 0.0).unwrap();
    let sn = g.thickness_from_shift(0.4);
    assert_relative_eq!(g.span_mm(4, sn).unwrap(), 32.8266272, epsilon = 1e-6);
    assert_eq!(g.span_teeth(sn).unwrap(), 4);
    // x = 0, z = 24: the usual rule k = z·α/180° + 0.5 = 3.17 → 3.
    assert_eq!(g.span_teeth(g.thickness_from_shift(0.0)).unwrap(), 3);
}

#[test]
fn out_of_range_inputs_are_refused() {
    let g = Involute::new(24, 3.0, 20.0, 0.0).unwrap();
    assert!(g.span_mm(0, 4.7).is_err());
    assert!(g.span_mm(24, 4.7).is_err());
    assert!(g.over_balls_mm(0.0, 4.7).is_err());
    assert!(g.thickness_from_over_balls(5.0, 10.0).is_err());
    assert!(Involute::new(2, 3.0, 20.0, 0.0).is_err());
    assert!(Involute::new(24, 3.0, 60.0, 0.0).is_err());
    assert!(inv_inverse(-0.1).is_err());
}

proptest! {
    #[test]
    fn inv_inverse_inverts_inv(a in 0.01f64..1.4) {
        prop_assert!((inv_inverse(inv(a)).unwrap() - a).abs() < 1e-10);
    }

    #[test]
    fn thickness_round_trips_through_span_and_balls(
        z in 8u32..200, mn in 0.5f64..20.0, beta in -40.0f64..40.0, x in -0.4f64..0.6,
    ) {
        let g = Involute::new(z, mn, 20.0, beta).unwrap();
        let sn = g.thickness_from_shift(x);
        let k = g.span_teeth(sn).unwrap();
        let w = g.span_mm(k, sn).unwrap();
        prop_assert!((g.thickness_from_span(k, w).unwrap() - sn).abs() < 1e-9 * mn);
        let ball = 1.7 * mn;
        let m = g.over_balls_mm(ball, sn).unwrap();
        prop_assert!((g.thickness_from_over_balls(ball, m).unwrap() - sn).abs() < 1e-8 * mn);
        // One more tooth in the span adds one normal base pitch π·mn·cos αn.
        if k + 1 < z {
            let step = g.span_mm(k + 1, sn).unwrap() - w;
            prop_assert!((step - PI * mn * 20f64.to_radians().cos()).abs() < 1e-9 * mn);
        }
    }
}
