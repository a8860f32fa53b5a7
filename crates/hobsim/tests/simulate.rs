//! Whole programs simulated end to end: cut, measured, graded, and the
//! safety findings of the same run.

mod common;

use gearcam_hobsim::simulate::{simulate, Settings};

fn run(name: &str, settings: &Settings) -> gearcam_proto::SimulationReport {
    let (text, model) = common::program(name);
    let (check, trace) = gearcam_nc::check(&text, &model);
    assert!(check.ok, "{:?}", check.findings);
    let sim = simulate(&trace, &model, settings).expect("simulates");
    if let Ok(m) = &sim.measurement {
        eprintln!("{name} ({}):\n{m}", settings.mode);
    }
    sim.report(0.0)
}

/// The example programs cut a gear that measures: every item graded, the
/// tooth thickness that of the drawing, no safety finding.
#[test]
#[ignore = "about a minute in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn the_example_programs_cut_a_gear_that_measures() {
    for name in ["spur_840d", "helical_climb_840d"] {
        let r = run(name, &Settings::coarse());
        assert_eq!(r.not_measured, None, "{name}");
        assert!(r.safety.is_empty(), "{name}: {:?}", r.safety);
        assert_eq!(r.deviations.len(), 9, "{name}: {:?}", r.deviations);
    }
}
