//! Job files: TOML in, a validated [`JobSpec`] out, with errors that name the
//! key, what was expected and what was given.

use gearcam_proto::Code;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicU32, Ordering};

use gearcam_proto::{
    now_ms, part_number_problem, ForeignSections, JobError, JobFile, JobId, JobRequest, JobSpec,
    Stage, MAX_PART_NUMBER,
};

/// Parses a job file's text. `origin` names it in messages.
pub fn parse(text: &str, origin: &str) -> Result<JobSpec, JobError> {
    let de = toml::Deserializer::new(text);
    let file = serde_path_to_error::deserialize::<_, JobFile>(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let detail = inner.message().to_string();
        let at = inner.span().map(|s| {
            let before = &text[..s.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            (line, column)
        });
        // Not a key's value but the file's own syntax (an unclosed header, a
        // stray character): no field to name; the line and column, and the
        // parser's sentence on one line.
        if path == "." {
            if let Some((line, column)) = at {
                return syntax_error(text, origin, line, column, &detail);
            }
        }
        let location = at
            .map(|(line, _)| format!(" (line {line})"))
            .unwrap_or_default();
        file_error(&path, &detail, &format!("{origin}{location}"))
    })?;
    let spec = JobSpec::try_from(file).map_err(|e| foreign_sections(&e, origin))?;
    check_part_number(&spec)?;
    check_finite(&spec, origin)?;
    Ok(spec)
}

/// `SECTION_FAMILY` for the sections of a job file that belong to another
/// family than its `[job] family`, on the first of them.
fn foreign_sections(e: &ForeignSections, origin: &str) -> JobError {
    let first = e.sections.first().map_or("job.family", |(s, _)| *s);
    Stage::Station.error(
        Code::SECTION_FAMILY,
        first,
        format!(
            "the sections of a {} job: {}",
            e.family.as_str(),
            e.family.sections().join(", ")
        ),
        e.sections
            .iter()
            .map(|(s, _)| format!("[{s}]"))
            .collect::<Vec<_>>()
            .join(", "),
        format!("{origin}: {e}; remove the section, or set [job] family to the job's family"),
    )
}

/// `NOT_FINITE` for the first number of the job that is `inf` or `nan`
/// ([`gearcam_proto::job::non_finite`], the station's check too).
fn check_finite(spec: &JobSpec, origin: &str) -> Result<(), JobError> {
    match gearcam_proto::job::non_finite(spec) {
        None => Ok(()),
        Some((field, f)) => Err(Stage::Station.error(
            Code::NOT_FINITE,
            &field,
            "a finite number",
            f.to_string(),
            format!("{origin}: {field} is {f}; give a finite number"),
        )),
    }
}

/// `JOB_FILE_INVALID` for TOML that does not parse, at `line` and `column`
/// (1-based): expected is what the parser expected there, got the line's
/// text, the message the parser's sentence, each on one line.
fn syntax_error(text: &str, origin: &str, line: usize, column: usize, detail: &str) -> JobError {
    let sentence: Vec<&str> = detail
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let (what, wanted) = match sentence.split_first() {
        Some((first, rest)) => (first.to_string(), rest.join("; ")),
        None => ("the file is not TOML".to_string(), String::new()),
    };
    let wanted = wanted
        .strip_prefix("expected ")
        .unwrap_or(&wanted)
        .to_string();
    let got = text.lines().nth(line - 1).unwrap_or("").trim().to_string();
    Stage::Station.error(
        Code::JOB_FILE_INVALID,
        &format!("line {line}, column {column}"),
        &if wanted.is_empty() {
            "TOML (see docs and examples/)".to_string()
        } else {
            wanted.clone()
        },
        &got,
        format!(
            "{origin} (line {line}, column {column}): {what}{}",
            if wanted.is_empty() {
                String::new()
            } else {
                format!("; expected {wanted}")
            }
        ),
    )
}

