//! Program naming rules of the controllers (docs/programs.md#program-names-and-files): the one place that says
//! what a program may be called and what file it is stored in.

use crate::plan::Dialect;
use crate::Code;

/// Longest 840D program name (without the `_N_` / `_MPF` decoration).
pub const MAX_840D_NAME: usize = 24;

/// Checks a program name against the dialect's rule and returns the file name
/// the controller stores it under, or the rule broken.
///
/// - 840D: letters, digits and `_`; the first two characters letters, or `_`
///   and a letter; at most 24 characters; stored as `_N_{NAME}_MPF`.
/// - FANUC: `O` and a number 1–9999 outside the builder range 8000–9999,
///   written with four digits (`O1234`); stored under that name.
/// - LinuxCNC: letters, digits, `_`, `-`, at most 64, stored as `{name}.ngc`.
/// - Wire 3B/4B: letters, digits, `_`, `-`, at most 32, stored as
///   `{name}.3b`; a name may end in `.3b` or `.4b` itself (a 4B program).
/// - Wire ISO: as FANUC.
pub fn file_name(dialect: Dialect, name: &str) -> Result<String, String> {
    match dialect {
        Dialect::Sinumerik840d => {
            check_name_840d(name)?;
            Ok(format!("_N_{name}_MPF"))
        }
        Dialect::Fanuc | Dialect::WireIso => {
            let digits = name.strip_prefix('O').ok_or_else(|| {
                format!("FANUC program names are O and a number, e.g. O1234; got {name:?}")
            })?;
            let n: u32 = digits
                .parse()
                .ok()
                .filter(|_| digits.len() == 4 && digits.chars().all(|c| c.is_ascii_digit()))
                .ok_or_else(|| {
                    format!("FANUC program number must be four digits, e.g. O0042; got {name:?}")
                })?;
            if !(1..8000).contains(&n) {
                return Err(format!(
                    "FANUC program number must be 1-7999 (8000-9999 is the builder's range); got {n}"
                ));
            }
            Ok(name.to_string())
        }
        Dialect::Linuxcnc => {
            check_plain(name, 64)?;
            Ok(format!("{name}.ngc"))
        }
        Dialect::Wire3b => match name
            .strip_suffix(".4b")
            .or_else(|| name.strip_suffix(".3b"))
        {
            Some(base) => {
                check_plain(base, 32)?;
                Ok(name.to_string())
            }
            None => {
                check_plain(name, 32)?;
                Ok(format!("{name}.3b"))
            }
        },
    }
}

fn check_plain(name: &str, max: usize) -> Result<(), String> {
    if name.is_empty() || name.len() > max {
        return Err(format!(
            "program names have 1-{max} characters; got {} in {name:?}",
            name.len()
        ));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_' || *c == '-'))
    {
        return Err(format!(
            "program names use only letters, digits, _ and -; got {c:?} in {name:?}"
        ));
    }
    if !name.starts_with(|c: char| c.is_ascii_alphanumeric()) {
        return Err(format!(
            "program names start with a letter or digit; got {name:?}"
        ));
    }
    Ok(())
}

/// The 840D program name for a part number ([`name_from_part`] with the
/// 840D alphabet: upper case, `_` the only separator, at most
/// [`MAX_840D_NAME`] characters, starting with two letters).
///
/// `SP-1001` → `SP_1001`; `123` → `GC_123`; `a1.b` → `GC_A1_B`.
pub fn program_name_840d(part: &str) -> String {
    name_from_part(part, Alphabet::Siemens)
}

/// Longest name made from a part number for the plain-name controls
/// (LinuxCNC allows 64).
pub const MAX_PLAIN_NAME: usize = 64;

/// Longest name made from a part number for a wire 3B/4B program, without
/// the `.4b` of a 4B program: 29, so that both forms fit the 32 the control
/// reads.
pub const MAX_WIRE_NAME: usize = 29;

/// What a control allows in a program name, for [`name_from_part`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Alphabet {
    /// SINUMERIK 840D: `A–Z 0–9 _`, the first two letters, at most
    /// [`MAX_840D_NAME`].
    Siemens,
    /// LinuxCNC and wire 3B/4B: `A–Z a–z 0–9 _ -`, the first a letter or
    /// digit, at most the given number of characters.
    Plain(usize),
}

