//! The 4B format against seed 002's examples and against itself: what is
//! written reads back, passes the check, and replays to the outline.

mod common;

use common::{circle, dist, four_fold, seg_gap};
use gearcam_wire::fourb::{check, program, read, replay, Sense};
use gearcam_wire::threeb::Kind;

/// Seed 002's first example parses field by field, J with its leading zero,
/// and its R agrees with √(7718² + 37973²) ≈ 38749.4 µm. L3 on NR is convex
/// on a contour run counter-clockwise; on a clockwise one it is refused.
#[test]
fn the_seed_example() {
    let b = read("L338750B7718B37973B079483GXNR1\nDD\n").unwrap();
    assert_eq!(b.len(), 1);
    let b0 = b[0];
    assert_eq!(
        (b0.line, b0.radius_um, b0.convex),
        (1, Some(38750), Some(true))
    );
    let k = b0.block;
    assert_eq!((k.x, k.y, k.j, k.gx), (7718, 37973, 79483, true));
    assert_eq!((k.kind, k.quadrant), (Kind::CounterClockwise, 1));
    assert!((7718f64.hypot(37973.0) - 38749.4).abs() < 0.05);
    check(&b, Sense::CounterClockwise).unwrap();
    let e = check(&b, Sense::Clockwise).unwrap_err();
    assert!(e.message.contains("L4"), "{e:?}");
}

/// The seed's second example parses (J `000385` is 385), but its R of 808
/// µm is not the 38,750 µm its X and Y put the start from the centre: the
/// check refuses it, naming its line.
#[test]
fn the_second_seed_example_parses_and_is_refused() {
    let b = read("B1000B0B1000GXL1\nL4808B5735B38323B000385GXSR1\nDD\n").unwrap();
    assert_eq!(b[1].block.j, 385);
    assert_eq!(b[1].radius_um, Some(808));
    let e = check(&b, Sense::CounterClockwise).unwrap_err();
    assert_eq!(e.line, 2);
    assert!(e.message.contains("R 808"), "{e:?}");
}

/// Blocks that are not 4B, or disagree with themselves, name their line.
#[test]
fn bad_blocks_name_their_line() {
    let e = read("B1B2B2GXL1\nL5100B0B100B100GXNR1\nDD\n").unwrap_err();
    assert_eq!(e.line, 2);
    let e = read("L3B0B100B100GXNR1\nDD\n").unwrap_err();
    assert!(e.message.contains("radius"), "{e:?}");
    let e = read("L3100B0B100B100GXNR1\n").unwrap_err();
    assert!(e.message.contains("DD"), "{e:?}");
    // An arc without its kind, a line with one, R off by 3 µm.
    let bad = [
        "B1000B0B1000GYSR1\nDD\n",
        "L31000B1000B0B1000GXL1\nDD\n",
        "L31003B1000B0B1000GYSR1\nDD\n",
    ];
    for text in bad {
        let e = check(&read(text).unwrap(), Sense::Clockwise).unwrap_err();
        assert_eq!(e.line, 1, "{text}");
    }
    // R 2 µm off still passes.
    check(
        &read("L31002B1000B0B1000GYSR1\nDD\n").unwrap(),
        Sense::Clockwise,
    )
    .unwrap();
}

/// The 4-fold outline (convex tip arcs clockwise, concave notches
/// counter-clockwise, chords): written, every arc is L3 when clockwise and
/// L4 when counter-clockwise, with R its radius; it passes the check for a
/// clockwise contour and replays to the outline within 1.5 µm.
#[test]
fn an_outline_round_trips() {
    let outline = four_fold();
    let text = program(&outline);
    assert!(text.ends_with("DD\n"));
    let blocks = read(&text).unwrap();
    check(&blocks, Sense::Clockwise).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // L3 and the radius as written: within the writer's µm of the ideal
    // 20 mm (it may move the centre a µm to keep the arc on its circle).
    let r: i64 = lines[0][2..lines[0].find('B').unwrap()].parse().unwrap();
    assert!(
        lines[0].starts_with("L3") && (r - 20000).abs() <= 2,
        "{}",
        lines[0]
    );
    assert_eq!(r, blocks[0].radius_um.unwrap());
    assert!(lines[1].starts_with("L4"), "{}", lines[1]);
    assert!(lines[2].starts_with('B'), "{}", lines[2]);
    let back = replay(&blocks, outline[0].from());
    for (b, s) in back.iter().zip(&outline) {
        assert!(dist(b.to(), s.to()) < 0.0015, "{b:?} vs {s:?}");
        assert!(seg_gap(b, s) < 0.01, "{b:?} vs {s:?}");
    }
    // 500 short arcs, their centres moved a little against drift, keep R
    // within the check's 2 µm.
    check(
        &read(&program(&circle(37.123_456_7, 500, 12.3))).unwrap(),
        Sense::Clockwise,
    )
    .unwrap();
}
