//! Deliveries in two overlapping stages. The first takes the queries
//! waiting, checks each program on its own, asks the station about the
//! group's jobs and re-runs the path checks; the second, on a thread of its
//! own that owns the store, commits what passed (one group commit for every
//! group waiting), answers the store's other queries, and replies. While a
//! group waits for its fsyncs the next one is already being checked, so a
//! delivery waits for the station's answer or for the disk, not for both in
//! a row. Queries are answered in the order their groups were taken, and a
//! group's store queries after its deliveries, as before.

use gearcam_bus::query::{keyed, send_answers, Answer};
use gearcam_bus::Bus;
use gearcam_proto::keys::{self, AgentKey};
use gearcam_proto::{JobError, JobId, MachineId, NcProgram, Stage};
use tokio::sync::mpsc;
use zenoh::query::Query;

use super::{answer_store_query, decode_delivery, delivered, refused};
use crate::guard::{self, Models};
use crate::store::{Store, StoreConfig};

/// A group of queries taken together, its deliveries checked, waiting for
/// the store.
pub(super) struct Group {
    queries: Vec<Query>,
    batch: Vec<(String, Vec<u8>)>,
    /// The answers decided so far (the refusals), by query.
    answers: Vec<Option<Answer>>,
    /// The programs to store, with the index of their query.
    to_store: Vec<(usize, NcProgram)>,
}

/// Most groups merged into one group commit.
const MERGED_GROUPS: usize = 8;

/// The first stage: every delivery of `queries` decoded and checked (on its
/// own, journaled for `machine`, against its model); the refusals answered.
pub(super) async fn check_group(
    bus: &Bus,
    machine: &MachineId,
    config: &StoreConfig,
    models: &Models,
    queries: Vec<Query>,
) -> Group {
    let batch = keyed(&queries);
    let mut answers: Vec<Option<Answer>> = batch.iter().map(|_| None).collect();
    let mut deliveries = Vec::new();
    for (i, (key, payload)) in batch.iter().enumerate() {
        if let Some(AgentKey::Delivery(job)) = keys::agent_key_of(machine, key) {
            let checked = decode_delivery(job, payload).and_then(|program| {
                match config.check_program(&program) {
                    Ok(_) => Ok(program),
                    Err(error) => Err(refused(Some(program.job_id), error)),
                }
            });
            match checked {
                Ok(program) => deliveries.push((i, program)),
                Err(answer) => answers[i] = Some(answer),
            }
        }
    }
    let mut to_store = Vec::with_capacity(deliveries.len());
    if !deliveries.is_empty() {
        // Defence in depth: a journaled job of this machine, and a program
        // that passes the path check against its model. The station is
        // asked first, so its round trip overlaps the path checks.
        let jobs: Vec<JobId> = deliveries.iter().map(|(_, p)| p.job_id.clone()).collect();
        let asked = {
            let (bus, machine, jobs) = (bus.clone(), machine.clone(), jobs.clone());
            tokio::spawn(async move { guard::journaled(&bus, &machine, &jobs).await })
        };
        models.wait_for(&jobs, guard::MODEL_WAIT).await;
        let checks: Vec<Result<(), JobError>> =
            deliveries.iter().map(|(_, p)| models.check(p)).collect();
        let verdicts = asked
            .await
            .unwrap_or_else(|e| vec![Err(guard::unasked(&e.to_string())); deliveries.len()]);
        for (((i, program), verdict), check) in deliveries.into_iter().zip(verdicts).zip(checks) {
            match verdict.and(check) {
                Ok(()) => to_store.push((i, program)),
                Err(error) => {
                    tracing::warn!(job = %program.job_id, code = error.code.as_str(), "program refused before storing");
                    answers[i] = Some(refused(Some(program.job_id), error));
                }
            }
        }
    }
    Group {
        queries,
        batch,
        answers,
        to_store,
    }
}

/// The second stage, until the first stops sending: each group (and every
/// other already waiting, up to [`MERGED_GROUPS`]) committed in one group
/// commit, then answered.
pub(super) fn store_groups(
    store: &mut Store,
    taken: &mut mpsc::Receiver<Group>,
    bus: &Bus,
    runtime: &tokio::runtime::Handle,
) {
    let reporter = keys::reporter(&keys::agent_service(&store.config().machine));
    while let Some(first) = taken.blocking_recv() {
        let mut groups = vec![first];
        while groups.len() < MERGED_GROUPS {
            match taken.try_recv() {
                Ok(g) => groups.push(g),
                Err(_) => break,
            }
        }
        let answered = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            store_and_answer(store, &mut groups)
        }));
        for group in groups {
            let answers: Vec<Answer> = group
                .answers
                .into_iter()
                .map(|a| match (a, &answered) {
                    (Some(a), Ok(())) => a,
                    _ => Answer::internal(Stage::Agent),
                })
                .collect();
            runtime.block_on(send_answers(
                bus,
                &reporter,
                Stage::Agent,
                group.queries,
                answers,
            ));
        }
    }
}

/// Stores every program the groups hold in one group commit, and answers
/// each group's other queries after its deliveries.
fn store_and_answer(store: &mut Store, groups: &mut [Group]) {
    let mut at = Vec::new();
    let mut programs = Vec::new();
    for (g, group) in groups.iter_mut().enumerate() {
        for (i, program) in std::mem::take(&mut group.to_store) {
            at.push((g, i));
            programs.push(program);
        }
    }
    let results = store.store_batch(&programs);
    for (((g, i), program), result) in at.into_iter().zip(programs).zip(results) {
        groups[g].answers[i] = Some(delivered(store, program, result));
    }
    for group in groups.iter_mut() {
        for (i, (key, payload)) in group.batch.iter().enumerate() {
            if group.answers[i].is_none() {
                group.answers[i] = Some(answer_store_query(store, key, payload));
            }
        }
    }
}
