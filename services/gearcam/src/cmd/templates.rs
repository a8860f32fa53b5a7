//! `gearcam templates analyze|import|list|show`: the standard module library
//! (docs/programs.md#standard-templates) from the command line, on `{data}/templates.db`.
//!
//! `analyze` and `import` read every `*.tpl` file of a directory, or by
//! default the shipped standard code compiled into the binary
//! (`services/template/standard`).
//!
//! Exit codes: 0 done, 1 refused (a template that does not parse, a changed
//! template whose `@version` was not bumped, an unknown template; every error
//! names the file, the line, what was expected and what was given), 2 the
//! database or a directory could not be opened.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Subcommand};
use gearcam_template::builtin::builtin_sources;
use gearcam_template::forms::generated;
use gearcam_template::library::{Library, LibraryError, TemplateSummary};
use gearcam_template::similarity::analyze;
use gearcam_template::stdcode::{self, TemplateFile};
use serde::Serialize;

/// `gearcam templates`: the standard module library of template versions.
#[derive(Debug, Args)]
pub struct TemplatesArgs {
    /// Data directory holding the template library (`templates.db`, created if missing).
    #[arg(
        long,
        env = "GEARCAM_DATA",
        default_value = "gearcam-data",
        global = true
    )]
    pub data: PathBuf,
    /// Print JSON.
    #[arg(long, global = true)]
    pub json: bool,
    #[command(subcommand)]
    pub command: TemplatesCommand,
}

/// A `gearcam templates` command.
#[derive(Debug, Subcommand)]
pub enum TemplatesCommand {
    /// Compare the classes' standard code line by line (Sim = K/(M+N−K)) per
    /// dialect and module: which lines are shared, what storing them once saves.
    Analyze {
        /// Directory of `*.tpl` template sources (default: the shipped standard code).
        dir: Option<PathBuf>,
    },
    /// Store the template sources in the library: changed ones as a new
    /// version (their `@version` must be higher), unchanged ones are skipped.
    Import {
        /// Directory of `*.tpl` template sources (default: the shipped standard code).
        dir: Option<PathBuf>,
    },
    /// Every template in the library with its latest version, then the
    /// program forms written by code (spiral and wire families).
    List,
    /// A template's decision table ((ID, P, S, T, N), (O)), or what a form
    /// written by code writes and what checks it.
    Show {
        /// Template id, e.g. cylindrical_840d or spiral-fanuc-macro.
        id: String,
        /// The version (default: the latest).
        #[arg(long)]
        version: Option<u32>,
    },
}

/// Runs a `gearcam templates` command.
pub fn run(args: TemplatesArgs) -> ExitCode {
    let json = args.json;
    let result = match args.command {
        TemplatesCommand::Analyze { dir } => read_and_parse(dir.as_deref()).and_then(|set| {
            let files: Vec<TemplateFile> = set.into_iter().map(|s| s.file).collect();
            print(json, &analyze(&files))
        }),
        TemplatesCommand::Import { dir } => import(&args.data, dir.as_deref(), json),
        // The library's templates, then the forms written by code (the
        // spiral and wire families), which programs name the same way.
        TemplatesCommand::List => open(&args.data).and_then(|lib| match lib.list() {
            Ok(list) if json => {
                let mut all = serde_json::to_value(&list)
                    .map_err(|e| unavailable(format!("cannot write JSON: {e}")))?;
                if let Some(all) = all.as_array_mut() {
                    all.extend(
                        generated()
                            .into_iter()
                            .filter_map(|f| serde_json::to_value(f).ok()),
                    );
                }
                print_json(&all)
            }
            Ok(list) => emit(&(list_table(&list) + "\n" + &generated_table(&generated()))),
            Err(e) => Err(refusal(e, None)),
        }),
        TemplatesCommand::Show { id, version } => match gearcam_template::forms::find(&id) {
            Some(form) if version.is_none_or(|v| v == form.version) => {
                if json {
                    print_json(&form)
                } else {
                    emit(&format!(
                        "{} version {} (family {}, {}), written by gearcam's code, not a template of the library\n  writes {}\n  checked by {}\n",
                        form.id,
                        form.version,
                        form.family,
                        form.dialect.as_str(),
                        form.writes,
                        form.checked_by
                    ))
                }
            }
            Some(form) => Err(Failure {
                code: crate::exit::NOT_FOUND,
                message: format!(
                    "{} has only version {} (it is written by gearcam's code)",
                    form.id, form.version
                ),
            }),
            None => open(&args.data).and_then(|lib| match lib.show(&id, version) {
                Ok(table) => print(json, &table),
                Err(e) => Err(refusal(e, None)),
            }),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure { code, message }) => {
            crate::output::fail(code, &[], &format!("gearcam: {message}"))
        }
    }
}

