//! Finding flanks on a polar outline: where the outline crosses a circle,
//! which crossings belong to which tooth, and following a tooth from
//! section to section.
//!
//! An outline r(θ) is known at its samples only. Between two samples
//! r₀ ≥ ρ > r₁ the crossing of the radius ρ is found on the cubic through
//! the four samples around them (Lagrange, in the sample index s), by
//! Newton's method kept inside s ∈ [0, 1] by bisection: the cubic passes
//! through r₀ and r₁, so the root is bracketed. Linear interpolation,
//! θ = θ₀ + (r₀ − ρ)/(r₀ − r₁)·Δθ, errs by r″·Δθ²/8 in r, which on a flank
//! turns into a slope of the profile trace of some 0.07 µm at n = 16 384
//! (docs/measurement.md, section 6); the cubic's error is of order Δθ⁴.
//! Where the four samples straddle a kink or a step the chord is used.
//! Material is where r ≥ ρ. Going counter-clockwise (+θ) the outline rises
//! through ρ on the left flank of a tooth (facing −θ) and falls on its
//! right flank (facing +θ).

use crate::Error;
use std::f64::consts::TAU;

/// One section's outline.
#[derive(Debug, Clone, Copy)]
pub(super) struct Section<'a> {
    r: &'a [f64],
    step: f64,
}

impl<'a> Section<'a> {
    /// The outline `r` (n radii at θᵢ = 2π·i/n).
    pub(super) fn new(r: &'a [f64], n: usize) -> Section<'a> {
        Section {
            r,
            step: TAU / n as f64,
        }
    }

    /// The radius at sample `i`, counted round the circle (any integer).
    pub(super) fn at(&self, i: i64) -> f64 {
        self.r[i.rem_euclid(self.r.len() as i64) as usize]
    }

    /// The angle of sample `i`, unwrapped (i·Δθ), rad.
    pub(super) fn theta(&self, i: i64) -> f64 {
        i as f64 * self.step
    }

    /// The sample at or before angle `theta` (unwrapped).
    pub(super) fn index_at(&self, theta: f64) -> i64 {
        (theta / self.step).floor() as i64
    }

    /// The angle where the outline first drops below `rho` going from the
    /// angle `from` in the direction `dir` (+1: +θ, −1: −θ), at most
    /// `within` rad away; `None` when the outline at `from` is already
    /// below `rho` or does not drop below it within reach.
    pub(super) fn crossing(&self, from: f64, rho: f64, dir: i64, within: f64) -> Option<f64> {
        let start = self.index_at(from);
        let mut prev = if dir > 0 { start } else { start + 1 };
        if self.at(prev) < rho {
            return None;
        }
        let steps = (within / self.step).ceil() as i64 + 1;
        for _ in 0..steps {
            let i = prev + dir;
            let (rp, ri) = (self.at(prev), self.at(i));
            if ri < rho {
                debug_assert!(rp >= rho);
                return Some(self.theta(prev) + dir as f64 * self.root(prev, dir, rho) * self.step);
            }
            prev = i;
        }
        None
    }

    /// The walk from the angle `from` in the direction `dir`, at most
    /// `within` rad, for many radii ([`Walk::crossing`]).
    pub(super) fn walk(&self, from: f64, dir: i64, within: f64) -> Walk<'a> {
        let start = if dir > 0 {
            self.index_at(from)
        } else {
            self.index_at(from) + 1
        };
        let steps = (within / self.step).ceil() as i64 + 1;
        let mut low = f64::INFINITY;
        let least = (0..=steps)
            .map(|k| {
                low = low.min(self.at(start + dir * k));
                low
            })
            .collect();
        Walk {
            section: *self,
            start,
            dir,
            least,
        }
    }

