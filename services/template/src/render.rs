//! Rendering a machining model into an NC program through a compiled template.
//!
//! Pure: no I/O, no async, no clock. [`Templates`] compiles every template once
//! (the shipped standard code, [`crate::builtin`], plus any given at start) with
//! the expression-driven engine of [`crate::engine`]: every record's expressions
//! are compiled to slot-resolved trees, evaluation is bounded by a step budget
//! ([`DEFAULT_FUEL`]) and an output limit ([`MAX_PROGRAM_BYTES`]), and numbers
//! reach NC text only through the NC number functions (`nc`, `deg`, `factor`).
//!
//! [`Templates::render`] picks the template by (class, dialect), fills the
//! parameter table from the [`MachiningModel`], instantiates it, and returns the
//! [`NcProgram`] with its name under the controller's rules, hash and provenance.

use gearcam_proto::Code;
use std::collections::BTreeMap;

use gearcam_proto::{naming, Dialect, JobError, MachiningModel, NcProgram, Stage, TemplateRef};
use sha2::{Digest, Sha256};

use crate::engine::{Compiled, RunFailure};
use crate::error::TemplateError;
use crate::params::{PartInput, UnitInput};
use crate::simulation::{simulation_errors, Simulations};
use crate::stdcode::{self, TemplateFile};
use gearcam_hobsim::simulate::Settings;

/// The generator named in every program: this crate and its version.
pub const GENERATOR: &str = concat!("gearcam-template ", env!("CARGO_PKG_VERSION"));

/// Expression steps one render may take. The shipped templates need a few
/// thousand for the largest example; a runaway template stops here.
pub const DEFAULT_FUEL: u64 = crate::engine::STEP_BUDGET;

/// Largest program text a render may produce, bytes.
pub const MAX_PROGRAM_BYTES: usize = crate::engine::MAX_PROGRAM_BYTES;

pub use gearcam_proto::naming::{
    check_name_840d, program_name_840d, program_name_fanuc, MAX_840D_NAME as MAX_NAME_840D,
};

/// A template's source text with its id (`{class}_{dialect}`, e.g. `cylindrical_840d`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TemplateSource {
    /// Template id: the class, `_`, the dialect suffix (`840d`, `fanuc`).
    pub id: String,
    /// Source text in the standard-code format ([`crate::stdcode`]).
    pub source: String,
}

/// The compiled template library. Build it once at start; rendering borrows it.
#[derive(Debug, Clone)]
pub struct Templates {
    compiled: BTreeMap<String, Compiled>,
    budget: u64,
    simulations: Simulations,
    /// How hobbing programs are run on the virtual machine before they
    /// leave; `None` (the default of a library built here): not run. The
    /// services turn it on ([`crate::simulation::before_delivery`]);
    /// `gearcam check --simulate` runs it on demand.
    simulation: Option<Settings>,
}

impl Templates {
    /// The shipped templates only, with [`DEFAULT_FUEL`].
    pub fn builtin() -> Self {
        Self::new(Vec::new(), DEFAULT_FUEL)
            .expect("the shipped templates compile (checked by the unit tests)")
    }

    /// These templates with every hobbing program run on the virtual
    /// machine with `settings` before it is returned (`None`: not run), the
    /// report in the program and its blocking findings refused by
    /// [`Templates::render`].
    pub fn with_simulation(mut self, settings: Option<Settings>) -> Self {
        self.simulation = settings;
        self
    }

    /// The shipped templates plus `extra` (which replace shipped ones of the same
    /// id), each render bounded by `budget` expression steps.
    pub fn new(
        extra: impl IntoIterator<Item = TemplateSource>,
        budget: u64,
    ) -> Result<Self, TemplateError> {
        let mut files: BTreeMap<String, TemplateFile> = BTreeMap::new();
        for (name, text) in crate::builtin::builtin_sources() {
            let file = stdcode::parse(name, text).map_err(TemplateError::Format)?;
            files.insert(file.id.clone(), file);
        }
        Self::from_files(files.into_values(), budget)?.with(extra)
    }

    /// The templates of the template library at `path` (SQLite, created if
    /// missing): the shipped standard code is imported first wherever the
    /// library has no version as new as it (a shop's own later versions stay),
    /// then the latest version of every template is assembled from its
    /// components and compiled. `now_ms` stamps what is imported.
    pub fn from_library(
        path: &std::path::Path,
        budget: u64,
        now_ms: u64,
    ) -> Result<Self, TemplateError> {
        let lib_err = |e: crate::library::LibraryError| TemplateError::Library(e.to_string());
        let mut library = crate::library::Library::open(path).map_err(lib_err)?;
        let stored: BTreeMap<String, u32> = library
            .list()
            .map_err(lib_err)?
            .into_iter()
            .map(|t| (t.id, t.version))
            .collect();
        let mut files = Vec::new();
        let mut sources = Vec::new();
        for (name, text) in crate::builtin::builtin_sources() {
            let file = stdcode::parse(name, text).map_err(TemplateError::Format)?;
            if stored.get(&file.id).is_none_or(|v| *v < file.version) {
                files.push(file);
                sources.push(text);
            }
        }
        if !files.is_empty() {
            library.import(&files, &sources, now_ms).map_err(lib_err)?;
        }
        Self::from_files(library.latest_versions().map_err(lib_err)?, budget)
    }

    /// This library with `extra` templates compiled in, replacing those of the
    /// same id.
    pub fn with(
        mut self,
        extra: impl IntoIterator<Item = TemplateSource>,
    ) -> Result<Self, TemplateError> {
        for s in extra {
            let file = stdcode::parse(&s.id, &s.source).map_err(TemplateError::Format)?;
            if file.id != s.id {
                return Err(TemplateError::BadId {
                    id: s.id,
                    reason: format!("the file says @template {}", file.id),
                });
            }
            let c = Compiled::new(&file).map_err(TemplateError::Compile)?;
            self.compiled.insert(file.id, c);
        }
        Ok(self)
    }

    /// Compiles assembled templates (e.g. the latest versions from the template
    /// library) with no shipped ones added.
    pub fn from_files(
        files: impl IntoIterator<Item = TemplateFile>,
        budget: u64,
    ) -> Result<Self, TemplateError> {
        let mut compiled = BTreeMap::new();
        for f in files {
            let c = Compiled::new(&f).map_err(TemplateError::Compile)?;
            compiled.insert(f.id.clone(), c);
        }
        Ok(Templates {
            compiled,
            budget,
            simulations: Simulations::default(),
            simulation: None,
        })
    }

    /// Every template in the library, by id.
    pub fn list(&self) -> Vec<TemplateRef> {
        self.compiled
            .values()
            .map(|c| TemplateRef {
                id: c.id.clone(),
                version: c.version,
            })
            .collect()
    }

