//! The generated tooth space against published geometry and against a
//! brute-force simulation of the rack cutting the gear.

use gearcam_arcfit::Curve;
use gearcam_wire::gear::RackGear;

fn gear(m: f64, z: u32, x: f64, rho: f64) -> RackGear {
    RackGear {
        module_mm: m,
        teeth: z,
        pressure_angle_deg: 20.0,
        profile_shift: x,
        addendum_coef: 1.0,
        clearance_coef: 0.25,
        tip_radius_coef: rho,
    }
}

/// ISO 21771 values from the MESYS online calculator: mn 1,
/// αn 20°, z 20, x 0, ha* 1, tool addendum 1.25 → d 20, db 18.7939, da 22,
/// df 17.5 (diameters).
#[test]
fn the_radii_are_the_published_ones() {
    let f = gear(1.0, 20, 0.0, 0.38).figures();
    assert!((2.0 * f.pitch_radius_mm - 20.0).abs() < 1e-12);
    assert!((2.0 * f.base_radius_mm - 18.7939).abs() < 5e-5);
    assert!((2.0 * f.tip_radius_mm - 22.0).abs() < 1e-12);
    assert!((2.0 * f.root_radius_mm - 17.5).abs() < 1e-12);
}

/// With a sharp rack corner the involute is generated down to the radius
/// the corner reaches along the line of action, √(rb² + (r·sin α −
/// (ha* + c* − x)·m / sin α)²) (the generation-limit formula), and the
/// fillet ends exactly there.
#[test]
fn a_sharp_corner_ends_the_involute_at_the_generation_limit() {
    for (m, z, x) in [(2.0, 20, 0.0), (3.0, 25, 0.3), (1.5, 40, -0.2)] {
        let g = gear(m, z, x, 0.0);
        let f = g.figures();
        let a = 20f64.to_radians();
        let r = f.pitch_radius_mm;
        let limit =
            (f.base_radius_mm.powi(2) + (r * a.sin() - (1.25 - x) * m / a.sin()).powi(2)).sqrt();
        assert!(
            (f.form_radius_mm - limit).abs() < 1e-9,
            "{m} {z} {x}: {} vs {limit}",
            f.form_radius_mm
        );
    }
}

/// The fillet ends on the involute, without a corner: the fillet's last
/// point is the flank's first (the flank placed by the tooth space's width
/// at the pitch circle, independently of the rack's motion), and their
/// tangents agree.
#[test]
fn the_fillet_joins_the_involute_without_a_corner() {
    for (m, z, x, rho) in [
        (2.0, 20, 0.0, 0.38),
        (4.0, 17, 0.5, 0.25),
        (1.0, 60, -0.3, 0.3),
    ] {
        let g = gear(m, z, x, rho);
        let (fillet, flank) = (g.fillet(), g.flank());
        let (_, t1) = fillet.domain();
        let (s0, _) = flank.domain();
        let (p, q) = (fillet.point(t1), flank.point(s0));
        let gap = ((p.0 - q.0).powi(2) + (p.1 - q.1).powi(2)).sqrt();
        assert!(gap < 1e-9, "{m} {z} {x}: {gap} mm");
        let turn =
            (fillet.tangent_angle(t1) - flank.tangent_angle(s0)).rem_euclid(std::f64::consts::TAU);
        assert!(
            !(1e-9..=std::f64::consts::TAU - 1e-9).contains(&turn),
            "{m} {z} {x}: corner {turn}"
        );
    }
}

/// The rack cutting the gear, simulated: along a ray from the gear's
/// centre the space reaches as deep as the deepest entry of the rack tooth
/// over every rolling position. The fillet and the flank lie on that
/// boundary within 0.1 µm.
#[test]
fn the_outline_is_the_boundary_of_the_racks_swept_positions() {
    // Without undercut, and two undercut pinions (z 8 and z 11 with a
    // negative shift): there the fillet cuts into the involute and the
    // flank starts where they cross.
    for (m, z, x) in [(2.0, 20, 0.2), (1.0, 8, 0.0), (3.0, 11, -0.2)] {
        let g = gear(m, z, x, 0.38);
        assert_eq!(g.undercut(), z < 17, "{z}");
        let worst = swept_boundary_gap(&g, m, x);
        assert!(worst < 1e-4, "z {z}: {worst} mm from the simulated cut");
    }
}

