//! One program of a machine's store: every version newest first with who
//! and what made each (the version's record and its program header), the
//! current one marked, an edit at the machine waiting for review with the
//! buttons to resolve it; one version's text and its download.

use std::collections::HashMap;

use axum::extract::{Path, State};
use axum::http::{header, StatusCode};
use axum::response::IntoResponse;
use axum::Extension;
use gearcam_proto::{utc_text, JobStatus, MachineId, ProgramVersion};
use maud::{html, Markup};

use super::{
    answered, change_refusal, conflicts, machine_of, on_the_bus, program_href, program_name_of,
    segment, seq_of, station_jobs, style, Reply,
};
use crate::store;
use crate::web::auth::{self, Session};
use crate::web::{page, Web};

/// The newest versions whose text is read for its header on the program's
/// page (older ones show their record only).
const HEADERS_READ: usize = 20;

/// What a program's header says made it, where the dialect writes it: who
/// submitted the job and when, the template and its version, the cases of
/// the knowledge base, the model and the generator.
#[derive(Debug, Default, Clone, PartialEq)]
pub(super) struct Provenance {
    /// `SUBMITTED …`: when and by whom.
    pub(super) submitted: Option<String>,
    /// `TEMPLATE …`: the template and its version.
    pub(super) template: Option<String>,
    /// `CASES …`: the knowledge base's records behind the values.
    pub(super) cases: Option<String>,
    /// `MODEL …`: the model service.
    pub(super) model: Option<String>,
    /// `GENERATOR …` (or a comment naming `gearcam-template`).
    pub(super) generator: Option<String>,
}

/// Reads the provenance from the comments of a program's first lines: the
/// text after `;` (840D, 3B/4B) and inside `( … )` (FANUC, ISO,
/// LinuxCNC).
pub(super) fn provenance(text: &str) -> Provenance {
    let mut p = Provenance::default();
    for line in text.lines().take(40) {
        let mut comments: Vec<&str> = Vec::new();
        let (code, after_semicolon) = match line.split_once(';') {
            Some((code, rest)) => (code, Some(rest)),
            None => (line, None),
        };
        let mut rest = code;
        while let Some((_, open)) = rest.split_once('(') {
            let (inside, tail) = open.split_once(')').unwrap_or((open, ""));
            comments.push(inside);
            rest = tail;
        }
        comments.extend(after_semicolon);
        for c in comments.into_iter().map(str::trim) {
            let (word, value) = c.split_once(' ').unwrap_or((c, ""));
            let value = Some(value.trim().to_string());
            match word.to_ascii_uppercase().as_str() {
                "SUBMITTED" => p.submitted = value,
                "TEMPLATE" => p.template = value,
                "CASES" => p.cases = value,
                "MODEL" => p.model = value,
                "GENERATOR" => p.generator = value,
                _ if p.generator.is_none()
                    && c.to_ascii_uppercase().contains("GEARCAM-TEMPLATE") =>
                {
                    p.generator = Some(c.to_string())
                }
                _ => {}
            }
        }
    }
    p
}

/// The oldest version before `v` with the same text: what a rollback or a
/// replacement made current again.
fn same_text_before<'a>(
    v: &ProgramVersion,
    versions: &'a [ProgramVersion],
) -> Option<&'a ProgramVersion> {
    versions
        .iter()
        .filter(|o| o.seq < v.seq && o.sha256 == v.sha256)
        .min_by_key(|o| o.seq)
}

/// Who and what made version `v`, in words.
pub(super) fn made_by(v: &ProgramVersion, versions: &[ProgramVersion]) -> String {
    let by = if v.by.is_empty() { "unknown" } else { &v.by };
    let origin = same_text_before(v, versions)
        .map(|o| format!(" version {}", o.seq))
        .unwrap_or_default();
    match v.state.as_str() {
        "stored" => format!("delivered by job {} (revision {})", v.job, v.revision),
        "rollback" => format!("rolled back to{origin} by {by}"),
        "adopted" => format!("edit at the machine, adopted by {by}"),
        "machine-edit" => format!("edit at the machine, kept in the history; replaced by {by}"),
        "restored" => format!("gearcam's{origin} written back over the edit by {by}"),
        other => format!("{other} by {by}"),
    }
}

/// The texts of versions `seqs` of program `name`, asked of the agent all
/// at once; a version that cannot be read is left out.
async fn texts(web: &Web, machine: &MachineId, name: &str, seqs: &[u64]) -> HashMap<u64, String> {
    let mut set = tokio::task::JoinSet::new();
    for &seq in seqs {
        let (bus, machine, name) = (web.bus.clone(), machine.clone(), name.to_string());
        set.spawn(async move { (seq, store::version(&bus, &machine, &name, seq).await) });
    }
    let mut out = HashMap::new();
    while let Some(Ok((seq, answer))) = set.join_next().await {
        if let Ok(Ok(t)) = answer {
            out.insert(seq, t.text);
        }
    }
    out
}

