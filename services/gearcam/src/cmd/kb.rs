//! `gearcam kb ...` and `gearcam confirm JOB ...`: the knowledge base's
//! libraries from the command line, on the database in the data directory
//! (the same file `gearcam up` serves; SQLite lets both work at once).
//!
//! Exit codes: 0 done, 1 refused (every error printed with field, expected
//! and got), 2 the database or a file could not be opened.

use gearcam_proto::Code;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Subcommand};
use gearcam_knowledge::library::{self, Library, Record};
use gearcam_knowledge::{csvio, db, learn};
use gearcam_proto::JobError;

use super::refused;
use gearcam_proto::Stage;
use serde_json::Value;

/// `gearcam kb`: list, show, add, edit, remove, import and export library records.
#[derive(Debug, Args)]
pub struct KbArgs {
    /// Data directory holding the knowledge base (created and seeded if missing).
    #[arg(
        long,
        env = "GEARCAM_DATA",
        default_value = "gearcam-data",
        global = true
    )]
    pub data: PathBuf,
    /// Print records as JSON.
    #[arg(long, global = true)]
    pub json: bool,
    #[command(subcommand)]
    pub command: KbCommand,
}

/// A `gearcam kb` command. LIBRARY is one of classes, workpieces, hobs,
/// machines, cases, jobs, materials, weights.
#[derive(Debug, Subcommand)]
pub enum KbCommand {
    /// The libraries and their fields (name, type, default, meaning).
    Libraries,
    /// Every change to the libraries, newest first: who, when, the record,
    /// the old and the new values (CLI, CSV import, confirmed jobs, the bus).
    Changes {
        /// At most this many.
        #[arg(long, default_value_t = 50)]
        limit: usize,
    },
    /// Every record of a library.
    List {
        /// The library.
        library: String,
    },
    /// One record, every field.
    Show {
        /// The library.
        library: String,
        /// The record's id (key).
        id: String,
    },
    /// Add a record: `--set field=value` for each field (defaults fill the rest).
    Add {
        /// The library.
        library: String,
        /// A field value, e.g. `--set module_mm=3` (repeat).
        #[arg(long = "set", value_name = "FIELD=VALUE")]
        set: Vec<String>,
        /// Or the whole record as a JSON file (machines: a complete profile).
        #[arg(long, value_name = "FILE.json")]
        from_json: Option<PathBuf>,
    },
    /// Change fields of a record: `--set field=value`, nested machine fields by
    /// dotted path (`--set limits.max_hob_rpm=1200`).
    Edit {
        /// The library.
        library: String,
        /// The record's id.
        id: String,
        /// A field value (repeat).
        #[arg(long = "set", value_name = "FIELD=VALUE", required = true)]
        set: Vec<String>,
    },
    /// Remove a record.
    Remove {
        /// The library.
        library: String,
        /// The record's id.
        id: String,
    },
    /// Import a CSV file (header row = field names); all rows or none.
    Import {
        /// workpieces, hobs, cases or materials.
        library: String,
        /// The CSV file.
        file: PathBuf,
    },
    /// Export a library as CSV (to stdout when no file is given).
    Export {
        /// workpieces, hobs, cases or materials.
        library: String,
        /// The CSV file to write.
        file: Option<PathBuf>,
    },
}