/// A command that did not succeed: the exit code and what to tell the user.
struct Failure {
    code: u8,
    message: String,
}

fn refused(message: String) -> Failure {
    Failure { code: 1, message }
}

fn unavailable(message: String) -> Failure {
    Failure { code: 2, message }
}

/// A library error as a failure: refusals exit 1, a database that cannot be
/// used exits 2. `files` names the source file of a template when known.
fn refusal(e: LibraryError, files: Option<&[Source]>) -> Failure {
    let file = |id: &str| {
        files
            .and_then(|fs| fs.iter().find(|s| s.file.id == id))
            .map(|s| format!("{}: ", s.name))
            .unwrap_or_default()
    };
    match &e {
        LibraryError::VersionNotBumped { id, .. }
        | LibraryError::VersionBehind { id, .. }
        | LibraryError::NotItsSource { id, .. }
        | LibraryError::Duplicate { id } => refused(format!("{}{e}", file(id))),
        LibraryError::NotFound { .. } => Failure {
            code: crate::exit::NOT_FOUND,
            message: e.to_string(),
        },
        _ => unavailable(e.to_string()),
    }
}

fn print<T: Serialize + std::fmt::Display>(json: bool, value: &T) -> Result<(), Failure> {
    if json {
        print_json(value)
    } else {
        emit(&value.to_string())
    }
}

/// Writes to stdout. A reader that stops early (`| head`) is not an error.
fn emit(text: &str) -> Result<(), Failure> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(unavailable(format!("cannot write to stdout: {e}")))
        }
        _ => Ok(()),
    }
}

fn print_json<T: Serialize + ?Sized>(value: &T) -> Result<(), Failure> {
    let text = serde_json::to_string_pretty(value)
        .map_err(|e| unavailable(format!("cannot write JSON: {e}")))?;
    emit(&(text + "\n"))
}

fn open(data: &Path) -> Result<Library, Failure> {
    let data = &crate::data_dir::absolute(data);
    eprintln!("gearcam: data directory {}", data.display());
    crate::data_dir::writable(data).map_err(|e| {
        unavailable(format!(
            "{}; {}",
            e.message,
            crate::data_dir::NOT_WRITABLE_HINT
        ))
    })?;
    Library::open(&data.join("templates.db")).map_err(|e| {
        unavailable(format!(
            "cannot open the template library in {}: {e}",
            data.display()
        ))
    })
}

/// A template source read and parsed: where it came from, its text, the file.
struct Source {
    name: String,
    text: String,
    file: TemplateFile,
}

/// Reads and parses every `*.tpl` of `dir`, or the shipped standard code.
/// Every file that does not parse is reported, not only the first.
fn read_and_parse(dir: Option<&Path>) -> Result<Vec<Source>, Failure> {
    let texts: Vec<(String, String)> = match dir {
        None => builtin_sources()
            .into_iter()
            .map(|(name, text)| (format!("standard/{name}"), text.to_string()))
            .collect(),
        Some(dir) => read_dir(dir)?,
    };
    if texts.is_empty() {
        let place = dir.map_or("the shipped standard code".to_string(), |d| {
            d.display().to_string()
        });
        return Err(refused(format!(
            "expected template sources (*.tpl) in {place}, found none"
        )));
    }
    let mut errors = Vec::new();
    let mut out: Vec<Source> = Vec::new();
    for (name, text) in texts {
        match stdcode::parse(&name, &text) {
            Ok(file) => {
                if let Some(first) = out.iter().find(|s| s.file.id == file.id) {
                    errors.push(format!(
                        "{name}: expected one file per template, got template {} again (first in {})",
                        file.id, first.name
                    ));
                    continue;
                }
                out.push(Source { name, text, file });
            }
            Err(e) => errors.push(e.to_string()),
        }
    }
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(refused(format!(
            "{} template file(s) refused:\n  {}",
            errors.len(),
            errors.join("\n  ")
        )))
    }
}

