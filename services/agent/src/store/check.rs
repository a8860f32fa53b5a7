//! The checks of a program on its own, before anything is asked or written:
//! they need the store's configuration only, so they run while an earlier
//! group is still being stored.

use gearcam_proto::{naming, Code, JobError, NcProgram, Stage};

use super::{sha256_hex, StoreConfig, MAX_PROGRAM_BYTES};

impl StoreConfig {
    /// The checks of a program on its own (machine, dialect, name, size,
    /// hash), before anything is asked or written; its file name.
    pub fn check_program(&self, p: &NcProgram) -> Result<String, JobError> {
        if p.machine != self.machine {
            return Err(Stage::Agent.error(
                Code::WRONG_MACHINE,
                "machine",
                self.machine.to_string(),
                p.machine.to_string(),
                "this agent stores programs for its own machine only",
            ));
        }
        if p.dialect != self.dialect {
            return Err(Stage::Agent.error(
                Code::WRONG_DIALECT,
                "dialect",
                self.dialect.as_str(),
                p.dialect.as_str(),
                "the program is written for another controller",
            ));
        }
        let file_name = naming::file_name(p.dialect, &p.name).map_err(|rule| {
            Stage::Agent.error(
                Code::BAD_PROGRAM_NAME,
                "name",
                rule.clone(),
                p.name.clone(),
                format!("program name refused: {rule}"),
            )
        })?;
        if p.text.len() > MAX_PROGRAM_BYTES {
            return Err(Stage::Agent.error(
                Code::PROGRAM_TOO_LARGE,
                "text",
                format!("at most {MAX_PROGRAM_BYTES} bytes"),
                format!("{} bytes", p.text.len()),
                "the program exceeds the store's size limit",
            ));
        }
        let hash = sha256_hex(p.text.as_bytes());
        if hash != p.sha256 {
            return Err(Stage::Agent.error(
                Code::HASH_MISMATCH,
                "sha256",
                hash,
                p.sha256.clone(),
                "the program text does not match its hash; it was damaged on the way",
            ));
        }
        Ok(file_name)
    }
}
