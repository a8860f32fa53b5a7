//! Guarding the SQLite files that must never be forgotten silently (an
//! agent's program index, the station's journal).
//!
//! An empty (0-byte) SQLite file is a valid empty database: opened as it is,
//! an index or journal truncated by a fault or a careless hand would start
//! afresh and forget every version or every unfinished job, with no error.
//! So the first successful open leaves a marker beside the file
//! (`{file}.gearcam`), and a later open refuses to start when the marker is
//! there but the file is missing or empty. The error says how to recover;
//! deleting the marker is the deliberate way to start afresh.

use std::path::{Path, PathBuf};

/// The marker beside `file`.
pub fn marker_of(file: &Path) -> PathBuf {
    let mut name = file.as_os_str().to_owned();
    name.push(".gearcam");
    PathBuf::from(name)
}

/// `Err` with the reason when `file` held data before (its marker exists)
/// and is now missing or empty; `what` names it for the message (`the
/// program index of H01`), `recovery` says what to do.
pub fn refuse_if_lost(file: &Path, what: &str, recovery: &str) -> Result<(), String> {
    let marker = marker_of(file);
    if !marker.exists() {
        return Ok(());
    }
    let lost = match std::fs::metadata(file) {
        Err(_) => Some("is missing"),
        Ok(m) if m.len() == 0 => Some("is empty (0 bytes)"),
        Ok(_) => None,
    };
    match lost {
        None => Ok(()),
        Some(how) => Err(format!(
            "{what} {} {how}, but it held data before ({} is there); refusing to start, \
             since starting afresh would forget it. {recovery} To start afresh on purpose, \
             delete {}.",
            file.display(),
            marker.display(),
            marker.display()
        )),
    }
}

/// Leaves the marker beside `file` (after it was opened and set up).
pub fn mark(file: &Path) -> std::io::Result<()> {
    let marker = marker_of(file);
    if marker.exists() {
        return Ok(());
    }
    std::fs::write(
        &marker,
        "gearcam: the file beside this marker holds data that must not be lost.\n\
         If that file is missing or empty, the service refuses to start; see deploy/README.md.\n",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_marked_file_that_became_empty_or_missing_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let db = dir.path().join("index.db");
        // Never opened: a fresh start is fine.
        assert!(refuse_if_lost(&db, "the index", "").is_ok());
        std::fs::write(&db, b"data").unwrap();
        mark(&db).unwrap();
        assert!(refuse_if_lost(&db, "the index", "").is_ok());
        std::fs::write(&db, b"").unwrap();
        let e = refuse_if_lost(&db, "the index", "Rebuild it.").unwrap_err();
        assert!(
            e.contains("is empty") && e.contains("Rebuild it.") && e.contains(".gearcam"),
            "{e}"
        );
        std::fs::remove_file(&db).unwrap();
        assert!(refuse_if_lost(&db, "the index", "")
            .unwrap_err()
            .contains("is missing"));
        std::fs::remove_file(marker_of(&db)).unwrap();
        assert!(refuse_if_lost(&db, "the index", "").is_ok());
    }
}
