//! The root fillet as the arc fit and the certificate see it: arcfit's
//! [`Sampled`] polyline, with the same distance found faster.
//!
//! [`Sampled::distance`] takes the nearest of every 16th point (the first
//! of equals), walks down from it to the nearest point of the polyline and
//! measures the two chords beside that. [`Fillet`] finds that same
//! coarse point without measuring all of them: the coarse points are kept in
//! groups of 8 with a circle round each group, and a group whose circle is
//! farther than the best point so far cannot hold a nearer point (nor an
//! equally near one: the bound keeps a margin of 10⁻⁹ of the distance for
//! the rounding). The walk and the chords are then [`Sampled`]'s own
//! ([`Sampled::distance_from`], on its points), so the distance is the same
//! to the last bit (the unit test holds the two equal on points all round the
//! fillet).

use gearcam_arcfit::{Curve, Sampled};

/// Coarse points per group.
const GROUP: usize = 8;
/// Groups at most: the fillet is sampled at [`crate::outline`]'s 1,024
/// points, 66 coarse ones (checked when it is built).
const MAX_GROUPS: usize = 16;

/// The fillet sampled at `n` + 1 points, as [`Sampled::new`], with the
/// coarse points grouped for the search.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Fillet {
    sampled: Sampled,
    /// The coarse points' indices into [`Sampled::points`], in its order.
    coarse: Vec<usize>,
    /// Each group of [`GROUP`] coarse points: its centre and radius.
    groups: Vec<((f64, f64), f64)>,
}

impl Fillet {
    /// `curve` sampled at `n` + 1 equally spaced parameters (n ≥ 2).
    pub(crate) fn new(curve: &dyn Curve, n: usize) -> Fillet {
        let sampled = Sampled::new(curve, n);
        let points = sampled.points();
        let n = points.len() - 1;
        let coarse: Vec<usize> = (0..=n)
            .step_by(Sampled::COARSE)
            .chain(std::iter::once(n))
            .collect();
        let groups = coarse
            .chunks(GROUP)
            .map(|g| {
                let k = g.len() as f64;
                let c = g.iter().fold((0.0, 0.0), |s, &i| {
                    (s.0 + points[i].0 / k, s.1 + points[i].1 / k)
                });
                let r = g
                    .iter()
                    .map(|&i| (points[i].0 - c.0).hypot(points[i].1 - c.1))
                    .fold(0.0, f64::max);
                (c, r)
            })
            .collect::<Vec<_>>();
        assert!(groups.len() <= MAX_GROUPS, "a fillet of {n} samples");
        Fillet {
            sampled,
            coarse,
            groups,
        }
    }

    /// The largest sagitta of a chord ([`Sampled::sag`]), mm.
    #[cfg(test)]
    pub(crate) fn sag(&self) -> f64 {
        self.sampled.sag()
    }

    /// The index of the nearest coarse point to `q`, the first of equals in
    /// [`Sampled`]'s order.
    fn nearest_coarse(&self, q: (f64, f64), d2: impl Fn(usize) -> f64) -> usize {
        // Each group's distance from q at least: to its circle.
        let mut bounds = [0.0f64; MAX_GROUPS];
        let groups = self.groups.len();
        let mut first = 0;
        for (g, &((cx, cy), r)) in self.groups.iter().enumerate() {
            let (dx, dy) = (cx - q.0, cy - q.1);
            bounds[g] = ((dx * dx + dy * dy).sqrt() - r).max(0.0);
            if bounds[g] < bounds[first] {
                first = g;
            }
        }
        // The group nearest by its circle first, then the others it does
        // not rule out.
        let mut best = (f64::INFINITY, usize::MAX);
        for g in std::iter::once(first).chain((0..groups).filter(|&g| g != first)) {
            let lb = bounds[g];
            if lb * lb > best.0 * (1.0 + 1e-9) + 1e-300 {
                continue;
            }
            for &i in &self.coarse[g * GROUP..((g + 1) * GROUP).min(self.coarse.len())] {
                let d = d2(i);
                if d < best.0 || (d == best.0 && i < best.1) {
                    best = (d, i);
                }
            }
        }
        best.1
    }
}

impl Curve for Fillet {
    fn domain(&self) -> (f64, f64) {
        self.sampled.domain()
    }
    fn point(&self, t: f64) -> (f64, f64) {
        self.sampled.point(t)
    }
    fn tangent_angle(&self, t: f64) -> f64 {
        self.sampled.tangent_angle(t)
    }
    fn distance(&self, q: (f64, f64)) -> f64 {
        let points = self.sampled.points();
        let d2 = |i: usize| {
            let p = points[i];
            (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)
        };
        let start = self.nearest_coarse(q, d2);
        self.sampled.distance_from(start, q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gear::{RackGear, ToothSpace};

    /// On the fillets of a fine and a coarse gear, at points all round
    /// each (near it, across the tooth space, far off), the grouped search
    /// starts from the coarse point a scan of them all finds and gives
    /// [`Sampled`]'s distance to the last bit.
    #[test]
    fn the_grouped_search_gives_the_sampled_distance_exactly() {
        for (m, z, x) in [(2.0, 40, 0.0), (0.5, 12, 0.4), (5.0, 17, -0.2)] {
            let gear = RackGear {
                module_mm: m,
                teeth: z,
                pressure_angle_deg: 20.0,
                profile_shift: x,
                addendum_coef: 1.0,
                clearance_coef: 0.25,
                tip_radius_coef: 0.38,
            };
            let curve = gear.fillet_curve();
            let fast = Fillet::new(curve.as_ref(), 1024);
            let plain = Sampled::new(curve.as_ref(), 1024);
            assert_eq!(fast.sag(), plain.sag());
            let (t0, t1) = curve.domain();
            let mut n = 0;
            for i in 0..=400 {
                let p = curve.point(t0 + (t1 - t0) * f64::from(i) / 400.0);
                for (dx, dy) in [
                    (0.0, 0.0),
                    (1e-4, -2e-4),
                    (0.05, 0.01),
                    (-0.3, 0.2),
                    (2.0 * m, -m),
                    (-7.0 * m, 3.0 * m),
                ] {
                    let q = (p.0 + dx, p.1 + dy);
                    assert_eq!(
                        fast.distance(q).to_bits(),
                        plain.distance(q).to_bits(),
                        "{q:?}"
                    );
                    // The coarse point the walk starts from: the first
                    // nearest by a scan of them all.
                    let d2 = |i: usize| {
                        let p = fast.sampled.points()[i];
                        (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)
                    };
                    let scan = fast
                        .coarse
                        .iter()
                        .copied()
                        .min_by(|&a, &b| d2(a).total_cmp(&d2(b)))
                        .unwrap();
                    assert_eq!(fast.nearest_coarse(q, d2), scan, "{q:?}");
                    n += 1;
                }
            }
            assert!(n > 2000);
        }
    }
}
