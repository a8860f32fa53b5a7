//! Contours shared by the format tests, built here independently of the
//! writers under test, and the wire process the die tests and the bench
//! cut with.
#![allow(dead_code)]

use gearcam_proto::{Source, Sourced, WireProcess, WireProgram};
use gearcam_wire::Segment;

/// W01's molybdenum wire (0.18 mm, spark gap 0.01 mm: offset 0.1 mm) with
/// the seeded tool-steel technology, writing `program`.
pub(crate) fn molybdenum(program: WireProgram, whole: bool) -> WireProcess {
    let s = |value: f64| Sourced {
        value,
        source: Source::Library,
    };
    WireProcess {
        wire: "MO-018".into(),
        wire_diameter_mm: s(0.18),
        spark_gap_mm: s(0.01),
        pulse_on_us: s(24.0),
        pulse_off_us: s(120.0),
        current_a: s(3.0),
        cutting_rate_mm2_min: s(60.0),
        program,
        whole,
    }
}

/// A point at `r` mm and `deg` degrees about the origin.
pub(crate) fn polar(r: f64, deg: f64) -> (f64, f64) {
    let a = deg.to_radians();
    (r * a.cos(), r * a.sin())
}

/// A point turned about the origin by `deg` degrees.
pub(crate) fn turn(p: (f64, f64), deg: f64) -> (f64, f64) {
    let (s, c) = deg.to_radians().sin_cos();
    (c * p.0 - s * p.1, s * p.0 + c * p.1)
}

/// A segment turned about the origin by `deg` degrees.
pub(crate) fn turn_segment(s: &Segment, deg: f64) -> Segment {
    match *s {
        Segment::Line { from, to } => Segment::Line {
            from: turn(from, deg),
            to: turn(to, deg),
        },
        Segment::Arc {
            from,
            to,
            centre,
            ccw,
        } => Segment::Arc {
            from: turn(from, deg),
            to: turn(to, deg),
            centre: turn(centre, deg),
            ccw,
        },
    }
}

/// The distance of two points.
pub(crate) fn dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).hypot(a.1 - b.1)
}

/// The largest distance between corresponding points (ends and centres)
/// of two segments; infinite when their kinds or senses differ.
pub(crate) fn seg_gap(a: &Segment, b: &Segment) -> f64 {
    match (*a, *b) {
        (Segment::Line { from: f1, to: t1 }, Segment::Line { from: f2, to: t2 }) => {
            dist(f1, f2).max(dist(t1, t2))
        }
        (
            Segment::Arc {
                from: f1,
                to: t1,
                centre: c1,
                ccw: d1,
            },
            Segment::Arc {
                from: f2,
                to: t2,
                centre: c2,
                ccw: d2,
            },
        ) if d1 == d2 => dist(f1, f2).max(dist(t1, t2)).max(dist(c1, c2)),
        _ => f64::INFINITY,
    }
}

/// One quarter of a 4-fold gear-like outline, clockwise about the origin
/// (material on the right) from (0, 20) to (20, 0): a convex tip arc
/// (clockwise, centre the origin) from 90° to 60°, a concave notch
/// (counter-clockwise, a half circle into the material on the chord from
/// 60° to 30°), a straight chord from 30° to 0°.
pub(crate) fn quarter() -> Vec<Segment> {
    let r = 20.0;
    let (a, b) = (polar(r, 60.0), polar(r, 30.0));
    let m = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
    vec![
        Segment::Arc {
            from: polar(r, 90.0),
            to: a,
            centre: (0.0, 0.0),
            ccw: false,
        },
        Segment::Arc {
            from: a,
            to: b,
            centre: m,
            ccw: true,
        },
        Segment::Line {
            from: b,
            to: polar(r, 0.0),
        },
    ]
}

/// The whole outline: [`quarter`] turned by 0°, −90°, −180°, −270°.
pub(crate) fn four_fold() -> Vec<Segment> {
    let q = quarter();
    (0..4)
        .flat_map(|k| q.iter().map(move |s| turn_segment(s, -90.0 * k as f64)))
        .collect()
}

/// A square of side `a` about the origin, clockwise from its top-left corner.
pub(crate) fn square(a: f64) -> Vec<Segment> {
    let h = a / 2.0;
    let c = [(-h, h), (h, h), (h, -h), (-h, -h)];
    (0..4)
        .map(|i| Segment::Line {
            from: c[i],
            to: c[(i + 1) % 4],
        })
        .collect()
}

/// A circle of radius `r` about the origin cut into `n` clockwise arcs,
/// starting at `a0` degrees.
pub(crate) fn circle(r: f64, n: usize, a0: f64) -> Vec<Segment> {
    (0..n)
        .map(|i| {
            let d = |k: usize| a0 - 360.0 * k as f64 / n as f64;
            Segment::Arc {
                from: polar(r, d(i)),
                to: polar(r, d(i + 1)),
                centre: (0.0, 0.0),
                ccw: false,
            }
        })
        .collect()
}
