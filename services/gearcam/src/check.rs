//! `gearcam check`: the whole computation done locally, without the bus —
//! knowledge (from the local database), model, template — and its report, as
//! JSON (a contract other tools read) or for a person.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use gearcam_proto::plan::HobChoice;
use gearcam_proto::{
    CoverageCheck, Family, Geometry, GrooveFigures, JobError, JobRequest, Kinematics, MillData,
    Source, Sourced, SpiralCut, SpiralFigures, SpiralModel, SpiralPart, Stage, TemplateRef,
    Warning, WorkpieceRef,
};
use gearcam_template::Templates;
use rusqlite::Connection;
use serde::Serialize;

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

fn case_summaries(cases: &[gearcam_proto::CaseRef]) -> Vec<CaseSummary> {
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
    /// or a proposal clamped to its limits), `default`, or `library` (the
    /// drawing data `gear.*` of a part from the workpiece library).
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
    /// Where the SVG picture of a spiral or wire job was written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub picture: Option<String>,
    /// Where the DXF of a wire job's outline was written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub drawing: Option<String>,
    /// The NC program.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub program: Option<ProgramSummary>,
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

/// True when the figures are those of a gear: every diameter, the depth
/// and the tooth thickness finite and positive, the root inside the tip.
fn describes_a_gear(g: &Geometry) -> bool {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    [g.d_mm, g.db_mm, g.da_mm, g.df_mm, g.whole_depth_mm, g.sn_mm]
        .into_iter()
        .all(positive)
        && g.df_mm < g.da_mm
}

/// Runs knowledge → model → template locally for one hobbing or spiral
/// request ([`crate::check_wire::check_any`] runs every family).
pub fn check(conn: &Connection, templates: &Templates, req: &JobRequest) -> CheckReport {
    let spec = &req.spec;
    let mut report = job_summary(req);
    if spec.job.family == Family::SpiralFace {
        return check_spiral(conn, req, report).0;
    }
    // Before the model has validated the gear, its figures are shown only
    // when they describe a gear (a module of -3 gives d -75 mm: no figures).
    if let Some(gear) = spec.hobbing().and_then(|h| h.gear.as_ref()) {
        report.geometry = Some(gearcam_model::geometry_of(gear)).filter(describes_a_gear);
    }
    let plan = match gearcam_knowledge::plan::plan(conn, req) {
        Ok(p) => p,
        Err(errors) => {
            report.errors = errors;
            return report;
        }
    };
    // The plan's gear: the job's, or the workpiece library's for a job that
    // names its part only.
    report.geometry = Some(gearcam_model::geometry_of(&plan.gear)).filter(describes_a_gear);
    report.plan = Some(PlanSummary {
        class: plan.class.to_string(),
        machine: MachineSummary::of(&plan.machine.id, &plan.machine.name, plan.machine.dialect),
        hob_id: plan.hob.id.clone(),
        confidence: plan.confidence,
        cases: case_summaries(&plan.cases),
        values: plan.values.clone(),
        proposed: plan.proposal.values.clone(),
        overridden: plan.proposal.overridden.clone(),
        tool: None,
        hob_choice: plan.proposal.hob.clone(),
        workpiece: plan.proposal.workpiece.clone(),
    });
    let model = match gearcam_model::compute(&plan) {
        Ok(m) => m,
        Err(errors) => {
            report.errors = errors;
            return report;
        }
    };
    report.geometry = Some(model.geometry.clone());
    report.model = Some(ModelReport::Hobbing(Box::new(model.model.clone())));
    report.warnings = model.warnings.clone();
    match templates.instantiate(&model) {
        Ok(p) => {
            report.errors = gearcam_template::render::path_check_errors(&p);
            report.ok = report.errors.is_empty();
            report.program = Some(ProgramSummary {
                name: p.name,
                dialect: p.dialect.as_str().into(),
                template: p.template,
                sha256: p.sha256,
                path_check: p.path_check,
                text: p.text,
            });
        }
        Err(errors) => report.errors = errors,
    }
    report
}

/// Knowledge → model → program for a spiral job; the report and the model
/// (for the picture).
pub fn check_spiral(
    conn: &Connection,
    req: &JobRequest,
    mut report: CheckReport,
) -> (CheckReport, Option<SpiralModel>) {
    let plan = match gearcam_knowledge::spiral::plan_spiral(conn, req) {
        Ok(p) => p,
        Err(errors) => {
            report.errors = errors;
            return (report, None);
        }
    };
    let p = &plan.process;
    let face = matches!(plan.part, SpiralPart::Face(_));
    let values: BTreeMap<String, Sourced> = [
        ("step_over_mm", p.step_over_mm),
        ("cutting_speed_m_min", p.cutting_speed_m_min),
        ("feed_per_tooth_mm", p.feed_per_tooth_mm),
        ("outer_overtravel_mm", p.outer_overtravel_mm),
        ("inner_overtravel_mm", p.inner_overtravel_mm),
        ("start_angle_deg", p.start_angle_deg),
        ("tolerance_mm", p.tolerance_mm),
        (
            "passes",
            Sourced {
                value: f64::from(p.passes),
                source: if plan
                    .request
                    .spec
                    .spiral()
                    .is_some_and(|s| s.milling.passes.is_some())
                {
                    Source::Job
                } else {
                    Source::Case
                },
            },
        ),
    ]
    .into_iter()
    // A groove's step-over is its pitch; the overtravels are a face's.
    .filter(|(k, _)| face || !k.ends_with("overtravel_mm"))
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    report.plan = Some(PlanSummary::of_sourced(
        format!("spiral-{}", plan.part.kind()),
        MachineSummary::of(&plan.machine.id, &plan.machine.name, plan.machine.dialect),
        plan.tool.id.clone(),
        plan.confidence,
        &plan.cases,
        values,
        Some(plan.tool.clone()),
    ));
    let model = match gearcam_model::spiral::compute_spiral(&plan) {
        Ok(m) => m,
        Err(errors) => {
            report.errors = errors;
            return (report, None);
        }
    };
    report.model = Some(ModelReport::Spiral(Box::new(SpiralReport {
        spiral: model.spiral.clone(),
        cut: model.cut,
        groove: model.groove,
        part_time_min: model.part_time_min,
    })));
    report.coverage = Some(model.coverage);
    report.warnings = model.warnings.clone();
    match gearcam_template::spiral::instantiate(&model) {
        Ok(p) => {
            report.errors = gearcam_template::render::path_check_errors(&p);
            report.ok = report.errors.is_empty();
            report.program = Some(ProgramSummary {
                name: p.name,
                dialect: p.form.map_or(p.dialect.as_str(), |f| f.as_str()).into(),
                template: p.template,
                sha256: p.sha256,
                path_check: p.path_check,
                text: p.text,
            });
        }
        Err(errors) => report.errors = errors,
    }
    (report, Some(model))
}

/// The SVG picture of a spiral model: the region (or the groove's band),
/// the swept band of the tool, the tool-centre path and the worst gap.
pub fn spiral_picture(model: &SpiralModel) -> String {
    let spiral = gearcam_spiral::verify::spiral_of(model);
    let (_, points) = spiral.chords(model.cut.tolerance_mm);
    let region = gearcam_spiral::Region {
        outer_radius_mm: model.spiral.outer_radius_mm,
        inner_radius_mm: model.spiral.inner_radius_mm,
    };
    let coverage = gearcam_spiral::Coverage {
        ok: model.coverage.ok,
        max_gap_mm: match model.plan.part {
            SpiralPart::Face(_) => model.coverage.max_gap_mm,
            SpiralPart::Groove(_) => 0.0,
        },
        worst_point: model.coverage.worst_point_mm,
        samples: model.coverage.samples as usize,
    };
    gearcam_spiral::picture::face_svg(&region, model.spiral.tool_radius_mm, &points, &coverage)
}

fn src(s: Source) -> &'static str {
    match s {
        Source::Job => "job",
        Source::Case => "case",
        Source::Machine => "machine",
        Source::Default => "default",
        Source::Library => "library",
    }
}

