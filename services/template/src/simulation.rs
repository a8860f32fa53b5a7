//! Virtual hobbing before a hobbing program leaves: the program as
//! rendered, read back, run on the model of its machine, the gear it cuts
//! measured and graded (`gearcam_hobsim::simulate`). The report travels
//! with the program; a program whose run is unsafe, or whose gear is
//! visibly wrong, is not sent ([`simulation_errors`]).
//!
//! The fine simulation takes seconds. Its result depends
//! only on the motion the program commands and on the gear, hob, blank and
//! machine it runs with, so it is kept, by a hash of exactly those, for the
//! next program that commands the same motion on the same set-up (a repeat
//! order of a part, under another part number or job).

use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};

use gearcam_hobsim::simulate::{part_report, simulate_part, Settings, Simulation};
use gearcam_nc::Trace;
use gearcam_proto::{Code, JobError, MachiningModel, NcProgram, SimulationReport, Source, Stage};
use sha2::{Digest, Sha256};

/// Reports kept.
const KEPT: usize = 256;

/// The reports kept, by key, and the order they came in.
type Kept = (HashMap<[u8; 32], SimulationReport>, VecDeque<[u8; 32]>);

/// The simulations run, by the hash of what decides them (clones share
/// them).
#[derive(Debug, Clone, Default)]
pub struct Simulations {
    kept: Arc<Mutex<Kept>>,
}

/// The run every hobbing program gets before the services deliver it: the
/// fine one (9 sections, the outline within 1 µm), whose classes and
/// findings the program carries to the machine.
pub fn before_delivery() -> Settings {
    Settings::fine()
}

/// How a service runs hobbing programs before delivery, as chosen on its
/// command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Mode {
    /// [`before_delivery`]: the fine run.
    Fine,
    /// The coarse run (the outline within about 10 µm), for a slow host.
    Coarse,
    /// Not run: the program leaves with its other checks only.
    Off,
}

impl Mode {
    /// The settings of this mode (`None` for [`Mode::Off`]).
    pub fn settings(self) -> Option<Settings> {
        match self {
            Mode::Fine => Some(before_delivery()),
            Mode::Coarse => Some(Settings::coarse()),
            Mode::Off => None,
        }
    }
}

/// Why a hobbing model is not simulated, when it is not: the simulator cuts
/// and measures cylindrical involute gears (crowned or not, one or several
/// on a part), spur conical gears (each section against its own involute)
/// and worm wheels (in their throat plane). A helical conical gear is not:
/// its two flanks have different transverse pressure angles and leads,
/// which the measurement's drawing of a gear does not hold.
pub fn out_of_scope(model: &MachiningModel) -> Option<&'static str> {
    let helical_cone = |m: &gearcam_proto::Kinematics, gear: &gearcam_proto::GearSpec| {
        m.cone.is_some() && gear.helix_angle_deg != 0.0
    };
    let k = &model.model;
    if helical_cone(k, &model.plan.gear) || k.units.iter().any(|u| helical_cone(&u.model, &u.gear))
    {
        Some("a helical conical gear is not simulated yet")
    } else {
        None
    }
}

impl Simulations {
    /// The simulation of `trace` (the program read back against `model`)
    /// with `settings`, run now or kept from an earlier run of the same motion on
    /// the same set-up; `None` for a model out of the simulator's scope.
    pub fn report(
        &self,
        trace: &Trace,
        model: &MachiningModel,
        settings: &Settings,
    ) -> Option<SimulationReport> {
        if out_of_scope(model).is_some() {
            return None;
        }
        let key = key_of(trace, model, settings);
        if let Some(kept) = self.kept.lock().ok().and_then(|k| k.0.get(&key).cloned()) {
            return Some(kept);
        }
        let (report, _) = run(trace, model, settings);
        if let Ok(mut k) = self.kept.lock() {
            let (map, order) = &mut *k;
            if map.insert(key, report.clone()).is_none() {
                order.push_back(key);
            }
            while order.len() > KEPT {
                if let Some(old) = order.pop_front() {
                    map.remove(&old);
                }
            }
        }
        Some(report)
    }
}

