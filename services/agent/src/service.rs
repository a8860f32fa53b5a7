//! The agent on the bus. Delivery is a request: the template service queries
//! `gearcam/v1/machines/{machine}/programs/{job}` with the program, and the
//! agent answers with its receipt only once file and index row are durable (or
//! with a typed refusal), and publishes the same as a job event. The store is
//! also queryable for lost receipts, history, versions and rollback.

use gearcam_bus::query::{run_queryable_batched, Answer};
use gearcam_bus::stage::codec_error;
use gearcam_bus::{Bus, CancellationToken};
use gearcam_proto::keys::AgentKey;
use gearcam_proto::Code;
use gearcam_proto::{
    decode, keys, DeliveryReply, EventKind, JobError, JobId, NcProgram, ProgramHistory, Stage,
    StoreReply, StoreRequest,
};

use crate::guard::{self, Models};
use crate::store::{Resolution, Store, StoreConfig};
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
    // One machine, one agent: the later of two refuses to serve.
    let serving = shutdown.child_token();
    let single = single_agent(&bus, &machine, serving.clone()).await?;
    if let Some(earlier) = single.refused() {
        return Err(AgentError::Duplicate(duplicate_message(&machine, &earlier)));
    }
    let models = Models::follow(&bus, machine.clone(), serving.clone()).await?;
    let guard_bus = bus.clone();
    let runtime = tokio::runtime::Handle::current();
    let pattern = keys::agent_any(&machine);
    run_queryable_batched(
        &bus,
        &pattern,
        Some(&keys::agent_service(&machine)),
        Stage::Agent,
        serving,
        MAX_BATCH,
        |batch| {
            // Deliveries are stored together (one group commit); every other
            // query is answered on its own, after them.
            let mut answers: Vec<Option<Answer>> = batch.iter().map(|_| None).collect();
            let mut deliveries = Vec::new();
            for (i, (key, payload)) in batch.iter().enumerate() {
                if let Some(AgentKey::Delivery(job)) = keys::agent_key_of(&machine, key) {
                    match decode_delivery(job, payload) {
                        Ok(program) => deliveries.push((i, program)),
                        Err(answer) => answers[i] = Some(answer),
                    }
                }
            }
            let guard = Guard {
                bus: &guard_bus,
                machine: &machine,
                models: &models,
                runtime: &runtime,
            };
            deliver(&mut store, &guard, deliveries, &mut answers);
            for (i, (key, payload)) in batch.iter().enumerate() {
                if answers[i].is_none() {
                    answers[i] = Some(answer_store_query(&mut store, key, payload));
                }
            }
            answers
                .into_iter()
                .map(|a| a.expect("every query answered"))
                .collect()
        },
    )
    .await?;
    if let Some(earlier) = single.refused() {
        return Err(AgentError::Duplicate(duplicate_message(&machine, &earlier)));
    }
    Ok(())
}

/// What the agent checks a delivery against beyond its store.
struct Guard<'g> {
    bus: &'g Bus,
    machine: &'g gearcam_proto::MachineId,
    models: &'g Models,
    runtime: &'g tokio::runtime::Handle,
}

/// The station's answer on a batch's jobs, asked before the checks and
/// waited for when first needed.
struct StationWord {
    task: Option<tokio::task::JoinHandle<Vec<Result<(), JobError>>>>,
    asked: usize,
    answer: Vec<Result<(), JobError>>,
}

impl StationWord {
    fn get(&mut self, runtime: &tokio::runtime::Handle, k: usize) -> Result<(), JobError> {
        if let Some(task) = self.task.take() {
            self.answer = tokio::task::block_in_place(|| runtime.block_on(task))
                .unwrap_or_else(|e| vec![Err(guard::unasked(&e.to_string())); self.asked]);
        }
        self.answer
            .get(k)
            .cloned()
            .unwrap_or_else(|| Err(guard::unasked("the answer left the job out")))
    }
}

