//! Whole programs simulated end to end: cut, measured, graded, and the
//! safety findings of the same run.

mod common;

use gearcam_gearmeasure::iso1328::{Grade, Item};
use gearcam_gearmeasure::outline::{self, GearSpec, PolarSections};
use gearcam_hobsim::safety::SafetyKind;
use gearcam_hobsim::simulate::{drawing, simulate, simulate_part, Settings};

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

/// The mean helix form deviation ffβ over every flank of `sim`'s gear
/// measured against `spec`, µm.
fn mean_helix_form(sim: &gearcam_hobsim::simulate::Simulation, spec: &GearSpec) -> f64 {
    let sections = PolarSections {
        z_mm: sim.blank.z_mm.clone(),
        r_mm: sim.blank.r_mm.clone(),
    };
    // A coarse run's sections are cut only about the teeth it traced.
    let m = outline::measure_traced(&sections, spec, sim.traced.as_deref()).expect("measures");
    let h = m.helix.expect("helix traced");
    let all: Vec<f64> = h.left.iter().chain(&h.right).map(|d| d.form_um).collect();
    all.iter().sum::<f64>() / all.len() as f64
}

/// The crowned spur program follows its `CIP` arc (radius 10 m, 0.02 mm
/// higher in the middle of the face): the gear it cuts fits the crowned
/// design helix (Cβ = 0.02·sin αt along the base tangent, 6.8 µm) better
/// than a plain one, by about the crowning's form over the evaluation
/// range. The arc taken as its chord (a straight feed, the bug put back)
/// cuts a plain helix, which fits the plain design better.
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_crowned_program_cuts_its_crowning() {
    let (text, model) = common::program("crowned_840d");
    let crowned = drawing(&model);
    assert!(crowned.helix_crowning_mm > 0.006, "{crowned:?}");
    let plain = GearSpec {
        helix_crowning_mm: 0.0,
        ..crowned
    };
    let sim = simulate_text(&text, &model);
    let (fit_crowned, fit_plain) = (
        mean_helix_form(&sim, &crowned),
        mean_helix_form(&sim, &plain),
    );
    assert!(
        fit_crowned + 3.0 < fit_plain,
        "ffβ against the crowned design {fit_crowned} µm, the plain {fit_plain} µm"
    );
    // Every flank, not only on average: a pass near the end of one of the
    // arc's short pieces sweeps on into the next one.
    let m = sim.measurement.as_ref().expect("measures");
    for item in [Item::ProfileTotal, Item::HelixTotal] {
        let v = m.item(item).map_or(f64::NAN, |i| i.value_um);
        eprintln!("{item:?} {v:.2} µm");
        assert!(v < 5.0, "{item:?} {v} µm");
    }
    let chord = text.replace(
        "CIP X=81.23 Z=100.0 I1=81.25 K1=120.0",
        "G1 X=81.23 Z=100.0",
    );
    assert_ne!(chord, text);
    let straight = simulate_text(&chord, &model);
    let (chord_crowned, chord_plain) = (
        mean_helix_form(&straight, &crowned),
        mean_helix_form(&straight, &plain),
    );
    eprintln!(
        "mean ffβ, crowned design / plain design: the arc {fit_crowned:.2} / {fit_plain:.2} µm, the chord {chord_crowned:.2} / {chord_plain:.2} µm"
    );
    assert!(
        chord_plain + 3.0 < chord_crowned,
        "the chord: ffβ against the crowned design {chord_crowned} µm, the plain {chord_plain} µm"
    );
}

/// A part of two gears (a module-3 spur gear of 25 teeth in four cuts, a
/// module-2 helical gear of 18 above it in five, a hob change between):
/// each gear's blank is cut by the hob mounted at each move and measured
/// against its own drawing, and the run is safe. Unit 2 coupled in unit
/// 1's ratio (1/25 for 1/18) is a wrong-ratio cut of unit 2's blank, named
/// by its gear.
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_part_of_two_gears_is_cut_and_measured_gear_by_gear() {
    let (text, model) = common::program("two_units_five_cuts_840d");
    let (check, trace) = gearcam_nc::check(&text, &model);
    assert!(check.ok, "{:?}", check.findings);
    let gears = simulate_part(&trace, &model, &Settings::coarse()).expect("simulates");
    assert_eq!(gears.len(), 2);
    for (g, teeth) in gears.iter().zip([25, 18]) {
        assert_eq!(g.spec.teeth, teeth);
        let m = g.measurement.as_ref().expect("measures");
        eprintln!("{:?}: {m}", g.unit);
        assert!(
            matches!(m.overall, gearcam_gearmeasure::iso1328::Grade::Class(_)),
            "{:?}: {:?}",
            g.unit,
            m.overall
        );
    }
    assert!(gears[0].safety.is_empty(), "{:?}", gears[0].safety);
    let wrong = text.replace("B,0,1,18,Z", "B,0,1,25,Z");
    assert_ne!(wrong, text);
    let (_, trace) = gearcam_nc::check(&wrong, &model);
    let gears = simulate_part(&trace, &model, &Settings::coarse()).expect("simulates");
    assert!(
        gears[0]
            .safety
            .iter()
            .any(|f| f.kind == SafetyKind::CutWrongRatio && f.what.contains("upper helical gear")),
        "{:?}",
        gears[0].safety
    );
}

