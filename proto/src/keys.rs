//! Key-expression builders: the only place key strings are spelled out.
//!
//! Every key starts with the versioned prefix [`PREFIX`]. See `proto/README.md`
//! for who publishes and who subscribes on each.

use crate::ids::{JobId, MachineId};

/// The versioned prefix of every gearcam key.
pub const PREFIX: &str = "gearcam/v1";

/// `gearcam/v1/jobs/{job}/request`: a [`crate::JobRequest`] from a planning station.
pub fn job_request(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/request")
}

/// `gearcam/v1/jobs/{job}/plan`: the knowledge service's [`crate::ProcessPlan`].
pub fn job_plan(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/plan")
}

/// `gearcam/v1/jobs/{job}/model`: the model service's [`crate::MachiningModel`].
pub fn job_model(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/model")
}

/// `gearcam/v1/jobs/{job}/events/{reporter}`: the [`crate::JobEvent`]s one
/// service reports: `station`, `knowledge`, `model`, `template`, or
/// `agent-{machine}`. A key per reporter lets an access control grant each
/// service its own, and the station accepts a state only from the service
/// that owns it ([`reporter_owns`]).
pub fn job_event(job: &JobId, reporter: &str) -> String {
    format!("{PREFIX}/jobs/{job}/events/{reporter}")
}

/// Every event of one job, whoever reports it (a subscription).
pub fn job_events(job: &JobId) -> String {
    format!("{PREFIX}/jobs/{job}/events/*")
}

/// The reporter of a service, by its liveliness name: the name itself, with
/// an agent's `agent/{machine}` written `agent-{machine}` (one key chunk).
pub fn reporter(service: &str) -> String {
    service.replace('/', "-")
}

/// The reporter chunk of an event key (`gearcam/v1/jobs/{job}/events/{reporter}`).
pub fn reporter_of(key: &str) -> Option<&str> {
    let rest = key.strip_prefix(PREFIX)?.strip_prefix("/jobs/")?;
    let (_, rest) = rest.split_once('/')?;
    rest.strip_prefix("events/").filter(|r| !r.contains('/'))
}

/// True when `reporter` may report `event` of a job for `machine`: every
/// service its own stage's events; `delivered` only the job's machine's
/// agent, `planned` only the knowledge service, `modelled` only the model
/// service, `programmed` only the template service, `accepted` only the
/// station.
pub fn reporter_owns(reporter: &str, event: &crate::JobEvent, machine: &MachineId) -> bool {
    use crate::{EventKind, Stage};
    let agent = format!("agent-{machine}");
    let own_stage = match event.stage {
        Stage::Station => reporter == "station",
        Stage::Knowledge => reporter == "knowledge",
        Stage::Model => reporter == "model",
        Stage::Template => reporter == "template",
        Stage::Agent => reporter == agent,
    };
    own_stage
        && match &event.event {
            EventKind::Accepted { .. } => event.stage == Stage::Station,
            EventKind::Planned { .. } => event.stage == Stage::Knowledge,
            EventKind::Modelled { .. } => event.stage == Stage::Model,
            EventKind::Programmed { .. } => event.stage == Stage::Template,
            EventKind::Delivered { receipt } => {
                event.stage == Stage::Agent && receipt.machine == *machine
            }
            EventKind::Superseded { .. } => event.stage == Stage::Agent,
            EventKind::Cancelled { .. } => event.stage == Stage::Station,
            EventKind::Waiting { .. } | EventKind::Failed { .. } => true,
        }
}

/// `gearcam/v1/machines/{machine}/programs/{job}`: an [`crate::NcProgram`] for a machine's agent.
pub fn machine_program(machine: &MachineId, job: &JobId) -> String {
    format!("{PREFIX}/machines/{machine}/programs/{job}")
}

/// Subscription pattern for all job requests.
pub const ALL_JOB_REQUESTS: &str = "gearcam/v1/jobs/*/request";
/// Subscription pattern for all process plans.
pub const ALL_JOB_PLANS: &str = "gearcam/v1/jobs/*/plan";
/// Subscription pattern for all machining models.
pub const ALL_JOB_MODELS: &str = "gearcam/v1/jobs/*/model";
/// Subscription pattern for all job events, every reporter.
pub const ALL_JOB_EVENTS: &str = "gearcam/v1/jobs/*/events/*";

