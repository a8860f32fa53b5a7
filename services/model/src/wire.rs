//! The wire EDM family's model (docs/wire.md): from a [`WirePlan`] the
//! gear's outline fitted with arcs, set off by the wire, written in the
//! plan's form and certified by its replay ([`gearcam_wire::programs`]),
//! checked against the machine. Every failure is a typed error on the job
//! file's field.

use gearcam_proto::Code;
use gearcam_proto::{DieFigures, JobError, Stage, WireModel, WirePlan};
use gearcam_wire::die::{centre_distance_mm, check, length_mm, tip_thickness_mm};
use gearcam_wire::programs::{make, Made};

use crate::MODEL_VERSION;

/// The job's die made, or the typed errors that stop it.
pub fn made(plan: &WirePlan) -> Result<Made, Vec<JobError>> {
    let m = &plan.machine;
    let p = &plan.process;
    let die = &plan.die;
    let mut errors: Vec<JobError> = check(die)
        .into_iter()
        .map(|p| p.raise(Stage::Model))
        .collect();
    if !m.programs.contains(&p.program) {
        let forms: Vec<&str> = m.programs.iter().map(|f| f.as_str()).collect();
        errors.push(crate::program_form_error(
            "wire.program",
            &m.id,
            &m.controller,
            &forms,
            p.program.as_str(),
        ));
    }
    if die.thickness_mm > m.max_thickness_mm {
        errors.push(Stage::Model.error(
            Code::MACHINE_RANGE,
            "die.thickness_mm",
            format!("at most {} mm (machine {})", m.max_thickness_mm, m.id),
            format!("{} mm", die.thickness_mm),
            "the plate is thicker than the machine cuts",
        ));
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let made = make(die, p, &[], 1).map_err(|e| vec![e.raise(Stage::Model)])?;
    let reach = made
        .cut
        .path
        .iter()
        .map(|s| s.from())
        .chain(std::iter::once(made.layout.start_hole))
        .map(|q| q.0.hypot(q.1))
        .fold(0.0, f64::max);
    if reach > m.max_radius_mm {
        return Err(vec![Stage::Model.error(
            Code::MACHINE_RANGE,
            "die.module_mm",
            format!(
                "a contour within {} mm of the centre (machine {})",
                m.max_radius_mm, m.id
            ),
            format!("{reach:.3} mm"),
            "the gear is larger than the machine's travel reaches",
        )]);
    }
    Ok(made)
}

/// The figures and certificate of a made die (`model.die`).
pub fn figures(plan: &WirePlan, made: &Made) -> DieFigures {
    let die = &plan.die;
    let o = &made.cut.outline;
    let f = &o.figures;
    let m = &made.certificate.measure;
    let path = length_mm(&made.cut.path);
    DieFigures {
        part: die.part,
        teeth: die.teeth,
        module_mm: die.module_mm,
        pressure_angle_deg: die.pressure_angle_deg,
        profile_shift: die.profile_shift,
        pitch_radius_mm: f.pitch_radius_mm,
        base_radius_mm: f.base_radius_mm,
        tip_radius_mm: f.tip_radius_mm,
        root_radius_mm: f.root_radius_mm,
        form_radius_mm: f.form_radius_mm,
        centre_distance_mm: centre_distance_mm(die),
        undercut: o.undercut,
        tip_thickness_mm: tip_thickness_mm(die),
        offset_mm: made.cut.offset_mm,
        arcs_per_flank: o.arcs_per_flank as u32,
        arcs_per_fillet: o.arcs_per_fillet as u32,
        outline_arcs: made.cut.contour.len() as u32,
        flank_tolerance_um: die.flank_tolerance_um,
        fillet_tolerance_um: die.fillet_tolerance_um,
        max_deviation_um: 1e3 * m.flank_mm.max(m.fillet_mm),
        flank_deviation_um: 1e3 * m.flank_mm,
        fillet_deviation_um: 1e3 * m.fillet_mm,
        closure_um: 1e3 * m.closure_mm,
        blocks: made.certificate.blocks,
        bytes: made.certificate.bytes,
        teeth_written: made.layout.teeth_per_section,
        path_length_mm: path,
        cutting_time_min: path * die.thickness_mm / plan.process.cutting_rate_mm2_min.value,
    }
}

/// The machining model of a wire job.
pub fn compute_wire(plan: &WirePlan) -> Result<WireModel, Vec<JobError>> {
    Ok(model_of(plan, &made(plan)?))
}

/// The machining model of a wire job from its die made ([`made`]).
pub fn model_of(plan: &WirePlan, made: &Made) -> WireModel {
    let mut warnings = Vec::new();
    if made.cut.outline.undercut {
        warnings.push(gearcam_proto::Warning {
            code: Code::FLANK_UNDERCUT,
            field: "die.teeth".into(),
            message: format!(
                "the flank is undercut: the fillet cuts into the involute below {:.3} mm",
                made.cut.outline.figures.form_radius_mm
            ),
        });
    }
    WireModel {
        job_id: plan.job_id.clone(),
        plan: plan.clone(),
        die: figures(plan, made),
        warnings,
        model_version: MODEL_VERSION.to_string(),
    }
}
