//! `gearcam check`: the job computed locally, no bus.

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

pub fn check(job: &Path, json: bool, data: &Path) -> ExitCode {
    let report = match jobfile::load(job) {
        Err(e) => CheckReport::failed(vec![e]),
        Ok(spec) => {
            let req = jobfile::request(spec);
            match gearcam_knowledge::db::open(&data.join("knowledge.db")) {
                Ok(conn) => match template_library(data) {
                    Ok(templates) => check::check(&conn, &templates, &req),
                    Err(e) => check::CheckReport::failed(vec![gearcam_proto::JobError {
                        stage: gearcam_proto::Stage::Template,
                        code: "TEMPLATE_LIBRARY_UNREADABLE".into(),
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
    if report.ok {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
