//! The measure of a wire path against the theoretical outline: what the
//! program's certificate states (docs/wire.md). Every point sampled on the
//! path should lie the offset d from the outline; the deviation is
//! | distance − d |, counted against the nearest piece (flank and tip, or
//! fillet and root). The path must close and go round the centre once,
//! clockwise.

use std::f64::consts::TAU;

use crate::outline::{Outline, Piece};
use crate::Segment;

/// What a path measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measure {
    /// The largest deviation where the flank or the tip is nearest, mm.
    pub flank_mm: f64,
    /// The largest deviation where the fillet or the root is nearest, mm.
    pub fillet_mm: f64,
    /// The gap between the path's end and its start, mm.
    pub closure_mm: f64,
    /// Turns about the centre (−1: once, clockwise).
    pub turns: f64,
}

/// Samples per segment of [`measure`].
pub const SAMPLES: usize = 16;

/// Measures `path` against `outline` set off by `offset_mm`, on
/// `samples` + 1 points per segment, equally spaced along it.
pub fn measure(outline: &Outline, path: &[Segment], offset_mm: f64, samples: usize) -> Measure {
    let (mut flank, mut fillet) = (0.0f64, 0.0f64);
    let mut angle = 0.0;
    let mut last: Option<f64> = None;
    for s in path {
        for p in samples_along(s, samples) {
            let polar = p.1.atan2(p.0);
            let (d, piece) = outline.distance_at((p.0 * p.0 + p.1 * p.1).sqrt(), polar);
            let dev = (d - offset_mm).abs();
            match piece {
                Piece::Flank | Piece::Tip => flank = flank.max(dev),
                Piece::Fillet | Piece::Root => fillet = fillet.max(dev),
            }
            if let Some(l) = last {
                angle += (polar - l + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
            }
            last = Some(polar);
        }
    }
    let closure = match (path.first(), path.last()) {
        (Some(a), Some(b)) => (a.from().0 - b.to().0).hypot(a.from().1 - b.to().1),
        _ => 0.0,
    };
    Measure {
        flank_mm: flank,
        fillet_mm: fillet,
        closure_mm: closure,
        turns: angle / TAU,
    }
}

/// `samples` + 1 points equally spaced along `s`, its ends among them: a
/// line's by the share of the way, an arc's by turning its start about
/// its centre a share of its sweep at a time (a rounding of a few units
/// in the last place after the turns).
fn samples_along(s: &Segment, samples: usize) -> impl Iterator<Item = (f64, f64)> + '_ {
    let n = samples.max(1);
    let (from, to) = (s.from(), s.to());
    let (centre, step) = match *s {
        Segment::Line { .. } => (None, (0.0, 1.0)),
        Segment::Arc { centre, ccw, .. } => {
            let turn = if ccw { 1.0 } else { -1.0 } * s.sweep() / n as f64;
            (Some(centre), turn.sin_cos())
        }
    };
    let mut at = centre.map(|c| (from.0 - c.0, from.1 - c.1));
    (0..=n).map(move |i| match (centre, at.as_mut()) {
        (None, _) => {
            let t = i as f64 / n as f64;
            (from.0 + t * (to.0 - from.0), from.1 + t * (to.1 - from.1))
        }
        (Some(c), Some(v)) => {
            let p = (c.0 + v.0, c.1 + v.1);
            let (sd, cd) = step;
            *v = (v.0 * cd - v.1 * sd, v.1 * cd + v.0 * sd);
            p
        }
        (Some(_), None) => unreachable!("an arc has its radius"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The points along a segment, turned step by step, against the arc
    /// spline's own point at the same length: lines, arcs both ways, small
    /// and large, a whole circle, within 10⁻¹² mm.
    #[test]
    fn the_samples_are_the_segments_points_at_equal_lengths() {
        let arc = |from, to, centre, ccw| Segment::Arc {
            from,
            to,
            centre,
            ccw,
        };
        for s in [
            Segment::Line {
                from: (1.0, 2.0),
                to: (-3.0, 7.5),
            },
            arc((20.0, 0.0), (0.0, 20.0), (0.0, 0.0), true),
            arc((20.0, 0.0), (0.0, 20.0), (0.0, 0.0), false),
            arc((5.1, 3.0), (5.0, 3.1), (5.0, 3.0), true),
            arc((5.1, 3.0), (5.0, 3.1), (5.0, 3.0), false),
            arc((2.0, 0.0), (2.0, 0.0), (0.0, 0.0), true),
        ] {
            let a = s.arc();
            for (i, p) in samples_along(&s, SAMPLES).enumerate() {
                let q = a.point_at(a.length * i as f64 / SAMPLES as f64);
                assert!(
                    (p.0 - q.0).hypot(p.1 - q.1) < 1e-12,
                    "{s:?} {i}: {p:?} {q:?}"
                );
            }
            assert_eq!(samples_along(&s, SAMPLES).count(), SAMPLES + 1);
        }
    }
}
