//! The involute function and what is solved with it.
//!
//! The involute of a base circle of radius rb reaches the radius r at the
//! pressure angle α with cos α = rb/r; its polar angle there is
//! inv α = tan α − α, and its roll angle √(r² − rb²)/rb. Two gears meshing
//! without backlash satisfy the meshing equation
//! inv α′ = inv α + 2·tan αn·(x1 + x2)/(z1 + z2) (ISO 21771), which
//! [`working_pressure_angle`] solves.

/// The involute function inv α = tan α − α, radians.
pub fn inv(alpha: f64) -> f64 {
    alpha.tan() - alpha
}

/// The inverse of [`inv`]: the angle α in [0, π/2) with tan α − α = v, radians
/// (Newton's method from α ≈ ∛(3v), which is exact to third order for small
/// v); NaN for a negative or NaN v.
pub fn inv_inverse(v: f64) -> f64 {
    if v == 0.0 {
        return 0.0;
    }
    if v.is_nan() || v < 0.0 {
        return f64::NAN;
    }
    let mut a = (3.0 * v).cbrt().min(1.5);
    for _ in 0..50 {
        let t = a.tan();
        let step = (t - a - v) / (t * t);
        a -= step;
        if a <= 0.0 {
            a = 1e-9;
        }
        if step.abs() < 1e-15 {
            break;
        }
    }
    a
}

/// The working transverse pressure angle of a meshing pair from the sum of
/// the profile shifts: inv αwt = inv αt + 2·(x1 + x2)·tan αn / (z1 + z2),
/// radians. For spur gears αn = αt.
pub fn working_pressure_angle(alpha_n: f64, alpha_t: f64, x_sum: f64, z_sum: f64) -> f64 {
    inv_inverse(inv(alpha_t) + 2.0 * x_sum * alpha_n.tan() / z_sum)
}

/// The roll angle at which the involute of the base radius `rb` reaches the
/// radius `r` (zero inside the base circle).
pub fn roll_at(rb: f64, r: f64) -> f64 {
    (r * r - rb * rb).max(0.0).sqrt() / rb
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;
    use proptest::prelude::*;

    /// inv α by bisection on (0, π/2), where inv rises: a reference that
    /// shares nothing with Newton's method.
    fn bisect(v: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, std::f64::consts::FRAC_PI_2 - 1e-12);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if inv(mid) < v {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn inv_of_20_degrees_is_the_tabulated_value() {
        // Involute tables: inv 20° = 0.014904 (tan 20° − π/9).
        assert_abs_diff_eq!(inv(20f64.to_radians()), 0.014_904_383_867, epsilon = 1e-12);
        assert_eq!(inv_inverse(0.0), 0.0);
        assert!(inv_inverse(-1e-3).is_nan());
    }

    #[test]
    fn a_pair_without_shift_meshes_at_its_pressure_angle() {
        let a = 20f64.to_radians();
        assert_abs_diff_eq!(working_pressure_angle(a, a, 0.0, 50.0), a, epsilon = 1e-14);
        // Positive shift opens the angle.
        assert!(working_pressure_angle(a, a, 0.5, 50.0) > a);
    }

    #[test]
    fn the_roll_angle_reaches_the_radius() {
        let (rb, r) = (40.0, 45.0);
        let u = roll_at(rb, r);
        // The involute point at roll u lies at rb·√(1 + u²) from the centre.
        assert_abs_diff_eq!(rb * (1.0 + u * u).sqrt(), r, epsilon = 1e-12);
        assert_eq!(roll_at(rb, 30.0), 0.0);
    }

    proptest! {
        /// Newton's inverse agrees with bisection over the range gears use.
        /// Both solve inv(α) = v in floating point: inv = tan α − α loses
        /// about ε·tan α to the subtraction, and an error δv in v moves the
        /// root by δv / tan²α (the derivative of inv), so near α = 0 the two
        /// may differ by a few ε·tan α / tan²α however exact each is.
        #[test]
        fn the_inverse_agrees_with_bisection(alpha in 1e-4..1.4f64) {
            let v = inv(alpha);
            let newton = inv_inverse(v);
            let t = alpha.tan();
            let tol = 1e-12f64.max(8.0 * f64::EPSILON * t / (t * t));
            prop_assert!((newton - bisect(v)).abs() < tol, "{newton} vs {}", bisect(v));
            prop_assert!((newton - alpha).abs() < 1e-9);
        }
    }
}