/// The typed error of a job file serde refused, in a planner's words: the
/// key, what it takes, what was given, and for an unknown key the nearest
/// known one.
fn file_error(path: &str, detail: &str, place: &str) -> JobError {
    if let Some(rest) = detail.strip_prefix("unknown field `") {
        let key = rest.split('`').next().unwrap_or_default();
        let known: Vec<&str> = rest
            .split_once("expected ")
            .map(|(_, e)| e.split('`').skip(1).step_by(2).collect())
            .unwrap_or_default();
        let field = join_path(path, key);
        let (expected, hint) = match nearest(key, &known) {
            Some(near) => (
                format!("`{near}` (the known keys here: {})", known.join(", ")),
                format!("; did you mean `{near}`?"),
            ),
            None => (format!("one of {}", known.join(", ")), String::new()),
        };
        return Stage::Station.error(
            Code::JOB_FILE_UNKNOWN_KEY,
            &field,
            &expected,
            key,
            format!("{place}: unknown key `{key}`{hint}"),
        );
    }
    if let Some(rest) = detail.strip_prefix("missing field `") {
        let key = rest.split('`').next().unwrap_or_default();
        let field = join_path(path, key);
        // A [gear] section is complete drawing data or absent: a part number
        // from the workpiece library stands for the whole section.
        let hint = if field.starts_with("gear.") {
            "; or leave out the whole [gear] section to take the drawing data of the part number from the workpiece library"
        } else {
            ""
        };
        return Stage::Station.error(
            Code::JOB_FILE_MISSING_KEY,
            &field,
            "a value",
            "nothing",
            format!("{place}: {key} is missing{hint}"),
        );
    }
    // serde: `invalid type: floating point `2.5`, expected u32`; an id:
    // `invalid machine id "H/01": it contains '/'; expected 1 to 32 …`.
    let split = detail
        .split_once(", expected ")
        .or_else(|| detail.split_once("; expected "));
    match split {
        Some((head, wanted)) => {
            let got = head
                .split('`')
                .nth(1)
                .or_else(|| head.split('"').nth(1))
                .unwrap_or(head)
                .to_string();
            // The number of parts takes 1 or more (0 is refused later).
            let expected = if path.ends_with("quantity") {
                "a whole number of parts, 1 or more".to_string()
            } else {
                plain_type(wanted)
            };
            Stage::Station.error(
                Code::JOB_FILE_INVALID,
                path,
                &expected,
                &got,
                format!("{place}: {path} takes {expected}, got {got} ({head})"),
            )
        }
        None => Stage::Station.error(
            Code::JOB_FILE_INVALID,
            path,
            "see message",
            "see message",
            format!("{place}: {path}: {detail}"),
        ),
    }
}

/// A Rust type name as a planner says it.
fn plain_type(rust: &str) -> String {
    match rust.trim() {
        "u8" => "a whole number from 0 to 255".into(),
        "u16" => "a whole number from 0 to 65535".into(),
        "u32" => "a whole number from 0 to 4294967295".into(),
        "u64" => "a whole number ≥ 0".into(),
        "i32" | "i64" => "a whole number".into(),
        "f32" | "f64" => "a number".into(),
        "a boolean" | "bool" => "true or false".into(),
        other => other.to_string(),
    }
}

/// The known key nearest to `key` (at most 2 edits away, and closer than
/// half its length), if any.
fn nearest<'a>(key: &str, known: &[&'a str]) -> Option<&'a str> {
    known
        .iter()
        .map(|k| (edit_distance(key, k), *k))
        .filter(|(d, _)| *d <= 2 && *d * 2 < key.len().max(1))
        .min()
        .map(|(_, k)| k)
}

/// The number of single-character insertions, deletions, substitutions and
/// transpositions of neighbours that turn `a` into `b`.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// The part number names the part: not empty, not over [`MAX_PART_NUMBER`]
/// characters, one line.
fn check_part_number(spec: &JobSpec) -> Result<(), JobError> {
    let p = &spec.job.part_number;
    let n = p.chars().count();
    match part_number_problem(p) {
        None => Ok(()),
        Some(reason) => Err(Stage::Station.error(
            Code::JOB_FILE_INVALID,
            "job.part_number",
            format!("the part (drawing) number: 1 to {MAX_PART_NUMBER} characters on one line"),
            &if n > 40 {
                format!(
                    "{}… ({n} characters)",
                    p.chars().take(40).collect::<String>()
                )
            } else {
                p.clone()
            },
            format!("the part number is not usable: {reason}"),
        )),
    }
}