/// The provenance of a version as table cells: template, cases, generator.
fn provenance_cells(p: Option<&Provenance>) -> Markup {
    let cell = |v: Option<&String>| html! { td { @if let Some(v) = v { (v) } @else { span.muted { "—" } } } };
    html! {
        (cell(p.and_then(|p| p.template.as_ref())))
        (cell(p.and_then(|p| p.cases.as_ref())))
        (cell(p.and_then(|p| p.generator.as_ref())))
    }
}

/// `GET /machines/{machine}/programs/{name}`: every version newest first,
/// the current one marked, an edit at the machine to review.
pub(super) async fn program_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((machine, name)): Path<(String, String)>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    on_the_bus(&web, &session, &machine).await?;
    let what = format!("Program {name} at {machine}");
    let history = answered(
        &session,
        &what,
        store::history(&web.bus, &machine, Some(name)).await,
    )?;
    let versions = history.versions;
    let Some(current) = versions.iter().find(|v| v.current).or(versions.first()) else {
        return Ok(StatusCode::NOT_FOUND.into_response());
    };
    let seqs: Vec<u64> = versions.iter().take(HEADERS_READ).map(|v| v.seq).collect();
    let headers: HashMap<u64, Provenance> = texts(&web, &machine, name, &seqs)
        .await
        .into_iter()
        .map(|(seq, text)| (seq, provenance(&text)))
        .collect();
    let jobs = station_jobs(&web).await;
    let waiting = jobs
        .as_deref()
        .map(|j| conflicts(j, &machine, current))
        .unwrap_or_default();
    let may = change_refusal(&session.user, &machine).is_none();
    let href = program_href(&machine, name);
    let body = html! {
        p { a href=(format!("/machines/{}", segment(machine.as_str()))) { "← programs of " (machine) } }
        h1 { (what) }
        (style())
        dl {
            dt { "file" } dd { code { (current.file_name) } }
            dt { "part" } dd { (current.part_number) }
            dt { "current" } dd #current { (current.seq) " — " (made_by(current, &versions)) }
        }
        @if !waiting.is_empty() { (conflict_box(&session, &machine, &href, current, &waiting, may)) }
        @if jobs.is_none() {
            p.muted { "The planning station does not answer: an edit at the machine that waits for review is not shown." }
        }
        h2 { "Versions" }
        (versions_table(&href, &versions, &headers, may))
        h2 { "Compare two versions" }
        (diff_form(&href, &versions))
    };
    Ok((StatusCode::OK, page(&what, Some(&session), body)).into_response())
}

