//! The clearance check's speed: `cargo bench -p gearcam-nc --bench clearance`.
//!
//! The programs are real: what the shipped templates write for the spur
//! example (10 moves) and for the two-unit example with five cuts a unit (59
//! moves, two hobs, a swivel between the units), with their machining models
//! (`tests/programs/`). Each is parsed and simulated once; what is timed is
//! the clearance and envelope check of its trace
//! (`collide_hook::clearance`), the part of the path check that moves the
//! hob through the obstacles. Before the timed runs, each program's figure
//! is printed as `clearance, N moves: X µs (target ≤ 100 µs)` from a plain
//! loop, next to criterion's.

// A bench measures time itself for the printed figure.
#![allow(clippy::disallowed_methods)]

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_nc::collide_hook::clearance;
use gearcam_proto::{MachiningModel, MoveKind};
use std::hint::black_box;
use std::time::Instant;

/// A program of `tests/programs/` and its model.
fn program(name: &str) -> (MachiningModel, String) {
    let dir = format!("{}/tests/programs", env!("CARGO_MANIFEST_DIR"));
    let read = |ext: &str| {
        std::fs::read_to_string(format!("{dir}/{name}.{ext}"))
            .unwrap_or_else(|e| panic!("{name}.{ext}: {e}"))
    };
    let model = serde_json::from_str(&read("model.json"))
        .unwrap_or_else(|e| panic!("{name}.model.json (see tests/programs/README.md): {e}"));
    (model, read("nc"))
}

fn clearance_check(c: &mut Criterion) {
    let mut g = c.benchmark_group("clearance");
    for name in ["spur_840d", "two_units_five_cuts_840d"] {
        let (m, text) = program(name);
        let (check, trace) = gearcam_nc::check(&text, &m);
        assert!(check.ok, "{name}: {:#?}", check.findings);
        let moves = trace
            .moves
            .iter()
            .filter(|mv| mv.kind != MoveKind::Dwell)
            .count();
        let runs = 2000u32;
        let start = Instant::now();
        for _ in 0..runs {
            black_box(clearance(black_box(&m), &trace));
        }
        let us = start.elapsed().as_secs_f64() * 1e6 / f64::from(runs);
        println!("clearance, {moves} moves: {us:.1} µs (target ≤ 100 µs)");
        g.bench_function(format!("{name}_{moves}_moves"), |b| {
            b.iter(|| black_box(clearance(black_box(&m), &trace)))
        });
    }
    g.finish();
}

criterion_group!(benches, clearance_check);
criterion_main!(benches);