/// Subscription pattern for every program sent to one machine.
pub fn machine_programs(machine: &MachineId) -> String {
    format!("{PREFIX}/machines/{machine}/programs/*")
}

/// Liveliness token of a running service: `gearcam/v1/alive/{service}`, e.g.
/// `gearcam/v1/alive/model` or, for an agent, `gearcam/v1/alive/agent/H01`.
pub fn alive(service: &str) -> String {
    format!("{PREFIX}/alive/{service}")
}

/// The liveliness name of a machine's delivery agent.
pub fn agent_service(machine: &MachineId) -> String {
    format!("agent/{machine}")
}

/// `gearcam/v1/kb/{library}`: queryable of the knowledge service; lists a
/// library's records or, with a [`crate::plan::KbRequest`] payload, adds to it.
/// Libraries: `classes`, `workpieces`, `hobs`, `machines`, `cases`, `jobs`,
/// `materials`, `weights`.
pub fn kb_library(library: &str) -> String {
    format!("{PREFIX}/kb/{library}")
}

/// A user's name as one key chunk: the name (trimmed) with every character
/// a key chunk cannot hold (`/`, `*`, `$`, `?`, `#`), every control
/// character and a leading `@` (a verbatim chunk, which no wildcard
/// matches) written `_`, or `unknown` for no name. `operator Li` stays
/// `operator Li`.
///
/// Every key that changes something carries the user who asks
/// ([`station_submit`], [`station_cancel`], [`kb_change`],
/// [`store_change`]), and the service records that user as the change's
/// author. On the secure deployment the router grants each login only the
/// keys with its own name, so the key says who is logged in: a payload's
/// `by` cannot make an admin's change someone else's.
pub fn user_chunk(user: &str) -> String {
    let chunk: String = user
        .trim()
        .chars()
        .enumerate()
        .map(|(i, c)| {
            if matches!(c, '/' | '*' | '$' | '?' | '#') || c.is_control() || (i == 0 && c == '@') {
                '_'
            } else {
                c
            }
        })
        .collect();
    if chunk.is_empty() {
        "unknown".into()
    } else {
        chunk
    }
}

/// True when `chunk` is a user's name as [`user_chunk`] writes it (so not a
/// wildcard, not empty): a key whose user chunk is anything else names no
/// one and is refused.
pub fn is_user_chunk(chunk: &str) -> bool {
    !chunk.is_empty() && user_chunk(chunk) == chunk
}

/// `gearcam/v1/kb-changes/{user}/{library}[/{id}]`: the knowledge
/// service's queryable for changes (add, edit, remove) asked by `user` —
/// keys of their own, so that an access control grants reading (`kb/**`)
/// and changing (`kb-changes/{user}/**`) to different users.
pub fn kb_change(user: &str, library: &str, id: Option<&str>) -> String {
    let user = user_chunk(user);
    match id {
        Some(id) => format!("{PREFIX}/kb-changes/{user}/{library}/{id}"),
        None => format!("{PREFIX}/kb-changes/{user}/{library}"),
    }
}

/// Every knowledge-base change key (the knowledge service's queryable).
pub const KB_CHANGES_ALL: &str = "gearcam/v1/kb-changes/**";

/// The user and the library (and record id) of a change key
/// (`gearcam/v1/kb-changes/{user}/{library}[/{id}]`), if the key is well
/// formed.
pub fn kb_change_of(key: &str) -> Option<(String, (String, Option<String>))> {
    let rest = key.strip_prefix(PREFIX)?.strip_prefix("/kb-changes/")?;
    let (user, rest) = rest.split_once('/')?;
    if !is_user_chunk(user) {
        return None;
    }
    Some((user.to_string(), kb_of(&format!("{PREFIX}/kb/{rest}"))?))
}

/// `gearcam/v1/kb/{library}/{id}`: one knowledge-base record (get, edit, remove).
pub fn kb_record(library: &str, id: &str) -> String {
    format!("{PREFIX}/kb/{library}/{id}")
}

