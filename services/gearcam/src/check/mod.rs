//! `gearcam check`: the whole computation done locally, without the bus —
//! knowledge (from the local database), model, template — and its report, as
//! JSON (a contract other tools read) or for a person.
//!
//! One module per family runs its pipeline into the one [`CheckReport`]
//! ([`hobbing`], [`spiral`], [`wire`]); [`check`] picks it by the job's
//! family, the only place here that tells families apart; [`human`] writes
//! the report for a person; [`picture_hobbing`] draws a hobbing job's
//! set-up and path.

use std::collections::BTreeMap;

use gearcam_proto::plan::HobChoice;
use gearcam_proto::{
    CoverageCheck, Family, Geometry, GrooveFigures, JobError, JobRequest, Kinematics, MillData,
    Source, Sourced, SpiralCut, SpiralFigures, SpiralModel, Stage, TemplateRef, Warning, WireModel,
    WorkpieceRef,
};
use gearcam_template::Templates;
use gearcam_wire::programs::Made;
use rusqlite::Connection;
use serde::Serialize;

pub mod hobbing;
pub mod human;
pub mod picture_hobbing;
pub mod picture_simulation;
pub mod spiral;
pub mod wire;

pub use human::{format_errors, format_human};
pub use picture_hobbing::hobbing_svg;
pub use spiral::spiral_picture;
pub use wire::die_drawings;

/// The job as checked.
#[derive(Debug, Clone, Serialize)]
pub struct JobSummary {
    /// Job id.
    pub id: String,
    /// Machine.
    pub machine: String,
    /// Part number.
    pub part_number: String,
    /// Quantity.
    pub quantity: u32,
}

/// A knowledge-base record used by the plan.
#[derive(Debug, Clone, Serialize)]
pub struct CaseSummary {
    /// Record id.
    pub id: String,
    /// Similarity, 0–1.
    pub similarity: f64,
    /// Provenance of its values.
    pub provenance: String,
}

pub(crate) fn case_summaries(cases: &[gearcam_proto::CaseRef]) -> Vec<CaseSummary> {
    cases
        .iter()
        .map(|c| CaseSummary {
            id: c.id.clone(),
            similarity: c.similarity,
            provenance: c.provenance.clone(),
        })
        .collect()
}

/// The machine a plan is for, in brief.
#[derive(Debug, Clone, Serialize)]
pub struct MachineSummary {
    /// Machine id, e.g. `H02`.
    pub id: String,
    /// Human name.
    pub name: String,
    /// Controller dialect, e.g. `sinumerik840d` or `fanuc`.
    pub dialect: String,
}

impl MachineSummary {
    pub(crate) fn of(
        id: &gearcam_proto::MachineId,
        name: &str,
        dialect: gearcam_proto::Dialect,
    ) -> Self {
        MachineSummary {
            id: id.to_string(),
            name: name.to_string(),
            dialect: dialect.as_str().into(),
        }
    }
}

/// The process plan in brief.
#[derive(Debug, Clone, Serialize)]
pub struct PlanSummary {
    /// Group-technology class.
    pub class: String,
    /// The machine, and so the dialect of the program.
    pub machine: MachineSummary,
    /// Hob chosen.
    pub hob_id: String,
    /// Confidence of the proposal.
    pub confidence: f64,
    /// Records used.
    pub cases: Vec<CaseSummary>,
    /// Every decided value with its source: `job` (the job file's override),
    /// `case` (proposed from retrieved cases), `machine` (the machine profile,
    /// or a proposal clamped to its limits), `default`, `grade` (a finishing
    /// feed held to the drawing's class), or `library` (the drawing data
    /// `gear.*` of a part from the workpiece library).
    pub values: BTreeMap<String, Sourced>,
    /// What the knowledge base proposed for each value, before the job's overrides.
    pub proposed: BTreeMap<String, Sourced>,
    /// The values the job overrode.
    pub overridden: Vec<String>,
    /// The mill (spiral face milling; absent for hobbing, whose tool is `hob_id`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool: Option<MillData>,
    /// How the hob was chosen (absent when the job named or gave its hob).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub hob_choice: Option<HobChoice>,
    /// The workpiece library's record of the part: whether it supplied the
    /// drawing data (values `gear.*` from `library`) or the job's `[gear]`
    /// replaced it. Absent when the part is not in the library.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub workpiece: Option<WorkpieceRef>,
}

