//! The involute of a gear's base circle, as a [`Curve`] for the arc fit,
//! with the exact distance of a point from it.
//!
//! With the roll angle φ, the involute of the base circle rb is
//! P(φ) = rb·(cos φ + φ·sin φ, sin φ − φ·cos φ); its tangent at φ points
//! along (cos φ, sin φ) and its normal touches the base circle at
//! rb·(cos φ, sin φ), at the distance rb·φ from P (the unwound string).
//!
//! **Distance.** A point q at radius R > rb lies on the normal of the one
//! roll angle φq whose base-circle tangent passes through it, at
//! l = √(R² − rb²) from the tangent point; its polar angle is then
//! θ = φq − arctan(l/rb), so φq = θ + arccos(rb/R), and q is
//! |l − rb·φq| from the involute along that normal — docs/wire.md's
//! √(R² − rb²) − rb·(θ + arccos(rb/R)), up to its sign. A normal is the
//! shortest way to a curve, so this is the exact distance whenever φq lies
//! within the flank's range; otherwise the nearer end point is.

use gearcam_arcfit::Curve;
use gearcam_geom::involute::roll_at;

/// An involute flank of the base circle `base_radius_mm` between two roll angles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Involute {
    /// Base radius rb, mm.
    pub base_radius_mm: f64,
    /// First roll angle, radians.
    pub roll_from: f64,
    /// Last roll angle, radians.
    pub roll_to: f64,
}

impl Involute {
    /// The flank between the radii `from_mm` and `to_mm` (both ≥ rb).
    pub fn between_radii(base_radius_mm: f64, from_mm: f64, to_mm: f64) -> Involute {
        Involute {
            base_radius_mm,
            roll_from: roll_at(base_radius_mm, from_mm),
            roll_to: roll_at(base_radius_mm, to_mm),
        }
    }
}

impl Curve for Involute {
    fn domain(&self) -> (f64, f64) {
        (self.roll_from, self.roll_to)
    }

    fn point(&self, t: f64) -> (f64, f64) {
        let rb = self.base_radius_mm;
        (rb * (t.cos() + t * t.sin()), rb * (t.sin() - t * t.cos()))
    }

    fn tangent_angle(&self, t: f64) -> f64 {
        t
    }

    fn distance(&self, q: (f64, f64)) -> f64 {
        let r = (q.0 * q.0 + q.1 * q.1).sqrt();
        self.distance_polar(r, q.1.atan2(q.0), || q)
    }
}

impl Involute {
    /// [`Curve::distance`] of the point at radius `r` and polar angle
    /// `angle` (radians, in (−π, π]), for a caller that has them; `point`
    /// gives the point itself, needed only when an end point is nearest.
    pub(crate) fn distance_polar(
        &self,
        r: f64,
        angle: f64,
        point: impl FnOnce() -> (f64, f64),
    ) -> f64 {
        let rb = self.base_radius_mm;
        let ends = || {
            let q = point();
            let d = |p: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
            d(self.point(self.roll_from)).min(d(self.point(self.roll_to)))
        };
        if r <= rb {
            return ends();
        }
        let l = (r * r - rb * rb).sqrt();
        let phi = angle + (rb / r).acos();
        if (self.roll_from..=self.roll_to).contains(&phi) {
            (l - rb * phi).abs()
        } else {
            ends()
        }
    }
}
