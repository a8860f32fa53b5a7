//! A job's picture and program on its page, read over the bus like
//! everything else the page shows:
//!
//! - `GET /jobs/{job}/picture.svg`: the job's model from the station's
//!   journal (`gearcam/v1/station/jobs/{job}/model`, the message the model
//!   service published), drawn by the functions `gearcam check` draws with:
//!   a hobbing job's set-up and path ([`crate::check::hobbing_svg`]), a
//!   spiral face's region, swept band, path and gaps
//!   ([`crate::check::spiral_picture`]), a wire die's tooth space and whole
//!   part ([`crate::check::die_drawings`], the die made again from the
//!   model's plan as `gearcam check` makes it). Served as
//!   `image/svg+xml` under a policy that lets nothing in it run; every
//!   text in it is a number or escaped by the `svg` crate.
//! - `GET /jobs/{job}/simulation.svg`: the measuring charts of each gear a
//!   delivered hobbing program cuts on the virtual machine (the stored
//!   program read back against the journaled model and run as the template
//!   service runs it before delivery; seconds), drawn as `gearcam check
//!   --simulate` draws them; shown when the planner opens them on the page.
//! - `GET /jobs/{job}/program`: the program as the machine's agent stored
//!   it for the job (its store's version with the job's id and the
//!   receipt's SHA-256, as `gearcam program show` reads it), header and
//!   certificate lines included, in a `<pre>`; `GET
//!   /jobs/{job}/program.txt` downloads it under its file name.
//! - [`section`]: what the job's page shows of them, the picture in a
//!   `div.zoomable` that `/static/zoom.js` ([`zoom_script`]) lets the user
//!   zoom and pan.

use axum::extract::{Path, State};
use axum::http::{header, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Extension, Router};
use gearcam_bus::query::{CallError, Retry};
use gearcam_proto::codec::kind_of;
use gearcam_proto::{
    decode, keys, AnyModel, Code, Incoming, JobError, JobId, JobState, JobStatus, Message,
    ProgramText, StationReply,
};
use maud::{html, Markup};
use sha2::{Digest, Sha256};

use super::auth::Session;
use super::{page, trouble, unreachable, Page, Web};
use crate::station;

/// The pictures' and programs' routes.
pub(super) fn routes() -> Router<Web> {
    Router::new()
        .route("/jobs/{job}/picture.svg", get(picture))
        .route("/jobs/{job}/simulation.svg", get(simulation_picture))
        .route("/jobs/{job}/program", get(program_page))
        .route("/jobs/{job}/program.txt", get(program_file))
}

/// `GET /static/zoom.js`: the zoom and pan of the pictures.
pub(super) async fn zoom_script() -> impl IntoResponse {
    (
        [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
        ZOOM_SCRIPT,
    )
}

/// The pictures' script: zoom with the wheel and buttons, pan by dragging.
const ZOOM_SCRIPT: &str = include_str!("zoom.js");

/// What the pictures look like on the page (no quotes: maud escapes them).
const PICTURE_STYLE: &str =
    ".zoomable{border:1px solid #ccc;overflow:auto;max-width:100%;max-height:80vh;background:#fff}\
.zoomable img{display:block;max-width:100%;height:auto}\
.zoom-tools{margin:.3rem 0}.zoom-tools button{margin-right:.3rem}\
.charts{overflow:auto;max-width:100%;background:#fff}.charts img{display:block;max-width:100%;height:auto}";

/// The job page's picture and the links to its program: the picture for
/// every job that may have a model (one not yet planned has none), and the
/// program's links once it is delivered.
pub(super) fn section(s: &JobStatus) -> Markup {
    let modelled = !matches!(s.state, JobState::Accepted | JobState::Planned);
    html! {
        style { (PICTURE_STYLE) }
        h2 { "Picture" }
        @if modelled {
            div.zoomable #picture {
                img src=(format!("/jobs/{}/picture.svg", s.job))
                    alt=(format!("The picture of job {}: none while the station has no model of the job.", s.job));
            }
        } @else {
            p.no-picture { "The picture is drawn from the job's model, once the model service has computed it (reload the page then)." }
        }
        @if s.program.is_some() {
            details #simulation {
                summary { "Virtual hobbing: the measuring charts of the gear the program cuts" }
                div.charts {
                    img loading="lazy" src=(format!("/jobs/{}/simulation.svg", s.job))
                        alt=(format!("The charts of job {}: only a hobbing program of one cylindrical gear is run on the virtual machine.", s.job));
                }
            }
        }
        @if let Some(p) = &s.program {
            h2 { "Program" }
            p #program-links {
                a href=(format!("/jobs/{}/program", s.job)) { "Program " code { (p.name) } " as delivered" }
                " · "
                a href=(format!("/jobs/{}/program.txt", s.job)) download { "download" }
            }
        }
    }
}

