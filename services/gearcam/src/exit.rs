//! The `gearcam` command's exit codes: one meaning each.
//!
//! | code | meaning |
//! |---|---|
//! | 0 | done (delivered, journaled, printed) |
//! | 1 | refused: a stage or the local knowledge base answered with typed errors (a failed job's status too) |
//! | 2 | unreachable: the bus, a service, or the local data directory (missing or not writable) |
//! | 3 | not found: an unknown job, program, version, record, library or template, or a job file that does not exist |
//! | 4 | not finished in time (`submit --wait`): the job stays journaled and the station keeps driving it |
//! | 64 | usage: the command line itself is wrong |

use gearcam_proto::Code;
use std::process::ExitCode;

use gearcam_proto::JobError;

/// Typed errors: a stage or the knowledge base refused.
pub const REFUSED: u8 = 1;
/// The bus, a service or the local data directory cannot be reached, or
/// the data directory cannot be written.
pub const UNREACHABLE: u8 = 2;
/// An unknown job, program, version or record.
pub const NOT_FOUND: u8 = 3;
/// `submit --wait` ended before the job did.
pub const UNFINISHED: u8 = 4;
/// The command line is wrong (as `EX_USAGE` of sysexits).
pub const USAGE: u8 = 64;

/// The codes as `--help` shows them.
pub const HELP: &str = "Exit codes: 0 done; 1 refused with typed errors (also the status of a \
failed job); 2 bus, services or data directory unreachable or not writable; 3 not found (unknown job, program, \
version, record, library or template; no such job file); 4 not finished in time (submit --wait; the job stays journaled); 64 usage error.";

/// The exit code `code`.
pub fn code(code: u8) -> ExitCode {
    ExitCode::from(code)
}

/// The error codes that mean "no such thing".
const NOT_FOUND_CODES: [Code; 6] = [
    Code::UNKNOWN_JOB,
    Code::UNKNOWN_PROGRAM,
    Code::UNKNOWN_VERSION,
    Code::UNKNOWN_LIBRARY,
    Code::JOB_FILE_NOT_FOUND,
    Code::NOT_FOUND,
];

/// The error codes that mean "nothing there answers".
const UNREACHABLE_CODES: [Code; 1] = [Code::AGENT_OFFLINE];

/// [`NOT_FOUND`] when every error says the thing asked for does not exist,
/// [`UNREACHABLE`] when every one says nothing answers, else [`REFUSED`].
pub fn for_errors(errors: &[JobError]) -> u8 {
    if !errors.is_empty() && errors.iter().all(|e| UNREACHABLE_CODES.contains(&e.code)) {
        return UNREACHABLE;
    }
    let not_found = !errors.is_empty() && errors.iter().all(|e| NOT_FOUND_CODES.contains(&e.code));
    if not_found {
        NOT_FOUND
    } else {
        REFUSED
    }
}