/// Defence in depth before the deliveries (index in the batch, program) are
/// stored: a journaled job of this machine, and a program that passes the
/// path check against its model. The station is asked first, so its round
/// trip overlaps the checks and the writes; nothing is renamed before its
/// answer, and its refusal comes before any other.
fn deliver(
    store: &mut Store,
    g: &Guard<'_>,
    deliveries: Vec<(usize, NcProgram)>,
    answers: &mut [Option<Answer>],
) {
    // A program for another machine or controller, or with a bad name, is
    // refused on its own.
    let deliveries: Vec<(usize, NcProgram)> = deliveries
        .into_iter()
        .filter_map(|(i, program)| match store.check_program(&program) {
            Ok(_) => Some((i, program)),
            Err(error) => {
                answers[i] = Some(refused(Some(program.job_id), error));
                None
            }
        })
        .collect();
    let jobs: Vec<JobId> = deliveries.iter().map(|(_, p)| p.job_id.clone()).collect();
    if jobs.is_empty() {
        return;
    }
    let task = {
        let (bus, machine, jobs) = (g.bus.clone(), g.machine.clone(), jobs.clone());
        g.runtime
            .spawn(async move { guard::journaled(&bus, &machine, &jobs).await })
    };
    let mut word = StationWord {
        task: Some(task),
        asked: jobs.len(),
        answer: Vec::new(),
    };
    tokio::task::block_in_place(|| {
        g.runtime
            .block_on(g.models.wait_for(&jobs, guard::MODEL_WAIT))
    });
    // (position among the asked, index in the batch, program)
    let mut checked = Vec::with_capacity(deliveries.len());
    let mut failed = Vec::new();
    for (k, (i, program)) in deliveries.into_iter().enumerate() {
        match g.models.check(&program) {
            Ok(()) => checked.push((k, i, program)),
            Err(error) => failed.push((k, i, program, error)),
        }
    }
    let programs: Vec<NcProgram> = checked.iter().map(|(_, _, p)| p.clone()).collect();
    let (results, verdicts) = store.store_confirmed(&programs, || {
        checked
            .iter()
            .map(|(k, _, _)| word.get(g.runtime, *k))
            .collect()
    });
    for (((_, i, program), result), verdict) in checked.into_iter().zip(results).zip(verdicts) {
        answers[i] = Some(match verdict {
            Ok(()) => delivered(store, program, result),
            Err(error) => refused_before_storing(program, error),
        });
    }
    for (k, i, program, error) in failed {
        let error = word.get(g.runtime, k).err().unwrap_or(error);
        answers[i] = Some(refused_before_storing(program, error));
    }
}

fn refused_before_storing(program: NcProgram, error: JobError) -> Answer {
    tracing::warn!(job = %program.job_id, code = error.code.as_str(), "program refused before storing");
    refused(Some(program.job_id), error)
}

fn duplicate_message(machine: &gearcam_proto::MachineId, earlier: &str) -> String {
    format!(
        "another agent already serves machine {machine} (instance {earlier}); a machine has exactly \
         one agent, so this one does not serve: stop one of them, or give this one the right --machine"
    )
}

/// The watch that keeps a machine to one agent.
struct SingleAgent {
    /// The earlier instance seen, once one is: this agent must not serve.
    earlier: std::sync::Arc<std::sync::Mutex<Option<String>>>,
    _token: zenoh::liveliness::LivelinessToken,
    _watch: tokio::task::JoinHandle<()>,
}

impl SingleAgent {
    fn refused(&self) -> Option<String> {
        self.earlier.lock().map(|e| e.clone()).unwrap_or(None)
    }
}

/// Declares this agent's instance token and watches the machine's others
/// (history included): an earlier instance cancels `serving` (this agent
/// stops, or never starts, serving); a later one is reported, and refuses
/// itself. The first look waits briefly for the tokens already declared.
async fn single_agent(
    bus: &Bus,
    machine: &gearcam_proto::MachineId,
    serving: CancellationToken,
) -> Result<SingleAgent, AgentError> {
    let me = format!("{:013}-{}", gearcam_proto::now_ms(), bus.session().zid());
    let zerr = |op: &'static str| {
        move |e: zenoh::Error| {
            AgentError::Bus(gearcam_bus::BusError::Zenoh {
                op,
                detail: e.to_string(),
            })
        }
    };
    let token = bus
        .session()
        .liveliness()
        .declare_token(keys::agent_instance(machine, &me))
        .await
        .map_err(zerr("liveliness token"))?;
    let others = bus
        .session()
        .liveliness()
        .declare_subscriber(keys::agent_instances(machine))
        .history(true)
        .await
        .map_err(zerr("liveliness subscriber"))?;
    let earlier = std::sync::Arc::new(std::sync::Mutex::new(None));
    let seen = earlier.clone();
    let machine = machine.clone();
    let watch = tokio::spawn(async move {
        while let Ok(s) = others.recv_async().await {
            if s.kind() != zenoh::sample::SampleKind::Put {
                continue;
            }
            let Some(other) = keys::agent_instance_of(&machine, s.key_expr().as_str()) else {
                continue;
            };
            if other == me {
                continue;
            }
            if other < me.as_str() {
                tracing::error!(%machine, other, "{}", duplicate_message(&machine, other));
                if let Ok(mut e) = seen.lock() {
                    *e = Some(other.to_string());
                }
                serving.cancel();
            } else {
                tracing::error!(%machine, other, "a second agent for machine {machine} started (instance {other}); it must not serve, and does not: a machine has exactly one agent");
            }
        }
    });
    // The tokens already declared arrive as history.
    tokio::time::sleep(std::time::Duration::from_millis(300)).await;
    Ok(SingleAgent {
        earlier,
        _token: token,
        _watch: watch,
    })
}