    /// Where between sample `i` (s = 0) and sample `i + dir` (s = 1) the
    /// cubic through samples i − dir … i + 2·dir equals `rho`, whose values
    /// at s = 0 and 1 lie on either side of it: Newton's method from the
    /// chord's root, kept inside the bracket by bisection.
    fn root(&self, i: i64, dir: i64, rho: f64) -> f64 {
        let y = [-1, 0, 1, 2].map(|k| self.at(i + k * dir) - rho);
        let chord = y[1] / (y[1] - y[2]);
        let start_above = y[1] >= 0.0;
        // Across a kink or a step (a tip corner, the foot of a flank) the
        // cubic overshoots: there the samples are not monotone, or the
        // cubic's bend at the middle, (y1 + y2 − y0 − y3)/16, is more than
        // a tenth of the step y1 − y2. Then the chord.
        let monotone = if start_above {
            y[0] >= y[1] && y[2] >= y[3]
        } else {
            y[0] <= y[1] && y[2] <= y[3]
        };
        let bend = (y[1] + y[2] - y[0] - y[3]) / 16.0;
        if !monotone || bend.abs() > 0.1 * (y[1] - y[2]).abs() {
            return chord;
        }
        // The Lagrange cubic through s = −1, 0, 1, 2 in powers of s.
        let a = [
            y[1],
            -y[0] / 3.0 - y[1] / 2.0 + y[2] - y[3] / 6.0,
            y[0] / 2.0 - y[1] + y[2] / 2.0,
            (y[3] - y[0]) / 6.0 + (y[1] - y[2]) / 2.0,
        ];
        let (mut lo, mut hi, mut s) = (0.0, 1.0, chord);
        for _ in 0..60 {
            let f = a[0] + s * (a[1] + s * (a[2] + s * a[3]));
            if f == 0.0 {
                return s;
            }
            if (f >= 0.0) == start_above {
                lo = s;
            } else {
                hi = s;
            }
            let df = a[1] + s * (2.0 * a[2] + 3.0 * s * a[3]);
            let mut next = s - f / df;
            if !(next > lo && next < hi) {
                next = (lo + hi) / 2.0;
            }
            if (next - s).abs() < 1e-15 {
                return next;
            }
            s = next;
        }
        s
    }

    /// Every crossing of the circle `rho` round the outline, in order of
    /// angle from 0: (θ, rising), rising when the outline goes from below
    /// `rho` to at least `rho` with growing θ.
    fn crossings(&self, rho: f64) -> Vec<(f64, bool)> {
        let n = self.r.len() as i64;
        let mut out = Vec::new();
        for i in 0..n {
            let (a, b) = (self.at(i), self.at(i + 1));
            if (a < rho) != (b < rho) {
                out.push((self.theta(i) + self.root(i, 1, rho) * self.step, b >= rho));
            }
        }
        out
    }
}

/// A walk along an outline from one sample in one direction, holding the
/// least radius met so far at every step: the first sample below ρ is the
/// first step whose least radius is below ρ, and the least radius never
/// grows, so it is found by bisection instead of a scan. A profile trace
/// asks for some 240 radii on the same walk.
#[derive(Debug, Clone)]
pub(super) struct Walk<'a> {
    section: Section<'a>,
    start: i64,
    dir: i64,
    least: Vec<f64>,
}

impl Walk<'_> {
    /// The same as [`Section::crossing`] from the walk's start: the angle
    /// where the outline first drops below `rho`, `None` when it starts
    /// below or does not drop within the walk.
    pub(super) fn crossing(&self, rho: f64) -> Option<f64> {
        let k = self.least.partition_point(|r| *r >= rho);
        if k == 0 || k == self.least.len() {
            return None;
        }
        let prev = self.start + self.dir * (k as i64 - 1);
        let sec = &self.section;
        Some(sec.theta(prev) + self.dir as f64 * sec.root(prev, self.dir, rho) * sec.step)
    }
}

/// One tooth at the measuring circle: the angles (rad, unwrapped) where
/// its left and right flanks cross it, left < right.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Tooth {
    pub(super) left: f64,
    pub(super) right: f64,
}

impl Tooth {
    /// The middle of the tooth at the measuring circle.
    pub(super) fn centre(&self) -> f64 {
        (self.left + self.right) / 2.0
    }
}

/// The z teeth of the section at the measuring radius `rho`, in order of
/// growing θ, tooth 0 the first whose left flank crosses at θ ≥ 0 and every
/// later angle unwrapped past it. The outline must cross the circle
/// exactly 2z times, rising and falling in turn.
pub(super) fn find_teeth(sec: &Section<'_>, teeth: u32, rho: f64) -> Result<Vec<Tooth>, Error> {
    let c = sec.crossings(rho);
    let z = teeth as usize;
    let bad = |got: f64| {
        Error::OutOfRange {
        field: "sections",
        expected: "an outline crossing the measuring circle 2z times (z teeth there), rising and falling in turn",
        got,
    }
    };
    if c.len() != 2 * z {
        return Err(bad(c.len() as f64));
    }
    let first = c.iter().position(|x| x.1).ok_or(bad(0.0))?;
    let mut out = Vec::with_capacity(z);
    let mut last = f64::NEG_INFINITY;
    let mut unwrap = |theta: f64| {
        let mut t = theta;
        while t < last {
            t += TAU;
        }
        last = t;
        t
    };
    for j in 0..z {
        let (l, rising_l) = c[(first + 2 * j) % (2 * z)];
        let (r, rising_r) = c[(first + 2 * j + 1) % (2 * z)];
        if !rising_l || rising_r {
            return Err(bad(c.len() as f64));
        }
        let left = unwrap(l);
        let right = unwrap(r);
        out.push(Tooth { left, right });
    }
    Ok(out)
}

