//! A 40-tooth die (m 2, α 20°, x 0) at ε = 1 µm on the flank and 5 µm on
//! the fillet, as the services make it: geometry and arc fit, the wire's
//! offset, the program and its replay with the certificate, for each form;
//! and the pieces on their own.
//! `cargo bench -p gearcam-wire --bench die`

#[path = "../tests/common/mod.rs"]
mod common;

use common::molybdenum;
use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_proto::{DiePart, DieSpec, WireProgram};
use gearcam_wire::die::cut;
use gearcam_wire::offset::offset;
use gearcam_wire::programs::{layout, make, write};

fn die() -> DieSpec {
    DieSpec::new(DiePart::Die, 2.0, 40, 20.0, "Cr12MoV")
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("40-tooth die at 1 um");
    g.sample_size(20);
    let d = die();
    for form in [
        WireProgram::ThreeB,
        WireProgram::FourB,
        WireProgram::IsoWire,
    ] {
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
    }
    let p = molybdenum(WireProgram::ThreeB, false);
    let mut aimed = d.clone();
    aimed.flank_tolerance_um *= 0.75;
    aimed.fillet_tolerance_um *= 0.75;
    g.bench_function("geometry + arc fit + offset", |b| {
        b.iter(|| cut(&aimed, &p).unwrap().path.len())
    });
    let k = cut(&aimed, &p).unwrap();
    g.bench_function("offset of the whole outline", |b| {
        b.iter(|| offset(&k.contour, k.side, k.offset_mm).unwrap().len())
    });
    let l = layout(&k, DiePart::Die, false);
    g.bench_function("3B program", |b| {
        b.iter(|| write(&k, WireProgram::ThreeB, &l, &[], 1).text.len())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