/// The tangential worm-wheel program: the wheel is measured in its throat
/// plane alone (profile, pitch, runout, size; no helix across throated
/// teeth), said so in a note, and the run is safe. The hob 2 mm off the
/// throat plane is found: the teeth are not enveloped where the worm runs.
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_worm_wheel_is_measured_in_its_throat_plane() {
    let (text, model) = common::program("worm_wheel_tangential_840d");
    let sim = simulate_text(&text, &model);
    assert!(sim.safety.is_empty(), "{:?}", sim.safety);
    assert!(sim.note.as_deref().is_some_and(|n| n.contains("throat")));
    let m = sim.measurement.as_ref().expect("measures");
    assert!(m.item(Item::SinglePitch).is_some() && m.item(Item::ProfileTotal).is_some());
    assert!(m.item(Item::HelixTotal).is_none(), "{:?}", m.items);
    assert!(matches!(
        m.overall,
        gearcam_gearmeasure::iso1328::Grade::Class(_)
    ));
    let off = text.replace("N60 G0 G90 Z=82.5", "N60 G0 G90 Z=84.5");
    assert_ne!(off, text);
    let sim = simulate_text(&off, &model);
    assert!(
        sim.safety
            .iter()
            .any(|f| f.kind == SafetyKind::FaceWidthNotCovered && f.what.contains("throat")),
        "{:?}",
        sim.safety
    );
}

/// The conical spur program (cone 6.5°, 5 mm face, large end at the
/// bottom): the hob's centre follows the cone line r0·(1/cos δ − 1) further
/// out than a cylinder's and ra0·sin δ on beyond the small end, and the gear
/// it cuts measures, section by section against the involute of its own
/// shift, with flanks at tan α′ = tan αn·cos δ, within the drawing's class 7
/// and its thickness. The path as it was (X held at the small face beyond
/// it, the centre line a cylinder's) cuts the small end as a cylinder and
/// every section too deep: the helix leans far beyond class 11 and the
/// teeth are thin. Measured against flanks at αn, the gear it cuts shows
/// the profile slope of the stretched rack.
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_conical_program_cuts_its_cone() {
    let (text, model) = common::program("conical_840d");
    let spec = drawing(&model);
    assert!(
        spec.taper < 0.0 && spec.normal_pressure_angle_deg < 19.9,
        "{spec:?}"
    );
    let sim = simulate_text(&text, &model);
    assert!(sim.safety.is_empty(), "{:?}", sim.safety);
    let m = sim.measurement.as_ref().expect("measures");
    eprintln!("conical_840d:\n{m}");
    let value = |m: &outline::Measurement, item| m.item(item).map_or(f64::NAN, |i| i.value_um);
    // Within class 7: the tolerance of the class the item measured in,
    // scaled to class 7 by √2 a class.
    for item in [Item::HelixSlope, Item::HelixTotal, Item::ProfileTotal] {
        let i = m.item(item).expect("graded");
        let class = match i.grade {
            Grade::Class(c) => f64::from(c.number()),
            Grade::WorseThan11 => 12.0,
        };
        let class7 = i.tolerance_um * 2f64.sqrt().powf(7.0 - class);
        assert!(i.value_um.abs() <= class7, "{i:?} (class 7: {class7} µm)");
    }
    let tolerance = |item| m.item(item).map_or(f64::NAN, |i| i.tolerance_um);
    let thin = m.size.thickness_mm - m.size.design_thickness_mm;
    assert!(thin.abs() < 0.010, "{:?}", m.size);
    // The path as it was: the cone line a cylinder's (its lift r0·(1/cos δ − 1)
    // taken off), from the small face, X held beyond it.
    let cone = model.model.cone.as_ref().expect("a cone");
    let hob = &model.plan.hob;
    let r0 = f64::from(hob.starts) * hob.module_mm / (2.0 * hob.lead_angle_deg.to_radians().sin());
    let large = cone.x_large_mm - r0 * (1.0 / cone.angle_deg.to_radians().cos() - 1.0);
    let gear = &model.plan.gear;
    let (bottom, top) = (
        gear.fixture_height_mm,
        gear.fixture_height_mm + gear.face_width_mm,
    );
    let small = large + cone.x_per_z * (top - bottom);
    let old = with_word(&text, "; B -> C", 'X', small);
    let old = with_word(&old, "; C -> CONE", 'Z', top);
    let old = with_word(&old, "; ALONG THE CONE", 'X', large);
    assert_ne!(old, text);
    let was = simulate_text(&old, &model);
    let w = was.measurement.as_ref().expect("measures");
    eprintln!("the path as it was:\n{w}");
    assert!(value(w, Item::HelixSlope).abs() > 5.0 * tolerance(Item::HelixSlope));
    assert!(
        w.size.thickness_mm - w.size.design_thickness_mm < -0.05,
        "{:?}",
        w.size
    );
    // Flanks at αn.
    let at_alpha_n = GearSpec {
        normal_pressure_angle_deg: model.plan.gear.pressure_angle_deg,
        ..spec
    };
    let sections = PolarSections {
        z_mm: sim.blank.z_mm.clone(),
        r_mm: sim.blank.r_mm.clone(),
    };
    let plain =
        outline::measure_traced(&sections, &at_alpha_n, sim.traced.as_deref()).expect("measures");
    assert!(
        value(&plain, Item::ProfileSlope).abs() > value(m, Item::ProfileSlope).abs() + 4.0,
        "fHα at αn {} µm, at α′ {} µm",
        value(&plain, Item::ProfileSlope),
        value(m, Item::ProfileSlope)
    );
}

