//! ISO wire G-code written and replayed: the outline comes back with its
//! lead-in and lead-out and the compensation side, a repeated section turned
//! by G68 comes back as the whole outline, and words outside the subset are
//! refused by line.

mod common;

use common::{circle, dist, four_fold, quarter, seg_gap, square};
use gearcam_wire::iso::{program, replay, IsoProgram, Side};
use gearcam_wire::Segment;

fn prog(contour: Vec<Segment>, side: Side, repeat: Option<(u32, f64)>) -> IsoProgram {
    IsoProgram {
        number: 1000,
        header: vec!["m2 z20 (punch)".into(), "wire 0.18".into()],
        start_hole: (0.0, 30.0),
        contour,
        side,
        offset_mm: 0.1,
        repeat,
    }
}

/// Checks a replay against the outline: a lead-in from the start hole to
/// the outline's start, the outline within 0.1 µm, a lead-out back, the side
/// and offset in force on each, and every arc's end on its circle.
fn assert_round_trip(text: &str, outline: &[Segment], side: Side) {
    let r = replay(text).unwrap();
    let m = &r.moves;
    assert_eq!(m.len(), outline.len() + 2, "{text}");
    let (lead_in, lead_out) = (m[0], m[m.len() - 1]);
    assert_eq!(lead_in.segment.from(), (0.0, 30.0));
    assert!(dist(lead_in.segment.to(), outline[0].from()) < 1e-4);
    assert_eq!((lead_in.side, lead_in.offset_mm), (Some(side), Some(0.1)));
    assert!(dist(lead_out.segment.to(), (0.0, 30.0)) < 1e-12);
    assert_eq!((lead_out.side, lead_out.offset_mm), (None, None));
    for (got, want) in m[1..m.len() - 1].iter().zip(outline) {
        assert!(seg_gap(&got.segment, want) < 1e-4, "{got:?} vs {want:?}");
        assert_eq!((got.side, got.offset_mm), (Some(side), Some(0.1)));
    }
    // I and J checked apart from the writer: every replayed arc's start and
    // end are as far from its centre.
    for mv in m {
        if let Segment::Arc {
            from, to, centre, ..
        } = mv.segment
        {
            let (a, b) = (dist(from, centre), dist(to, centre));
            assert!((a - b).abs() < 1e-4, "line {}: {a} vs {b}", mv.line);
        }
    }
}

/// A square cut as a die (G42) and a circle of 8 arcs as a punch (G41).
#[test]
fn a_square_and_a_circle_round_trip() {
    let sq = square(25.0);
    let text = program(&prog(sq.clone(), Side::Right, None));
    assert!(text.starts_with("%\nO1000\n(m2 z20 [punch])\n(wire 0.18)\nG90 G17 G21\n"));
    assert!(
        text.contains("G92 X0.0000 Y30.0000\nG10 L12 P1 R0.1000\nG42 D1 G01 X-12.5000 Y12.5000\n")
    );
    assert!(
        text.ends_with("G40 G01 X0.0000 Y30.0000\nM02\n%\n"),
        "{text}"
    );
    assert_round_trip(&text, &sq, Side::Right);
    let c = circle(20.123_46, 8, 90.0);
    let text = program(&prog(c.clone(), Side::Left, None));
    assert!(text.contains("G41 D1 G01 X0.0000 Y20.1235\n"), "{text}");
    // The first arc, clockwise from the top to 45° (20.12346 · cos 45° =
    // 14.22944), its centre 20.1235 below.
    assert!(
        text.contains("\nG02 X14.2294 Y14.2294 I0.0000 J-20.1235\n"),
        "{text}"
    );
    assert_round_trip(&text, &c, Side::Left);
}

/// A quarter of the 4-fold outline run 4 times, turned by −90° each time
/// (a subprogram called under G68), replays as the whole outline.
#[test]
fn a_repeated_section_replays_as_the_whole() {
    let text = program(&prog(quarter(), Side::Left, Some((4, -90.0))));
    for k in 0..4 {
        let call = format!("G68 X0 Y0 R{:.4}\nM98 P1001\nG69\n", -90.0 * f64::from(k));
        assert!(
            text.contains(&call.replace("R-0.0000", "R0.0000")),
            "{text}"
        );
    }
    assert!(text.contains("M02\nO1001\nG02 "), "{text}");
    assert!(text.ends_with("M99\n%\n"), "{text}");
    assert_round_trip(&text, &four_fold(), Side::Left);
}

/// Words outside the subset, or out of place, are refused with their line.
#[test]
fn unknown_words_are_refused_by_line() {
    let ok = "%\nO0001\nG90 G17 G21\nG92 X0 Y0\nG01 X1 Y0 (fine)\nM02\n%\n";
    assert_eq!(replay(ok).unwrap().moves.len(), 1);
    let cases = [
        ("%\nO0001\nG90\nG01 X1 Y0 F2.5\nM02\n%\n", 4, "F"),
        ("O0001\nG91\nG01 X1 Y0\nM02\n", 2, "G91"),
        ("O0001\nG90\nG01 X1 Y0\nM08\nM02\n", 4, "M8"),
        ("O0001\nG01 X1 Y0 (open\nM02\n", 2, ")"),
        ("O0001\nG41 D2 G01 X1 Y0\nM02\n", 2, "D2"),
        ("O0001\nG02 X2 Y0 I0.5 J0\nM02\n", 2, "centre"),
        ("O0001\nM98 P7\nM02\n", 2, "O7"),
        ("O0001\nG01 X1 Y0\n", 2, "M02"),
    ];
    for (text, line, word) in cases {
        let e = replay(text).unwrap_err();
        assert_eq!(e.line, line, "{text}: {e:?}");
        assert!(e.message.contains(word), "{text}: {e:?}");
    }
}

proptest::proptest! {
    /// Any text made of G-code's characters is replayed or refused, never
    /// a panic or a hang, and a refusal names a line the text has.
    #[test]
    fn any_text_is_replayed_or_refused_by_line(text in "[GXYIJRLPDMOF0-9 .()%\n-]{0,300}") {
        if let Err(e) = replay(&text) {
            proptest::prop_assert!(e.line <= text.lines().count().max(1), "{e:?}");
        }
    }
}
