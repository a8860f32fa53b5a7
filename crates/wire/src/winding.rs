//! Points against a closed contour: the winding number that tells inside
//! from outside, and where a lead from the start hole enters the kept part.
//! The die job's certificate uses them to hold the wire and its leads to
//! the scrap side of the outline.

use gearcam_geom::plane::{length, sub};

use crate::Segment;

/// Where a lead — a line from the start hole to the contour's point `join`
/// — enters the kept part: the start hole itself when it lies in the part
/// (inside the contour for a punch, outside for a die's opening), else the
/// first point where the line meets the contour away from `join` (2 µm).
pub(crate) fn lead_crossing(
    lead: &Segment,
    join: (f64, f64),
    contour: &[Segment],
    scrap_inside: bool,
) -> Option<(f64, f64)> {
    let (a, b) = (lead.from(), lead.to());
    let hole = if length(sub(a, join)) < length(sub(b, join)) {
        b
    } else {
        a
    };
    let inside = winds(hole, contour) != 0;
    if inside != scrap_inside {
        return Some(hole);
    }
    let mut hits: Vec<(f64, f64)> = contour
        .iter()
        .flat_map(|s| crate::intersect::line_segment(a, b, s))
        .filter(|&p| length(sub(p, join)) > 0.002)
        .collect();
    hits.sort_by(|p, q| length(sub(*p, hole)).total_cmp(&length(sub(*q, hole))));
    hits.first().copied()
}

/// Turns of the closed `path` about `p` (counter-clockwise positive): the
/// angle each segment turns as seen from `p`, summed, over 2π.
///
/// A line turns by the principal angle from its start to its end (under a
/// half turn: a straight segment not through `p`). So does an arc seen from
/// outside its circle: the circle lies within a half plane seen from there.
/// Seen from inside its circle, an arc turns the way it runs, steadily, by
/// up to a whole turn: its principal angle moved into (0, 2π) for a
/// counter-clockwise arc, (−2π, 0) for a clockwise one; an arc that ends
/// where it starts ([`Segment::sweep`]: a whole turn) turns by ±2π from
/// inside and 0 from outside. Exact, with one arctangent a segment.
pub(crate) fn winding(p: (f64, f64), path: &[Segment]) -> f64 {
    use std::f64::consts::TAU;
    let mut angle = 0.0;
    for s in path {
        let (a, b) = (sub(s.from(), p), sub(s.to(), p));
        let mut turn = (a.0 * b.1 - a.1 * b.0).atan2(a.0 * b.0 + a.1 * b.1);
        if let Segment::Arc { centre, ccw, .. } = *s {
            // Nearer the centre than the arc's start, by the squares.
            let d2 = |v: (f64, f64)| v.0 * v.0 + v.1 * v.1;
            let inside = d2(sub(p, centre)) < d2(sub(s.from(), centre));
            // A whole turn ends where it starts: its principal angle is
            // next to nothing (the sweep only asked then).
            let whole = || turn.abs() < 1e-9 && s.sweep() == TAU;
            if inside && whole() {
                turn = if ccw { TAU } else { -TAU };
            } else if inside && ccw && turn < 0.0 {
                turn += TAU;
            } else if inside && !ccw && turn > 0.0 {
                turn -= TAU;
            } else if whole() {
                turn = 0.0;
            }
        }
        angle += turn;
    }
    angle / TAU
}

