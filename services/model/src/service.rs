//! The model service on the bus: subscribes to process plans, publishes
//! machining models and `modelled` events, or typed errors listing every
//! failed check.

use gearcam_bus::stage::{codec_error, run_stage, Handled, Output};
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::{encode, keys, AnyPlan, EventKind, JobError, Stage};

use crate::{compute, spiral::compute_spiral};

/// The liveliness name of the model service.
pub const SERVICE: &str = "model";

/// Runs the model service until `shutdown` is cancelled.
pub async fn run(bus: Bus, shutdown: CancellationToken) -> Result<(), BusError> {
    run_stage::<AnyPlan, _>(
        &bus,
        keys::ALL_JOB_PLANS,
        SERVICE,
        Stage::Model,
        shutdown,
        |key, plan| {
            if keys::job_of(key).as_ref() != Some(plan.job_id()) {
                return Err(vec![JobError::job_id_mismatch(
                    Stage::Model,
                    key,
                    plan.job_id(),
                    "plan",
                )]);
            }
            // Each family computes its own model; both go out on the job's
            // model key under their own envelope kind.
            let (job, warnings, payload) = match plan {
                AnyPlan::Hobbing(plan) => {
                    let model = compute(&plan)?;
                    (model.job_id.clone(), model.warnings.clone(), encode(&model))
                }
                AnyPlan::Spiral(plan) => {
                    let model = compute_spiral(&plan)?;
                    (model.job_id.clone(), model.warnings.clone(), encode(&model))
                }
                AnyPlan::Wire(plan) => {
                    let model = crate::wire::compute_wire(&plan)?;
                    (model.job_id.clone(), model.warnings.clone(), encode(&model))
                }
            };
            let payload = payload.map_err(|e| vec![codec_error::<AnyPlan>(Stage::Model, &e)])?;
            Ok(Handled {
                events: vec![EventKind::Modelled { warnings }],
                outputs: vec![Output {
                    key: keys::job_model(&job),
                    payload,
                }],
            })
        },
    )
    .await
}
