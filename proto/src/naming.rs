//! Program naming rules of the controllers (docs/programs.md#program-names-and-files): the one place that says
//! what a program may be called and what file it is stored in.

use crate::plan::Dialect;

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
/// - Wire 3B: letters, digits, `_`, `-`, at most 32, stored as `{name}.3b`.
pub fn file_name(dialect: Dialect, name: &str) -> Result<String, String> {
    match dialect {
        Dialect::Sinumerik840d => {
            check_name_840d(name)?;
            Ok(format!("_N_{name}_MPF"))
        }
        Dialect::Fanuc => {
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
        Dialect::Wire3b => {
            check_plain(name, 32)?;
            Ok(format!("{name}.3b"))
        }
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

/// The 840D program name for a part number (docs/programs.md#program-names-and-files).
///
/// Letters and digits are kept and upper-cased; every other character (`-`, `.`,
/// spaces, ...) becomes `_`, runs of `_` collapse to one and leading and trailing
/// `_` are dropped, so a generated name always starts with a letter. A name that
/// would not start with two letters gets the prefix `GC_`; an empty one becomes
/// `GC_PART`. The result is cut to [`MAX_840D_NAME`] characters.
///
/// `SP-1001` → `SP_1001`; `123` → `GC_123`; `a1.b` → `GC_A1_B`.
pub fn program_name_840d(part: &str) -> String {
    let mut name = String::with_capacity(part.len() + 3);
    for c in part.chars() {
        let c = if c.is_ascii_alphanumeric() {
            c.to_ascii_uppercase()
        } else {
            '_'
        };
        if !(c == '_' && name.ends_with('_')) {
            name.push(c);
        }
    }
    let mut name = name.trim_matches('_').to_string();
    if name.is_empty() {
        name = "GC_PART".into();
    } else if !starts_840d(&name) {
        name.insert_str(0, "GC_");
    }
    name.truncate(MAX_840D_NAME);
    name
}

/// The FANUC program name (`O` and four digits, O0001–O7999) for a part number.
///
/// The last run of digits in the part number, when it is 1–7999, is the program
/// number (`SP-2002` → `O2002`), so the operator finds the part by its number.
/// Otherwise the number is 1000 + (FNV-1a hash of the part number mod 7000): a
/// stable number in O1000–O7999. Two parts can share a number; the agent keeps
/// every version, so nothing is lost, and the program header names the part.
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
    let number = from_digits.unwrap_or_else(|| {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in part.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
        1000 + (h % 7000) as u32
    });
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
        assert!(check_name_840d(&program_name_840d("../../etc/passwd")).is_ok());
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
}