    /// The template for a (class, dialect) pair, if the library has one.
    pub fn find(&self, class: &str, dialect: Dialect) -> Option<TemplateRef> {
        self.compiled_for(class, dialect).map(|c| TemplateRef {
            id: c.id.clone(),
            version: c.version,
        })
    }

    /// The compiled template for a (class, dialect) pair.
    pub fn compiled_for(&self, class: &str, dialect: Dialect) -> Option<&Compiled> {
        self.compiled
            .get(&format!("{class}_{}", stdcode::dialect_suffix(dialect)))
            .filter(|c| c.dialect == dialect)
    }

    /// Renders the NC program of a machining model and checks its path: the
    /// program is returned only when the path check finds nothing.
    ///
    /// Errors are typed [`JobError`]s of stage `template`: those of
    /// [`Templates::instantiate`], and one `PATH_CHECK_FAILED` per finding, its
    /// field `program.line.N`, its `expected` the rule, its message the finding's.
    pub fn render(&self, model: &MachiningModel) -> Result<NcProgram, Vec<JobError>> {
        let program = self.instantiate(model)?;
        if !program.path_check.ok {
            return Err(path_check_errors(&program));
        }
        let unsafe_or_wrong = simulation_errors(&program);
        if unsafe_or_wrong.is_empty() {
            return Ok(program);
        }
        Err(unsafe_or_wrong)
    }

    /// Renders the NC program of a machining model and attaches its path check,
    /// whatever the check found (for `gearcam check`, which shows both).
    ///
    /// The template is chosen by the plan's class and the machine's dialect. Every
    /// error is a typed [`JobError`] of stage `template`: `TEMPLATE_NOT_FOUND`,
    /// `INVALID_AXIS_NAME`, `INVALID_COUPLING`, `TEMPLATE_FUEL_EXHAUSTED`,
    /// `PROGRAM_TOO_LARGE`, `TEMPLATE_RENDER_FAILED`, `INVALID_PROGRAM_NAME`.
    pub fn instantiate(&self, model: &MachiningModel) -> Result<NcProgram, Vec<JobError>> {
        let plan = &model.plan;
        let machine = &plan.machine;
        let Some(template) = self.compiled_for(plan.class.as_str(), machine.dialect) else {
            return Err(vec![self.not_found(model)]);
        };
        check_inputs(model)?;

        let part_number = &plan.request.spec.job.part_number;
        let (name, file) = naming::program_name(machine.dialect, &plan.request.spec.job, false)
            .map_err(|p| vec![p.error(Stage::Template, machine.dialect)])?;
        let case_ids: Vec<String> = plan.cases.iter().map(|c| c.id.clone()).collect();
        let cases = if case_ids.is_empty() {
            "NONE".to_string()
        } else {
            case_ids.join(" ")
        };
        let units = unit_inputs(model);
        let input = PartInput {
            model,
            gear: units[0].gear,
            program_name: &name,
            program_file: &file,
            template_id: &template.id,
            template_version: template.version,
            generator: GENERATOR,
            cases: &cases,
            units: &units,
        };
        let text = template.instantiate(&input, self.budget).map_err(|e| {
            let field = format!("template.{}", template.id);
            vec![match &e.error {
                RunFailure::TooLarge => Stage::Template.error(
                    Code::PROGRAM_TOO_LARGE,
                    &field,
                    format!("at most {MAX_PROGRAM_BYTES} bytes"),
                    format!("more than {MAX_PROGRAM_BYTES} bytes"),
                    format!("{e}; check the template for runaway repetition"),
                ),
                RunFailure::Eval(crate::expr::EvalError::Budget(n)) => Stage::Template.error(
                    Code::TEMPLATE_FUEL_EXHAUSTED,
                    &field,
                    format!("at most {n} expression steps"),
                    "more",
                    format!("{e}; check the template"),
                ),
                RunFailure::Eval(_) => Stage::Template.error(
                    Code::TEMPLATE_RENDER_FAILED,
                    &field,
                    "a template that instantiates with this model",
                    e.error.to_string(),
                    e.to_string(),
                ),
            }]
        })?;
        let (path_check, trace) = gearcam_nc::check(&text, model);
        // Only a program whose path holds is run on the virtual machine.
        let simulation = match (&self.simulation, path_check.ok) {
            (Some(settings), true) => self.simulations.report(&trace, model, settings),
            _ => None,
        };
        let sha256 = hex::encode(Sha256::digest(text.as_bytes()));
        tracing::debug!(job = %model.job_id, template = %template.id, %name, bytes = text.len(), "rendered");
        Ok(NcProgram {
            job_id: model.job_id.clone(),
            machine: machine.id.clone(),
            name,
            revision: 1,
            dialect: machine.dialect,
            text,
            sha256,
            template: TemplateRef {
                id: template.id.clone(),
                version: template.version,
            },
            part_number: part_number.clone(),
            cases: case_ids,
            model_version: model.model_version.clone(),
            generator: GENERATOR.to_string(),
            path_check,
            form: None,
            simulation,
        })
    }

    /// The error for a (class, dialect) pair without a template.
    fn not_found(&self, model: &MachiningModel) -> JobError {
        let plan = &model.plan;
        let dialect = plan.machine.dialect.as_str();
        let supported: Vec<String> = self
            .compiled
            .values()
            .map(|c| format!("{}/{}", c.class, c.dialect.as_str()))
            .collect();
        let class_known = self
            .compiled
            .values()
            .any(|c| c.class == plan.class.as_str());
        let (field, advice) = if class_known {
            (
                "job.machine",
                "choose a machine whose controller has a template for this class",
            )
        } else {
            (
                "class",
                "this class cannot be programmed yet; add its template to the template library",
            )
        };
        Stage::Template.error(
            Code::TEMPLATE_NOT_FOUND,
            field,
            format!("one of {}", supported.join(", ")),
            format!("{}/{dialect}", plan.class),
            format!(
                "no template for class {} on a {dialect} controller (machine {}); {advice}",
                plan.class, plan.machine.id
            ),
        )
    }
}

/// One `PATH_CHECK_FAILED` error per finding of a program's path check.
pub fn path_check_errors(program: &NcProgram) -> Vec<JobError> {
    program
        .path_check
        .findings
        .iter()
        .map(|f| {
            Stage::Template.error(
                Code::PATH_CHECK_FAILED,
                &format!("program.line.{}", f.line),
                format!("a program that keeps rule {}", f.rule),
                program
                    .text
                    .lines()
                    .nth(f.line as usize - 1)
                    .unwrap_or("")
                    .trim(),
                format!(
                    "program {} (template {} v{}) line {}: {} [{}]; the program was not sent",
                    program.name,
                    program.template.id,
                    program.template.version,
                    f.line,
                    f.message,
                    f.rule
                ),
            )
        })
        .collect()
}

