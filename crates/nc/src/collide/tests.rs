//! Unit tests of the closed-form clearance on set-ups with a known answer.

use super::hook::{depth, Depth};
use super::{HobMove, Solid};

/// A hob standing still at (X, Z) with tilt η.
fn still(x: f64, z: f64, eta_deg: f64, radius: f64, half_length: f64) -> HobMove {
    HobMove {
        from: [x, z, 0.0],
        to: [x, z, 0.0],
        eta_from_deg: eta_deg,
        eta_to_deg: eta_deg,
        radius,
        half_length,
    }
}

fn blank(z_lo: f64, z_hi: f64, r: f64) -> Solid {
    Solid {
        z_lo,
        z_hi,
        r_lo: r,
        r_hi: r,
    }
}

fn bracketed(d: &Depth) {
    assert!(d.hi - d.lo <= 1e-4, "{d:?}");
}

#[test]
fn a_hob_just_above_a_disc_is_outside_and_just_below_is_inside() {
    // Hob r 40 × 100 without tilt at X = 73.75 over a blank R 40.5
    // (h 6.75): the lowest point over the disc lies √(h·(2r − h)) =
    // 22.235951 mm below the hob centre, at the blank's rim.
    let reach = (6.75f64 * (80.0 - 6.75)).sqrt();
    let ob = blank(0.0, 30.0, 40.5);
    let at = |z: f64| depth(&still(73.75, z, 0.0, 40.0, 50.0), &ob);
    // Outside, the depth is minus the distance: 0.5 mm above the rim, the
    // distance from the rim (40.5, 0, 30) to the hob's axis line, less r.
    let above = at(30.0 + reach + 0.5);
    bracketed(&above);
    let gap = (73.75f64 - 40.5).hypot(reach + 0.5) - 40.0;
    assert!((above.lo + gap).abs() < 1e-4, "{above:?} {gap}");
    let touching = at(30.0 + reach + 0.01);
    assert!(touching.hi < 0.0, "{touching:?}");
    // 0.5 mm below, the rim is inside the hob by r less its distance from the
    // axis line.
    let below = at(30.0 + reach - 0.5);
    bracketed(&below);
    let inside = 40.0 - (73.75f64 - 40.5).hypot(reach - 0.5);
    assert!(
        below.lo > 0.1 && below.lo >= inside - 1e-4,
        "{below:?} {inside}"
    );
}

#[test]
fn a_tilted_hob_reaches_further_down_by_its_length() {
    // Tilted by 30° with half length 50, the low end of the axis is 25 mm
    // below the centre, and the tip cylinder r·cos 30° below that.
    let table = Solid {
        z_lo: f64::NEG_INFINITY,
        z_hi: 0.0,
        r_lo: 500.0,
        r_hi: 500.0,
    };
    let low = 25.0 + 10.0 * 30f64.to_radians().cos();
    let w = depth(&still(100.0, low - 1.0, 30.0, 10.0, 50.0), &table);
    bracketed(&w);
    assert!((w.lo - 1.0).abs() < 1e-4, "{w:?}");
    assert!(w.hob_point && w.at[2].abs() < 1.0 + 1e-4, "{w:?}");
    let w = depth(&still(100.0, low + 1.0, 30.0, 10.0, 50.0), &table);
    bracketed(&w);
    assert!((w.lo + 1.0).abs() < 1e-4, "{w:?}");
}

#[test]
fn a_move_through_the_blank_is_caught_between_its_end_points() {
    // A rapid straight across a small blank: both end poses are clear,
    // the middle of the move is not.
    let ob = blank(0.0, 10.0, 20.0);
    let mv = HobMove {
        from: [-100.0, 5.0, 0.0],
        to: [100.0, 5.0, 0.0],
        ..still(0.0, 0.0, 0.0, 5.0, 10.0)
    };
    for t in [0.0, 1.0] {
        let end = HobMove {
            from: if t == 0.0 { mv.from } else { mv.to },
            to: if t == 0.0 { mv.from } else { mv.to },
            ..mv
        };
        assert!(depth(&end, &ob).hi < 0.0);
    }
    let w = depth(&mv, &ob);
    bracketed(&w);
    // Through the middle the blank's mid-plane point on the axis is 5 mm
    // inside the hob (its radius), and the hob's axis 5 mm inside the blank
    // (half the face width): D* = 5.
    assert!((w.lo - 5.0).abs() < 1e-4, "{w:?}");
}