/// A job id from the path, or the page that says it is none.
fn job_id(raw: &str, session: Option<&Session>) -> Result<JobId, Page> {
    JobId::new(raw).map_err(|e| {
        (
            StatusCode::NOT_FOUND,
            page(
                "No such job",
                session,
                html! { h1 { "No such job" } p { "Not a job id: " code { (raw) } " (" (e.to_string()) ")" } },
            ),
        )
    })
}

/// The job's model from the station's journal.
async fn model(web: &Web, job: &JobId) -> Result<AnyModel, Page> {
    let bytes = match web
        .bus
        .call_bytes(&keys::station_job_model(job), None, Retry::default())
        .await
    {
        Ok(bytes) => bytes,
        Err(e @ CallError::NoReply { .. }) => return Err(unreachable(&e.to_string())),
        Err(e) => return Err(undecodable(job, &e.to_string())),
    };
    if kind_of(&bytes, AnyModel::KINDS).is_ok_and(|k| k == StationReply::KIND) {
        let errors = match decode::<StationReply>(&bytes) {
            Ok(StationReply::Refused { errors }) => errors,
            Ok(other) => return Err(undecodable(job, &format!("{other:?}"))),
            Err(e) => return Err(undecodable(job, &e.to_string())),
        };
        let status = super::refusal_status(&errors);
        return Err(trouble(status, &format!("the model of job {job}"), &errors));
    }
    let model = AnyModel::decode_incoming(&bytes).map_err(|e| undecodable(job, &e.to_string()))?;
    if model.job_id() != job {
        let got = format!("the model of job {}", model.job_id());
        return Err(undecodable(job, &got));
    }
    Ok(model)
}

/// The page for a station's answer that is not the job's model.
fn undecodable(job: &JobId, got: &str) -> Page {
    let error = JobError::new(
        gearcam_proto::Stage::Station,
        Code::UNEXPECTED_REPLY,
        "reply",
        format!("the model of job {job} (machining_model, spiral_model or wire_model)"),
        got,
        "the station answered the model view with something else; is it another version?",
    );
    trouble(
        StatusCode::BAD_GATEWAY,
        &format!("the model of job {job}"),
        &[error],
    )
}

/// The SVG picture of a model of any family, drawn as `gearcam check`
/// draws it: a wire die is made again from its plan first (the model
/// carries the die's figures, not its outline).
fn svg_of(model: &AnyModel) -> Result<String, String> {
    match model {
        AnyModel::Hobbing(m) => Ok(crate::check::hobbing_svg(m)),
        AnyModel::Spiral(m) => Ok(crate::check::spiral_picture(m)),
        AnyModel::Wire(m) => {
            let made = gearcam_model::wire::made(&m.plan).map_err(|errors| {
                errors
                    .iter()
                    .map(|e| format!("{} {}: {}", e.code, e.field, e.message))
                    .collect::<Vec<_>>()
                    .join("; ")
            })?;
            crate::check::die_drawings(m, &made).map(|(svg, _)| svg)
        }
    }
}

/// The job named in the path and its model, or the page that says why not.
async fn job_and_model(web: &Web, session: &Session, job: &str) -> Result<(JobId, AnyModel), Page> {
    let id = job_id(job, Some(session))?;
    let model = model(web, &id).await?;
    Ok((id, model))
}