/// The dotted path of `key` under `path`; the path may already end with it
/// (serde_path_to_error includes an unknown key, not a missing one).
fn join_path(path: &str, key: &str) -> String {
    if path == "." || path.is_empty() {
        key.to_string()
    } else if path == key || path.ends_with(&format!(".{key}")) {
        path.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// Reads and parses a job file.
pub fn load(path: &Path) -> Result<JobSpec, JobError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        let code = if e.kind() == std::io::ErrorKind::NotFound {
            Code::JOB_FILE_NOT_FOUND
        } else {
            Code::JOB_FILE_UNREADABLE
        };
        Stage::Station.error(
            code,
            "-",
            "a readable TOML job file",
            &origin,
            format!("cannot read {origin}: {e}"),
        )
    })?;
    parse(&text, &origin)
}

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// The job id: the file's `[job] id`, or `{part}-{ms}-{pid}-{n}`: the part,
/// the milliseconds, the process (its id mod 1000) and a counter of the
/// process, each after its own `-` so that no two of them run together.
pub fn job_id(spec: &JobSpec) -> JobId {
    if let Some(id) = &spec.job.id {
        return id.clone();
    }
    let part: String = spec
        .job
        .part_number
        .chars()
        .filter_map(|c| match c {
            c if c.is_ascii_alphanumeric() => Some(c),
            '-' | '_' | '.' | ' ' => Some('-'),
            _ => None,
        })
        .take(24)
        .collect();
    let part = part.trim_matches('-');
    let part = if part.is_empty() { "job" } else { part };
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    JobId::new(format!(
        "{part}-{}-{}-{n}",
        now_ms(),
        std::process::id() % 1000
    ))
    .expect("generated job ids are valid")
}

/// `MESSAGE_TOO_LARGE` when the request is larger than a request on the
/// bus may be ([`gearcam_proto::keys::MAX_REQUEST_BYTES`]): the station
/// refuses it and a secure router drops it, so `check` says so too and
/// `submit` says so before sending.
pub fn check_size(req: &JobRequest) -> Result<(), JobError> {
    let limit = gearcam_proto::keys::MAX_REQUEST_BYTES;
    let bytes = gearcam_proto::encode(req)
        .map(|b| b.len())
        .unwrap_or(usize::MAX);
    if bytes <= limit {
        return Ok(());
    }
    Err(Stage::Station.error(
        Code::MESSAGE_TOO_LARGE,
        "-",
        format!("a job request of at most {limit} bytes"),
        format!("{bytes} bytes"),
        format!(
            "the job is larger than a message on the bus may be ({bytes} of {limit} bytes); the station refuses it"
        ),
    ))
}

/// Wraps a spec into a request from this station, submitted by [`user`].
pub fn request(spec: JobSpec) -> JobRequest {
    JobRequest {
        job_id: job_id(&spec),
        submitted_at_ms: now_ms(),
        submitted_by: user(),
        spec,
    }
}

/// Who a command acts as on the bus: the login of an authenticated
/// connection (its configuration's user, the name the router checks), else
/// `--by`, else [`user`]. With a login, a `--by` naming someone else is a
/// usage error: the router grants each login only the keys with its own
/// name, so the change would be dropped, not recorded as theirs.
pub fn who(bus_args: &gearcam_bus::BusArgs, by: Option<String>) -> Result<String, ExitCode> {
    if let Some(by) = by
        .as_deref()
        .filter(|b| !gearcam_proto::delivery::valid_by(b))
    {
        return Err(crate::output::fail(
            crate::exit::USAGE,
            &[],
            &format!("gearcam: --by {by:?}: give who decides, 1 to 64 characters on one line"),
        ));
    }
    let login = crate::bus_config::client(bus_args).login();
    match (login, by) {
        (Some(login), Some(by)) if by != login => Err(crate::output::fail(
            crate::exit::USAGE,
            &[],
            &format!(
                "gearcam: --by {by}: this connection logs in as {login}, and a change is recorded as the login's; leave --by out"
            ),
        )),
        (Some(login), _) => Ok(login),
        (None, Some(by)) => Ok(by),
        (None, None) => Ok(user()),
    }
}

