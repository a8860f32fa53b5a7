//! The error-code catalogue (`gearcam_proto::codes::CATALOGUE`, which
//! declares the `gearcam_proto::Code` enum) against the source and against
//! `docs/errors.md`:
//!
//! - no code is written as a string outside the catalogue: the services, the
//!   protocol and the shared crates name a code as `Code::X`, so the compiler
//!   checks it;
//! - every catalogue entry is raised somewhere (no stale entries);
//! - `docs/errors.md` is exactly the page generated from the catalogue. A
//!   deliberate change is written back with `GEARCAM_BLESS=1 cargo test -p
//!   gearcam-tests --test error_codes` and reviewed in the diff.
//!
//! # What the walk reads
//!
//! Every `.rs` and `.tpl` file under `services/*/src`, `proto/src` and
//! `crates/*/src`, except the catalogue itself (`proto/src/codes.rs`) and
//! test code: an item under `#[cfg(test)]` (a `mod tests { … }` block, a test
//! helper function) is skipped to its closing brace, and a test module in its
//! own file (`#[cfg(test)] mod tests;`) is not read at all. Comment lines are
//! skipped.
//!
//! In what is left,
//!
//! - a *string code* is a literal `"X"` where X is UPPER_SNAKE with at least
//!   one underscore (`^[A-Z][A-Z0-9]*(_[A-Z0-9]+)+$`) or any upper-case word
//!   that is a catalogue code (`"PARSE"`): every one fails the test unless
//!   [`NOT_CODES`] lists it as a literal that is not a code;
//! - a *raise* is a path `Code::X`.
//!
//! Literals on a line that names an environment variable (`env!(`,
//! `env = `) are not codes. NC words and SQL never match (no quoted
//! UPPER_SNAKE word of their own).
// Test code: the environment for the bless switch.
#![allow(clippy::disallowed_methods)]

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use gearcam_proto::codes::{CodeInfo, CATALOGUE};

/// Literals and `codes::` names of that shape that are not error codes.
const NOT_CODES: &[(&str, &str)] = &[
    (
        "GEARCAM_DATA",
        "services/gearcam/src/data_dir.rs: the environment variable naming the data directory",
    ),
    (
        "GC_PART",
        "proto/src/naming.rs: the 840D program name of a part number without usable characters",
    ),
    (
        "NOT_FOUND",
        "services/gearcam/src/output.rs: the name of exit code 3 in a JSON failure",
    ),
];

/// The catalogue's own file: its codes are definitions, not uses.
const CATALOGUE_FILE: &str = "proto/src/codes.rs";

/// The page generated from the catalogue.
const PAGE: &str = "docs/errors.md";

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ lies in the workspace")
        .to_path_buf()
}

/// The directories walked: `services/*/src`, `proto/src`, `crates/*/src`.
fn source_roots(root: &Path) -> Vec<PathBuf> {
    let mut roots = vec![root.join("proto/src")];
    for parent in ["services", "crates"] {
        let dir = root.join(parent);
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("a directory entry").path().join("src"))
            .filter(|src| src.is_dir())
            .collect();
        entries.sort();
        roots.extend(entries);
    }
    roots
}

fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a directory entry").path())
        .collect();
    entries.sort();
    for path in entries {
        if path.is_dir() {
            files_under(&path, out);
        } else if path.extension().is_some_and(|x| x == "rs" || x == "tpl") {
            out.push(path);
        }
    }
}

/// The file (or directory) of module `name` declared in `file`.
fn module_paths(file: &Path, name: &str) -> [PathBuf; 2] {
    let dir = file.parent().expect("a file has a directory");
    let stem = file
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or_default();
    let base = if matches!(stem, "mod" | "lib" | "main") {
        dir.to_path_buf()
    } else {
        dir.join(stem)
    };
    [base.join(format!("{name}.rs")), base.join(name)]
}

/// `mod NAME;` (any visibility) → NAME.
fn declared_module(line: &str) -> Option<&str> {
    let rest = line.trim().strip_suffix(';')?;
    let name = rest.rsplit_once("mod ")?.1.trim();
    (!name.is_empty() && name.chars().all(|c| c.is_alphanumeric() || c == '_')).then_some(name)
}

/// The lines of `text` outside `#[cfg(test)]` items and comment lines, each
/// with its 1-based number; the test modules declared without a body are
/// added to `test_files`.
fn non_test_lines(file: &Path, text: &str, test_files: &mut Vec<PathBuf>) -> Vec<(usize, String)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut kept = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line.trim() == "#[cfg(test)]" {
            // Skip further attributes, then the item: to its `;` (a
            // declaration) or from its `{` to the closing brace at its indent.
            let mut j = i + 1;
            while j < lines.len() && lines[j].trim_start().starts_with("#[") {
                j += 1;
            }
            let Some(item) = lines.get(j) else { break };
            let indent = &item[..item.len() - item.trim_start().len()];
            let mut end = j;
            while end < lines.len()
                && !lines[end].trim_end().ends_with('{')
                && !lines[end].trim_end().ends_with(';')
            {
                end += 1;
            }
            if end < lines.len() && lines[end].trim_end().ends_with(';') {
                if let Some(name) = declared_module(lines[end]) {
                    test_files.extend(module_paths(file, name));
                }
                i = end + 1;
                continue;
            }
            let close = format!("{indent}}}");
            while end < lines.len() && lines[end].trim_end() != close {
                end += 1;
            }
            i = end + 1;
            continue;
        }
        if !line.trim_start().starts_with("//") {
            kept.push((i + 1, line.to_string()));
        }
        i += 1;
    }
    kept
}

