//! The client side of a machine's program store (`gearcam program …`): every
//! answer is the agent's typed [`StoreReply`]; a refusal comes back as its
//! [`JobError`].

use gearcam_bus::query::{CallError, Retry};
use gearcam_bus::Bus;
use gearcam_proto::Code;
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
    Ok(match ask(bus, machine, &key, None).await? {
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
        match ask(bus, machine, &keys::store_version(machine, name, seq), None).await? {
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
        match ask(
            bus,
            machine,
            &keys::store_change(machine, request.by(), name),
            Some(request),
        )
        .await?
        {
            StoreReply::Changed {
                receipt,
                superseded,
            } => Ok((receipt, superseded)),
            other => Err(refusal(other)),
        },
    )
}

/// Asks the store of `machine`. When nothing answers and the machine has
/// no agent on the bus, the answer is the refusal `AGENT_OFFLINE` naming
/// the machines whose agents are there (an unknown machine, or its agent
/// not running), not a question whether `gearcam up` runs.
async fn ask(
    bus: &Bus,
    machine: &MachineId,
    key: &str,
    request: Option<&StoreRequest>,
) -> Result<StoreReply, CallError> {
    let reply = match request {
        Some(r) => {
            bus.call::<StoreRequest, StoreReply>(key, Some(r), Retry::default())
                .await
        }
        None => {
            bus.call::<JobRequest, StoreReply>(key, None, Retry::default())
                .await
        }
    };
    match reply {
        Err(e)
            if !bus
                .is_alive(&keys::agent_service(machine))
                .await
                .unwrap_or(true) =>
        {
            let agents = agents_on_the_bus(bus).await;
            Ok(StoreReply::Refused {
                error: JobError::new(
                    Stage::Agent,
                    Code::AGENT_OFFLINE,
                    "machine",
                    if agents.is_empty() {
                        "a machine whose agent is on the bus (none is: is `gearcam up` or the machine's agent running?)".to_string()
                    } else {
                        format!("a machine whose agent is on the bus: {}", agents.join(", "))
                    },
                    machine.as_str(),
                    format!(
                        "no agent of machine {machine} is on the bus ({e}); check the machine's id (gearcam kb list machines, mill-machines, wire-machines) and that its agent runs"
                    ),
                ),
            })
        }
        other => other,
    }
}

/// The machines whose agents have a liveliness token on the bus, sorted.
pub async fn agents_on_the_bus(bus: &Bus) -> Vec<String> {
    let Ok(replies) = bus
        .session()
        .liveliness()
        .get(keys::alive("agent/*"))
        .timeout(std::time::Duration::from_millis(500))
        .await
    else {
        return Vec::new();
    };
    let mut machines = Vec::new();
    while let Ok(reply) = replies.recv_async().await {
        if let Ok(sample) = reply.result() {
            if let Some(m) =
                keys::alive_of(sample.key_expr().as_str()).and_then(keys::agent_machine_of)
            {
                machines.push(m.to_string());
            }
        }
    }
    machines.sort();
    machines.dedup();
    machines
}

fn refusal(reply: StoreReply) -> JobError {
    match reply {
        StoreReply::Refused { error } => error,
        other => JobError::new(
            Stage::Agent,
            Code::UNEXPECTED_REPLY,
            "reply",
            "the reply of the store's protocol for this query",
            format!("{other:?}"),
            "the agent answered with another kind of reply; is it another version?",
        ),
    }
}