/// The program name made from a part number, by one rule for every control
/// that names programs by text (docs/programs.md#program-names-and-files):
///
/// 1. letters and digits are kept (upper-cased for 840D), `-` is kept where
///    the control allows it, every other character becomes `_`;
/// 2. runs of `_` collapse to one, and leading and trailing `_` and `-` are
///    dropped, so `../../etc/x` is `ETC_X` on an 840D and `etc_x` on
///    LinuxCNC or a wire control, and `<script>` is `SCRIPT` or `script`;
/// 3. an 840D name that would not start with two letters gets `GC_`;
/// 4. when that would lose what tells two parts apart (the name is over the
///    control's length, the part number has characters outside ASCII, or
///    nothing usable is left), the name is cut and ends in `_` and a
///    five-character tag of the whole part number ([`part_tag`]), so
///    `GEARBOX-OUTPUT-SHAFT-PINION-STAGE2-A` and `…-B` get different names.
///
/// The agent's store keeps the part of every name and refuses a name held
/// by another part, so a collision the rule still allows is refused, never
/// merged. FANUC controls name programs by number ([`program_name_fanuc`]).
pub fn name_from_part(part: &str, alphabet: Alphabet) -> String {
    let (siemens, max) = match alphabet {
        Alphabet::Siemens => (true, MAX_840D_NAME),
        Alphabet::Plain(max) => (false, max),
    };
    let mut name = String::with_capacity(part.len() + 3);
    for c in part.chars() {
        let c = match c {
            c if c.is_ascii_alphanumeric() && siemens => c.to_ascii_uppercase(),
            c if c.is_ascii_alphanumeric() => c,
            '-' if !siemens => '-',
            _ => '_',
        };
        if !(c == '_' && name.ends_with('_')) {
            name.push(c);
        }
    }
    let mut name = name.trim_matches(['_', '-']).to_string();
    if name.is_empty() {
        name = "GC_PART".into();
    } else if siemens && !starts_840d(&name) {
        name.insert_str(0, "GC_");
    }
    let lossy =
        !part.is_ascii() || name.len() > max || !part.chars().any(|c| c.is_ascii_alphanumeric());
    if lossy {
        name.truncate(max - 6);
        let name = name.trim_end_matches(['_', '-']);
        return format!("{name}_{}", part_tag(part));
    }
    name
}

/// Why a program name cannot be used: the job's own, or the one made from
/// its part number.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NameProblem {
    /// The job's field the name comes from: `job.program_name` or
    /// `job.part_number`.
    pub field: &'static str,
    /// The name.
    pub name: String,
    /// The control's rule it breaks.
    pub reason: String,
}

impl NameProblem {
    /// The problem as a typed error of `stage`, naming the field, the rule
    /// and the way out (`[job] program_name`).
    pub fn error(&self, stage: crate::Stage, dialect: Dialect) -> crate::JobError {
        stage.error(
            Code::INVALID_PROGRAM_NAME,
            self.field,
            format!("a program name {} accepts", dialect.as_str()),
            self.name.clone(),
            format!(
                "the program name {:?} is not valid on {}: {}; give the job a name the control accepts in [job] program_name",
                self.name,
                dialect.as_str(),
                self.reason
            ),
        )
    }
}

/// The refusal of `job`'s program name on a control of `dialect`, as a
/// typed error of `stage`, or `None` when the control accepts it
/// ([`program_name`]).
pub fn name_error(
    dialect: Dialect,
    job: &crate::JobHeader,
    four_b: bool,
    stage: crate::Stage,
) -> Option<crate::JobError> {
    program_name(dialect, job, four_b)
        .err()
        .map(|p| p.error(stage, dialect))
}

