//! The template service on the bus: subscribes to machining models, renders the
//! machine's NC program and sends it to the machine's delivery agent, with a
//! `programmed` event; failures come back as typed errors.

use gearcam_bus::stage::{codec_error, run_stage, Handled, Output};
use gearcam_bus::{Bus, BusError, CancellationToken};
use gearcam_proto::{encode, keys, EventKind, JobError, MachiningModel, Stage};

use crate::Templates;

/// The liveliness name of the template service.
pub const SERVICE: &str = "template";

/// Runs the template service until `shutdown` is cancelled.
pub async fn run(
    bus: Bus,
    templates: Templates,
    shutdown: CancellationToken,
) -> Result<(), BusError> {
    run_stage::<MachiningModel, _>(
        &bus,
        keys::ALL_JOB_MODELS,
        SERVICE,
        Stage::Template,
        shutdown,
        |key, model| {
            if keys::job_of(key).as_ref() != Some(&model.job_id) {
                return Err(vec![JobError {
                    stage: Stage::Template,
                    code: "JOB_ID_MISMATCH".into(),
                    field: "job_id".into(),
                    expected: key.to_string(),
                    got: model.job_id.to_string(),
                    message: "the model's job id differs from the job id in its key".into(),
                }]);
            }
            let program = templates.render(&model)?;
            let payload = encode(&program)
                .map_err(|e| vec![codec_error::<MachiningModel>(Stage::Template, &e)])?;
            Ok(Handled {
                events: vec![EventKind::Programmed {
                    name: program.name.clone(),
                    sha256: program.sha256.clone(),
                }],
                outputs: vec![Output {
                    key: keys::machine_program(&program.machine, &program.job_id),
                    payload,
                }],
            })
        },
    )
    .await
}