/// The knowledge base's key forms, for messages that name them.
pub const KB_KEY_FORMS: &str = "gearcam/v1/kb/{library}[/{id}] (reads) or gearcam/v1/kb-changes/{user}/{library}[/{id}] (changes)";

/// The form of a record's key in `library`, for messages that name it.
pub fn kb_record_form(library: &str) -> String {
    format!("{PREFIX}/kb/{library}/{{id}}")
}

/// Pattern of everything the knowledge service's library queryable answers.
pub const KB_ALL: &str = "gearcam/v1/kb/**";

/// The library and record id inside a knowledge-base key
/// (`gearcam/v1/kb/{library}[/{id}]`), if the key is well formed.
pub fn kb_of(key: &str) -> Option<(String, Option<String>)> {
    let rest = key.strip_prefix(PREFIX)?.strip_prefix("/kb/")?;
    let parts: Vec<&str> = rest.split('/').collect();
    match parts.as_slice() {
        [lib] if !lib.is_empty() => Some((lib.to_string(), None)),
        [lib, id] if !lib.is_empty() && !id.is_empty() => {
            Some((lib.to_string(), Some(id.to_string())))
        }
        _ => None,
    }
}

/// `gearcam/v1/kb-log[/{library}[/{id}]]`: the knowledge service's
/// queryable for the change log (a [`crate::plan::KbLogRequest`], or no
/// payload for the newest [`crate::plan::KbLogRequest::DEFAULT_LIMIT`]) of
/// every library, of one, or of one record. A read key of its own, beside
/// the libraries' (`kb/…`), so that no library name is taken from them;
/// an access control grants it to everyone who reads.
pub fn kb_log(library: Option<&str>, id: Option<&str>) -> String {
    match (library, id) {
        (Some(library), Some(id)) => format!("{PREFIX}/kb-log/{library}/{id}"),
        (Some(library), None) => format!("{PREFIX}/kb-log/{library}"),
        (None, _) => format!("{PREFIX}/kb-log"),
    }
}

/// Pattern of the change log's queryable (`**` matches the key without a
/// library too).
pub const KB_LOG_ALL: &str = "gearcam/v1/kb-log/**";

/// The change log's key form, for messages that name it.
pub const KB_LOG_FORM: &str = "gearcam/v1/kb-log[/{library}[/{id}]]";

/// The library and the record a change-log key names (both `None` for
/// every library), if the key is well formed.
pub fn kb_log_of(key: &str) -> Option<(Option<String>, Option<String>)> {
    let rest = key.strip_prefix(PREFIX)?.strip_prefix("/kb-log")?;
    if rest.is_empty() {
        return Some((None, None));
    }
    let (library, id) = kb_of(&format!("{PREFIX}/kb{rest}"))?;
    Some((Some(library), id))
}

/// `gearcam/v1/kb-confirm/{user}/{job}`: the knowledge service's queryable
/// that confirms a delivered job asked by `user` (a
/// [`crate::plan::ConfirmRequest`]; the reply a [`crate::plan::ConfirmReply`]):
/// the job becomes a case, recorded as `user`'s. A key of its own, with the
/// user, so that an access control grants it to planners, each under their
/// own name, without granting them changes of the libraries.
pub fn kb_confirm(user: &str, job: &JobId) -> String {
    format!("{PREFIX}/kb-confirm/{}/{job}", user_chunk(user))
}

/// Pattern of the confirmations' queryable (`**`: a key without a user or
/// job still reaches the service and is refused by name).
pub const KB_CONFIRM_ALL: &str = "gearcam/v1/kb-confirm/**";

/// The confirmation key's form, for messages that name it.
pub const KB_CONFIRM_FORM: &str = "gearcam/v1/kb-confirm/{user}/{job}";

/// The user and the raw job id of a confirmation key
/// (`gearcam/v1/kb-confirm/{user}/{job}`), if the key is well formed.
pub fn kb_confirm_of(key: &str) -> Option<(&str, &str)> {
    key.strip_prefix(PREFIX)?
        .strip_prefix("/kb-confirm/")?
        .split_once('/')
        .filter(|(user, job)| is_user_chunk(user) && !job.is_empty() && !job.contains('/'))
}