/// Largest group of deliveries committed together.
const MAX_BATCH: usize = gearcam_proto::JobIds::MAX;

/// Answers a store query (lost receipts, history, versions, changes), always
/// with a typed reply.
fn answer_store_query(store: &mut Store, key: &str, payload: &[u8]) -> Answer {
    let machine = store.config().machine.clone();
    let refuse = |error: JobError| Answer::message(&StoreReply::Refused { error });
    let Some(asked) = keys::agent_key_of(&machine, key) else {
        return refuse(bad_request(
            "key",
            keys::STORE_KEY_FORMS,
            key,
            "the store has no such key",
        ));
    };
    match asked {
        AgentKey::StoredJob(job) => match JobId::new(job) {
            Err(e) => Answer::message(&DeliveryReply::Refused {
                error: JobError::bad_id(Stage::Agent, "job", &e),
            }),
            Ok(job) => match store.stored_receipt(job.as_str()) {
                Ok(Some(receipt)) => Answer::message(&DeliveryReply::Stored { receipt }),
                Ok(None) => Answer::message(&DeliveryReply::NotStored),
                Err(e) => Answer::message(&DeliveryReply::Refused {
                    error: index_error(e),
                }),
            },
        },
        AgentKey::Programs => history(store, None),
        AgentKey::Program(name) => match known(store, name) {
            Ok(()) => history(store, Some(name)),
            Err(error) => refuse(error),
        },
        AgentKey::Version(name, seq) => {
            let Ok(seq) = seq.parse::<u64>() else {
                return refuse(bad_request(
                    "seq",
                    "a version number",
                    seq,
                    "a version is a number",
                ));
            };
            if let Err(error) = known(store, name) {
                return refuse(error);
            }
            match store.version(name, seq) {
                Ok(Some(program)) => Answer::message(&StoreReply::Version {
                    program: Box::new(program),
                }),
                Ok(None) => refuse(unknown_version(name, seq)),
                Err(e) => refuse(index_error(e)),
            }
        }
        AgentKey::Change(user, name) => {
            if payload.is_empty() {
                return refuse(bad_request(
                    "payload",
                    "a store_request message",
                    "no payload",
                    "a change of the current program is asked with a store_request payload",
                ));
            }
            let request = match decode::<StoreRequest>(payload) {
                Ok(r) => r,
                Err(e) => return refuse(codec_error::<StoreRequest>(Stage::Agent, &e)),
            };
            if let Err(error) = known(store, name) {
                return refuse(error);
            }
            // Who changes the program is the user of the key, which a
            // secure router grants to that login only; the payload's `by`
            // is not proof of anything.
            let by = user;
            let result = match &request {
                StoreRequest::Rollback { seq, .. } => {
                    store.rollback(name, *seq, by).map(|r| (r, None))
                }
                StoreRequest::Adopt { .. } => store
                    .resolve(name, Resolution::Adopt, by)
                    .map(|r| (r.receipt, Some((r.seq, r.superseded)))),
                StoreRequest::Replace { .. } => store
                    .resolve(name, Resolution::Replace, by)
                    .map(|r| (r.receipt, None)),
            };
            match result {
                Ok((receipt, adopted)) => {
                    tracing::info!(
                        program = name,
                        ?request,
                        sha256 = receipt.sha256,
                        "current program changed"
                    );
                    let superseded = adopted
                        .as_ref()
                        .map(|(_, jobs)| jobs.clone())
                        .unwrap_or_default();
                    let mut a = Answer::message(&StoreReply::Changed {
                        receipt,
                        superseded: superseded.clone(),
                    });
                    // The jobs the adoption ended, to the station now (and
                    // again to any re-drive of them).
                    if let (Some((seq, _)), StoreRequest::Adopt { .. }) = (&adopted, &request) {
                        for job in superseded {
                            tracing::info!(%job, program = name, "job superseded by the adopted edit");
                            a.events.push((
                                job,
                                EventKind::Superseded {
                                    name: name.to_string(),
                                    seq: *seq,
                                    by: by.to_string(),
                                },
                            ));
                        }
                    }
                    a
                }
                Err(error) => refuse(error),
            }
        }
        AgentKey::Delivery(_) => unreachable!("deliveries are answered first"),
    }
}