/// The hash of what decides a simulation: every block the trace holds
/// (with its line, which the safety findings name) and the gear, hob,
/// blank and machine of the model, and the settings. The numbers go in as
/// their bits and the model's records in their MessagePack form: the key is
/// asked for every hobbing program, so it is not spelled out as text.
fn key_of(trace: &Trace, model: &MachiningModel, settings: &Settings) -> [u8; 32] {
    let mut h = Sha256::new();
    // The thread count does not change the run's result.
    let settings = Settings {
        threads: 0,
        ..*settings
    };
    h.update(format!("{settings:?}").as_bytes());
    let opt = |h: &mut Sha256, v: Option<f64>| match v {
        Some(x) => h.update([&[1u8][..], &x.to_bits().to_le_bytes()].concat()),
        None => h.update([0u8]),
    };
    h.update((trace.moves.len() as u64).to_le_bytes());
    for m in &trace.moves {
        h.update(m.line.to_le_bytes());
        h.update([m.kind as u8, u8::from(m.coupled)]);
        for x in [m.x_mm, m.z_mm, m.y_mm] {
            h.update(x.to_bits().to_le_bytes());
        }
        opt(&mut h, m.feed_mm_min);
        opt(&mut h, m.dwell_s);
        opt(&mut h, m.c_correction_deg);
        match &m.arc {
            Some(a) => {
                h.update([1u8]);
                for x in [a.centre_z_mm, a.centre_x_mm, a.sweep_rad] {
                    h.update(x.to_bits().to_le_bytes());
                }
            }
            None => h.update([0u8]),
        }
    }
    h.update((trace.couplings.len() as u64).to_le_bytes());
    for c in &trace.couplings {
        h.update(c.line.to_le_bytes());
        h.update(c.num.to_le_bytes());
        h.update(c.den.to_le_bytes());
        opt(&mut h, c.c_per_z_deg_per_mm);
        opt(&mut h, c.c_per_y_deg_per_mm);
        h.update([u8::from(c.unit_start), u8::from(c.synchronised)]);
    }
    for list in [&trace.spindle_rpm, &trace.swivel_deg] {
        h.update((list.len() as u64).to_le_bytes());
        for (line, x) in list {
            h.update(line.to_le_bytes());
            h.update(x.to_bits().to_le_bytes());
        }
    }
    h.update((trace.mcodes.len() as u64).to_le_bytes());
    for (line, m) in &trace.mcodes {
        h.update(line.to_le_bytes());
        h.update(m.to_le_bytes());
    }
    let plan = &model.plan;
    let setup = (
        &plan.gear,
        &plan.hob,
        &plan.machine,
        model.model.blank_od_mm,
        &model.geometry,
        &model.model.crowning,
        &model.model.units,
    );
    // Plain data always encodes; an empty slice would still key the rest.
    h.update(rmp_serde::to_vec(&setup).unwrap_or_default());
    h.finalize().into()
}

/// One timed run of `trace` on the virtual machine: its report (with the
/// wall time), and the run of every gear of the part for its charts; a
/// program the simulator cannot run gets a report that says why, and no
/// run.
pub fn run(
    trace: &Trace,
    model: &MachiningModel,
    settings: &Settings,
) -> (SimulationReport, Vec<Simulation>) {
    let started = tokio::time::Instant::now();
    match simulate_part(trace, model, settings) {
        Ok(gears) => {
            let report = part_report(&gears, started.elapsed().as_secs_f64() * 1e3);
            (report, gears)
        }
        Err(e) => (unsimulated(settings, &e.to_string()), Vec::new()),
    }
}

/// The report of a program the simulator could not run.
fn unsimulated(settings: &Settings, why: &str) -> SimulationReport {
    SimulationReport {
        mode: settings.mode.to_string(),
        what_if: Vec::new(),
        grade: None,
        required_grade: 0,
        deviations: Vec::new(),
        not_measured: Some(format!("the program could not be simulated: {why}")),
        safety: Vec::new(),
        sections: 0,
        samples_per_section: 0,
        passes: 0,
        thickness_mm: None,
        span_mm: None,
        over_balls_mm: None,
        ms: 0.0,
        unit: None,
        note: None,
        units: Vec::new(),
    }
}

/// The errors that stop a simulated program: every safety finding
/// (`SIMULATION_UNSAFE`), and a gear visibly wrong (`SIMULATED_GEAR_WRONG`):
/// one that cannot be measured as the drawing's gear (a wrong tooth count,
/// a gap not cut), a helix beyond class 11 (a wrong hand or lead), or pitch
/// deviations beyond the drawing's class. A grade worse than the drawing's
/// in the other items is a warning, not an error ([`grade_warning`]).
pub fn simulation_errors(program: &NcProgram) -> Vec<JobError> {
    match &program.simulation {
        Some(sim) => errors_of(&program.name, sim),
        None => Vec::new(),
    }
}