/// Every `*.tpl` file of `dir` (not recursively), sorted by name.
fn read_dir(dir: &Path) -> Result<Vec<(String, String)>, Failure> {
    let cannot = |e: std::io::Error| {
        unavailable(format!(
            "cannot read the template directory {}: {e}",
            dir.display()
        ))
    };
    let mut paths: Vec<PathBuf> = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(cannot)? {
        let path = entry.map_err(cannot)?.path();
        if path.is_file() && path.extension().is_some_and(|e| e == "tpl") {
            paths.push(path);
        }
    }
    paths.sort();
    paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).map_err(|e| {
                unavailable(format!("cannot read template source {}: {e}", p.display()))
            })?;
            Ok((p.display().to_string(), text))
        })
        .collect()
}

fn import(data: &Path, dir: Option<&Path>, json: bool) -> Result<(), Failure> {
    let sources = read_and_parse(dir)?;
    let mut lib = open(data)?;
    let files: Vec<TemplateFile> = sources.iter().map(|s| s.file.clone()).collect();
    let texts: Vec<&str> = sources.iter().map(|s| s.text.as_str()).collect();
    let report = lib
        .import(&files, &texts, gearcam_proto::now_ms())
        .map_err(|e| refusal(e, Some(&sources)))?;
    if !json {
        emit(&format!(
            "template library {}\n",
            data.join("templates.db").display()
        ))?;
    }
    print(json, &report)
}

/// The library as a table, one line per template.
/// The forms written by code, as a table.
fn generated_table(forms: &[gearcam_template::forms::GeneratedForm]) -> String {
    let mut out = String::from(
        "program forms written by gearcam's code (not in the library; versioned with gearcam):\n",
    );
    let w = forms.iter().map(|f| f.id.len()).max().unwrap_or(0);
    for f in forms {
        out.push_str(&format!(
            "{:<w$}  {:<11}  {:<13}  v{}\n",
            f.id,
            f.family,
            f.dialect.as_str(),
            f.version
        ));
    }
    out
}

fn list_table(list: &[TemplateSummary]) -> String {
    if list.is_empty() {
        return "the template library is empty; store the standard code with \
                `gearcam templates import`\n"
            .to_string();
    }
    let head = [
        "template",
        "class",
        "dialect",
        "current",
        "stored versions",
        "records",
        "similar",
        "own",
        "imported",
    ];
    let rows: Vec<[String; 9]> = list
        .iter()
        .map(|t| {
            let versions: Vec<String> = t.versions.iter().map(|v| format!("v{v}")).collect();
            [
                t.id.clone(),
                t.class.clone(),
                t.dialect.as_str().to_string(),
                format!("v{}", t.version),
                versions.join(" "),
                t.records.to_string(),
                t.similar.to_string(),
                t.non_similar.to_string(),
                crate::output::utc(t.imported_at_ms),
            ]
        })
        .collect();
    let mut widths: Vec<usize> = head.iter().map(|h| h.len()).collect();
    for row in &rows {
        for (w, c) in widths.iter_mut().zip(row) {
            *w = (*w).max(c.len());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (i, (c, w)) in cells.iter().zip(&widths).enumerate() {
            if (5..8).contains(&i) {
                s.push_str(&format!("{c:>w$}  "));
            } else {
                s.push_str(&format!("{c:<w$}  "));
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(&head.map(String::from));
    for row in &rows {
        out.push_str(&line(row));
    }
    out.push_str(&format!("({} templates)\n", list.len()));
    out
}