impl PlanSummary {
    /// The plan of a family whose decided values each carry their source:
    /// the job's are the overridden ones, the rest the proposal.
    pub(crate) fn of_sourced(
        class: String,
        machine: MachineSummary,
        tool_id: String,
        confidence: f64,
        cases: &[gearcam_proto::CaseRef],
        values: BTreeMap<String, Sourced>,
        tool: Option<MillData>,
    ) -> PlanSummary {
        PlanSummary {
            class,
            machine,
            hob_id: tool_id,
            confidence,
            cases: case_summaries(cases),
            overridden: values
                .iter()
                .filter(|(_, v)| v.source == Source::Job)
                .map(|(k, _)| k.clone())
                .collect(),
            proposed: values
                .iter()
                .filter(|(_, v)| v.source != Source::Job)
                .map(|(k, v)| (k.clone(), *v))
                .collect(),
            values,
            tool,
            hob_choice: None,
            workpiece: None,
        }
    }
}

/// The program in brief, with its text.
#[derive(Debug, Clone, Serialize)]
pub struct ProgramSummary {
    /// Program name.
    pub name: String,
    /// Dialect: the controller's (`sinumerik840d`, `fanuc`) for hobbing;
    /// the program form (`fanuc-macro`, `fanuc-arcs`, `fanuc-chords`,
    /// `linuxcnc`) for spiral face milling, (`3b`, `4b`, `iso-wire`) for
    /// wire EDM.
    pub dialect: String,
    /// Template that made it.
    pub template: TemplateRef,
    /// SHA-256 of the text.
    pub sha256: String,
    /// The path check of the text: `ok` and every finding (line, rule, message).
    /// A program whose check is not ok is shown here but never sent.
    pub path_check: gearcam_proto::PathCheck,
    /// The program.
    pub text: String,
}

/// The model of either family, as reported.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum ModelReport {
    /// Hobbing: the kinematics (its fields at the top of `model`).
    Hobbing(Box<Kinematics>),
    /// Spiral face milling.
    Spiral(Box<SpiralReport>),
    /// Wire EDM: `model.die`.
    Wire(Box<WireReport>),
}

impl ModelReport {
    /// The hobbing kinematics, if this is a hobbing model.
    pub fn hobbing(&self) -> Option<&Kinematics> {
        match self {
            ModelReport::Hobbing(k) => Some(k),
            ModelReport::Spiral(_) | ModelReport::Wire(_) => None,
        }
    }
}

/// A wire job's model (`model` in the JSON report).
#[derive(Debug, Clone, Serialize)]
pub struct WireReport {
    /// The die's figures and the program's certificate.
    pub die: gearcam_proto::DieFigures,
}

/// A spiral job's model (`model` in the JSON report).
#[derive(Debug, Clone, Serialize)]
pub struct SpiralReport {
    /// The spiral's figures; the face's centre is the origin.
    pub spiral: SpiralFigures,
    /// The cutting data.
    pub cut: SpiralCut,
    /// A groove's width, pitch and land.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub groove: Option<GrooveFigures>,
    /// Cutting time of one part, min.
    pub part_time_min: f64,
}

/// The report of `gearcam check` (JSON contract: keep these names).
#[derive(Debug, Clone, Serialize)]
pub struct CheckReport {
    /// True when a program was produced without errors.
    pub ok: bool,
    /// The command's exit code when not ok (the shape of every failure:
    /// `ok`, `exit`, `errors`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exit: Option<u8>,
    /// Every error found, each with stage, code, field, expected, got, message.
    pub errors: Vec<JobError>,
    /// Warnings.
    pub warnings: Vec<Warning>,
    /// The job.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub job: Option<JobSummary>,
    /// The plan.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plan: Option<PlanSummary>,
    /// Gear geometry.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geometry: Option<Geometry>,
    /// Machining model: the hobbing kinematics, the spiral's figures
    /// (`model.spiral`, `model.cut`, `model.groove`, `model.part_time_min`),
    /// or the die's figures and certificate (`model.die`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelReport>,
    /// The coverage check of a spiral face (or the pitch check of a groove)
    /// and the program's largest deviation from the spiral.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coverage: Option<CoverageCheck>,
    /// Where the SVG picture of the job was written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub picture: Option<String>,
    /// Where the DXF of a wire job's outline was written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drawing: Option<String>,
    /// The NC program.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<ProgramSummary>,
    /// The hobbing program's virtual run: the gear it cuts, measured and
    /// graded (`grade`, `deviations`), the run's `safety` findings,
    /// `sections`, `ms`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub simulation: Option<gearcam_proto::SimulationReport>,
    /// Why a hobbing program was not simulated, when it was not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_simulated: Option<String>,
    /// Where the simulated gear's measuring charts (SVG) were written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub simulation_picture: Option<String>,
}

