//! Pitch deviations against constructed gears with known answers and
//! against a brute-force search over every sector.

use super::*;
use approx::assert_relative_eq;
use proptest::prelude::*;

#[test]
fn one_displaced_tooth_gives_two_pitches_of_opposite_sign() {
    // Tooth 3 of 10 is 4 µm late: pitch 3 is +4, pitch 4 is −4.
    let mut p = vec![0.0; 10];
    p[3] = 4.0;
    let d = evaluate_pitch(&p).unwrap();
    assert_eq!(d.single_um[3], 4.0);
    assert_eq!(d.single_um[4], -4.0);
    assert_eq!(d.single_max_um, 4.0);
    assert_eq!(d.cumulative_total_um, 4.0);
    assert_relative_eq!(d.single_um.iter().sum::<f64>(), 0.0);
}

#[test]
fn an_eccentric_gear_has_a_sine_of_cumulative_pitch() {
    // An eccentricity e moves tooth i by e·sin(2πi/z) along the circle: Fp
    // is 2e, fp the largest step of the sine, 2e·sin(π/z) at most.
    let (z, e) = (36, 10.0);
    let p: Vec<f64> = (0..z)
        .map(|i| e * (2.0 * std::f64::consts::PI * i as f64 / z as f64).sin())
        .collect();
    let d = evaluate_pitch(&p).unwrap();
    assert_relative_eq!(d.cumulative_total_um, 2.0 * e, epsilon = 1e-9);
    let bound = 2.0 * e * (std::f64::consts::PI / z as f64).sin();
    assert!(d.single_max_um <= bound + 1e-9 && d.single_max_um > 0.99 * bound);
}

#[test]
fn angles_and_pitches_give_the_same_positions() {
    // z = 4 on a 100 mm circle: tooth 2 is 0.001° late (0.8727 µm).
    let angles = [10.0, 100.0, 190.001, 280.0];
    let p = positions_from_angles(&angles, 100.0);
    assert_relative_eq!(p[2], 0.001_f64.to_radians() * 50_000.0, epsilon = 1e-9);
    assert_relative_eq!(p[1], 0.0, epsilon = 1e-9);
    // Given modulo 360°, the same.
    let wrapped = positions_from_angles(&[370.0, 100.0, 190.001, -80.0], 100.0);
    for (a, b) in p.iter().zip(&wrapped) {
        assert_relative_eq!(a, b, epsilon = 1e-6);
    }
    let d = evaluate_pitch(&p).unwrap();
    let back = positions_from_pitches(&d.single_um);
    for (a, b) in p.iter().zip(&back) {
        assert_relative_eq!(a, b, epsilon = 1e-9);
    }
}

#[test]
fn runout_is_the_range_of_the_ball_positions() {
    assert_eq!(runout_um(&[3.0, -1.0, 2.5, 0.0]).unwrap(), 4.0);
    assert!(runout_um(&[1.0, 2.0]).is_err());
    assert!(runout_um(&[1.0, f64::NAN, 2.0]).is_err());
    assert!(evaluate_pitch(&[1.0, 2.0]).is_err());
    assert!(evaluate_flanks(&[0.0; 5], &[0.0; 6]).is_err());
}

proptest! {
    #[test]
    fn fp_and_fp_total_match_brute_force_over_every_sector(
        p in prop::collection::vec(-20.0f64..20.0, 3..80),
    ) {
        let d = evaluate_pitch(&p).unwrap();
        let z = p.len();
        // Every sector of k consecutive pitches starting at tooth i: the
        // sum of its fpi, by adding them up.
        let mut worst_sector = 0.0_f64;
        let mut worst_single = 0.0_f64;
        for i in 0..z {
            let mut sum = 0.0;
            for k in 1..z {
                let j = (i + k) % z;
                let prev = (j + z - 1) % z;
                let fpi = p[j] - p[prev];
                if k == 1 {
                    worst_single = worst_single.max(fpi.abs());
                }
                sum += fpi;
                worst_sector = worst_sector.max(sum.abs());
            }
        }
        prop_assert!((d.cumulative_total_um - worst_sector).abs() < 1e-9);
        prop_assert!((d.single_max_um - worst_single).abs() < 1e-12);
        prop_assert!(d.single_um.iter().sum::<f64>().abs() < 1e-9);
        // A whole-gear offset changes nothing.
        let moved: Vec<f64> = p.iter().map(|x| x + 7.5).collect();
        let m = evaluate_pitch(&moved).unwrap();
        prop_assert!((m.cumulative_total_um - d.cumulative_total_um).abs() < 1e-9);
    }
}
