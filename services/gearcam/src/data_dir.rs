//! The data directory: the local knowledge base (`knowledge.db`), the
//! template library (`templates.db`), the pictures, and for `up` and `demo`
//! the journal and the machines' program stores.
//!
//! Every command that uses one says which, as an absolute path, on standard
//! error (standard output stays the command's data, JSON included); the
//! directory comes from `--data`, else `GEARCAM_DATA`, else `./gearcam-data`.
//! A knowledge base is never made and seeded without saying so: a shop's
//! own confirmed cases live in its data directory, and a job checked
//! against a fresh one gets gearcam's starting data instead.
//!
//! Every command that uses one also writes to it (the databases migrate and
//! record who changed what), so [`open`] makes sure it can before anything
//! else: a directory that cannot be made or written is refused with
//! `DATA_DIR_NOT_WRITABLE` (exit 2) and the operating system's reason, not
//! a database's complaint halfway through.

use gearcam_proto::Code;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use gearcam_proto::{JobError, Stage};

/// The environment variable naming the data directory.
pub const ENV: &str = "GEARCAM_DATA";

/// What to do about a data directory that cannot be written.
pub const NOT_WRITABLE_HINT: &str =
    "give --data or GEARCAM_DATA a directory you can write, or change its permissions";

/// The data directory when neither `--data` nor [`ENV`] names one.
pub const DEFAULT: &str = "gearcam-data";

/// `data` as an absolute path (relative paths from the working directory).
pub fn absolute(data: &Path) -> PathBuf {
    std::path::absolute(data).unwrap_or_else(|_| data.to_path_buf())
}

/// Makes the data directory if it does not exist, checks it can be written
/// and announces it (see [`announce`]). A failure is said (exit 2, JSON
/// too, naming the directory) and its exit code returned.
pub fn open(data: &Path) -> Result<PathBuf, ExitCode> {
    let abs = absolute(data);
    writable(&abs).map_err(|e| {
        crate::output::fail(
            crate::exit::UNREACHABLE,
            std::slice::from_ref(&e),
            &format!("gearcam: {}; {NOT_WRITABLE_HINT}", e.message),
        )
    })?;
    Ok(announce(&abs))
}

/// Makes `dir` if it does not exist and writes and removes a file in it:
/// the one test of "can be written" that a permission, an owner, a
/// read-only mount and an access list all answer alike.
pub fn writable(dir: &Path) -> Result<(), JobError> {
    let refuse = |what: String, e: std::io::Error| {
        Stage::Station.error(
            Code::DATA_DIR_NOT_WRITABLE,
            "data directory",
            "a directory this user can write",
            dir.display().to_string(),
            format!(
                "the data directory {} is not writable: {what}: {}",
                dir.display(),
                reason(&e)
            ),
        )
    };
    std::fs::create_dir_all(dir).map_err(|e| refuse("cannot make it".into(), e))?;
    let probe = dir.join(format!(".gearcam-write-test-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| refuse("cannot make a file in it".into(), e))?;
    std::fs::remove_file(&probe).map_err(|e| refuse("cannot remove a file from it".into(), e))
}

/// The operating system's reason in words, without the error number.
fn reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::ReadOnlyFilesystem => "read-only file system".into(),
        std::io::ErrorKind::NotADirectory => "a part of the path is a file".into(),
        _ => e.to_string(),
    }
}

/// Says on standard error which data directory the command uses and, when
/// it holds no knowledge base yet, that a new one is made and seeded there.
/// Returns the absolute path.
pub fn announce(data: &Path) -> PathBuf {
    let abs = absolute(data);
    if abs.join("knowledge.db").exists() {
        eprintln!("gearcam: data directory {}", abs.display());
    } else {
        eprintln!(
            "gearcam: data directory {} has no knowledge base: a new one is made there and seeded with gearcam's starting data, without this shop's confirmed cases (give --data or {ENV} for the shop's own)",
            abs.display()
        );
    }
    abs
}
