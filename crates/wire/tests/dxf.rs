//! A contour as DXF: only LINE and ARC on the outline's layer, in mm, and
//! read back into the same closed contour.

mod common;

use common::{circle, dist, four_fold, seg_gap, square};
use gearcam_wire::dxf::{drawing, read_back, LAYER};
use gearcam_wire::Segment;

/// What the dxf crate itself reads from the bytes: the entity kinds, their
/// layers, the units.
fn entities(bytes: &[u8]) -> Vec<(String, String)> {
    let d = dxf::Drawing::load(&mut &bytes[..]).unwrap();
    assert_eq!(
        d.header.default_drawing_units,
        dxf::enums::Units::Millimeters
    );
    d.entities()
        .map(|e| {
            let kind = match e.specific {
                dxf::entities::EntityType::Line(_) => "LINE",
                dxf::entities::EntityType::Arc(_) => "ARC",
                _ => "other",
            };
            (kind.to_string(), e.common.layer.clone())
        })
        .collect()
}

/// Written and read back: LINE and ARC only, on `OUTLINE`, $INSUNITS 4; the
/// chain closed (each end on the next start within 1e-6 mm) and equal to
/// the original segment by segment, clockwise arcs clockwise again.
#[test]
fn contours_round_trip() {
    for contour in [four_fold(), square(30.0), circle(12.5, 7, 10.0)] {
        let bytes = drawing(&contour).unwrap();
        let text = String::from_utf8_lossy(&bytes);
        // The ENTITIES section's entity names (code 0): LINE and ARC only.
        let from = text.find("ENTITIES").expect("an ENTITIES section");
        let section = &text[from..from + text[from..].find("ENDSEC").unwrap()];
        let lines: Vec<&str> = section.lines().map(str::trim).collect();
        // After the section's name the lines go in pairs: code, value.
        let names: Vec<&str> = lines[1..]
            .chunks_exact(2)
            .filter(|w| w[0] == "0")
            .map(|w| w[1])
            .collect();
        assert_eq!(names.len(), contour.len());
        assert!(
            names.iter().all(|n| *n == "LINE" || *n == "ARC"),
            "{names:?}"
        );
        let units = text.find("$INSUNITS").expect("$INSUNITS in the header");
        let after: Vec<&str> = text[units..].lines().take(3).map(str::trim).collect();
        assert_eq!(after, ["$INSUNITS", "70", "4"]);
        let kinds = entities(&bytes);
        assert_eq!(kinds.len(), contour.len());
        for ((kind, layer), s) in kinds.iter().zip(&contour) {
            let want = if matches!(s, Segment::Line { .. }) {
                "LINE"
            } else {
                "ARC"
            };
            assert_eq!((kind.as_str(), layer.as_str()), (want, LAYER));
        }
        let back = read_back(&bytes).unwrap();
        assert_eq!(back.len(), contour.len());
        for (k, s) in back.iter().enumerate() {
            let next = back[(k + 1) % back.len()];
            assert!(dist(s.to(), next.from()) < 1e-6, "gap after {k}");
            assert!(seg_gap(s, &contour[k]) < 1e-6, "{s:?} vs {:?}", contour[k]);
        }
    }
}

/// A clockwise arc is written counter-clockwise with its ends swapped: the
/// quarter circle from (0, 5) clockwise to (5, 0) is the ARC from 0° to 90°.
#[test]
fn a_clockwise_arc_is_written_from_its_end() {
    let arc = Segment::Arc {
        from: (0.0, 5.0),
        to: (5.0, 0.0),
        centre: (0.0, 0.0),
        ccw: false,
    };
    let d = dxf::Drawing::load(&mut &drawing(&[arc]).unwrap()[..]).unwrap();
    let e: Vec<_> = d.entities().collect();
    let dxf::entities::EntityType::Arc(a) = &e[0].specific else {
        panic!("an ARC");
    };
    assert!(
        a.start_angle.abs() < 1e-9 && (a.end_angle - 90.0).abs() < 1e-9,
        "{a:?}"
    );
    assert!((a.radius - 5.0).abs() < 1e-12);
    // A whole circle is two half circles, read back clockwise from its start.
    let whole = Segment::Arc {
        from: (3.0, 0.0),
        to: (3.0, 0.0),
        centre: (0.0, 0.0),
        ccw: false,
    };
    let back = read_back(&drawing(&[whole]).unwrap()).unwrap();
    assert_eq!(back.len(), 2);
    assert!(
        seg_gap(
            &back[0],
            &Segment::Arc {
                from: (3.0, 0.0),
                to: (-3.0, 0.0),
                centre: (0.0, 0.0),
                ccw: false
            }
        ) < 1e-9,
        "{back:?}"
    );
    assert!(
        seg_gap(
            &back[1],
            &Segment::Arc {
                from: (-3.0, 0.0),
                to: (3.0, 0.0),
                centre: (0.0, 0.0),
                ccw: false
            }
        ) < 1e-9,
        "{back:?}"
    );
}

/// Shuffled entities, some turned round, chain back to the same contour;
/// an open outline and a foreign entity are refused.
#[test]
fn entities_in_any_order_chain_and_gaps_are_refused() {
    let contour = four_fold();
    // Lines turned round, the order shuffled (written through the library
    // with a contour that is not a chain is still a drawing of its pieces).
    let mut pieces: Vec<Segment> = contour.clone();
    pieces.reverse();
    pieces.swap(0, 11);
    for s in pieces.iter_mut() {
        if let Segment::Line { from, to } = *s {
            *s = Segment::Line { from: to, to: from };
        }
    }
    let back = read_back(&drawing(&pieces).unwrap()).unwrap();
    // It starts with the first entity, contour[0]; the rest follow in order.
    for (k, s) in back.iter().enumerate() {
        assert!(seg_gap(s, &contour[k]) < 1e-6, "{k}: {s:?}");
    }
    let open = read_back(&drawing(&contour[..11]).unwrap()).unwrap_err();
    assert!(
        open.message.contains("close") || open.message.contains("open"),
        "{open:?}"
    );
    let mut d = dxf::Drawing::new();
    d.add_entity(dxf::entities::Entity::new(
        dxf::entities::EntityType::Circle(dxf::entities::Circle::new(dxf::Point::origin(), 3.0)),
    ));
    let mut bytes = Vec::new();
    d.save(&mut bytes).unwrap();
    let e = read_back(&bytes).unwrap_err();
    assert!(e.message.contains("Circle"), "{e:?}");
}
