//! Geometry in a section's plane: a point's polar angle, its distance
//! from a line, the chord of a disc a pass sweeps.

/// A point of a section in the workpiece frame: x, y and its polar angle.
pub(super) type Point = [f64; 3];

/// The polar angle of (x, y): from `near`'s angle and the small turn
/// between them when `near` is within a tenth of a radian (atan of
/// t = cross/dot by its series to t⁹, below 10⁻¹² rad), else atan2. Two
/// pieces that share a point share its angle, so the rays they span meet
/// without a gap whatever the angle's last digits.
pub(super) fn polar_angle(x: f64, y: f64, near: Option<&Point>) -> f64 {
    if let Some(n) = near {
        let (cross, dot) = (n[0] * y - n[1] * x, n[0] * x + n[1] * y);
        if dot > 0.0 && cross.abs() < 0.1 * dot {
            let t = cross / dot;
            let t2 = t * t;
            let series = 1.0 - t2 * (1.0 / 3.0 - t2 * (0.2 - t2 * (1.0 / 7.0 - t2 * (1.0 / 9.0))));
            return n[2] + t * series;
        }
    }
    y.atan2(x)
}

/// Distance of `m` from the line through `p` and `q`.
pub(super) fn off_line(p: Point, q: Point, m: Point) -> f64 {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let v = [m[0] - p[0], m[1] - p[1]];
    if len == 0.0 {
        return (v[0] * v[0] + v[1] * v[1]).sqrt();
    }
    (v[0] * d[1] - v[1] * d[0]).abs() / len
}

/// The chord parameters s (along e1) whose hob angle atan2(t, s) lies in
/// [pa, pb], within [−S, S].
pub(super) fn s_range(t: f64, pa: f64, pb: f64, big_s: f64) -> Option<(f64, f64)> {
    let cot = |p: f64| p.cos() / p.sin();
    let (lo, hi) = if t > 0.0 {
        let (a, b) = (pa.max(1e-12), pb.min(std::f64::consts::PI - 1e-12));
        if a >= b {
            return None;
        }
        (t * cot(b), t * cot(a))
    } else if t < 0.0 {
        let (a, b) = (pa.max(-std::f64::consts::PI + 1e-12), pb.min(-1e-12));
        if a >= b {
            return None;
        }
        (t * cot(a), t * cot(b))
    } else if pa <= 0.0 && 0.0 < pb {
        (0.0, big_s)
    } else {
        return None;
    };
    let (lo, hi) = (lo.max(-big_s), hi.min(big_s));
    (lo < hi).then_some((lo, hi))
}
