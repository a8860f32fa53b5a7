//! The hobbing simulation's speed: `cargo bench -p gearcam-hobsim --bench hobbing`.
//!
//! The program is real: the helical climb cut the 840D template writes
//! (`crates/nc/tests/programs/helical_climb_840d`: z 31, β 20° left hand,
//! face width 25 mm, one-start right-hand hob of 80 mm with 12 gashes, one
//! cut at 1.6 mm per table turn), read back by `gearcam_nc::check` into a
//! trace once. Printed first: the whole `simulate::simulate` (timeline, cut
//! on 9 sections, measurement and grading) at `Settings::fine()` (1 µm
//! outline, `Resolution::fine()`) and `Settings::coarse()` (10 µm, the
//! sections other than the middle one cut only about the four teeth it
//! traces), each on one thread and on every core, the best of three runs;
//! then `cut::cut` alone (every section all round) and how its coarse cost
//! grows with sections, samples, tolerance and face width. Criterion times
//! the coarse cut. The figures are upper bounds on a shared machine.

// A bench measures time itself for the printed figure.
#![allow(clippy::disallowed_methods)]

use criterion::{criterion_group, criterion_main, Criterion};
use gearcam_hobsim::cut::{self, samples_for, Blank, Resolution};
use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{self, MachineRates, Timeline};
use gearcam_hobsim::simulate::{simulate, Settings};
use gearcam_nc::Trace;
use gearcam_proto::MachiningModel;
use std::hint::black_box;
use std::time::Instant;

/// The helical program's timeline, hob, blank radius and section heights
/// (`sections` over the face width less 1 mm at either end).
struct Setup {
    trace: Trace,
    model: MachiningModel,
    timeline: Timeline,
    hob: Hob,
    radius_mm: f64,
    z_lo: f64,
    z_hi: f64,
}

fn setup() -> Setup {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../nc/tests/programs/");
    let name = "helical_climb_840d";
    let text = std::fs::read_to_string(format!("{dir}{name}.nc")).expect("program");
    let json = std::fs::read_to_string(format!("{dir}{name}.model.json")).expect("model");
    let model: MachiningModel = serde_json::from_str(&json).expect("model reads");
    let (check, trace) = gearcam_nc::check(&text, &model);
    assert!(check.ok, "{:?}", check.findings);
    let timeline =
        kinematics::from_trace(&trace, &model, MachineRates::default()).expect("timeline");
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let g = &model.plan.gear;
    Setup {
        trace,
        model: model.clone(),
        timeline,
        hob,
        radius_mm: model.model.blank_od_mm / 2.0,
        z_lo: g.fixture_height_mm + 1.0,
        z_hi: g.fixture_height_mm + g.face_width_mm - 1.0,
    }
}

fn run(s: &Setup, sections: usize, samples: usize, res: Resolution, width: f64) -> u64 {
    let z_hi = s.z_lo + (s.z_hi - s.z_lo) * width;
    let planes = Blank::planes(s.z_lo, z_hi, sections);
    let mut blank = Blank::new(planes, s.radius_mm, samples).expect("blank");
    cut::cut(&s.timeline, &s.hob, &mut blank, res).expect("cut")
}

/// Milliseconds of one run (the best of `reps`).
fn time_ms(reps: u32, mut f: impl FnMut() -> u64) -> f64 {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::MAX, f64::min)
}

fn hobbing(c: &mut Criterion) {
    let s = setup();
    let cores = Settings::fine().thread_count();
    for (name, settings, target) in [
        ("fine", Settings::fine(), 1000.0),
        ("coarse", Settings::coarse(), 100.0),
    ] {
        for threads in [1, cores] {
            let settings = Settings {
                threads,
                ..settings
            };
            let mut grade = String::new();
            let ms = time_ms(3, || {
                let sim = simulate(&s.trace, &s.model, &settings).expect("simulates");
                grade = format!("{:?}", sim.report(0.0).grade);
                sim.passes
            });
            println!(
                "simulate helical_climb_840d, {name}, 9 sections, cut + measure + grade, {threads} thread(s): {ms:.0} ms (target < {target:.0} ms), grade {grade}"
            );
            if cores == 1 {
                break;
            }
        }
    }
    let fine_n = samples_for(s.radius_mm, 1.0);
    let coarse_n = samples_for(s.radius_mm, 10.0);
    let fine = Resolution::fine();
    let coarse = Resolution::coarse();
    println!(
        "cut alone, 9 sections: fine ({fine_n} samples): {:.1} ms; coarse ({coarse_n} samples): {:.1} ms",
        time_ms(1, || run(&s, 9, fine_n, fine, 1.0)),
        time_ms(1, || run(&s, 9, coarse_n, coarse, 1.0)),
    );
    for sections in [3, 9, 18] {
        println!(
            "  coarse, {sections} sections: {:.1} ms",
            time_ms(1, || run(&s, sections, coarse_n, coarse, 1.0))
        );
    }
    for n in [coarse_n / 2, coarse_n, 2 * coarse_n, fine_n] {
        println!(
            "  coarse, {n} samples: {:.1} ms",
            time_ms(1, || run(&s, 9, n, coarse, 1.0))
        );
    }
    for tol in [1e-3, 1e-4, 1e-5] {
        let res = Resolution {
            tolerance_mm: tol,
            ..coarse
        };
        println!(
            "  coarse samples, tolerance {tol:e} mm: {:.1} ms",
            time_ms(1, || run(&s, 9, coarse_n, res, 1.0))
        );
    }
    for width in [0.5, 1.0] {
        println!(
            "  coarse, {:.0} % of the face width (9 sections): {:.1} ms",
            width * 100.0,
            time_ms(1, || run(&s, 9, coarse_n, coarse, width))
        );
    }
    let mut g = c.benchmark_group("hobbing");
    g.sample_size(10);
    g.bench_function("helical_climb_840d coarse cut", |b| {
        b.iter(|| run(&s, 9, coarse_n, coarse, 1.0))
    });
    g.finish();
}

criterion_group!(benches, hobbing);
criterion_main!(benches);