/// [`winding`]'s whole turns without an arctangent: the same integer
/// (what [`winding`] is within rounding of) for a point not on the path.
///
/// [`winding`] sums each segment's turn: a line's principal angle from its
/// start to its end as seen from `p`, and an arc's the principal angle of
/// its chord, plus a whole turn (its sense's) when `p` lies inside its
/// circle and that angle has the other sign (the arc goes round `p` the
/// long way), or ±2π for a whole circle from inside. The principal angles
/// of the chords sum to 2π times the winding number of the closed polygon
/// of the segments' ends (each segment's start taken as the end of the one
/// before: the same angles to within the joins' rounding, far below a
/// turn), which the crossing rule counts (Sunday): an edge running up
/// across the horizontal through `p` with `p` on its left counts +1, one
/// running down with `p` on its right −1. The sign of the angle (a − p) × (b − p) is [`winding`]'s own
/// arctangent's (its first argument): on which side `p` lies. So the sum
/// is the chord polygon's count plus the arcs' whole turns, an integer.
///
/// Where that cross product is next to nothing (`p` on or within 10⁻⁹ of
/// a segment's chord, relative to the chord's size, or an arc that ends
/// where it starts) its sign is rounding: [`winding`] itself answers.
pub(crate) fn winds(p: (f64, f64), path: &[Segment]) -> i64 {
    let Some(last) = path.last() else {
        return 0;
    };
    let norm = |v: (f64, f64)| v.0.abs() + v.1.abs();
    let answer = || winding(p, path).round() as i64;
    let mut turns = 0i64;
    // The polygon's last corner: the path's end.
    let mut prev = sub(last.to(), p);
    for s in path {
        let (a, b) = (sub(s.from(), p), sub(s.to(), p));
        // A segment starts where the one before ended, to a rounding far
        // below its distance from p, or the polygon's angles are not the
        // chords'.
        if norm(sub(a, prev)) > 1e-9 * norm(a) {
            return answer();
        }
        let cross = a.0 * b.1 - a.1 * b.0;
        let edge = prev.0 * b.1 - prev.1 * b.0;
        let dot = a.0 * b.0 + a.1 * b.1;
        let size = norm(a) * norm(b);
        let arc = matches!(s, Segment::Arc { .. });
        if (cross.abs() <= 1e-9 * size || edge.abs() <= 1e-9 * size) && (arc || dot <= 0.0) {
            return answer();
        }
        // The crossing rule on the polygon's edge from the path's last
        // point (the polygon closes exactly, whatever the rounding of the
        // segments' joins).
        if prev.1 <= 0.0 {
            if b.1 > 0.0 && edge > 0.0 {
                turns += 1;
            }
        } else if b.1 <= 0.0 && edge < 0.0 {
            turns -= 1;
        }
        prev = b;
        if let Segment::Arc { centre, ccw, .. } = *s {
            let d2 = |v: (f64, f64)| v.0 * v.0 + v.1 * v.1;
            let inside = d2(sub(p, centre)) < d2(sub(s.from(), centre));
            if inside && ccw && cross < 0.0 {
                turns += 1;
            } else if inside && !ccw && cross > 0.0 {
                turns -= 1;
            }
        }
    }
    turns
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{PI, TAU};

    /// The winding number as it was first taken: the polar angle of points
    /// 1° apart at most along every arc, its changes summed. The reference
    /// for points not closer to the path than a sample step.
    fn sampled(p: (f64, f64), path: &[Segment]) -> f64 {
        let mut angle = 0.0;
        let mut last: Option<f64> = None;
        for s in path {
            let arc = s.arc();
            let n = (s.sweep().to_degrees().ceil() as usize).max(1) * 8;
            for i in 0..=n {
                let q = arc.point_at(arc.length * i as f64 / n as f64);
                let a = (q.1 - p.1).atan2(q.0 - p.0);
                if let Some(l) = last {
                    angle += (a - l + PI).rem_euclid(TAU) - PI;
                }
                last = Some(a);
            }
        }
        angle / TAU
    }

    /// A closed path of lines and arcs both ways, big and small (a slot with
    /// a bite out of one side, run clockwise, and its reverse), against
    /// the sampled winding at points on a grid over and around it, and
    /// a whole circle from inside and outside.
    #[test]
    fn the_exact_winding_agrees_with_the_sampled_one() {
        let arc = |from, to, centre, ccw| Segment::Arc {
            from,
            to,
            centre,
            ccw,
        };
        let line = |from, to| Segment::Line { from, to };
        // Clockwise: over the top by a half circle, down the right, a
        // bite (counter-clockwise arc into the shape) along the bottom,
        // up the left.
        let path = vec![
            arc((-3.0, 2.0), (3.0, 2.0), (0.0, 2.0), false),
            line((3.0, 2.0), (3.0, -2.0)),
            line((3.0, -2.0), (1.0, -2.0)),
            arc((1.0, -2.0), (-1.0, -2.0), (0.0, -2.0), true),
            line((-1.0, -2.0), (-3.0, -2.0)),
            line((-3.0, -2.0), (-3.0, 2.0)),
        ];
        let back: Vec<Segment> = path.iter().rev().map(Segment::reversed).collect();
        let mut inside = 0;
        for i in -45..=45 {
            for j in -45..=60 {
                let p = (0.1 * f64::from(i) + 0.013, 0.1 * f64::from(j) + 0.007);
                for (way, sense) in [(&path, -1.0), (&back, 1.0)] {
                    let w = winding(p, way);
                    assert!((w - sampled(p, way)).abs() < 1e-9, "{p:?}: {w}");
                    assert!(w.abs() < 1e-12 || (w - sense).abs() < 1e-12, "{p:?}: {w}");
                    inside += usize::from(w.abs() > 0.5);
                }
            }
        }
        // Inside: the 6 × 4 box and the half disc, less the bite.
        assert!(inside > 2 * 2000, "{inside}");
        let circle = [arc((2.0, 0.0), (2.0, 0.0), (0.0, 0.0), true)];
        assert_eq!(winding((0.5, 0.5), &circle), 1.0);
        assert_eq!(winding((3.0, 0.5), &circle), 0.0);
        assert_eq!(winds((0.5, 0.5), &circle), 1);
        assert_eq!(winds((3.0, 0.5), &circle), 0);
    }

    /// The whole turns by crossings against [`winding`], rounded: the
    /// slot above both ways and a 40-tooth die's outline (arcs both ways,
    /// inside and outside their circles), at points on a grid over them,
    /// on the path's own ends and on its arcs' middles (where [`winding`]
    /// answers), and a shape that winds twice.
    #[test]
    fn the_crossings_give_the_windings_whole_turns() {
        use crate::gear::RackGear;
        use crate::outline::{outline, Tolerances};
        let gear = RackGear {
            module_mm: 2.0,
            teeth: 40,
            pressure_angle_deg: 20.0,
            profile_shift: 0.0,
            addendum_coef: 1.0,
            clearance_coef: 0.25,
            tip_radius_coef: 0.38,
        };
        let tol = Tolerances {
            flank_mm: 0.001,
            fillet_mm: 0.005,
            min_radius_mm: 0.005,
        };
        let die = outline(&gear, &tol).unwrap().segments();
        let back: Vec<Segment> = die.iter().rev().map(Segment::reversed).collect();
        // Twice round a circle, in two halves each time.
        let arc = |from, to, ccw| Segment::Arc {
            from,
            to,
            centre: (0.0, 0.0),
            ccw,
        };
        let twice: Vec<Segment> = (0..2)
            .flat_map(|_| {
                [
                    arc((3.0, 0.0), (-3.0, 0.0), true),
                    arc((-3.0, 0.0), (3.0, 0.0), true),
                ]
            })
            .collect();
        let mut counts = [0usize; 3];
        for path in [&die, &back, &twice] {
            let mut points: Vec<(f64, f64)> = Vec::new();
            for i in -45..=45 {
                for j in -45..=45 {
                    points.push((f64::from(i) + 0.0031, f64::from(j) - 0.0017));
                }
            }
            // Near the teeth: a fine ring of points across the outline.
            for i in 0..6_000 {
                let a = std::f64::consts::TAU * f64::from(i) / 6_000.0;
                let r = 37.0 + 6.0 * f64::from(i % 97) / 96.0;
                points.push((r * a.cos(), r * a.sin()));
            }
            for s in path.iter() {
                points.push(s.from());
                let m = s.arc();
                points.push(m.point_at(m.length / 2.0));
            }
            for &p in &points {
                let w = winding(p, path);
                let n = winds(p, path);
                assert_eq!(n, w.round() as i64, "{p:?}: {w}");
                counts[n.unsigned_abs().min(2) as usize] += 1;
            }
        }
        // Outside, inside once and inside twice all met.
        assert!(counts.iter().all(|&c| c > 20), "{counts:?}");
    }
}
