//! The contact walk of `safety` on hand-built moves: the hob's end face, a
//! graze within the sampling bound, and the sampled distance against a finer
//! brute force.

mod common;

use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{Axes, Segment, Timeline};
use gearcam_hobsim::safety::{self, BlankGeometry, Fixtures, SafetyKind, SAMPLE_MM};

/// The spur program's hob, its tip radius 40 mm and length 100 mm.
fn hob() -> Hob {
    let (_, model) = common::program("spur_840d");
    let mut hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    hob.tip_radius_mm = 40.0;
    hob.length_mm = 100.0;
    hob
}

fn blank() -> BlankGeometry {
    BlankGeometry {
        outer_radius_mm: 40.5,
        z_lo_mm: 100.0,
        z_hi_mm: 130.0,
        root_radius_mm: 33.75,
        taper: 0.0,
        teeth: 25,
        crowning_mm: 0.0,
        throat_z_mm: None,
    }
}

/// One rapid move of 1 s from `from` to `to` at tilt η (radians).
fn rapid(from: Axes, to: Axes, eta: f64) -> Timeline {
    Timeline::from_segments(vec![Segment {
        line: 7,
        t0_s: 0.0,
        t1_s: 1.0,
        from,
        to,
        eta_rad: eta,
        hob_rev_s: 0.0,
        gearbox: None,
        c_extra_rad: 0.0,
        feed: false,
    }])
    .expect("timeline")
}

fn rapid_contacts(tl: &Timeline) -> Vec<String> {
    safety::check(tl, &hob(), &blank(), &Fixtures::default())
        .into_iter()
        .filter(|f| f.kind == SafetyKind::RapidContact)
        .map(|f| f.what)
        .collect()
}

/// η 0 puts u along y: with the hob's middle at x 0, y −89.5 its end face is
/// the disc y = −39.5 of radius 40 about (0, ·, 115), 1 mm into the blank of
/// radius 40.5 at x 0; its rim and lateral surface stay outside (a rim point
/// inside the face heights has |x| ≥ 37, so ρ ≥ √(37² + 39.5²) > 40.5).
#[test]
fn the_hobs_end_face_entering_the_blank_is_a_contact() {
    let at = |y| Axes {
        x_mm: 0.0,
        y_mm: y,
        z_mm: 115.0,
    };
    let tl = rapid(at(-120.0), at(-89.5), 0.0);
    let found = rapid_contacts(&tl);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains("enters the blank 1.000 mm"), "{found:?}");
    // 2 mm short of it: clear.
    let tl = rapid(at(-120.0), at(-91.5), 0.0);
    assert!(rapid_contacts(&tl).is_empty());
}

/// A rapid right across the blank above its upper face (η 0, X from 200 to
/// −200, both ends clear of it): the tip cylinder's lowest line stands `gap`
/// above the face. Every penetration deeper than 2·h is found, and a pass
/// `gap` ≥ 0 away never is.
#[test]
fn a_pass_over_the_blank_is_found_when_deeper_than_the_bound() {
    // The lowest line of the tip cylinder at η 0 is z = Z − 40.
    for gap in [-3.0, -1.5, -2.0 * SAMPLE_MM - 0.01, 0.0, 0.3, 2.0] {
        let at = |x| Axes {
            x_mm: x,
            y_mm: 0.0,
            z_mm: 130.0 + 40.0 + gap,
        };
        let tl = rapid(at(200.0), at(-200.0), 0.0);
        let found = rapid_contacts(&tl);
        assert_eq!(!found.is_empty(), gap < 0.0, "gap {gap}: {found:?}");
    }
}

