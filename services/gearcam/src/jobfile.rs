//! Job files: TOML in, a validated [`JobSpec`] out, with errors that name the
//! key, what was expected and what was given.

use std::path::Path;
use std::sync::atomic::{AtomicU32, Ordering};

use gearcam_proto::{now_ms, JobError, JobId, JobRequest, JobSpec, Stage};

fn station_error(code: &str, field: &str, expected: &str, got: &str, message: String) -> JobError {
    JobError::new(Stage::Station, code, field, expected, got, message)
}

/// Parses a job file's text. `origin` names it in messages.
pub fn parse(text: &str, origin: &str) -> Result<JobSpec, JobError> {
    let de = toml::Deserializer::new(text);
    serde_path_to_error::deserialize::<_, JobSpec>(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let detail = inner.message().to_string();
        let location = inner
            .span()
            .map(|s| {
                let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
                format!(" (line {line})")
            })
            .unwrap_or_default();
        // serde names an unknown key in its message; put it in the field path.
        let (code, field, expected) = if let Some(rest) = detail.strip_prefix("unknown field `") {
            let key = rest.split('`').next().unwrap_or_default();
            let expected = rest
                .split_once("expected ")
                .map(|(_, e)| e.to_string())
                .unwrap_or_else(|| "a known key".into());
            ("JOB_FILE_UNKNOWN_KEY", join_path(&path, key), expected)
        } else if let Some(rest) = detail.strip_prefix("missing field `") {
            let key = rest.split('`').next().unwrap_or_default();
            (
                "JOB_FILE_MISSING_KEY",
                join_path(&path, key),
                "a value".to_string(),
            )
        } else {
            ("JOB_FILE_INVALID", path.clone(), "see message".to_string())
        };
        // A [gear] section is complete drawing data or absent: a part number
        // from the workpiece library stands for the whole section.
        let hint = if code == "JOB_FILE_MISSING_KEY" && field.starts_with("gear.") {
            "; or leave out the whole [gear] section to take the drawing data of the part number from the workpiece library"
        } else {
            ""
        };
        station_error(
            code,
            &field,
            &expected,
            if code == "JOB_FILE_MISSING_KEY" {
                "nothing"
            } else {
                "see message"
            },
            format!("{origin}{location}: {detail}{hint}"),
        )
    })
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
        station_error(
            "JOB_FILE_UNREADABLE",
            "-",
            "a readable TOML job file",
            &origin,
            format!("cannot read {origin}: {e}"),
        )
    })?;
    parse(&text, &origin)
}

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// The job id: the file's `[job] id`, or `{part}-{ms}-{n}` made unique per
/// process and millisecond.
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
        "{part}-{}-{}{n}",
        now_ms(),
        std::process::id() % 1000
    ))
    .expect("generated job ids are valid")
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

/// Who submits: the login name (`$USER`), or `gearcam`. The one place the
/// command's library reads the environment.
#[allow(clippy::disallowed_methods)]
pub fn user() -> String {
    std::env::var("USER").unwrap_or_else(|_| "gearcam".into())
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
        assert_eq!(spec.gear.as_ref().unwrap().pressure_angle_deg, 20.0);
        assert_eq!(spec.job.quantity, 1);
        assert!(spec.options.coolant);
        let id = job_id(&spec);
        assert!(id.as_str().starts_with("SP-1-"), "{id}");
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
            spec.process.operation,
            Some(gearcam_proto::Operation::Rough)
        );
        assert_eq!(parse(MINIMAL, "t.toml").unwrap().process.operation, None);
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
