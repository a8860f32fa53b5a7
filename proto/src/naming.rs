//! Program naming rules of the controllers (SPEC §9): the one place that says
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
            check_840d(name)?;
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

fn check_840d(name: &str) -> Result<(), String> {
    if name.is_empty() || name.len() > MAX_840D_NAME {
        return Err(format!(
            "840D program names have 1-{MAX_840D_NAME} characters; got {} in {name:?}",
            name.len()
        ));
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '_'))
    {
        return Err(format!(
            "840D program names use only letters, digits and _; got {c:?} in {name:?}"
        ));
    }
    let b = name.as_bytes();
    let ok_start = match (b.first(), b.get(1)) {
        (Some(a), Some(c)) => {
            (a.is_ascii_alphabetic() && c.is_ascii_alphabetic())
                || (*a == b'_' && c.is_ascii_alphabetic())
        }
        _ => false,
    };
    if !ok_start {
        return Err(format!(
            "840D program names start with two letters, or _ and a letter; got {name:?}"
        ));
    }
    Ok(())
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

/// An 840D program name derived from a part number: uppercase, every other
/// character `_`, prefixed `GC_` when it does not start with two letters, cut
/// to 24 characters.
pub fn name_840d_for_part(part: &str) -> String {
    let mut s: String = part
        .trim()
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect();
    if check_840d(&s[..s.len().min(MAX_840D_NAME)]).is_err() {
        s = format!("GC_{s}");
    }
    s.truncate(MAX_840D_NAME);
    s
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
        assert_eq!(name_840d_for_part("sp-1001"), "SP_1001");
        assert_eq!(name_840d_for_part("1001"), "GC_1001");
        assert_eq!(name_840d_for_part(&"X".repeat(40)).len(), 24);
        assert!(check_840d(&name_840d_for_part("../../etc/passwd")).is_ok());
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
