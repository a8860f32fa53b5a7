//! `gearcam check` for a spiral face milling job: knowledge → model →
//! program and its replay, and the picture of the path and its coverage.

use std::collections::BTreeMap;

use gearcam_proto::{JobRequest, Source, Sourced, SpiralModel, SpiralPart};
use rusqlite::Connection;

use super::{CheckReport, MachineSummary, ModelReport, PlanSummary, ProgramSummary, SpiralReport};

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
