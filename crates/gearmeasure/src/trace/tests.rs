//! Traces with known answers (a pure slope, a pure form wave, their sum),
//! random traces against a brute-force search for the enclosing lines, and
//! the invariances of the definitions.

use super::*;
use approx::assert_relative_eq;
use proptest::prelude::*;

fn grid(n: usize, x0: f64, x1: f64) -> Vec<f64> {
    (0..n)
        .map(|i| x0 + (x1 - x0) * i as f64 / (n - 1) as f64)
        .collect()
}

/// A wave symmetric about the middle of [0, L] (whole periods of a
/// cosine): it has no least-squares slope, so it is pure form.
fn wave(x: f64, len: f64, amp: f64, periods: f64) -> f64 {
    amp * (2.0 * std::f64::consts::PI * periods * x / len).cos()
}

#[test]
fn a_pure_slope_is_all_slope_and_no_form() {
    let x = grid(201, 0.0, 10.0);
    let e: Vec<f64> = x.iter().map(|x| 0.5 * x - 2.0).collect();
    let d = evaluate(&x, &e, 0.0, 10.0).unwrap();
    assert_relative_eq!(d.total_um, 5.0, epsilon = 1e-9);
    assert_relative_eq!(d.slope_um, 5.0, epsilon = 1e-9);
    assert!(d.form_um.abs() < 1e-9, "form {}", d.form_um);
    assert_relative_eq!(d.mean_at_start_um, -2.0, epsilon = 1e-9);
    // Read from the other end, the slope changes sign.
    let back = evaluate(&x, &e, 10.0, 0.0).unwrap();
    assert_relative_eq!(back.slope_um, -5.0, epsilon = 1e-9);
}

#[test]
fn a_pure_form_wave_is_all_form_and_no_slope() {
    let x = grid(401, 0.0, 12.0);
    let e: Vec<f64> = x.iter().map(|&x| wave(x, 12.0, 1.5, 3.0)).collect();
    let d = evaluate(&x, &e, 0.0, 12.0).unwrap();
    assert!(d.slope_um.abs() < 1e-9, "slope {}", d.slope_um);
    assert_relative_eq!(d.form_um, 3.0, epsilon = 1e-9);
    assert_relative_eq!(d.total_um, 3.0, epsilon = 1e-9);
}

#[test]
fn slope_plus_wave_separates_into_its_parts() {
    let x = grid(401, 0.0, 12.0);
    let e: Vec<f64> = x
        .iter()
        .map(|&x| -0.25 * x + wave(x, 12.0, 1.0, 4.0))
        .collect();
    let d = evaluate(&x, &e, 0.0, 12.0).unwrap();
    assert_relative_eq!(d.slope_um, -3.0, epsilon = 1e-9);
    assert_relative_eq!(d.form_um, 2.0, epsilon = 1e-9);
    // The total is the sampled range of the sum, found here by brute force.
    let (lo, hi) = e
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    assert_relative_eq!(d.total_um, hi - lo, epsilon = 1e-12);
    assert!(d.total_um > 3.0 && d.total_um < 5.0, "{}", d.total_um);
}

#[test]
fn samples_outside_the_range_are_left_out() {
    let x = grid(101, -2.0, 12.0);
    // A spike of 50 µm outside [0, 10] changes nothing.
    let e: Vec<f64> = x
        .iter()
        .map(|&x| if x < 0.0 { 50.0 } else { 0.1 * x })
        .collect();
    let d = evaluate(&x, &e, 0.0, 10.0).unwrap();
    assert_relative_eq!(d.slope_um, 1.0, epsilon = 1e-9);
    assert!(d.samples < x.len());
    assert!(evaluate(&x, &e, 20.0, 30.0).is_err());
    assert!(evaluate(&x[..3], &e[..2], 0.0, 10.0).is_err());
    assert!(evaluate(&[1.0, 1.0, 1.0], &[0.0, 1.0, 2.0], 0.0, 2.0).is_err());
    assert!(evaluate(&x, &e, f64::NAN, 10.0).is_err());
}

/// The least-squares slope found by golden-section search on the sum of
/// squares (for each slope the best offset is the mean residual): no
/// normal equations.
fn brute_slope(x: &[f64], e: &[f64]) -> f64 {
    let sse = |s: f64| {
        let a = x.iter().zip(e).map(|(x, e)| e - s * x).sum::<f64>() / x.len() as f64;
        x.iter()
            .zip(e)
            .map(|(x, e)| (e - a - s * x).powi(2))
            .sum::<f64>()
    };
    let (mut lo, mut hi) = (-100.0_f64, 100.0_f64);
    let g = (5.0_f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (m1, m2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if sse(m1) < sse(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    (lo + hi) / 2.0
}

/// The narrowest band of two lines of slope `s` enclosing every point,
/// searched over the pairs of points the lines can rest on: a line of
/// slope s through point i is the upper line when no point is above it.
fn brute_band(x: &[f64], e: &[f64], s: f64) -> f64 {
    let off = |i: usize| e[i] - s * x[i];
    let n = x.len();
    let upper = (0..n)
        .filter(|&i| (0..n).all(|j| off(j) <= off(i)))
        .map(off)
        .next()
        .unwrap();
    let lower = (0..n)
        .filter(|&i| (0..n).all(|j| off(j) >= off(i)))
        .map(off)
        .next()
        .unwrap();
    upper - lower
}

proptest! {
    #[test]
    fn random_traces_match_the_brute_force_enclosing_lines(
        e in prop::collection::vec(-5.0f64..5.0, 5..60),
        x0 in -20.0f64..20.0,
        len in 0.5f64..30.0,
    ) {
        let x = grid(e.len(), x0, x0 + len);
        let d = evaluate(&x, &e, x0, x0 + len).unwrap();
        let s = brute_slope(&x, &e);
        prop_assert!((d.slope_um - s * len).abs() < 1e-6 * (1.0 + d.slope_um.abs()), "{} vs {}", d.slope_um, s * len);
        prop_assert!((d.form_um - brute_band(&x, &e, s)).abs() < 1e-6, "form {} vs {}", d.form_um, brute_band(&x, &e, s));
        prop_assert!((d.total_um - brute_band(&x, &e, 0.0)).abs() < 1e-12);
    }

    #[test]
    fn the_definitions_keep_their_invariances(
        e in prop::collection::vec(-5.0f64..5.0, 5..40),
        offset in -10.0f64..10.0,
        tilt in -2.0f64..2.0,
        scale in -3.0f64..3.0,
    ) {
        let x = grid(e.len(), 1.0, 9.0);
        let d = evaluate(&x, &e, 1.0, 9.0).unwrap();
        // A constant moves nothing; a tilt moves the slope only.
        let moved: Vec<f64> = x.iter().zip(&e).map(|(x, e)| e + offset + tilt * x).collect();
        let m = evaluate(&x, &moved, 1.0, 9.0).unwrap();
        prop_assert!((m.slope_um - d.slope_um - 8.0 * tilt).abs() < 1e-9);
        prop_assert!((m.form_um - d.form_um).abs() < 1e-9);
        // Scaling the deviations scales all three.
        let scaled: Vec<f64> = e.iter().map(|e| e * scale).collect();
        let k = evaluate(&x, &scaled, 1.0, 9.0).unwrap();
        prop_assert!((k.total_um - d.total_um * scale.abs()).abs() < 1e-9);
        prop_assert!((k.form_um - d.form_um * scale.abs()).abs() < 1e-9);
        prop_assert!((k.slope_um - d.slope_um * scale).abs() < 1e-9);
        prop_assert!(d.total_um >= 0.0 && d.form_um >= 0.0);
    }
}