/// Who acts — submits, cancels, resolves, rolls back, confirms, edits the
/// knowledge base: the login name (`$USER`, else `$LOGNAME`), else
/// `unknown`; one rule for every command that records who. The one place
/// the command's library reads the environment.
#[allow(clippy::disallowed_methods)]
pub fn user() -> String {
    ["USER", "LOGNAME"]
        .iter()
        .filter_map(|v| std::env::var(v).ok())
        .map(|v| v.trim().to_string())
        .find(|v| !v.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
[job]
machine = "H01"
part_number = "SP-1"
[gear]
module_mm = 3.0
teeth = 25
face_width_mm = 30.0
fixture_height_mm = 100.0
"#;

    #[test]
    fn parses_a_minimal_job_with_defaults() {
        let spec = parse(MINIMAL, "t.toml").unwrap();
        assert_eq!(
            spec.hobbing()
                .unwrap()
                .gear
                .as_ref()
                .unwrap()
                .pressure_angle_deg,
            20.0
        );
        assert_eq!(spec.job.quantity, 1);
        assert!(spec.hobbing().unwrap().options.coolant);
        let id = job_id(&spec);
        assert!(id.as_str().starts_with("SP-1-"), "{id}");
        // Part, milliseconds, process, counter: four fields, the last two
        // apart, so a counter of 10 after process 692 is not process 69's 210.
        let next = job_id(&spec);
        let fields: Vec<&str> = next.as_str().rsplitn(4, '-').collect();
        assert_eq!(fields.len(), 4, "{next}");
        assert_eq!(fields[1], (std::process::id() % 1000).to_string(), "{next}");
        assert!(fields[0].parse::<u64>().is_ok(), "{next}");
        assert_ne!(id, next);
    }

    #[test]
    fn a_section_of_another_family_is_named_when_the_file_is_read() {
        let text = format!("{MINIMAL}[wire]\nprogram = \"3b\"\n");
        let err = parse(&text, "t.toml").unwrap_err();
        assert_eq!(err.code, Code::SECTION_FAMILY);
        assert_eq!(err.stage, Stage::Station);
        assert_eq!(err.field, "wire");
        assert_eq!(err.got, "[wire]");
        assert!(err.expected.contains("[gear]"), "{}", err.expected);
        assert!(
            err.message
                .contains("[wire] belongs to the wire-edm family"),
            "{}",
            err.message
        );
        // The same file as a wire job: its [gear] is the foreign one.
        let text = text.replace("[job]\n", "[job]\nfamily = \"wire-edm\"\n");
        let err = parse(&text, "t.toml").unwrap_err();
        assert_eq!(
            (err.code, err.field.as_str()),
            (Code::SECTION_FAMILY, "gear")
        );
    }

    #[test]
    fn an_unknown_key_is_named_with_its_section() {
        let text = MINIMAL.replace("teeth = 25", "teeth = 25\nmodul_mm = 3");
        let err = parse(&text, "t.toml").unwrap_err();
        assert_eq!(err.code, "JOB_FILE_UNKNOWN_KEY");
        assert_eq!(err.field, "gear.modul_mm");
        assert!(err.expected.contains("module_mm"), "{}", err.expected);
        assert!(err.message.contains("t.toml (line"), "{}", err.message);
    }

    #[test]
    fn a_job_without_a_gear_section_parses_for_the_library_to_fill() {
        let text = MINIMAL.split("[gear]").next().unwrap();
        let spec = parse(text, "t.toml").unwrap();
        assert!(!spec.has_gear());
        assert_eq!(spec.job.part_number, "SP-1");
    }

    #[test]
    fn the_operation_is_rough_or_finish() {
        let spec = parse(
            &format!("{MINIMAL}[process]\noperation = \"rough\"\n"),
            "t.toml",
        )
        .unwrap();
        assert_eq!(
            spec.hobbing().unwrap().process.operation,
            Some(gearcam_proto::Operation::Rough)
        );
        let spec = parse(MINIMAL, "t.toml").unwrap();
        assert_eq!(spec.hobbing().unwrap().process.operation, None);
        let err = parse(
            &format!("{MINIMAL}[process]\noperation = \"semi\"\n"),
            "t.toml",
        )
        .unwrap_err();
        assert_eq!(err.field, "process.operation");
        assert!(err.message.contains("rough"), "{}", err.message);
    }

    #[test]
    fn a_missing_key_and_a_bad_id_are_named() {
        let text = MINIMAL.replace("teeth = 25\n", "");
        let err = parse(&text, "t.toml").unwrap_err();
        assert_eq!(
            (err.code.as_str(), err.field.as_str()),
            ("JOB_FILE_MISSING_KEY", "gear.teeth")
        );
        assert!(
            err.message.contains("leave out the whole [gear] section"),
            "{}",
            err.message
        );
        let text = MINIMAL.replace("machine = \"H01\"", "machine = \"H/01\"");
        let err = parse(&text, "t.toml").unwrap_err();
        assert_eq!(err.field, "job.machine");
        assert!(err.message.contains("machine id"), "{}", err.message);
    }
}
