//! The wire EDM family's programs (docs/wire.md): the model's die written
//! in the plan's form (3B, 4B or ISO wire G-code) by
//! [`gearcam_wire::programs`], with a header naming the job, the part, the
//! gear, the wire and the certificate; then read back, replayed and
//! measured against the theoretical outline before it may leave.

use gearcam_proto::naming;
use gearcam_proto::Code;
use gearcam_proto::{
    utc_text, Cutter, DiePart, JobError, NcProgram, PathCheck, Stage, TemplateRef, WireModel,
    WireProgram,
};
use gearcam_wire::programs::make;
use sha2::{Digest, Sha256};

use crate::render::GENERATOR;

pub use crate::forms::WIRE_FORMS_VERSION;

/// The header lines of a wire program.
pub fn header(model: &WireModel, name: &str) -> Vec<String> {
    let plan = &model.plan;
    let job = &plan.request.spec.job;
    let d = &plan.die;
    let f = &model.die;
    let p = &plan.process;
    let cutter = match (d.cutter, d.cutter_teeth) {
        (Cutter::Pinion, Some(z0)) => format!(
            "PINION CUTTER Z0 {z0} X0 {} TIP R {}M",
            d.cutter_shift, d.cutter_tip_radius_coef
        ),
        _ => format!("RACK CUTTER TIP R {}M", d.cutter_tip_radius_coef),
    };
    vec![
        format!("PROGRAM {name} JOB {} PART {}", plan.job_id, job.part_number),
        format!(
            "ORDER QTY={} PLATE {} {} MM",
            job.quantity, d.material, d.thickness_mm
        ),
        format!(
            "SUBMITTED {} BY {}",
            utc_text(plan.request.submitted_at_ms),
            plan.request.submitted_by
        ),
        format!("MACHINE {} {}", plan.machine.id, plan.machine.controller),
        format!(
            "{} OF SPUR GEAR M {} Z {} ALPHA {} X {} HA {} C {} {cutter}",
            match d.part {
                DiePart::Punch => "PUNCH",
                DiePart::Die => "DIE",
            },
            d.module_mm,
            d.teeth,
            d.pressure_angle_deg,
            d.profile_shift,
            d.addendum_coef,
            d.clearance_coef
        ),
        format!(
            "RADII BASE {:.4} TIP {:.4} ROOT {:.4} FORM {:.4} MM{}",
            f.base_radius_mm,
            f.tip_radius_mm,
            f.root_radius_mm,
            f.form_radius_mm,
            if f.undercut { " UNDERCUT" } else { "" }
        ),
        format!(
            "WIRE {} D {} GAP {} OFFSET {:.4} MM {}",
            p.wire,
            p.wire_diameter_mm.value,
            p.spark_gap_mm.value,
            f.offset_mm,
            match d.part {
                DiePart::Punch => "OUTSIDE",
                DiePart::Die => "INSIDE",
            }
        ),
        format!(
            "TECHNOLOGY ON {} US OFF {} US I {} A RATE {} MM2/MIN",
            p.pulse_on_us.value, p.pulse_off_us.value, p.current_a.value, p.cutting_rate_mm2_min.value
        ),
        format!(
            "ARCS PER FLANK {} PER FILLET {} OUTLINE {}",
            f.arcs_per_flank, f.arcs_per_fillet, f.outline_arcs
        ),
        format!(
            "CERTIFICATE REPLAYED MAX DEVIATION FLANK {:.3} UM FILLET {:.3} UM CLOSURE {:.3} UM TOLERANCE {} / {} UM BLOCKS {}",
            f.flank_deviation_um,
            f.fillet_deviation_um,
            f.closure_um,
            d.flank_tolerance_um,
            d.fillet_tolerance_um,
            f.blocks
        ),
        format!(
            "TEETH WRITTEN {} OF {} PATH {:.1} MM TIME {:.1} MIN",
            f.teeth_written, f.teeth, f.path_length_mm, f.cutting_time_min
        ),
        format!("{} {}", model.model_version, GENERATOR),
    ]
}

/// The number of an `O` program name (1 for a plain name).
fn number(name: &str) -> u32 {
    name.strip_prefix('O')
        .and_then(|n| n.parse().ok())
        .unwrap_or(1)
}

/// Writes the program of a wire model, replays it, and returns it when
/// its replay holds the tolerances.
pub fn render(model: &WireModel) -> Result<NcProgram, Vec<JobError>> {
    let plan = &model.plan;
    let form = plan.process.program;
    let dialect = form.dialect();
    if dialect != plan.machine.dialect {
        return Err(vec![Stage::Template.error(
            Code::PROGRAM_FORM,
            "wire.program",
            format!("a {} form", plan.machine.dialect.as_str()),
            form.as_str().to_string(),
            format!(
                "{} runs {} programs",
                plan.machine.id,
                plan.machine.dialect.as_str()
            ),
        )]);
    }
    let job = &model.plan.request.spec.job;
    let four_b = model.plan.process.program == WireProgram::FourB;
    let (name, _file) = naming::program_name(dialect, job, four_b)
        .map_err(|p| vec![p.error(Stage::Template, dialect)])?;
    let lines = header(model, &name);
    // `make` writes the text, reads it back, replays it and measures it:
    // it returns a program only when the replay holds the tolerances.
    let made = make(&plan.die, &plan.process, &lines, number(&name))
        .map_err(|p| vec![p.raise(Stage::Template)])?;
    let text = made.written.text;
    let path_check = PathCheck {
        ok: true,
        findings: vec![],
    };
    let sha256 = hex::encode(Sha256::digest(text.as_bytes()));
    Ok(NcProgram {
        job_id: model.job_id.clone(),
        machine: plan.machine.id.clone(),
        name,
        revision: 1,
        dialect,
        text,
        sha256,
        template: TemplateRef {
            id: crate::forms::wire_id(form),
            version: WIRE_FORMS_VERSION,
        },
        part_number: plan.request.spec.job.part_number.clone(),
        cases: plan.cases.iter().map(|c| c.id.clone()).collect(),
        model_version: model.model_version.clone(),
        generator: GENERATOR.to_string(),
        path_check,
        form: None,
        simulation: None,
    })
}