/// The errors of the simulation `sim` of program `name`.
fn errors_of(name: &str, sim: &SimulationReport) -> Vec<JobError> {
    let mut errors: Vec<JobError> = sim
        .safety
        .iter()
        .map(|f| {
            Stage::Template.error(
                Code::SIMULATION_UNSAFE,
                &format!("program.line.{}", f.line),
                "a program whose virtual run is safe",
                f.kind.clone(),
                format!(
                    "program {} line {}: {}; {}; the program was not sent",
                    name, f.line, f.what, f.why
                ),
            )
        })
        .collect();
    for gear in sim.every_gear() {
        errors.extend(gear_errors(name, gear));
    }
    errors
}

/// How a gear of the part is named in a message: "the gear", or its unit.
fn gear_name(gear: &SimulationReport) -> String {
    match &gear.unit {
        Some(u) => format!("the gear \"{u}\""),
        None => "the gear".to_string(),
    }
}

/// The errors of one gear of the simulation of program `name`: it cannot
/// be measured, its helix is beyond class 11, its pitch beyond its class.
fn gear_errors(name: &str, sim: &SimulationReport) -> Vec<JobError> {
    let mut errors = Vec::new();
    let gear = gear_name(sim);
    if let Some(why) = &sim.not_measured {
        errors.push(Stage::Template.error(
            Code::SIMULATED_GEAR_WRONG,
            "simulation",
            "a gear that measures as the drawing's",
            why.clone(),
            format!(
                "program {}: {gear} its virtual run cuts cannot be measured as the drawing's gear ({why}); the program was not sent",
                name
            ),
        ));
    }
    // A gear graded as an indication only (its note says why: a worm
    // wheel) is not stopped by its classes.
    let graded = sim.note.is_none();
    for d in sim.deviations.iter().filter(|_| graded) {
        let helix = d.item == "fHβ" && d.class.is_none();
        let pitch =
            (d.item == "fp" || d.item == "Fp") && d.class.unwrap_or(12) > sim.required_grade;
        if helix || pitch {
            errors.push(Stage::Template.error(
                Code::SIMULATED_GEAR_WRONG,
                &format!("simulation.{}", d.item),
                if helix {
                    "a helix within class 11 (the drawing's hand and lead)".to_string()
                } else {
                    format!("{} within class {}", d.item, sim.required_grade)
                },
                format!("{:.1} µm ({})", d.value_um, class_text(d.class)),
                format!(
                    "program {}: {gear} its virtual run cuts has {} {:.1} µm, {} against the drawing's class {}; the program was not sent",
                    name,
                    d.item,
                    d.value_um,
                    class_text(d.class),
                    sim.required_grade
                ),
            ));
        }
    }
    errors
}

/// The warnings of a program's virtual run for the planner: a predicted
/// grade worse than the drawing's ([`grade_warning`]), for each gear of the
/// part; when feed marks set it (ffβ, Fβ or Fr) and the finish feeds faster
/// than the knowledge base's feed for the class, that feed too
/// ([`feed_advice`]).
pub fn warnings(
    program: &NcProgram,
    model: Option<&MachiningModel>,
) -> Vec<gearcam_proto::model::Warning> {
    let Some(sim) = &program.simulation else {
        return Vec::new();
    };
    let advice = model.and_then(feed_advice);
    sim.every_gear()
        .filter_map(|gear| {
            let message = grade_warning(gear)?;
            let by_feed = gear
                .limiting()
                .is_some_and(|d| FEED_MARK_ITEMS.contains(&d.item.as_str()));
            Some(match (&advice, by_feed) {
                (Some(a), true) => format!("{message}; {a}"),
                _ => message,
            })
        })
        .map(|message| gearcam_proto::model::Warning {
            code: Code::PREDICTED_GRADE,
            field: "simulation.grade".into(),
            message,
        })
        .collect()
}

/// The graded items the feed marks add to (docs/knowledge.md).
const FEED_MARK_ITEMS: [&str; 3] = ["ffβ", "Fβ", "Fr"];