/// `GET /jobs/{job}/picture.svg`: the job's picture, drawn from its model.
async fn picture(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(job): Path<String>,
) -> Result<Response, Page> {
    let (id, model) = job_and_model(&web, &session, &job).await?;
    // Drawing a die fits its arcs again: off the page's threads.
    let drawn = tokio::task::spawn_blocking(move || svg_of(&model))
        .await
        .map_err(|e| e.to_string())
        .and_then(|svg| svg.map_err(|why| why.to_string()));
    Ok(match drawn {
        Ok(svg) => svg_response(svg),
        Err(why) => (
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the picture of job {id} cannot be drawn: {why}"),
        )
            .into_response(),
    })
}

/// An SVG picture as the page serves it.
fn svg_response(svg: String) -> Response {
    let mut response = svg.into_response();
    let headers = response.headers_mut();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("image/svg+xml"),
    );
    // Opened on its own, the picture is a document: nothing in it may run
    // or load.
    headers.insert(
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static("default-src 'none'; style-src 'unsafe-inline'"),
    );
    headers.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        HeaderValue::from_static("nosniff"),
    );
    response
}

/// The measuring charts of each gear a hobbing program cuts on the virtual
/// machine: the program's text read back against the job's model and run
/// as the template service runs it before delivery, drawn as `gearcam
/// check --simulate` draws them.
fn simulation_svg_of(model: &AnyModel, text: &str) -> Result<String, String> {
    let AnyModel::Hobbing(m) = model else {
        return Err("only hobbing programs are run on the virtual machine".into());
    };
    if let Some(why) = gearcam_template::simulation::out_of_scope(m) {
        return Err(why.into());
    }
    let (_, trace) = gearcam_nc::check(text, m);
    let settings = gearcam_template::simulation::before_delivery();
    let (report, gears) = gearcam_template::simulation::run(&trace, m, &settings);
    if gears.is_empty() {
        return Err(format!(
            "the program cannot be run on the virtual machine: {}",
            report.not_measured.unwrap_or_default()
        ));
    }
    crate::check::picture_simulation::simulation_svg(&gears)
        .ok_or_else(|| "no gear the program cuts could be measured, so there are no charts".into())
}

/// `GET /jobs/{job}/simulation.svg`: the measuring charts of each gear the
/// job's delivered program cuts on the virtual machine ([`simulation_svg_of`]
/// on the program as the machine's agent stored it). A run takes seconds.
async fn simulation_picture(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(job): Path<String>,
) -> Result<Response, Page> {
    let (id, model) = job_and_model(&web, &session, &job).await?;
    let text = delivered(&web, &id).await?.1.text;
    let drawn = tokio::task::spawn_blocking(move || simulation_svg_of(&model, &text)).await;
    Ok(match drawn {
        Ok(Ok(svg)) => svg_response(svg),
        Ok(Err(why)) => (
            StatusCode::NOT_FOUND,
            format!("no virtual hobbing charts for job {id}: {why}"),
        )
            .into_response(),
        Err(e) => (
            StatusCode::INTERNAL_SERVER_ERROR,
            format!("the charts of job {id} cannot be drawn: {e}"),
        )
            .into_response(),
    })
}

