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
/// `samples` + 1 points per segment.
pub fn measure(outline: &Outline, path: &[Segment], offset_mm: f64, samples: usize) -> Measure {
    let (mut flank, mut fillet) = (0.0f64, 0.0f64);
    let mut angle = 0.0;
    let mut last: Option<f64> = None;
    for s in path {
        let a = s.arc();
        for i in 0..=samples {
            let p = a.point_at(a.length * i as f64 / samples as f64);
            let (d, piece) = outline.distance(p);
            let dev = (d - offset_mm).abs();
            match piece {
                Piece::Flank | Piece::Tip => flank = flank.max(dev),
                Piece::Fillet | Piece::Root => fillet = fillet.max(dev),
            }
            let polar = p.1.atan2(p.0);
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