/// `gearcam confirm JOB`: after delivery, record the values actually used and
/// the outcome; the job becomes a case and its hob's shift and life move on.
#[derive(Debug, Args)]
pub struct ConfirmArgs {
    /// The job id (as planned by the knowledge service; `gearcam kb list jobs`).
    pub job: String,
    /// Data directory holding the knowledge base.
    #[arg(long, env = "GEARCAM_DATA", default_value = "gearcam-data")]
    pub data: PathBuf,
    /// Parts actually cut (default: the job's quantity).
    #[arg(long)]
    pub quantity: Option<u32>,
    /// Cutting speed actually used, m/min (default: the plan's).
    #[arg(long)]
    pub cutting_speed: Option<f64>,
    /// Feed actually used (default: the plan's): mm/rev for hobbing, mm per
    /// tooth for spiral face milling.
    #[arg(long)]
    pub feed: Option<f64>,
    /// Cuts actually made (default: the plan's); depth passes for spiral
    /// face milling.
    #[arg(long)]
    pub cuts: Option<u32>,
    /// Outcome of the cut (required): ok, rework, scrap or unknown.
    #[arg(long)]
    pub outcome: String,
    /// Accuracy grade measured.
    #[arg(long)]
    pub quality: Option<u8>,
    /// Remarks.
    #[arg(long, default_value = "")]
    pub notes: String,
    /// How far to trust the new case, 0–1.
    #[arg(long, default_value_t = 0.8)]
    pub confidence: f64,
    /// Who confirms (default: the login name, else `unknown`).
    #[arg(long)]
    pub by: Option<String>,
    /// Accept a job whose delivery the knowledge service did not hear.
    #[arg(long)]
    pub undelivered: bool,
    /// Print the new case as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Opens the knowledge base; the changes made through it are recorded as
/// the login user's (`gearcam_knowledge::audit`).
fn open(data: &Path) -> Result<rusqlite::Connection, ExitCode> {
    let conn = open_db(data)?;
    gearcam_knowledge::audit::acting_as(&conn, &crate::jobfile::user()).map_err(|e| {
        crate::output::fail(
            crate::exit::UNREACHABLE,
            &[],
            &format!(
                "gearcam: the knowledge base in {} cannot be written: {e}",
                data.display()
            ),
        )
    })?;
    Ok(conn)
}

fn open_db(data: &Path) -> Result<rusqlite::Connection, ExitCode> {
    let data = &crate::data_dir::open(data)?;
    db::open(&data.join("knowledge.db")).map_err(|e| {
        crate::output::fail(
            crate::exit::UNREACHABLE,
            &[],
            &format!(
                "gearcam: cannot open the knowledge base in {}: {e}",
                data.display()
            ),
        )
    })
}

/// Parses `--set field=value` pairs by the library's field types.
pub fn parse_sets(lib: &Library, sets: &[String]) -> Result<Record, Vec<JobError>> {
    let mut rec = Record::new();
    let mut errors = Vec::new();
    for s in sets {
        let Some((k, v)) = s.split_once('=') else {
            errors.push(Stage::Knowledge.error(
                Code::BAD_ARGUMENT,
                "--set",
                "FIELD=VALUE",
                s.as_str(),
                "each --set names a field and its value",
            ));
            continue;
        };
        match library::parse_value(lib, k.trim(), v) {
            Ok(val) => {
                rec.insert(k.trim().to_string(), val);
            }
            Err(e) => errors.push(e),
        }
    }
    if errors.is_empty() {
        Ok(rec)
    } else {
        Err(errors)
    }
}

/// The columns `gearcam kb list` shows per library.
fn columns(lib: &Library) -> &'static [&'static str] {
    match lib.name {
        "classes" => &["id", "parent", "name", "programmable"],
        "workpieces" => &[
            "part_number",
            "class",
            "module_mm",
            "teeth",
            "helix_angle_deg",
            "material",
            "quality_grade",
        ],
        "hobs" => &[
            "id",
            "module_mm",
            "starts",
            "hand",
            "od_mm",
            "accuracy_class",
            "material",
            "coating",
            "shift_position_mm",
            "remaining_life_parts",
        ],
        "machines" => &["id", "name", "dialect"],
        "cases" => &[
            "id",
            "class",
            "material",
            "module_mm",
            "teeth",
            "operation",
            "cutting_speed_m_min",
            "feed_mm_per_rev",
            "confidence",
            "outcome",
        ],
        "jobs" => &[
            "job_id",
            "part_number",
            "machine",
            "state",
            "tool_id",
            "confidence",
        ],
        "materials" => &["name", "material_group", "hardness_hb"],
        "mill-machines" => &[
            "id",
            "controller",
            "dialect",
            "default_program",
            "max_rpm",
            "max_feed_mm_min",
            "max_radius_mm",
        ],
        "mills" => &[
            "id",
            "kind",
            "diameter_mm",
            "corner_radius_mm",
            "flutes",
            "material",
        ],
        "milling-data" => &[
            "id",
            "material_group",
            "cutting_speed_m_min",
            "feed_per_tooth_mm",
            "step_over_ratio",
            "max_depth_per_pass_mm",
            "confidence",
        ],
        "wire-machines" => &[
            "id",
            "controller",
            "dialect",
            "programs",
            "default_program",
            "wire",
            "max_thickness_mm",
            "max_radius_mm",
        ],
        "wires" => &["id", "material", "diameter_mm", "spark_gap_mm"],
        "wire-data" => &[
            "id",
            "wire_material",
            "material_group",
            "pulse_on_us",
            "pulse_off_us",
            "current_a",
            "cutting_rate_mm2_min",
            "confidence",
        ],
        "milling-cases" => &[
            "id",
            "kind",
            "material",
            "outer_radius_mm",
            "inner_radius_mm",
            "tool_id",
            "step_over_mm",
            "cutting_speed_m_min",
            "feed_per_tooth_mm",
            "outcome",
        ],
        "weights" => &["feature", "weight", "source"],
        _ => &["id"],
    }
}

