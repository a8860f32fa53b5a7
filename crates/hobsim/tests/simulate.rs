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

/// The simulation of a program text as it is, without the path check
/// first: the defects below are the simulator's to catch.
fn simulate_text(
    text: &str,
    model: &gearcam_proto::MachiningModel,
) -> gearcam_hobsim::simulate::Simulation {
    let (_, trace) = gearcam_nc::check(text, model);
    simulate(&trace, model, &Settings::coarse()).expect("simulates")
}

/// The indexing ratio with the wrong sign: the table turns against the
/// hob, and the blank is cut away instead of into 25 teeth; the gear does
/// not measure.
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_flipped_indexing_cuts_no_gear() {
    let (text, model) = common::program("spur_840d");
    let flipped = text.replace("B,0,1,25)", "B,0,-1,25)");
    assert_ne!(flipped, text);
    let sim = simulate_text(&flipped, &model);
    assert!(
        sim.measurement.is_err(),
        "{:?}",
        sim.measurement.map(|m| m.overall)
    );
    let good = simulate_text(&text, &model);
    assert!(good.measurement.is_ok());
}

/// The differential with the wrong sign: the helix is cut with the wrong
/// lead, and the gear fails the helix far beyond class 11 (or does not
/// measure at all).
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_flipped_differential_cuts_a_wrong_helix() {
    let (text, model) = common::program("helical_climb_840d");
    let flipped = text.replace("Z,0,-0.421426,1)", "Z,0,0.421426,1)");
    assert_ne!(flipped, text);
    let sim = simulate_text(&flipped, &model);
    let helix_class = sim.measurement.as_ref().ok().and_then(|m| {
        m.item(gearcam_gearmeasure::iso1328::Item::HelixSlope)
            .map(|i| i.grade)
    });
    assert!(
        matches!(
            helix_class,
            None | Some(gearcam_gearmeasure::iso1328::Grade::WorseThan11)
        ),
        "{helix_class:?}"
    );
}
