//! The evaluation shared by profile and helix traces, as ISO 1328-1:2013
//! defines it for both (docs/measurement.md):
//!
//! - the deviation chart plots the trace's deviation e (µm, +material)
//!   against its position x (mm) along the evaluation range [x0, x1]; the
//!   design flank is the line e = 0;
//! - the total deviation F is the distance between two copies of the
//!   design line enclosing the trace over the range: max e − min e;
//! - the mean line is the least-squares line e ≈ a + s·x of the trace over
//!   the range; the slope deviation fH is the difference of the mean line
//!   between the ends of the range, s·(x1 − x0), signed (positive when the
//!   mean line rises from x0 to x1);
//! - the form deviation ff is the distance between two copies of the mean
//!   line enclosing the trace: max r − min r of the residuals
//!   r = e − (a + s·x).
//!
//! Distances are measured along the deviation axis of the chart, which is
//! the flank normal: the trace's abscissa is millimetres and its ordinate
//! micrometres, so a distance "perpendicular" to a line drawn in these
//! mixed units would have no meaning, and in consistent units (both in mm)
//! it differs from the normal distance by the factor cos(atan(s·10⁻³)),
//! less than 10⁻⁶ away from 1 for any slope a gear can have.

use crate::Error;
use serde::{Deserialize, Serialize};

/// The deviations of one trace over its evaluation range.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FlankDeviations {
    /// Total deviation (Fα or Fβ), µm.
    pub total_um: f64,
    /// Slope deviation (fHα or fHβ), µm, signed: the mean line's rise from
    /// the start to the end of the range.
    pub slope_um: f64,
    /// Form deviation (ffα or ffβ), µm.
    pub form_um: f64,
    /// The mean line's value at the start of the range, µm.
    pub mean_at_start_um: f64,
    /// The samples that lay in the range and were evaluated.
    pub samples: usize,
}

/// A least-squares line e ≈ a + s·(x − xm), with xm the mean abscissa.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanLine {
    /// The mean abscissa xm, mm.
    pub x_mean_mm: f64,
    /// The line's value at xm (the mean deviation), µm.
    pub at_mean_um: f64,
    /// Its slope, µm per mm.
    pub slope_um_per_mm: f64,
}

impl MeanLine {
    /// The line's value at `x_mm`, µm.
    pub fn at(&self, x_mm: f64) -> f64 {
        self.at_mean_um + self.slope_um_per_mm * (x_mm - self.x_mean_mm)
    }
}

/// The least-squares line through the points, from the normal equations
/// with the abscissae centred on their mean (which keeps them well
/// conditioned): s = Σ(x−xm)(e−em) / Σ(x−xm)². `None` when fewer than two
/// distinct abscissae.
pub fn mean_line(x_mm: &[f64], e_um: &[f64]) -> Option<MeanLine> {
    let n = x_mm.len().min(e_um.len());
    if n < 2 {
        return None;
    }
    let xm = x_mm[..n].iter().sum::<f64>() / n as f64;
    let em = e_um[..n].iter().sum::<f64>() / n as f64;
    let (mut sxx, mut sxe) = (0.0, 0.0);
    for (x, e) in x_mm[..n].iter().zip(&e_um[..n]) {
        sxx += (x - xm) * (x - xm);
        sxe += (x - xm) * (e - em);
    }
    (sxx > 0.0).then(|| MeanLine {
        x_mean_mm: xm,
        at_mean_um: em,
        slope_um_per_mm: sxe / sxx,
    })
}

/// Evaluates a trace (positions `x_mm`, deviations `e_um`, same length)
/// over the evaluation range from `start_mm` to `end_mm` (either order;
/// the slope is the rise from `start_mm` to `end_mm`). Samples outside
/// the range are left out. At least three samples at two or more distinct
/// positions must lie in it.
pub fn evaluate(
    x_mm: &[f64],
    e_um: &[f64],
    start_mm: f64,
    end_mm: f64,
) -> Result<FlankDeviations, Error> {
    if x_mm.len() != e_um.len() {
        return Err(Error::TooFewSamples {
            what: "deviations for as many positions",
            needed: x_mm.len(),
            got: e_um.len(),
        });
    }
    for (field, v) in [("start_mm", start_mm), ("end_mm", end_mm)] {
        crate::check_range(field, v, f64::MIN, f64::MAX, "a finite position, mm")?;
    }
    if let Some(bad) = x_mm.iter().chain(e_um).find(|v| !v.is_finite()) {
        return Err(Error::OutOfRange {
            field: "trace",
            expected: "finite positions and deviations",
            got: *bad,
        });
    }
    let (lo, hi) = (start_mm.min(end_mm), start_mm.max(end_mm));
    let slack = 1e-9 * (hi - lo).max(1.0);
    let (xs, es): (Vec<f64>, Vec<f64>) = x_mm
        .iter()
        .zip(e_um)
        .filter(|(x, _)| **x >= lo - slack && **x <= hi + slack)
        .map(|(x, e)| (*x, *e))
        .unzip();
    let few = Error::TooFewSamples {
        what: "samples at distinct positions in the evaluation range",
        needed: 3,
        got: xs.len(),
    };
    if xs.len() < 3 {
        return Err(few);
    }
    let line = mean_line(&xs, &es).ok_or(few)?;
    let range = |v: &mut dyn Iterator<Item = f64>| {
        let (mn, mx) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        mx - mn
    };
    let total_um = range(&mut es.iter().copied());
    let form_um = range(&mut xs.iter().zip(&es).map(|(x, e)| e - line.at(*x)));
    Ok(FlankDeviations {
        total_um,
        slope_um: line.at(end_mm) - line.at(start_mm),
        form_um,
        mean_at_start_um: line.at(start_mm),
        samples: xs.len(),
    })
}

#[cfg(test)]
mod tests;
