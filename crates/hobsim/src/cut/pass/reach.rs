//! How far along the hob a pass can reach a section.

use super::Pass;

impl Pass<'_> {
    /// The axial positions a (from the hob's middle) whose disc of radius
    /// tip can meet the disc of radius `clip_r` about the gear axis in the
    /// section `zs`, as an interval (widened by 0.1 mm), or None.
    ///
    /// A section point (x, y, z_s) lies at a = y·cos η − (z_s − Z)·sin η − Y
    /// along the hob and t = y·sin η + (z_s − Z)·cos η across it (along w),
    /// at distance √((x − X)² + t²) from the hob axis. At a given y the
    /// point within `tip` of the hob axis nearest the gear axis has
    /// x = max(X − √(tip² − t²), 0), so the y that reach the blank are where
    /// h(y) = y² + max(X − √(tip² − t²), 0)² − clip_r² ≤ 0 (h = ∞ where
    /// |t| ≥ tip). h is convex (a nonnegative convex function squared plus
    /// y²), so its minimum is found by a golden-section search and the
    /// interval's ends by bisection on either side, to well within the
    /// widening. The pose is the pass's at φ = 0; the hob moves by far less
    /// than the widening while it sweeps.
    pub(super) fn reach(&self, clip_r: f64, zs: f64) -> Option<(f64, f64)> {
        let p0 = self.pose(0.0);
        let tip = self.tip;
        let (se, ce) = (self.se, self.ce);
        let dz = zs - p0.axes.z_mm;
        let big_x = p0.axes.x_mm;
        let h = |y: f64| {
            let t = y * se + dz * ce;
            if t.abs() >= tip {
                return f64::INFINITY;
            }
            let near_x = (big_x - (tip * tip - t * t).sqrt()).max(0.0);
            y * y + near_x * near_x - clip_r * clip_r
        };
        // A point of both discs has x ≥ X − tip, so |y| ≤ √(clip_r² −
        // (X − tip)²) where X ≥ tip, and x ≤ clip_r, so the tip circle's
        // half chord √(tip² − t²) ≥ X − clip_r: |t| ≤ √(tip² − (X −
        // clip_r)²) where X ≥ clip_r. That |t| < tip: y within (±t_max −
        // dz·cos η)/sin η.
        let y_max = (clip_r * clip_r - (big_x - tip).max(0.0).powi(2)).sqrt();
        let t_max = (tip * tip - (big_x - clip_r).max(0.0).powi(2)).sqrt();
        if !(y_max > 0.0 && t_max > 0.0) {
            return None;
        }
        let (mut lo, mut hi) = (-y_max, y_max);
        if se.abs() > 1e-12 {
            let (y1, y2) = ((-t_max - dz * ce) / se, (t_max - dz * ce) / se);
            lo = lo.max(y1.min(y2));
            hi = hi.min(y1.max(y2));
        } else if (dz * ce).abs() >= t_max {
            return None;
        }
        if lo >= hi {
            return None;
        }
        let g = (5f64.sqrt() - 1.0) / 2.0;
        let (mut a, mut b) = (lo, hi);
        // The bracket narrowed to 0.03 mm, within the widening (h is flat
        // at its minimum: a pass that reaches the blank by less than that
        // error's square cuts only air within the clip margin). Each step
        // keeps one of its two inner points, at the golden ratio of the
        // narrower bracket, and its value.
        let steps =
            |ratio: f64| ((hi - lo) / 0.03).ln().div_euclid(-ratio.ln()).max(0.0) as u32 + 1;
        let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
        let (mut hc, mut hd) = (h(c), h(d));
        for _ in 0..steps(g) {
            if hc < hd {
                (b, d, hd) = (d, c, hc);
                c = b - g * (b - a);
                hc = h(c);
            } else {
                (a, c, hc) = (c, d, hd);
                d = a + g * (b - a);
                hd = h(d);
            }
        }
        let y_min = 0.5 * (a + b);
        if h(y_min) > 0.0 {
            return None;
        }
        let edge = |inside: f64, outside: f64| {
            let (mut a, mut b) = (inside, outside);
            // Halved to below 0.03 mm.
            for _ in 0..steps(0.5) {
                let m = 0.5 * (a + b);
                if h(m) <= 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            b
        };
        let (y_lo, y_hi) = (edge(y_min, lo), edge(y_min, hi));
        let a = |y: f64| y * ce - dz * se - p0.axes.y_mm;
        let (a0, a1) = (a(y_lo), a(y_hi));
        Some((a0.min(a1) - 0.1, a0.max(a1) + 0.1))
    }
}