fn is_code_shaped(s: &str) -> bool {
    let mut parts = s.split('_');
    let first = parts.next().unwrap_or_default();
    let word = |p: &str| {
        !p.is_empty()
            && p.chars()
                .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit())
    };
    first.starts_with(|c: char| c.is_ascii_uppercase())
        && word(first)
        && s.contains('_')
        && parts.all(word)
}

fn is_upper_word(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_uppercase())
        && s.chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

/// The quoted upper-case words of a line (`"X"` with X of `A-Z 0-9 _` only).
fn quoted_words(line: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let bytes = line.as_bytes();
    let mut start = None;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'"' {
            if let Some(s) = start {
                let word = &line[s..i];
                if is_upper_word(word) && (s < 2 || bytes[s - 2] != b'\\') {
                    out.push(word);
                }
            }
            start = Some(i + 1);
        } else if !(b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_') {
            start = None;
        }
    }
    out
}

/// The variants named as `Code::X` in `text`.
fn variant_uses(text: &str) -> Vec<String> {
    text.match_indices("Code::")
        .map(|(at, _)| {
            text[at + "Code::".len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect::<String>()
        })
        .filter(|name| is_upper_word(name))
        .collect()
}

/// What the walk finds in the non-test source: string codes and raises,
/// each with where (file:line).
#[derive(Debug, Default)]
struct Uses {
    /// Code-shaped string literals (see the module's documentation).
    strings: BTreeMap<String, Vec<String>>,
    /// `Code::X` paths.
    raises: BTreeMap<String, Vec<String>>,
}

impl Uses {
    /// Records the uses on `lines` of file `name`.
    fn read(&mut self, name: &str, lines: &[(usize, String)], catalogue: &BTreeSet<&str>) {
        let not_codes: BTreeSet<&str> = NOT_CODES.iter().map(|(c, _)| *c).collect();
        for (n, line) in lines {
            let at = format!("{name}:{n}");
            for code in variant_uses(line) {
                self.raises.entry(code).or_default().push(at.clone());
            }
            if line.contains("env!(") || line.contains("env = ") {
                continue;
            }
            for word in quoted_words(line) {
                if (is_code_shaped(word) || catalogue.contains(word)) && !not_codes.contains(word) {
                    self.strings
                        .entry(word.to_string())
                        .or_default()
                        .push(at.clone());
                }
            }
        }
    }
}

/// The codes of the catalogue, as text.
fn catalogue_codes() -> BTreeSet<&'static str> {
    CATALOGUE.iter().map(|c| c.code.as_str()).collect()
}

/// Every use in the non-test source.
fn uses_in_source() -> Uses {
    let root = workspace();
    let mut files = Vec::new();
    for dir in source_roots(&root) {
        files_under(&dir, &mut files);
    }
    let rel = |p: &Path| {
        p.strip_prefix(&root)
            .unwrap_or(p)
            .to_string_lossy()
            .replace('\\', "/")
    };
    // Test modules in their own files are known only once their parent is
    // read: read every file first, then drop those.
    let mut test_files: Vec<PathBuf> = Vec::new();
    let mut per_file: Vec<(String, Vec<(usize, String)>)> = Vec::new();
    for file in &files {
        if rel(file) == CATALOGUE_FILE {
            continue;
        }
        let text =
            std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let lines = non_test_lines(file, &text, &mut test_files);
        per_file.push((rel(file), lines));
    }
    let test_rel: Vec<String> = test_files.iter().map(|p| rel(p)).collect();
    let catalogue = catalogue_codes();
    let mut uses = Uses::default();
    for (name, lines) in per_file {
        let is_test = test_rel
            .iter()
            .any(|t| name == *t || name.starts_with(&format!("{t}/")));
        if !is_test {
            uses.read(&name, &lines, &catalogue);
        }
    }
    uses
}

/// `text` as numbered lines, the way the walk reads a file.
fn numbered(text: &str) -> Vec<(usize, String)> {
    let mut none = Vec::new();
    non_test_lines(Path::new("services/x/src/lib.rs"), text, &mut none)
}

