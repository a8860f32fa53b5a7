//! A job's request, plan, model and program computed in this process: the
//! seeded knowledge base (in memory), the model, the shipped templates. And the
//! seeded machines, read from the seed itself.

use gearcam_proto::{
    GearSpec, Hand, JobError, JobId, JobRequest, JobSpec, MachineProfile, MachiningModel,
    NcProgram, ProcessPlan,
};

/// The request of a job file's text, under job id `job`.
pub fn request(text: &str, job: &str) -> JobRequest {
    let spec: JobSpec = toml::from_str(text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    JobRequest {
        job_id: JobId::new(job).expect("a valid job id"),
        submitted_at_ms: 0,
        submitted_by: "test".into(),
        spec,
    }
}

/// The job's plan from the seeded knowledge base, or the knowledge service's errors.
pub fn plan_of(text: &str) -> Result<ProcessPlan, Vec<JobError>> {
    let conn = gearcam_knowledge::db::open_in_memory().expect("an in-memory knowledge base");
    gearcam_knowledge::plan::plan(&conn, &request(text, "TEST-1"))
}

/// The job's model (planned, then computed), or the first refusing stage's errors.
pub fn model_of(text: &str) -> Result<MachiningModel, Vec<JobError>> {
    gearcam_model::compute(&plan_of(text)?)
}

/// A spiral job's model (planned, then computed), or the first refusing stage's errors.
pub fn spiral_model_of(text: &str) -> Result<gearcam_proto::SpiralModel, Vec<JobError>> {
    let conn = gearcam_knowledge::db::open_in_memory().expect("an in-memory knowledge base");
    let plan = gearcam_knowledge::spiral::plan_spiral(&conn, &request(text, "TEST-1"))?;
    gearcam_model::spiral::compute_spiral(&plan)
}

/// A wire job's model (planned, then computed), or the first refusing stage's errors.
pub fn wire_model_of(text: &str) -> Result<gearcam_proto::WireModel, Vec<JobError>> {
    let conn = gearcam_knowledge::db::open_in_memory().expect("an in-memory knowledge base");
    let plan = gearcam_knowledge::wire::plan_wire(&conn, &request(text, "TEST-1"))?;
    gearcam_model::wire::compute_wire(&plan)
}

/// The checked program the shipped templates make of a model.
pub fn program_of(model: &MachiningModel) -> Result<NcProgram, Vec<JobError>> {
    gearcam_template::Templates::builtin().render(model)
}

/// The seeded 840D machine `H01`.
pub fn h01() -> MachineProfile {
    gearcam_knowledge::seed::seed_machine_h01()
}

/// The seeded FANUC machine `H02`.
pub fn h02() -> MachineProfile {
    gearcam_knowledge::seed::seed_machine_h02()
}

/// A gear for unit tests: normal module `module_mm`, `teeth` teeth, helix
/// `helix_angle_deg` (right hand when not 0), αn 20°, face width 30 mm, no
/// profile shift, ha* 1, c* 0.25, blank at the tip diameter, 42CrMo4, grade 8,
/// 100 mm above the table.
pub fn gear(module_mm: f64, teeth: u32, helix_angle_deg: f64) -> GearSpec {
    GearSpec {
        module_mm,
        teeth,
        pressure_angle_deg: 20.0,
        helix_angle_deg,
        helix_hand: (helix_angle_deg != 0.0).then_some(Hand::Right),
        face_width_mm: 30.0,
        profile_shift: 0.0,
        addendum_coef: 1.0,
        clearance_coef: 0.25,
        blank_od_mm: None,
        od_correction_mm: 0.0,
        material: "42CrMo4".into(),
        quality_grade: 8,
        fixture_height_mm: 100.0,
        fixture_diameter_mm: None,
        ball_diameter_mm: None,
        mate: None,
        cone: None,
        crowning: None,
        worm_wheel: None,
        curved_tooth: None,
    }
}
