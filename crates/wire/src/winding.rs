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
    let inside = winding(hole, contour).abs() > 0.5;
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

/// Turns of the closed `path` about `p` (counter-clockwise positive), from
/// points 1° apart at most on every arc.
pub(crate) fn winding(p: (f64, f64), path: &[Segment]) -> f64 {
    let mut angle = 0.0;
    let mut last: Option<f64> = None;
    let mut add = |q: (f64, f64)| {
        let a = (q.1 - p.1).atan2(q.0 - p.0);
        if let Some(l) = last {
            angle += (a - l + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
        }
        last = Some(a);
    };
    for s in path {
        let arc = s.arc();
        let n = (s.sweep().to_degrees().ceil() as usize).max(1);
        for i in 0..=n {
            add(arc.point_at(arc.length * i as f64 / n as f64));
        }
    }
    angle / std::f64::consts::TAU
}