/// The program's name at the machine and the file it is stored in: the
/// job's own (`[job] program_name`), else the one made from the part number
/// by the control's rule; either checked against the rule. `four_b` is a
/// wire program in the 4B form, whose name ends in `.4b`.
///
/// The knowledge service asks this before it plans, the template service
/// when it names the program, the agent's store checks the name again
/// ([`file_name`]): one rule, so a name is refused first where it is
/// cheapest and never accepted by one stage and refused by a later one.
pub fn program_name(
    dialect: Dialect,
    job: &crate::JobHeader,
    four_b: bool,
) -> Result<(String, String), NameProblem> {
    let (name, field) = match &job.program_name {
        Some(name) => (name.clone(), "job.program_name"),
        None => {
            let part = &job.part_number;
            let name = match dialect {
                Dialect::Fanuc | Dialect::WireIso => program_name_fanuc(part),
                Dialect::Sinumerik840d => name_from_part(part, Alphabet::Siemens),
                Dialect::Linuxcnc => name_from_part(part, Alphabet::Plain(MAX_PLAIN_NAME)),
                Dialect::Wire3b => {
                    let name = name_from_part(part, Alphabet::Plain(MAX_WIRE_NAME));
                    if four_b {
                        format!("{name}.4b")
                    } else {
                        name
                    }
                }
            };
            (name, "job.part_number")
        }
    };
    match file_name(dialect, &name) {
        Ok(file) => Ok((name, file)),
        Err(reason) => Err(NameProblem {
            field,
            name,
            reason,
        }),
    }
}

/// A five-character tag (`A–Z`, `0–9`) of a part number: 25 bits of its FNV-1a
/// hash, written in base 32 (Crockford's alphabet, no I, L, O, U). The same part
/// number always gets the same tag.
pub fn part_tag(part: &str) -> String {
    const ALPHABET: &[u8; 32] = b"0123456789ABCDEFGHJKMNPQRSTVWXYZ";
    let mut h = fnv1a(part) >> 39;
    let mut tag = [0u8; 5];
    for t in tag.iter_mut().rev() {
        *t = ALPHABET[(h & 31) as usize];
        h >>= 5;
    }
    String::from_utf8(tag.to_vec()).expect("ASCII")
}