/// The units to program: every unit of a multi-gear part, or the job's gear.
pub fn unit_inputs(model: &MachiningModel) -> Vec<UnitInput<'_>> {
    let plan = &model.plan;
    if model.model.units.is_empty() {
        return vec![UnitInput {
            name: "",
            z_offset_mm: 0.0,
            hob_change: false,
            gear: &plan.gear,
            hob: &plan.hob,
            kin: &model.model,
        }];
    }
    model
        .model
        .units
        .iter()
        .map(|u| UnitInput {
            name: &u.name,
            z_offset_mm: u.z_offset_mm,
            hob_change: u.hob_change,
            gear: &u.gear,
            hob: &u.hob,
            kin: &u.model,
        })
        .collect()
}

pub use gearcam_nc::number::format_fixed;

pub use crate::expr::comment_text;

/// Checks the values that go into NC words verbatim (not through a number filter).
fn check_inputs(model: &MachiningModel) -> Result<(), Vec<JobError>> {
    let axes = &model.plan.machine.axes;
    let named = [
        ("radial", &axes.radial),
        ("axial", &axes.axial),
        ("swivel", &axes.swivel),
        ("hob", &axes.hob),
        ("table", &axes.table),
        ("shift", &axes.shift),
    ];
    let mut errors = Vec::new();
    for (i, (role, name)) in named.iter().enumerate() {
        let field = format!("machine.axes.{role}");
        if !is_axis_name(name) {
            errors.push(Stage::Template.error(
                Code::INVALID_AXIS_NAME,
                &field,
                "1 to 8 characters from A-Z a-z 0-9 _, starting with a letter",
                name.as_str(),
                format!("the {role} axis name {name:?} in the machine profile is not an 840D axis identifier; correct the machine profile"),
            ));
        } else if let Some((other, _)) = named[..i].iter().find(|(_, n)| n == name) {
            errors.push(Stage::Template.error(
                Code::INVALID_AXIS_NAME,
                &field,
                "an axis name different from every other axis of the machine",
                name.as_str(),
                format!("the {role} axis and the {other} axis are both called {name:?} in the machine profile; correct the machine profile"),
            ));
        }
    }
    let coupling = model.model.coupling;
    if coupling.num == 0 || coupling.den == 0 {
        errors.push(
            Stage::Template.error(
                Code::INVALID_COUPLING,
                "model.coupling",
                "hob starts ≥ 1 and teeth ≥ 1",
                format!("{}/{}", coupling.num, coupling.den),
                "the gearbox ratio z0/z has a zero term; the model should have rejected this job"
                    .to_string(),
            ),
        );
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors)
    }
}

