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
//! within the flank's range; otherwise the nearer end point is. The arc
//! fit's many distances take φq as the argument of one product (one
//! arctangent, no arccosine); the certificate's, from the polar angle it
//! has, take the sum.

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

    /// The distance by one arctangent (the polar form's φ = θ + arccos(rb/R)
    /// as the argument of one product; derived where it is worked out).
    fn distance(&self, q: (f64, f64)) -> f64 {
        self.distance_one_atan(q)
    }
}

impl Involute {
    /// [`Curve::distance`] (the arc fit's many distances) with one
    /// arctangent instead of an arctangent and an arccosine.
    ///
    /// With R = |q|, l = √(R² − rb²), θ the polar angle of q and
    /// β = arccos(rb/R) (cos β = rb/R, sin β = l/R, β in [0, π/2]), the roll
    /// angle of the normal through q is φ = θ + β, and
    /// R²·(cos φ, sin φ) = R²·(cos θ cos β − sin θ sin β,
    /// sin θ cos β + cos θ sin β) = (x·rb − y·l, y·rb + x·l); so
    /// ψ = atan2(y·rb + x·l, x·rb − y·l) is φ up to a whole turn. As
    /// θ ∈ (−π, π], φ ∈ (−π, 3π/2]: ψ = φ when φ ≤ π, else ψ = φ − 2π ≤ −π/2.
    /// On a domain within [0, π] the two are therefore in the domain
    /// together and equal there: the same distance |l − rb·φ|, or the same
    /// nearer end, as [`Involute::distance_polar`] (up to rounding; the
    /// test holds them within 10⁻¹² mm). Another domain takes the polar
    /// form.
    fn distance_one_atan(&self, q: (f64, f64)) -> f64 {
        let r2 = q.0 * q.0 + q.1 * q.1;
        if !(self.roll_from >= 0.0 && self.roll_to <= std::f64::consts::PI) {
            return self.distance_polar(r2.sqrt(), q.1.atan2(q.0), || q);
        }
        let rb = self.base_radius_mm;
        let ends = || {
            let d = |p: (f64, f64)| ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
            d(self.point(self.roll_from)).min(d(self.point(self.roll_to)))
        };
        if r2 <= rb * rb {
            return ends();
        }
        let l = (r2 - rb * rb).sqrt();
        let phi = (q.1 * rb + q.0 * l).atan2(q.0 * rb - q.1 * l);
        if (self.roll_from..=self.roll_to).contains(&phi) {
            (l - rb * phi).abs()
        } else {
            ends()
        }
    }

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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4000))]

        /// The one-arctangent distance against the polar form (an
        /// arctangent and an arccosine): points all round involutes of
        /// base radii 2–100 mm, near and far, inside the base circle too,
        /// agree within 10⁻¹² mm relative to the point's radius.
        #[test]
        fn one_arctangent_is_the_polar_distance(
            rb in 2.0..100.0f64,
            from in 0.0..0.6f64,
            span in 0.05..1.5f64,
            r_share in 0.5..2.5f64,
            angle in -std::f64::consts::PI..std::f64::consts::PI,
        ) {
            let inv = Involute { base_radius_mm: rb, roll_from: from, roll_to: from + span };
            let r = rb * r_share;
            let q = (r * angle.cos(), r * angle.sin());
            let polar = inv.distance_polar(
                (q.0 * q.0 + q.1 * q.1).sqrt(), q.1.atan2(q.0), || q);
            let fast = inv.distance_one_atan(q);
            prop_assert!((fast - polar).abs() <= 1e-12 * (1.0 + r), "{fast} vs {polar}");
        }

        /// Points on the involute's own normals, a little off it either
        /// side: the distance is the offset.
        #[test]
        fn a_point_on_a_normal_is_its_offset_away(
            rb in 2.0..100.0f64,
            t in 0.05..1.2f64,
            off in -0.05..0.05f64,
        ) {
            let inv = Involute { base_radius_mm: rb, roll_from: 0.0, roll_to: 1.3 };
            let p = inv.point(t);
            // The normal at t: (sin t, −cos t), towards the base circle
            // when the offset is negative.
            let q = (p.0 + off * t.sin(), p.1 - off * t.cos());
            prop_assert!((inv.distance_one_atan(q) - off.abs()).abs() < 1e-12 * rb);
        }
    }
}
