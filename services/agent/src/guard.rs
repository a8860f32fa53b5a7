//! Defence in depth before a program is stored: the agent stores
//! only programs of jobs the station journaled for its machine, and checks
//! each program again against the model the model service computed for the
//! job — not the one the sender might claim.
//!
//! - **Journaled**: the station is asked for the jobs' statuses, one
//!   question for a group (`gearcam/v1/station/journaled/{machine}`): each
//!   must exist, be for this machine and
//!   not be failed, superseded or cancelled (`JOB_CANCELLED`: a cancelled
//!   job is never stored, even when its program was on its way). No such job: `JOB_NOT_JOURNALED` (final). No answer:
//!   `STATION_UNREACHABLE` (the job waits and is re-driven). The model the
//!   agent holds already shows the job was journaled for this machine (the
//!   model service plans only what the knowledge service planned from a
//!   request, and under `deploy/secure` only the station publishes requests,
//!   after journaling them), but not that nobody cancelled it since: a
//!   cancellation is a person's decision at the station, so the station's
//!   word at store time is what keeps it. The question is asked before the
//!   programs are checked, and its answer waited for only once their files
//!   are written aside, so its round trip overlaps the checks and the
//!   writes; nothing is renamed into the program directory before it.
//! - **Path check**: the agent follows the models the model service
//!   publishes for its machine (`gearcam/v1/jobs/*/model`, which only the
//!   model service may publish under `deploy/secure`) and re-runs the NC path
//!   check (`gearcam_nc::check`; for the spiral family the replay of
//!   `gearcam_spiral::verify`, for the wire family the replay of
//!   `gearcam_wire::programs::check_plan`) of every program against its job's model.
//!   A finding: `PATH_CHECK_FAILED` (final). No model seen within [`MODEL_WAIT`] of
//!   the delivery (the agent started after it was published): `MODEL_UNKNOWN` (the job waits; the
//!   station's re-drive publishes the model again).

use gearcam_proto::Code;
use std::collections::{HashMap, VecDeque};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use gearcam_bus::query::Retry;
use gearcam_bus::{Bus, CancellationToken};
use gearcam_proto::{
    keys, AnyModel, Incoming, JobError, JobId, JobIds, JobState, JobStatus, MachineId, NcProgram,
    Stage, StationReply,
};

/// Models kept, newest last (a bounded memory).
const MAX_MODELS: usize = 4096;

/// The models kept, by job, and the order they came in.
type Kept = (HashMap<JobId, Arc<AnyModel>>, VecDeque<JobId>);

/// The models the model service published for this machine, by job.
#[derive(Debug, Clone, Default)]
pub struct Models {
    inner: Arc<Mutex<Kept>>,
    /// Woken at each model kept.
    arrived: Arc<tokio::sync::Notify>,
}

/// How long a delivery waits for its job's model: the model goes to the
/// template service and to the agent at once, and the template's program
/// can reach the agent before the model does.
pub const MODEL_WAIT: Duration = Duration::from_millis(500);

impl Models {
    fn insert(&self, model: AnyModel) {
        let Ok(mut g) = self.inner.lock() else { return };
        let (map, order) = &mut *g;
        let job = model.job_id().clone();
        if map.insert(job.clone(), Arc::new(model)).is_none() {
            order.push_back(job);
        }
        while order.len() > MAX_MODELS {
            if let Some(old) = order.pop_front() {
                map.remove(&old);
            }
        }
        drop(g);
        self.arrived.notify_waiters();
    }

    /// Waits until the model of every job in `jobs` is kept, or `limit`
    /// has passed (the check then says which one is missing).
    pub async fn wait_for(&self, jobs: &[JobId], limit: Duration) {
        let deadline = tokio::time::Instant::now() + limit;
        loop {
            let arrived = self.arrived.notified();
            if jobs.iter().all(|j| self.get(j).is_some()) {
                return;
            }
            if tokio::time::timeout_at(deadline, arrived).await.is_err() {
                return;
            }
        }
    }

    fn get(&self, job: &JobId) -> Option<Arc<AnyModel>> {
        self.inner.lock().ok()?.0.get(job).cloned()
    }

    /// Follows the models of `machine` until `shutdown`.
    pub async fn follow(
        bus: &Bus,
        machine: MachineId,
        shutdown: CancellationToken,
    ) -> Result<Models, crate::AgentError> {
        let models = Models::default();
        let sub = bus
            .session()
            .declare_subscriber(keys::ALL_JOB_MODELS)
            .await
            .map_err(|e| {
                crate::AgentError::Bus(gearcam_bus::BusError::Zenoh {
                    op: "declare subscriber",
                    detail: e.to_string(),
                })
            })?;
        let kept = models.clone();
        tokio::spawn(async move {
            loop {
                let sample = tokio::select! {
                    _ = shutdown.cancelled() => break,
                    s = sub.recv_async() => match s { Ok(s) => s, Err(_) => break },
                };
                if let Ok(model) = AnyModel::decode_incoming(&sample.payload().to_bytes()) {
                    if *model.machine() == machine {
                        kept.insert(model);
                    }
                }
            }
        });
        Ok(models)
    }

