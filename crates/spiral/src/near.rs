//! The nearest point of the spiral to a point close to it, by Newton's
//! method, for the many points the arc fit and the chords' measure take:
//! the spiral's constants worked out once ([`Frame`]) and no sine or cosine
//! evaluated for the steps.

use crate::Spiral;

/// (c, s) = (cos a, sin a) turned by the angle whose sine and cosine are
/// `(sd, cd)` (the order `f64::sin_cos` gives them).
pub(crate) fn turned((c, s): (f64, f64), (sd, cd): (f64, f64)) -> (f64, f64) {
    (c * cd - s * sd, s * cd + c * sd)
}

/// The spiral's constants for the many points the fit measures:
/// S(φ) = r(φ)·(cos a, sin a), r = R1 + bφ, a = θ0 + sense·φ.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    /// R1, mm.
    pub(crate) r1: f64,
    /// b = dR/dφ, mm per radian.
    pub(crate) b: f64,
    /// +1 counter-clockwise, −1 clockwise.
    pub(crate) sense: f64,
    /// θ0, radians.
    pub(crate) theta0: f64,
}

impl Frame {
    pub(crate) fn of(spiral: &Spiral) -> Frame {
        Frame {
            r1: spiral.start_radius_mm,
            b: (spiral.end_radius_mm - spiral.start_radius_mm)
                / (std::f64::consts::TAU * f64::from(spiral.turns)),
            sense: f64::from(spiral.sense),
            theta0: spiral.start_angle_deg.to_radians(),
        }
    }

    /// r(φ), as [`Spiral::radius_at`].
    pub(crate) fn radius(&self, phi: f64) -> f64 {
        self.r1 + self.b * phi
    }

    /// The polar angle a(φ), radians.
    pub(crate) fn angle(&self, phi: f64) -> f64 {
        self.theta0 + self.sense * phi
    }