impl CheckReport {
    /// A report of errors only (e.g. an unreadable job file).
    pub fn failed(errors: Vec<JobError>) -> CheckReport {
        CheckReport {
            ok: false,
            exit: None,
            errors,
            warnings: vec![],
            job: None,
            plan: None,
            geometry: None,
            model: None,
            coverage: None,
            picture: None,
            drawing: None,
            program: None,
            simulation: None,
            not_simulated: None,
            simulation_picture: None,
        }
    }
}

pub(crate) fn job_summary(req: &JobRequest) -> CheckReport {
    let spec = &req.spec;
    let mut report = CheckReport::failed(vec![]);
    report.job = Some(JobSummary {
        id: req.job_id.to_string(),
        machine: spec.job.machine.to_string(),
        part_number: spec.job.part_number.clone(),
        quantity: spec.job.quantity,
    });
    report
}

/// The model of a job that has a picture.
#[derive(Debug, Clone)]
pub enum Drawing {
    /// A hobbing job's, with the virtual run of each of its gears when
    /// there was one.
    Hobbing(
        Box<gearcam_proto::MachiningModel>,
        Vec<gearcam_hobsim::simulate::Simulation>,
    ),
    /// A spiral job's.
    Spiral(Box<SpiralModel>),
    /// A wire job's, with its die as made (outline, path, program).
    Wire(Box<WireModel>, Box<Made>),
}

/// Runs knowledge → model → program locally for one request of any
/// family; the job's model comes back too (for its picture). A hobbing
/// program is run on the virtual machine with `simulation`, when given.
pub fn check(
    conn: &Connection,
    templates: &Templates,
    req: &JobRequest,
    simulation: Option<&gearcam_hobsim::simulate::Settings>,
) -> (CheckReport, Option<Drawing>) {
    let report = job_summary(req);
    match req.spec.family() {
        Family::Hobbing => {
            let (r, m, sim) = hobbing::check_hobbing(conn, templates, req, report, simulation);
            (r, m.map(|m| Drawing::Hobbing(Box::new(m), sim)))
        }
        Family::SpiralFace => {
            let (r, m) = spiral::check_spiral(conn, req, report);
            (r, m.map(|m| Drawing::Spiral(Box::new(m))))
        }
        Family::WireEdm => {
            let (r, m) = wire::check_wire(conn, req, report);
            (
                r,
                m.map(|(model, made)| Drawing::Wire(Box::new(model), Box::new(made))),
            )
        }
    }
}

/// The stage a check error belongs to, for exit codes and summaries.
pub fn first_stage(r: &CheckReport) -> Option<Stage> {
    r.errors.first().map(|e| e.stage)
}

#[cfg(test)]
mod tests {
    use super::Drawing;
    use super::*;
    use gearcam_proto::SpiralPart;

    /// Every valid hobbing example of `examples/` moved to machine H02 (FANUC).
    fn examples_on_h02() -> Vec<(String, String)> {
        gearcam_testkit::examples::valid_hobbing()
            .into_iter()
            .map(|(name, text)| {
                let text = gearcam_testkit::examples::on_machine(&text, "H02");
                (name, text)
            })
            .collect()
    }

    fn check_example(name: &str) -> CheckReport {
        let path = gearcam_testkit::examples::dir().join(name);
        let spec = crate::jobfile::load(&path).unwrap();
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        check(
            &conn,
            &Templates::builtin(),
            &crate::jobfile::request(spec),
            None,
        )
        .0
    }