#[test]
fn the_walk_skips_test_code_and_finds_strings_and_raises() {
    let catalogue = catalogue_codes();
    let mut uses = Uses::default();
    let text = r#"
fn raise() -> JobError {
    let _ = Stage::Model.error("CUT_DEPTH", "process.cuts", "1", "0", "no");
    let _ = finding(3, "PARSE", String::new());
    let _ = ("NOT_FOUND", env!("CARGO_PKG_VERSION"), "REFUSED", "Fα");
    Stage::Model.error(Code::BASE_PITCH_MISMATCH, "hob.module_mm", "", "", "")
}
// Stage::Model.error("IN_A_COMMENT", ...)
#[cfg(test)]
mod tests {
    fn t() { assert_eq!(e.code, "SP_1001_REV_B"); let _ = Code::ARC_FIT; }
}
"#;
    uses.read("x.rs", &numbered(text), &catalogue);
    let strings: Vec<&str> = uses.strings.keys().map(String::as_str).collect();
    assert_eq!(strings, ["CUT_DEPTH", "PARSE"], "{uses:?}");
    assert_eq!(uses.strings["CUT_DEPTH"], ["x.rs:3"]);
    let raises: Vec<&str> = uses.raises.keys().map(String::as_str).collect();
    assert_eq!(raises, ["BASE_PITCH_MISMATCH"], "{uses:?}");

    // The real source: raises of each kind (a model check, a path-check rule,
    // a codec code in proto, a wire-die problem).
    let uses = uses_in_source();
    for code in [
        "BASE_PITCH_MISMATCH",
        "PARSE",
        "UNKNOWN_SCHEMA_VERSION",
        "WIRE_DEVIATION",
    ] {
        assert!(uses.raises.contains_key(code), "{code} not found");
    }
}

#[test]
fn no_code_is_written_as_a_string_outside_the_catalogue() {
    let uses = uses_in_source();
    let strings: Vec<String> = uses
        .strings
        .iter()
        .map(|(code, at)| format!("  \"{code}\" at {}", at.join(", ")))
        .collect();
    assert!(
        strings.is_empty(),
        "{} code(s) written as strings: name a code as gearcam_proto::Code::X (add a new one to proto/src/codes.rs), or list a literal that is not a code in NOT_CODES of this test:\n{}",
        strings.len(),
        strings.join("\n")
    );
}

#[test]
fn every_catalogue_entry_is_raised() {
    let uses = uses_in_source();
    let stale: Vec<&str> = catalogue_codes()
        .into_iter()
        .filter(|code| !uses.raises.contains_key(*code))
        .collect();
    assert!(
        stale.is_empty(),
        "{} catalogue entr(y/ies) raised nowhere in the source (remove them from proto/src/codes.rs): {}",
        stale.len(),
        stale.join(", ")
    );
}

/// A table cell: no line breaks, `|` escaped.
fn cell(text: &str) -> String {
    text.replace('\n', " ").replace('|', "\\|")
}

/// `docs/errors.md` as generated from the catalogue.
fn page(catalogue: &[CodeInfo]) -> String {
    let mut out = String::from(
        "# Error and warning codes\n\
         \n\
         <!-- Generated from gearcam_proto::codes::CATALOGUE (proto/src/codes.rs); do not edit.\n\
         \x20    Rewrite with: GEARCAM_BLESS=1 cargo test -p gearcam-tests --test error_codes -->\n\
         \n\
         Every error a stage reports is a typed error: `stage`, `code`, `field`,\n\
         `expected`, `got` and `message` (proto/README.md). This page lists every\n\
         code gearcam raises, the stages that raise it, what it means and what to\n\
         do. Stage `any` marks the codec's codes, which every stage that decodes a\n\
         message can raise. A code marked `template (path check)` is a rule of the\n\
         NC path check (crates/nc/DIALECTS.md): each finding is reported as a\n\
         `PATH_CHECK_FAILED` error whose `expected` names the rule, and the program\n\
         is not sent.\n\
         \n",
    );
    out.push_str(&format!("{} codes.\n\n", catalogue.len()));
    out.push_str("| code | stage | meaning | what to do |\n|---|---|---|---|\n");
    for c in catalogue {
        out.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            c.code,
            cell(c.stage),
            cell(c.meaning),
            cell(c.action)
        ));
    }
    out
}

/// The codes listed in the first column of a page's table.
fn codes_on_page(text: &str) -> BTreeSet<String> {
    text.lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_string)
        .collect()
}

#[test]
fn docs_errors_md_is_the_page_generated_from_the_catalogue() {
    let path = workspace().join(PAGE);
    let want = page(CATALOGUE);
    if std::env::var_os("GEARCAM_BLESS").is_some() {
        std::fs::write(&path, &want).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        return;
    }
    let got = std::fs::read_to_string(&path).unwrap_or_default();
    if got == want {
        return;
    }
    let listed = codes_on_page(&got);
    let catalogue: BTreeSet<String> = CATALOGUE.iter().map(|c| c.code.to_string()).collect();
    let missing: Vec<&String> = catalogue.difference(&listed).collect();
    let extra: Vec<&String> = listed.difference(&catalogue).collect();
    panic!(
        "{PAGE} differs from the catalogue (missing codes {missing:?}, codes not in the catalogue {extra:?}, or changed text).\n\
         Rewrite it with `GEARCAM_BLESS=1 cargo test -p gearcam-tests --test error_codes`, or paste this page:\n\n{want}"
    );
}