/// `text` with the word `letter`=… of the block after the comment line
/// starting `comment` set to `value`.
fn with_word(text: &str, comment: &str, letter: char, value: f64) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let at = lines
        .iter()
        .position(|l| l.starts_with(comment))
        .unwrap_or_else(|| panic!("no comment {comment}"))
        + 1;
    let block: Vec<String> = lines[at]
        .split(' ')
        .map(|w| {
            if w.starts_with(letter) && w[1..].starts_with('=') {
                format!("{letter}={value:.3}")
            } else {
                w.to_string()
            }
        })
        .collect();
    let mut out: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
    out[at] = block.join(" ");
    out.join("\n") + "\n"
}

/// The sections are shared among threads, each cut by one with every pass,
/// and the safety rules run beside them: the run's result is the same on
/// one thread and on three (more threads than cores, an uneven share of
/// the sections), for a part of two gears with a safety finding.
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_run_on_several_threads_is_the_run_on_one() {
    let (text, model) = common::program("two_units_five_cuts_840d");
    let wrong = text.replace("B,0,1,18,Z", "B,0,1,25,Z");
    let (_, trace) = gearcam_nc::check(&wrong, &model);
    let on = |threads: usize| {
        let settings = Settings {
            threads,
            ..Settings::coarse()
        };
        simulate_part(&trace, &model, &settings).expect("simulates")
    };
    let (one, three) = (on(1), on(3));
    assert!(!one[0].safety.is_empty());
    assert_eq!(one.len(), three.len());
    for (a, b) in one.iter().zip(&three) {
        assert_eq!(a.blank, b.blank, "{:?}", a.unit);
        assert_eq!(a.passes, b.passes);
        assert_eq!(format!("{:?}", a.safety), format!("{:?}", b.safety));
        assert_eq!(
            format!("{:?}", a.measurement),
            format!("{:?}", b.measurement)
        );
    }
}

/// A coarse run cuts the sections other than the middle one only about the
/// four teeth it traces there: its measurement is the one of the same cut
/// made all round with those teeth traced, item for item, and its blank the
/// same within the windows the traces read (the middle section entirely).
#[test]
#[ignore = "seconds in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_coarse_run_measures_its_four_teeth_as_the_cut_all_round_does() {
    // A cut 2 mm shallow leaves teeth some 0.7 mm thicker than their
    // design, beyond the windows' margin: they widen with them (without
    // that, this case fails).
    let shallow = gearcam_hobsim::kinematics::MachineErrors {
        centre_distance_mm: 2.0,
        ..Default::default()
    };
    for (name, errors) in [
        ("spur_840d", Default::default()),
        ("helical_climb_840d", Default::default()),
        ("crowned_840d", Default::default()),
        ("conical_840d", Default::default()),
        ("spur_840d", shallow),
    ] {
        let (text, model) = common::program(name);
        let (check, trace) = gearcam_nc::check(&text, &model);
        assert!(check.ok, "{name}: {:?}", check.findings);
        let settings = Settings {
            errors,
            ..Settings::coarse()
        };
        let coarse = simulate(&trace, &model, &settings).expect("simulates");
        let all_round = Settings {
            four_teeth: false,
            ..settings
        };
        let whole = simulate(&trace, &model, &all_round).expect("simulates");
        let teeth = coarse.traced.clone().expect("four teeth traced");
        // The report says which, numbered from 1 as the charts print them.
        let note = coarse.report(0.0).note.expect("a note");
        let named: Vec<String> = teeth.iter().map(|t| (t + 1).to_string()).collect();
        assert!(note.contains(&named.join(", ")), "{note}");
        assert_eq!(whole.report(0.0).note, None);
        assert_eq!(teeth, outline::four_teeth(model.plan.gear.teeth as usize));
        assert_eq!(whole.traced, None);
        let sections = whole.measured_sections();
        let of_whole = outline::measure_traced(&sections, &whole.spec, Some(&teeth))
            .map_err(|e| e.to_string());
        assert_eq!(
            format!("{:?}", coarse.measurement),
            format!("{of_whole:?}"),
            "{name}"
        );
        // Outside the windows the coarse blank is left higher.
        let higher = coarse
            .blank
            .r_mm
            .iter()
            .flatten()
            .zip(whole.blank.r_mm.iter().flatten())
            .filter(|(c, w)| *c > &(*w + 1e-3))
            .count();
        assert!(higher > 1000, "{name}: {higher}");
    }
}