/// The knowledge base's finishing feed for the drawing's class, when it
/// held its proposal to the class (source `grade`) and the program's
/// finishing cut feeds faster (the planner's own feed, kept as the
/// planner's decision).
pub fn feed_advice(model: &MachiningModel) -> Option<String> {
    let plan = &model.plan;
    let key = if plan.process.cuts > 1 {
        "finish_feed_mm_per_rev"
    } else {
        "feed_mm_per_rev"
    };
    let proposed = plan.proposal.values.get(key)?;
    let used = model.model.cuts.last()?.feed_mm_per_rev;
    (proposed.source == Source::Grade && used > proposed.value + 1e-9).then(|| {
        format!(
            "for class {} the knowledge base proposes a finishing feed of at most {:.2} mm/rev, the program's finish feeds {:.2} mm/rev",
            plan.gear.quality_grade, proposed.value, used
        )
    })
}

/// The warning for a predicted grade of one gear worse than its drawing's,
/// naming the deviation that sets it (and the gear, on a part of several).
pub fn grade_warning(sim: &SimulationReport) -> Option<String> {
    let d = sim.limiting()?;
    let worse = sim.grade.is_none_or(|g| g > sim.required_grade);
    let of = sim
        .unit
        .as_ref()
        .map_or(String::new(), |u| format!(" of the gear \"{u}\""));
    // The tolerance a deviation carries is that of the class it meets.
    let met = match d.class {
        Some(c) => format!("class {c} allows {:.1} µm", d.tolerance_um),
        None => format!("beyond class 11's {:.1} µm", d.tolerance_um),
    };
    worse.then(|| {
        format!(
            "the predicted class{of} ({}) is worse than the drawing's class {}: {} is {:.1} µm ({met})",
            class_text(sim.grade),
            sim.required_grade,
            d.item,
            d.value_um,
        )
    })
}