/// The program the machine's agent stored for the job: its status and
/// the stored version with its text, whose SHA-256 is the receipt's.
async fn delivered(web: &Web, job: &JobId) -> Result<(JobStatus, ProgramText), Page> {
    let s = match station::status(&web.bus, job).await {
        Ok(Ok(s)) => s,
        Ok(Err(errors)) => {
            return Err(trouble(
                super::refusal_status(&errors),
                &format!("job {job}"),
                &errors,
            ))
        }
        Err(e) => return Err(unreachable(&e.to_string())),
    };
    let Some(p) = s.program.clone() else {
        let body = html! {
            h1 { "No program yet" }
            p { "Job " code { (job) } " is " (s.state.as_str()) "; its program shows here once the machine's agent has stored it." }
            p { a href=(format!("/jobs/{job}")) { "← job " (job) } }
        };
        return Err((StatusCode::NOT_FOUND, page("No program yet", None, body)));
    };
    let asking = |e: CallError| unreachable(&format!("the agent of machine {}: {e}", s.machine));
    let refused = |e: JobError| {
        trouble(
            StatusCode::BAD_GATEWAY,
            &format!("the program of job {job}"),
            &[e],
        )
    };
    let history = crate::store::history(&web.bus, &s.machine, Some(&p.name))
        .await
        .map_err(asking)?
        .map_err(refused)?;
    // The version the job stored: its id and the receipt's hash (a
    // rollback to it later is another version with the same text).
    let version = history
        .versions
        .iter()
        .filter(|v| v.sha256 == p.sha256)
        .min_by_key(|v| (v.job != job.as_str(), v.seq))
        .ok_or_else(|| {
            let got = format!(
                "program {} at {} without sha256 {}",
                p.name, s.machine, p.sha256
            );
            refused(not_stored(
                Code::UNKNOWN_VERSION,
                "the version the job stored in the agent's store",
                &got,
                format!(
                    "the store of machine {} no longer holds the version job {job} stored",
                    s.machine
                ),
            ))
        })?;
    let text = crate::store::version(&web.bus, &s.machine, &p.name, version.seq)
        .await
        .map_err(asking)?
        .map_err(refused)?;
    let sha = hex::encode(Sha256::digest(text.text.as_bytes()));
    if sha != p.sha256 {
        let got = format!("a text with sha256 {sha}");
        return Err(refused(not_stored(
            Code::HASH_MISMATCH,
            &format!(
                "the text with sha256 {}, as the delivery receipt says",
                p.sha256
            ),
            &got,
            format!(
                "the agent of machine {} answered another text for job {job}'s program",
                s.machine
            ),
        )));
    }
    Ok((s, text))
}

/// The error of a program the agent's store does not give as delivered.
fn not_stored(code: Code, expected: &str, got: &str, message: String) -> JobError {
    JobError::new(
        gearcam_proto::Stage::Agent,
        code,
        "program",
        expected,
        got,
        message,
    )
}

/// `GET /jobs/{job}/program`: the program as delivered.
async fn program_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(job): Path<String>,
) -> Page {
    let id = match job_id(&job, Some(&session)) {
        Ok(id) => id,
        Err(page) => return page,
    };
    let (s, t) = match delivered(&web, &id).await {
        Ok(found) => found,
        Err(page) => return page,
    };
    let v = &t.version;
    let body = html! {
        p { a href=(format!("/jobs/{}", s.job)) { "← job " (s.job) } }
        h1 { "Program " (v.name) }
        dl #program-facts {
            dt { "job" } dd { (s.job) }
            dt { "part number" } dd { (s.part_number) }
            dt { "machine" } dd { (s.machine) }
            dt { "file" } dd { code { (v.file_name) } }
            dt { "version" } dd { (v.seq) " (" (v.state) (if v.current { ", current" } else { "" }) ")" }
            dt { "stored" } dd { (gearcam_proto::utc_text(v.stored_at_ms)) }
            dt { "sha256" } dd { code { (v.sha256) } " — the text below has it, as the delivery receipt says" }
            dt { "size" } dd { (v.size_bytes) " bytes" }
            dt { "checked" } dd { "by the agent against the job's model before it stored the program" }
        }
        p { a #download href=(format!("/jobs/{}/program.txt", s.job)) download { "Download " code { (v.file_name) } } }
        pre.program #program { (t.text) }
    };
    (
        StatusCode::OK,
        page(&format!("Program {}", v.name), Some(&session), body),
    )
}

/// A file name safe in a `Content-Disposition` header: the stored file's
/// name with anything but letters, digits, `.`, `_` and `-` written `_`.
fn file_name(name: &str) -> String {
    let safe: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-') {
                c
            } else {
                '_'
            }
        })
        .collect();
    if safe.is_empty() {
        "program.txt".into()
    } else {
        safe
    }
}

