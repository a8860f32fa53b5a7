//! A 3B program of many blocks without drift, and blocks turned by quarter
//! turns as a control's rotate instruction does.

mod common;

use common::{circle, dist, seg_gap, turn_segment};
use gearcam_wire::threeb::{block, program, program_from, read, replay, rotate_quarter};
use gearcam_wire::Segment;
use proptest::prelude::*;

/// Where the control ends each block, replaying `text` from `start`.
fn ends(text: &str, start: (f64, f64)) -> Vec<(f64, f64)> {
    replay(&read(text).unwrap(), start)
        .iter()
        .map(Segment::to)
        .collect()
}

/// The largest distance between the replayed block ends and the ideal ends.
fn worst(text: &str, segments: &[Segment]) -> f64 {
    ends(text, segments[0].from())
        .iter()
        .zip(segments)
        .map(|(e, s)| dist(*e, s.to()))
        .fold(0.0, f64::max)
}

/// Each block rounded on its own, as the first writer did.
fn independent(segments: &[Segment]) -> String {
    let mut p: String = segments.iter().map(|s| block(s) + "\n").collect();
    p.push_str("DD\n");
    p
}

/// A random chain of `n` arcs joined without a corner (a small LCG, so the
/// chain is the same on every run): turning 2°–30° each way, radius 3–60 mm,
/// off the µm grid.
fn arc_chain(n: usize) -> Vec<Segment> {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut unit = move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut p = (0.123_456_7, -0.765_432_1);
    let mut heading: f64 = 0.3;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let r = 3.0 + 57.0 * unit();
        let turn = (2.0 + 28.0 * unit()).to_radians();
        let ccw = unit() < 0.5;
        // The centre is on the left of the heading for a counter-clockwise arc.
        let side = if ccw { 1.0 } else { -1.0 };
        let normal = (-heading.sin() * side, heading.cos() * side);
        let c = (p.0 + r * normal.0, p.1 + r * normal.1);
        let a0 = (p.1 - c.1).atan2(p.0 - c.0);
        let a1 = a0 + side * turn;
        let to = (c.0 + r * a1.cos(), c.1 + r * a1.sin());
        out.push(Segment::Arc {
            from: p,
            to,
            centre: c,
            ccw,
        });
        p = to;
        heading += side * turn;
    }
    out
}

/// 500 arcs of a circle and chains of 600 and 2,400 random arcs: replayed
/// block by block, every end of the drift-free program stays within 1.5 µm
/// of its
/// ideal end, however many blocks came before; the same blocks rounded on
/// their own wander further the more blocks there are.
#[test]
fn many_blocks_do_not_drift() {
    for segments in [
        circle(37.123_456_7, 500, 12.345),
        arc_chain(600),
        arc_chain(2400),
    ] {
        let text = program(&segments);
        let fixed = worst(&text, &segments);
        assert!(fixed < 0.0015, "drift-free program off by {fixed} mm");
        // The arcs themselves keep to the ideal circles: the middle of each
        // replayed arc within 3 µm of its ideal circle.
        for (b, s) in replay(&read(&text).unwrap(), segments[0].from())
            .iter()
            .zip(&segments)
        {
            let (
                Segment::Arc {
                    from,
                    to,
                    centre,
                    ccw,
                },
                Segment::Arc { centre: c, .. },
            ) = (*b, *s)
            else {
                panic!("arcs replay as arcs");
            };
            let a0 = (from.1 - centre.1).atan2(from.0 - centre.0);
            let a1 = (to.1 - centre.1).atan2(to.0 - centre.0);
            let sweep = if ccw { a1 - a0 } else { a0 - a1 }.rem_euclid(std::f64::consts::TAU);
            let am = if ccw {
                a0 + sweep / 2.0
            } else {
                a0 - sweep / 2.0
            };
            let r = dist(from, centre);
            let mid = (centre.0 + r * am.cos(), centre.1 + r * am.sin());
            let off = (dist(mid, c) - dist(s.from(), c)).abs();
            assert!(off < 0.003, "{off} mm off the ideal circle");
        }
        let drifting = worst(&independent(&segments), &segments);
        eprintln!("worst end: drift-free {fixed} mm, independent {drifting} mm");
        assert!(drifting > 3.0 * fixed, "{drifting} vs {fixed}");
    }
}