#[test]
fn a_support_almost_along_the_axis_stays_on_the_end_face() {
    // Found by the property test against the sampled sweep: for a direction
    // 1e-11 off the hob's axis, the rim point was taken along the rounding
    // residue of n − (n·u)u, 4e-4 mm beyond the end face, and the distance
    // query's lower bound was no bound.
    use super::shapes::Support;
    use super::P3;
    let hob = HobMove::axis(-15.934);
    let sweep = super::Sweep {
        start: P3::new(19.2, 29.9, 118.9),
        travel: P3::zeros(),
        axis: hob,
        r: 36.257,
        half: 31.328,
    };
    let off = hob.cross(&P3::new(1.0, 0.0, 0.0));
    for k in [1e-9, 1e-11, 1e-13] {
        let (p, _) = sweep.support(&(-hob + off * k));
        let v = p - sweep.start;
        let a = v.dot(&hob);
        let w = (v - hob * a).norm();
        assert!((a.abs() - sweep.half).abs() < 1e-12, "{k}: a {a}");
        assert!(w <= sweep.r + 1e-12, "{k}: w {w}");
    }
}

mod swivel {
    use super::super::depth::{straight, Need, TAU};
    use super::super::P3;
    use super::*;
    use proptest::prelude::*;

    fn swivel_move() -> impl Strategy<Value = HobMove> {
        (
            prop::array::uniform3(-100.0..100.0f64),
            prop::array::uniform3(-100.0..100.0f64),
            -45.0..45.0f64,
            -45.0..45.0f64,
            5.0..60.0f64,
            5.0..100.0f64,
        )
            .prop_map(
                |(from, to, eta_from_deg, eta_to_deg, radius, half_length)| HobMove {
                    from,
                    to,
                    eta_from_deg,
                    eta_to_deg,
                    radius,
                    half_length,
                },
            )
    }

    /// The point of the hob at body coordinates (w1 across along X, w2
    /// across the other way, a along the axis) at the move's parameter t.
    fn body_point(m: &HobMove, t: f64, w: [f64; 3]) -> P3 {
        let pose = m.pose_at(t);
        let e1 = P3::new(1.0, 0.0, 0.0);
        let e2 = pose.axis.cross(&e1);
        pose.start + e1 * w[0] + e2 * w[1] + pose.axis * w[2]
    }

    proptest! {
        /// The branch and bound's constant bounds the speed of every hob
        /// point (the derivation in `HobMove::lipschitz`), checked on the
        /// poses themselves.
        #[test]
        fn no_hob_point_moves_faster_than_the_lipschitz_constant(
            m in swivel_move(),
            t in (0.0..1.0f64, 0.0..1.0f64),
            w in (0.0..1.0f64, 0.0..std::f64::consts::TAU, -1.0..1.0f64),
        ) {
            let (radius, angle, along) = w;
            let body = [
                radius * m.radius * angle.cos(),
                radius * m.radius * angle.sin(),
                along * m.half_length,
            ];
            let moved = (body_point(&m, t.0, body) - body_point(&m, t.1, body)).norm();
            prop_assert!(moved <= m.lipschitz() * (t.0 - t.1).abs() + 1e-9);
        }

        /// And so the depth of the poses into a solid changes no faster.
        #[test]
        fn the_depth_changes_no_faster_than_the_lipschitz_constant(
            m in swivel_move(),
            t in (0.0..1.0f64, 0.0..1.0f64),
            cone in (0.0..50.0f64, 10.0..120.0f64, 10.0..120.0f64),
        ) {
            let solid = Solid {
                z_lo: cone.0 - 60.0,
                z_hi: cone.0,
                r_lo: cone.1,
                r_hi: cone.2,
            };
            let at = |t: f64| straight(&m.pose_at(t), &solid, Need::Exact);
            let (a, b) = (at(t.0), at(t.1));
            let bound = m.lipschitz() * (t.0 - t.1).abs() + 2.0 * TAU;
            prop_assert!(a.lo - b.hi <= bound && b.lo - a.hi <= bound, "{a:?} {b:?}");
        }
    }
}
