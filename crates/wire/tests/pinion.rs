//! The tooth space cut by a pinion-type cutter against a brute-force
//! simulation of the cutter cutting the gear: the cutter's tooth (involute
//! flanks, tip circle, rounded corners) placed at 8,000 rolling positions;
//! every fillet and flank point lies on the boundary of the swept region.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use gearcam_arcfit::Curve;
use gearcam_wire::gear::{RackGear, ToothSpace};
use gearcam_wire::pinion::PinionGear;

fn inv(a: f64) -> f64 {
    a.tan() - a
}

fn pinion(m: f64, z: u32, x: f64, z0: u32, x0: f64) -> PinionGear {
    PinionGear {
        gear: RackGear {
            module_mm: m,
            teeth: z,
            pressure_angle_deg: 20.0,
            profile_shift: x,
            addendum_coef: 1.0,
            clearance_coef: 0.25,
            tip_radius_coef: 0.2,
        },
        cutter_teeth: z0,
        cutter_shift: x0,
    }
}

/// The largest gap between 26 fillet and flank points and the boundary of
/// the swept cutter, measured along each point's normal.
fn swept_gap(p: &PinionGear) -> f64 {
    let g = &p.gear;
    let (m, a) = (g.module_mm, 20f64.to_radians());
    let (z, z0) = (f64::from(g.teeth), f64::from(p.cutter_teeth));
    // The cutting mesh, computed here on its own.
    let inv_w = inv(a) + 2.0 * a.tan() * (g.profile_shift + p.cutter_shift) / (z + z0);
    let w = (0..200).fold((0.0f64, FRAC_PI_2), |(lo, hi), _| {
        let mid = 0.5 * (lo + hi);
        if inv(mid) < inv_w {
            (mid, hi)
        } else {
            (lo, mid)
        }
    });
    let centre_distance = m * (z + z0) / 2.0 * a.cos() / (0.5 * (w.0 + w.1)).cos();
    let r0 = m * z0 / 2.0;
    let rb0 = r0 * a.cos();
    let ra0 = r0 + (1.25 + p.cutter_shift) * m;
    let rho = 0.2 * m;
    let s0 = m * (PI / 2.0 + 2.0 * p.cutter_shift * a.tan());
    let half = |r: f64| s0 / (2.0 * r0) + inv(a) - inv((rb0 / r.max(rb0)).acos());
    // The round's centre: at ra0 − ρ, ρ from the flank (found by bisection
    // on the distance to the flank sampled densely, not by the involute
    // offset rule the code uses).
    let flank_point = |r: f64| {
        let t = -FRAC_PI_2 + half(r);
        (r * t.cos(), r * t.sin())
    };
    let flank_distance = |q: (f64, f64)| {
        (0..=4000)
            .map(|i| {
                let f = flank_point(rb0 + (ra0 - rb0) * f64::from(i) / 4000.0);
                (f.0 - q.0).hypot(f.1 - q.1)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let rc = ra0 - rho;
    let (mut lo, mut hi) = (0.0, half(rc));
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let c = (rc * mid.sin(), -rc * mid.cos());
        if flank_distance(c) > rho {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let gamma = 0.5 * (lo + hi);
    let centre = (rc * gamma.sin(), -rc * gamma.cos());
    // The round touches the tip circle on the centre's radius and the flank
    // at its nearest point; between the two rays from the centre the
    // cutter is the round.
    let t2 = (ra0 * gamma.sin(), -ra0 * gamma.cos());
    let t = (0..=20_000)
        .map(|i| flank_point(rb0 + (ra0 - rb0) * f64::from(i) / 20_000.0))
        .min_by(|p, q| {
            (p.0 - centre.0)
                .hypot(p.1 - centre.1)
                .total_cmp(&(q.0 - centre.0).hypot(q.1 - centre.1))
        })
        .unwrap();
    let cross = |u: (f64, f64), v: (f64, f64)| u.0 * v.1 - u.1 * v.0;
    let (v1, v2) = (
        (t2.0 - centre.0, t2.1 - centre.1),
        (t.0 - centre.0, t.1 - centre.1),
    );
    let in_sector = |q: (f64, f64)| {
        let w = (q.0 - centre.0, q.1 - centre.1);
        let s = cross(v1, v2).signum();
        cross(v1, w) * s >= 0.0 && cross(w, v2) * s >= 0.0
    };
    // Inside the cutter (all its teeth), in the cutter's frame.
    let inside = |q: (f64, f64)| {
        let r = q.0.hypot(q.1);
        if r > ra0 {
            return false;
        }
        let pitch = TAU / z0;
        let d = (q.1.atan2(q.0) + FRAC_PI_2 + pitch / 2.0).rem_euclid(pitch) - pitch / 2.0;
        let d = d.abs();
        // Below the base circle the flank runs on radially, down to the
        // cutter's root circle r0 − 1.25·m (clear of the gear's tip).
        if r > r0 - 1.25 * m && d > half(r) {
            return false;
        }
        // The point moved to the right half of the tooth about −Y.
        let c = (r * d.sin(), -r * d.cos());
        if in_sector(c) {
            return (c.0 - centre.0).hypot(c.1 - centre.1) <= rho;
        }
        true
    };
    let covered = |q: (f64, f64)| {
        let n = 8000;
        (0..=n).any(|i| {
            let phi = -1.5 + 3.0 * f64::from(i) / f64::from(n);
            let fixed = (
                phi.cos() * q.0 - phi.sin() * q.1,
                phi.sin() * q.0 + phi.cos() * q.1,
            );
            let psi = -phi * z / z0;
            let rel = (fixed.0, fixed.1 - centre_distance);
            let local = (
                (-psi).cos() * rel.0 - (-psi).sin() * rel.1,
                (-psi).sin() * rel.0 + (-psi).cos() * rel.1,
            );
            inside(local)
        })
    };
    let h = 0.02 * m;
    let mut worst: f64 = 0.0;
    let fillet = p.fillet();
    let flank = p.flank();
    for curve in [&fillet as &dyn Curve, &flank] {
        let (t0, t1) = curve.domain();
        for i in 0..=12 {
            let t = t0 + (t1 - t0) * f64::from(i) / 12.0;
            let (q, ang) = (curve.point(t), curve.tangent_angle(t));
            let at = |s: f64| (q.0 - s * ang.sin(), q.1 + s * ang.cos());
            let lo_in = covered(at(-h));
            assert_ne!(
                lo_in,
                covered(at(h)),
                "z {}: no boundary at point {i}",
                g.teeth
            );
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
        }
    }
    worst
}

/// m 2, z 20 cut by a 25-tooth cutter; a shifted pair; an undercut pinion.
#[test]
fn the_pinion_cut_space_is_the_boundary_of_the_swept_cutter() {
    for (m, z, x, z0, x0) in [
        (2.0, 20, 0.0, 25, 0.0),
        (1.5, 30, 0.3, 20, 0.1),
        (1.0, 9, 0.0, 30, 0.0),
    ] {
        let p = pinion(m, z, x, z0, x0);
        let gap = swept_gap(&p);
        eprintln!("z {z} z0 {z0}: {gap:e}");
        assert!(gap < 1e-4, "z {z} z0 {z0}: {gap} mm from the simulated cut");
        if z == 9 {
            assert!(p.undercut(), "z 9 is undercut");
        }
    }
}

/// The root radius is a′ − r_a0 (the cutting mesh's centre distance less
/// the cutter's tip radius) and the fillet's deepest point lies on it; with
/// a very large cutter the space approaches the rack's.
#[test]
fn the_root_follows_the_cutting_mesh_and_a_large_cutter_acts_as_a_rack() {
    let p = pinion(2.0, 20, 0.0, 25, 0.0);
    let f = p.figures();
    let (t0, _) = p.fillet().domain();
    let deepest = p.fillet().point(t0);
    assert!((deepest.0.hypot(deepest.1) - f.root_radius_mm).abs() < 1e-9);
    // x + x0 = 0: a′ = m(z + z0)/2, root = 45 − (25 + 2.5) = 17.5 mm.
    assert!(
        (f.root_radius_mm - 17.5).abs() < 1e-9,
        "{}",
        f.root_radius_mm
    );
    let big = pinion(2.0, 20, 0.0, 4000, 0.0);
    let rack = big.gear;
    let (fb, fr) = (big.figures(), ToothSpace::figures(&rack));
    assert!(
        (fb.form_radius_mm - fr.form_radius_mm).abs() < 2e-3,
        "{} vs {}",
        fb.form_radius_mm,
        fr.form_radius_mm
    );
}