fn fnv1a(s: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The FANUC program name (`O` and four digits, O0001–O7999) for a part number.
///
/// The last run of digits in the part number, when it is 1–7999, is the program
/// number (`SP-2002` → `O2002`), so the operator finds the part by its number.
/// Otherwise the number is 1000 + (FNV-1a hash of the part number mod 7000): a
/// stable number in O1000–O7999. Four digits cannot tell every part apart:
/// two parts can get the same number (`HG-2107` and `XX-9-2107`). The agent's
/// store keeps the part of every name and refuses a number held by another
/// part, naming both and a free number; the job then gives its own
/// (`[job] program_name`).
pub fn program_name_fanuc(part: &str) -> String {
    let digits: String = {
        let rev: Vec<char> = part
            .chars()
            .rev()
            .skip_while(|c| !c.is_ascii_digit())
            .take_while(|c| c.is_ascii_digit())
            .collect();
        rev.into_iter().rev().collect()
    };
    let from_digits = digits
        .trim_start_matches('0')
        .parse::<u32>()
        .ok()
        .filter(|n| (1..=7999).contains(n) && digits.len() <= 4);
    let number = from_digits.unwrap_or_else(|| 1000 + (fnv1a(part) % 7000) as u32);
    format!("O{number:04}")
}

fn starts_840d(name: &str) -> bool {
    let b = name.as_bytes();
    b.len() >= 2 && (b[0].is_ascii_alphabetic() || b[0] == b'_') && b[1].is_ascii_alphabetic()
}

/// Checks an 840D program name (without `_N_` and `_MPF`) against docs/programs.md#program-names-and-files:
/// 1 to 24 characters from `A–Z 0–9 _`, the first two letters or `_` plus a letter.
/// The error says what is wrong.
pub fn check_name_840d(name: &str) -> Result<(), String> {
    if name.is_empty() {
        return Err("the name is empty".into());
    }
    if name.chars().count() > MAX_840D_NAME {
        return Err(format!(
            "the name has {} characters, at most {MAX_840D_NAME} are allowed",
            name.chars().count()
        ));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_uppercase() || c.is_ascii_digit() || *c == '_'))
    {
        return Err(format!(
            "the name contains {c:?}; only upper-case letters A-Z, digits and _ are allowed"
        ));
    }
    if !starts_840d(name) {
        return Err(
            "the name must start with two letters or with _ followed by a letter".to_string(),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn siemens_names() {
        assert_eq!(
            file_name(Dialect::Sinumerik840d, "SP_1001").unwrap(),
            "_N_SP_1001_MPF"
        );
        assert!(file_name(Dialect::Sinumerik840d, "_A1").is_ok());
        for bad in ["1AB", "A1", "../X", "AB/C", "AB.C", "", &"A".repeat(25)] {
            assert!(file_name(Dialect::Sinumerik840d, bad).is_err(), "{bad}");
        }
        assert_eq!(program_name_840d("sp-1001"), "SP_1001");
        assert_eq!(program_name_840d("1001"), "GC_1001");
        assert_eq!(program_name_840d(&"X".repeat(40)).len(), 24);
        assert_eq!(program_name_840d(&"X".repeat(24)), "X".repeat(24));
        assert!(check_name_840d(&program_name_840d("../../etc/passwd")).is_ok());
    }

    /// A plain 840D rule would cut long part numbers to 24 characters and drop
    /// what is not ASCII, so different parts would get one name: a lossy name
    /// carries a tag of the whole part number.
    #[test]
    fn lossy_840d_names_keep_parts_apart() {
        let a = program_name_840d("GEARBOX-OUTPUT-SHAFT-PINION-STAGE2-A");
        let b = program_name_840d("GEARBOX-OUTPUT-SHAFT-PINION-STAGE2-B");
        assert_ne!(a, b);
        assert!(a.starts_with("GEARBOX_OUTPUT_SHA_"), "{a}");
        let (u, v) = (
            program_name_840d("Zahnrad-Ä"),
            program_name_840d("Zahnrad-Ö"),
        );
        assert_ne!(u, v);
        assert_ne!(program_name_840d("---"), program_name_840d("..."));
        for name in [a, b, u, v, program_name_840d(""), program_name_840d("Ä")] {
            assert!(check_name_840d(&name).is_ok(), "{name}");
        }
        // A name the rule keeps whole has no tag.
        assert_eq!(program_name_840d("SP-1001"), "SP_1001");
        // Tags of 10,000 part numbers: distinct but for the birthday rate of
        // 2^25 values (about 1.5 expected), so a collision is rare and the
        // store refuses it.
        let tags: std::collections::HashSet<String> =
            (0..10_000).map(|i| part_tag(&format!("P-{i}"))).collect();
        assert!(tags.len() >= 9_990, "{}", tags.len());
    }

    #[test]
    fn fanuc_program_names_come_from_the_part_number() {
        assert_eq!(program_name_fanuc("SP-2002"), "O2002");
        assert_eq!(program_name_fanuc("HG-42"), "O0042");
        let hashed = program_name_fanuc("GEAR-A");
        assert_eq!(hashed, program_name_fanuc("GEAR-A"));
        for part in ["GEAR-A", "P-9000", "P-0000", "X-123456", ""] {
            let name = program_name_fanuc(part);
            assert!(file_name(Dialect::Fanuc, &name).is_ok(), "{part} -> {name}");
        }
    }

    #[test]
    fn fanuc_names() {
        assert_eq!(file_name(Dialect::Fanuc, "O0042").unwrap(), "O0042");
        for bad in ["O8000", "O0000", "O42", "1234", "O12345", "O/123"] {
            assert!(file_name(Dialect::Fanuc, bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn plain_names_refuse_paths() {
        assert!(file_name(Dialect::Wire3b, "..").is_err());
        assert!(file_name(Dialect::Linuxcnc, "a/b").is_err());
        assert_eq!(
            file_name(Dialect::Linuxcnc, "face-01").unwrap(),
            "face-01.ngc"
        );
    }

    /// A part number makes its program's name by one rule on every control
    /// that names programs by text: the same characters kept, the same
    /// separators dropped; only the alphabet and the length differ.
    #[test]
    fn one_rule_for_every_control_that_names_by_text() {
        let plain = |p: &str| name_from_part(p, Alphabet::Plain(MAX_PLAIN_NAME));
        let wire = |p: &str| name_from_part(p, Alphabet::Plain(MAX_WIRE_NAME));
        assert_eq!(program_name_840d("../../etc/x"), "ETC_X");
        assert_eq!(plain("../../etc/x"), "etc_x");
        assert_eq!(wire("../../etc/x"), "etc_x");
        assert_eq!(
            program_name_840d("<script>alert(1)</script>"),
            "SCRIPT_ALERT_1_SCRIPT"
        );
        assert_eq!(plain("<script>alert(1)</script>"), "script_alert_1_script");
        assert_eq!(plain("FL-3004"), "FL-3004");
        assert_eq!(plain("FL 30/04.b"), "FL_30_04_b");
        assert_eq!(wire("PD-2001"), "PD-2001");
        // Nothing usable, too long, outside ASCII: tagged, and still apart.
        for part in ["", "---", "Zahnrad-Ä", &"P".repeat(40)] {
            for (alphabet, dialect) in [
                (Alphabet::Plain(MAX_PLAIN_NAME), Dialect::Linuxcnc),
                (Alphabet::Plain(MAX_WIRE_NAME), Dialect::Wire3b),
                (Alphabet::Siemens, Dialect::Sinumerik840d),
            ] {
                let name = name_from_part(part, alphabet);
                assert!(file_name(dialect, &name).is_ok(), "{part:?} -> {name}");
            }
        }
        assert_eq!(wire(&"P".repeat(40)).len(), MAX_WIRE_NAME);
        assert_ne!(wire("Zahnrad-Ä"), wire("Zahnrad-Ö"));
        assert_ne!(plain("---"), plain("..."));
    }

    /// The job's own name is checked by the control's rule and its refusal
    /// names `[job] program_name`; a name made from the part number always
    /// passes, in every dialect.
    #[test]
    fn a_job_name_is_checked_and_its_refusal_names_the_field() {
        let job = |part: &str, name: Option<&str>| crate::JobHeader {
            family: crate::Family::Hobbing,
            id: None,
            machine: crate::MachineId::new("M1").unwrap(),
            quantity: 1,
            part_number: part.into(),
            program_name: name.map(str::to_string),
        };
        for dialect in [
            Dialect::Sinumerik840d,
            Dialect::Fanuc,
            Dialect::Linuxcnc,
            Dialect::Wire3b,
            Dialect::WireIso,
        ] {
            for part in ["../../etc/x", "<script>", "", "SP-1001", "Ä"] {
                let made = program_name(dialect, &job(part, None), false);
                assert!(made.is_ok(), "{dialect:?} {part:?}: {made:?}");
            }
            let problem = program_name(dialect, &job("SP-1", Some("../x")), false).unwrap_err();
            assert_eq!(problem.field, "job.program_name");
            let e = problem.error(crate::Stage::Knowledge, dialect);
            assert_eq!(e.code, "INVALID_PROGRAM_NAME");
            assert!(e.message.contains("[job] program_name"), "{}", e.message);
        }
        let (name, file) = program_name(Dialect::Wire3b, &job("PP-2001", None), true).unwrap();
        assert_eq!((name.as_str(), file.as_str()), ("PP-2001.4b", "PP-2001.4b"));
        let (name, file) =
            program_name(Dialect::Linuxcnc, &job("../../etc/x", None), false).unwrap();
        assert_eq!((name.as_str(), file.as_str()), ("etc_x", "etc_x.ngc"));
    }
}