fn short(v: &Value) -> String {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if x.fract() != 0.0 => format!("{:.4}", x).trim_end_matches('0').to_string(),
            _ => n.to_string(),
        },
        other => library::cell(other),
    }
}

fn table(lib: &Library, records: &[Record]) -> String {
    let cols = columns(lib);
    let rows: Vec<Vec<String>> = records
        .iter()
        .map(|r| {
            cols.iter()
                .map(|c| short(r.get(*c).unwrap_or(&Value::Null)))
                .collect()
        })
        .collect();
    let widths: Vec<usize> = cols
        .iter()
        .enumerate()
        .map(|(i, c)| {
            rows.iter()
                .map(|r| r[i].chars().count())
                .chain([c.len()])
                .max()
                .unwrap_or(0)
                .min(40)
        })
        .collect();
    let line = |cells: &[String]| {
        cells
            .iter()
            .zip(&widths)
            .map(|(c, w)| {
                let c: String = c.chars().take(*w).collect();
                format!("{c:<w$}")
            })
            .collect::<Vec<_>>()
            .join("  ")
            .trim_end()
            .to_string()
    };
    let mut out = line(&cols.iter().map(|c| c.to_string()).collect::<Vec<_>>());
    out.push('\n');
    for r in &rows {
        out.push_str(&line(r));
        out.push('\n');
    }
    out.push_str(&format!("({} {})\n", records.len(), lib.name));
    out
}

fn print_record(r: &Record, json: bool) {
    if json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(r).unwrap_or_else(|e| e.to_string())
        );
        return;
    }
    for (k, v) in r {
        match v {
            Value::Object(_) | Value::Array(_) => crate::outln!(
                "{k}: {}",
                serde_json::to_string(v).unwrap_or_else(|e| e.to_string())
            ),
            other => crate::outln!("{k}: {}", library::cell(other)),
        }
    }
}

/// Runs `gearcam kb ...`.
pub fn run(args: KbArgs) -> ExitCode {
    if let KbCommand::Libraries = args.command {
        print_libraries(args.json);
        return ExitCode::SUCCESS;
    }
    let conn = match open(&args.data) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let json = args.json;
    let result: Result<(), ExitCode> = match &args.command {
        KbCommand::Libraries => Ok(()),
        KbCommand::Changes { limit } => changes(&conn, *limit, json),
        KbCommand::List { library: l } => list(&conn, l, json),
        KbCommand::Show { library: l, id } => show(&conn, l, id, json),
        KbCommand::Add {
            library: l,
            set,
            from_json,
        } => add(&conn, l, set, from_json.as_deref(), json),
        KbCommand::Edit {
            library: l,
            id,
            set,
        } => edit(&conn, l, id, set, json),
        KbCommand::Remove { library: l, id } => remove(&conn, l, id, json),
        KbCommand::Import { library: l, file } => import(&conn, l, file, json),
        KbCommand::Export { library: l, file } => export(&conn, l, file.as_deref(), json),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(code) => code,
    }
}

/// `gearcam kb libraries`: every library with its key and fields, needing no
/// database (as JSON with `--json`).
fn print_libraries(json: bool) {
    if json {
        let libs: Vec<serde_json::Value> = library::LIBRARIES
            .iter()
            .map(|lib| {
                let fields: Vec<serde_json::Value> = lib
                    .fields
                    .iter()
                    .map(|f| {
                        serde_json::json!({
                            "name": f.name,
                            "type": f.kind.to_string(),
                            "need": f.need.to_string(),
                            "meaning": f.doc,
                        })
                    })
                    .collect();
                serde_json::json!({
                    "name": lib.name,
                    "key": lib.key,
                    "csv": lib.csv,
                    "meaning": lib.doc,
                    "fields": fields,
                })
            })
            .collect();
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&libs).unwrap_or_default()
        );
        return;
    }
    for lib in library::LIBRARIES {
        crate::outln!(
            "{} (key {}{}): {}",
            lib.name,
            lib.key,
            if lib.csv { ", CSV" } else { "" },
            lib.doc
        );
        for f in lib.fields {
            let (kind, need) = (f.kind.to_string(), f.need.to_string());
            crate::outln!("    {:<22} {:<10} {:<18} {}", f.name, kind, need, f.doc);
        }
    }
}