    /// The distance from `p` to the spiral near `guess` (radians from θ0),
    /// kept within `lo..=hi`, where `cs` is (cos a, sin a) at the guess:
    /// Newton's method on (S(φ) − p)·S′(φ) = 0 with the spiral's exact
    /// derivatives, which converges in a few steps from a guess this close.
    /// Each step turns (cos a, sin a) by its change of angle Δ (cos Δ and
    /// sin Δ from their series, exact to the last bit for |Δ| < 10⁻³, a
    /// sine and cosine beyond), so no sine or cosine is taken for the
    /// steps; at most four steps, fewer once a step turns less than 10⁻⁸
    /// (the error left is of the order of its square).
    pub(crate) fn nearest(
        &self,
        p: (f64, f64),
        guess: f64,
        cs: (f64, f64),
        lo: f64,
        hi: f64,
    ) -> f64 {
        let (b, s) = (self.b, self.sense);
        let (mut c, mut n) = cs;
        let mut phi = guess;
        for _ in 0..4 {
            let r = self.radius(phi);
            let q = (r * c - p.0, r * n - p.1);
            let d1 = (b * c - r * s * n, b * n + r * s * c);
            let d2 = (-2.0 * b * s * n - r * c, 2.0 * b * s * c - r * n);
            let f = q.0 * d1.0 + q.1 * d1.1;
            let df = d1.0 * d1.0 + d1.1 * d1.1 + q.0 * d2.0 + q.1 * d2.1;
            if df.abs() < 1e-300 {
                break;
            }
            let next = (phi - f / df).clamp(lo, hi);
            let turn = s * (next - phi);
            let (sd, cd) = if turn.abs() < 1e-3 {
                let t2 = turn * turn;
                (
                    turn * (1.0 - t2 / 6.0 * (1.0 - t2 / 20.0)),
                    1.0 - t2 / 2.0 * (1.0 - t2 / 12.0),
                )
            } else {
                turn.sin_cos()
            };
            (c, n) = (c * cd - n * sd, n * cd + c * sd);
            phi = next;
            // Converged: Newton's error after a step is of the order of the
            // step squared, here under 10⁻¹⁵ radians.
            if turn.abs() < 1e-8 {
                break;
            }
        }
        let r = self.radius(phi);
        ((r * c - p.0).powi(2) + (r * n - p.1).powi(2)).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance from `p` to the spiral between `lo` and `hi` by
    /// golden-section search on the squared distance (60 steps, each
    /// taking the spiral's point afresh): the reference, slow and sure
    /// where the distance is unimodal, which it is on a piece this short.
    fn golden(spiral: &Spiral, p: (f64, f64), lo: f64, hi: f64) -> f64 {
        let d2 = |phi: f64| {
            let (sx, sy) = spiral.point_at(phi);
            (sx - p.0).powi(2) + (sy - p.1).powi(2)
        };
        let (mut lo, mut hi) = (lo, hi);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if d2(m1) < d2(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        d2(0.5 * (lo + hi)).sqrt()
    }

    /// Newton's nearest point, its angle turned by series, against the
    /// golden-section search: points up to 50 µm off spirals of both
    /// senses, from a guess up to a milliradian off, agree within 10⁻¹⁰ mm.
    #[test]
    fn newton_with_turned_angles_agrees_with_a_golden_section_search() {
        let mut seed: u64 = 99;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut worst: f64 = 0.0;
        for i in 0..2000 {
            let spiral = Spiral {
                start_radius_mm: 5.0 + 150.0 * rnd(),
                end_radius_mm: 50.0 * rnd(),
                start_angle_deg: 360.0 * rnd(),
                turns: 1 + (rnd() * 12.0) as u32,
                sense: if i % 2 == 0 { 1 } else { -1 },
            };
            let frame = Frame::of(&spiral);
            let total = std::f64::consts::TAU * f64::from(spiral.turns);
            let (lo, hi) = {
                let a = (total - 0.02) * rnd();
                (a, a + 0.02)
            };
            let phi = lo + (hi - lo) * rnd();
            let (x, y) = spiral.point_at(phi);
            let off = (0.05 * (rnd() - 0.5), 0.05 * (rnd() - 0.5));
            let p = (x + off.0, y + off.1);
            let guess = (phi + 1e-3 * (rnd() - 0.5)).clamp(lo, hi);
            let (s, c) = frame.angle(guess).sin_cos();
            let fast = frame.nearest(p, guess, (c, s), lo, hi);
            let sure = golden(&spiral, p, lo, hi);
            worst = worst.max((fast - sure).abs());
        }
        assert!(worst < 1e-10, "{worst}");
    }

    /// The chords' measured deviation against the same measure taken with
    /// the golden-section search, chord by chord.
    #[test]
    fn the_chords_deviation_agrees_with_a_golden_section_measure() {
        for (spiral, tol) in [
            (
                Spiral {
                    start_radius_mm: 110.0,
                    end_radius_mm: 0.0,
                    start_angle_deg: 0.0,
                    turns: 10,
                    sense: 1,
                },
                0.001,
            ),
            (
                Spiral {
                    start_radius_mm: 20.0,
                    end_radius_mm: 63.0,
                    start_angle_deg: 33.0,
                    turns: 4,
                    sense: -1,
                },
                0.005,
            ),
        ] {
            let (_, pts) = spiral.chords(tol);
            let n = pts.len() - 1;
            let dphi = std::f64::consts::TAU * f64::from(spiral.turns) / n as f64;
            let mut sure: f64 = 0.0;
            for (i, w) in pts.windows(2).enumerate() {
                for k in 1..16 {
                    let t = k as f64 / 16.0;
                    let p = (
                        w[0].0 + t * (w[1].0 - w[0].0),
                        w[0].1 + t * (w[1].1 - w[0].1),
                    );
                    let lo = dphi * i as f64;
                    sure = sure.max(golden(&spiral, p, lo, lo + dphi));
                }
            }
            let fast = crate::chord_deviation(&spiral, &pts);
            assert!((fast - sure).abs() < 1e-12, "{fast} vs {sure}");
        }
    }
}
