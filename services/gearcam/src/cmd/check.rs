//! `gearcam check`: the job computed locally, no bus.

use gearcam_proto::Code;
use std::path::Path;
use std::process::ExitCode;

use gearcam_template::Templates;

use crate::check::{self, CheckReport};
use crate::jobfile;

/// The template library of the data directory (`templates.db`), with the
/// shipped standard code imported where it is newer.
pub fn template_library(data: &Path) -> anyhow::Result<Templates> {
    Ok(Templates::from_library(
        &data.join("templates.db"),
        gearcam_template::DEFAULT_FUEL,
        gearcam_proto::now_ms(),
    )?)
}

/// Where the picture of a job goes by default: `DATA/pictures/STEM.svg`, STEM the job file's name without `.toml`.
fn default_picture(job: &Path, data: &Path) -> std::path::PathBuf {
    let stem = job
        .file_stem()
        .map_or("job".into(), |s| s.to_string_lossy().into_owned());
    data.join("pictures").join(format!("{stem}.svg"))
}

/// Writes `bytes` to `path`, making its folder; the path written, or an
/// error line.
fn write_file(path: &Path, bytes: &[u8]) -> Result<String, String> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(path.display().to_string())
}

/// Writes the picture of a hobbing, spiral or wire model to `svg`, and a
/// wire job's outline as DXF to `dxf`.
fn write_drawings(model: &crate::check::Drawing, report: &mut CheckReport, svg: &Path, dxf: &Path) {
    if let crate::check::Drawing::Hobbing(_, sims) = model {
        let stem = svg
            .file_stem()
            .map_or("job".into(), |s| s.to_string_lossy());
        let charts = svg.with_file_name(format!("{stem}-simulation.svg"));
        if let Some(doc) = check::picture_simulation::simulation_svg(sims) {
            match write_file(&charts, doc.as_bytes()) {
                Ok(p) => report.simulation_picture = Some(p),
                Err(e) => eprintln!("gearcam: cannot write the simulation's charts {e}"),
            }
        }
    }
    let files = match model {
        crate::check::Drawing::Hobbing(m, _) => Ok((check::hobbing_svg(m), None)),
        crate::check::Drawing::Spiral(m) => Ok((check::spiral_picture(m), None)),
        crate::check::Drawing::Wire(m, made) => {
            crate::check::die_drawings(m, made).map(|(svg, dxf)| (svg, Some(dxf)))
        }
    };
    match files {
        Ok((picture, outline)) => {
            match write_file(svg, picture.as_bytes()) {
                Ok(p) => report.picture = Some(p),
                Err(e) => eprintln!("gearcam: cannot write the picture {e}"),
            }
            if let Some(bytes) = outline {
                match write_file(dxf, &bytes) {
                    Ok(p) => report.drawing = Some(p),
                    Err(e) => eprintln!("gearcam: cannot write the DXF {e}"),
                }
            }
        }
        Err(e) => eprintln!("gearcam: cannot draw the job: {e}"),
    }
}

pub fn check(
    job: &Path,
    json: bool,
    data: &Path,
    simulation: Option<&gearcam_hobsim::simulate::Settings>,
    svg: Option<&Path>,
    dxf: Option<&Path>,
) -> ExitCode {
    let data = &match crate::data_dir::open(data) {
        Ok(data) => data,
        Err(code) => return code,
    };
    let report = match jobfile::load(job) {
        Err(e) => CheckReport::failed(vec![e]),
        Ok(spec) => {
            let req = jobfile::request(spec);
            if let Err(e) = jobfile::check_size(&req) {
                return finish(CheckReport::failed(vec![e]), json);
            }
            match gearcam_knowledge::db::open(&data.join("knowledge.db")) {
                Ok(conn) => match template_library(data) {
                    Ok(templates) => {
                        let (mut report, model) =
                            crate::check::check(&conn, &templates, &req, simulation);
                        if let Some(model) = model {
                            let svg =
                                svg.map_or_else(|| default_picture(job, data), Path::to_path_buf);
                            let dxf =
                                dxf.map_or_else(|| svg.with_extension("dxf"), Path::to_path_buf);
                            write_drawings(&model, &mut report, &svg, &dxf);
                        }
                        report
                    }
                    Err(e) => check::CheckReport::failed(vec![gearcam_proto::JobError {
                        stage: gearcam_proto::Stage::Template,
                        code: Code::TEMPLATE_LIBRARY_UNREADABLE,
                        field: "data".into(),
                        expected: "a readable template library (templates.db)".into(),
                        got: data.join("templates.db").display().to_string(),
                        message: format!("{e:#}"),
                    }]),
                },
                Err(e) => {
                    return crate::output::fail(
                        crate::exit::UNREACHABLE,
                        &[],
                        &format!(
                            "gearcam: cannot open the knowledge base in {}: {e}",
                            data.display()
                        ),
                    );
                }
            }
        }
    };
    finish(report, json)
}

/// Prints the report (JSON or for people) and gives the exit code: 0, or
/// the failure's, which the JSON carries as `exit`.
fn finish(mut report: CheckReport, json: bool) -> ExitCode {
    let code = if report.ok {
        0
    } else {
        crate::exit::for_errors(&report.errors)
    };
    if !report.ok {
        report.exit = Some(code);
    }
    if json {
        match serde_json::to_string_pretty(&report) {
            Ok(s) => crate::outln!("{s}"),
            Err(e) => {
                eprintln!("gearcam: cannot write JSON: {e}");
                return crate::exit::code(crate::exit::UNREACHABLE);
            }
        }
    } else {
        crate::out!("{}", check::format_human(&report));
    }
    crate::exit::code(code)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hobbing job's picture is written where asked and named in the
    /// report's `picture`, as a spiral job's or a die's is; it has no DXF.
    #[test]
    fn a_hobbing_jobs_picture_is_written_and_named_in_the_report() {
        let text = gearcam_testkit::examples::example("spur_840d.toml");
        let spec = jobfile::parse(&text, "spur_840d.toml").unwrap();
        let conn = gearcam_knowledge::db::open_in_memory().unwrap();
        let (mut report, drawing) =
            crate::check::check(&conn, &Templates::builtin(), &jobfile::request(spec), None);
        let dir = tempfile::tempdir().unwrap();
        let svg = dir.path().join("pictures").join("spur_840d.svg");
        let dxf = svg.with_extension("dxf");
        write_drawings(&drawing.expect("a model"), &mut report, &svg, &dxf);
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["picture"], svg.display().to_string());
        assert!(json.get("drawing").is_none() && !dxf.exists());
        let picture = std::fs::read_to_string(&svg).unwrap();
        assert!(picture.starts_with("<svg") && picture.contains("hob Ø80"));
    }
}
