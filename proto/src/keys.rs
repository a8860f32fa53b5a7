//! Key-expression builders: the only place key strings are spelled out.
//!
//! Every key starts with the versioned prefix [`PREFIX`]. See `proto/README.md`
//! for who publishes and who subscribes on each.

use crate::ids::{JobId, MachineId};

/// The versioned prefix of every gearcam key.
pub const PREFIX: &str = "gearcam/v1";

/// `gearcam/v1/jobs/{job}/request`: a [`crate::JobRequest`] from a planning station.
pub fn job_request(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/request")
}

/// `gearcam/v1/jobs/{job}/plan`: the knowledge service's [`crate::ProcessPlan`].
pub fn job_plan(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/plan")
}

/// `gearcam/v1/jobs/{job}/model`: the model service's [`crate::MachiningModel`].
pub fn job_model(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/model")
}

/// `gearcam/v1/jobs/{job}/events`: [`crate::JobEvent`]s from every stage.
pub fn job_events(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/events")
}

/// `gearcam/v1/machines/{machine}/programs/{job}`: an [`crate::NcProgram`] for a machine's agent.
pub fn machine_program(machine: &MachineId, job: &JobId) -> String {
    format!("{PREFIX}/machines/{machine}/programs/{job}")
}

/// Subscription pattern for all job requests.
pub const ALL_JOB_REQUESTS: &str = "gearcam/v1/jobs/*/request";
/// Subscription pattern for all process plans.
pub const ALL_JOB_PLANS: &str = "gearcam/v1/jobs/*/plan";
/// Subscription pattern for all machining models.
pub const ALL_JOB_MODELS: &str = "gearcam/v1/jobs/*/model";
/// Subscription pattern for all job events.
pub const ALL_JOB_EVENTS: &str = "gearcam/v1/jobs/*/events";

/// Subscription pattern for every program sent to one machine.
pub fn machine_programs(machine: &MachineId) -> String {
    format!("{PREFIX}/machines/{machine}/programs/*")
}

/// Liveliness token of a running service: `gearcam/v1/alive/{service}`, e.g.
/// `gearcam/v1/alive/model` or, for an agent, `gearcam/v1/alive/agent/H01`.
pub fn alive(service: &str) -> String {
    format!("{PREFIX}/alive/{service}")
}

/// The liveliness name of a machine's delivery agent.
pub fn agent_service(machine: &MachineId) -> String {
    format!("agent/{machine}")
}

/// The job id inside a job key (`gearcam/v1/jobs/{job}/...`) or program key
/// (`gearcam/v1/machines/{machine}/programs/{job}`), if the key is well formed.
pub fn job_of(key: &str) -> Option<JobId> {
    let rest = key.strip_prefix(PREFIX)?.strip_prefix('/')?;
    let parts: Vec<&str> = rest.split('/').collect();
    let raw = match parts.as_slice() {
        ["jobs", job, _] => job,
        ["machines", _, "programs", job] => job,
        _ => return None,
    };
    JobId::new(*raw).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builds_and_parses_keys() {
        let job = JobId::new("J1").unwrap();
        let m = MachineId::new("H01").unwrap();
        assert_eq!(job_request(&job), "gearcam/v1/jobs/J1/request");
        assert_eq!(
            machine_program(&m, &job),
            "gearcam/v1/machines/H01/programs/J1"
        );
        assert_eq!(job_of(&job_events(&job)), Some(job.clone()));
        assert_eq!(job_of(&machine_program(&m, &job)), Some(job));
        assert_eq!(job_of("gearcam/v1/other/J1"), None);
        assert_eq!(alive(&agent_service(&m)), "gearcam/v1/alive/agent/H01");
    }
}
