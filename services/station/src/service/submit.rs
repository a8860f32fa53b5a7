//! Checking a submission before it is journaled: the request itself (its
//! size, the submitter in its key, its decoding, a spec every stage can plan
//! with), then that the knowledge base knows its machine.

use std::collections::HashSet;
use std::time::Duration;

use gearcam_bus::query::Retry;
use gearcam_bus::Bus;
use gearcam_proto::plan::{KbReply, KbRequest, KbValue};
use gearcam_proto::{
    decode, keys, part_number_problem, Code, JobError, JobRequest, MachineId, Stage,
    MAX_PART_NUMBER,
};
use zenoh::query::Query;

/// A submission's verdict: the request to journal, or why it is refused.
pub(super) type Verdict = Result<JobRequest, Vec<JobError>>;

/// Checks each new submission in turn: the request itself, then that the
/// knowledge base knows its machine (which may ask the knowledge base, so
/// it happens before the journal's transaction).
pub(super) async fn check_submits(
    bus: &Bus,
    machines: &mut HashSet<MachineId>,
    new_submits: Vec<Query>,
) -> Vec<(Query, Verdict)> {
    let mut checked = Vec::with_capacity(new_submits.len());
    for q in new_submits {
        let verdict = match submitted_request(&q) {
            Ok(req) => match known_machine(bus, machines, &req.spec.job.machine).await {
                Ok(()) => Ok(req),
                Err(e) => Err(vec![e]),
            },
            Err(errors) => Err(errors),
        };
        checked.push((q, verdict));
    }
    checked
}

/// The request of a submit query, with the key's user as its submitter, or
/// why it is refused: too large, a key without a user, a payload that does
/// not decode (its id errors first), or a spec no stage can plan with.
fn submitted_request(q: &Query) -> Verdict {
    let payload = q
        .payload()
        .map(|p| p.to_bytes().into_owned())
        .unwrap_or_default();
    let limit = gearcam_proto::keys::MAX_REQUEST_BYTES;
    let key = q.key_expr().as_str();
    // The submitter is the user of the key, which a secure
    // router grants to that login only; a payload's own name
    // is not proof of anything, and a key without a user is
    // refused rather than trusted.
    let user = keys::station_submit_of(key);
    match (payload.len() > limit, user) {
        // A request over the limit a secure router drops: the
        // same refusal on every deployment, before decoding.
        (true, _) => Err(vec![Stage::Station.error(
            Code::MESSAGE_TOO_LARGE,
            "-",
            format!("a job request of at most {limit} bytes"),
            format!("{} bytes", payload.len()),
            "the job request is larger than a request on the bus may be",
        )]),
        (false, None) => Err(vec![Stage::Station.error(
            Code::BAD_KEY,
            "key",
            keys::STATION_SUBMIT_FORM,
            key,
            "a job is submitted on the key of the user who submits it; the station journals that user as its submitter",
        )]),
        (false, Some(user)) => match decode::<JobRequest>(&payload) {
            Err(e) => {
                let mut errors = gearcam_proto::job::request_id_errors(&payload, Stage::Station);
                if errors.is_empty() {
                    errors.push(gearcam_bus::stage::codec_error::<JobRequest>(
                        Stage::Station,
                        &e,
                    ));
                }
                Err(errors)
            }
            Ok(mut req) => {
                req.submitted_by = user.to_string();
                match spec_problem(&req) {
                    Some(error) => Err(vec![error]),
                    None => Ok(req),
                }
            }
        },
    }
}

/// What makes a decoded request's spec unplannable, if anything: a part
/// number that cannot name a program, or a number that is not finite.
fn spec_problem(req: &JobRequest) -> Option<JobError> {
    if let Some(reason) = part_number_problem(&req.spec.job.part_number) {
        Some(Stage::Station.error(
            Code::INVALID_PART_NUMBER,
            "spec.job.part_number",
            format!("the part (drawing) number: 1 to {MAX_PART_NUMBER} characters on one line"),
            req.spec.job.part_number.chars().take(80).collect::<String>(),
            format!("the part number is not usable: {reason}; it names the program and its history at the machine"),
        ))
    } else if let Some((field, f)) = gearcam_proto::job::non_finite(&req.spec) {
        Some(Stage::Station.error(
            Code::NOT_FINITE,
            &format!("spec.{field}"),
            "a finite number",
            f.to_string(),
            format!("spec.{field} is {f}; no stage can plan with it: give a finite number"),
        ))
    } else {
        None
    }
}

/// Checks that the knowledge base knows `machine` (`UNKNOWN_MACHINE`
/// otherwise). Known machines are remembered; when the knowledge base does
/// not answer, the job is accepted and waits for it like any other job.
async fn known_machine(
    bus: &Bus,
    known: &mut HashSet<MachineId>,
    machine: &MachineId,
) -> Result<(), JobError> {
    if known.contains(machine) {
        return Ok(());
    }
    let retry = Retry {
        timeout: Duration::from_secs(2),
        attempts: 1,
        pause: Duration::ZERO,
    };
    // Hobbing, milling and wire EDM machines: every family's library.
    let mut families: Vec<Vec<String>> = Vec::new();
    for library in [MACHINES, MILL_MACHINES, WIRE_MACHINES] {
        let key = keys::kb_library(library);
        match bus.call::<KbRequest, KbReply>(&key, None, retry).await {
            Ok(reply) if reply.errors.is_empty() => families.push(
                reply
                    .records
                    .iter()
                    .filter_map(|r| match r.get("id") {
                        Some(KbValue::Text(id)) => Some(id.clone()),
                        _ => None,
                    })
                    .collect(),
            ),
            Ok(reply) => {
                tracing::warn!(library, errors = ?reply.errors, "the knowledge base refused the machine list");
                return Ok(());
            }
            Err(e) => {
                tracing::warn!(library, error = %e, "the knowledge base did not answer; the machine is checked when the job is planned");
                return Ok(());
            }
        }
    }
    known.extend(
        families
            .iter()
            .flatten()
            .filter_map(|id| MachineId::new(id.as_str()).ok()),
    );
    if known.contains(machine) {
        Ok(())
    } else {
        Err(JobError::new(
            Stage::Station,
            Code::UNKNOWN_MACHINE,
            "spec.job.machine",
            format!(
                "one of the knowledge base's machines: {}",
                gearcam_proto::job::machines_by_family(&families[0], &families[1], &families[2])
            ),
            machine.as_str(),
            "the knowledge base has no such machine (gearcam kb list machines, mill-machines and wire-machines list them); the job was not journaled",
        ))
    }
}

/// The knowledge base's library of machines.
const MACHINES: &str = "machines";
/// The knowledge base's library of milling machines.
const MILL_MACHINES: &str = "mill-machines";
/// The knowledge base's library of wire EDM machines.
const WIRE_MACHINES: &str = "wire-machines";
