//! A 40-tooth die (m 2, α 20°, x 0) at ε = 1 µm on the flank and 5 µm on
//! the fillet, as the services make it: geometry and arc fit, the wire's
//! offset, the program and its replay with the certificate, for each form;
//! and the pieces on their own.
//! `cargo bench -p gearcam-wire --bench die`

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_proto::{DiePart, DieSpec, Source, Sourced, WireProcess, WireProgram};
use gearcam_wire::die::cut;
use gearcam_wire::offset::offset;
use gearcam_wire::programs::{layout, make, write};

fn die() -> DieSpec {
    DieSpec::new(DiePart::Die, 2.0, 40, 20.0, "Cr12MoV")
}

fn process(program: WireProgram) -> WireProcess {
    let s = |value: f64| Sourced {
        value,
        source: Source::Library,
    };
    WireProcess {
        wire: "MO-018".into(),
        wire_diameter_mm: s(0.18),
        spark_gap_mm: s(0.01),
        pulse_on_us: s(24.0),
        pulse_off_us: s(120.0),
        current_a: s(3.0),
        cutting_rate_mm2_min: s(60.0),
        program,
        whole: false,
    }
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
        let p = process(form);
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
    let p = process(WireProgram::ThreeB);
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
