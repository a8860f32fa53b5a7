//! The spiral face milling family in the knowledge base (docs/spiral.md):
//! its seed (milling machines, mills, starting cutting data, starting
//! cases), the plan of a spiral job (machine, tool, process values from the
//! job, the most similar cases or the cutting data, each with its
//! provenance; the values in `values`), and the learning loop's record of
//! a planned spiral job.

use gearcam_proto::{
    Code, Dialect, Family, JobError, JobRequest, JobSpec, MachineId, MillData, MillKind,
    MillProfile, Source, SpiralPart, SpiralPlan, SpiralProgram, SpiralSpec, Stage,
};
use rusqlite::{Connection, Transaction};
use serde_json::{json, Value};

use crate::library::{self, Record};
use crate::records;
use crate::KnowledgeError;

mod values;

use values::{case_refs, milling_process, proposed, ranked_cases, within_machine};

/// Provenance of the seeded milling machines.
pub const MACHINES_SEED: &str = "gearcam seed: example machine (engineering estimate of a typical \
machine of its kind; enter your machine's travels and limits with gearcam kb edit mill-machines)";

/// Provenance of the seeded tools.
pub const TOOLS_SEED: &str = "gearcam seed: example tool library (catalogue-typical geometry; \
enter your own tools with gearcam kb add mills)";

/// Provenance of the starting cutting data.
pub const DATA_SEED: &str = "gearcam seed: engineering estimate of starting values for coated \
carbide face milling (tool makers' catalogues give vc 150-250 m/min and fz 0.1-0.2 mm for \
steels and grey cast iron); not shop history; replace by importing your cases";

/// Provenance of the starting cases.
pub const CASES_SEED: &str = "gearcam seed: engineering estimate (not shop history), \
to show retrieval; replace by importing your cases (gearcam kb import milling-cases FILE.csv)";

/// The similarity a case needs for its values to be proposed.
pub const MIN_SIMILARITY: f64 = 0.6;

/// Default outer overtravel beyond Ro + tool radius, mm: the tool starts
/// wholly clear of the part and enters it gradually.
pub const DEFAULT_OUTER_OVERTRAVEL_MM: f64 = 2.0;
/// Default inner overtravel past the inner edge, mm.
pub const DEFAULT_INNER_OVERTRAVEL_MM: f64 = 0.5;
/// Default chord/arc tolerance, mm (seed 001's 5 µm).
pub const DEFAULT_TOLERANCE_MM: f64 = 0.005;

/// Adds a seed record unless one with its key is there (a shop's own
/// record of the same id is kept; a migration run again adds nothing twice).
pub(crate) fn add(
    tx: &Transaction<'_>,
    lib: &library::Library,
    v: Value,
) -> Result<(), KnowledgeError> {
    let key = v.get(lib.key).and_then(Value::as_str).unwrap_or_default();
    if library::get(tx, lib, key)?.is_some() {
        return Ok(());
    }
    crate::seed::insert(tx, lib, v)
}

/// Seeds the tables of migration 7, each from its own example rows: the
/// milling machines, the mills, the face milling example materials, the
/// starting cutting data and the starting cases, in that order.
pub fn seed_v7(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    crate::audit::acting_as(tx, "seed")?;
    seed_mill_machines(tx)?;
    seed_mills(tx)?;
    seed_milling_materials(tx)?;
    seed_milling_data(tx)?;
    seed_milling_cases(tx)
}

/// The example milling machines: a FANUC machining centre and a LinuxCNC
/// knee mill, so that every program form has a machine.
fn seed_mill_machines(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    add(
        tx,
        &library::MILL_MACHINES,
        json!({"id": "M01", "name": "Vertical machining centre, FANUC 0i-MF",
               "controller": "FANUC 0i-MF", "dialect": "fanuc",
               "programs": "fanuc-macro fanuc-arcs fanuc-chords", "default_program": "fanuc-macro",
               "max_rpm": 8000.0, "max_feed_mm_min": 10000.0, "max_radius_mm": 250.0,
               "safe_z_mm": 5.0, "work_offset": "G54", "source": MACHINES_SEED}),
    )?;
    add(
        tx,
        &library::MILL_MACHINES,
        json!({"id": "M02", "name": "Knee mill retrofit, LinuxCNC 2.9",
               "controller": "LinuxCNC 2.9", "dialect": "linuxcnc",
               "programs": "linuxcnc", "default_program": "linuxcnc",
               "max_rpm": 4000.0, "max_feed_mm_min": 3000.0, "max_radius_mm": 150.0,
               "safe_z_mm": 5.0, "work_offset": "G54", "source": MACHINES_SEED}),
    )
}