/// The job id inside a job key (`gearcam/v1/jobs/{job}/...`) or program key
/// (`gearcam/v1/machines/{machine}/programs/{job}`), if the key is well formed.
pub fn job_of(key: &str) -> Option<JobId> {
    let rest = key.strip_prefix(PREFIX)?.strip_prefix('/')?;
    let parts: Vec<&str> = rest.split('/').collect();
    let raw = match parts.as_slice() {
        ["jobs", job, _] | ["jobs", job, "events", _] => job,
        ["machines", _, "programs", job] => job,
        _ => return None,
    };
    JobId::new(*raw).ok()
}

/// `gearcam/v1/station/submit/{user}`: queryable of the planning station;
/// the query carries a [`crate::JobRequest`] of `user` (its submitter, as
/// the station journals it), the reply a [`crate::JobStatus`] once the job
/// is journaled (or a [`crate::StationReply::Refused`]).
pub fn station_submit(user: &str) -> String {
    format!("{PREFIX}/station/submit/{}", user_chunk(user))
}

/// Pattern of the station's submit queryable, every user (`**`, so that a
/// key without a user, or with more than one chunk, still reaches the
/// station and is refused by name).
pub const STATION_SUBMIT_ANY: &str = "gearcam/v1/station/submit/**";

/// The submit key's form, for messages that name it.
pub const STATION_SUBMIT_FORM: &str = "gearcam/v1/station/submit/{user}";

/// The user of a submit key (`gearcam/v1/station/submit/{user}`).
pub fn station_submit_of(key: &str) -> Option<&str> {
    key.strip_prefix(PREFIX)?
        .strip_prefix("/station/submit/")
        .filter(|u| !u.contains('/') && is_user_chunk(u))
}

/// `gearcam/v1/station/jobs`: queryable listing every journaled job ([`crate::StationReply::Jobs`]).
pub const STATION_JOBS: &str = "gearcam/v1/station/jobs";

/// `gearcam/v1/station/jobs/{job}`: queryable with one job's [`crate::JobStatus`].
pub fn station_job(job: &JobId) -> String {
    format!("{PREFIX}/station/jobs/{job}")
}

/// `gearcam/v1/station/journaled/{machine}`: queryable the machine's agent
/// asks, with a [`crate::JobIds`], before it stores a group of programs:
/// the station answers [`crate::StationReply::Jobs`] with the status of
/// each of those jobs it journaled for that machine (one question for the
/// group, not one per job).
pub fn station_journaled(machine: &MachineId) -> String {
    format!("{PREFIX}/station/journaled/{machine}")
}

/// Pattern of [`station_journaled`].
pub const STATION_JOURNALED_ANY: &str = "gearcam/v1/station/journaled/*";

/// The machine of a [`station_journaled`] key.
pub fn station_journaled_of(key: &str) -> Option<&str> {
    key.strip_prefix(PREFIX)?
        .strip_prefix("/station/journaled/")
        .filter(|m| !m.is_empty() && !m.contains('/'))
}

/// Pattern of the station's per-job views, a job's status and its model
/// (`**`, so that a bad id with a `/` in it still reaches the station and is
/// refused by name).
pub const STATION_JOB_ANY: &str = "gearcam/v1/station/jobs/**";

/// `gearcam/v1/station/jobs/{job}/model`: queryable with the model the
/// station journaled for a job, the bytes the model service published on
/// [`job_model`] (a `machining_model`, `spiral_model` or `wire_model`, read
/// as a [`crate::AnyModel`]), or a [`crate::StationReply::Refused`] when the
/// station has none (`UNKNOWN_JOB`, `MODEL_NOT_JOURNALED`).
pub fn station_job_model(job: &JobId) -> String {
    format!("{PREFIX}/station/jobs/{job}/model")
}

/// The raw job id of a station model key
/// (`gearcam/v1/station/jobs/{job}/model`).
pub fn station_job_model_of(key: &str) -> Option<&str> {
    station_job_of(key)?
        .strip_suffix("/model")
        .filter(|job| !job.contains('/'))
}

