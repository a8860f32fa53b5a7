//! An involute flank through the whole wire chain as far as it is built:
//! the exact distance, the arc fit, the 3B program, read back and replayed.

use gearcam_arcfit::{fit, Curve, Options};
use gearcam_wire::involute::Involute;
use gearcam_wire::threeb::{program, read, replay};
use gearcam_wire::Segment;

/// m 2, z 20, α 20°, x 0, ha* 1: the flank from the rack's form circle
/// (√(rb² + (r·sin α − ha*·m/sin α)²)) to the tip circle.
fn flank() -> Involute {
    let (m, z, alpha) = (2.0, 20.0, 20f64.to_radians());
    let r = m * z / 2.0;
    let rb = r * alpha.cos();
    let r_form = (rb * rb + (r * alpha.sin() - m / alpha.sin()).powi(2)).sqrt();
    Involute::between_radii(rb, r_form, r + m)
}

/// The closed-form distance equals a brute-force nearest-point search.
#[test]
fn the_closed_form_distance_is_the_nearest_point_distance() {
    let inv = flank();
    let (t0, t1) = inv.domain();
    for k in 0..50 {
        let t = t0 + (t1 - t0) * (f64::from(k) + 0.5) / 50.0;
        let p = inv.point(t);
        let off = 0.02 * (f64::from(k) - 25.0) / 25.0;
        let q = (p.0 + off * t.sin(), p.1 - off * t.cos());
        let brute = (0..=20_000)
            .map(|i| {
                let s = inv.point(t0 + (t1 - t0) * f64::from(i) / 20_000.0);
                ((s.0 - q.0).powi(2) + (s.1 - q.1).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        let exact = inv.distance(q);
        // The scan's spacing bounds its own error (about 0.2 µm here).
        assert!(
            (exact - brute).abs() < 2e-4 && exact <= brute + 1e-12,
            "{k}: {exact} vs {brute}"
        );
        assert!((exact - off.abs()).abs() < 1e-9, "{k}");
    }
}

/// The flank at 1 µm, written as 3B, read back and replayed: the replayed
/// path's deviation from the involute, measured with the exact distance on
/// 2,000 points per block, is the fit's plus the format's µm rounding.
#[test]
fn the_flank_in_3b_replays_onto_the_involute() {
    let inv = flank();
    let f = fit(&inv, &Options::tolerance(0.001)).unwrap();
    let segments: Vec<Segment> = f.arcs.iter().map(Segment::of_arc).collect();
    let text = program(&segments);
    let back = replay(&read(&text).unwrap(), segments[0].from());
    assert_eq!(back.len(), f.arcs.len());
    let mut worst: f64 = 0.0;
    for s in &back {
        let Segment::Arc {
            from, centre, ccw, ..
        } = *s
        else {
            panic!("a line")
        };
        let to = s.to();
        let r = ((from.0 - centre.0).powi(2) + (from.1 - centre.1).powi(2)).sqrt();
        let a0 = (from.1 - centre.1).atan2(from.0 - centre.0);
        let a1 = (to.1 - centre.1).atan2(to.0 - centre.0);
        let sweep = if ccw { a1 - a0 } else { a0 - a1 }.rem_euclid(std::f64::consts::TAU);
        for i in 0..=2000 {
            let a = a0 + if ccw { 1.0 } else { -1.0 } * sweep * f64::from(i) / 2000.0;
            worst = worst.max(inv.distance((centre.0 + r * a.cos(), centre.1 + r * a.sin())));
        }
    }
    let closure = {
        let (e, goal) = (back.last().unwrap().to(), inv.point(inv.roll_to));
        ((e.0 - goal.0).powi(2) + (e.1 - goal.1).powi(2)).sqrt()
    };
    eprintln!(
        "m2 z20 flank: {} arcs, fit {:.3} um, 3B replay {:.3} um, end {:.3} um from the tip point\n{text}",
        f.arcs.len(),
        f.max_deviation * 1000.0,
        worst * 1000.0,
        closure * 1000.0
    );
    assert!(f.arcs.len() <= 4);
    assert!(worst <= f.max_deviation + 0.0015, "{worst}");
    assert!(closure <= 0.0025, "{closure}");
}
