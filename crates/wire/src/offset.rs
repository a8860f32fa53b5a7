//! The wire's path: the closed outline set off by the wire's radius plus
//! the spark gap, d, to one side (docs/wire.md).
//!
//! An arc set off keeps its centre and changes its radius by d (exact: the
//! points at distance d from a circle are two circles); a line moves by d
//! along its normal. Where two segments join without a corner their offsets
//! join too. At a corner the offsets either leave a gap — the wire goes
//! round the corner on an arc of radius d about it — or cross, and both are
//! cut back to the crossing. An arc whose radius would shrink to d or below
//! (a concave place of the part tighter than the wire) is an error naming
//! the segment and the radius.

use crate::Segment;
use gearcam_geom::plane::{length, sub};

/// The side of travel the wire runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// Left of the direction of travel (a punch, outline clockwise).
    Left,
    /// Right of it (a die).
    Right,
}

/// A place tighter than the wire.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffsetError {
    /// The segment's index in the outline.
    pub index: usize,
    /// Its radius, mm.
    pub radius_mm: f64,
    /// The offset, mm.
    pub offset_mm: f64,
}

impl std::fmt::Display for OffsetError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "segment {} has the radius {:.4} mm on the wire's side, not more than the offset {:.4} mm",
            self.index, self.radius_mm, self.offset_mm
        )
    }
}

impl std::error::Error for OffsetError {}

/// The unit tangent of a segment at its start (`at_end` false) or end.
fn tangent(s: &Segment, at_end: bool) -> (f64, f64) {
    match *s {
        Segment::Line { from, to } => {
            let v = sub(to, from);
            (v.0 / length(v), v.1 / length(v))
        }
        Segment::Arc {
            from,
            to,
            centre,
            ccw,
        } => {
            let p = if at_end { to } else { from };
            let r = sub(p, centre);
            let l = length(r);
            if ccw {
                (-r.1 / l, r.0 / l)
            } else {
                (r.1 / l, -r.0 / l)
            }
        }
    }
}

/// A segment set off by `s` (positive: left of travel).
fn shifted(seg: &Segment, index: usize, s: f64) -> Result<Segment, OffsetError> {
    match *seg {
        Segment::Line { from, to } => {
            let t = tangent(seg, false);
            let n = (-t.1 * s, t.0 * s);
            Ok(Segment::Line {
                from: (from.0 + n.0, from.1 + n.1),
                to: (to.0 + n.0, to.1 + n.1),
            })
        }
        Segment::Arc {
            from,
            to,
            centre,
            ccw,
        } => {
            let r = length(sub(from, centre));
            // Left of a counter-clockwise arc is towards its centre.
            let new_r = if ccw { r - s } else { r + s };
            if new_r <= 0.0 {
                return Err(OffsetError {
                    index,
                    radius_mm: r,
                    offset_mm: s.abs(),
                });
            }
            let at = |p: (f64, f64)| {
                let v = sub(p, centre);
                let k = new_r / length(v);
                (centre.0 + v.0 * k, centre.1 + v.1 * k)
            };
            Ok(Segment::Arc {
                from: at(from),
                to: at(to),
                centre,
                ccw,
            })
        }
    }
}

/// The crossings of the lines or circles carrying two segments.
fn crossings(a: &Segment, b: &Segment) -> Vec<(f64, f64)> {
    /// A segment's circle (centre, radius) or line (point, direction).
    enum Carrier {
        Circle((f64, f64), f64),
        Line((f64, f64), (f64, f64)),
    }
    fn carrier(s: &Segment) -> Carrier {
        match *s {
            Segment::Line { from, to } => Carrier::Line(from, sub(to, from)),
            Segment::Arc { from, centre, .. } => Carrier::Circle(centre, length(sub(from, centre))),
        }
    }
    let line_circle = |p: (f64, f64), v: (f64, f64), c: (f64, f64), r: f64| {
        // |p + t·v − c|² = r².
        let w = sub(p, c);
        let (qa, qb, qc) = (
            v.0 * v.0 + v.1 * v.1,
            2.0 * (w.0 * v.0 + w.1 * v.1),
            w.0 * w.0 + w.1 * w.1 - r * r,
        );
        let disc = qb * qb - 4.0 * qa * qc;
        if disc < 0.0 {
            return vec![];
        }
        [-1.0, 1.0]
            .iter()
            .map(|sg| {
                let t = (-qb + sg * disc.sqrt()) / (2.0 * qa);
                (p.0 + t * v.0, p.1 + t * v.1)
            })
            .collect()
    };
    match (carrier(a), carrier(b)) {
        (Carrier::Circle(c1, r1), Carrier::Circle(c2, r2)) => {
            let d = sub(c2, c1);
            let dist = length(d);
            if dist < 1e-15 {
                return vec![];
            }
            let along = (dist * dist + r1 * r1 - r2 * r2) / (2.0 * dist);
            let h2 = r1 * r1 - along * along;
            if h2 < 0.0 {
                return vec![];
            }
            let (u, h) = ((d.0 / dist, d.1 / dist), h2.sqrt());
            let m = (c1.0 + along * u.0, c1.1 + along * u.1);
            vec![
                (m.0 - h * u.1, m.1 + h * u.0),
                (m.0 + h * u.1, m.1 - h * u.0),
            ]
        }
        (Carrier::Line(p, v), Carrier::Circle(c, r))
        | (Carrier::Circle(c, r), Carrier::Line(p, v)) => line_circle(p, v, c, r),
        (Carrier::Line(p, v), Carrier::Line(q, w)) => {
            let den = v.0 * w.1 - v.1 * w.0;
            if den.abs() < 1e-15 {
                return vec![];
            }
            let t = ((q.0 - p.0) * w.1 - (q.1 - p.1) * w.0) / den;
            vec![(p.0 + t * v.0, p.1 + t * v.1)]
        }
    }
}