/// `gearcam/v1/station/jobs/{job}/request`: queryable with the request the
/// station journaled for a job, the bytes of its [`crate::JobRequest`]
/// message as submitted (so a client submits the same job again, under a
/// new id), or a [`crate::StationReply::Refused`] for an unknown job.
pub fn station_job_request(job: &JobId) -> String {
    format!("{PREFIX}/station/jobs/{job}/request")
}

/// The raw job id of a station request key
/// (`gearcam/v1/station/jobs/{job}/request`).
pub fn station_job_request_of(key: &str) -> Option<&str> {
    station_job_of(key)?
        .strip_suffix("/request")
        .filter(|job| !job.contains('/'))
}

/// `gearcam/v1/station/cancel/{user}/{job}`: queryable of the planning
/// station; the query of `user` carries a [`crate::CancelRequest`], the
/// reply is the job's [`crate::StationReply::Status`] (now `cancelled`) or a
/// refusal.
pub fn station_cancel(user: &str, job: &JobId) -> String {
    format!("{PREFIX}/station/cancel/{}/{job}", user_chunk(user))
}

/// Pattern of the station's cancel queryable (`**`: a bad id still reaches
/// the station and is refused by name).
pub const STATION_CANCEL_ANY: &str = "gearcam/v1/station/cancel/**";

/// The cancel key's form, for messages that name it.
pub const STATION_CANCEL_FORM: &str = "gearcam/v1/station/cancel/{user}/{job}";

/// The user and the raw job id of a station cancel key
/// (`gearcam/v1/station/cancel/{user}/{job}`).
pub fn station_cancel_of(key: &str) -> Option<(&str, &str)> {
    key.strip_prefix(PREFIX)?
        .strip_prefix("/station/cancel/")?
        .split_once('/')
        .filter(|(user, _)| is_user_chunk(user))
}

/// The liveliness name of the planning station service.
pub const STATION_SERVICE: &str = "station";

/// `gearcam/v1/machines/{machine}/store/jobs/{job}`: the agent's stored receipt
/// for a job, if any (resolves lost receipts).
pub fn store_job(machine: &MachineId, job: &JobId) -> String {
    format!("{PREFIX}/machines/{machine}/store/jobs/{job}")
}

/// `gearcam/v1/machines/{machine}/store/programs`: every version of every
/// program in the agent's store (a [`crate::StoreReply::History`]).
pub fn store_programs(machine: &MachineId) -> String {
    format!("{PREFIX}/machines/{machine}/store/programs")
}

/// `gearcam/v1/machines/{machine}/store/programs/{name}`: one program's versions.
pub fn store_program(machine: &MachineId, name: &str) -> String {
    format!("{PREFIX}/machines/{machine}/store/programs/{name}")
}

/// `gearcam/v1/machines/{machine}/store/programs/{name}/versions/{seq}`: one
/// version's text (a [`crate::StoreReply::Version`]).
pub fn store_version(machine: &MachineId, name: &str, seq: u64) -> String {
    format!("{PREFIX}/machines/{machine}/store/programs/{name}/versions/{seq}")
}

/// `gearcam/v1/machines/{machine}/store/changes/{user}/{name}`: a change of
/// the machine's current program asked by `user` with a
/// [`crate::StoreRequest`] payload (a query without one is refused). Its
/// own key so that an access-control list can grant changes to some users
/// and reads to all, and each user only under their own name.
pub fn store_change(machine: &MachineId, user: &str, name: &str) -> String {
    format!(
        "{PREFIX}/machines/{machine}/store/changes/{}/{name}",
        user_chunk(user)
    )
}

/// Everything a machine's agent answers: deliveries and its store.
pub fn agent_any(machine: &MachineId) -> String {
    format!("{PREFIX}/machines/{machine}/**")
}

/// An agent store's key forms, for messages that name them.
pub const STORE_KEY_FORMS: &str = "gearcam/v1/machines/{machine}/store/programs[/{name}[/versions/{seq}]], …/store/changes/{user}/{name} or …/store/jobs/{job}";