/// The example tool library: face mills and end mills of catalogue-typical
/// geometry.
fn seed_mills(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (id, kind, d, corner, flutes) in [
        ("FM-125", "face-mill", 125.0, 0.8, 8),
        ("FM-063", "face-mill", 63.0, 0.8, 5),
        ("EM-16", "end-mill", 16.0, 0.5, 4),
        ("EM-10", "end-mill", 10.0, 0.0, 4),
        ("EM-06", "end-mill", 6.0, 0.0, 3),
    ] {
        add(
            tx,
            &library::MILLS,
            json!({"id": id, "kind": kind, "diameter_mm": d, "corner_radius_mm": corner,
                   "flutes": flutes, "material": "carbide", "source": TOOLS_SEED}),
        )?;
    }
    Ok(())
}

/// The aluminium materials of the face milling examples (a shop's own
/// material of the same name is kept).
fn seed_milling_materials(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (name, group) in [("AlMg3", "aluminium"), ("6061-T6", "aluminium")] {
        tx.execute(
            "INSERT OR IGNORE INTO materials (name, material_group, source) VALUES (?1, ?2, ?3)",
            rusqlite::params![name, group, "gearcam seed: face milling example material"],
        )?;
    }
    Ok(())
}

/// The starting cutting data of coated carbide face milling, one row per
/// material group.
fn seed_milling_data(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (id, group, vc, fz, ratio, depth, conf) in [
        (
            "MD-QT-STEEL",
            "quenched_tempered_steel",
            180.0,
            0.12,
            0.6,
            2.0,
            0.5,
        ),
        (
            "MD-CH-STEEL",
            "case_hardening_steel",
            200.0,
            0.12,
            0.6,
            2.0,
            0.5,
        ),
        ("MD-CAST-IRON", "cast_iron", 200.0, 0.15, 0.6, 3.0, 0.5),
        ("MD-NONFERROUS", "nonferrous", 250.0, 0.10, 0.6, 2.0, 0.4),
        ("MD-ALUMINIUM", "aluminium", 500.0, 0.10, 0.6, 3.0, 0.4),
    ] {
        add(
            tx,
            &library::MILLING_DATA,
            json!({"id": id, "material_group": group, "tool_material": "carbide",
                   "cutting_speed_m_min": vc, "feed_per_tooth_mm": fz, "step_over_ratio": ratio,
                   "max_depth_per_pass_mm": depth, "confidence": conf, "source": DATA_SEED}),
        )?;
    }
    Ok(())
}

/// The starting cases: a face of steel, a face of cast iron and a groove,
/// so that retrieval has something to show before the shop's own cases.
fn seed_milling_cases(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    for (id, kind, material, group, ro, ri, tool, d, z, step, passes, depth, vc, fz) in [
        (
            "MC-FACE-C45-100",
            "face",
            "C45",
            "quenched_tempered_steel",
            100.0,
            20.0,
            "FM-063",
            63.0,
            5,
            38.0,
            1,
            1.0,
            170.0,
            0.11,
        ),
        (
            "MC-FACE-HT250-150",
            "face",
            "HT250",
            "cast_iron",
            150.0,
            0.0,
            "FM-125",
            125.0,
            8,
            75.0,
            2,
            3.0,
            190.0,
            0.14,
        ),
        (
            "MC-GROOVE-C45-60",
            "groove",
            "C45",
            "quenched_tempered_steel",
            60.0,
            0.0,
            "EM-10",
            10.0,
            4,
            16.0,
            4,
            4.0,
            120.0,
            0.04,
        ),
    ] {
        add(
            tx,
            &library::MILLING_CASES,
            json!({"id": id, "kind": kind, "material": material, "material_group": group,
                   "outer_radius_mm": ro, "inner_radius_mm": ri, "tool_id": tool,
                   "tool_diameter_mm": d, "flutes": z, "step_over_mm": step, "passes": passes,
                   "depth_mm": depth, "cutting_speed_m_min": vc, "feed_per_tooth_mm": fz,
                   "outcome": "ok", "confidence": 0.5, "provenance": CASES_SEED,
                   "created_at_ms": 0}),
        )?;
    }
    Ok(())
}

pub(crate) fn num(r: &Record, field: &str) -> f64 {
    r.get(field).and_then(Value::as_f64).unwrap_or(f64::NAN)
}