fn with_end(s: &Segment, p: (f64, f64)) -> Segment {
    match *s {
        Segment::Line { from, .. } => Segment::Line { from, to: p },
        Segment::Arc {
            from, centre, ccw, ..
        } => Segment::Arc {
            from,
            to: p,
            centre,
            ccw,
        },
    }
}

fn with_start(s: &Segment, p: (f64, f64)) -> Segment {
    match *s {
        Segment::Line { to, .. } => Segment::Line { from: p, to },
        Segment::Arc {
            to, centre, ccw, ..
        } => Segment::Arc {
            from: p,
            to,
            centre,
            ccw,
        },
    }
}

/// The largest gap between two offsets that is a kink of rounded arcs (a
/// program's arcs meet at a µrad or so), not a corner, mm: 0.1 µm, while a
/// corner of a gear's outline opens a gap of tenths of the offset.
pub const KINK_MM: f64 = 1e-4;

/// The largest turn at a junction that is a kink of rounded arcs, not a
/// corner, radians (0.1°): a gear outline's corners turn by degrees.
pub const KINK_RAD: f64 = 1.75e-3;

/// The closed `outline` set off by `d` to `side`.
pub fn offset(outline: &[Segment], side: Side, d: f64) -> Result<Vec<Segment>, OffsetError> {
    let s = match side {
        Side::Left => d,
        Side::Right => -d,
    };
    let moved = outline
        .iter()
        .enumerate()
        .map(|(i, seg)| shifted(seg, i, s))
        .collect::<Result<Vec<_>, _>>()?;
    let n = moved.len();
    let mut out: Vec<Segment> = Vec::with_capacity(n + n / 4);
    let mut pending = moved.clone();
    for i in 0..n {
        let j = (i + 1) % n;
        let (a, b) = (pending[i], moved[j]);
        let gap = length(sub(a.to(), b.from()));
        if gap < 1e-9 {
            out.push(a);
            continue;
        }
        let (ta, tb) = (tangent(&outline[i], true), tangent(&outline[j], false));
        // Positive: the outline turns left at the junction.
        let cross = ta.0 * tb.1 - ta.1 * tb.0;
        let turn = cross.atan2(ta.0 * tb.0 + ta.1 * tb.1);
        if gap < KINK_MM || turn.abs() < KINK_RAD {
            // Not a corner of the part but the kink of a program's rounded
            // arcs: the two meet half-way across the gap.
            let mid = (0.5 * (a.to().0 + b.from().0), 0.5 * (a.to().1 + b.from().1));
            out.push(with_end(&a, mid));
            if j == 0 {
                out[0] = with_start(&out[0], mid);
            } else {
                pending[j] = with_start(&moved[j], mid);
            }
            continue;
        }
        let corner = outline[i].to();
        let turns_away = (cross < 0.0) == (s > 0.0);
        if turns_away {
            // A gap: round the corner on the wire's own radius.
            out.push(a);
            out.push(Segment::Arc {
                from: a.to(),
                to: b.from(),
                centre: corner,
                ccw: cross > 0.0,
            });
        } else {
            // A crossing: both cut back to the one nearest the corner. At a
            // corner it lies within about half the gap of the two ends; a
            // crossing much further off belongs to two nearly tangent
            // offsets (a kink of rounded arcs), which meet half-way.
            let x = crossings(&a, &b)
                .into_iter()
                .min_by(|p, q| length(sub(*p, corner)).total_cmp(&length(sub(*q, corner))))
                .filter(|x| length(sub(*x, a.to())) <= 4.0 * gap)
                .unwrap_or((0.5 * (a.to().0 + b.from().0), 0.5 * (a.to().1 + b.from().1)));
            out.push(with_end(&a, x));
            if j == 0 {
                out[0] = with_start(&out[0], x);
            } else {
                pending[j] = with_start(&moved[j], x);
            }
        }
    }
    Ok(out)
}
