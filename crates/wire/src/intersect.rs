//! Where a straight line meets a segment of a path: the points a lead-in
//! or lead-out shares with the contour it joins.

use std::f64::consts::TAU;

use crate::Segment;

/// The points where the line from `a` to `b` meets `s` (none, one or two;
/// a line along a line meets it in its two overlapping ends).
pub fn line_segment(a: (f64, f64), b: (f64, f64), s: &Segment) -> Vec<(f64, f64)> {
    let d = (b.0 - a.0, b.1 - a.1);
    let len2 = d.0 * d.0 + d.1 * d.1;
    if len2 == 0.0 {
        return Vec::new();
    }
    let along = |p: (f64, f64)| ((p.0 - a.0) * d.0 + (p.1 - a.1) * d.1) / len2;
    let on_line = |t: f64| (-1e-12..=1.0 + 1e-12).contains(&t);
    match *s {
        Segment::Line { from, to } => {
            let e = (to.0 - from.0, to.1 - from.1);
            let cross = d.0 * e.1 - d.1 * e.0;
            let w = (from.0 - a.0, from.1 - a.1);
            if cross.abs() < 1e-15 * len2.sqrt() * e.0.hypot(e.1).max(1e-300) {
                // Parallel: they meet only when on one line, at the ends
                // of their overlap.
                if (w.0 * d.1 - w.1 * d.0).abs() > 1e-9 * len2.sqrt() {
                    return Vec::new();
                }
                let mut out: Vec<(f64, f64)> = [from, to]
                    .into_iter()
                    .filter(|&p| on_line(along(p)))
                    .collect();
                out.extend([a, b].into_iter().filter(|&p| {
                    let u = ((p.0 - from.0) * e.0 + (p.1 - from.1) * e.1) / (e.0 * e.0 + e.1 * e.1);
                    (0.0..=1.0).contains(&u)
                }));
                return out;
            }
            let t = (w.0 * e.1 - w.1 * e.0) / cross;
            let u = (w.0 * d.1 - w.1 * d.0) / cross;
            if on_line(t) && (-1e-12..=1.0 + 1e-12).contains(&u) {
                vec![(a.0 + t * d.0, a.1 + t * d.1)]
            } else {
                Vec::new()
            }
        }
        Segment::Arc {
            from, centre, ccw, ..
        } => {
            let r = (from.0 - centre.0).hypot(from.1 - centre.1);
            // |a + t d − c|² = r²: t² |d|² + 2 t (a − c)·d + |a − c|² − r² = 0.
            let f = (a.0 - centre.0, a.1 - centre.1);
            let half_b = f.0 * d.0 + f.1 * d.1;
            let c = f.0 * f.0 + f.1 * f.1 - r * r;
            let disc = half_b * half_b - len2 * c;
            if disc < 0.0 {
                return Vec::new();
            }
            let a0 = (from.1 - centre.1).atan2(from.0 - centre.0);
            let sweep = s.sweep();
            let root = disc.sqrt();
            let mut ts = vec![(-half_b - root) / len2];
            if root > 0.0 {
                ts.push((-half_b + root) / len2);
            }
            ts.into_iter()
                .filter(|&t| on_line(t))
                .map(|t| (a.0 + t * d.0, a.1 + t * d.1))
                .filter(|p| {
                    let ap = (p.1 - centre.1).atan2(p.0 - centre.0);
                    let turned = if ccw { ap - a0 } else { a0 - ap }.rem_euclid(TAU);
                    turned <= sweep + 1e-12 || turned >= TAU - 1e-12
                })
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_meets_a_line_once_and_an_arc_where_the_sweep_is() {
        let l = Segment::Line {
            from: (0.0, -1.0),
            to: (0.0, 1.0),
        };
        let p = line_segment((-1.0, 0.0), (1.0, 0.0), &l);
        assert_eq!(p, vec![(0.0, 0.0)]);
        // The upper half of the unit circle, clockwise from (−1, 0) to (1, 0).
        let arc = Segment::Arc {
            from: (-1.0, 0.0),
            to: (1.0, 0.0),
            centre: (0.0, 0.0),
            ccw: false,
        };
        let up = line_segment((0.0, -2.0), (0.0, 2.0), &arc);
        assert_eq!(up.len(), 1);
        assert!((up[0].1 - 1.0).abs() < 1e-12);
        // The same ends counter-clockwise: the lower half.
        let lower = Segment::Arc {
            from: (-1.0, 0.0),
            to: (1.0, 0.0),
            centre: (0.0, 0.0),
            ccw: true,
        };
        let low = line_segment((0.0, -2.0), (0.0, 2.0), &lower);
        assert_eq!(low.len(), 1);
        assert!((low[0].1 + 1.0).abs() < 1e-12);
        // A line short of the circle meets nothing.
        assert!(line_segment((0.0, -0.5), (0.0, 0.5), &arc).is_empty());
    }
}