fn class_text(class: Option<u8>) -> String {
    match class {
        Some(c) => format!("class {c}"),
        None => "worse than class 11".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gearcam_proto::simulation::{Deviation, SafetyIssue};

    fn deviation(item: &str, class: Option<u8>) -> Deviation {
        Deviation {
            item: item.into(),
            value_um: 3.0,
            tolerance_um: 3.5,
            class,
        }
    }

    /// A measured gear of the drawing's class 7 with `deviations`.
    fn report(deviations: Vec<Deviation>) -> SimulationReport {
        let worst = deviations.iter().map(|d| d.class.unwrap_or(12)).max();
        SimulationReport {
            grade: worst.filter(|c| *c <= 11),
            required_grade: 7,
            deviations,
            not_measured: None,
            ..unsimulated(&Settings::coarse(), "-")
        }
    }

    fn codes(errors: &[JobError]) -> Vec<(Code, String)> {
        errors.iter().map(|e| (e.code, e.field.clone())).collect()
    }

    /// On a part of several gears every gear is held to its drawing, and
    /// the messages name the gear.
    #[test]
    fn every_gear_of_a_part_is_held_to_its_class() {
        let mut part = report(vec![deviation("fp", Some(4))]);
        part.unit = Some("unit 1".into());
        let mut upper = report(vec![deviation("fp", Some(9)), deviation("ffα", Some(8))]);
        upper.unit = Some("upper gear".into());
        part.units.push(upper);
        assert_eq!(part.part_grade(), Some(9));
        let errors = errors_of("P", &part);
        assert_eq!(
            codes(&errors),
            vec![(Code::SIMULATED_GEAR_WRONG, "simulation.fp".to_string())]
        );
        assert!(errors[0].message.contains("\"upper gear\""), "{errors:?}");
        let w: Vec<String> = part.every_gear().filter_map(grade_warning).collect();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].contains("\"upper gear\""), "{w:?}");
    }

    /// A gear graded only as an indication (a worm wheel, whose note says
    /// so) is not stopped by its pitch, but its class still warns.
    #[test]
    fn an_indicative_grade_warns_and_does_not_stop() {
        let mut wheel = report(vec![deviation("fp", Some(9))]);
        assert_eq!(codes(&errors_of("P", &wheel)).len(), 1);
        wheel.note = Some("a worm wheel: an indication".into());
        assert!(errors_of("P", &wheel).is_empty());
        assert!(grade_warning(&wheel).is_some());
    }

    /// Within the drawing's class: no error, no warning.
    #[test]
    fn a_gear_within_its_class_passes_quietly() {
        let r = report(vec![deviation("fp", Some(4)), deviation("fHα", Some(7))]);
        assert!(errors_of("P", &r).is_empty());
        assert_eq!(grade_warning(&r), None);
    }

    /// A profile worse than the drawing is a warning naming it; a pitch
    /// worse than the drawing, a helix beyond class 11, a gear that does
    /// not measure and every safety finding stop the program.
    #[test]
    fn what_stops_a_program_and_what_warns() {
        let r = report(vec![deviation("fp", Some(4)), deviation("fHα", Some(9))]);
        assert!(errors_of("P", &r).is_empty());
        let w = grade_warning(&r).expect("a warning");
        assert!(w.contains("fHα") && w.contains("class 9"), "{w}");
        // The tolerance given is the class the item meets, said as such.
        assert!(w.contains("fHα is 3.0 µm (class 9 allows 3.5 µm)"), "{w}");

        let r = report(vec![deviation("Fp", Some(8)), deviation("fHβ", None)]);
        assert_eq!(
            codes(&errors_of("P", &r)),
            vec![
                (Code::SIMULATED_GEAR_WRONG, "simulation.Fp".to_string()),
                (Code::SIMULATED_GEAR_WRONG, "simulation.fHβ".to_string())
            ]
        );
        // A helix worse than the drawing but within class 11 warns only.
        let r = report(vec![deviation("fHβ", Some(10))]);
        assert!(errors_of("P", &r).is_empty());
        assert!(grade_warning(&r).is_some());

        let mut r = report(vec![]);
        r.not_measured = Some("21 gaps, not 25".into());
        r.safety.push(SafetyIssue {
            kind: "rapid_contact".into(),
            line: 31,
            what: "the hob enters the blank 2.0 mm".into(),
            why: "a rapid through material breaks the hob".into(),
        });
        let errors = errors_of("P", &r);
        assert_eq!(
            codes(&errors),
            vec![
                (Code::SIMULATION_UNSAFE, "program.line.31".to_string()),
                (Code::SIMULATED_GEAR_WRONG, "simulation".to_string())
            ]
        );
        assert!(
            errors[0].message.contains("line 31"),
            "{}",
            errors[0].message
        );
    }

    /// The same motion on the same set-up is the same simulation; another
    /// gear is another.
    #[test]
    fn the_key_is_the_motion_and_the_set_up() {
        let trace = Trace::default();
        let json = include_str!("../../../crates/nc/tests/programs/spur_840d.model.json");
        let model: MachiningModel = serde_json::from_str(json).expect("model");
        let mut other = model.clone();
        let fine = Settings::fine();
        let key = |t: &Trace, m: &MachiningModel| key_of(t, m, &fine);
        assert_eq!(key(&trace, &model), key(&trace, &other));
        other.plan.gear.teeth += 1;
        assert_ne!(key(&trace, &model), key(&trace, &other));
        // The crowning and the other gears of the part are the set-up too.
        let mut crowned = model.clone();
        crowned.model.crowning = Some(gearcam_proto::model::CrowningModel {
            shape: Default::default(),
            amount_mm: 0.02,
            radius_mm: None,
            chords: 1,
            tolerance_mm: 0.001,
            max_deviation_mm: 0.0,
        });
        assert_ne!(key(&trace, &model), key(&trace, &crowned));
        let mut moved = Trace::default();
        moved.spindle_rpm.push((12, 300.0));
        assert_ne!(key(&trace, &model), key(&moved, &model));
        // Every number of a move counts, down to its last bit.
        let (_, real) = gearcam_nc::check(
            include_str!("../../../crates/nc/tests/programs/spur_840d.nc"),
            &model,
        );
        assert!(!real.moves.is_empty());
        let mut nudged = real.clone();
        let last = nudged.moves.last_mut().expect("a move");
        last.z_mm = f64::from_bits(last.z_mm.to_bits() + 1);
        assert_ne!(key(&real, &model), key(&nudged, &model));
        // An arc is not its chord.
        let mut arced = real.clone();
        let last = arced.moves.last_mut().expect("a move");
        last.arc = Some(gearcam_nc::TraceArc {
            centre_z_mm: last.z_mm,
            centre_x_mm: last.x_mm - 1e4,
            sweep_rad: 1e-3,
        });
        assert_ne!(key(&real, &model), key(&arced, &model));
        assert_eq!(key(&real, &model), key(&real.clone(), &model));
        assert_ne!(
            key(&trace, &model),
            key_of(&trace, &model, &Settings::coarse())
        );
        // One run whatever the threads it used.
        let fine = Settings::fine();
        assert_eq!(
            key_of(&trace, &model, &Settings { threads: 1, ..fine }),
            key_of(&trace, &model, &Settings { threads: 3, ..fine })
        );
    }
}