/// Pattern of everything an agent's store answers.
pub fn store_any(machine: &MachineId) -> String {
    format!("{PREFIX}/machines/{machine}/store/**")
}

/// What a key under `gearcam/v1/machines/{machine}/` asks of its agent. Ids
/// and names are raw text: the agent checks them and names the bad one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AgentKey<'a> {
    /// `programs/{job}`: a delivery.
    Delivery(&'a str),
    /// `store/jobs/{job}`: the stored receipt of a job.
    StoredJob(&'a str),
    /// `store/programs`: every program's versions.
    Programs,
    /// `store/programs/{name}`: one program's versions.
    Program(&'a str),
    /// `store/programs/{name}/versions/{seq}`: one version's text.
    Version(&'a str, &'a str),
    /// `store/changes/{user}/{name}`: a change of the current program by a
    /// user.
    Change(&'a str, &'a str),
}

/// The request inside an agent's key, if `key` is one of `machine`'s agent keys.
pub fn agent_key_of<'a>(machine: &MachineId, key: &'a str) -> Option<AgentKey<'a>> {
    let rest = key
        .strip_prefix(PREFIX)?
        .strip_prefix("/machines/")?
        .strip_prefix(machine.as_str())?
        .strip_prefix('/')?;
    let parts: Vec<&str> = rest.split('/').collect();
    Some(match parts.as_slice() {
        ["programs", job] => AgentKey::Delivery(job),
        ["store", "jobs", job] => AgentKey::StoredJob(job),
        ["store", "programs"] => AgentKey::Programs,
        ["store", "programs", name] => AgentKey::Program(name),
        ["store", "programs", name, "versions", seq] => AgentKey::Version(name, seq),
        ["store", "changes", user, name] if is_user_chunk(user) => AgentKey::Change(user, name),
        _ => return None,
    })
}

/// Pattern of every liveliness token.
pub const ALIVE_ANY: &str = "gearcam/v1/alive/**";

/// The service named by a liveliness key (`gearcam/v1/alive/{service}`).
pub fn alive_of(key: &str) -> Option<&str> {
    key.strip_prefix(PREFIX)?.strip_prefix("/alive/")
}

/// The machine of an agent's liveliness name (`agent/{machine}`).
pub fn agent_machine_of(service: &str) -> Option<&str> {
    service.strip_prefix("agent/").filter(|m| !m.contains('/'))
}

/// Liveliness token of one running agent process of a machine:
/// `gearcam/v1/alive/agent/{machine}/instance/{instance}`, where the instance
/// id (`{start ms, 13 digits}-{zenoh id}`) orders agents by start. A machine
/// has exactly one agent; the later of two refuses to serve.
pub fn agent_instance(machine: &MachineId, instance: &str) -> String {
    format!("{PREFIX}/alive/agent/{machine}/instance/{instance}")
}

/// Every agent instance token of a machine (a liveliness subscription).
pub fn agent_instances(machine: &MachineId) -> String {
    format!("{PREFIX}/alive/agent/{machine}/instance/*")
}

/// The instance id of an agent instance token.
pub fn agent_instance_of<'a>(machine: &MachineId, key: &'a str) -> Option<&'a str> {
    key.strip_prefix(PREFIX)?
        .strip_prefix("/alive/agent/")?
        .strip_prefix(machine.as_str())?
        .strip_prefix("/instance/")
}

/// The raw job id of a station status key (`gearcam/v1/station/jobs/{job}`).
pub fn station_job_of(key: &str) -> Option<&str> {
    key.strip_prefix(PREFIX)?.strip_prefix("/station/jobs/")
}

// How large a message may be on each key.
//
// A request of a person's command (a job, a cancel, a status, a
// knowledge-base change, a program store's change) is a few hundred bytes
// to a few kilobytes; a stage's message (a plan, a model, a program) can be
// megabytes. The secure router drops anything over its key's limit before it
// reaches a service (`low_pass_filter` in `deploy/secure/router.json5`, which
// a test holds equal to [`SIZE_LIMITS`]), so no user can push a third of a
// megabyte where a job request is 1 KB; the station and the CLI refuse an
// oversized request themselves (`MESSAGE_TOO_LARGE`), so what the router
// would drop silently is never sent by gearcam's own tools.