    /// The knowledge base holds a finishing feed to what the drawing's
    /// class allows, and the virtual run checks the bound: the spur example
    /// drawn to class 4 is planned below its cases' 2 mm/rev, with the
    /// source `grade`, and its program cuts a gear of class 4 or better; in
    /// two cuts the rough cut keeps the cases' feed and the finish runs at
    /// the bound, and the gear is as good. The planner's own 3 mm/rev is
    /// kept (the planner's decision, the bound still shown as proposed) and
    /// cuts a gear worse than class 4; the warning names the item the feed
    /// marks set and the knowledge base's feed for the class.
    #[test]
    fn a_finishing_feed_is_held_to_the_class_and_the_virtual_run_confirms_it() {
        let example = gearcam_testkit::examples::example("spur_840d.toml");
        let class4 = example.replace("quality_grade = 7 ", "quality_grade = 4 ");
        assert_ne!(class4, example);
        let run = |text: &str| {
            let spec = crate::jobfile::parse(text, "spur_class4.toml").unwrap();
            let conn = gearcam_knowledge::db::open_in_memory().unwrap();
            let settings = gearcam_hobsim::simulate::Settings::fine();
            let req = crate::jobfile::request(spec);
            check(&conn, &Templates::builtin(), &req, Some(&settings)).0
        };
        let finish_feed = |r: &CheckReport| {
            let k = r.model.as_ref().unwrap().hobbing().unwrap();
            k.cuts.last().unwrap().feed_mm_per_rev
        };
        let bounded = run(&class4);
        assert!(bounded.ok, "{}", format_errors(&bounded.errors));
        let feed = bounded.plan.as_ref().unwrap().values["feed_mm_per_rev"];
        assert_eq!(feed.source, Source::Grade);
        assert!(feed.value > 1.0 && feed.value < 1.5, "{feed:?}");
        assert_eq!(finish_feed(&bounded), feed.value);
        let sim = bounded.simulation.as_ref().expect("simulated");
        assert!(sim.grade.is_some_and(|g| g <= 4), "{sim:?}");
        assert!(bounded.warnings.is_empty(), "{:?}", bounded.warnings);

        let two_cuts = class4.replace("cuts = 1 ", "cuts = 2 ");
        assert_ne!(two_cuts, class4);
        let two = run(&two_cuts);
        assert!(two.ok, "{}", format_errors(&two.errors));
        let values = &two.plan.as_ref().unwrap().values;
        assert_eq!(values["feed_mm_per_rev"].source, Source::Case);
        assert_eq!(values["finish_feed_mm_per_rev"], feed);
        assert_eq!(finish_feed(&two), feed.value);
        let sim = two.simulation.as_ref().expect("simulated");
        assert!(sim.grade.is_some_and(|g| g <= 4), "{sim:?}");

        let planners = class4.replace("# feed_mm_per_rev = 2.0 ", "feed_mm_per_rev = 3.0 #");
        assert_ne!(planners, class4);
        let unbounded = run(&planners);
        let plan = unbounded.plan.as_ref().unwrap();
        assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Job);
        assert_eq!(plan.proposed["feed_mm_per_rev"], feed);
        let sim = unbounded.simulation.as_ref().expect("simulated");
        assert!(sim.grade.is_some_and(|g| g > 4), "{sim:?}");
        let warning = unbounded
            .warnings
            .iter()
            .find(|w| w.code == gearcam_proto::Code::PREDICTED_GRADE)
            .expect("a grade warning");
        let item = sim.limiting().unwrap().item.as_str();
        assert!(["ffβ", "Fβ", "Fr"].contains(&item), "{item}");
        assert!(
            warning.message.contains(&format!("{item} is")),
            "{}",
            warning.message
        );
        let advice = format!(
            "finishing feed of at most {:.2} mm/rev, the program's finish feeds 3.00",
            feed.value
        );
        assert!(warning.message.contains(&advice), "{}", warning.message);
    }

    #[test]
    fn a_job_by_part_number_gets_the_model_of_the_same_job_with_its_gear_written_out() {
        let by_part = check_example("spur_by_part_840d.toml");
        let written = check_example("spur_840d.toml");
        assert!(by_part.ok, "{}", format_errors(&by_part.errors));
        assert!(written.ok, "{}", format_errors(&written.errors));
        assert_eq!(by_part.geometry, written.geometry);
        // The same kinematics; only the explanation's origins differ.
        let (mut a, mut b) = (
            by_part.model.unwrap().hobbing().unwrap().clone(),
            written.model.unwrap().hobbing().unwrap().clone(),
        );
        let origin = |k: &Kinematics, name: &str| {
            k.explain
                .iter()
                .find(|e| e.name == name)
                .map(|e| e.origin)
                .unwrap()
        };
        assert_eq!(origin(&a, "gear.module_mm"), gearcam_proto::Origin::Library);
        assert_eq!(origin(&b, "gear.module_mm"), gearcam_proto::Origin::Job);
        a.explain.clear();
        b.explain.clear();
        assert_eq!(a, b);
        let (pa, pb) = (by_part.plan.unwrap(), written.plan.unwrap());
        assert_eq!(pa.cases.len(), pb.cases.len());
        for name in ["cutting_speed_m_min", "feed_mm_per_rev", "cuts"] {
            assert_eq!(pa.values[name], pb.values[name], "{name}");
        }
        assert_eq!(pa.values["gear.teeth"].source, Source::Library);
        assert!(pa.workpiece.as_ref().unwrap().supplied_gear);
        // The written-out job names the same part: the record is found, the
        // job's [gear] wins, and it differs in nothing.
        let w = pb.workpiece.unwrap();
        assert!(!w.supplied_gear && w.differs.is_empty(), "{w:?}");
        // Both programs are the same but for the header's job id and the
        // second it was submitted in (two checks can straddle a second).
        let (ta, tb) = (by_part.program.unwrap().text, written.program.unwrap().text);
        let body = |t: &str| {
            t.lines()
                .filter(|l| !l.contains("JOB") && !l.contains("job") && !l.contains("SUBMITTED"))
                .map(str::to_string)
                .collect::<Vec<_>>()
        };
        assert_eq!(body(&ta), body(&tb));
    }

    /// Regression: the seeded workpiece HG-3003-L lacked the profile shift of
    /// its example job, so the job's [gear] differed from the library.
    #[test]
    fn every_example_that_names_a_library_part_agrees_with_the_library() {
        let mut named = 0;
        for name in [
            "spur_840d.toml",
            "helical_840d.toml",
            "helical_climb_840d.toml",
        ] {
            let report = check_example(name);
            let w = report.plan.unwrap().workpiece.unwrap();
            assert!(w.differs.is_empty(), "{name}: {w:?}");
            named += 1;
        }
        assert_eq!(named, 3);
    }

    #[test]
    fn a_job_by_an_unknown_part_number_without_gear_is_refused_naming_the_gear() {
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let spec = crate::jobfile::parse(
            "[job]\nmachine = \"H01\"\npart_number = \"XX-9\"\n",
            "t.toml",
        )
        .unwrap();
        let report = check(
            &conn,
            &Templates::builtin(),
            &crate::jobfile::request(spec),
            None,
        )
        .0;
        assert!(!report.ok);
        assert!(report.geometry.is_none() && report.plan.is_none());
        let e = &report.errors[0];
        assert_eq!(
            (e.stage, e.code.as_str(), e.field.as_str()),
            (Stage::Knowledge, "GEAR_MISSING", "gear")
        );
        assert!(e.got.contains("XX-9"), "{}", e.got);
    }

    /// Every spiral example of `examples/` through knowledge, model and
    /// program: a valid one is covered, replays onto its model and is in
    /// its machine's form; an invalid one gets the code it names.
    #[test]
    fn every_spiral_example_runs_or_fails_with_its_named_error() {
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let templates = Templates::builtin();
        let mut forms = std::collections::BTreeSet::new();
        let mut kinds = std::collections::BTreeSet::new();
        let spiral: Vec<_> = gearcam_testkit::examples::all()
            .into_iter()
            .filter(|(_, t)| gearcam_testkit::examples::is_spiral(t))
            .collect();
        assert!(spiral.len() >= 10, "{} spiral examples", spiral.len());
        for (name, text) in spiral {
            let spec = crate::jobfile::parse(&text, &name).unwrap();
            let (report, model) = check(&conn, &templates, &crate::jobfile::request(spec), None);
            match gearcam_testkit::examples::expected_code(&text) {
                Some(code) => assert!(
                    report.errors.iter().any(|e| e.code == code),
                    "{name}: expected {code}: {}",
                    format_errors(&report.errors)
                ),
                None => {
                    assert!(report.ok, "{name}: {}", format_errors(&report.errors));
                    let Some(Drawing::Spiral(model)) = model else {
                        panic!("{name}: no spiral model")
                    };
                    assert!(report.coverage.unwrap().ok, "{name}");
                    let p = report.program.unwrap();
                    assert!(p.path_check.ok, "{name}");
                    forms.insert(p.dialect.clone());
                    kinds.insert(
                        match (&model.plan.part, model.spiral.inner_radius_mm > 0.0) {
                            (SpiralPart::Groove(_), _) => "groove",
                            (_, true) => "annulus",
                            (_, false) => "circle",
                        },
                    );
                    // The picture shows the path and, for a face, the region.
                    let svg = spiral_picture(&model);
                    assert!(svg.starts_with("<svg") && svg.contains("<path"), "{name}");
                }
            }
        }
        let all_forms: Vec<&str> = gearcam_proto::SpiralProgram::ALL
            .iter()
            .map(|f| f.as_str())
            .collect();
        assert_eq!(forms.iter().map(String::as_str).collect::<Vec<_>>(), {
            let mut v = all_forms.clone();
            v.sort();
            v
        });
        assert_eq!(
            kinds.into_iter().collect::<Vec<_>>(),
            ["annulus", "circle", "groove"]
        );
    }

    /// The JSON contract of a spiral job: `model.spiral` with the region,
    /// the tool and the tool-centre spiral, `coverage`, `program.dialect`.
    #[test]
    fn a_spiral_report_has_the_spiral_the_coverage_and_the_form_in_json() {
        let report = check_example("face_circle_arcs_fanuc.toml");
        let v = serde_json::to_value(&report).unwrap();
        let s = &v["model"]["spiral"];
        for key in [
            "outer_radius_mm",
            "inner_radius_mm",
            "tool_radius_mm",
            "turns",
            "step_over_mm",
            "start_radius_mm",
            "end_radius_mm",
            "angle_step_deg",
            "path_length_mm",
            "blocks",
        ] {
            assert!(s[key].is_number(), "model.spiral.{key}: {s}");
        }
        assert_eq!(s["outer_radius_mm"], 90.0);
        assert_eq!(s["end_radius_mm"], 0.0, "a full circle ends at the centre");
        for key in ["ok", "max_gap_mm", "max_deviation_mm"] {
            assert!(!v["coverage"][key].is_null(), "coverage.{key}");
        }
        assert_eq!(v["program"]["dialect"], "fanuc-arcs");
        assert_eq!(v["plan"]["tool"]["id"], "FM-063");
    }

    #[test]
    fn every_example_on_the_fanuc_machine_h02_gets_a_fanuc_plan_and_a_model() {
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let templates = Templates::builtin();
        let all = examples_on_h02();
        assert!(all.len() >= 10, "{} examples", all.len());
        for (name, text) in all {
            let spec = crate::jobfile::parse(&text, &name).unwrap();
            let report = check(&conn, &templates, &crate::jobfile::request(spec), None).0;
            let plan = report
                .plan
                .as_ref()
                .unwrap_or_else(|| panic!("{name}: no plan: {}", format_errors(&report.errors)));
            assert_eq!(
                (plan.machine.id.as_str(), plan.machine.dialect.as_str()),
                ("H02", "fanuc"),
                "{name}"
            );
            assert!(
                report.model.is_some(),
                "{name} does not fit H02: {}",
                format_errors(&report.errors)
            );
            // Until the FANUC templates land the template stage refuses the
            // job; nothing before it may.
            assert!(
                report.errors.iter().all(|e| e.stage == Stage::Template),
                "{name}: {}",
                format_errors(&report.errors)
            );
            if let Some(p) = &report.program {
                assert_eq!(p.dialect, "fanuc", "{name}");
            }
        }
    }
}