/// A worm wheel's radial cut: a coupled feed from X 90 in to X 70 at the
/// middle of the face (the tip cylinder, radius 40, reaches 10.5 mm into
/// the blank of radius 40.5), a dwell, then a rapid. A rapid straight back
/// along the feed, coupled, retraces space the feed has cut: no contact.
/// The same rapid ending 1 mm higher, the way back with the gearbox off,
/// at another swivel, after a feed too fast to sweep every hob angle, or
/// after a rapid (not a feed) in, are contacts of the rapid's own line; so
/// is the way back on a blank that is not a worm wheel's.
#[test]
fn a_rapid_back_along_its_coupled_feed_is_no_contact_and_any_other_is() {
    let gearbox = Some(gearcam_hobsim::kinematics::Gearbox {
        c_per_b: 1.0 / 25.0,
        c_per_z_rad_mm: 0.0,
        c_per_y_rad_mm: 0.0,
    });
    let at = |x: f64, z: f64| Axes {
        x_mm: x,
        y_mm: 0.0,
        z_mm: z,
    };
    // 20 mm in 10 s at 50 turns a second: 25 turns per millimetre.
    let seg = |t0: f64, from: Axes, to: Axes, feed: bool, gearbox| Segment {
        line: t0 as u32,
        t0_s: t0,
        t1_s: t0 + 10.0,
        from,
        to,
        eta_rad: 0.0,
        hob_rev_s: 50.0,
        gearbox,
        c_extra_rad: 0.0,
        feed,
    };
    let worm = BlankGeometry {
        throat_z_mm: Some(115.0),
        ..blank()
    };
    let run_on = |blank: BlankGeometry, first: Segment, back: Segment| {
        let tl = Timeline::from_segments(vec![
            first,
            seg(10.0, at(70.0, 115.0), at(70.0, 115.0), false, gearbox),
            Segment {
                line: 2,
                t0_s: 20.0,
                t1_s: 20.1,
                ..back
            },
        ])
        .expect("timeline");
        safety::check(&tl, &hob(), &blank, &Fixtures::default())
            .into_iter()
            .filter(|f| f.kind == SafetyKind::RapidContact && f.line == 2)
            .map(|f| f.what)
            .collect::<Vec<_>>()
    };
    let feed_in = seg(0.0, at(90.0, 115.0), at(70.0, 115.0), true, gearbox);
    let run = |back: Segment| run_on(worm, feed_in, back);
    let back = seg(20.0, at(70.0, 115.0), at(90.0, 115.0), false, gearbox);
    assert!(run(back).is_empty(), "{:?}", run(back));
    let higher = seg(20.0, at(70.0, 115.0), at(90.0, 116.0), false, gearbox);
    assert!(!run(higher).is_empty());
    let decoupled = seg(20.0, at(70.0, 115.0), at(90.0, 115.0), false, None);
    assert!(!run(decoupled).is_empty());
    let swivelled = Segment {
        eta_rad: 0.01,
        ..back
    };
    assert!(!run(swivelled).is_empty());
    let fast = Segment {
        t1_s: 0.1,
        ..feed_in
    };
    assert!(!run_on(worm, fast, back).is_empty());
    let rapid_in = Segment {
        feed: false,
        ..feed_in
    };
    assert!(!run_on(worm, rapid_in, back).is_empty());
    // Not a worm wheel: the rule does not apply.
    assert!(!run_on(blank(), feed_in, back).is_empty());
}

/// A cone's frustum (the conical example's: radius 21.25 at the lower face,
/// 4 mm high, narrowing by tan 6.5° per mm up): its signed distance against
/// the nearest of its boundary's points sampled every 5 µm in the (ρ, z)
/// half-plane, negative inside, for points all round it, inside and out,
/// at every azimuth: within the sampling's 2.5 µm.
#[test]
fn a_frustums_signed_distance_is_its_nearest_boundary_points() {
    for cone in [
        safety::Cylinder {
            radius_mm: 21.25,
            z_lo_mm: 100.0,
            z_hi_mm: 104.0,
            taper: -6.5f64.to_radians().tan(),
        },
        // Its mirror: the large end on top.
        safety::Cylinder {
            radius_mm: 21.25 - 4.0 * 6.5f64.to_radians().tan(),
            z_lo_mm: 100.0,
            z_hi_mm: 104.0,
            taper: 6.5f64.to_radians().tan(),
        },
    ] {
        frustum_against_its_boundary(cone);
    }
}

/// [`a_frustums_signed_distance_is_its_nearest_boundary_points`] for one
/// frustum.
fn frustum_against_its_boundary(cone: safety::Cylinder) {
    let r_at = |z: f64| cone.radius_mm + cone.taper * (z - cone.z_lo_mm);
    let corners = [
        (0.0, cone.z_lo_mm),
        (cone.radius_mm, cone.z_lo_mm),
        (r_at(cone.z_hi_mm), cone.z_hi_mm),
        (0.0, cone.z_hi_mm),
    ];
    let mut boundary = Vec::new();
    for w in corners.windows(2) {
        let ((r0, z0), (r1, z1)) = (w[0], w[1]);
        let n = ((r1 - r0).hypot(z1 - z0) / 0.005).ceil() as usize;
        boundary.extend((0..=n).map(|k| {
            let f = k as f64 / n as f64;
            (r0 + f * (r1 - r0), z0 + f * (z1 - z0))
        }));
    }
    // A fixed sequence of points (a linear congruential generator): ρ up to
    // 30 mm, z from 97 to 107 mm, the azimuth anywhere.
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut inside = 0;
    for _ in 0..400 {
        let (rho, z, phi) = (30.0 * next(), 97.0 + 10.0 * next(), 6.3 * next());
        let is_in = (cone.z_lo_mm..=cone.z_hi_mm).contains(&z) && rho <= r_at(z);
        inside += usize::from(is_in);
        let near = boundary
            .iter()
            .map(|&(r, zz)| (rho - r).hypot(z - zz))
            .fold(f64::INFINITY, f64::min);
        let brute = if is_in { -near } else { near };
        let d = cone.signed_distance([rho * phi.cos(), rho * phi.sin(), z]);
        assert!(
            (d - brute).abs() < 0.0025,
            "ρ {rho} z {z}: {d} against {brute}"
        );
    }
    assert!(inside > 50, "{inside} points inside");
}