/// The first block starts where the caller says, not at the first segment's
/// start: a program from (0.0004, 0) to a segment starting at (0, 0) makes
/// good the 0.4 µm at once.
#[test]
fn program_from_counts_from_the_given_start() {
    let line = Segment::Line {
        from: (0.0, 0.0),
        to: (1.0, 0.0),
    };
    assert_eq!(
        program_from((0.0004, 0.0), &[line]),
        "B1000B0B1000GXL1\nDD\n"
    );
    assert_eq!(program_from((0.0006, 0.0), &[line]), "B999B0B999GXL1\nDD\n");
    // The published check still holds through the program writer.
    let circle = Segment::Arc {
        from: (9.9, 0.0),
        to: (9.9, 0.0),
        centre: (0.0, 0.0),
        ccw: true,
    };
    assert_eq!(program(&[circle]), "B9900B0B39600GYNR1\nDD\n");
}

/// A line turned by a quarter: quadrant 1 → 2, X and Y swap, GX → GY.
#[test]
fn a_quarter_turn_of_one_block() {
    let b = read("B3000B1000B3000GXL1\nB0B5000B5000GYSR1\nDD\n").unwrap();
    let one: Vec<String> = rotate_quarter(&b, 1)
        .iter()
        .map(|b| b.to_string())
        .collect();
    assert_eq!(one, ["B1000B3000B3000GYL2", "B5000B0B5000GXSR2"]);
    let four: Vec<String> = rotate_quarter(&b, 5)
        .iter()
        .map(|b| b.to_string())
        .collect();
    assert_eq!(four, ["B1000B3000B3000GYL2", "B5000B0B5000GXSR2"]);
    assert_eq!(rotate_quarter(&b, 4), b);
}

/// A random segment of a contour, with its start on the µm grid.
fn any_segment() -> impl Strategy<Value = Segment> {
    let g = |v: f64| (v * 1000.0).round() / 1000.0;
    (
        -40.0f64..40.0,
        -40.0f64..40.0,
        1.0f64..30.0,
        0.0f64..std::f64::consts::TAU,
        0.1f64..6.0,
        0u8..3,
    )
        .prop_map(move |(x, y, r, a0, sweep, kind)| {
            let from = (g(x), g(y));
            if kind == 0 {
                let to = (g(x + r * a0.cos()), g(y + r * a0.sin()));
                return Segment::Line { from, to };
            }
            let ccw = kind == 1;
            let centre = (from.0 - r * a0.cos(), from.1 - r * a0.sin());
            let a1 = if ccw { a0 + sweep } else { a0 - sweep };
            let to = (centre.0 + r * a1.cos(), centre.1 + r * a1.sin());
            Segment::Arc {
                from,
                to,
                centre,
                ccw,
            }
        })
}

proptest! {
    /// The blocks turned by k quarters replay (from the turned start) to the
    /// replay of the original blocks turned by k·90° about the origin: the
    /// turn is checked against an independent rotation of the points.
    #[test]
    fn turned_blocks_replay_turned(seg in prop::collection::vec(any_segment(), 1..6), k in 0u8..8) {
        let start = seg[0].from();
        let blocks = read(&program(&seg)).unwrap();
        let original = replay(&blocks, start);
        let deg = 90.0 * f64::from(k % 4);
        let turned = replay(&rotate_quarter(&blocks, k), common::turn(start, deg));
        prop_assert_eq!(turned.len(), original.len());
        for (t, o) in turned.iter().zip(&original) {
            let gap = seg_gap(t, &turn_segment(o, deg));
            prop_assert!(gap < 1e-9, "{gap} mm: {t:?} vs {o:?}");
        }
    }
}