    /// Re-runs the path check of `program` against its job's model.
    pub fn check(&self, program: &NcProgram) -> Result<(), JobError> {
        let Some(model) = self.get(&program.job_id) else {
            return Err(Stage::Agent.error(
                Code::MODEL_UNKNOWN,
                "job_id",
                "a job whose model the agent has seen from the model service",
                program.job_id.as_str(),
                "the agent checks every program again against the model service's model and has not seen this job's; the job waits and the station's re-drive publishes it again",
            ));
        };
        let check = match &*model {
            AnyModel::Hobbing(model) => gearcam_nc::check(&program.text, model).0,
            AnyModel::Spiral(model) => {
                let form = model.plan.process.program;
                if program.form != Some(form) {
                    return Err(Stage::Agent.error(
                        Code::PATH_CHECK_FAILED,
                        "program.form",
                        format!("the form of the job's model, {}", form.as_str()),
                        program.form.map_or("none", |f| f.as_str()),
                        format!(
                            "program {} is not in the form its job's model was computed for; it was not stored",
                            program.name
                        ),
                    ));
                }
                gearcam_spiral::verify::verify(&program.text, form, model).0
            }
            AnyModel::Wire(model) => {
                match gearcam_wire::programs::check_plan(&program.text, &model.plan) {
                    Ok(_) => gearcam_proto::PathCheck {
                        ok: true,
                        findings: vec![],
                    },
                    Err(p) => gearcam_proto::PathCheck {
                        ok: false,
                        findings: vec![gearcam_proto::PathFinding {
                            line: 0,
                            rule: p.code,
                            message: format!(
                                "{}: expected {}, got {}",
                                p.message, p.expected, p.got
                            ),
                        }],
                    },
                }
            }
        };
        match check.findings.first() {
            None => Ok(()),
            Some(f) => Err(Stage::Agent.error(
                Code::PATH_CHECK_FAILED,
                &format!("program.line.{}", f.line),
                format!("a program that keeps rule {}", f.rule),
                program
                    .text
                    .lines()
                    .nth((f.line as usize).saturating_sub(1))
                    .unwrap_or("")
                    .trim()
                    .to_string(),
                format!(
                    "the agent's own path check of program {} line {}: {} [{}]; {} finding(s) in all; the program was not stored",
                    program.name,
                    f.line,
                    f.message,
                    f.rule,
                    check.findings.len()
                ),
            )),
        }
    }
}

/// Asks the station whether each job is journaled for `machine`, in one
/// question ([`keys::station_journaled`]); one verdict per job, in order.
pub async fn journaled(
    bus: &Bus,
    machine: &MachineId,
    jobs: &[JobId],
) -> Vec<Result<(), JobError>> {
    let retry = Retry {
        timeout: Duration::from_secs(3),
        attempts: 2,
        pause: Duration::from_millis(200),
    };
    let asked = JobIds {
        jobs: jobs.to_vec(),
    };
    let reply = bus
        .call::<JobIds, StationReply>(&keys::station_journaled(machine), Some(&asked), retry)
        .await;
    let statuses: HashMap<&JobId, &JobStatus> = match &reply {
        Ok(StationReply::Jobs { jobs: statuses }) => statuses.iter().map(|s| (&s.job, s)).collect(),
        Ok(other) => {
            let why = format!("the station answered {other:?}");
            return jobs.iter().map(|_| Err(unasked(&why))).collect();
        }
        Err(e) => {
            let error = Stage::Agent.error(
                Code::STATION_UNREACHABLE,
                "job_id",
                "an answer of the planning station about the job",
                e.to_string(),
                "the agent stores only programs of journaled jobs and could not ask the station; the job waits",
            );
            return jobs.iter().map(|_| Err(error.clone())).collect();
        }
    };
    jobs.iter()
        .map(|job| match statuses.get(job) {
            // A cancelled job is never stored, whatever reached the agent
            // before the cancellation did.
            Some(status) if status.machine == *machine && status.state == JobState::Cancelled => {
                Err(status
                    .errors
                    .first()
                    .cloned()
                    .unwrap_or_else(|| JobError::cancelled("unknown")))
            }
            Some(status)
                if status.machine == *machine
                    && !matches!(status.state, JobState::Failed | JobState::Superseded) =>
            {
                Ok(())
            }
            Some(status) => Err(not_journaled(
                job,
                machine,
                &format!(
                    "job {job} of machine {} in state {}",
                    status.machine,
                    status.state.as_str()
                ),
            )),
            None => Err(not_journaled(
                job,
                machine,
                &format!("no job {job} of machine {machine} in the station's journal"),
            )),
        })
        .collect()
}

/// The verdict on a job the station could not be asked about (`why`): the
/// job waits.
pub fn unasked(why: &str) -> JobError {
    Stage::Agent.error(
        Code::STATION_UNREACHABLE,
        "job_id",
        "an answer of the planning station about the job",
        why,
        "the agent could not ask the station; the job waits",
    )
}

fn not_journaled(job: &JobId, machine: &MachineId, got: &str) -> JobError {
    Stage::Agent.error(
        Code::JOB_NOT_JOURNALED,
        "job_id",
        format!("a job the station journaled for machine {machine}, not failed or superseded"),
        got.to_string(),
        format!("the agent stores only programs of journaled jobs of its machine; job {job} is not one, so nothing was stored"),
    )
}
