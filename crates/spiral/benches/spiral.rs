//! A 200 mm face (Ro 100 mm, Ri 0), a 16 mm tool, 12 mm step-over, at 1 µm:
//! the model, the programs and their verification, each timed.
//! `cargo bench -p gearcam-spiral --bench spiral`

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_spiral::fanuc::{arc_program, macro_program};
use gearcam_spiral::linuxcnc::Cut;
use gearcam_spiral::macrob::replay;
use gearcam_spiral::{arcs, coverage, plan, Direction, Region, SpiralSpec};

fn face() -> (SpiralSpec, Cut) {
    (
        SpiralSpec {
            region: Region {
                outer_radius_mm: 100.0,
                inner_radius_mm: 0.0,
            },
            tool_radius_mm: 8.0,
            step_over_mm: 12.0,
            outer_overtravel_mm: 2.0,
            inner_overtravel_mm: 1.0,
            start_angle_deg: 0.0,
            direction: Direction::OutsideIn,
        },
        Cut {
            depth_mm: 0.5,
            passes: 1,
            feed_mm_min: 800.0,
            plunge_feed_mm_min: 200.0,
            spindle_rpm: 1200.0,
            safe_z_mm: 5.0,
            tolerance_mm: 0.001,
        },
    )
}

fn bench(c: &mut Criterion) {
    let (spec, cut) = face();
    let spiral = plan(&spec).unwrap();
    c.bench_function("plan + chords at 1 um", |b| {
        b.iter(|| plan(&spec).unwrap().chords(cut.tolerance_mm).1.len())
    });
    c.bench_function("tangent arcs at 1 um", |b| {
        b.iter(|| arcs::fit(&spiral, cut.tolerance_mm).len())
    });
    c.bench_function("macro program + Macro B replay", |b| {
        b.iter(|| {
            replay(&macro_program(&spiral, &cut, 1, &[]), 10_000_000)
                .unwrap()
                .len()
        })
    });
    c.bench_function("arc program + replay", |b| {
        b.iter(|| {
            replay(&arc_program(&spiral, &cut, 1, &[]), 1_000_000)
                .unwrap()
                .len()
        })
    });
    let (_, points) = spiral.chords(cut.tolerance_mm);
    c.bench_function("coverage at 0.5 mm", |b| {
        b.iter(|| coverage(&spec.region, spec.tool_radius_mm, &points, 0.5).ok)
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
