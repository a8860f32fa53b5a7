//! The model service on the bus: subscribes to process plans, publishes
//! machining models and `modelled` events, or typed errors listing every
//! failed check.

use gearcam_bus::stage::{codec_error, run_stage, Handled, Output};
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::{encode, keys, EventKind, JobError, ProcessPlan, Stage};

use crate::compute;

/// The liveliness name of the model service.
pub const SERVICE: &str = "model";

/// Runs the model service until `shutdown` is cancelled.
pub async fn run(bus: Bus, shutdown: CancellationToken) -> Result<(), BusError> {
    run_stage::<ProcessPlan, _>(
        &bus,
        keys::ALL_JOB_PLANS,
        SERVICE,
        Stage::Model,
        shutdown,
        |key, plan| {
            if keys::job_of(key).as_ref() != Some(&plan.job_id) {
                return Err(vec![JobError::job_id_mismatch(
                    Stage::Model,
                    key,
                    &plan.job_id,
                    "plan",
                )]);
            }
            let model = compute(&plan)?;
            let payload =
                encode(&model).map_err(|e| vec![codec_error::<ProcessPlan>(Stage::Model, &e)])?;
            Ok(Handled {
                events: vec![EventKind::Modelled {
                    warnings: model.warnings.clone(),
                }],
                outputs: vec![Output {
                    key: keys::job_model(&model.job_id),
                    payload,
                }],
            })
        },
    )
    .await
}