/// The largest gap between 26 points of fillet and flank and the boundary
/// of the rack's swept positions.
fn swept_boundary_gap(g: &RackGear, m: f64, x: f64) -> f64 {
    let f = g.figures();
    let a = 20f64.to_radians();
    let r = f.pitch_radius_mm;
    let k = std::f64::consts::PI * m / 4.0 - x * m * a.tan();
    let rho = 0.38 * m;
    let v_tip = (1.25 - x) * m;
    let (v_c, u_c) = (v_tip - rho, k - (v_tip - rho) * a.tan() - rho / a.cos());
    // Inside the rack tooth (rack coordinates u, v towards the gear's centre).
    let inside = |u: f64, v: f64| {
        let u = u.abs();
        if v > v_tip || u > k - v * a.tan() {
            return false;
        }
        !(v > v_c && u > u_c) || (u - u_c).powi(2) + (v - v_c).powi(2) <= rho * rho
    };
    // Whether any rolling position of the rack covers q (a scan of 6,000
    // positions: between two the rack moves a few µm, whose scallop is far
    // below 0.01 µm).
    let covered = |q: (f64, f64)| {
        let n = 6000;
        (0..=n).any(|i| {
            let phi = -1.2 + 2.4 * f64::from(i) / f64::from(n);
            let (sn, cs) = phi.sin_cos();
            let (fx, fy) = (cs * q.0 + sn * q.1, -sn * q.0 + cs * q.1);
            inside(fx - r * phi, r - fy)
        })
    };
    // Along the curve's normal through p, the swept region's boundary lies
    // between −h (covered) and +h (not), or the other way round: bisect.
    let h = 0.02 * m;
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for curve in [&g.fillet() as &dyn Curve, &g.flank()] {
        let (t0, t1) = curve.domain();
        for i in 0..=12 {
            let t = t0 + (t1 - t0) * f64::from(i) / 12.0;
            let (p, a) = (curve.point(t), curve.tangent_angle(t));
            let at = |s: f64| (p.0 - s * a.sin(), p.1 + s * a.cos());
            let (lo_in, hi_in) = (covered(at(-h)), covered(at(h)));
            assert_ne!(lo_in, hi_in, "z {}: no boundary near point {i}", g.teeth);
            let (mut lo, mut hi) = (-h, h);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if covered(at(mid)) == lo_in {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            worst = worst.max((0.5 * (lo + hi)).abs());
            checked += 1;
        }
    }
    assert_eq!(checked, 26);
    worst
}

/// The fillet's distance (a scan and Newton's method) is the distance of
/// points set off along the fillet's normal, and never below a dense scan's.
#[test]
fn the_fillet_distance_is_the_normal_offset() {
    let g = gear(2.0, 20, 0.0, 0.38);
    let fillet = g.fillet();
    let (t0, t1) = fillet.domain();
    for i in 1..20 {
        let t = t0 + (t1 - t0) * f64::from(i) / 20.0;
        let (p, a) = (fillet.point(t), fillet.tangent_angle(t));
        let off = 0.003 * (f64::from(i) - 10.0) / 10.0;
        let q = (p.0 - off * a.sin(), p.1 + off * a.cos());
        let d = fillet.distance(q);
        assert!((d - off.abs()).abs() < 1e-8, "{i}: {d} vs {off}");
        let scan = (0..=20_000)
            .map(|k| {
                let s = fillet.point(t0 + (t1 - t0) * f64::from(k) / 20_000.0);
                ((s.0 - q.0).powi(2) + (s.1 - q.1).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(d <= scan + 1e-12, "{i}: {d} above the scan's {scan}");
    }
}
