//! Rotations and mirrors of the plane.
//!
//! A rotation by `a` (radians, counter-clockwise) maps (x, y) to
//! (x·cos a − y·sin a, x·sin a + y·cos a); the mirror about the line through
//! the origin at angle θ maps (x, y) to (x·cos 2θ + y·sin 2θ, x·sin 2θ − y·cos 2θ)
//! (rotate by −θ, flip y, rotate back by θ). Each is written once here, for
//! every [`Planar`] point, and computed in this order so that a result is the
//! same to the last bit wherever it is used.

use nalgebra::Point2;

/// A point of the plane: its coordinates out, and a point of the same kind
/// from coordinates.
pub trait Planar: Copy {
    /// The point's (x, y).
    fn xy(self) -> (f64, f64);
    /// The point at (x, y).
    fn at(x: f64, y: f64) -> Self;
}

impl Planar for (f64, f64) {
    fn xy(self) -> (f64, f64) {
        self
    }
    fn at(x: f64, y: f64) -> Self {
        (x, y)
    }
}

impl Planar for Point2<f64> {
    fn xy(self) -> (f64, f64) {
        (self.x, self.y)
    }
    fn at(x: f64, y: f64) -> Self {
        Point2::new(x, y)
    }
}

/// `p` turned by `angle` radians (counter-clockwise) about the origin.
pub fn rotate<P: Planar>(p: P, angle: f64) -> P {
    let (x, y) = p.xy();
    let (s, c) = angle.sin_cos();
    P::at(c * x - s * y, s * x + c * y)
}

/// `p` turned by `angle` radians (counter-clockwise) about `centre`.
pub fn rotate_about<P: Planar>(p: P, centre: P, angle: f64) -> P {
    let ((x, y), (cx, cy)) = (p.xy(), centre.xy());
    let (s, c) = angle.sin_cos();
    let (dx, dy) = (x - cx, y - cy);
    P::at(cx + c * dx - s * dy, cy + s * dx + c * dy)
}

/// The mirror image of `p` about the line through the origin at `angle`
/// radians from +x.
pub fn mirror<P: Planar>(p: P, angle: f64) -> P {
    let (x, y) = p.xy();
    let (s, c) = (2.0 * angle).sin_cos();
    P::at(c * x + s * y, s * x - c * y)
}

/// The vector from `b` to `a`.
pub fn sub<P: Planar>(a: P, b: P) -> (f64, f64) {
    let ((ax, ay), (bx, by)) = (a.xy(), b.xy());
    (ax - bx, ay - by)
}

/// The length of the vector `v`.
pub fn length(v: (f64, f64)) -> f64 {
    v.0.hypot(v.1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;
    use nalgebra::{Rotation2, Vector2};
    use proptest::prelude::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn a_quarter_turn_takes_x_to_y() {
        let (x, y) = rotate((1.0, 0.0), FRAC_PI_2);
        assert_abs_diff_eq!(x, 0.0, epsilon = 1e-15);
        assert_abs_diff_eq!(y, 1.0, epsilon = 1e-15);
        let p = rotate_about(Point2::new(2.0, 1.0), Point2::new(1.0, 1.0), FRAC_PI_2);
        assert_abs_diff_eq!(p.x, 1.0, epsilon = 1e-15);
        assert_abs_diff_eq!(p.y, 2.0, epsilon = 1e-15);
    }

    #[test]
    fn the_mirror_about_the_diagonal_swaps_the_coordinates() {
        let (x, y) = mirror((3.0, 1.0), std::f64::consts::FRAC_PI_4);
        assert_abs_diff_eq!(x, 1.0, epsilon = 1e-14);
        assert_abs_diff_eq!(y, 3.0, epsilon = 1e-14);
        let (x, y) = mirror((3.0, 1.0), 0.0);
        assert_eq!((x, y), (3.0, -1.0));
    }

    proptest! {
        /// The rotation agrees with nalgebra's rotation matrix (an
        /// independent implementation), keeps lengths and is undone by the
        /// opposite angle; a mirror keeps lengths, fixes its line and is its
        /// own inverse.
        #[test]
        fn rotations_and_mirrors_are_isometries(
            x in -1e3..1e3f64, y in -1e3..1e3f64, a in -7.0..7.0f64,
        ) {
            let p = (x, y);
            let q = rotate(p, a);
            let m = Rotation2::new(a) * Vector2::new(x, y);
            prop_assert!((q.0 - m.x).abs() < 1e-9 && (q.1 - m.y).abs() < 1e-9);
            prop_assert!((length(q) - length(p)).abs() < 1e-9);
            let back = rotate(q, -a);
            prop_assert!(length(sub(back, p)) < 1e-9);
            let r = mirror(p, a);
            prop_assert!((length(r) - length(p)).abs() < 1e-9);
            prop_assert!(length(sub(mirror(r, a), p)) < 1e-9);
            let on_line = (a.cos() * 5.0, a.sin() * 5.0);
            prop_assert!(length(sub(mirror(on_line, a), on_line)) < 1e-9);
            let c = (y * 0.5, -x);
            let about = rotate_about(p, c, a);
            let moved = rotate(sub(p, c), a);
            prop_assert!(length(sub(about, (c.0 + moved.0, c.1 + moved.1))) < 1e-9);
        }
    }
}
