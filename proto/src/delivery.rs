//! Messages of end-to-end delivery: the planning station's journal states and
//! queries, and the agent's replies (receipts, refusals, program history).

use serde::{Deserialize, Serialize};

use crate::codec::Message;
use crate::error::JobError;
use crate::ids::{JobId, MachineId};
use crate::program::DeliveryReceipt;

/// A job's state in the planning station's journal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum JobState {
    /// Journaled; the request is (being) sent to the knowledge service.
    Accepted,
    /// The knowledge service planned it.
    Planned,
    /// The model service computed it.
    Modelled,
    /// The template service produced the program and is delivering it.
    Programmed,
    /// The machine's agent is offline; the job is delivered when it returns.
    Waiting,
    /// The agent stored the program (final).
    Delivered,
    /// A stage refused the job (final).
    Failed,
    /// An operator adopted an edit at the machine of the program the job
    /// waited to replace (final): the job is never delivered over it; its
    /// `errors` hold `JOB_SUPERSEDED`, naming the adopted version and who.
    Superseded,
    /// A person cancelled the job before it was delivered (final); its
    /// `errors` hold `JOB_CANCELLED`, naming who.
    Cancelled,
}

impl JobState {
    /// The state's name.
    pub fn as_str(self) -> &'static str {
        match self {
            JobState::Accepted => "accepted",
            JobState::Planned => "planned",
            JobState::Modelled => "modelled",
            JobState::Programmed => "programmed",
            JobState::Waiting => "waiting",
            JobState::Delivered => "delivered",
            JobState::Failed => "failed",
            JobState::Superseded => "superseded",
            JobState::Cancelled => "cancelled",
        }
    }

    /// Every state, in the order a job moves through them.
    pub const ALL: [JobState; 9] = [
        JobState::Accepted,
        JobState::Planned,
        JobState::Modelled,
        JobState::Programmed,
        JobState::Waiting,
        JobState::Delivered,
        JobState::Failed,
        JobState::Superseded,
        JobState::Cancelled,
    ];

    /// Parses a state name.
    pub fn parse(s: &str) -> Option<JobState> {
        JobState::ALL.into_iter().find(|st| st.as_str() == s)
    }

    /// True for delivered, failed, superseded and cancelled: nothing moves
    /// the job on.
    pub fn is_final(self) -> bool {
        matches!(
            self,
            JobState::Delivered | JobState::Failed | JobState::Superseded | JobState::Cancelled
        )
    }
}

/// A delivered program in brief.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProgramRef {
    /// Program name.
    pub name: String,
    /// SHA-256 of the stored text.
    pub sha256: String,
    /// Path on the agent's host.
    pub path: String,
}

/// One job as the station's journal knows it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobStatus {
    /// The job.
    pub job: JobId,
    /// Target machine.
    pub machine: MachineId,
    /// Part number.
    pub part_number: String,
    /// State.
    pub state: JobState,
    /// How often the station (re)sent the job.
    pub attempts: u32,
    /// When the job was journaled, ms since the epoch.
    pub accepted_at_ms: u64,
    /// Last change, ms since the epoch.
    pub updated_at_ms: u64,
    /// What the job waits for, when waiting.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub waiting_for: Option<String>,
    /// The delivered program, once delivered.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<ProgramRef>,
    /// The agent's receipt, once delivered.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub receipt: Option<DeliveryReceipt>,
    /// The errors, when failed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub errors: Vec<JobError>,
    /// The model's warnings (what to check before cutting), once modelled.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::model::Warning>,
    /// Parts to cut (the job's `[job] quantity`); 0 from a station that
    /// does not say.
    #[serde(default)]
    pub quantity: u32,
}

impl Message for JobStatus {
    const KIND: &'static str = "job_status";
}

/// Every answer of the station's queryables: to a submission (`accepted` or
/// `refused`), to a status query (`status` or `refused`), to the job list
/// (`jobs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum StationReply {
    /// Journaled (or already journaled: the same job id with the same spec).
    Accepted {
        /// The job's status.
        status: Box<JobStatus>,
    },
    /// One job's status.
    Status {
        /// The job's status.
        status: Box<JobStatus>,
    },
    /// Every journaled job, oldest first.
    Jobs {
        /// The jobs.
        jobs: Vec<JobStatus>,
    },
    /// Not journaled, or not answerable (unknown job, bad id).
    Refused {
        /// Why.
        errors: Vec<JobError>,
    },
}

impl Message for StationReply {
    const KIND: &'static str = "station_reply";
}

/// The agent's answer to a delivery, or to the query for a job's stored receipt.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum DeliveryReply {
    /// Durably stored; the receipt.
    Stored {
        /// The receipt.
        receipt: DeliveryReceipt,
    },
    /// Refused, with the rule broken.
    Refused {
        /// Why.
        error: JobError,
    },
    /// The store has nothing for the job (answer to a store query).
    NotStored,
}

impl Message for DeliveryReply {
    const KIND: &'static str = "delivery_reply";
}