pub(crate) fn text<'a>(r: &'a Record, field: &str) -> &'a str {
    r.get(field).and_then(Value::as_str).unwrap_or("")
}

fn form(name: &str) -> Option<SpiralProgram> {
    SpiralProgram::ALL.into_iter().find(|f| f.as_str() == name)
}

/// A milling machine's profile from its record.
fn profile(r: &Record) -> Result<MillProfile, KnowledgeError> {
    let id = text(r, "id");
    let bad = |field: &str| {
        KnowledgeError::Seed(format!(
            "mill-machines record {id}: field {field} is not usable"
        ))
    };
    let programs: Vec<SpiralProgram> = text(r, "programs")
        .split_whitespace()
        .map(|p| form(p).ok_or_else(|| bad("programs")))
        .collect::<Result<_, _>>()?;
    Ok(MillProfile {
        id: MachineId::new(id).map_err(|_| bad("id"))?,
        name: text(r, "name").to_string(),
        controller: text(r, "controller").to_string(),
        dialect: match text(r, "dialect") {
            "fanuc" => Dialect::Fanuc,
            "linuxcnc" => Dialect::Linuxcnc,
            _ => return Err(bad("dialect")),
        },
        default_program: form(text(r, "default_program")).ok_or_else(|| bad("default_program"))?,
        programs,
        max_rpm: num(r, "max_rpm"),
        max_feed_mm_min: num(r, "max_feed_mm_min"),
        max_radius_mm: num(r, "max_radius_mm"),
        safe_z_mm: num(r, "safe_z_mm"),
        work_offset: text(r, "work_offset").to_string(),
    })
}

/// Every milling machine's profile, ordered by id.
pub fn mill_machines(conn: &Connection) -> Result<Vec<MillProfile>, KnowledgeError> {
    library::list(conn, &library::MILL_MACHINES)?
        .iter()
        .map(profile)
        .collect()
}

fn tool_of(r: &Record) -> MillData {
    MillData {
        id: text(r, "id").to_string(),
        kind: if text(r, "kind") == "face-mill" {
            MillKind::FaceMill
        } else {
            MillKind::EndMill
        },
        radius_mm: num(r, "diameter_mm") / 2.0,
        corner_radius_mm: num(r, "corner_radius_mm"),
        flutes: num(r, "flutes") as u32,
        material: text(r, "material").to_string(),
        source: Source::Library,
    }
}

/// The errors of a spiral job's sections (empty when they fit): it mills
/// one face or one groove, so exactly one of `[face]` and `[groove]`.
fn section_errors(spec: &SpiralSpec) -> Vec<JobError> {
    match (&spec.face, &spec.groove) {
        (Some(_), Some(_)) => vec![Stage::Knowledge.error(
            Code::SECTION_FAMILY,
            "groove",
            "either [face] or [groove]",
            "both",
            "a spiral job mills one face or one groove",
        )],
        (None, None) => vec![Stage::Knowledge.error(
            Code::MISSING_SECTION,
            "face",
            "a [face] (outer_radius_mm, inner_radius_mm, depth_mm, material) or a [groove] section",
            "neither",
            "a spiral-face job describes the face or the groove it mills",
        )],
        _ => Vec::new(),
    }
}

/// Plans a spiral job: every typed error found, or the plan.
pub fn plan_spiral(conn: &Connection, req: &JobRequest) -> Result<SpiralPlan, Vec<JobError>> {
    plan_inner(conn, req).map_err(|e| match e {
        Failed::Job(e) => e,
        Failed::Kb(e) => vec![Stage::Knowledge.error(
            Code::KNOWLEDGE_BASE_ERROR,
            "-",
            "a readable knowledge base",
            e.to_string(),
            "the knowledge base could not be read; check the knowledge service's log and database file",
        )],
    })
}

enum Failed {
    Job(Vec<JobError>),
    Kb(KnowledgeError),
}

impl From<KnowledgeError> for Failed {
    fn from(e: KnowledgeError) -> Self {
        Failed::Kb(e)
    }
}

