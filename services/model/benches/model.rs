//! Geometry + model of one job (the README's spur gear on H01 with the
//! library hob HOB-M3-80, one cut): `cargo bench -p gearcam-model`.
//!
//! The plan is built once from the seeded knowledge base; the benchmark times
//! only the pure computation the model service does per job:
//! validation, geometry, kinematics, explanation and the limit checks.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_proto::{JobId, JobRequest, JobSpec, ProcessPlan};

fn plan(job: &str) -> ProcessPlan {
    let spec: JobSpec = toml::from_str(job).expect("job file");
    let req = JobRequest {
        job_id: JobId::new("BENCH-1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "bench".into(),
        spec,
    };
    let conn = gearcam_knowledge::db::open_in_memory().unwrap();
    gearcam_knowledge::plan::plan(&conn, &req).expect("a valid plan")
}

const SPUR: &str = r#"
[job]
machine = "H01"
part_number = "SP-1001"
quantity = 20
[gear]
module_mm = 3.0
teeth = 25
face_width_mm = 30.0
blank_od_mm = 81.0
material = "20CrMnTi"
fixture_height_mm = 100.0
[hob]
id = "HOB-M3-80"
"#;

fn bench(c: &mut Criterion) {
    let spur = plan(SPUR);
    c.bench_function("geometry+model, spur gear, one cut", |b| {
        b.iter(|| gearcam_model::compute(black_box(&spur)).unwrap())
    });
    let geo_only = spur.gear.clone();
    c.bench_function("geometry only", |b| {
        b.iter(|| gearcam_model::geometry_of(black_box(&geo_only)))
    });
    // The blank of the helical gear is its own tip diameter (the default).
    let helical = plan(
        &SPUR
            .replace(
                "teeth = 25",
                "teeth = 25\nhelix_angle_deg = 15.0\nhelix_hand = \"right\"",
            )
            .replace("blank_od_mm = 81.0\n", ""),
    );
    c.bench_function("geometry+model, helical gear, one cut", |b| {
        b.iter(|| gearcam_model::compute(black_box(&helical)).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