/// Formats errors for a person, one block each.
pub fn format_errors(errors: &[JobError]) -> String {
    let mut out = String::new();
    for e in errors {
        let _ = writeln!(
            out,
            "  ✗ [{}] {} — {}\n      field {}: expected {}, got {}",
            e.stage.as_str(),
            e.code,
            e.message,
            e.field,
            e.expected,
            e.got
        );
    }
    out
}

/// The wire model's lines for a person.
fn format_die(out: &mut String, d: &gearcam_proto::DieFigures) {
    let _ = writeln!(
        out,
        "{} m {} z {} α {}° x {}  radii base {:.4} tip {:.4} root {:.4} form {:.4} mm{}{}",
        d.part.as_str(),
        d.module_mm,
        d.teeth,
        d.pressure_angle_deg,
        d.profile_shift,
        d.base_radius_mm,
        d.tip_radius_mm,
        d.root_radius_mm,
        d.form_radius_mm,
        if d.undercut { "  UNDERCUT" } else { "" },
        d.centre_distance_mm
            .map_or(String::new(), |a| format!("  centre distance {a:.4} mm"))
    );
    let _ = writeln!(
        out,
        "  arcs per flank {} (tolerance {} µm)  per fillet {} ({} µm)  outline {} arcs  tip thickness {:.3} mm",
        d.arcs_per_flank,
        d.flank_tolerance_um,
        d.arcs_per_fillet,
        d.fillet_tolerance_um,
        d.outline_arcs,
        d.tip_thickness_mm
    );
    let _ = writeln!(
        out,
        "  wire offset {:.4} mm  path {:.1} mm  {:.1} min  teeth written {} of {}",
        d.offset_mm, d.path_length_mm, d.cutting_time_min, d.teeth_written, d.teeth
    );
    let _ = writeln!(
        out,
        "certificate (the program replayed): max deviation {:.3} µm (flank {:.3}, fillet {:.3})  closure {:.3} µm  {} blocks  {} bytes",
        d.max_deviation_um,
        d.flank_deviation_um,
        d.fillet_deviation_um,
        d.closure_um,
        d.blocks,
        d.bytes
    );
}

