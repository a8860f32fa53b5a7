//! [`deviation`]: the fit's check, measured densely both ways.
//!
//! Each arc's constants (its end, its circle, the polar angle of its start
//! about the centre, the sine and cosine of its start tangent) are worked
//! out once, not once per point, by the same operations as
//! [`Arc::point_at`] and [`Arc::distance`]; and a point of the curve takes
//! its distance only from the arcs that can be the nearest. An arc's
//! distance is at least its circle's, |‖q − c‖ − r| (a point of the arc is
//! on the circle; a line's is exact and cheap), so an arc whose circle lies
//! farther than the nearest arc so far, by more than the rounding of its
//! end points against its circle (10⁻¹² of the radius and 10⁻¹² mm, some
//! thousand times that rounding), cannot change the minimum. The result is
//! therefore [`Arc::distance`]'s minimum to the last bit (the property
//! tests hold the two equal).

use std::f64::consts::TAU;

use crate::{Arc, Curve};

/// Samples per arc and per curve piece of [`deviation`].
pub const CHECK_SAMPLES: usize = 500;

/// The distance from `q` to `p`, as [`Arc::distance`] takes it.
fn dist(p: (f64, f64), q: (f64, f64)) -> f64 {
    ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt()
}

/// An arc's circle for many distances: the centre, the radius, the polar
/// angle of the start about the centre, the sense (±1) and the sweep.
#[derive(Clone, Copy)]
struct Circle {
    centre: (f64, f64),
    r: f64,
    a0: f64,
    sense: f64,
    sweep: f64,
}

/// An arc with its constants for many distances.
struct Near {
    arc: Arc,
    end: (f64, f64),
    sin_a: f64,
    cos_a: f64,
    /// `None` for a line.
    circle: Option<Circle>,
}

impl Near {
    fn of(arc: &Arc) -> Near {
        let circle = arc.circle().map(|(centre, r)| {
            let a0 = (arc.start.1 - centre.1).atan2(arc.start.0 - centre.0);
            Circle {
                centre,
                r,
                a0,
                sense: arc.curvature.signum(),
                sweep: arc.curvature.abs() * arc.length,
            }
        });
        Near {
            arc: *arc,
            end: arc.end(),
            sin_a: arc.start_angle.sin(),
            cos_a: arc.start_angle.cos(),
            circle,
        }
    }

    /// At most the distance from `q`, and how much rounding that bound may
    /// carry against the exact distance's end points.
    fn bound(&self, q: (f64, f64)) -> (f64, f64) {
        match self.circle {
            None => (self.distance(q), 0.0),
            Some(c) => ((dist(c.centre, q) - c.r).abs(), 1e-12 * (1.0 + c.r)),
        }
    }

    /// [`Arc::distance`], to the last bit.
    fn distance(&self, q: (f64, f64)) -> f64 {
        let a = &self.arc;
        match self.circle {
            None => {
                let (c, s) = (self.cos_a, self.sin_a);
                let u = ((q.0 - a.start.0) * c + (q.1 - a.start.1) * s).clamp(0.0, a.length);
                dist((a.start.0 + u * c, a.start.1 + u * s), q)
            }
            Some(c) => {
                let aq = (q.1 - c.centre.1).atan2(q.0 - c.centre.0);
                let rel = (c.sense * (aq - c.a0)).rem_euclid(TAU);
                if rel <= c.sweep {
                    (dist(c.centre, q) - c.r).abs()
                } else {
                    dist(a.start, q).min(dist(self.end, q))
                }
            }
        }
    }
}

/// The distance from `q` to the nearest of `arcs`: the arc nearest by its
/// bound first, then the others their bounds do not rule out.
fn nearest(arcs: &[Near], q: (f64, f64)) -> f64 {
    let Some(first) =
        (0..arcs.len()).min_by(|&a, &b| arcs[a].bound(q).0.total_cmp(&arcs[b].bound(q).0))
    else {
        return f64::INFINITY;
    };
    let mut best = arcs[first].distance(q);
    for (i, a) in arcs.iter().enumerate() {
        if i == first {
            continue;
        }
        let (lb, rounding) = a.bound(q);
        if lb - rounding > best {
            continue;
        }
        best = best.min(a.distance(q));
    }
    best
}

/// The largest distance between `arcs` and `curve`, both ways: `samples`
/// points along each arc against the curve, and `samples`·n points of the
/// curve against the nearest arc; and the end points' gaps. Independent of
/// the fit's own sampling.
pub fn deviation(curve: &dyn Curve, arcs: &[Arc], samples: usize) -> f64 {
    let (t0, t1) = curve.domain();
    let near: Vec<Near> = arcs.iter().map(Near::of).collect();
    let mut worst: f64 = 0.0;
    for a in &near {
        for i in 0..=samples {
            let s = a.arc.length * i as f64 / samples as f64;
            let q = a.arc.point_with(a.sin_a, a.cos_a, s);
            worst = worst.max(curve.distance(q));
        }
    }
    let n = samples * arcs.len().max(1);
    for i in 0..=n {
        let t = t0 + (t1 - t0) * i as f64 / n as f64;
        let q = curve.point(t);
        worst = worst.max(nearest(&near, q) * curve.scale_at(t));
    }
    worst
}