/// The library named `name`, or the refusal printed (an unknown library).
fn lib_of(name: &str) -> Result<Library, ExitCode> {
    library::library(name).map_err(|e| refused(&[e]))
}

/// `gearcam kb changes`: the newest `limit` changes to the libraries, a
/// table or JSON.
fn changes(conn: &rusqlite::Connection, limit: usize, json: bool) -> Result<(), ExitCode> {
    let changes = gearcam_knowledge::audit::changes(conn, limit).map_err(|e| {
        crate::output::fail(crate::exit::UNREACHABLE, &[], &format!("gearcam: {e}"))
    })?;
    if json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&changes).unwrap_or_default()
        );
    } else {
        crate::outln!(
            "{:>6}  {:<23}  {:<24} {:<7} {:<12} RECORD",
            "SEQ",
            "WHEN",
            "BY",
            "OP",
            "LIBRARY"
        );
        for c in &changes {
            crate::outln!(
                "{:>6}  {:<23}  {:<24} {:<7} {:<12} {}",
                c.seq,
                crate::output::utc(c.at_ms.max(0) as u64),
                c.by,
                c.op,
                c.library,
                c.record_id
            );
        }
    }
    Ok(())
}

/// `gearcam kb list LIBRARY`: every record, as a table of the library's
/// main columns or as JSON.
fn list(conn: &rusqlite::Connection, l: &str, json: bool) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    let records = library::list(conn, &lib).map_err(|e| refused(&Vec::from(e)))?;
    if json {
        crate::outln!(
            "{}",
            serde_json::to_string_pretty(&records).unwrap_or_default()
        );
    } else {
        crate::out!("{}", table(&lib, &records));
    }
    Ok(())
}

/// `gearcam kb show LIBRARY ID`: one record, every field; `NOT_FOUND` when
/// the library has no such record.
fn show(conn: &rusqlite::Connection, l: &str, id: &str, json: bool) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    match library::get(conn, &lib, id).map_err(|e| refused(&Vec::from(e)))? {
        Some(r) => print_record(&r, json),
        None => {
            return Err(refused(&[Stage::Knowledge.error(
                Code::NOT_FOUND,
                lib.key,
                format!("an existing {} id (gearcam kb list {})", lib.name, lib.name),
                id,
                format!("there is no record {id:?} in {}", lib.name),
            )]))
        }
    }
    Ok(())
}

/// `gearcam kb add LIBRARY`: a record from `--from-json` (if given) with the
/// `--set` values over it, added and printed.
fn add(
    conn: &rusqlite::Connection,
    l: &str,
    set: &[String],
    from_json: Option<&Path>,
    json: bool,
) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    let mut rec = match from_json {
        Some(path) => record_file(path)?,
        None => Record::new(),
    };
    rec.extend(parse_sets(&lib, set).map_err(|e| refused(&e))?);
    let r = library::add(conn, &lib, &rec).map_err(|e| refused(&e))?;
    crate::outln!(
        "added {} {}",
        lib.name,
        library::cell(r.get(lib.key).unwrap_or(&Value::Null))
    );
    print_record(&r, json);
    Ok(())
}

/// The record in the JSON file at `path` (`gearcam kb add --from-json`):
/// exit 2 when it cannot be read, `BAD_JSON` when it is not a JSON object.
fn record_file(path: &Path) -> Result<Record, ExitCode> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        crate::output::fail(
            crate::exit::UNREACHABLE,
            &[],
            &format!("gearcam: cannot read {}: {e}", path.display()),
        )
    })?;
    serde_json::from_str::<Record>(&text).map_err(|e| {
        refused(&[Stage::Knowledge.error(
            Code::BAD_JSON,
            &path.display().to_string(),
            "a JSON object of the record's fields",
            e.to_string(),
            "the file is not a JSON object",
        )])
    })
}

/// `gearcam kb edit LIBRARY ID --set ...`: the changed fields, then the
/// record as it is now.
fn edit(
    conn: &rusqlite::Connection,
    l: &str,
    id: &str,
    set: &[String],
    json: bool,
) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    let set = parse_sets(&lib, set).map_err(|e| refused(&e))?;
    let r = library::edit(conn, &lib, id, &set).map_err(|e| refused(&e))?;
    crate::outln!("changed {} {id}", lib.name);
    print_record(&r, json);
    Ok(())
}