/// The report for a person.
pub fn format_human(r: &CheckReport) -> String {
    let mut out = String::new();
    if let Some(j) = &r.job {
        let _ = writeln!(
            out,
            "job {}  part {}  machine {}  quantity {}",
            j.id, j.part_number, j.machine, j.quantity
        );
    }
    if let Some(p) = &r.plan {
        let _ = writeln!(
            out,
            "machine {} ({}, {})",
            p.machine.id, p.machine.name, p.machine.dialect
        );
        match &p.tool {
            Some(t) => {
                let _ = writeln!(
                    out,
                    "class {}  tool {} ({} Ø{} mm, corner R{} mm, {} flutes, from {})  confidence {:.2}",
                    p.class,
                    t.id,
                    t.kind.as_str(),
                    2.0 * t.radius_mm,
                    t.corner_radius_mm,
                    t.flutes,
                    src(t.source),
                    p.confidence
                );
            }
            None => {
                // A wire job's "tool" is its wire.
                let tool = if p.class.starts_with("wire-") {
                    "wire"
                } else {
                    "hob"
                };
                let _ = writeln!(
                    out,
                    "class {}  {tool} {}  confidence {:.2}",
                    p.class, p.hob_id, p.confidence
                );
            }
        }
        for c in &p.cases {
            let _ = writeln!(
                out,
                "  case {} (similarity {:.2}): {}",
                c.id, c.similarity, c.provenance
            );
        }
        if let Some(w) = &p.workpiece {
            if w.supplied_gear {
                let _ = writeln!(
                    out,
                    "  drawing data: workpiece {} from the library ({})",
                    w.part_number, w.provenance
                );
            } else {
                let _ = writeln!(
                    out,
                    "  drawing data: the job's [gear], over workpiece {} of the library{}",
                    w.part_number,
                    if w.differs.is_empty() {
                        " (the same values)".to_string()
                    } else {
                        format!(" (differs in {})", w.differs.join(", "))
                    }
                );
            }
        }
        if let Some(h) = &p.hob_choice {
            let _ = writeln!(out, "  hob choice: {}", h.reason);
            if !h.alternatives.is_empty() {
                let _ = writeln!(out, "    also fit: {}", h.alternatives.join(", "));
            }
            for r in &h.rejected {
                let _ = writeln!(out, "    rejected {}: {}", r.id, r.reasons.join("; "));
            }
        }
        for (k, v) in &p.values {
            let proposed = match p.proposed.get(k) {
                Some(pv) if p.overridden.contains(k) => {
                    format!("  (proposed {:.4} from {})", pv.value, src(pv.source))
                }
                _ => String::new(),
            };
            let _ = writeln!(
                out,
                "  {k:<22} {:>10.4}  from {}{proposed}",
                v.value,
                src(v.source)
            );
        }
    }
    if let Some(g) = &r.geometry {
        let _ = writeln!(
            out,
            "geometry  d {:.4}  db {:.4}  da {:.4}  df {:.4} mm",
            g.d_mm, g.db_mm, g.da_mm, g.df_mm
        );
        let _ = writeln!(
            out,
            "  sn {:.4}  span over k = {} teeth Wk {:.4}  over {} mm balls MdK {:.4} mm",
            g.sn_mm, g.span_teeth, g.span_mm, g.ball_mm, g.over_balls_mm
        );
    }
    if let Some(ModelReport::Spiral(m)) = &r.model {
        let s = &m.spiral;
        let _ = writeln!(
            out,
            "spiral  region Ro {} Ri {} mm  tool radius {} mm  centre R1 {:.4} → R2 {:.4} mm  {} turns  step-over {:.4} mm  {}",
            s.outer_radius_mm,
            s.inner_radius_mm,
            s.tool_radius_mm,
            s.start_radius_mm,
            s.end_radius_mm,
            s.turns,
            s.step_over_mm,
            if s.sense > 0 { "counter-clockwise" } else { "clockwise" }
        );
        let _ = writeln!(
            out,
            "  path {:.1} mm per pass  {} blocks ({} arcs or {} chords at {} mm, angle step {:.4}°)",
            s.path_length_mm, s.blocks, s.arcs, s.chords, m.cut.tolerance_mm, s.angle_step_deg
        );
        let _ = writeln!(
            out,
            "  {} pass(es) to {} mm  {:.0} rpm  feed {:.1} mm/min (plunge {:.1})  {:.2} min per part",
            m.cut.passes,
            m.cut.depth_mm,
            m.cut.spindle_rpm,
            m.cut.feed_mm_min,
            m.cut.plunge_feed_mm_min,
            m.part_time_min
        );
        if let Some(g) = &m.groove {
            let _ = writeln!(
                out,
                "  groove width {} mm  pitch {} mm  land {} mm",
                g.width_mm, g.pitch_mm, g.land_mm
            );
        }
    }
    if let Some(ModelReport::Wire(w)) = &r.model {
        format_die(&mut out, &w.die);
    }
    let groove = matches!(&r.model, Some(ModelReport::Spiral(m)) if m.groove.is_some());
    if let Some(c) = &r.coverage {
        let _ = writeln!(
            out,
            "{} {}  {} {:.4} mm  max deviation from the spiral {:.5} mm  ({} {})",
            if groove { "pitch check" } else { "coverage" },
            if c.ok { "ok" } else { "FAILED" },
            if groove {
                "worst pitch error"
            } else {
                "max gap"
            },
            c.max_gap_mm,
            c.max_deviation_mm,
            c.samples,
            if groove { "rays" } else { "points of the face" }
        );
    }
    if let Some(p) = &r.picture {
        let _ = writeln!(out, "picture: {p}");
    }
    if let Some(p) = &r.drawing {
        let _ = writeln!(out, "outline (DXF): {p}");
    }
    if let Some(ModelReport::Hobbing(m)) = &r.model {
        let _ = writeln!(
            out,
            "model  swivel {:.4}°  ΔH′ {:.3} mm (+{:.3} safety)  L {:.3} mm  depth {:.3} mm",
            m.swivel_deg, m.clearance_mm, m.safety_mm, m.centre_distance_mm, m.depth_mm
        );
        let p = &m.positions;
        for (name, pos) in [("A", p.A), ("B", p.B), ("C", p.C), ("D", p.D), ("E", p.E)] {
            let _ = writeln!(out, "  {name}  X {:>9.3}  Z {:>9.3}", pos.x_mm, pos.z_mm);
        }
        let _ = writeln!(
            out,
            "  hob {:.3} rpm  table {:.4} rpm  feed {:.3} mm/min  differential {:.6}°/mm  ratio {}/{}  {:.2} min/cut",
            m.hob_rpm,
            m.table_rpm,
            m.axial_feed_mm_min,
            m.differential_deg_per_mm,
            m.coupling.num,
            m.coupling.den,
            m.cut_time_min
        );
        let _ = writeln!(
            out,
            "  class {}  {} cut(s)  {:.2} min per part",
            m.class,
            m.cuts.len(),
            m.part_time_min
        );
        for e in &m.explain {
            let _ = writeln!(
                out,
                "    {:<34} {:>12.4} {:<6} from {:?}: {}",
                e.name, e.value, e.unit, e.origin, e.note
            );
        }
    }
    for w in &r.warnings {
        let _ = writeln!(out, "  ! {} {}: {}", w.code, w.field, w.message);
    }
    if !r.errors.is_empty() {
        let _ = writeln!(out, "{} error(s):", r.errors.len());
        out.push_str(&format_errors(&r.errors));
    }
    if let Some(p) = &r.program {
        let _ = writeln!(
            out,
            "program {} ({}, template {} v{}, sha256 {})",
            p.name, p.dialect, p.template.id, p.template.version, p.sha256
        );
        if p.path_check.ok {
            let _ = writeln!(out, "path check: ok\n");
        } else {
            let _ = writeln!(
                out,
                "path check: {} finding(s); the program would not be sent",
                p.path_check.findings.len()
            );
            for f in &p.path_check.findings {
                let _ = writeln!(out, "  line {} [{}] {}", f.line, f.rule, f.message);
            }
            out.push('\n');
        }
        out.push_str(&p.text);
    }
    out
}

/// The stage a check error belongs to, for exit codes and summaries.
pub fn first_stage(r: &CheckReport) -> Option<Stage> {
    r.errors.first().map(|e| e.stage)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check_wire::{check_any, Drawing};

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
        check(&conn, &Templates::builtin(), &crate::jobfile::request(spec))
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
        let report = check(&conn, &Templates::builtin(), &crate::jobfile::request(spec));
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
            let (report, model) = check_any(&conn, &templates, &crate::jobfile::request(spec));
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
            let report = check(&conn, &templates, &crate::jobfile::request(spec));
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