/// Every version newest first: who and what made it, its job, its header's
/// template, cases and generator, and what can be done with it.
fn versions_table(
    href: &str,
    versions: &[ProgramVersion],
    headers: &HashMap<u64, Provenance>,
    may: bool,
) -> Markup {
    html! {
        table #versions {
            thead { tr {
                th { "version" } th { "made by" } th { "job" } th { "template" } th { "cases" } th { "generator" }
                th { "stored at" } th { "sha256" } th { "bytes" } th { "" }
            } }
            tbody {
                @for (i, v) in versions.iter().enumerate() {
                    tr.current[v.current] data-seq=(v.seq) {
                        td { (v.seq) @if v.current { " (current)" } }
                        td.made { (made_by(v, versions)) }
                        td { a href=(format!("/jobs/{}", segment(&v.job))) { (v.job) } }
                        (provenance_cells(headers.get(&v.seq)))
                        td { (utc_text(v.stored_at_ms)) }
                        td { code { (v.sha256.chars().take(12).collect::<String>()) } }
                        td { (v.size_bytes) }
                        td {
                            a href=(format!("{href}/versions/{}", v.seq)) { "text" } " · "
                            a href=(format!("{href}/versions/{}/download", v.seq)) { "download" }
                            @if let Some(older) = versions.get(i + 1) {
                                " · " a.diff href=(format!("{href}/diff?a={}&b={}", older.seq, v.seq)) { "diff with " (older.seq) }
                            }
                            @if may && !v.current {
                                " · " a.rollback href=(format!("{href}/versions/{}/rollback", v.seq)) { "Roll back to this" }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The form that asks for the diff of two versions.
fn diff_form(href: &str, versions: &[ProgramVersion]) -> Markup {
    let select = |field: &str, chosen: usize| {
        html! {
            select name=(field) {
                @for (i, v) in versions.iter().enumerate() {
                    option value=(v.seq) selected[i == chosen] { (v.seq) " — " (v.state) " " (utc_text(v.stored_at_ms)) }
                }
            }
        }
    };
    html! {
        form #compare method="get" action=(format!("{href}/diff")) {
            label { "from " (select("a", 1.min(versions.len().saturating_sub(1)))) } " "
            label { "to " (select("b", 0)) } " "
            button type="submit" { "Diff" }
        }
    }
}

/// An edit at the machine that jobs wait on: what is known of it and,
/// for those who may, the buttons that adopt or replace it.
fn conflict_box(
    session: &Session,
    machine: &MachineId,
    href: &str,
    current: &ProgramVersion,
    waiting: &[&JobStatus],
    may: bool,
) -> Markup {
    html! {
        section.conflict #conflict {
            h2 { "Changed at the machine: a conflict to review" }
            p {
                "The file " code { (current.file_name) } " at " (machine) " is no longer gearcam's current version "
                (current.seq) " (sha256 " code { (current.sha256.chars().take(12).collect::<String>()) } "): it was edited at the machine. "
                "The agent kept the edit and overwrites nothing; these jobs wait for a decision:"
            }
            ul {
                @for s in waiting {
                    li {
                        a href=(format!("/jobs/{}", segment(s.job.as_str()))) { (s.job) }
                        " since " (utc_text(s.updated_at_ms)) ": "
                        span.muted { (s.waiting_for.as_deref().unwrap_or_default()) }
                    }
                }
            }
            p.muted {
                "The agent sends the edit's text once it is resolved: either way the edit becomes a version of this history, "
                "and its diff against gearcam's version " (current.seq) " is linked in the table below."
            }
            @if may {
                form.inline method="post" action=(format!("{href}/adopt")) {
                    (auth::csrf_input(session))
                    button type="submit" #adopt { "Adopt" }
                    span.muted { "the edit becomes the current version; the jobs that waited end superseded" }
                }
                br;
                form.inline method="post" action=(format!("{href}/replace")) {
                    (auth::csrf_input(session))
                    button type="submit" #replace { "Replace" }
                    span.muted { "gearcam's version " (current.seq) " is written back; the edit stays in the history" }
                }
            } @else {
                p { "Only an operator of " (machine) " or a supervisor may adopt or replace it." }
            }
        }
    }
}

/// `GET …/versions/{seq}`: one version's record, header and text.
pub(super) async fn version_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((machine, name, seq)): Path<(String, String, String)>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let seq = seq_of(&session, "seq", &seq)?;
    on_the_bus(&web, &session, &machine).await?;
    let what = format!("{name} at {machine}, version {seq}");
    let t = answered(
        &session,
        &what,
        store::version(&web.bus, &machine, name, seq).await,
    )?;
    let history = answered(
        &session,
        &what,
        store::history(&web.bus, &machine, Some(name)).await,
    )?;
    let v = &t.version;
    let p = provenance(&t.text);
    let href = program_href(&machine, name);
    let current = history.versions.iter().find(|o| o.current);
    let may = change_refusal(&session.user, &machine).is_none();
    let body = html! {
        p { a href=(href) { "← " (name) " at " (machine) } }
        h1 { (what) @if v.current { " (current)" } }
        dl {
            dt { "made by" } dd { (made_by(v, &history.versions)) }
            dt { "job" } dd { a href=(format!("/jobs/{}", segment(&v.job))) { (v.job) } }
            dt { "part" } dd { (v.part_number) }
            dt { "stored at" } dd { (utc_text(v.stored_at_ms)) }
            dt { "file" } dd { code { (v.file_name) } " (" (v.size_bytes) " bytes, sha256 " code { (v.sha256) } ")" }
            @for (label, value) in [("submitted", &p.submitted), ("template", &p.template), ("cases", &p.cases), ("model", &p.model), ("generator", &p.generator)] {
                @if let Some(value) = value { dt { (label) } dd { (value) } }
            }
        }
        p {
            a #download href=(format!("{href}/versions/{seq}/download")) { "Download" }
            @if let Some(c) = current.filter(|c| c.seq != seq) {
                " · " a href=(format!("{href}/diff?a={seq}&b={}", c.seq)) { "diff with the current version " (c.seq) }
                @if may { " · " a.rollback href=(format!("{href}/versions/{seq}/rollback")) { "Roll back to this" } }
            }
        }
        pre.program { (t.text) }
    };
    Ok((StatusCode::OK, page(&what, Some(&session), body)).into_response())
}

/// The controller's file name made safe for a download: letters, digits,
/// `_`, `-` and `.`, not starting with a dot.
pub(super) fn attachment_name(file_name: &str) -> String {
    let safe: String = file_name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let safe = safe.trim_start_matches('.');
    if safe.is_empty() {
        "program.txt".to_string()
    } else {
        safe.to_string()
    }
}

/// `GET …/versions/{seq}/download`: the version's text as a file named as
/// the controller stores it.
pub(super) async fn download(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((machine, name, seq)): Path<(String, String, String)>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let seq = seq_of(&session, "seq", &seq)?;
    on_the_bus(&web, &session, &machine).await?;
    let what = format!("{name} at {machine}, version {seq}");
    let t = answered(
        &session,
        &what,
        store::version(&web.bus, &machine, name, seq).await,
    )?;
    let disposition = format!(
        "attachment; filename=\"{}\"",
        attachment_name(&t.version.file_name)
    );
    Ok((
        [
            (
                header::CONTENT_TYPE,
                "text/plain; charset=utf-8".to_string(),
            ),
            (header::CONTENT_DISPOSITION, disposition),
            (header::X_CONTENT_TYPE_OPTIONS, "nosniff".to_string()),
        ],
        t.text,
    )
        .into_response())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_header_of_each_dialect_names_template_cases_and_generator() {
        // The first lines of tests/golden/spur_840d.H01.nc and of
        // helical_climb_fanuc.H02.nc, die_m2z20_3b.3b.
        let sinumerik = "%_N_SP_1001_MPF\n;$PATH=/_N_MPF_DIR\n; JOB TEST-1\n\
            ; SUBMITTED 1970-01-01 00:00:00 UTC BY test\n; TEMPLATE cylindrical_840d VERSION 7\n\
            ; CASES SEED-CASE-M3 SEED-CASE-M4\n; MODEL gearcam-model 0.1.0\n; GENERATOR gearcam-template 0.1.0\n\
            N10 G71 G90 ; METRIC\n";
        let p = provenance(sinumerik);
        assert_eq!(p.template.as_deref(), Some("cylindrical_840d VERSION 7"));
        assert_eq!(p.cases.as_deref(), Some("SEED-CASE-M3 SEED-CASE-M4"));
        assert_eq!(p.generator.as_deref(), Some("gearcam-template 0.1.0"));
        assert_eq!(
            p.submitted.as_deref(),
            Some("1970-01-01 00:00:00 UTC BY test")
        );
        let fanuc = "%\nO2108 (2108 HOBBING)\n(TEMPLATE CYLINDRICAL_FANUC VERSION 5)\n(CASES SEED-QT-M3)\n(GENERATOR GEARCAM-TEMPLATE 0.1.0)\n";
        let p = provenance(fanuc);
        assert_eq!(p.template.as_deref(), Some("CYLINDRICAL_FANUC VERSION 5"));
        assert_eq!(p.cases.as_deref(), Some("SEED-QT-M3"));
        let wire = "; PROGRAM PD-2001 JOB TEST-1\n; gearcam-model 0.1.0 gearcam-template 0.1.0\n";
        let p = provenance(wire);
        assert_eq!(
            p.generator.as_deref(),
            Some("gearcam-model 0.1.0 gearcam-template 0.1.0")
        );
        assert_eq!(p.template, None);
    }

    #[test]
    fn a_download_name_has_no_path_and_no_quote() {
        assert_eq!(attachment_name("_N_SP_1001_MPF"), "_N_SP_1001_MPF");
        assert_eq!(attachment_name("PD-2001.4b"), "PD-2001.4b");
        assert_eq!(attachment_name("../../etc/x\"y"), "_.._etc_x_y");
        assert_eq!(attachment_name("..."), "program.txt");
    }

    #[test]
    fn a_rollback_names_the_version_whose_text_it_made_current() {
        let v = |seq, sha: &str, state: &str| ProgramVersion {
            seq,
            name: "SP_1".into(),
            file_name: "_N_SP_1_MPF".into(),
            job: format!("J{seq}"),
            revision: 1,
            sha256: sha.into(),
            size_bytes: 1,
            stored_at_ms: seq,
            state: state.into(),
            current: false,
            part_number: "P".into(),
            by: if state == "stored" {
                String::new()
            } else {
                "operator".into()
            },
        };
        let versions = vec![
            v(3, "a", "rollback"),
            v(2, "b", "stored"),
            v(1, "a", "stored"),
        ];
        assert_eq!(
            made_by(&versions[0], &versions),
            "rolled back to version 1 by operator"
        );
        assert_eq!(
            made_by(&versions[1], &versions),
            "delivered by job J2 (revision 1)"
        );
    }
}
