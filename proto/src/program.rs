//! NC programs, delivery receipts and job events.

use serde::{Deserialize, Serialize};

use crate::codec::Message;
use crate::error::{JobError, Stage};
use crate::ids::{JobId, MachineId};
use crate::plan::Dialect;

/// The template that produced a program.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TemplateRef {
    /// Template id, e.g. `cylindrical_840d`.
    pub id: String,
    /// Template version.
    pub version: u32,
}

/// One finding of the path check: a program line that breaks a rule.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct PathFinding {
    /// 1-based line number in the program text.
    pub line: u32,
    /// Rule id, e.g. `RAPID_CLEARANCE` (the rules are listed in
    /// `crates/nc/DIALECTS.md`).
    pub rule: crate::Code,
    /// What is wrong, in one sentence naming the values.
    pub message: String,
}

/// The result of parsing a program back and simulating its axis motion.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct PathCheck {
    /// True when there are no findings.
    pub ok: bool,
    /// Every finding, in line order.
    pub findings: Vec<PathFinding>,
}

/// Message: an NC program for one machine.
///
/// Key `gearcam/v1/machines/{machine}/programs/{job}`; published by the template
/// service, subscribed by that machine's delivery agent.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct NcProgram {
    /// The job's id.
    pub job_id: JobId,
    /// Target machine.
    pub machine: MachineId,
    /// Program name under the controller's rules, e.g. `SP_1001` (stored as `_N_SP_1001_MPF` on 840D).
    pub name: String,
    /// Revision of this job's program, starting at 1.
    pub revision: u32,
    /// Dialect.
    pub dialect: Dialect,
    /// The program text.
    pub text: String,
    /// SHA-256 of `text` (UTF-8 bytes), lowercase hex.
    pub sha256: String,
    /// Template that produced it.
    pub template: TemplateRef,
    /// Part number.
    pub part_number: String,
    /// Knowledge-base records used.
    pub cases: Vec<String>,
    /// Model code version.
    pub model_version: String,
    /// Generator (template service) version.
    pub generator: String,
    /// The path check of this text: a program leaves the template service only
    /// when it is ok.
    #[serde(default)]
    pub path_check: PathCheck,
    /// The program form of a spiral face milling job (`fanuc-macro`,
    /// `fanuc-arcs`, `fanuc-chords`, `linuxcnc`); absent for hobbing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub form: Option<crate::milling::SpiralProgram>,
    /// The virtual run of a hobbing program: the gear it cuts, measured and
    /// graded, and the run's safety findings; absent for the other families.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulation: Option<crate::simulation::SimulationReport>,
}

impl Message for NcProgram {
    const KIND: &'static str = "nc_program";
}

/// A delivery receipt: the agent's word that a program is durably stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeliveryReceipt {
    /// The job's id.
    pub job_id: JobId,
    /// The machine.
    pub machine: MachineId,
    /// Program name.
    pub name: String,
    /// File name in the program directory, e.g. `_N_SP_1001_MPF`.
    pub file_name: String,
    /// Absolute path of the stored file on the agent's host.
    pub path: String,
    /// Revision stored.
    pub revision: u32,
    /// SHA-256 of the stored file, lowercase hex.
    pub sha256: String,
    /// Size in bytes.
    pub size_bytes: u64,
    /// When it was stored, milliseconds since the Unix epoch.
    pub stored_at_ms: u64,
    /// True when this receipt answers a repeat of an already stored program.
    pub duplicate: bool,
}

/// What happened to a job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum EventKind {
    /// The planning station journaled the job (published once, when first
    /// journaled; a resubmission of the same job is not a new state).
    Accepted {
        /// The machine the job is for.
        machine: MachineId,
    },
    /// The knowledge service produced the plan.
    Planned {
        /// The cutting tool's id: the hob chosen (hobbing) or the mill
        /// (spiral face milling). The name is kept for compatibility.
        hob_id: String,
        /// Confidence of the proposal.
        confidence: f64,
    },
    /// The model service validated and computed the model.
    Modelled {
        /// Every warning found (code, field, what to check), for the planner.
        warnings: Vec<crate::model::Warning>,
    },
    /// The template service produced the program.
    Programmed {
        /// Program name.
        name: String,
        /// Its hash.
        sha256: String,
        /// The ISO 1328-1 class the virtual machine predicts for the gear
        /// the program cuts, the worst gear's on a part of several
        /// (hobbing programs run before delivery; absent when not run or
        /// no class fits).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        predicted_grade: Option<u8>,
        /// What the planner should look at: a predicted class worse than
        /// the drawing's (`PREDICTED_GRADE`), naming the deviation.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        warnings: Vec<crate::model::Warning>,
    },
    /// The agent stored the program.
    Delivered {
        /// The receipt.
        receipt: DeliveryReceipt,
    },
    /// The job cannot go on yet: a service or the machine's agent is offline
    /// or not answering (published by the station, and by the template
    /// service for an agent that does not answer); the station re-drives the
    /// job when they are back. Published again only when the reason changes.
    Waiting {
        /// Why.
        reason: String,
    },
    /// The job failed at a stage.
    Failed {
        /// Every error found.
        errors: Vec<JobError>,
    },
    /// The machine's agent: an operator adopted the edit at the machine of
    /// the program this job waited to replace; the job ends and is never
    /// delivered over the edit.
    Superseded {
        /// Program name.
        name: String,
        /// The adopted version in the machine's store.
        seq: u64,
        /// Who adopted it.
        by: String,
    },
    /// The planning station: a person cancelled the job.
    Cancelled {
        /// Who cancelled it.
        by: String,
    },
}

/// Message: an event of a job.
///
/// Key `gearcam/v1/jobs/{job}/events`; published by every stage, subscribed by
/// planning stations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JobEvent {
    /// The job's id.
    pub job_id: JobId,
    /// Stage that reports.
    pub stage: Stage,
    /// When, milliseconds since the Unix epoch.
    pub at_ms: u64,
    /// What happened.
    pub event: EventKind,
}

impl Message for JobEvent {
    const KIND: &'static str = "job_event";
}

/// Unix milliseconds as `YYYY-MM-DD HH:MM:SS UTC` (proleptic Gregorian; days
/// to civil date after H. Hinnant, "chrono-Compatible Low-Level Date
/// Algorithms").
pub fn utc_text(ms: u64) -> String {
    let secs = ms / 1000;
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Milliseconds since the Unix epoch, for message timestamps.
#[allow(clippy::disallowed_methods)]
pub fn now_ms() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_millis() as u64)
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::utc_text;

    #[test]
    fn utc_text_formats_unix_milliseconds() {
        assert_eq!(utc_text(0), "1970-01-01 00:00:00 UTC");
        // 2000-02-29T12:34:56Z = 951 827 696 s (a leap day in a century leap year).
        assert_eq!(utc_text(951_827_696_000), "2000-02-29 12:34:56 UTC");
        // 2023-11-14T22:13:20Z = 1 700 000 000 s.
        assert_eq!(utc_text(1_700_000_000_999), "2023-11-14 22:13:20 UTC");
    }
}