/// Plans a checked job: its machine and part, the material's group, the
/// tool, the most similar cases and the cutting data; the values they
/// propose, kept within the machine; the cases cited and the confidence.
fn plan_inner(conn: &Connection, req: &JobRequest) -> Result<SpiralPlan, Failed> {
    let spec = crate::sections::sections(req, Family::SpiralFace, JobSpec::spiral)
        .map_err(|e| Failed::Job(vec![e]))?;
    let (machine, part) = machine_and_part(conn, req, spec)?;
    let material = records::material(conn, part.material())?;
    let group = material
        .as_ref()
        .map_or("unknown".to_string(), |m| m.material_group.clone());
    let tool = choose_tool(conn, spec, &part)?.map_err(Failed::Job)?;
    let o = &spec.milling;
    let program = o.program.unwrap_or(machine.default_program);

    // The most similar cases of this kind.
    let d = 2.0 * tool.radius_mm;
    let scored = ranked_cases(conn, &part, &group, d, req.spec.job.machine.as_str())?;
    let best = scored.first().filter(|(s, _)| *s >= MIN_SIMILARITY);
    let data = library::list(conn, &library::MILLING_DATA)?
        .into_iter()
        .find(|r| text(r, "material_group") == group);
    if best.is_none()
        && data.is_none()
        && (o.cutting_speed_m_min.is_none() || o.feed_per_tooth_mm.is_none())
    {
        return Err(Failed::Job(vec![no_cutting_data(&part, &group)]));
    }
    let values = proposed(o, &part, best.map(|(_, c)| c), data.as_ref(), d);
    let values = within_machine(values, &machine, &tool, d);
    let cases = case_refs(&scored);
    let confidence = match (best, &data) {
        (Some((s, c)), _) => s * num(c, "confidence"),
        (None, Some(r)) => num(r, "confidence"),
        (None, None) => 1.0,
    };
    Ok(SpiralPlan {
        job_id: req.job_id.clone(),
        request: req.clone(),
        part,
        machine,
        tool,
        process: milling_process(o, values, program),
        cases,
        confidence,
    })
}

/// The job's machine and part, once the job is checked: its sections, its
/// machine, and its program's name by the control's rule, before anything
/// is planned. Every error found, in that order, or both.
fn machine_and_part(
    conn: &Connection,
    req: &JobRequest,
    spec: &SpiralSpec,
) -> Result<(MillProfile, SpiralPart), Failed> {
    let mut errors = section_errors(spec);
    let machine_id = req.spec.job.machine.as_str();
    let machine = match library::get(conn, &library::MILL_MACHINES, machine_id)? {
        Some(r) => Some(profile(&r)?),
        None => {
            errors.push(library::machine_error(
                conn,
                machine_id,
                "spiral face milling",
            )?);
            None
        }
    };
    let part = match (&spec.face, &spec.groove) {
        (Some(f), None) => Some(SpiralPart::Face(f.clone())),
        (None, Some(g)) => Some(SpiralPart::Groove(g.clone())),
        _ => None,
    };
    if let Some(m) = &machine {
        // The program's name by the control's rule, before anything is planned.
        let dialect = spec.milling.program.unwrap_or(m.default_program).dialect();
        errors.extend(gearcam_proto::naming::name_error(
            dialect,
            &req.spec.job,
            false,
            Stage::Knowledge,
        ));
    }
    let (Some(machine), Some(part), true) = (machine, part, errors.is_empty()) else {
        return Err(Failed::Job(errors));
    };
    Ok((machine, part))
}

/// The refusal of a job for whose material the knowledge base has neither a
/// similar case nor cutting data, and whose `[milling]` does not give both
/// the cutting speed and the feed.
fn no_cutting_data(part: &SpiralPart, group: &str) -> JobError {
    Stage::Knowledge.error(
        Code::NO_CUTTING_DATA,
        &format!("{}.material", part.kind()),
        "a material whose group has milling data or similar cases (gearcam kb list milling-data), or [milling] cutting_speed_m_min and feed_per_tooth_mm",
        format!("{} (group {group})", part.material()),
        "the knowledge base has nothing to propose for this material",
    )
}