/// `GET /jobs/{job}/program.txt`: the program as delivered, as a file.
async fn program_file(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path(job): Path<String>,
) -> Response {
    let id = match job_id(&job, Some(&session)) {
        Ok(id) => id,
        Err(page) => return page.into_response(),
    };
    let (_, t) = match delivered(&web, &id).await {
        Ok(found) => found,
        Err(page) => return page.into_response(),
    };
    let disposition = format!(
        "attachment; filename=\"{}\"",
        file_name(&t.version.file_name)
    );
    let mut response = t.text.into_response();
    let headers = response.headers_mut();
    headers.insert(
        header::CONTENT_TYPE,
        HeaderValue::from_static("text/plain; charset=utf-8"),
    );
    if let Ok(v) = HeaderValue::from_str(&disposition) {
        headers.insert(header::CONTENT_DISPOSITION, v);
    }
    response
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::{check, Drawing};
    use gearcam_template::Templates;

    /// The model of an example as `gearcam check` computes it, with its
    /// part number replaced by `part`.
    fn model_of(example: &str, part: &str) -> AnyModel {
        let text = gearcam_testkit::examples::example(example);
        let mut spec = crate::jobfile::parse(&text, example).unwrap();
        spec.job.part_number = part.into();
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let (report, drawing) = check(
            &conn,
            &Templates::builtin(),
            &crate::jobfile::request(spec),
            None,
        );
        match drawing {
            Some(Drawing::Hobbing(m, _)) => AnyModel::Hobbing(m),
            Some(Drawing::Spiral(m)) => AnyModel::Spiral(m),
            Some(Drawing::Wire(m, _)) => AnyModel::Wire(m),
            None => panic!("{example}: no model: {:?}", report.errors),
        }
    }

    /// The charts of the gear a hobbing program cuts are drawn from the
    /// program's text and the job's model; a spiral job, and a program cut
    /// short before its cutting moves, have none and say why.
    #[test]
    fn a_hobbing_programs_charts_are_drawn_from_its_text() {
        let model = model_of("spur_840d.toml", "SP-1");
        let AnyModel::Hobbing(m) = &model else {
            panic!("spur_840d is a hobbing job")
        };
        let program = Templates::builtin().render(m).expect("renders");
        let svg = simulation_svg_of(&model, &program.text).expect("charts");
        assert!(svg.starts_with("<svg"), "{svg}");
        assert!(svg.contains("Profile, middle section"), "{svg}");
        let spiral = model_of("face_annulus_fanuc.toml", "F-1");
        let why = simulation_svg_of(&spiral, "").unwrap_err();
        assert!(why.contains("only hobbing"), "{why}");
        let short: Vec<&str> = program.text.lines().take(8).collect();
        let why = simulation_svg_of(&model, &short.join("\n")).unwrap_err();
        assert!(
            why.contains("cannot be run") || why.contains("no charts"),
            "{why}"
        );
    }

    /// The page draws each family's model as `gearcam check` does, and a
    /// part number with a script in it is text in every picture, never an
    /// element.
    #[test]
    fn every_family_is_drawn_and_a_script_in_a_part_number_is_text() {
        let script = "<script>alert(1)</script>";
        for (example, family) in [
            ("spur_840d.toml", "hobbing"),
            ("face_annulus_fanuc.toml", "spiral"),
            ("die_m1z40_iso.toml", "wire"),
        ] {
            let model = model_of(example, script);
            let svg = svg_of(&model).unwrap();
            assert!(svg.starts_with("<svg"), "{family}");
            assert!(!svg.contains("<script"), "{family}: {svg}");
            match family {
                // The spiral's picture names no part.
                "spiral" => {}
                _ => assert!(svg.contains("&lt;script&gt;"), "{family}: no part number"),
            }
        }
    }

    #[test]
    fn a_download_name_is_only_safe_characters() {
        assert_eq!(file_name("_N_SP_1001_MPF"), "_N_SP_1001_MPF");
        assert_eq!(file_name("a\"; b\r\n.nc"), "a___b__.nc");
        assert_eq!(file_name(""), "program.txt");
    }
}
