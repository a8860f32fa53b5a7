//! The agent on the bus: subscribes to its machine's programs, stores each one,
//! and publishes the receipt (or a typed refusal) on the job's events key.

use gearcam_bus::stage::{run_stage, Handled};
use gearcam_bus::{Bus, CancellationToken};
use gearcam_proto::{keys, EventKind, JobError, NcProgram, Stage};

use crate::store::{Store, StoreConfig};
use crate::AgentError;

/// Runs the agent for one machine until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    config: StoreConfig,
    shutdown: CancellationToken,
) -> Result<(), AgentError> {
    let machine = config.machine.clone();
    let mut store = Store::open(config)?;
    tracing::info!(%machine, dir = %store.config().program_dir.display(), "program store open");
    run_stage::<NcProgram, _>(&bus, &keys::machine_programs(&machine), &keys::agent_service(&machine), Stage::Agent, shutdown, |key, p| {
        if keys::job_of(key).as_ref() != Some(&p.job_id) {
            return Err(vec![JobError {
                stage: Stage::Agent,
                code: "JOB_ID_MISMATCH".into(),
                field: "job_id".into(),
                expected: key.to_string(),
                got: p.job_id.to_string(),
                message: "the program's job id differs from the job id in its key".into(),
            }]);
        }
        let receipt = store.store(&p).map_err(|e| vec![e])?;
        tracing::info!(job = %receipt.job_id, file = receipt.file_name, sha256 = receipt.sha256, duplicate = receipt.duplicate, "program stored");
        Ok(Handled {
            events: vec![EventKind::Delivered { receipt }],
            outputs: vec![],
        })
    })
    .await?;
    Ok(())
}