/// Largest request, bytes (payload and attachment), on the keys people's
/// commands query: the station's, the knowledge base's and the program
/// stores'.
pub const MAX_REQUEST_BYTES: usize = 64 * 1024;

/// One size limit of the router: `messages` (`put`, `query`, `reply`) on
/// the keys `key_exprs` carry at most `bytes` of payload and attachment.
/// Where two limits match a message, the smaller holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SizeLimit {
    /// The filter's id in the router's configuration.
    pub id: &'static str,
    /// The kinds of message limited.
    pub messages: &'static [&'static str],
    /// The keys limited.
    pub key_exprs: &'static [&'static str],
    /// The limit, bytes.
    pub bytes: usize,
}

/// The router's size limits.
pub const SIZE_LIMITS: [SizeLimit; 2] = [
    SizeLimit {
        id: "requests",
        messages: &["query"],
        key_exprs: &[
            "gearcam/v1/station/**",
            "gearcam/v1/kb/**",
            "gearcam/v1/kb-changes/**",
            "gearcam/v1/kb-log/**",
            "gearcam/v1/kb-confirm/**",
            "gearcam/v1/machines/*/store/**",
        ],
        bytes: MAX_REQUEST_BYTES,
    },
    SizeLimit {
        id: "messages",
        messages: &["put", "query", "reply"],
        key_exprs: &["gearcam/v1/**"],
        bytes: crate::codec::MAX_MESSAGE_BYTES,
    },
];

#[cfg(test)]
mod tests {
    use super::*;

    /// A user's name is one key chunk: what a chunk cannot hold is `_`, a
    /// blank name is `unknown`, and the parsers of the change keys give the
    /// user back and refuse a key whose user is a wildcard or missing.
    #[test]
    fn user_chunks_and_the_keys_that_carry_them() {
        assert_eq!(user_chunk(" operator Li "), "operator Li");
        assert_eq!(user_chunk("a/b*c$d?e#f\nx"), "a_b_c_d_e_f_x");
        assert_eq!(user_chunk("@admin"), "_admin");
        assert_eq!(user_chunk("  "), "unknown");
        assert!(is_user_chunk("planner") && !is_user_chunk("*") && !is_user_chunk("@x"));
        assert!(!is_user_chunk("") && !is_user_chunk("**"));
        assert_eq!(station_submit_of(&station_submit("Wu Li")), Some("Wu Li"));
        assert_eq!(station_submit_of("gearcam/v1/station/submit"), None);
        assert_eq!(station_submit_of("gearcam/v1/station/submit/*"), None);
        assert_eq!(station_submit_of("gearcam/v1/station/submit/a/b"), None);
        let job = JobId::new("J1").unwrap();
        assert_eq!(
            station_cancel_of(&station_cancel("planner", &job)),
            Some(("planner", "J1"))
        );
        assert_eq!(station_cancel_of("gearcam/v1/station/cancel/J1"), None);
        let h01 = MachineId::new("H01").unwrap();
        assert_eq!(station_journaled_of(&station_journaled(&h01)), Some("H01"));
        assert_eq!(station_journaled_of("gearcam/v1/station/journaled/"), None);
        assert_eq!(
            station_journaled_of("gearcam/v1/station/journaled/a/b"),
            None
        );
        assert_eq!(station_cancel_of("gearcam/v1/station/cancel/*/J1"), None);
        assert_eq!(
            kb_change_of(&kb_change("admin", "hobs", Some("H-1"))),
            Some(("admin".into(), ("hobs".into(), Some("H-1".into()))))
        );
        assert_eq!(kb_change_of("gearcam/v1/kb-changes/hobs"), None);
        assert_eq!(kb_change_of("gearcam/v1/kb-changes/*/hobs"), None);
        assert_eq!(
            kb_confirm_of(&kb_confirm("Wu Li/x", &JobId::new("J1").unwrap())),
            Some(("Wu Li_x", "J1"))
        );
        assert_eq!(kb_confirm_of("gearcam/v1/kb-confirm/J1"), None);
        assert_eq!(kb_confirm_of("gearcam/v1/kb-confirm/*/J1"), None);
        assert_eq!(kb_confirm_of("gearcam/v1/kb-confirm/planner/J1/x"), None);
        let m = MachineId::new("H01").unwrap();
        assert_eq!(
            agent_key_of(&m, "gearcam/v1/machines/H01/store/changes/*/SP_1"),
            None
        );
        assert_eq!(
            agent_key_of(&m, "gearcam/v1/machines/H01/store/changes/SP_1"),
            None
        );
    }