/// The tooth near `predicted` (rad, the centre expected) at the radius
/// `rho`: its flanks found by going out from `predicted` both ways, at
/// most a pitch. `None` when `predicted` is not on material.
pub(super) fn tooth_near(sec: &Section<'_>, predicted: f64, rho: f64, pitch: f64) -> Option<Tooth> {
    let left = sec.crossing(predicted, rho, -1, pitch)?;
    let right = sec.crossing(predicted, rho, 1, pitch)?;
    Some(Tooth { left, right })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// A square wave: teeth of radius 2 from 10° to 20° (and every 90°),
    /// spaces of radius 1, sampled every degree.
    fn square() -> Vec<f64> {
        (0..360)
            .map(|i| {
                if (10..=20).contains(&(i % 90)) {
                    2.0
                } else {
                    1.0
                }
            })
            .collect()
    }

    #[test]
    fn crossings_interpolate_between_the_samples() {
        let r = square();
        let s = Section::new(&r, 360);
        let deg = 1.0_f64.to_radians();
        // From 15° going +θ: samples 19, 20 are 2, 21, 22 are 1; r = 1.5
        // halfway between 20 and 21.
        let t = s.crossing(15.0 * deg, 1.5, 1, 1.0).unwrap();
        assert!((t - 20.5 * deg).abs() < 1e-12);
        // The cubic through 2, 2, 1, 1 (s = −1 … 2) is 1.5 + (s − 0.5)·(…):
        // odd about s = 0.5, so r = 1.5 there.
        let t = s.crossing(15.0 * deg, 1.5, -1, 1.0).unwrap();
        assert!((t - 9.5 * deg).abs() < 1e-12);
        assert!(s.crossing(50.0 * deg, 1.5, 1, 1.0).is_none());
        let teeth = find_teeth(&s, 4, 1.5).unwrap();
        assert_eq!(teeth.len(), 4);
        assert!((teeth[3].left - 279.5 * deg).abs() < 1e-12);
        assert!((teeth[0].centre() - 15.0 * deg).abs() < 1e-12);
        assert!(find_teeth(&s, 5, 1.5).is_err());
    }

    #[test]
    fn a_step_beyond_the_crossing_does_not_bend_it() {
        // Falling by 0.2 a sample, then a step down to the root: the chord
        // (the data are linear up to the step) puts r = 1.7 halfway between
        // samples 11 and 12; the cubic through the step would not.
        let mut r = vec![2.0; 64];
        r[10..20].copy_from_slice(&[2.0, 1.8, 1.6, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5]);
        let s = Section::new(&r, 64);
        let step = TAU / 64.0;
        let t = s.crossing(5.0 * step, 1.7, 1, 1.0).unwrap();
        assert!((t - 11.5 * step).abs() < 1e-12, "{}", t / step);
        // Smooth data: the cubic is exact for a cubic in the index.
        let c: Vec<f64> = (0..64)
            .map(|i| {
                let x = f64::from(i) / 64.0;
                3.0 - x * x * x - x
            })
            .collect();
        let s = Section::new(&c, 64);
        let x0 = 0.4_f64;
        let t = s.crossing(0.0, 3.0 - x0.powi(3) - x0, 1, 7.0).unwrap();
        assert!((t / step / 64.0 - x0).abs() < 1e-12);
    }

    proptest! {
        #[test]
        fn a_walk_finds_what_a_scan_finds(
            r in prop::collection::vec(1.0f64..2.0, 64..200),
            from in 0.0f64..7.0,
            rho in 1.0f64..2.0,
            right in any::<bool>(),
        ) {
            let s = Section::new(&r, r.len());
            let dir = if right { 1 } else { -1 };
            let walk = s.walk(from, dir, 1.5);
            prop_assert_eq!(walk.crossing(rho), s.crossing(from, rho, dir, 1.5));
        }
    }

    #[test]
    fn a_tooth_across_zero_is_unwrapped_past_the_others() {
        // Teeth from 355° to 5° (and every 90°).
        let r: Vec<f64> = (0..360)
            .map(|i| if ((i + 5) % 90) <= 10 { 2.0 } else { 1.0 })
            .collect();
        let s = Section::new(&r, 360);
        let teeth = find_teeth(&s, 4, 1.5).unwrap();
        let deg = 1.0_f64.to_radians();
        assert!((teeth[0].left - 84.5 * deg).abs() < 1e-12);
        assert!((teeth[3].centre() - 360.0 * deg).abs() < 1e-12);
        assert!(teeth.windows(2).all(|w| w[1].left > w[0].right));
    }
}
