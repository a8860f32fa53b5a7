//! A 40-tooth die (m 2, α 20°, x 0) at ε = 1 µm on the flank and 5 µm on
//! the fillet, as the services make it: geometry and arc fit, the wire's
//! offset, the program and its replay with the certificate, for each form;
//! the pieces of each form's job on their own; then each whole job beside
//! its target (the median of 30 runs).
//! `cargo bench -p gearcam-wire --bench die`
#![allow(clippy::disallowed_methods)] // a bench reads the clock

#[path = "../tests/common/mod.rs"]
mod common;

use std::time::{Duration, Instant};

use common::molybdenum;
use criterion::{criterion_group, Criterion};
use gearcam_proto::{DiePart, DieSpec, WireProgram};
use gearcam_wire::die::cut;
use gearcam_wire::offset::offset;
use gearcam_wire::programs::{certify, layout, make, write};

fn die() -> DieSpec {
    DieSpec::new(DiePart::Die, 2.0, 40, 20.0, "Cr12MoV")
}

const FORMS: [WireProgram; 3] = [
    WireProgram::ThreeB,
    WireProgram::FourB,
    WireProgram::IsoWire,
];

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("40-tooth die at 1 um");
    g.sample_size(20);
    let d = die();
    let tol = (d.flank_tolerance_um / 1e3, d.fillet_tolerance_um / 1e3);
    for form in FORMS {
        let p = molybdenum(form, false);
        let made = make(&d, &p, &[], 1).unwrap();
        eprintln!(
            "{}: fit at {} of the tolerances, {} arcs per flank, {} per fillet, {} blocks, {} bytes, flank {:.3} um, fillet {:.3} um",
            form.as_str(),
            made.fit_share,
            made.cut.outline.arcs_per_flank,
            made.cut.outline.arcs_per_fillet,
            made.certificate.blocks,
            made.certificate.bytes,
            made.certificate.measure.flank_mm * 1e3,
            made.certificate.measure.fillet_mm * 1e3
        );
        g.bench_function(format!("whole job, {}", form.as_str()), |b| {
            b.iter(|| make(&d, &p, &[], 1).unwrap().certificate.blocks)
        });
        // The pieces of the job, at the share of the tolerances it fits at.
        let mut aimed = d.clone();
        aimed.flank_tolerance_um *= made.fit_share;
        aimed.fillet_tolerance_um *= made.fit_share;
        let k = made.cut.clone();
        let l = made.layout;
        g.bench_function(
            format!("{}: geometry + arc fit + offset", form.as_str()),
            |b| b.iter(|| cut(&aimed, &p).unwrap().path.len()),
        );
        g.bench_function(format!("{}: program", form.as_str()), |b| {
            b.iter(|| write(&k, form, &l, &[], 1).text.len())
        });
        let text = made.written.text.clone();
        g.bench_function(format!("{}: certificate", form.as_str()), |b| {
            b.iter(|| certify(&text, form, &k, &l, tol).unwrap().blocks)
        });
    }
    let p = molybdenum(WireProgram::ThreeB, false);
    let k = cut(&d, &p).unwrap();
    g.bench_function("offset of the whole outline", |b| {
        b.iter(|| offset(&k.contour, k.side, k.offset_mm).unwrap().len())
    });
    let l = layout(&k, DiePart::Die, false);
    g.bench_function("3B program at the full tolerances", |b| {
        b.iter(|| write(&k, WireProgram::ThreeB, &l, &[], 1).text.len())
    });
    g.finish();
}

/// The median time of `runs` runs of `f`, after one to warm up.
fn median(runs: usize, mut f: impl FnMut() -> u32) -> Duration {
    assert!(f() > 0);
    let mut times: Vec<Duration> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            assert!(f() > 0);
            t.elapsed()
        })
        .collect();
    times.sort();
    times[runs / 2]
}

/// Each whole job beside its target.
fn figures() {
    let d = die();
    println!("\nThe 40-tooth die at 1 um, whole job (make), median of 30 runs:");
    for form in FORMS {
        let p = molybdenum(form, false);
        let t = median(30, || make(&d, &p, &[], 1).unwrap().certificate.blocks);
        println!(
            "40-tooth die, {}: {:.1} ms (target <= 5 ms)",
            form.as_str(),
            t.as_secs_f64() * 1e3
        );
    }
}

criterion_group!(benches, bench);

fn main() {
    benches();
    figures();
    Criterion::default().configure_from_args().final_summary();
}