fn is_axis_name(name: &str) -> bool {
    (1..=8).contains(&name.len())
        && name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use gearcam_proto::{
        AxisNames, CaseRef, CouplingFactors, Cut, CutMode, FamilySpec, GearClass, Geometry, Hand,
        HobData, HobbingSpec, Infeed, JobHeader, JobId, JobRequest, JobSpec, Kinematics, Move,
        MoveKind, Options, Position, Positions, ProcessData, ProcessPlan, Ratio, Source,
    };

    use super::*;

    /// A spur gear mn 3, z 25 with an 80 mm single-start hob on machine H01, the
    /// numbers of docs/reference.md#worked-self-check (vc 100 m/min → Nt 397.887 rpm, fa 2 mm/rev
    /// → Vf = 2·397.887/25 = 31.831 mm/min). Positions as the model computes them
    /// for H = 50, b = 30, ΔH′ + safety = 24.5, L = 75.073, A = (300, 400).
    fn spur_model() -> MachiningModel {
        let job_id = JobId::new("J-0001").unwrap();
        // The seeded H01, at the home position this hand-built model's
        // positions were computed for.
        let mut machine = gearcam_knowledge::seed::seed_machine_h01();
        machine.home_x_mm = 300.0;
        machine.home_z_mm = 400.0;
        let mut gear = gearcam_testkit::pipeline::gear(3.0, 25, 0.0);
        gear.material = "20CrMnTi".into();
        let spec = JobSpec::new(
            JobHeader {
                family: Default::default(),
                id: Some(job_id.clone()),
                machine: machine.id.clone(),
                quantity: 10,
                part_number: "SP-1001".into(),
                program_name: None,
            },
            FamilySpec::Hobbing(HobbingSpec {
                gear: Some(gear.clone()),
                ..HobbingSpec::default()
            }),
        );
        let hob = HobData {
            id: "HOB-M3-80".into(),
            starts: 1,
            od_mm: 80.0,
            module_mm: 3.0,
            pressure_angle_deg: 20.0,
            lead_angle_deg: 2.2,
            hand: Hand::Right,
            length_mm: 100.0,
            usable_length_mm: None,
            source: Source::Library,
        };
        let plan = ProcessPlan {
            job_id: job_id.clone(),
            request: JobRequest {
                job_id: job_id.clone(),
                submitted_at_ms: 1_700_000_000_000,
                submitted_by: "station-1".into(),
                spec,
            },
            class: GearClass::Cylindrical,
            gear,
            machine,
            hob,
            process: ProcessData {
                cut_mode: CutMode::Conventional,
                cuts: 1,
                cutting_speed_m_min: 100.0,
                feed_mm_per_rev: 2.0,
                depth_mm: None,
                safety_mm: 2.0,
            },
            values: BTreeMap::new(),
            cases: vec![
                CaseRef {
                    id: "CD-STEEL-HSS-1".into(),
                    similarity: 0.92,
                    provenance: "shop history".into(),
                },
                CaseRef {
                    id: "CASE-0042".into(),
                    similarity: 0.88,
                    provenance: "shop history".into(),
                },
            ],
            confidence: 0.9,
            proposal: Default::default(),
        };
        let p = |x_mm, z_mm| Position { x_mm, z_mm };
        let model = MachiningModel {
            job_id,
            plan,
            geometry: Geometry {
                d_mm: 75.0,
                db_mm: 70.477,
                da_mm: 81.0,
                df_mm: 67.5,
                mt_mm: 3.0,
                alpha_t_deg: 20.0,
                whole_depth_mm: 6.75,
                lead_mm: None,
                base_helix_deg: 0.0,
                sn_mm: 4.712,
                span_teeth: 3,
                span_mm: 23.191,
                ball_mm: 5.1,
                over_balls_mm: 81.5,
                pair: None,
            },
            model: Kinematics {
                swivel_deg: -2.2,
                swivel_axis_deg: 2.2,
                clearance_mm: 22.5,
                safety_mm: 2.0,
                centre_distance_mm: 73.75,
                depth_mm: 6.75,
                blank_od_mm: 81.0,
                positions: Positions {
                    A: p(300.0, 400.0),
                    B: p(173.75, 154.5),
                    C: p(73.75, 154.5),
                    D: p(73.75, 75.5),
                    E: p(78.75, 75.5),
                },
                hob_rpm: 397.887_357_729_738,
                index_rpm: 15.915_494_309_189_5,
                table_rpm: 15.915_494_309_189_5,
                axial_feed_mm_min: 31.830_988_618_379,
                differential_deg_per_mm: 0.0,
                coupling: Ratio { num: 1, den: 25 },
                cut_time_min: 2.984,
                cut_mode: CutMode::Conventional,
                cuts: Vec::new(),
                class: GearClass::Cylindrical,
                infeed: Infeed::Axial,
                factors: CouplingFactors::default(),
                part_time_min: 2.6,
                job_time_min: 26.0,
                shift: None,
                cone: None,
                crowning: None,
                worm: None,
                units: Vec::new(),
                explain: Vec::new(),
            },
            warnings: Vec::new(),
            model_version: "gearcam-model 0.1.0".into(),
        };
        with_one_cut(model)
    }

    /// The model with one axial cut built from its top-level positions and
    /// feed, as the model service writes it: B -> C rapid in X, C -> D feed in
    /// Z, D -> E rapid in X.
    fn with_one_cut(mut model: MachiningModel) -> MachiningModel {
        let k = &model.model;
        let p = k.positions;
        let mv = |kind, x_mm, z_mm, feed_mm_min, note: &str| Move {
            kind,
            x_mm,
            z_mm,
            y_mm: None,
            feed_mm_min,
            via: None,
            radius_mm: None,
            dwell_s: 0.0,
            note: note.into(),
        };
        let cut = Cut {
            number: 1,
            finish: true,
            depth_mm: k.depth_mm,
            allowance_mm: 0.0,
            centre_distance_mm: k.centre_distance_mm,
            clearance_mm: k.clearance_mm,
            positions: p,
            feed_mm_per_rev: 2.0,
            table_rpm: k.table_rpm,
            axial_feed_mm_min: k.axial_feed_mm_min,
            radial_feed_mm_min: 0.0,
            shift_mm: 0.0,
            resync: false,
            moves: vec![
                mv(
                    MoveKind::Rapid,
                    Some(p.C.x_mm),
                    None,
                    0.0,
                    "B -> C: INFEED TO DEPTH",
                ),
                mv(
                    MoveKind::Feed,
                    None,
                    Some(p.D.z_mm),
                    k.axial_feed_mm_min,
                    "C -> D: AXIAL FEED",
                ),
                mv(
                    MoveKind::Rapid,
                    Some(p.E.x_mm),
                    None,
                    0.0,
                    "D -> E: RETRACT",
                ),
            ],
            time_min: 2.6,
        };
        model.model.factors = CouplingFactors {
            c_per_b: k.coupling,
            c_per_z_deg_per_mm: k.differential_deg_per_mm,
            c_per_y_deg_per_mm: 0.0,
        };
        model.model.cuts = vec![cut];
        model
    }

    /// The spur model turned helical: β = 15° right hand, differential
    /// 360·sin β / (π·mn·z) = 0.395446 °/mm (docs/reference.md#worked-self-check).
    fn helical_model() -> MachiningModel {
        let mut m = spur_model();
        let beta = 15f64.to_radians();
        m.plan.gear.helix_angle_deg = 15.0;
        m.plan.gear.helix_hand = Some(Hand::Right);
        m.geometry.lead_mm = Some(std::f64::consts::PI * 3.0 * 25.0 / beta.sin());
        m.model.swivel_deg = 12.8;
        m.model.swivel_axis_deg = 12.8;
        m.model.differential_deg_per_mm = 360.0 * beta.sin() / (std::f64::consts::PI * 3.0 * 25.0);
        with_one_cut(m)
    }

    fn render(model: &MachiningModel) -> NcProgram {
        Templates::builtin()
            .render(model)
            .unwrap_or_else(|e| panic!("render failed: {e:#?}"))
    }

    /// The NC block whose words (after the `N` number) start with `prefix`.
    fn block<'a>(text: &'a str, prefix: &str) -> &'a str {
        let found: Vec<&str> = text
            .lines()
            .filter_map(|l| l.split_once(' ').map(|(_, rest)| rest))
            .filter(|rest| rest.starts_with(prefix))
            .collect();
        assert_eq!(
            found.len(),
            1,
            "expected one block starting {prefix:?} in\n{text}"
        );
        found[0]
    }

    /// The M-codes programmed, in order.
    fn m_codes(text: &str) -> Vec<u16> {
        text.lines()
            .filter(|l| l.starts_with('N'))
            .flat_map(|l| l.split(';').next().unwrap().split_whitespace())
            .filter_map(|w| w.strip_prefix('M').and_then(|n| n.parse().ok()))
            .collect()
    }

    #[test]
    fn header_is_840d_file_header_then_provenance_comments() {
        let program = render(&spur_model());
        let lines: Vec<&str> = program.text.lines().collect();
        assert_eq!(lines[0], "%_N_SP_1001_MPF");
        assert_eq!(lines[1], ";$PATH=/_N_MPF_DIR");
        assert_eq!(lines[2], "; GEARCAM HOBBING PROGRAM SP_1001");
        assert_eq!(lines[3], "; JOB J-0001");
        assert_eq!(lines[4], "; PART SP-1001");
        // The header names the order: quantity, material, quality grade, and
        // when the job was submitted (the request's time, so a re-drive renders the
        // same bytes).
        assert_eq!(lines[5], "; ORDER QTY=10 MATERIAL 20CrMnTi QUALITY GRADE 8");
        assert_eq!(lines[6], "; SUBMITTED 2023-11-14 22:13:20 UTC BY station-1");
        assert_eq!(lines[7], "; CLASS cylindrical");
        assert_eq!(
            lines[8],
            "; MACHINE H01 six-axis CNC hobbing machine, SINUMERIK 840D sl"
        );
        assert_eq!(lines[9], "; TEMPLATE cylindrical_840d VERSION 7");
        assert_eq!(lines[10], "; CASES CD-STEEL-HSS-1 CASE-0042");
        assert_eq!(lines[11], "; MODEL gearcam-model 0.1.0");
        assert_eq!(lines[12], format!("; GENERATOR {GENERATOR}"));
        assert_eq!(lines[13], "; GEAR MN=3.0 Z=25 BETA=0.0 B=30.0 DA1=81.0");
        assert_eq!(
            lines[14],
            "; HOB HOB-M3-80 Z0=1 DA0=80.0 MN0=3.0 GAMMA0=2.2 RIGHT"
        );
        assert_eq!(
            lines[15],
            "; CUT CONVENTIONAL VC=100.0 FA=2.0 H=6.75 L=73.75"
        );
    }

    #[test]
    fn program_carries_name_hash_and_provenance() {
        let model = spur_model();
        let program = render(&model);
        assert_eq!(program.name, "SP_1001");
        assert_eq!(program.revision, 1);
        assert_eq!(program.dialect, Dialect::Sinumerik840d);
        assert_eq!(program.machine.as_str(), "H01");
        assert_eq!(program.job_id, model.job_id);
        assert_eq!(program.part_number, "SP-1001");
        assert_eq!(
            program.template,
            TemplateRef {
                id: "cylindrical_840d".into(),
                version: 7
            }
        );
        assert_eq!(program.cases, vec!["CD-STEEL-HSS-1", "CASE-0042"]);
        assert_eq!(program.model_version, "gearcam-model 0.1.0");
        assert_eq!(program.generator, GENERATOR);
        assert!(program.generator.starts_with("gearcam-template "));
        assert_eq!(
            program.sha256,
            hex::encode(Sha256::digest(program.text.as_bytes()))
        );
        assert_eq!(program.sha256.len(), 64);
        // Rendering is deterministic: the same model gives the same bytes.
        assert_eq!(render(&model).sha256, program.sha256);
    }

    #[test]
    fn blocks_follow_the_patent_order_with_numbers_by_ten() {
        let program = render(&spur_model());
        let blocks: Vec<&str> = program
            .text
            .lines()
            .skip(2)
            .filter(|l| !l.starts_with(';'))
            .collect();
        for (i, b) in blocks.iter().enumerate() {
            assert!(
                b.starts_with(&format!("N{} ", (i + 1) * 10)),
                "block {i} is {b:?}"
            );
        }
        let words: Vec<&str> = blocks
            .iter()
            .map(|b| b.split_once(' ').unwrap().1)
            .collect();
        let expected = [
            "G71 G90 G94 DIAMOF ; METRIC, ABSOLUTE, FEED PER MINUTE, X IS THE CENTRE DISTANCE (A RADIUS)",
            "G54 ; WORK OFFSET: Z0 ON THE TABLE PLANE, X0 ON THE TABLE AXIS",
            "G0 G90 X=300.0 ; RADIAL RETRACT FIRST, FROM WHEREVER THE HOB STANDS",
            "G0 G90 Z=400.0",
            "G0 G90 A=2.2 ; HOB HEAD SWIVELLED AT THE START POINT",
            "G0 G90 Z=154.5",
            "G0 G90 X=173.75",
            "M10 ; FIXTURE CLAMP",
            "M7 ; COOLANT ON",
            "M24 ; CHIP CONVEYOR ON",
            "R1=3.0 ; NORMAL MODULE MN, MM",
            "R2=25 ; NUMBER OF TEETH Z",
            "R3=0.0 ; HELIX ANGLE BETA, DEG",
            "R4=1 ; HOB STARTS Z0",
            "R5=2.2 ; HOB LEAD ANGLE GAMMA0, DEG",
            "EGDEF(C,B,1)",
            "EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25) ; COUPLED AT FIXED SYNCHRONISED POSITIONS: EVERY CUT SHARES THIS REFERENCE",
            "M3 S=397.887 ; HOB ON, RPM",
            "G0 G90 X=73.75",
            "G1 G90 G94 Z=75.5 F=31.831",
            "G0 G90 X=78.75",
            "M5 ; HOB OFF",
            "G0 G90 X=300.0 ; RADIAL RETRACT FIRST: THE HOB LEAVES THE BLANK ZONE",
            "G0 G90 Z=400.0",
            "EGOFS(C) ; GEARBOX OFF",
            "EGDEL(C) ; GEARBOX DEFINITION DELETED",
            "M9 ; COOLANT OFF",
            "M25 ; CHIP CONVEYOR OFF",
            "M11 ; FIXTURE UNCLAMP",
            "M2 ; END OF PROGRAM",
        ];
        assert_eq!(words, expected, "program:\n{}", program.text);
        assert!(program.text.ends_with("M2 ; END OF PROGRAM\n"));
    }

    #[test]
    fn gearbox_couples_table_to_hob_by_the_exact_ratio() {
        let mut model = spur_model();
        model.plan.hob.starts = 2;
        model.model.coupling = Ratio { num: 2, den: 37 };
        model.model.factors.c_per_b = Ratio { num: 2, den: 37 };
        let text = Templates::builtin().instantiate(&model).unwrap().text;
        assert_eq!(block(&text, "EGDEF"), "EGDEF(C,B,1)");
        assert_eq!(
            block(&text, "EGONSYNE"),
            "EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,2,37) ; COUPLED AT FIXED SYNCHRONISED POSITIONS: EVERY CUT SHARES THIS REFERENCE"
        );
        // A left-hand hob turns the table the other way: the C-per-B ratio's
        // sign is the hob's hand.
        model.model.factors.c_per_b = Ratio { num: -2, den: 37 };
        let text = Templates::builtin().instantiate(&model).unwrap().text;
        assert!(
            text.contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,-2,37)"),
            "{text}"
        );
    }

    #[test]
    fn helical_gear_adds_the_axial_axis_with_the_differential() {
        let text = render(&helical_model()).text;
        assert_eq!(block(&text, "EGDEF"), "EGDEF(C,B,1,Z,1)");
        // 360·sin 15° / (π·3·25) = 0.395446 °/mm (docs/hobbing.md#4-the-cycle-positions-speeds-feeds).
        assert!(
            text.contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25,Z,0,0.395446,1)"),
            "{text}"
        );
        assert_eq!(block(&text, "R3="), "R3=15.0 ; HELIX ANGLE BETA, DEG");
        assert_eq!(
            block(&text, "G0 G90 A="),
            "G0 G90 A=12.8 ; HOB HEAD SWIVELLED AT THE START POINT"
        );
        assert!(
            text.contains("; GEAR MN=3.0 Z=25 BETA=15.0 RIGHT B=30.0"),
            "{text}"
        );
    }

    #[test]
    fn negative_differential_keeps_its_sign() {
        let mut model = helical_model();
        model.model.differential_deg_per_mm = -0.395_446_2;
        let model = with_one_cut(model);
        let text = render(&model).text;
        assert!(
            text.contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25,Z,0,-0.395446,1)"),
            "{text}"
        );
    }

    #[test]
    fn feed_block_goes_to_d_at_the_axial_feed() {
        let text = render(&spur_model()).text;
        assert_eq!(block(&text, "G1 "), "G1 G90 G94 Z=75.5 F=31.831");
    }

    #[test]
    fn climb_cut_feeds_up_to_d() {
        let mut model = spur_model();
        model.plan.process.cut_mode = CutMode::Climb;
        model.model.cut_mode = CutMode::Climb;
        let pos = &mut model.model.positions;
        pos.B.z_mm = 75.5;
        pos.C.z_mm = 75.5;
        pos.D.z_mm = 154.5;
        pos.E.z_mm = 154.5;
        let model = with_one_cut(model);
        let text = render(&model).text;
        assert_eq!(block(&text, "G0 G90 Z=75.5"), "G0 G90 Z=75.5");
        assert_eq!(block(&text, "G1 "), "G1 G90 G94 Z=154.5 F=31.831");
        assert!(text.contains("; CUT CLIMB "), "{text}");
        assert!(text.contains("(CLIMB CUT)"), "{text}");
    }

    #[test]
    fn options_off_leave_their_m_codes_out() {
        let mut model = spur_model();
        model.plan.sections_mut().options = Options {
            coolant: false,
            outer_support: false,
            fixture_clamp: false,
            sync_cancel: false,
            chip_conveyor: false,
            mist_separator: false,
        };
        let text = render(&model).text;
        assert_eq!(m_codes(&text), vec![3, 5, 2], "{text}");
        assert!(!text.contains("EGOFS"), "{text}");
        assert!(!text.contains("EGDEL"), "{text}");
    }

    #[test]
    fn options_on_emit_their_m_codes_paired() {
        let mut model = spur_model();
        model.plan.sections_mut().options = Options {
            coolant: true,
            outer_support: true,
            fixture_clamp: true,
            sync_cancel: true,
            chip_conveyor: true,
            mist_separator: true,
        };
        let text = render(&model).text;
        assert_eq!(
            m_codes(&text),
            vec![20, 10, 7, 24, 26, 3, 5, 9, 25, 27, 21, 11, 2],
            "{text}"
        );
        let at = |code: &str| text.find(code).unwrap();
        assert!(at("EGOFS(C)") < at("EGDEL(C)"));
        assert!(at("G0 G90 Z=400.0") < at("EGOFS(C)"));
    }

    #[test]
    fn axis_names_and_m_codes_come_from_the_machine_profile() {
        let mut model = spur_model();
        let machine = &mut model.plan.machine;
        machine.axes = AxisNames {
            radial: "X1".into(),
            axial: "Z1".into(),
            swivel: "A1".into(),
            hob: "SP1".into(),
            table: "C1".into(),
            shift: "Y1".into(),
        };
        machine.mcodes.spindle_on = 13;
        machine.mcodes.spindle_off = 15;
        machine.mcodes.program_end = 2;
        machine.mcodes.coolant_on = 7;
        let mut helical = helical_model();
        helical.plan.machine = machine.clone();
        let text = render(&model).text;
        assert_eq!(block(&text, "G0 G90 X1=173.75"), "G0 G90 X1=173.75");
        assert_eq!(
            block(&text, "G0 G90 A1="),
            "G0 G90 A1=2.2 ; HOB HEAD SWIVELLED AT THE START POINT"
        );
        assert_eq!(block(&text, "EGDEF"), "EGDEF(C1,SP1,1)");
        assert!(
            text.contains("EGONSYNE(C1,\"FINE\",0,\"DCT\",SP1,0,1,25)"),
            "{text}"
        );
        assert_eq!(block(&text, "G1 "), "G1 G90 G94 Z1=75.5 F=31.831");
        assert_eq!(block(&text, "EGOFS"), "EGOFS(C1) ; GEARBOX OFF");
        assert_eq!(m_codes(&text), vec![10, 7, 24, 13, 15, 9, 25, 11, 2]);
        let text = render(&helical).text;
        assert_eq!(block(&text, "EGDEF"), "EGDEF(C1,SP1,1,Z1,1)");
        assert!(
            text.contains("EGONSYNE(C1,\"FINE\",0,\"DCT\",SP1,0,1,25,Z1,0,0.395446,1)"),
            "{text}"
        );
        assert!(!text.contains("EGDEF(C,"), "{text}");
    }

    #[test]
    fn bad_axis_names_are_refused_before_rendering() {
        let mut model = spur_model();
        model.plan.machine.axes.table = "C\nM30".into();
        model.plan.machine.axes.hob = "X".into();
        let errors = Templates::builtin().render(&model).unwrap_err();
        let fields: Vec<(&str, &str)> = errors
            .iter()
            .map(|e| (e.code.as_str(), e.field.as_str()))
            .collect();
        assert_eq!(
            fields,
            vec![
                ("INVALID_AXIS_NAME", "machine.axes.hob"),
                ("INVALID_AXIS_NAME", "machine.axes.table"),
            ]
        );
        assert!(errors.iter().all(|e| e.stage == Stage::Template));
    }

    #[test]
    fn free_text_cannot_break_out_of_a_comment() {
        let mut model = spur_model();
        model.plan.request.spec.job.part_number = "SP-1001\nM30\r\nG0 X=0".into();
        model.plan.machine.name = "Wälzfräsmaschine\tNr. 1".into();
        let program = render(&model);
        assert_eq!(program.name, "SP_1001_M30_G0_X_0");
        assert!(
            program.text.contains("\n; PART SP-1001 M30  G0 X=0\n"),
            "{}",
            program.text
        );
        assert!(program
            .text
            .contains("\n; MACHINE H01 W?lzfr?smaschine Nr. 1\n"));
        assert!(program.text.is_ascii());
        for line in program.text.lines().skip(2) {
            assert!(
                line.starts_with(';') || line.starts_with('N'),
                "stray line {line:?}"
            );
        }
    }

    #[test]
    fn no_negative_zero_and_every_number_is_fixed_point() {
        let mut model = spur_model();
        model.model.swivel_axis_deg = -0.000_01;
        model.model.positions.A.z_mm = -0.0001;
        let model = with_one_cut(model);
        // Formatting only: the fixture's A is not a place a real profile has.
        let text = Templates::builtin().instantiate(&model).unwrap().text;
        assert!(
            !text.contains("-0.0 ") && !text.contains("-0.0\n"),
            "{text}"
        );
        assert_eq!(
            block(&text, "G0 G90 A="),
            "G0 G90 A=0.0 ; HOB HEAD SWIVELLED AT THE START POINT"
        );
        assert!(text.contains(" G0 G90 Z=0.0\n"), "{text}");
        assert!(!text.contains('e') || !text.contains("e-"), "{text}");
    }

    #[test]
    fn non_finite_numbers_fail_with_a_typed_error() {
        let mut model = spur_model();
        model.model.axial_feed_mm_min = f64::NAN;
        let model = with_one_cut(model);
        let errors = Templates::builtin().render(&model).unwrap_err();
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].code, "TEMPLATE_RENDER_FAILED");
        assert_eq!(errors[0].field, "template.cylindrical_840d");
        assert!(errors[0].got.contains("NaN"), "{:?}", errors[0]);
    }

    #[test]
    fn unknown_class_is_template_not_found_on_class() {
        let mut model = spur_model();
        model.plan.class = GearClass::CurvedTooth;
        let errors = Templates::builtin().render(&model).unwrap_err();
        assert_eq!(errors.len(), 1);
        let e = &errors[0];
        assert_eq!(e.stage, Stage::Template);
        assert_eq!(e.code, "TEMPLATE_NOT_FOUND");
        assert_eq!(e.field, "class");
        assert!(
            e.expected
                .starts_with("one of conical/sinumerik840d, conical/fanuc, "),
            "{}",
            e.expected
        );
        assert!(
            e.expected.contains("cylindrical/sinumerik840d"),
            "{}",
            e.expected
        );
        assert_eq!(e.got, "curved_tooth/sinumerik840d");
    }

    #[test]
    fn other_dialect_is_template_not_found_on_the_machine() {
        let mut model = spur_model();
        model.plan.machine.dialect = Dialect::Linuxcnc;
        let errors = Templates::builtin().render(&model).unwrap_err();
        let e = &errors[0];
        assert_eq!(e.code, "TEMPLATE_NOT_FOUND");
        assert_eq!(e.field, "job.machine");
        assert!(e.expected.contains("cylindrical/fanuc"), "{}", e.expected);
        assert_eq!(e.got, "cylindrical/linuxcnc");
        assert!(e.message.contains("H01"), "{}", e.message);
    }

    #[test]
    fn program_names_follow_the_840d_rules() {
        assert_eq!(program_name_840d("SP-1001"), "SP_1001");
        assert_eq!(program_name_840d("sp.1001 rev b"), "SP_1001_REV_B");
        assert_eq!(program_name_840d("123"), "GC_123");
        assert_eq!(program_name_840d("A1"), "GC_A1");
        assert_eq!(program_name_840d("-A1"), "GC_A1");
        assert_eq!(program_name_840d("_AB"), "AB");
        assert_eq!(program_name_840d(" 7-b"), "GC_7_B");
        assert_eq!(program_name_840d("SP--1001.."), "SP_1001");
        // Nothing usable left, or too long: a tag of the whole part number.
        let tag = gearcam_proto::naming::part_tag;
        assert_eq!(program_name_840d(""), format!("GC_PART_{}", tag("")));
        assert_eq!(program_name_840d("---"), format!("GC_PART_{}", tag("---")));
        let part = "GEARBOX-SHAFT-PINION-STAGE-2-REV-C";
        let long = program_name_840d(part);
        assert_eq!(long, format!("GEARBOX_SHAFT_PINI_{}", tag(part)));
        assert_eq!(long.len(), MAX_NAME_840D);
        let part = "1234567890123456789012345";
        let long_digits = program_name_840d(part);
        assert_eq!(long_digits, format!("GC_123456789012345_{}", tag(part)));
        for part in [
            "SP-1001",
            "123",
            "_AB",
            "",
            "ÄÖÜ-7",
            "x",
            "GEARBOX-SHAFT-PINION-STAGE-2",
        ] {
            let name = program_name_840d(part);
            assert_eq!(check_name_840d(&name), Ok(()), "{part:?} → {name:?}");
        }
    }

    #[test]
    fn name_check_says_what_is_wrong() {
        assert_eq!(check_name_840d("SP_1001"), Ok(()));
        assert_eq!(check_name_840d("_A"), Ok(()));
        assert!(check_name_840d("").unwrap_err().contains("empty"));
        assert!(check_name_840d("S1").unwrap_err().contains("two letters"));
        assert!(check_name_840d("_1A").unwrap_err().contains("two letters"));
        assert!(check_name_840d("SP-1001").unwrap_err().contains("'-'"));
        assert!(check_name_840d("sp_1001").unwrap_err().contains("'s'"));
        assert!(check_name_840d(&"A".repeat(25))
            .unwrap_err()
            .contains("25 characters"));
        assert_eq!(check_name_840d(&"A".repeat(24)), Ok(()));
    }

    #[test]
    fn numbers_are_fixed_point_trimmed_and_never_negative_zero() {
        assert_eq!(format_fixed(123.4, 3).unwrap(), "123.4");
        assert_eq!(format_fixed(-0.05, 3).unwrap(), "-0.05");
        assert_eq!(format_fixed(12.0, 3).unwrap(), "12.0");
        assert_eq!(format_fixed(0.0, 3).unwrap(), "0.0");
        assert_eq!(format_fixed(-0.0, 3).unwrap(), "0.0");
        assert_eq!(format_fixed(-0.0004, 3).unwrap(), "0.0");
        assert_eq!(format_fixed(-0.0005001, 3).unwrap(), "-0.001");
        assert_eq!(format_fixed(397.887_357_7, 3).unwrap(), "397.887");
        assert_eq!(format_fixed(2.999_96, 4).unwrap(), "3.0");
        assert_eq!(format_fixed(-12.345_67, 4).unwrap(), "-12.3457");
        assert_eq!(format_fixed(1e7, 3).unwrap(), "10000000.0");
        assert_eq!(format_fixed(f64::NAN, 3), None);
        assert_eq!(format_fixed(f64::INFINITY, 3), None);
    }

    fn with_template(id: &str, records: &str, fuel: u64) -> Templates {
        let (class, dialect) = id.rsplit_once('_').unwrap();
        let dialect = if dialect == "840d" {
            "sinumerik840d"
        } else {
            dialect
        };
        Templates::new(
            vec![TemplateSource {
                id: id.into(),
                source: format!(
                    "@template {id}\n@class {class}\n@dialect {dialect}\n@version 1\n{records}"
                ),
            }],
            fuel,
        )
        .unwrap()
    }

    #[test]
    fn evaluation_is_stopped_by_the_step_budget() {
        // Many steps per record: repeated per move of every cut.
        let templates = with_template(
            "conical_840d",
            "main/unit :: ;\nmain/cut :: ;\nmain/move calc: a = 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1 :: {N()}\n",
            20,
        );
        let mut model = spur_model();
        model.plan.class = GearClass::Conical;
        let errors = templates.render(&model).unwrap_err();
        assert_eq!(errors.len(), 1);
        assert_eq!(errors[0].code, "TEMPLATE_FUEL_EXHAUSTED");
        assert_eq!(errors[0].field, "template.conical_840d");
        assert!(
            errors[0].message.contains("line 7"),
            "{}",
            errors[0].message
        );
    }

    #[test]
    fn oversized_output_is_stopped_by_the_size_limit() {
        let mut calc = String::from("a0 = \"XXXXXXXXXXXXXXXX\"");
        for i in 1..=17 {
            calc.push_str(&format!("; a{i} = a{} + a{}", i - 1, i - 1));
        }
        let templates = with_template(
            "crowned_840d",
            &format!("main calc: {calc} :: {{a17}}\n"),
            DEFAULT_FUEL,
        );
        let mut model = spur_model();
        model.plan.class = GearClass::Crowned;
        let errors = templates.render(&model).unwrap_err();
        assert_eq!(errors[0].code, "PROGRAM_TOO_LARGE");
    }

    #[test]
    fn shipped_templates_use_little_of_the_budget() {
        // A hundredth of the default budget is enough for the largest example, so a
        // template of this kind never trips the limit.
        let templates = Templates::new(Vec::new(), DEFAULT_FUEL / 100).unwrap();
        assert!(templates.render(&helical_model()).is_ok());
    }

    #[test]
    fn unknown_names_are_refused_when_the_template_is_compiled() {
        let err = Templates::new(
            vec![TemplateSource {
                id: "typo_840d".into(),
                source: "@template typo_840d\n@class typo\n@dialect sinumerik840d\n@version 1\nmain :: %{program.file}\nmotion :: G0 X={nc(kin.positons)}\n".into(),
            }],
            DEFAULT_FUEL,
        )
        .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("line 6") && text.contains("kin.positons"),
            "{text}"
        );
    }

    #[test]
    fn a_move_parameter_outside_the_move_scope_is_refused() {
        let err = Templates::new(
            vec![TemplateSource {
                id: "scope_840d".into(),
                source: "@template scope_840d\n@class scope\n@dialect sinumerik840d\n@version 1\nmotion :: G0 X={nc(m.x)}\n".into(),
            }],
            DEFAULT_FUEL,
        )
        .unwrap_err();
        assert!(err.to_string().contains("m.x"), "{err}");
    }

    #[test]
    fn a_fraction_written_without_a_number_function_is_a_render_error() {
        let templates = with_template("worm_wheel_840d", "main :: G0 X{kin.depth}\n", DEFAULT_FUEL);
        let mut model = spur_model();
        model.plan.class = GearClass::WormWheel;
        let errors = templates.render(&model).unwrap_err();
        assert_eq!(errors[0].code, "TEMPLATE_RENDER_FAILED");
        assert!(errors[0].message.contains("nc()"), "{}", errors[0].message);
    }

    #[test]
    fn given_template_replaces_the_shipped_one_and_names_its_version() {
        let templates = Templates::new(
            vec![TemplateSource {
                id: "cylindrical_840d".into(),
                source: "@template cylindrical_840d\n@class cylindrical\n@dialect sinumerik840d\n@version 7\nmain :: %{program.file}\nmain :: ;$PATH=/_N_MPF_DIR\nmain :: {N()} M{mc.program_end}\n".into(),
            }],
            DEFAULT_FUEL,
        )
        .unwrap();
        let program = templates.render(&spur_model()).unwrap();
        assert_eq!(program.template.version, 7);
        assert_eq!(
            program.text,
            "%_N_SP_1001_MPF\n;$PATH=/_N_MPF_DIR\nN10 M2\n"
        );
        // The other classes keep the shipped one.
        let list = templates.list();
        assert!(list.contains(&TemplateRef {
            id: "cylindrical_840d".into(),
            version: 7
        }));
        assert!(list.contains(&TemplateRef {
            id: "conical_840d".into(),
            version: 8
        }));
    }

    #[test]
    fn templates_without_version_or_with_mismatched_ids_are_refused() {
        let add = |id: &str, source: &str| {
            Templates::new(
                vec![TemplateSource {
                    id: id.into(),
                    source: source.into(),
                }],
                DEFAULT_FUEL,
            )
        };
        let head = "@template conical_840d\n@class conical\n@dialect sinumerik840d\n";
        assert!(matches!(
            add("conical_840d", &format!("{head}main :: M2\n")),
            Err(TemplateError::Format(_))
        ));
        assert!(matches!(
            add("conical_840d", &format!("{head}@version 0\nmain :: M2\n")),
            Err(TemplateError::Format(_))
        ));
        assert!(matches!(
            add("conical_fanuc", &format!("{head}@version 1\nmain :: M2\n")),
            Err(TemplateError::BadId { .. })
        ));
        assert!(matches!(
            add(
                "conical_840d",
                &format!("{head}@version 1\nmain :: {{1 +}}\n")
            ),
            Err(TemplateError::Compile(_))
        ));
        assert_eq!(
            add("conical_840d", &format!("{head}@version 4\nmain :: M2\n"))
                .unwrap()
                .find("conical", Dialect::Sinumerik840d),
            Some(TemplateRef {
                id: "conical_840d".into(),
                version: 4
            })
        );
    }

    #[test]
    fn the_library_starts_with_the_shipped_code_and_keeps_a_shops_newer_version() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("templates.db");
        let fresh = Templates::from_library(&path, DEFAULT_FUEL, 1).unwrap();
        assert_eq!(fresh.list(), Templates::builtin().list());
        // Assembled from the stored components, the program is the shipped one.
        assert_eq!(
            fresh.render(&spur_model()).unwrap().text,
            render(&spur_model()).text
        );
        // The shop imports its own version 9 of the cylindrical 840D code.
        let shipped = crate::builtin::builtin_sources()
            .into_iter()
            .find(|(n, _)| *n == "cylindrical_840d.tpl")
            .unwrap()
            .1;
        let own = shipped
            .replace("@version 7", "@version 9")
            .replace("; GEARCAM HOBBING PROGRAM", "; SHOP HOBBING PROGRAM");
        let file = crate::stdcode::parse("own.tpl", &own).unwrap();
        crate::library::Library::open(&path)
            .unwrap()
            .import(&[file], &[own.as_str()], 2)
            .unwrap();
        // At the next start the service compiles the shop's version, and the
        // shipped version 7 is not imported over it.
        let next = Templates::from_library(&path, DEFAULT_FUEL, 3).unwrap();
        let t = next.find("cylindrical", Dialect::Sinumerik840d).unwrap();
        assert_eq!(t.version, 9);
        let program = next.render(&spur_model()).unwrap();
        assert!(program.text.contains("; SHOP HOBBING PROGRAM SP_1001"));
        assert!(program
            .text
            .contains("; TEMPLATE cylindrical_840d VERSION 9"));
    }

    #[test]
    fn shipped_library_has_the_hobbing_template_of_every_programmable_class() {
        let templates = Templates::builtin();
        let ids: Vec<String> = templates.list().into_iter().map(|t| t.id).collect();
        for class in [
            "conical",
            "crowned",
            "cylindrical",
            "multi_gear",
            "worm_wheel",
        ] {
            assert!(ids.contains(&format!("{class}_840d")), "{ids:?}");
            assert!(ids.contains(&format!("{class}_fanuc")), "{ids:?}");
        }
        // Version 3 of the 840D code is the first in the record format.
        assert!(templates
            .list()
            .iter()
            .all(|t| t.version >= 3 || t.id.ends_with("_fanuc")));
    }
}
