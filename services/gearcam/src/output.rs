//! What the commands print on standard output. A reader that stops early
//! (`gearcam jobs | head -1`, `| true`) is not an error and never a panic:
//! the rest of the output is dropped. Any other write error is said once on
//! standard error.

use std::io::{ErrorKind, Write};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

/// Writes `text` to standard output.
pub fn emit(text: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        if e.kind() != ErrorKind::BrokenPipe {
            eprintln!("gearcam: cannot write to standard output: {e}");
        }
    }
}

/// Whether the command runs with `--json`: then a failure is also a JSON
/// object on standard output ([`fail`]).
static JSON: AtomicBool = AtomicBool::new(false);

/// Says that the command runs with `--json` (set once, before it runs).
pub fn set_json(on: bool) {
    JSON.store(on, Ordering::Relaxed);
}

/// Says a failure and gives its exit code. A person reads `text` on standard
/// error; under `--json` a program also reads, on standard output,
/// `{"ok": false, "exit": N, "errors": [...]}`: the typed errors, or for a
/// failure without them (a bus that cannot be reached, a file that cannot be
/// read) one error with `code` (`REFUSED`, `UNREACHABLE`, `NOT_FOUND`,
/// `UNFINISHED` or `USAGE`, after the exit code) and `message`.
pub fn fail(exit: u8, errors: &[gearcam_proto::JobError], text: &str) -> ExitCode {
    eprintln!("{text}");
    if JSON.load(Ordering::Relaxed) {
        let message = text.trim_start_matches("gearcam: ");
        emit(&format!(
            "{}\n",
            failure_json(exit, errors, message, serde_json::json!({}))
        ));
    }
    crate::exit::code(exit)
}

/// The JSON of a failure that carries more than its errors (`submit`: the
/// job and its state): `{"ok": false, "exit": N, "errors": [...]}` with the
/// fields of `extra`. Without typed errors, one error named after the exit
/// code, with `message`.
pub fn failure_json(
    exit: u8,
    errors: &[gearcam_proto::JobError],
    message: &str,
    extra: serde_json::Value,
) -> serde_json::Value {
    let errors = if errors.is_empty() {
        serde_json::json!([{"code": exit_name(exit), "message": message}])
    } else {
        serde_json::json!(errors)
    };
    let mut v = serde_json::json!({"ok": false, "exit": exit, "errors": errors});
    if let (Some(v), serde_json::Value::Object(extra)) = (v.as_object_mut(), extra) {
        for (k, x) in extra {
            v.entry(k).or_insert(x);
        }
    }
    v
}

/// The name of an exit code in a JSON failure.
fn exit_name(exit: u8) -> &'static str {
    match exit {
        crate::exit::REFUSED => "REFUSED",
        crate::exit::UNREACHABLE => "UNREACHABLE",
        crate::exit::NOT_FOUND => "NOT_FOUND",
        crate::exit::UNFINISHED => "UNFINISHED",
        crate::exit::USAGE => "USAGE",
        _ => "FAILED",
    }
}

/// `println!` that survives a closed pipe ([`emit`]).
#[macro_export]
macro_rules! outln {
    () => {
        $crate::output::emit("\n")
    };
    ($($arg:tt)*) => {
        $crate::output::emit(&format!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that survives a closed pipe ([`emit`]).
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::output::emit(&format!($($arg)*))
    };
}

/// Unix milliseconds as `YYYY-MM-DD HH:MM:SS UTC` ([`gearcam_proto::utc_text`]).
pub fn utc(ms: u64) -> String {
    gearcam_proto::utc_text(ms)
}