    #[test]
    fn builds_and_parses_keys() {
        let job = JobId::new("J1").unwrap();
        let m = MachineId::new("H01").unwrap();
        assert_eq!(job_request(&job), "gearcam/v1/jobs/J1/request");
        assert_eq!(
            machine_program(&m, &job),
            "gearcam/v1/machines/H01/programs/J1"
        );
        assert_eq!(job_of(&job_event(&job, "agent-H01")), Some(job.clone()));
        assert_eq!(
            reporter_of(&job_event(&job, "agent-H01")),
            Some("agent-H01")
        );
        assert_eq!(
            reporter(&agent_service(&MachineId::new("H01").unwrap())),
            "agent-H01"
        );
        assert_eq!(job_of(&machine_program(&m, &job)), Some(job.clone()));
        assert_eq!(job_of("gearcam/v1/other/J1"), None);
        assert_eq!(alive(&agent_service(&m)), "gearcam/v1/alive/agent/H01");
        assert_eq!(
            kb_record("hobs", "HOB-M3-80"),
            "gearcam/v1/kb/hobs/HOB-M3-80"
        );
        assert_eq!(
            kb_of(&kb_record("hobs", "HOB-M3-80")),
            Some(("hobs".into(), Some("HOB-M3-80".into())))
        );
        assert_eq!(kb_of(&kb_library("cases")), Some(("cases".into(), None)));
        assert_eq!(kb_of("gearcam/v1/kb/a/b/c"), None);
        assert_eq!(kb_log_of(&kb_log(None, Some("x"))), Some((None, None)));
        assert_eq!(
            kb_log_of(&kb_log(Some("hobs"), None)),
            Some((Some("hobs".into()), None))
        );
        assert_eq!(
            kb_log_of(&kb_log(Some("hobs"), Some("HOB-M3-80"))),
            Some((Some("hobs".into()), Some("HOB-M3-80".into())))
        );
        assert_eq!(kb_log_of("gearcam/v1/kb-logs"), None);
        assert_eq!(kb_log_of("gearcam/v1/kb-log/a/b/c"), None);
        assert_eq!(kb_log_of("gearcam/v1/kb-log/"), None);
        assert_eq!(
            agent_key_of(&m, &store_version(&m, "SP_1", 3)),
            Some(AgentKey::Version("SP_1", "3"))
        );
        assert_eq!(
            agent_key_of(&m, &store_change(&m, "Wu Li/x", "SP_1")),
            Some(AgentKey::Change("Wu Li_x", "SP_1"))
        );
        assert_eq!(
            agent_key_of(&m, &machine_program(&m, &job)),
            Some(AgentKey::Delivery("J1"))
        );
        let other = MachineId::new("H011").unwrap();
        assert_eq!(agent_key_of(&m, &store_programs(&other)), None);
        assert_eq!(alive_of(&alive("station")), Some("station"));
        assert_eq!(station_job_of(&station_job(&job)), Some("J1"));
        assert_eq!(station_job_model(&job), "gearcam/v1/station/jobs/J1/model");
        assert_eq!(station_job_model_of(&station_job_model(&job)), Some("J1"));
        assert_eq!(station_job_model_of(&station_job(&job)), None);
        assert_eq!(
            station_job_request(&job),
            "gearcam/v1/station/jobs/J1/request"
        );
        assert_eq!(
            station_job_request_of(&station_job_request(&job)),
            Some("J1")
        );
        assert_eq!(station_job_request_of(&station_job_model(&job)), None);
        assert_eq!(
            station_job_model_of("gearcam/v1/station/jobs/a/b/model"),
            None
        );
    }
}
