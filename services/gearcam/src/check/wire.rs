//! `gearcam check` for a wire EDM job: knowledge → model → program, the
//! figures and certificate (`model.die`), and the picture of the seed's
//! graphical check.

use std::collections::BTreeMap;

use gearcam_proto::{JobRequest, Sourced, WireModel};
use gearcam_wire::programs::Made;
use rusqlite::Connection;

use super::{CheckReport, MachineSummary, ModelReport, PlanSummary, ProgramSummary, WireReport};

/// Knowledge → model → program for a wire job; the report, and the model
/// with its die as made (for the picture).
pub fn check_wire(
    conn: &Connection,
    req: &JobRequest,
    mut report: CheckReport,
) -> (CheckReport, Option<(WireModel, Made)>) {
    let plan = match gearcam_knowledge::wire::plan_wire(conn, req) {
        Ok(p) => p,
        Err(errors) => {
            report.errors = errors;
            return (report, None);
        }
    };
    let p = &plan.process;
    let values: BTreeMap<String, Sourced> = [
        ("wire_diameter_mm", p.wire_diameter_mm),
        ("spark_gap_mm", p.spark_gap_mm),
        ("pulse_on_us", p.pulse_on_us),
        ("pulse_off_us", p.pulse_off_us),
        ("current_a", p.current_a),
        ("cutting_rate_mm2_min", p.cutting_rate_mm2_min),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    report.plan = Some(PlanSummary::of_sourced(
        format!("wire-{}", plan.die.part.as_str()),
        MachineSummary::of(&plan.machine.id, &plan.machine.name, plan.machine.dialect),
        p.wire.clone(),
        plan.confidence,
        &plan.cases,
        values,
        None,
    ));
    let made = match gearcam_model::wire::made(&plan) {
        Ok(m) => m,
        Err(errors) => {
            report.errors = errors;
            return (report, None);
        }
    };
    let model = gearcam_model::wire::model_of(&plan, &made);
    report.model = Some(ModelReport::Wire(Box::new(WireReport {
        die: model.die.clone(),
    })));
    report.warnings = model.warnings.clone();
    match gearcam_template::wire::render(&model) {
        Ok(p) => {
            report.ok = true;
            report.program = Some(ProgramSummary {
                name: p.name,
                dialect: plan.process.program.as_str().into(),
                template: p.template,
                sha256: p.sha256,
                path_check: p.path_check,
                text: p.text,
            });
        }
        Err(errors) => report.errors = errors,
    }
    (report, Some((model, made)))
}

/// The picture of a wire model's die (SVG) and its part outline as DXF.
pub fn die_drawings(model: &WireModel, made: &Made) -> Result<(String, Vec<u8>), String> {
    let plan = &model.plan;
    let svg = gearcam_wire::picture::die_svg(
        made,
        &format!(
            "{} {} m{} z{}",
            plan.request.spec.job.part_number,
            plan.die.part.as_str(),
            plan.die.module_mm,
            plan.die.teeth
        ),
    );
    let dxf = gearcam_wire::dxf::drawing(&made.cut.contour).map_err(|e| e.message)?;
    Ok((svg, dxf))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{check as check_any, format_errors, Drawing};
    use gearcam_template::Templates;

    /// Every wire example of `examples/` through knowledge, model and
    /// program as `gearcam check` runs it: a valid one is certified by its
    /// replay within its tolerances and drawn; an invalid one gets the code
    /// it names. Between them the examples use every form, both parts, a
    /// quarter, a half or whole, both cutters and an undercut.
    #[test]
    fn every_wire_example_runs_or_fails_with_its_named_error() {
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let templates = Templates::builtin();
        let wire: Vec<_> = gearcam_testkit::examples::all()
            .into_iter()
            .filter(|(_, t)| gearcam_testkit::examples::is_wire(t))
            .collect();
        assert!(wire.len() >= 8, "{} wire examples", wire.len());
        let mut seen = std::collections::BTreeSet::new();
        for (name, text) in wire {
            let spec = crate::jobfile::parse(&text, &name).unwrap();
            let (report, model) =
                check_any(&conn, &templates, &crate::jobfile::request(spec), None);
            match gearcam_testkit::examples::expected_code(&text) {
                Some(code) => assert!(
                    report.errors.iter().any(|e| e.code == code),
                    "{name}: expected {code}: {}",
                    format_errors(&report.errors)
                ),
                None => {
                    assert!(report.ok, "{name}: {}", format_errors(&report.errors));
                    let Some(Drawing::Wire(model, made)) = model else {
                        panic!("{name}: no wire model")
                    };
                    let d = &model.die;
                    assert!(d.flank_deviation_um <= d.flank_tolerance_um, "{name}");
                    assert!(d.fillet_deviation_um <= d.fillet_tolerance_um, "{name}");
                    assert!(d.closure_um <= d.flank_tolerance_um, "{name}");
                    seen.insert(report.program.unwrap().dialect);
                    seen.insert(d.part.as_str().to_string());
                    seen.insert(format!("teeth written {}", d.teeth / d.teeth_written));
                    if d.undercut {
                        seen.insert("undercut".into());
                    }
                    let (svg, dxf) = die_drawings(&model, &made).unwrap();
                    assert!(svg.starts_with("<svg") && svg.contains("<path"), "{name}");
                    // The outline as DXF reads back closed, every tooth.
                    let back = gearcam_wire::dxf::read_back(&dxf).unwrap();
                    assert!(back.len() >= d.outline_arcs as usize, "{name}");
                }
            }
        }
        for want in [
            "3b",
            "4b",
            "iso-wire",
            "punch",
            "die",
            "teeth written 4",
            "teeth written 1",
            "undercut",
        ] {
            assert!(seen.contains(want), "no example with {want}: {seen:?}");
        }
    }

    /// `gearcam check --json` of a die: `model.die` with the gear's figures
    /// and the fit's certificate (arcs, deviation, closure, blocks),
    /// `program.dialect` the form.
    #[test]
    fn a_die_report_has_the_figures_and_certificate_in_json() {
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let text = gearcam_testkit::examples::example("die_m1z40_iso.toml");
        let spec = crate::jobfile::parse(&text, "die_m1z40_iso.toml").unwrap();
        let (report, _) = check_any(
            &conn,
            &Templates::builtin(),
            &crate::jobfile::request(spec),
            None,
        );
        let v = serde_json::to_value(&report).unwrap();
        let die = &v["model"]["die"];
        for key in [
            "part",
            "teeth",
            "module_mm",
            "pressure_angle_deg",
            "profile_shift",
            "base_radius_mm",
            "tip_radius_mm",
            "root_radius_mm",
            "arcs_per_flank",
            "arcs_per_fillet",
            "max_deviation_um",
            "closure_um",
            "outline_arcs",
            "blocks",
        ] {
            assert!(!die[key].is_null(), "model.die.{key} missing: {die}");
        }
        assert_eq!(die["part"], "die");
        assert_eq!(die["teeth"], 40);
        // ISO 21771 radii for m 1, z 40, x 0 (d = m·z, db = d·cos 20°).
        assert!(
            (die["base_radius_mm"].as_f64().unwrap() - 20.0 * 20f64.to_radians().cos()).abs()
                < 1e-9
        );
        assert_eq!(v["program"]["dialect"], "iso-wire");
        assert!(v["program"]["text"].as_str().unwrap().contains("G42 D1"));
    }
}
