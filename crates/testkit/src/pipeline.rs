//! A job's request, plan, model and program computed in this process: the
//! seeded knowledge base (in memory), the model, the shipped templates. And the
//! seeded machines, read from the seed itself.

use gearcam_proto::{
    JobError, JobId, JobRequest, JobSpec, MachineProfile, MachiningModel, NcProgram, ProcessPlan,
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
