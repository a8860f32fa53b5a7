//! The pierce solution and its tangent against their definitions.

use super::*;
use crate::kinematics::{Gearbox, Segment};

/// A helical cut: the hob tilted, feeding down in Z and in by X, the
/// table coupled with a differential.
fn pass<'t>(timeline: &'t Timeline, hob: &Hob) -> Pass<'t> {
    let s = &timeline.segments()[0];
    Pass::new(
        timeline,
        0,
        0.5 * (s.t0_s + s.t1_s),
        hob,
        0,
        45.0,
        Resolution::fine(),
    )
}

/// The hob's tests' hob with rounded tips (1 mm), and a helical cut.
fn setup() -> (Hob, Timeline) {
    setup_swivelled(0.35)
}

/// [`setup`] with the hob swivelled by `eta_rad`.
fn setup_swivelled(eta_rad: f64) -> (Hob, Timeline) {
    let hob = Hob {
        tip_corner_radius_mm: 1.0,
        ..crate::hob::tests::hob()
    };
    let axes = |x: f64, z: f64| Axes {
        x_mm: x,
        y_mm: 0.0,
        z_mm: z,
    };
    let timeline = Timeline::from_segments(vec![Segment {
        line: 0,
        t0_s: 0.0,
        t1_s: 60.0,
        from: axes(82.0, 130.0),
        to: axes(81.5, 100.0),
        eta_rad,
        hob_rev_s: 2.0,
        gearbox: Some(Gearbox {
            c_per_b: 1.0 / 25.0,
            c_per_z_rad_mm: 0.004,
            c_per_y_rad_mm: 0.0,
        }),
        c_extra_rad: 0.0,
        feed: true,
    }])
    .expect("timeline");
    (hob, timeline)
}

/// Every pierce point is where its disc meets the section at the hob
/// angle it was posed at: atan2(t, s) = φ within the 10⁻⁸ rad one
/// Newton step is held to (a step the wrong way is 10⁻⁴ rad off).
#[test]
fn a_pierce_point_is_posed_at_its_own_hob_angle() {
    let (hob, timeline) = setup();
    let p = pass(&timeline, &hob);
    let mut checked = 0;
    for dz in [-20.0, -5.0, 0.0, 3.0, 12.0] {
        let zs = p.q0.axes.z_mm + dz;
        for i in 0..400 {
            let a = -40.0 + 80.0 * f64::from(i) / 400.0;
            if let Some(q) = p.pierce_at(a, p.edge.radius(a), zs, None) {
                let err = (q.tt.atan2(q.s) - q.phi).abs();
                assert!(err < 1e-8, "a {a}, z {zs}: φ off by {err} rad");
                checked += 1;
            }
        }
    }
    assert!(checked > 500, "{checked} points");
}

/// The tangent of the pierce curve is its derivative: a central
/// difference of pierce points away from the profile's knots, on the
/// tip land, the corner arcs, the flanks and the root.
#[test]
fn the_tangent_is_the_derivative_of_the_pierce_curve() {
    let (hob, timeline) = setup();
    let p = pass(&timeline, &hob);
    let zs = p.q0.axes.z_mm + 3.0;
    let mut checked = 0;
    for a in p.edge.off_knots(-30.0, 30.0, 600, 1.3e-3) {
        let h = 1e-5;
        let at = |a: f64| p.pierce_at(a, p.edge.radius(a), zs, None);
        let (Some(mid), Some(lo), Some(hi)) = (at(a), at(a - h), at(a + h)) else {
            continue;
        };
        let fd = [
            (hi.point[0] - lo.point[0]) / (2.0 * h),
            (hi.point[1] - lo.point[1]) / (2.0 * h),
        ];
        for dir in [1.0, -1.0] {
            let Some(t) = p.tangent(&mid, dir) else {
                continue;
            };
            let err = (t[0] - fd[0]).hypot(t[1] - fd[1]);
            assert!(
                err < 1e-5 * (1.0 + fd[0].hypot(fd[1])),
                "a {a}: tangent {t:?}, difference {fd:?}"
            );
            checked += 1;
        }
    }
    assert!(checked > 200, "{checked} tangents checked");
}

/// The axial interval `reach` gives holds every point of the section that
/// lies both within the tip radius of the hob axis and within the clip
/// radius of the gear axis (a brute-force scan of the section at 0.05 mm),
/// and no more than its widening (0.1 mm) and the scan's and the search's
/// steps beyond them; None comes only where there is no such point. With
/// the hob swivelled and not, and clip radii below and beyond the hob's
/// centre distance.
#[test]
fn the_reach_holds_every_point_of_both_discs() {
    let (mut inside, mut none) = (0, 0);
    for eta in [0.35, 0.0] {
        let (hob, timeline) = setup_swivelled(eta);
        let p = pass(&timeline, &hob);
        let (q, tip) = (p.pose(0.0), p.tip);
        for clip in [42.0, 45.0, 60.0, 90.0] {
            for dz in [-45.0, -38.0, -20.0, -5.0, 0.0, 7.0, 30.0, 41.0] {
                let zs = q.axes.z_mm + dz;
                let reach = p.reach(clip, zs);
                let (mut a_lo, mut a_hi) = (f64::MAX, f64::MIN);
                let n = (2.0 * clip / 0.05) as i32;
                for i in 0..=n {
                    let y = -clip + 0.05 * f64::from(i);
                    let t = y * p.se + dz * p.ce;
                    let half = (tip * tip - t * t).sqrt();
                    let x_far = (clip * clip - y * y).sqrt();
                    // The hob's disc meets the gear's at this y.
                    if !(half > 0.0 && q.axes.x_mm - half < x_far) {
                        continue;
                    }
                    let a = y * p.ce - dz * p.se - q.axes.y_mm;
                    (a_lo, a_hi) = (a_lo.min(a), a_hi.max(a));
                    inside += 1;
                }
                match reach {
                    None => {
                        assert!(a_lo > a_hi, "no reach at η {eta}, clip {clip}, dz {dz}");
                        none += 1;
                    }
                    Some((lo, hi)) if a_lo <= a_hi => {
                        let at =
                            format!("η {eta}, clip {clip}, dz {dz}: {lo}..{hi} for {a_lo}..{a_hi}");
                        assert!(lo < a_lo && hi > a_hi, "{at}");
                        assert!(lo > a_lo - 0.2 && hi < a_hi + 0.2, "{at}");
                    }
                    Some(_) => {}
                }
            }
        }
    }
    assert!(
        inside > 1000 && none > 0,
        "{inside} points, {none} sections out of reach"
    );
}
