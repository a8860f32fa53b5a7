//! The knowledge service on the bus: subscribes to job requests, publishes
//! process plans and `planned` events, reports typed errors.

use std::path::PathBuf;

use gearcam_bus::stage::{run_stage, Handled, Output};
use gearcam_bus::{Bus, CancellationToken};
use gearcam_proto::{encode, keys, EventKind, JobError, JobRequest, Stage};

use crate::{db, plan, KnowledgeError};

/// Configuration of the knowledge service.
#[derive(Debug, Clone)]
pub struct Config {
    /// The SQLite database file (created and seeded if missing).
    pub db_path: PathBuf,
}

/// The liveliness name of the knowledge service.
pub const SERVICE: &str = "knowledge";

/// Runs the knowledge service until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    config: Config,
    shutdown: CancellationToken,
) -> Result<(), KnowledgeError> {
    let conn = db::open(&config.db_path)?;
    tracing::info!(db = %config.db_path.display(), "knowledge base open");
    run_stage::<JobRequest, _>(
        &bus,
        keys::ALL_JOB_REQUESTS,
        SERVICE,
        Stage::Knowledge,
        shutdown,
        move |key, req| {
            if keys::job_of(key).as_ref() != Some(&req.job_id) {
                return Err(vec![JobError {
                    stage: Stage::Knowledge,
                    code: "JOB_ID_MISMATCH".into(),
                    field: "job_id".into(),
                    expected: key.to_string(),
                    got: req.job_id.to_string(),
                    message: "the request's job id differs from the job id in its key".into(),
                }]);
            }
            let plan = plan::plan(&conn, &req)?;
            let payload = encode(&plan).map_err(|e| {
                vec![gearcam_bus::stage::codec_error::<JobRequest>(
                    Stage::Knowledge,
                    &e,
                )]
            })?;
            Ok(Handled {
                events: vec![EventKind::Planned {
                    hob_id: plan.hob.id.clone(),
                    confidence: plan.confidence,
                }],
                outputs: vec![Output {
                    key: keys::job_plan(&plan.job_id),
                    payload,
                }],
            })
        },
    )
    .await?;
    Ok(())
}
