//! The client side of a machine's program store (`gearcam program …`): every
//! answer is the agent's typed [`StoreReply`]; a refusal comes back as its
//! [`JobError`].

use gearcam_bus::query::{CallError, Retry};
use gearcam_bus::Bus;
use gearcam_proto::{
    keys, DeliveryReceipt, JobError, JobId, JobRequest, MachineId, ProgramHistory, ProgramText,
    Stage, StoreReply, StoreRequest,
};

/// What a store query gives: the answer, or the store's refusal.
pub type Answer<T> = Result<T, JobError>;

/// Every version of every program (or of program `name`), newest first.
pub async fn history(
    bus: &Bus,
    machine: &MachineId,
    name: Option<&str>,
) -> Result<Answer<ProgramHistory>, CallError> {
    let key = match name {
        Some(n) => keys::store_program(machine, n),
        None => keys::store_programs(machine),
    };
    Ok(match ask(bus, &key, None).await? {
        StoreReply::History { history } => Ok(history),
        other => Err(refusal(other)),
    })
}

/// Version `seq` of program `name`, with its text.
pub async fn version(
    bus: &Bus,
    machine: &MachineId,
    name: &str,
    seq: u64,
) -> Result<Answer<ProgramText>, CallError> {
    Ok(
        match ask(bus, &keys::store_version(machine, name, seq), None).await? {
            StoreReply::Version { program } => Ok(*program),
            other => Err(refusal(other)),
        },
    )
}

/// Changes the machine's current program `name`: a rollback to a stored
/// version, or the resolution of an edit at the machine. The version now
/// current, and the jobs an adoption ended (`superseded`).
pub async fn change(
    bus: &Bus,
    machine: &MachineId,
    name: &str,
    request: &StoreRequest,
) -> Result<Answer<(DeliveryReceipt, Vec<JobId>)>, CallError> {
    Ok(
        match ask(bus, &keys::store_change(machine, name), Some(request)).await? {
            StoreReply::Changed {
                receipt,
                superseded,
            } => Ok((receipt, superseded)),
            other => Err(refusal(other)),
        },
    )
}

async fn ask(
    bus: &Bus,
    key: &str,
    request: Option<&StoreRequest>,
) -> Result<StoreReply, CallError> {
    match request {
        Some(r) => {
            bus.call::<StoreRequest, StoreReply>(key, Some(r), Retry::default())
                .await
        }
        None => {
            bus.call::<JobRequest, StoreReply>(key, None, Retry::default())
                .await
        }
    }
}

fn refusal(reply: StoreReply) -> JobError {
    match reply {
        StoreReply::Refused { error } => error,
        other => JobError::new(
            Stage::Agent,
            "UNEXPECTED_REPLY",
            "reply",
            "the reply of the store's protocol for this query",
            format!("{other:?}"),
            "the agent answered with another kind of reply; is it another version?",
        ),
    }
}
