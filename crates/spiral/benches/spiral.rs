//! A 200 mm face (Ro 100 mm, Ri 0), a 16 mm tool, 12 mm step-over, at 1 µm:
//! the model, the programs and their verification, each timed; then each
//! figure with a target printed beside it (the median of 30 runs).
//! `cargo bench -p gearcam-spiral --bench spiral`
#![allow(clippy::disallowed_methods)] // a bench reads the clock

use std::time::{Duration, Instant};

use criterion::{criterion_group, Criterion};
use gearcam_spiral::fanuc::{arc_program, macro_program};
use gearcam_spiral::linuxcnc::Cut;
use gearcam_spiral::macrob::replay;
use gearcam_spiral::{
    arcs, chord_deviation, coverage, plan, prove_coverage, Direction, Region, SpiralSpec,
};

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

/// What the model service computes for a face (`gearcam_model::spiral`'s
/// `model_of` and `coverage_of`): the spiral, its chords and tangent arcs
/// (both counted in the model's figures), the measured deviation of the
/// form's path and the coverage proof with the path's stray. `arcs_form`:
/// the `fanuc-arcs` form, else a chord form.
fn model_with_coverage(spec: &SpiralSpec, tol: f64, arcs_form: bool) -> bool {
    let spiral = plan(spec).unwrap();
    let (_, points) = spiral.chords(tol);
    let fitted = arcs::fit(&spiral, tol);
    let (deviation, stray) = if arcs_form {
        let d = arcs::max_deviation(&spiral, &fitted, 20_000);
        (d, d.max(tol))
    } else {
        let d = chord_deviation(&spiral, &points);
        (d, spiral.chord_stray_mm(tol).max(d))
    };
    let proof = prove_coverage(&spec.region, &spiral, spec.tool_radius_mm, stray);
    proof.ok && deviation < 2.0 * tol
}

fn bench(c: &mut Criterion) {
    let (spec, cut) = face();
    let spiral = plan(&spec).unwrap();
    let tol = cut.tolerance_mm;
    c.bench_function("plan + chords at 1 um", |b| {
        b.iter(|| plan(&spec).unwrap().chords(tol).1.len())
    });
    c.bench_function("tangent arcs at 1 um", |b| {
        b.iter(|| arcs::fit(&spiral, tol).len())
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
    let (_, points) = spiral.chords(tol);
    c.bench_function("chord deviation measured", |b| {
        b.iter(|| chord_deviation(&spiral, &points))
    });
    c.bench_function("sampled coverage at 0.5 mm (the reference)", |b| {
        b.iter(|| coverage(&spec.region, spec.tool_radius_mm, &points, 0.5).ok)
    });
    c.bench_function("coverage proof", |b| {
        b.iter(|| prove_coverage(&spec.region, &spiral, spec.tool_radius_mm, tol).ok)
    });
    c.bench_function("spiral model with coverage, chords", |b| {
        b.iter(|| model_with_coverage(&spec, tol, false))
    });
    c.bench_function("spiral model with coverage, arcs", |b| {
        b.iter(|| model_with_coverage(&spec, tol, true))
    });
}

/// The median time of `runs` runs of `f`, after one to warm up.
fn median(runs: usize, mut f: impl FnMut() -> bool) -> Duration {
    assert!(f());
    let mut times: Vec<Duration> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            assert!(f());
            t.elapsed()
        })
        .collect();
    times.sort();
    times[runs / 2]
}

/// Each whole figure beside its target.
fn figures() {
    let (spec, cut) = face();
    let tol = cut.tolerance_mm;
    let spiral = plan(&spec).unwrap();
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    println!("\nThe 200 mm face at 1 um, median of 30 runs:");
    for (name, arcs_form) in [("chords", false), ("arcs", true)] {
        let t = median(30, || model_with_coverage(&spec, tol, arcs_form));
        println!(
            "spiral model with coverage ({name}): {:.1} ms (target <= 10 ms)",
            ms(t)
        );
    }
    let t = median(30, || !arcs::fit(&spiral, tol).is_empty());
    println!("tangent arcs: {:.1} ms", ms(t));
    let t = median(30, || {
        !replay(&arc_program(&spiral, &cut, 1, &[]), 1_000_000)
            .unwrap()
            .is_empty()
    });
    println!("arc program + replay: {:.1} ms", ms(t));
    let t = median(30, || {
        !replay(&macro_program(&spiral, &cut, 1, &[]), 10_000_000)
            .unwrap()
            .is_empty()
    });
    println!("macro program + replay: {:.1} ms", ms(t));
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}

fn main() {
    benches();
    figures();
    Criterion::default().configure_from_args().final_summary();
}
