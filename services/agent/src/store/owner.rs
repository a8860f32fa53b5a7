//! One program name, one part: the index records the part of every version,
//! and a program of another part is refused under a name already taken.

use gearcam_proto::Code;
use gearcam_proto::{naming, Dialect, JobError, NcProgram, Stage};

use super::{index_error, Store};

impl Store {
    /// Refuses `p` when its file already holds a program of another part
    /// (`PROGRAM_NAME_TAKEN`, naming both parts and a free name).
    pub(super) fn check_owner(&self, p: &NcProgram, file_name: &str) -> Result<(), JobError> {
        let owner: Option<String> = self.row(
                "SELECT part FROM programs WHERE file_name = ?1 AND part != '' AND state != 'pending' ORDER BY seq DESC LIMIT 1",
                [file_name],
                |r| r.get(0),
            )?;
        let Some(owner) = owner else { return Ok(()) };
        if owner == p.part_number {
            return Ok(());
        }
        let free = self.free_name(p.dialect, &p.name).map_err(index_error)?;
        let suggestion = match free {
            Some(free) => format!("give the job its own name, e.g. `program_name = \"{free}\"` in [job] ({free} is free at {})", self.config.machine),
            None => "give the job its own `program_name` in [job]".to_string(),
        };
        Err(Stage::Agent.error(
            Code::PROGRAM_NAME_TAKEN,
            "name",
            format!("a program name not held by another part ({} belongs to part {owner:?})", p.name),
            format!("{} for part {:?}", p.name, p.part_number),
            format!(
                "program {} at {} belongs to part {owner:?}; part {:?} would replace it; {suggestion}",
                p.name, self.config.machine, p.part_number
            ),
        ))
    }

    /// A name near `name` that no program of the store has ever had and no
    /// file at the machine uses: for FANUC the next free number, otherwise the
    /// name with a number appended.
    fn free_name(&self, dialect: Dialect, name: &str) -> rusqlite::Result<Option<String>> {
        let candidates: Box<dyn Iterator<Item = String>> = match dialect {
            Dialect::Fanuc => {
                let n: u32 = name
                    .trim_start_matches('O')
                    .parse()
                    .unwrap_or(1000)
                    .clamp(1, 7999);
                Box::new((1..8000).map(move |k| format!("O{:04}", (n - 1 + k) % 7999 + 1)))
            }
            _ => {
                let stem: String = name.chars().take(naming::MAX_840D_NAME - 3).collect();
                Box::new((2..100).map(move |k| format!("{stem}_{k:02}")))
            }
        };
        for candidate in candidates {
            let Ok(file_name) = naming::file_name(dialect, &candidate) else {
                continue;
            };
            let known = self
                .conn
                .prepare_cached("SELECT 1 FROM programs WHERE file_name = ?1 OR name = ?2")?
                .exists([&file_name, &candidate])?;
            if !known && !self.config.program_dir.join(&file_name).exists() {
                return Ok(Some(candidate));
            }
        }
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{program, store};

    /// A program of another part must not replace the current program under
    /// the same name (FANUC `O2107` of `HG-2107` by `XX-9-2107`): it is
    /// refused, naming both parts.
    #[test]
    fn a_name_of_another_part_is_refused_naming_both() {
        let dir = tempfile::tempdir().unwrap();
        let mut s = store(dir.path());
        let mut first = program("J1", "SP_2107", "first\n");
        first.part_number = "HG-2107".into();
        s.store(&first).unwrap();
        let mut other = program("J2", "SP_2107", "other part\n");
        other.part_number = "XX-9-2107".into();
        let e = s.store(&other).unwrap_err();
        assert_eq!(e.code, "PROGRAM_NAME_TAKEN");
        assert!(
            e.message.contains("HG-2107") && e.message.contains("XX-9-2107"),
            "{}",
            e.message
        );
        assert!(e.message.contains("SP_2107_02"), "{}", e.message);
        let path = dir.path().join("programs/_N_SP_2107_MPF");
        assert_eq!(std::fs::read_to_string(path).unwrap(), "first\n");
        // The same part stores a new version under its name.
        let mut again = program("J3", "SP_2107", "second\n");
        again.part_number = "HG-2107".into();
        s.store(&again).unwrap();
        let h = s.history(Some("SP_2107")).unwrap();
        assert!(h.iter().all(|v| v.part_number == "HG-2107"));
    }
}