fn history(store: &Store, name: Option<&str>) -> Answer {
    match store.history(name) {
        Ok(versions) => Answer::message(&StoreReply::History {
            history: ProgramHistory {
                machine: store.config().machine.clone(),
                versions,
            },
        }),
        Err(e) => Answer::message(&StoreReply::Refused {
            error: index_error(e),
        }),
    }
}

/// `UNKNOWN_PROGRAM` unless the store has held a program called `name`.
fn known(store: &Store, name: &str) -> Result<(), JobError> {
    match store.knows(name) {
        Ok(true) => Ok(()),
        Ok(false) => Err(JobError::new(
            Stage::Agent,
            Code::UNKNOWN_PROGRAM,
            "name",
            format!(
                "a program in the store of {} (gearcam program history --machine {})",
                store.config().machine,
                store.config().machine
            ),
            name,
            "this machine's store has never held a program of this name",
        )),
        Err(e) => Err(index_error(e)),
    }
}

fn unknown_version(name: &str, seq: u64) -> JobError {
    JobError::new(
        Stage::Agent,
        Code::UNKNOWN_VERSION,
        "seq",
        format!("a stored version of {name} (gearcam program history)"),
        seq.to_string(),
        "no such version of this program in the store",
    )
}

fn bad_request(field: &str, expected: &str, got: &str, message: &str) -> JobError {
    JobError::new(
        Stage::Agent,
        Code::BAD_STORE_REQUEST,
        field,
        expected,
        got,
        message,
    )
}

fn index_error(e: AgentError) -> JobError {
    JobError::new(
        Stage::Agent,
        Code::STORE_INDEX_ERROR,
        "-",
        "a readable program index",
        e.to_string(),
        "the program index could not be read; see the agent's log",
    )
}

/// The refusal of a delivery, with the job's event: `failed` when retrying
/// cannot change the answer; `waiting` when it can: a program changed at the
/// machine (a person resolves the edit with `gearcam program resolve`), or a
/// store that cannot write or index now (a full disk). The station re-drives
/// a waiting job until it is delivered.
fn refused(job: Option<JobId>, error: JobError) -> Answer {
    let mut a = Answer::message(&DeliveryReply::Refused {
        error: error.clone(),
    });
    if let Some(job) = job {
        let waits = [
            Code::PROGRAM_CHANGED_AT_MACHINE,
            Code::STORE_IO_ERROR,
            Code::STORE_INDEX_ERROR,
            Code::STATION_UNREACHABLE,
            Code::MODEL_UNKNOWN,
        ];
        let event = if waits.contains(&error.code) {
            EventKind::Waiting {
                reason: format!("{}: {}", error.code, error.message),
            }
        } else {
            EventKind::Failed {
                errors: vec![error],
            }
        };
        a.events.push((job, event));
    }
    a
}

/// Decodes a delivery's program, or the refusal to answer with.
fn decode_delivery(job: &str, payload: &[u8]) -> Result<NcProgram, Answer> {
    let job_id = match JobId::new(job) {
        Ok(id) => Some(id),
        Err(e) => return Err(refused(None, JobError::bad_id(Stage::Agent, "job", &e))),
    };
    let program = match decode::<NcProgram>(payload) {
        Ok(p) => p,
        Err(e) => {
            tracing::warn!(job, error = %e, "refusing an undecodable program");
            return Err(refused(job_id, codec_error::<NcProgram>(Stage::Agent, &e)));
        }
    };
    if job_id.as_ref() != Some(&program.job_id) {
        return Err(refused(
            job_id,
            JobError::job_id_mismatch(Stage::Agent, job, &program.job_id, "program"),
        ));
    }
    Ok(program)
}

/// The answer to a delivery once the store has decided.
fn delivered(
    store: &Store,
    program: NcProgram,
    result: Result<gearcam_proto::DeliveryReceipt, JobError>,
) -> Answer {
    match result {
        Ok(receipt) => {
            tracing::info!(job = %receipt.job_id, file = receipt.file_name, sha256 = receipt.sha256, duplicate = receipt.duplicate, "program stored");
            let mut a = Answer::message(&DeliveryReply::Stored {
                receipt: receipt.clone(),
            });
            a.events
                .push((program.job_id, EventKind::Delivered { receipt }));
            a
        }
        Err(error) => {
            tracing::info!(job = %program.job_id, code = error.code.as_str(), "program refused");
            // A job an adoption ended ends `superseded`, not `failed`.
            if let Ok(Some(s)) = store.superseded(program.job_id.as_str()) {
                let mut a = Answer::message(&DeliveryReply::Refused { error });
                a.events.push((
                    program.job_id,
                    EventKind::Superseded {
                        name: s.name,
                        seq: s.seq,
                        by: s.by,
                    },
                ));
                return a;
            }
            refused(Some(program.job_id), error)
        }
    }
}
