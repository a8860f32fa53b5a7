//! The spiral family's work per job, as the services do it: model (spiral,
//! chords, tangent arcs and their measured deviation, coverage), then the
//! program of each form written and replayed against the model. A 200 mm
//! face (Ro 100, Ri 0) with a 63 mm face mill at 1 µm:
//! `cargo bench -p gearcam-template --bench spiral`.
//!
//! The plan is made once from the seeded knowledge base; the benchmark
//! times the model service's computation and the template service's
//! render-and-verify per form.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_proto::{JobId, JobRequest, JobSpec, SpiralPlan};

fn plan(form: &str) -> SpiralPlan {
    let job = format!(
        r#"
[job]
family = "spiral-face"
machine = "M01"
part_number = "FL-BENCH"
[face]
outer_radius_mm = 100.0
depth_mm = 1.0
material = "C45"
[mill]
id = "FM-063"
[milling]
tolerance_mm = 0.001
program = "{form}"
"#
    );
    let spec: JobSpec = toml::from_str(&job).expect("job file");
    let req = JobRequest {
        job_id: JobId::new("BENCH-1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "bench".into(),
        spec,
    };
    let conn = gearcam_knowledge::db::open_in_memory().unwrap();
    gearcam_knowledge::spiral::plan_spiral(&conn, &req).expect("a valid plan")
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("spiral-200mm-1um");
    g.sample_size(10);
    let macro_plan = plan("fanuc-macro");
    let m = gearcam_model::spiral::compute_spiral(&macro_plan).unwrap();
    eprintln!(
        "200 mm face, FM-063, 1 um: {} turns, {} tangent arcs or {} chords per pass ({:.1}x), coverage {} on {} points",
        m.spiral.turns,
        m.spiral.arcs,
        m.spiral.chords,
        f64::from(m.spiral.chords) / f64::from(m.spiral.arcs),
        m.coverage.ok,
        m.coverage.samples
    );
    g.bench_function("model (spiral, arcs, deviation, coverage)", |b| {
        b.iter(|| black_box(gearcam_model::spiral::compute_spiral(black_box(&macro_plan)).unwrap()))
    });
    for form in ["fanuc-macro", "fanuc-arcs", "fanuc-chords"] {
        let m = gearcam_model::spiral::compute_spiral(&plan(form)).unwrap();
        g.bench_function(format!("program + replay: {form}"), |b| {
            b.iter(|| black_box(gearcam_template::spiral::render(black_box(&m)).unwrap()))
        });
    }
    let whole = plan("fanuc-arcs");
    g.bench_function("model + arc program + replay", |b| {
        b.iter(|| {
            let m = gearcam_model::spiral::compute_spiral(black_box(&whole)).unwrap();
            black_box(gearcam_template::spiral::render(&m).unwrap())
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
