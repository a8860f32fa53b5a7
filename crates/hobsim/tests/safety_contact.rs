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
        teeth: 25,
        crowning_mm: 0.0,
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
