//! `gearcam check` for a hobbing job: knowledge → model → template and the
//! NC path check, with the gear's figures; the model comes back for the
//! picture of the set-up and the path ([`super::picture_hobbing`]).

use gearcam_hobsim::simulate::{Settings, Simulation};
use gearcam_proto::{Geometry, JobRequest, MachiningModel};
use gearcam_template::Templates;
use rusqlite::Connection;

use super::{
    case_summaries, CheckReport, MachineSummary, ModelReport, PlanSummary, ProgramSummary,
};

/// True when the figures are those of a gear: every diameter, the depth
/// and the tooth thickness finite and positive, the root inside the tip.
fn describes_a_gear(g: &Geometry) -> bool {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    [g.d_mm, g.db_mm, g.da_mm, g.df_mm, g.whole_depth_mm, g.sn_mm]
        .into_iter()
        .all(positive)
        && g.df_mm < g.da_mm
}

/// Knowledge → model → template for a hobbing job; the report, the model
/// (for the picture) and, when it was simulated, the run of each gear of
/// the part (for the charts).
pub fn check_hobbing(
    conn: &Connection,
    templates: &Templates,
    req: &JobRequest,
    mut report: CheckReport,
    simulation: Option<&Settings>,
) -> (CheckReport, Option<MachiningModel>, Vec<Simulation>) {
    let spec = &req.spec;
    // Before the model has validated the gear, its figures are shown only
    // when they describe a gear (a module of -3 gives d -75 mm: no figures).
    if let Some(gear) = spec.hobbing().and_then(|h| h.gear.as_ref()) {
        report.geometry = Some(gearcam_model::geometry_of(gear)).filter(describes_a_gear);
    }
    let plan = match gearcam_knowledge::plan::plan(conn, req) {
        Ok(p) => p,
        Err(errors) => {
            report.errors = errors;
            return (report, None, Vec::new());
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
            return (report, None, Vec::new());
        }
    };
    report.geometry = Some(model.geometry.clone());
    report.model = Some(ModelReport::Hobbing(Box::new(model.model.clone())));
    report.warnings = model.warnings.clone();
    let mut sim = Vec::new();
    match templates.instantiate(&model) {
        Ok(mut p) => {
            report.errors = gearcam_template::render::path_check_errors(&p);
            // Only a program whose path holds is run on the virtual machine.
            if let (Some(settings), true) = (simulation, p.path_check.ok) {
                match gearcam_template::simulation::out_of_scope(&model) {
                    Some(why) => report.not_simulated = Some(why.to_string()),
                    None => sim = run(&model, settings, &mut p),
                }
            }
            report
                .errors
                .extend(gearcam_template::simulation::simulation_errors(&p));
            report.ok = report.errors.is_empty();
            report
                .warnings
                .extend(gearcam_template::simulation::warnings(&p, Some(&model)));
            report.simulation = p.simulation;
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
    (report, Some(model), sim)
}

/// The program run on the virtual machine: its report goes into
/// `program`, the run of every gear comes back (for the charts).
fn run(
    model: &MachiningModel,
    settings: &Settings,
    program: &mut gearcam_proto::NcProgram,
) -> Vec<Simulation> {
    let (_, trace) = gearcam_nc::check(&program.text, model);
    let (report, sim) = gearcam_template::simulation::run(&trace, model, settings);
    program.simulation = Some(report);
    sim
}
