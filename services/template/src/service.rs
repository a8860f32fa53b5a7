//! The template service on the bus: subscribes to machining models, renders the
//! machine's NC program (`programmed` event), and delivers it to the machine's
//! agent as a request (query) answered by the agent's receipt or refusal.
//!
//! Delivery runs in its own task per program, so a slow or absent agent never
//! holds up programs for other machines. When the agent is offline or does not
//! answer, the job gets a `waiting` event; the planning station re-drives it
//! when the agent is back (every stage is idempotent, and the agent answers a
//! repeat with the original receipt).

use std::time::Duration;

use gearcam_bus::alive::Alive;
use gearcam_bus::query::{CallError, Retry};
use gearcam_bus::stage::{run_stage, Handled};
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::{keys, AnyModel, DeliveryReply, EventKind, JobError, NcProgram, Stage};
use tokio::sync::mpsc;

use crate::Templates;

/// The liveliness name of the template service.
pub const SERVICE: &str = "template";

/// How long one delivery attempt waits for the agent's receipt.
pub const DELIVERY_TIMEOUT: Duration = Duration::from_secs(10);

/// Runs the template service until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    templates: Templates,
    shutdown: CancellationToken,
) -> Result<(), BusError> {
    let (tx, mut rx) = mpsc::unbounded_channel::<NcProgram>();
    let delivery_bus = bus.clone();
    let alive = Alive::follow(&bus, shutdown.clone()).await?;
    let stop = shutdown.clone();
    let deliveries = tokio::spawn(async move {
        loop {
            let program = tokio::select! {
                _ = stop.cancelled() => break,
                p = rx.recv() => match p { Some(p) => p, None => break },
            };
            tokio::spawn(deliver(delivery_bus.clone(), alive.clone(), program));
        }
    });
    let result = run_stage::<AnyModel, _>(
        &bus,
        keys::ALL_JOB_MODELS,
        SERVICE,
        Stage::Template,
        shutdown,
        |key, model| {
            if keys::job_of(key).as_ref() != Some(model.job_id()) {
                return Err(vec![JobError::job_id_mismatch(
                    Stage::Template,
                    key,
                    model.job_id(),
                    "model",
                )]);
            }
            let hobbing = match &model {
                AnyModel::Hobbing(model) => Some(&**model),
                _ => None,
            };
            let program = match &model {
                AnyModel::Hobbing(model) => templates.render(model)?,
                AnyModel::Spiral(model) => crate::spiral::render(model)?,
                AnyModel::Wire(model) => crate::wire::render(model)?,
            };
            let event = EventKind::Programmed {
                name: program.name.clone(),
                sha256: program.sha256.clone(),
                predicted_grade: program.simulation.as_ref().and_then(|s| s.part_grade()),
                warnings: crate::simulation::warnings(&program, hobbing),
            };
            // The receiver lives until shutdown; a send after it is gone is moot.
            let _ = tx.send(program);
            Ok(Handled {
                events: vec![event],
                outputs: vec![],
            })
        },
    )
    .await;
    deliveries.abort();
    result
}

/// Hands one program to its machine's agent (asked only when `alive` has
/// seen its token, or the bus says it is there).
pub async fn deliver(bus: Bus, alive: Alive, program: NcProgram) {
    let job = program.job_id.clone();
    let agent = keys::agent_service(&program.machine);
    let waiting = |reason: String| EventKind::Waiting { reason };
    let event = match alive.check(&bus, &agent).await {
        Ok(false) => Some(waiting(format!(
            "the agent of machine {} is offline",
            program.machine
        ))),
        Err(e) => Some(waiting(format!("cannot reach the bus: {e}"))),
        Ok(true) => {
            let retry = Retry {
                timeout: DELIVERY_TIMEOUT,
                attempts: 3,
                pause: Duration::from_millis(300),
            };
            let key = keys::machine_program(&program.machine, &job);
            match bus
                .call::<NcProgram, DeliveryReply>(&key, Some(&program), retry)
                .await
            {
                // The agent publishes `delivered` or `failed` itself.
                Ok(DeliveryReply::Stored { .. }) | Ok(DeliveryReply::Refused { .. }) => None,
                Ok(DeliveryReply::NotStored) => {
                    Some(waiting("the agent answered without storing".into()))
                }
                Err(CallError::NoReply { .. }) => Some(waiting(format!(
                    "the agent of machine {} did not answer",
                    program.machine
                ))),
                Err(e) => Some(waiting(format!(
                    "delivery to machine {} failed: {e}",
                    program.machine
                ))),
            }
        }
    };
    if let Some(ev) = event {
        tracing::info!(%job, ?ev, "delivery pending");
        if let Err(e) = bus.event(&job, Stage::Template, ev).await {
            tracing::warn!(%job, error = %e, "cannot publish event");
        }
    }
}