/// A change of a machine's current program, asked on
/// `gearcam/v1/machines/{machine}/store/changes/{user}/{name}`; the agent
/// records `user` as who changed it, not the `by` of the request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum StoreRequest {
    /// Make the stored version `seq` of the program current again.
    Rollback {
        /// The version.
        seq: u64,
        /// Who rolled it back (`unknown` when a client of an older release
        /// does not say).
        #[serde(default = "unknown_user")]
        by: String,
    },
    /// Take the program as it now is at the machine (an operator's edit) as
    /// the current version, recorded with who and when.
    Adopt {
        /// Who reviewed and adopted the edit.
        by: String,
    },
    /// Write gearcam's current version back over an edit at the machine; the
    /// edit is kept in the history as a `machine-edit` version.
    Replace {
        /// Who reviewed and replaced the edit.
        by: String,
    },
}

impl StoreRequest {
    /// Who asks for the change, as the client says (the agent records the
    /// user of the change's key, see [`crate::keys::store_change`]).
    pub fn by(&self) -> &str {
        match self {
            StoreRequest::Rollback { by, .. }
            | StoreRequest::Adopt { by }
            | StoreRequest::Replace { by } => by,
        }
    }
}

fn unknown_user() -> String {
    "unknown".into()
}

impl Message for StoreRequest {
    const KIND: &'static str = "store_request";
}

/// True when `by` can be recorded as who decided (a resolution, a
/// rollback, a cancellation): 1 to 64 characters on one line.
pub fn valid_by(by: &str) -> bool {
    !by.trim().is_empty() && !by.chars().any(char::is_control) && by.chars().count() <= 64
}

/// Message: the jobs an agent asks the station about before it stores their
/// programs, at most [`JobIds::MAX`] (key [`crate::keys::station_journaled`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobIds {
    /// The jobs.
    pub jobs: Vec<JobId>,
}

impl JobIds {
    /// Most jobs in one question (an agent's largest group of deliveries).
    pub const MAX: usize = 256;
}

impl Message for JobIds {
    const KIND: &'static str = "job_ids";
}

/// Message: a person cancels a journaled job that is not yet final
/// (`gearcam cancel JOB`). Key [`crate::keys::station_cancel`], which names
/// who cancels; the station records that user and answers with the job's
/// status.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CancelRequest {
    /// The client's own name for who cancels it; not recorded (the key's
    /// user is).
    pub by: String,
}

impl Message for CancelRequest {
    const KIND: &'static str = "cancel_request";
}

/// Every answer of an agent's store queryables (`…/store/programs[/{name}]`,
/// `…/versions/{seq}`, `…/store/changes/{user}/{name}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum StoreReply {
    /// Versions of the programs asked for, newest first.
    History {
        /// The history.
        history: ProgramHistory,
    },
    /// One version with its text.
    Version {
        /// The version and its text.
        program: Box<ProgramText>,
    },
    /// A change done: the version now current, as a receipt.
    Changed {
        /// The receipt.
        receipt: DeliveryReceipt,
        /// The jobs that waited to replace the adopted edit and now end
        /// `superseded` (an adoption only).
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        superseded: Vec<JobId>,
    },
    /// Refused: unknown program or version, bad key or request, store error.
    Refused {
        /// Why.
        error: JobError,
    },
}

impl Message for StoreReply {
    const KIND: &'static str = "store_reply";
}

/// One stored version of a program in an agent's store.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProgramVersion {
    /// Sequence number in the store (increasing).
    pub seq: u64,
    /// Program name.
    pub name: String,
    /// File name in the program directory.
    pub file_name: String,
    /// Job that delivered it (or the job rolled back to).
    pub job: String,
    /// Job revision.
    pub revision: u32,
    /// SHA-256 of the text.
    pub sha256: String,
    /// Size, bytes.
    pub size_bytes: u64,
    /// When stored, ms since the epoch.
    pub stored_at_ms: u64,
    /// How the version came: `stored` (delivered by a job), `rollback` (an
    /// older version made current again), `adopted` (an edit at the machine
    /// taken as the current version), `machine-edit` (an edit at the machine
    /// kept in the history but not current) or `restored` (gearcam's version
    /// written back over an edit).
    pub state: String,
    /// True for the version now in the program directory.
    pub current: bool,
    /// The part (drawing) number the program belongs to; one program name
    /// belongs to one part. Empty for versions stored before it was recorded.
    #[serde(default)]
    pub part_number: String,
    /// Who resolved an edit at the machine (`adopted`, `machine-edit`,
    /// `restored`); empty otherwise.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub by: String,
}

/// Versions of the programs in an agent's store.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProgramHistory {
    /// The machine.
    pub machine: MachineId,
    /// Versions, newest first.
    pub versions: Vec<ProgramVersion>,
}

impl Message for ProgramHistory {
    const KIND: &'static str = "program_history";
}

/// One stored version's text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProgramText {
    /// The version.
    pub version: ProgramVersion,
    /// Its text.
    pub text: String,
}

impl Message for ProgramText {
    const KIND: &'static str = "program_text";
}
