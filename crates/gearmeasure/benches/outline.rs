//! `outline::measure` on two design gears sampled at n = 16 384 per section
//! (the density docs/measurement.md recommends for 0.1 µm): a spur gear in
//! one section and a helical gear in 21 sections. Figures on a shared
//! machine are upper bounds.
//! `cargo bench -p gearcam-gearmeasure --bench outline`

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_gearmeasure::helix::Hand;
use gearcam_gearmeasure::outline::{measure, GearSpec, PolarSections};
use std::f64::consts::{PI, TAU};

/// The design gear of `spec` as polar sections: involute flanks ψb − inv α
/// either side of each tooth's middle, tip and root circles, the teeth
/// turned by h·z·tan β / r.
fn outline(spec: &GearSpec, z_mm: &[f64], n: usize) -> PolarSections {
    let (mn, an, beta) = (
        spec.normal_module_mm,
        spec.normal_pressure_angle_deg.to_radians(),
        spec.helix_deg.to_radians(),
    );
    let z = f64::from(spec.teeth);
    let r = z * mn / beta.cos() / 2.0;
    let at = (an.tan() / beta.cos()).atan();
    let rb = r * at.cos();
    let psi_b = mn * PI / 2.0 / beta.cos() / (2.0 * r) + (at.tan() - at);
    let h = match spec.hand {
        Some(Hand::Right) => 1.0,
        Some(Hand::Left) => -1.0,
        None => 0.0,
    };
    let (ra, rf) = (spec.tip_diameter_mm / 2.0, spec.root_diameter_mm / 2.0);
    let flank = |rho: f64| {
        let l = (rho * rho - rb * rb).sqrt() / rb;
        psi_b - (l - l.atan())
    };
    let radius = |theta: f64, height: f64| {
        let pitch = TAU / z;
        let t = theta - h * beta.tan() / r * height;
        let delta = (t - pitch * (t / pitch).round()).abs();
        let low = rb.max(rf);
        if delta <= flank(ra) {
            return ra;
        }
        if delta > flank(low) {
            return rf;
        }
        let (mut lo, mut hi) = (low, ra);
        for _ in 0..60 {
            let m = (lo + hi) / 2.0;
            if flank(m) >= delta {
                lo = m;
            } else {
                hi = m;
            }
        }
        (lo + hi) / 2.0
    };
    PolarSections {
        z_mm: z_mm.to_vec(),
        r_mm: z_mm
            .iter()
            .map(|&hh| {
                (0..n)
                    .map(|i| radius(TAU * i as f64 / n as f64, hh))
                    .collect()
            })
            .collect(),
    }
}

fn bench(c: &mut Criterion) {
    let n = 16384;
    let spur = GearSpec::standard(24, 3.0, 0.0, None, 20.0);
    let spur_sections = outline(&spur, &[10.0], n);
    let helical = GearSpec::standard(31, 2.5, 15.0, Some(Hand::Right), 20.0);
    let faces: Vec<f64> = (0..=20).map(f64::from).collect();
    let helical_sections = outline(&helical, &faces, n);
    // Both must measure (a broken outline would time an early error).
    measure(&spur_sections, &spur).expect("spur measures");
    measure(&helical_sections, &helical).expect("helical measures");
    let mut g = c.benchmark_group("outline_measure");
    g.sample_size(10);
    g.bench_function("spur z24 1 section n16384", |b| {
        b.iter(|| measure(&spur_sections, &spur).unwrap())
    });
    g.bench_function("helical z31 21 sections n16384", |b| {
        b.iter(|| measure(&helical_sections, &helical).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