/// The tool: the job's library id, the job's inline tool, or the library's
/// choice (a groove: an end mill of the groove's width; a face: the largest
/// mill no wider than the face's radius).
fn choose_tool(
    conn: &Connection,
    spec: &SpiralSpec,
    part: &SpiralPart,
) -> Result<Result<MillData, Vec<JobError>>, KnowledgeError> {
    let m = &spec.mill;
    let tools = library::list(conn, &library::MILLS)?;
    let ids = || {
        tools
            .iter()
            .map(|t| text(t, "id").to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    if let Some(id) = &m.id {
        return Ok(match tools.iter().find(|t| text(t, "id") == id) {
            Some(t) => Ok(tool_of(t)),
            None => Err(vec![Stage::Knowledge.error(
                Code::UNKNOWN_TOOL,
                "mill.id",
                format!("a mill of the tool library: one of {}", ids()),
                id.clone(),
                "the tool is not in the knowledge base (gearcam kb list mills), or give the tool inline: [mill] kind, radius_mm, flutes",
            )]),
        });
    }
    if m.radius_mm.is_some() || m.flutes.is_some() || m.kind.is_some() {
        let missing: Vec<&str> = [
            ("mill.kind", m.kind.is_none()),
            ("mill.radius_mm", m.radius_mm.is_none()),
            ("mill.flutes", m.flutes.is_none()),
        ]
        .into_iter()
        .filter_map(|(f, missing)| missing.then_some(f))
        .collect();
        return Ok(match (m.kind, m.radius_mm, m.flutes) {
            (Some(kind), Some(r), Some(z)) => {
                let mut errors = Vec::new();
                if !(r.is_finite() && r > 0.0) {
                    errors.push(Stage::Knowledge.error(Code::TOOL_RANGE, "mill.radius_mm", "a radius > 0 mm", format!("{r}"), "the tool's cutting radius"));
                }
                if z == 0 {
                    errors.push(Stage::Knowledge.error(Code::TOOL_RANGE, "mill.flutes", "1 or more", "0", "flutes or inserts of the tool"));
                }
                let corner = m.corner_radius_mm.unwrap_or(0.0);
                if !(corner.is_finite() && corner >= 0.0 && corner <= r) {
                    errors.push(Stage::Knowledge.error(Code::TOOL_RANGE, "mill.corner_radius_mm", format!("0 to the tool's radius {r} mm"), format!("{corner}"), "the tool's corner radius"));
                }
                if errors.is_empty() {
                    Ok(MillData {
                        id: "job".into(),
                        kind,
                        radius_mm: r,
                        corner_radius_mm: corner,
                        flutes: z,
                        material: "carbide".into(),
                        source: Source::Job,
                    })
                } else {
                    Err(errors)
                }
            }
            _ => Err(vec![Stage::Knowledge.error(
                Code::MISSING_FIELD,
                missing[0],
                "an inline tool gives kind, radius_mm and flutes (or [mill] id names a library tool)",
                format!("no {}", missing.join(", no ")),
                "the tool is incomplete",
            )]),
        });
    }
    let mut candidates: Vec<MillData> = tools.iter().map(tool_of).collect();
    candidates.sort_by(|a, b| b.radius_mm.total_cmp(&a.radius_mm));
    Ok(match part {
        SpiralPart::Groove(g) => candidates
            .into_iter()
            .find(|t| t.kind == MillKind::EndMill && (2.0 * t.radius_mm - g.width_mm).abs() < 1e-3)
            .ok_or_else(|| {
                vec![Stage::Knowledge.error(
                    Code::NO_TOOL,
                    "groove.width_mm",
                    format!(
                        "the diameter of an end mill in the tool library ({})",
                        tools
                            .iter()
                            .filter(|t| text(t, "kind") == "end-mill")
                            .map(|t| format!("{} mm", num(t, "diameter_mm")))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                    format!("{}", g.width_mm),
                    "a groove is cut in one pass of the tool's full width; add an end mill of this diameter or give [mill]",
                )]
            }),
        SpiralPart::Face(f) => {
            let fits = candidates
                .iter()
                .find(|t| 2.0 * t.radius_mm <= f.outer_radius_mm)
                .cloned();
            fits.or_else(|| candidates.last().cloned()).ok_or_else(|| {
                vec![Stage::Knowledge.error(
                    Code::NO_TOOL,
                    "mill",
                    "a mill in the tool library",
                    "an empty tool library",
                    "add mills (gearcam kb add mills) or give [mill]",
                )]
            })
        }
    })
}

/// Records a planned spiral job in the jobs library (state `planned`; its
/// class is `spiral-face` or `spiral-groove`, its tool in `tool_id`).
pub fn record_planned(
    conn: &Connection,
    plan: &SpiralPlan,
    at_ms: u64,
) -> Result<(), KnowledgeError> {
    crate::learn::record_job(
        conn,
        &crate::learn::Planned {
            job_id: plan.job_id.as_str(),
            part_number: &plan.request.spec.job.part_number,
            machine: plan.machine.id.as_str(),
            class: &format!("spiral-{}", plan.part.kind()),
            quantity: plan.request.spec.job.quantity,
            tool: &plan.tool.id,
            confidence: plan.confidence,
            plan_json: serde_json::to_string(plan)?,
        },
        at_ms,
    )
}

#[cfg(test)]
mod tests;
