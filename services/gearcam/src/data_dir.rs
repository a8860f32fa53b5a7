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

use std::path::{Path, PathBuf};

/// The environment variable naming the data directory.
pub const ENV: &str = "GEARCAM_DATA";

/// The data directory when neither `--data` nor [`ENV`] names one.
pub const DEFAULT: &str = "gearcam-data";

/// `data` as an absolute path (relative paths from the working directory).
pub fn absolute(data: &Path) -> PathBuf {
    std::path::absolute(data).unwrap_or_else(|_| data.to_path_buf())
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
