//! Template service speed: assembly + instantiation + path check of one
//! job, release build. `cargo bench -p gearcam-tests --bench template`.
//!
//! - `one_job/{840d,fanuc}_{spur,helical_multicut}`: find the compiled template of
//!   the job's class and dialect (assembly from the library happens once at
//!   start; the lookup is what a job pays), fill the parameter table, run the
//!   expression-driven algorithm, hash, parse the program back and simulate it.
//! - `assembly_instantiation_check/{840d,fanuc}_spur`: the same with nothing
//!   cached: assemble the template from the SQLite library, compile it, then
//!   instantiate and check (`*/assembly_only`: the assembly alone).
//! - `expression/*`: one NC output expression, `"G1 X" + nc(X) + " F" + nc(F)`,
//!   evaluated by our compiled expression and by minijinja's expression API
//!   (the candidate crate; see services/template/EXPRESSIONS.md).

// A bench: the wall clock is what it measures.
#![allow(clippy::disallowed_methods)]

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_proto::{JobId, JobRequest, JobSpec, MachiningModel};
use gearcam_template::expr::{self, EvalState, TplValue};
use gearcam_template::Templates;
use std::hint::black_box;
use std::time::{Duration, Instant};

fn model(file: &str, machine: &str) -> MachiningModel {
    let path = format!("{}/../examples/{file}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("machine = \"H01\"", &format!("machine = \"{machine}\""));
    let spec: JobSpec = toml::from_str(&text).unwrap();
    let req = JobRequest {
        job_id: JobId::new("BENCH-1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "bench".into(),
        spec,
    };
    let conn = gearcam_knowledge::db::open_in_memory().unwrap();
    let plan = gearcam_knowledge::plan::plan(&conn, &req).unwrap();
    gearcam_model::compute(&plan).unwrap()
}

fn one_job(c: &mut Criterion) {
    let templates = Templates::builtin();
    let mut g = c.benchmark_group("one_job");
    for (name, file, machine) in [
        ("840d_spur", "spur_840d.toml", "H01"),
        ("840d_multicut_shift", "multi_cut_shift_840d.toml", "H01"),
        ("fanuc_spur", "spur_840d.toml", "H02"),
        ("fanuc_multicut_shift", "multi_cut_shift_840d.toml", "H02"),
    ] {
        let m = model(file, machine);
        let p = templates
            .render(&m)
            .expect("renders and passes the path check");
        println!(
            "{name}: {} lines, {} bytes",
            p.text.lines().count(),
            p.text.len()
        );
        g.bench_function(name, |b| {
            b.iter(|| {
                let p = templates.render(black_box(&m)).unwrap();
                black_box(p.sha256.len())
            })
        });
        g.bench_function(format!("{name}/path_check_only"), |b| {
            b.iter(|| black_box(gearcam_nc::check(black_box(&p.text), &m).0.ok))
        });
    }
    g.finish();
}

fn expression(c: &mut Criterion) {
    let mut g = c.benchmark_group("expression");
    let names = ["X", "F"];
    let mut resolve = |n: &str| names.iter().position(|k| *k == n);
    let ours = expr::compile("\"G1 X\" + nc(X) + \" F\" + nc(F)", &mut resolve).unwrap();
    let vars = [TplValue::Num(74.05), TplValue::Num(28.634)];
    g.bench_function("gearcam_expr", |b| {
        b.iter(|| {
            let mut st = EvalState::new(1000);
            black_box(ours.eval(black_box(&vars), &mut st).unwrap())
        })
    });

    let mut env = minijinja::Environment::new();
    env.set_fuel(Some(1000));
    env.add_filter("nc", |v: f64| format!("{v:.3}"));
    let theirs = env
        .compile_expression("'G1 X' ~ (X | nc) ~ ' F' ~ (F | nc)")
        .unwrap();
    let ctx = minijinja::context! { X => 74.05, F => 28.634 };
    g.bench_function("minijinja_expression", |b| {
        b.iter(|| black_box(theirs.eval(black_box(&ctx)).unwrap()))
    });
    g.finish();
}

/// The whole per-job path when nothing is cached: assemble the class's
/// template from the SQLite template library (components fetched, ordered by
/// N and concatenated by module), compile it, instantiate, path check.
fn cold_job(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("templates.db");
    Templates::from_library(&path, gearcam_template::DEFAULT_FUEL, 0).unwrap();
    let library = gearcam_template::library::Library::open(&path).unwrap();
    let mut g = c.benchmark_group("assembly_instantiation_check");
    for (name, file, machine, id) in [
        ("840d_spur", "spur_840d.toml", "H01", "cylindrical_840d"),
        ("fanuc_spur", "spur_840d.toml", "H02", "cylindrical_fanuc"),
    ] {
        let m = model(file, machine);
        g.bench_function(name, |b| {
            b.iter(|| {
                let t = library.assemble(black_box(id), None).unwrap();
                let templates = Templates::from_files([t], gearcam_template::DEFAULT_FUEL).unwrap();
                let p = templates.render(black_box(&m)).unwrap();
                black_box(p.sha256.len())
            })
        });
        g.bench_function(format!("{name}/assembly_only"), |b| {
            b.iter(|| black_box(library.assemble(black_box(id), None).unwrap().records.len()))
        });
    }
    g.finish();
}

/// Mean time of `f` over enough runs to fill about a second.
fn mean(mut f: impl FnMut()) -> Duration {
    f();
    let mut runs = 0u32;
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(1) || runs < 20 {
        f();
        runs += 1;
    }
    start.elapsed() / runs
}

/// The figures of the spur job beside what they are held to: the clearance
/// of a program's moves within 100 µs for 50 moves, so that the template
/// and the path check of a whole program stay far below a person's notice.
fn figures(_c: &mut Criterion) {
    let templates = Templates::builtin();
    let m = model("spur_840d.toml", "H01");
    let p = templates
        .render(&m)
        .expect("renders and passes the path check");
    let whole = mean(|| {
        black_box(templates.render(black_box(&m)).unwrap().sha256.len());
    });
    let check = mean(|| {
        black_box(gearcam_nc::check(black_box(&p.text), &m).0.ok);
    });
    let (_, trace) = gearcam_nc::check(&p.text, &m);
    let moves = trace
        .moves
        .iter()
        .filter(|mv| mv.kind != gearcam_proto::MoveKind::Dwell)
        .count();
    let clear = mean(|| {
        black_box(gearcam_nc::collide_hook::clearance(black_box(&m), &trace));
    });
    let per_50 = clear.as_secs_f64() * 1e6 * 50.0 / moves.max(1) as f64;
    println!();
    println!("figures, 840D spur job ({moves} moves):");
    println!(
        "  template + path check: {:.1} µs; the path check alone: {:.1} µs",
        whole.as_secs_f64() * 1e6,
        check.as_secs_f64() * 1e6
    );
    println!(
        "  {} clearance of its {moves} moves: {:.1} µs, {per_50:.1} µs per 50 moves (target ≤ 100 µs per 50 moves)",
        if per_50 <= 100.0 { "met:    " } else { "NOT MET:" },
        clear.as_secs_f64() * 1e6
    );
}

criterion_group!(benches, figures, one_job, cold_job, expression);
criterion_main!(benches);
