use super::*;

fn zone() -> Zone {
    Zone {
        unit: 0,
        x_hi: 80.5,
        z_lo: 25.798,
        z_hi: 104.202,
        y_half: None,
    }
}

#[test]
fn segments_along_the_zone_edge_are_outside() {
    let z = zone();
    // B → C at the top of the band, D → E at the bottom.
    assert!(!z.crossed_by([173.75, 104.202, 0.0], [73.75, 104.202, 0.0]));
    assert!(!z.crossed_by([73.75, 25.798, 0.0], [78.75, 25.798, 0.0]));
    // C → D through the band, and a rapid into it.
    assert!(z.crossed_by([73.75, 104.202, 0.0], [73.75, 25.798, 0.0]));
    assert!(z.crossed_by([174.05, 82.0, 0.0], [75.0, 40.0, 0.0]));
    // E → A diagonally: X is below 80.5 while Z climbs into the band.
    assert!(z.crossed_by([78.75, 25.798, 0.0], [300.0, 350.0, 0.0]));
    // A point.
    assert!(z.crossed_by([70.0, 50.0, 0.0], [70.0, 50.0, 0.0]));
    assert!(!z.crossed_by([90.0, 50.0, 0.0], [90.0, 50.0, 0.0]));
}

#[test]
fn tangential_zone_is_clear_while_the_hob_is_shifted_out() {
    // The worm wheel example: R + r = 63.05 + 40, throat 82.5 ± 40.
    let z = Zone {
        unit: 0,
        x_hi: 103.05,
        z_lo: 42.5,
        z_hi: 122.5,
        y_half: Some(78.384),
    };
    assert!(!z.crossed_by([205.0, 82.5, -80.384], [96.301, 82.5, -80.384]));
    assert!(z.crossed_by([96.301, 82.5, -80.384], [96.301, 82.5, 78.384]));
}

#[test]
fn circle_through_three_points_and_radius_arcs() {
    // A quarter circle of radius 10 around (Z 0, X 0): from (10, 0) via 45° to (0, 10).
    let s = 10.0 / 2f64.sqrt();
    let (c, t0, sweep) = circle_via((10.0, 0.0), (s, s), (0.0, 10.0)).unwrap();
    assert!(c.0.abs() < 1e-9 && c.1.abs() < 1e-9);
    assert!(t0.abs() < 1e-12);
    assert!((sweep - PI / 2.0).abs() < 1e-12);
    // The same arc the other way round through the far side.
    let (_, _, sweep) = circle_via((10.0, 0.0), (-10.0, 0.0), (0.0, 10.0)).unwrap();
    assert!((sweep + 1.5 * PI).abs() < 1e-12);
    assert!(circle_via((0.0, 0.0), (1.0, 1.0), (2.0, 2.0)).is_none());
    // G03 (counter-clockwise) R10 from (10, 0) to (0, 10): centre at the origin.
    let (c, _, sweep) = arc_radius((10.0, 0.0), (0.0, 10.0), 10.0, true).unwrap();
    assert!(c.0.abs() < 1e-9 && c.1.abs() < 1e-9);
    assert!((sweep - PI / 2.0).abs() < 1e-12);
    // G02 (clockwise) R10 between the same points: centre at (10, 10).
    let (c, _, sweep) = arc_radius((10.0, 0.0), (0.0, 10.0), 10.0, false).unwrap();
    assert!((c.0 - 10.0).abs() < 1e-9 && (c.1 - 10.0).abs() < 1e-9);
    assert!((sweep + PI / 2.0).abs() < 1e-12);
    assert!(arc_radius((0.0, 0.0), (30.0, 0.0), 10.0, true).is_none());
}
