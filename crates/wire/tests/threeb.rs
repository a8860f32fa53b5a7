//! The 3B format against its published example and against itself: what is
//! written reads back, and replayed as a control would, ends where the
//! segment ends (within the µm of the format).

use gearcam_wire::threeb::{block, program, read, replay};
use gearcam_wire::Segment;
use proptest::prelude::*;

/// The published 3B example (seed 002; docs/wire.md): the R 9.9 mm circle from
/// (9.9, 0) counter-clockwise about the origin.
#[test]
fn the_published_r9_9_circle() {
    let circle = Segment::Arc {
        from: (9.9, 0.0),
        to: (9.9, 0.0),
        centre: (0.0, 0.0),
        ccw: true,
    };
    assert_eq!(block(&circle), "B9900B0B39600GYNR1");
    // Read back and replayed: a whole circle, back at the start.
    let blocks = read(&program(&[circle])).unwrap();
    let s = replay(&blocks, (9.9, 0.0));
    let end = s[0].to();
    assert!((end.0 - 9.9).abs() < 1e-6 && end.1.abs() < 1e-6, "{end:?}");
}

/// Lines in each quadrant, the counting axis the larger component.
#[test]
fn lines_take_the_quadrant_of_their_move() {
    let line = |to: (f64, f64)| {
        block(&Segment::Line {
            from: (1.0, 1.0),
            to,
        })
    };
    assert_eq!(line((4.0, 2.0)), "B3000B1000B3000GXL1");
    assert_eq!(line((1.0, 5.0)), "B0B4000B4000GYL2");
    assert_eq!(line((-2.0, 1.0)), "B3000B0B3000GXL3");
    assert_eq!(line((2.0, -6.0)), "B1000B7000B7000GYL4");
    // A quarter circle from +Y clockwise to +X: SR1 (it moves into the
    // first quadrant), ends on X (|x| > |y|: counts along Y), J = R.
    let q = block(&Segment::Arc {
        from: (0.0, 5.0),
        to: (5.0, 0.0),
        centre: (0.0, 0.0),
        ccw: false,
    });
    assert_eq!(q, "B0B5000B5000GYSR1");
}

proptest! {
    /// Random arcs (any centre, radius 0.5–100 mm, any start, sweep up to
    /// almost a turn, either sense) written and replayed end within a few µm
    /// of their end (the format rounds to 1 µm).
    #[test]
    fn arcs_replay_to_their_end(
        cx in -50.0f64..50.0, cy in -50.0f64..50.0, r in 0.5f64..100.0,
        a0 in 0.0f64..std::f64::consts::TAU, sweep in 0.05f64..6.2, ccw in any::<bool>(),
    ) {
        let a1 = if ccw { a0 + sweep } else { a0 - sweep };
        // Start and end on the µm grid, as a program's coordinates are.
        let g = |v: f64| (v * 1000.0).round() / 1000.0;
        let from = (g(cx + r * a0.cos()), g(cy + r * a0.sin()));
        let centre = (g(cx), g(cy));
        let to = (g(cx + r * a1.cos()), g(cy + r * a1.sin()));
        let seg = Segment::Arc { from, to, centre, ccw };
        let blocks = read(&program(&[seg])).unwrap();
        let back = replay(&blocks, from);
        let end = back[0].to();
        let miss = ((end.0 - to.0).powi(2) + (end.1 - to.1).powi(2)).sqrt();
        // Off the grid by up to half a µm on each axis, the radius to 0.7 µm,
        // and a count near an extremum of the counting axis moves the end
        // along the circle by more: within 5 µm.
        prop_assert!(miss < 0.005, "{miss} mm: {}", block(&seg));
    }

    /// Random lines come back exactly (to the µm).
    #[test]
    fn lines_replay_exactly(x0 in -50.0f64..50.0, y0 in -50.0f64..50.0, dx in -50.0f64..50.0, dy in -50.0f64..50.0) {
        let g = |v: f64| (v * 1000.0).round() / 1000.0;
        let (from, to) = ((g(x0), g(y0)), (g(x0 + dx), g(y0 + dy)));
        let back = replay(&read(&program(&[Segment::Line { from, to }])).unwrap(), from);
        let end = back[0].to();
        prop_assert!((end.0 - to.0).abs() < 1e-9 && (end.1 - to.1).abs() < 1e-9);
    }
}

/// A block that is not 3B is refused with its line.
#[test]
fn bad_blocks_name_their_line() {
    let e = read("B1B2B2GXL1\nB1B2GXL1\nDD\n").unwrap_err();
    assert_eq!(e.line, 2);
    let e = read("B1B2B2GXL5\nDD\n").unwrap_err();
    assert!(e.message.contains("quadrant"), "{e:?}");
    assert!(read("B1B2B2GXL1\n").is_err(), "no DD");
}

/// A block a control could not follow ends in finite time: an arc of no
/// radius stays where it is, a count beyond a whole turn stops after one.
#[test]
fn impossible_arcs_end() {
    let s = replay(&read("B0B0B5000GXNR1\nDD\n").unwrap(), (1.0, 2.0));
    assert_eq!(s[0].to(), (1.0, 2.0));
    let s = replay(&read("B1000B0B99999999GYNR1\nDD\n").unwrap(), (1.0, 0.0));
    let end = s[0].to();
    assert!((end.0 - 1.0).abs() < 1e-9 && end.1.abs() < 1e-9, "{end:?}");
}