/// `gearcam kb remove LIBRARY ID`.
fn remove(conn: &rusqlite::Connection, l: &str, id: &str, json: bool) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    library::remove(conn, &lib, id).map_err(|e| refused(&e))?;
    if json {
        crate::outln!(
            "{}",
            serde_json::json!({"removed": {"library": lib.name, "id": id}})
        );
    } else {
        crate::outln!("removed {} {id}", lib.name);
    }
    Ok(())
}

/// `gearcam kb import LIBRARY FILE`: a CSV file, all rows or none; says how
/// many were added and replaced.
fn import(conn: &rusqlite::Connection, l: &str, file: &Path, json: bool) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    let f = std::fs::File::open(file).map_err(|e| {
        crate::output::fail(
            crate::exit::UNREACHABLE,
            &[],
            &format!("gearcam: cannot open {}: {e}", file.display()),
        )
    })?;
    let r = csvio::import(conn, &lib, f).map_err(|e| refused(&e))?;
    if json {
        crate::outln!(
            "{}",
            serde_json::json!({"imported": {"file": file.display().to_string(), "library": lib.name, "added": r.added, "replaced": r.replaced}})
        );
    } else {
        crate::outln!(
            "imported {} into {}: {} added, {} replaced",
            file.display(),
            lib.name,
            r.added,
            r.replaced
        );
    }
    Ok(())
}

/// `gearcam kb export LIBRARY [FILE]`: CSV to the file or to stdout; with
/// `--json` and no file, the records as JSON (as `kb list --json`).
fn export(
    conn: &rusqlite::Connection,
    l: &str,
    file: Option<&Path>,
    json: bool,
) -> Result<(), ExitCode> {
    let lib = lib_of(l)?;
    match file {
        Some(path) => {
            let f = std::fs::File::create(path).map_err(|e| {
                crate::output::fail(
                    crate::exit::UNREACHABLE,
                    &[],
                    &format!("gearcam: cannot create {}: {e}", path.display()),
                )
            })?;
            let n = csvio::export(conn, &lib, f).map_err(|e| refused(&e))?;
            crate::outln!("exported {n} {} to {}", lib.name, path.display());
        }
        None if json => {
            // `--json`: the records as JSON, as `kb list --json`.
            let records = library::list(conn, &lib).map_err(|e| refused(&Vec::from(e)))?;
            crate::outln!(
                "{}",
                serde_json::to_string_pretty(&records).unwrap_or_default()
            );
        }
        None => {
            csvio::export(conn, &lib, std::io::stdout().lock()).map_err(|e| refused(&e))?;
        }
    }
    Ok(())
}

/// Runs `gearcam confirm JOB ...`.
pub fn confirm(args: ConfirmArgs) -> ExitCode {
    let conn = match open(&args.data) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let c = learn::Confirmation {
        job_id: args.job.clone(),
        quantity: args.quantity,
        cutting_speed_m_min: args.cutting_speed,
        feed_mm_per_rev: args.feed,
        cuts: args.cuts,
        outcome: args.outcome,
        quality_achieved: args.quality,
        notes: args.notes,
        confidence: args.confidence,
        by: args.by.unwrap_or_else(crate::jobfile::user),
        at_ms: gearcam_proto::now_ms(),
        allow_undelivered: args.undelivered,
    };
    match learn::confirm(&conn, &c) {
        Ok(done) => {
            if args.json {
                print_record(&done.case, true);
            } else {
                crate::outln!(
                    "job {} confirmed: case {} (vc {} m/min, fa {} mm/rev, outcome {})",
                    args.job,
                    library::cell(&done.case["id"]),
                    short(&done.case["cutting_speed_m_min"]),
                    short(&done.case["feed_mm_per_rev"]),
                    library::cell(&done.case["outcome"]),
                );
                if let Some(h) = &done.hob {
                    crate::outln!(
                        "hob {}: shift position {} mm, remaining life {} parts",
                        library::cell(&h["id"]),
                        short(&h["shift_position_mm"]),
                        short(&h["remaining_life_parts"])
                    );
                }
            }
            ExitCode::SUCCESS
        }
        Err(errors) => refused(&errors),
    }
}
