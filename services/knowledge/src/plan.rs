//! From a job request to a process plan: machine, hob (matched and
//! explained), cutting data proposed by case-based reasoning and adapted to
//! the machine, the job's overrides on top, every value with its source.
//!
//! Sources of the decided values: `job` (the job file overrides), `case`
//! (retrieved and adapted cases, [`crate::cbr`]), `machine` (the machine
//! profile, or a proposal clamped to the machine's limits), `default`
//! (gearcam's documented defaults when no case applies) and `library` (the
//! drawing data `gear.*` of a job that names its part instead of giving a
//! `[gear]` section; the plan's request carries the filled gear).

use gearcam_proto::plan::Proposal;
use gearcam_proto::{
    CaseRef, CutMode, GearSpec, HobData, HobSpec, JobError, JobRequest, MachineProfile,
    ProcessData, ProcessPlan, Source, Sourced, WorkpieceRef,
};
use rusqlite::Connection;

use crate::cbr::{self, CaseBase, Limits, Problem};
use crate::history::{self, LibraryHob};
use crate::hobmatch;
use crate::{db, KnowledgeError};

/// Cutting speed when no case applies, m/min: an engineering estimate for
/// HSS hobs in steel, deliberately low.
pub const DEFAULT_CUTTING_SPEED_M_MIN: f64 = 80.0;
/// Feed per workpiece revolution when no case applies, mm/rev (engineering estimate).
pub const DEFAULT_FEED_MM_PER_REV: f64 = 1.8;
/// Confidence of a proposal made of defaults only.
pub const DEFAULT_CONFIDENCE: f64 = 0.2;

use crate::library::kb_err as err;

/// The group-technology class of a job (docs/knowledge.md#group-technology-classes), by the rule in
/// [`gearcam_proto::classify`]: `[[units]]` make a multi-gear part, otherwise
/// the `[gear]` table's class marker (cone, crowning, worm wheel, curved
/// tooth) or cylindrical.
pub fn classify(req: &JobRequest) -> &'static str {
    gearcam_proto::classify(&req.spec).as_str()
}

/// Builds the process plan for a request, or every reason it cannot be built.
/// Loads the case base from the database; a service that plans many jobs
/// keeps it in memory and calls [`plan_with`].
pub fn plan(conn: &Connection, req: &JobRequest) -> Result<ProcessPlan, Vec<JobError>> {
    let cases = history::load_case_base(conn).map_err(kb_error)?;
    plan_with(conn, &cases, req)
}

/// Builds the process plan with a case base already in memory.
pub fn plan_with(
    conn: &Connection,
    cases: &CaseBase,
    req: &JobRequest,
) -> Result<ProcessPlan, Vec<JobError>> {
    plan_inner(conn, cases, req).map_err(|e| match e {
        PlanError::Job(errors) => errors,
        PlanError::Kb(e) => kb_error(e),
    })
}

fn kb_error(e: KnowledgeError) -> Vec<JobError> {
    vec![err(
        "KNOWLEDGE_BASE_ERROR",
        "-",
        "a readable knowledge base",
        e.to_string(),
        "the knowledge base could not be read; check the knowledge service's log and database file",
    )]
}

enum PlanError {
    Job(Vec<JobError>),
    Kb(KnowledgeError),
}

impl From<KnowledgeError> for PlanError {
    fn from(e: KnowledgeError) -> Self {
        PlanError::Kb(e)
    }
}

/// The hob as resolved, with what retrieval needs to know of it.
struct Resolved {
    data: HobData,
    material: Option<String>,
    coating: Option<String>,
}

fn plan_inner(
    conn: &Connection,
    cases: &CaseBase,
    req: &JobRequest,
) -> Result<ProcessPlan, PlanError> {
    let mut proposal = Proposal::default();
    // The drawing data first: every later step reads the resolved gear, and
    // the plan carries it in its copy of the request.
    let resolved = resolve_gear(conn, req, &mut proposal)?;
    let machine = db::machine(conn, &req.spec.job.machine)?;
    let (WithGear { req, hardness_hb }, machine) = match (resolved, machine) {
        (Ok(with_gear), Some(machine)) => (with_gear, machine),
        (resolved, machine) => {
            let mut errors: Vec<JobError> = resolved.err().into_iter().collect();
            if machine.is_none() {
                let known: Vec<String> = db::machines(conn)?
                    .into_iter()
                    .map(|m| m.id.to_string())
                    .collect();
                errors.push(err(
                    "UNKNOWN_MACHINE",
                    "job.machine",
                    format!("one of {}", known.join(", ")),
                    req.spec.job.machine.to_string(),
                    "the machine is not in the knowledge base; pick a configured machine or add it",
                ));
            }
            return Err(PlanError::Job(errors));
        }
    };
    let req = &req;
    let spec = &req.spec;
    let mut errors = Vec::new();
    let class = classify(req);
    let hob = resolve_hob(conn, req, &machine, &mut errors, &mut proposal)?;

    // The job as a retrieval problem.
    let g = &spec.gear;
    let material = history::material(conn, &g.material)?;
    let problem = Problem {
        class: class.to_string(),
        material: g.material.trim().to_string(),
        material_group: material.as_ref().map(|m| m.0.clone()).unwrap_or_default(),
        // The part's own hardness when the workpiece library knows it, else
        // the material's typical one.
        hardness_hb: hardness_hb.or_else(|| material.as_ref().and_then(|m| m.1)),
        module_mm: g.module_mm,
        teeth: g.teeth,
        helix_angle_deg: g.helix_angle_deg.abs(),
        face_width_mm: Some(g.face_width_mm),
        quality_grade: g.quality_grade,
        hob_material: hob.as_ref().and_then(|h| h.material.clone()),
        hob_coating: hob.as_ref().and_then(|h| h.coating.clone()),
        hob_starts: hob.as_ref().map(|h| h.data.starts).unwrap_or(1),
        // `[process] operation`; a job that does not say finishes the flanks.
        operation: spec.process.operation.unwrap_or_default().into(),
        machine: Some(machine.id.to_string()),
    };
    let weights = history::load_weights(conn)?;
    proposal.weights = weights.to_map();
    let hob_od = hob.as_ref().map(|h| h.data.od_mm);
    let limits = Limits {
        max_cutting_speed_m_min: hob_od
            .map(|d| machine.limits.max_hob_rpm * std::f64::consts::PI * d / 1000.0)
            .unwrap_or(f64::INFINITY),
    };
    let hits = if material.is_some() && g.module_mm > 0.0 && g.module_mm.is_finite() {
        cases.retrieve(&problem, &limits, &weights, cbr::TOP_K)
    } else {
        Vec::new()
    };
    let adapted = cbr::adapt(cases, &hits, &problem);

    // The proposal: adapted cases, else defaults; then the machine's limits.
    let mut prop = |name: &str, value: f64, source: Source| {
        proposal
            .values
            .insert(name.to_string(), Sourced { value, source });
    };
    let (mut vc, mut vc_src, mut fa, mut fa_src, cuts, cuts_src, mode, mode_src, confidence) =
        match &adapted {
            Some(a) => (
                a.cutting_speed_m_min,
                Source::Case,
                a.feed_mm_per_rev.unwrap_or(DEFAULT_FEED_MM_PER_REV),
                if a.feed_mm_per_rev.is_some() {
                    Source::Case
                } else {
                    Source::Default
                },
                a.cuts,
                Source::Case,
                a.cut_mode.unwrap_or(CutMode::Conventional),
                if a.cut_mode.is_some() {
                    Source::Case
                } else {
                    Source::Default
                },
                a.confidence,
            ),
            None => (
                DEFAULT_CUTTING_SPEED_M_MIN,
                Source::Default,
                DEFAULT_FEED_MM_PER_REV,
                Source::Default,
                1,
                Source::Default,
                CutMode::Conventional,
                Source::Default,
                DEFAULT_CONFIDENCE,
            ),
        };
    if let Some(h) = &hob {
        let (da0, z0, z) = (
            h.data.od_mm,
            f64::from(h.data.starts.max(1)),
            f64::from(g.teeth.max(1)),
        );
        // Hob speed and table speed limits bound the cutting speed.
        let nt_max = machine
            .limits
            .max_hob_rpm
            .min(machine.limits.max_table_rpm * z / z0);
        let vc_max = nt_max * std::f64::consts::PI * da0 / 1000.0;
        if da0 > 0.0 && vc > vc_max {
            vc = vc_max;
            vc_src = Source::Machine;
        }
        // The axial feed rate limit bounds the feed per revolution (spur estimate Nw = z0·Nt/z).
        let nt = vc * 1000.0 / (std::f64::consts::PI * da0);
        let fa_max = machine.limits.max_axial_feed_mm_min * z / (z0 * nt);
        if da0 > 0.0 && fa > fa_max {
            fa = fa_max;
            fa_src = Source::Machine;
        }
    }
    prop("cutting_speed_m_min", vc, vc_src);
    prop("feed_mm_per_rev", fa, fa_src);
    prop("cuts", f64::from(cuts), cuts_src);
    prop(
        "cut_mode_climb",
        f64::from(u8::from(mode == CutMode::Climb)),
        mode_src,
    );
    prop("safety_mm", machine.settings.safety_mm, Source::Machine);
    // Rough or finish is the job's to say; finish unless it does.
    prop("operation_rough", 0.0, Source::Default);
    if let Some(a) = &adapted {
        if let Some(r) = a.radial_feed_mm_min {
            prop("radial_feed_mm_min", r, Source::Case);
        }
        if let Some(x) = a.allowance_mm {
            prop("allowance_mm", x, Source::Case);
        }
    }

    // The job's overrides win.
    let p = &spec.process;
    let overrides: [(&str, Option<f64>); 7] = [
        (
            "operation_rough",
            p.operation
                .map(|o| f64::from(u8::from(o == gearcam_proto::Operation::Rough))),
        ),
        ("cutting_speed_m_min", p.cutting_speed_m_min),
        ("feed_mm_per_rev", p.feed_mm_per_rev),
        ("cuts", p.cuts.map(f64::from)),
        (
            "cut_mode_climb",
            p.cut_mode.map(|m| f64::from(u8::from(m == CutMode::Climb))),
        ),
        ("safety_mm", p.safety_mm),
        ("depth_mm", p.depth_mm),
    ];
    let mut values = proposal.values.clone();
    // A job that names a library part and gives its own [gear] overrides the
    // record's drawing data as a whole.
    if proposal
        .workpiece
        .as_ref()
        .is_some_and(|w| !w.supplied_gear)
    {
        for (name, value) in gear_values(&spec.gear) {
            values.insert(
                name.to_string(),
                Sourced {
                    value,
                    source: Source::Job,
                },
            );
            if proposal.values.contains_key(name) {
                proposal.overridden.push(name.to_string());
            }
        }
    }
    for (name, v) in overrides {
        if let Some(value) = v {
            values.insert(
                name.to_string(),
                Sourced {
                    value,
                    source: Source::Job,
                },
            );
            if proposal.values.contains_key(name) {
                proposal.overridden.push(name.to_string());
            }
        }
    }
    let value = |name: &str| values[name].value;
    let from_kb = [
        "cutting_speed_m_min",
        "feed_mm_per_rev",
        "cuts",
        "cut_mode_climb",
    ]
    .iter()
    .any(|n| values[*n].source != Source::Job);
    let cases_used: Vec<CaseRef> = if from_kb {
        hits.iter()
            .filter(|h| h.similarity > 0.0)
            .map(|h| {
                let c = &cases.cases()[h.index];
                CaseRef {
                    id: c.id.clone(),
                    similarity: h.similarity,
                    provenance: c.provenance.clone(),
                }
            })
            .collect()
    } else {
        Vec::new()
    };

    if !errors.is_empty() {
        return Err(PlanError::Job(errors));
    }
    let hob = hob.expect("a hob when there are no errors").data;
    Ok(ProcessPlan {
        job_id: req.job_id.clone(),
        request: req.clone(),
        class: class.into(),
        machine,
        hob,
        process: ProcessData {
            cut_mode: p.cut_mode.unwrap_or(mode),
            cuts: value("cuts") as u32,
            cutting_speed_m_min: value("cutting_speed_m_min"),
            feed_mm_per_rev: value("feed_mm_per_rev"),
            depth_mm: p.depth_mm,
            safety_mm: value("safety_mm"),
        },
        values,
        cases: cases_used,
        confidence: if from_kb { confidence } else { 1.0 },
        proposal,
    })
}

/// The numeric drawing data of a gear as plan values (`gear.*`), as the
/// model's explanation names them.
fn gear_values(g: &GearSpec) -> Vec<(&'static str, f64)> {
    let mut v = vec![
        ("gear.module_mm", g.module_mm),
        ("gear.teeth", f64::from(g.teeth)),
        ("gear.pressure_angle_deg", g.pressure_angle_deg),
        ("gear.helix_angle_deg", g.helix_angle_deg),
        ("gear.face_width_mm", g.face_width_mm),
        ("gear.profile_shift", g.profile_shift),
        ("gear.addendum_coef", g.addendum_coef),
        ("gear.clearance_coef", g.clearance_coef),
        ("gear.od_correction_mm", g.od_correction_mm),
        ("gear.quality_grade", f64::from(g.quality_grade)),
        ("gear.fixture_height_mm", g.fixture_height_mm),
    ];
    if let Some(od) = g.blank_od_mm {
        v.push(("gear.blank_od_mm", od));
    }
    if let Some(c) = &g.cone {
        v.push(("gear.cone.angle_deg", c.angle_deg));
    }
    v
}

/// The drawing-data fields in which two gears differ, by name.
fn gear_differences(job: &GearSpec, record: &GearSpec) -> Vec<String> {
    let theirs: std::collections::BTreeMap<&str, f64> = gear_values(record).into_iter().collect();
    let ours: std::collections::BTreeMap<&str, f64> = gear_values(job).into_iter().collect();
    let mut names: Vec<&str> = ours.keys().chain(theirs.keys()).copied().collect();
    names.sort_unstable();
    names.dedup();
    let mut out: Vec<String> = names
        .into_iter()
        .filter(|n| ours.get(n) != theirs.get(n))
        .map(str::to_string)
        .collect();
    if job.material.trim() != record.material.trim() {
        out.push("gear.material".into());
    }
    if job.helix_hand != record.helix_hand && job.helix_angle_deg != 0.0 {
        out.push("gear.helix_hand".into());
    }
    if gearcam_proto::class::unit_class(job) != gearcam_proto::class::unit_class(record) {
        out.push("gear.class".into());
    }
    out
}

/// A request with its drawing data resolved.
struct WithGear {
    /// The request, its `spec.gear` filled.
    req: JobRequest,
    /// The part's hardness from the workpiece library, when the record gives
    /// one and the gear is of the record's material.
    hardness_hb: Option<f64>,
}

/// The request with its drawing data resolved: the job's `[gear]`, or the
/// workpiece library's record of its part number. Records the library's
/// part in the proposal (and its values with source `library`). The inner
/// error is the job's: no gear and no library part.
fn resolve_gear(
    conn: &Connection,
    req: &JobRequest,
    proposal: &mut Proposal,
) -> Result<Result<WithGear, JobError>, KnowledgeError> {
    let spec = &req.spec;
    let part = spec.job.part_number.trim();
    let record = crate::library::get(conn, &crate::library::WORKPIECES, part)?;
    let Some(record) = record else {
        if spec.has_gear() {
            return Ok(Ok(WithGear {
                req: req.clone(),
                hardness_hb: None,
            }));
        }
        let known: Vec<String> = crate::library::list(conn, &crate::library::WORKPIECES)?
            .iter()
            .filter_map(|r| r.get("part_number").and_then(|v| v.as_str()))
            .take(20)
            .map(str::to_string)
            .collect();
        return Ok(Err(err(
            "GEAR_MISSING",
            "gear",
            format!(
                "a [gear] section or a part number in the workpiece library ({})",
                if known.is_empty() {
                    "the library is empty".to_string()
                } else {
                    format!("one of {}", known.join(", "))
                }
            ),
            format!("no [gear] section, and part number {part:?} is not in the workpiece library"),
            "the job has no drawing data: add the [gear] section, or add the part to the workpiece library (gearcam kb add workpieces ...) and name it in [job] part_number",
        )));
    };
    let library_gear = history::gear_from_workpiece(&record);
    let provenance = record
        .get("source")
        .and_then(|v| v.as_str())
        .unwrap_or_default()
        .to_string();
    for (name, value) in gear_values(&library_gear) {
        proposal.values.insert(
            name.to_string(),
            Sourced {
                value,
                source: Source::Library,
            },
        );
    }
    let hardness = |g: &GearSpec| {
        record
            .get("hardness_hb")
            .and_then(|v| v.as_f64())
            .filter(|_| g.material.trim() == library_gear.material.trim())
    };
    if spec.has_gear() {
        proposal.workpiece = Some(WorkpieceRef {
            part_number: part.to_string(),
            provenance,
            supplied_gear: false,
            differs: gear_differences(&spec.gear, &library_gear),
        });
        return Ok(Ok(WithGear {
            req: req.clone(),
            hardness_hb: hardness(&spec.gear),
        }));
    }
    if let Some(missing) = history::workpiece_lacks_class_data(&record, !spec.units.is_empty()) {
        let class = record
            .get("class")
            .and_then(|v| v.as_str())
            .unwrap_or_default();
        return Ok(Err(err(
            "WORKPIECE_INCOMPLETE",
            "gear",
            format!("a [gear] section with {missing}"),
            format!("part number {part:?}: a {class} workpiece without {missing}"),
            format!("the workpiece library has no {missing} of {part}; give the job's [gear] section in full"),
        )));
    }
    proposal.workpiece = Some(WorkpieceRef {
        part_number: part.to_string(),
        provenance,
        supplied_gear: true,
        differs: Vec::new(),
    });
    let hardness_hb = hardness(&library_gear);
    let mut req = req.clone();
    req.spec.gear = library_gear;
    Ok(Ok(WithGear { req, hardness_hb }))
}

fn inline_hob(h: &HobSpec, errors: &mut Vec<JobError>) -> Option<HobData> {
    // Every missing field is reported, not only the first.
    fn need<T>(v: Option<T>, field: &str, errors: &mut Vec<JobError>) -> Option<T> {
        if v.is_none() {
            errors.push(err(
                "HOB_FIELD_MISSING",
                &format!("hob.{field}"),
                "a value (inline hob data needs starts, od_mm, module_mm, lead_angle_deg, hand, length_mm)",
                "nothing",
                format!("inline hob data is incomplete: add hob.{field}, or give hob.id from the library instead"),
            ));
        }
        v
    }
    let starts = need(h.starts, "starts", errors);
    let od = need(h.od_mm, "od_mm", errors);
    let module = need(h.module_mm, "module_mm", errors);
    let lead = need(h.lead_angle_deg, "lead_angle_deg", errors);
    let hand = need(h.hand, "hand", errors);
    let length = need(h.length_mm, "length_mm", errors);
    Some(HobData {
        id: "inline".into(),
        starts: starts?,
        od_mm: od?,
        module_mm: module?,
        pressure_angle_deg: h.pressure_angle_deg.unwrap_or(20.0),
        lead_angle_deg: lead?,
        hand: hand?,
        length_mm: length?,
        source: Source::Job,
    })
}

fn resolve_hob(
    conn: &Connection,
    req: &JobRequest,
    machine: &MachineProfile,
    errors: &mut Vec<JobError>,
    proposal: &mut Proposal,
) -> Result<Option<Resolved>, KnowledgeError> {
    let spec = &req.spec;
    let h = &spec.hob;
    let library = |l: LibraryHob| Resolved {
        data: l.data,
        material: Some(l.material),
        coating: Some(l.coating),
    };
    match (&h.id, h.has_inline_data()) {
        (Some(id), true) => {
            errors.push(err(
                "HOB_AMBIGUOUS",
                "hob",
                "either hob.id or inline hob data",
                format!("hob.id = {id} and inline data"),
                "give either a library hob id or the hob's data inline, not both",
            ));
            Ok(None)
        }
        (Some(id), false) => match crate::library::get(conn, &crate::library::HOBS, id.as_str())? {
            Some(r) => Ok(Some(library(history::hob_from_record(&r)))),
            None => {
                let known: Vec<String> = db::hobs(conn)?.into_iter().map(|h| h.id).collect();
                errors.push(err(
                        "UNKNOWN_HOB",
                        "hob.id",
                        format!("one of {}", known.join(", ")),
                        id.to_string(),
                        "the hob is not in the tool library; use a library id or give the hob's data inline",
                    ));
                Ok(None)
            }
        },
        (None, true) => Ok(inline_hob(h, errors).map(|data| Resolved {
            data,
            material: None,
            coating: None,
        })),
        (None, false) => {
            let g = &spec.gear;
            let hobs = history::library_hobs(conn)?;
            let need = hobmatch::Need {
                module_mm: g.module_mm,
                pressure_angle_deg: g.pressure_angle_deg,
                helix_angle_deg: g.helix_angle_deg.abs(),
                helix_hand: if g.helix_angle_deg != 0.0 {
                    g.helix_hand
                } else {
                    None
                },
                quality_grade: g.quality_grade,
                quantity: spec.job.quantity,
                max_hob_od_mm: machine.limits.max_hob_od_mm,
                max_swivel_deg: machine.limits.max_swivel_deg,
            };
            let plain: Vec<hobmatch::Hob> = hobs.iter().map(|l| l.hob.clone()).collect();
            match hobmatch::choose(&plain, &need) {
                Ok((chosen, why)) => {
                    proposal.hob = Some(why);
                    let l = hobs
                        .into_iter()
                        .find(|l| l.hob.id == chosen.id)
                        .expect("the chosen hob is a library hob");
                    Ok(Some(library(l)))
                }
                Err(why) => {
                    let pb = g.module_mm * g.pressure_angle_deg.to_radians().cos();
                    let got = why
                        .rejected
                        .iter()
                        .map(|r| format!("{}: {}", r.id, r.reasons.join("; ")))
                        .collect::<Vec<_>>()
                        .join(" | ");
                    errors.push(err(
                        "NO_MATCHING_HOB",
                        "hob",
                        format!(
                            "a library hob with normal base pitch mn0·cos α0 = {pb:.4} mm, class for grade {}, usable length for {} parts",
                            g.quality_grade, spec.job.quantity
                        ),
                        if got.is_empty() { "an empty tool library".to_string() } else { got },
                        "no library hob fits the gear; add one (gearcam kb add hobs ...) or give the hob inline",
                    ));
                    proposal.hob = Some(why);
                    Ok(None)
                }
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::library;
    use approx::assert_abs_diff_eq;
    use gearcam_proto::{JobSpec, MachineId, ProcessOverrides};
    use serde_json::json;

    /// A left-hand helical gear, module 3, 16MnCr5, grade 7 (built from JSON so
    /// the test does not depend on every optional field of the job file).
    pub(crate) fn request(hob: serde_json::Value, process: serde_json::Value) -> JobRequest {
        let spec: JobSpec = serde_json::from_value(json!({
            "job": {"machine": "H01", "quantity": 20, "part_number": "P-1"},
            "gear": {"module_mm": 3.0, "teeth": 25, "helix_angle_deg": 15.0,
                     "helix_hand": "left", "face_width_mm": 30.0, "material": "16MnCr5",
                     "quality_grade": 7, "fixture_height_mm": 100.0},
            "hob": hob,
            "process": process,
        }))
        .unwrap();
        JobRequest {
            job_id: gearcam_proto::JobId::new("J1").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec,
        }
    }

    #[test]
    fn proposes_cutting_data_from_the_most_similar_cases_with_provenance() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan(&conn, &request(json!({}), json!({}))).unwrap();
        // Module 3 case-hardening steel first; then module 4 (ln(4/3) < ln(3/2)), then 2.
        let ids: Vec<&str> = plan.cases.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(ids, ["SEED-CASE-M3", "SEED-CASE-M4", "SEED-CASE-M2"]);
        let s0 = plan.cases[0].similarity;
        assert!(s0 > 0.7 && s0 < 1.0, "{s0}");
        assert!(plan.cases[0].provenance.contains("engineering estimate"));
        let vc = plan.values["cutting_speed_m_min"];
        assert_eq!(vc.source, Source::Case);
        assert_abs_diff_eq!(vc.value, 90.0, epsilon = 1e-9);
        assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Case);
        assert_abs_diff_eq!(plan.values["feed_mm_per_rev"].value, 2.0, epsilon = 0.01);
        assert_eq!(plan.values["cuts"].source, Source::Case);
        assert_eq!(plan.values["safety_mm"].source, Source::Machine);
        // Confidence = best similarity × mean confidence of the seed cases (0.5).
        assert_abs_diff_eq!(plan.confidence, s0 * 0.5, epsilon = 1e-9);
        assert_eq!(plan.process.cut_mode, CutMode::Conventional);
        // Hob matching: module 3 at 20°, the left-hand AA hob for a left-hand grade-7 gear.
        assert_eq!(plan.hob.id, "HOB-M3-80L");
        let why = plan.proposal.hob.as_ref().unwrap();
        assert!(
            why.reason.contains("class AA fits grade 7"),
            "{}",
            why.reason
        );
        let m2 = why.rejected.iter().find(|r| r.id == "HOB-M2-70").unwrap();
        assert!(m2.reasons[0].contains("normal base pitch"), "{m2:?}");
        let a = why
            .rejected
            .iter()
            .find(|r| r.id == "HOB-M3-100-2")
            .unwrap();
        assert!(a.reasons[0].contains("class A too coarse"), "{a:?}");
        assert!(plan.proposal.overridden.is_empty());
        assert_eq!(plan.proposal.weights["module"], 3.0);
        // Every decided value has one of the documented sources.
        for (name, v) in &plan.values {
            assert!(
                matches!(
                    v.source,
                    Source::Job | Source::Case | Source::Machine | Source::Default
                ),
                "{name}: {:?}",
                v.source
            );
        }
    }

    #[test]
    fn a_job_on_the_fanuc_machine_h02_gets_the_general_cases_as_on_h01() {
        let conn = db::open_in_memory().unwrap();
        let h01 = plan(&conn, &request(json!({}), json!({}))).unwrap();
        let mut req = request(json!({}), json!({}));
        req.spec.job.machine = MachineId::new("H02").unwrap();
        let h02 = plan(&conn, &req).unwrap();
        assert_eq!(h02.machine, crate::seed::seed_machine_h02());
        assert_eq!(h02.machine.dialect, gearcam_proto::Dialect::Fanuc);
        // The seed cases name no machine, so they fit both machines alike.
        assert_eq!(h02.cases, h01.cases);
        assert_eq!(h02.values["cutting_speed_m_min"].source, Source::Case);
        assert_eq!(
            h02.values["safety_mm"],
            Sourced {
                value: 3.0,
                source: Source::Machine
            }
        );
    }

    #[test]
    fn a_case_cut_on_h02_ranks_first_for_h02_jobs_only() {
        let conn = db::open_in_memory().unwrap();
        let rec = record(json!({
            "id": "SHOP-H02-1",
            "machine": "H02",
            "material": "20CrMnTi",
            "material_group": "case_hardening_steel",
            "hardness_hb": 180.0,
            "module_mm": 3.0,
            "teeth": 30,
            "face_width_mm": 30.0,
            "quality_grade": 8,
            "hob_material": "HSS",
            "hob_coating": "TiN",
            "cutting_speed_m_min": 70.0,
            "feed_mm_per_rev": 1.6,
            "confidence": 0.9,
            "provenance": "shop history, H02",
        }));
        library::add(&conn, &library::CASES, &rec).unwrap();
        // The same problem as SEED-CASE-M3 but for the machine.
        let h01 = plan(&conn, &request(json!({}), json!({}))).unwrap();
        assert_eq!(h01.cases[0].id, "SEED-CASE-M3");
        assert_eq!(h01.cases[1].id, "SHOP-H02-1");
        assert_abs_diff_eq!(
            h01.cases[0].similarity,
            h01.cases[1].similarity,
            epsilon = 1e-6
        );
        let mut req = request(json!({}), json!({}));
        req.spec.job.machine = MachineId::new("H02").unwrap();
        let h02 = plan(&conn, &req).unwrap();
        assert_eq!(h02.cases[0].id, "SHOP-H02-1");
        assert!(h02.cases[0].similarity > h02.cases[1].similarity);
    }

    /// A library record from a JSON object.
    fn record(v: serde_json::Value) -> library::Record {
        v.as_object().cloned().expect("a JSON object")
    }

    /// A request from a job that names part `part` and gives no `[gear]`.
    fn by_part(part: &str) -> JobRequest {
        let mut req = request(json!({}), json!({}));
        req.spec.job.part_number = part.into();
        req.spec.gear = GearSpec::absent();
        req
    }

    #[test]
    fn a_job_naming_a_library_part_gets_its_drawing_data_from_the_library() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan(&conn, &by_part("SP-1001")).unwrap();
        let g = &plan.request.spec.gear;
        assert!(plan.request.spec.has_gear());
        assert_eq!((g.module_mm, g.teeth), (3.0, 25));
        assert_eq!((g.face_width_mm, g.blank_od_mm), (30.0, Some(81.0)));
        assert_eq!((g.material.as_str(), g.quality_grade), ("20CrMnTi", 7));
        assert_eq!(g.fixture_height_mm, 100.0);
        assert_eq!(plan.class, "cylindrical");
        for name in ["gear.module_mm", "gear.teeth", "gear.blank_od_mm"] {
            assert_eq!(plan.values[name].source, Source::Library, "{name}");
        }
        assert_eq!(plan.values["gear.teeth"].value, 25.0);
        let w = plan.proposal.workpiece.as_ref().unwrap();
        assert!(w.supplied_gear);
        assert_eq!(w.part_number, "SP-1001");
        assert!(w.provenance.contains("examples"), "{}", w.provenance);
        assert!(plan.proposal.overridden.is_empty());
        // The hob is matched to the library's gear (module 3, spur, grade 7).
        assert_eq!(plan.hob.id, "HOB-M3-80");
    }

    #[test]
    fn a_gear_section_wins_over_the_library_part_and_the_plan_says_where_they_differ() {
        let conn = db::open_in_memory().unwrap();
        let mut req = request(json!({}), json!({}));
        req.spec.job.part_number = "SP-1001".into();
        let plan = plan(&conn, &req).unwrap();
        assert_eq!(plan.request.spec.gear, req.spec.gear);
        assert_eq!(plan.values["gear.teeth"].source, Source::Job);
        assert_eq!(
            plan.proposal.values["gear.face_width_mm"],
            Sourced {
                value: 30.0,
                source: Source::Library
            }
        );
        assert!(plan
            .proposal
            .overridden
            .contains(&"gear.helix_angle_deg".to_string()));
        let w = plan.proposal.workpiece.as_ref().unwrap();
        assert!(!w.supplied_gear);
        // The fixture gear is a left-hand 15° helical gear of 16MnCr5 with no
        // blank OD; the record a spur gear of 20CrMnTi with a blank of 81 mm.
        assert_eq!(
            w.differs,
            [
                "gear.blank_od_mm",
                "gear.helix_angle_deg",
                "gear.material",
                "gear.helix_hand"
            ]
        );
    }

    #[test]
    fn a_job_with_neither_gear_nor_library_part_is_refused_naming_the_gear() {
        let conn = db::open_in_memory().unwrap();
        let errors = plan(&conn, &by_part("NO-SUCH-PART")).unwrap_err();
        assert_eq!(errors.len(), 1, "{errors:#?}");
        let e = &errors[0];
        assert_eq!(
            (e.code.as_str(), e.field.as_str()),
            ("GEAR_MISSING", "gear")
        );
        assert!(
            e.expected
                .starts_with("a [gear] section or a part number in the workpiece library"),
            "{}",
            e.expected
        );
        assert!(e.expected.contains("SP-1001"), "{}", e.expected);
        assert!(e.got.contains("\"NO-SUCH-PART\""), "{}", e.got);
        // With an unknown machine as well, both are reported.
        let mut req = by_part("NO-SUCH-PART");
        req.spec.job.machine = MachineId::new("H99").unwrap();
        let codes: Vec<String> = plan(&conn, &req)
            .unwrap_err()
            .into_iter()
            .map(|e| e.code)
            .collect();
        assert_eq!(codes, ["GEAR_MISSING", "UNKNOWN_MACHINE"]);
    }

    #[test]
    fn a_library_part_without_its_class_data_needs_the_gear_section() {
        let conn = db::open_in_memory().unwrap();
        let mut rec = record(json!({
            "part_number": "CR-1",
            "class": "crowned",
            "module_mm": 3.0,
            "teeth": 25,
            "face_width_mm": 30.0,
            "fixture_height_mm": 100.0,
        }));
        library::add(&conn, &library::WORKPIECES, &rec).unwrap();
        let errors = plan(&conn, &by_part("CR-1")).unwrap_err();
        assert_eq!(errors[0].code, "WORKPIECE_INCOMPLETE");
        assert!(errors[0].expected.contains("[gear.crowning]"), "{errors:?}");
        // A conical part with its cone angle is complete.
        rec.insert("part_number".into(), json!("CO-1"));
        rec.insert("class".into(), json!("conical"));
        rec.insert("cone_angle_deg".into(), json!(6.5));
        library::add(&conn, &library::WORKPIECES, &rec).unwrap();
        let p = plan(&conn, &by_part("CO-1")).unwrap();
        assert_eq!(p.class, "conical");
        assert_eq!(p.values["gear.cone.angle_deg"].value, 6.5);
    }

    /// Seed 000's bevel gear (docs/knowledge.md#case-based-reasoning): conical, mn 2, z 19, OD 42.5, 40Cr,
    /// grade 7, cone 6.5°, on the module-2 hob; `process` as given.
    fn bevel(process: serde_json::Value) -> JobRequest {
        let spec: JobSpec = serde_json::from_value(json!({
            "job": {"machine": "H01", "quantity": 10, "part_number": "CB-1901"},
            "gear": {"module_mm": 2.0, "teeth": 19, "face_width_mm": 20.0,
                     "blank_od_mm": 42.5, "material": "40Cr", "quality_grade": 7,
                     "fixture_height_mm": 100.0, "cone": {"angle_deg": 6.5}},
            "hob": {"id": "HOB-M2-70"},
            "process": process,
        }))
        .unwrap();
        JobRequest {
            job_id: gearcam_proto::JobId::new("J2").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec,
        }
    }

    #[test]
    fn seed_conical_case_gives_a_roughing_feed_to_a_finish() {
        // Issue 10: seed 000's bevel cut was a rough cut, 105 mm/min at
        // 246 rpm, 19 teeth, one start: 8.1 mm per table revolution as
        // published. A finishing job got 7.92 mm/rev from it; now the feed of
        // a finish comes only from finishing cases, else the default.
        let conn = db::open_in_memory().unwrap();
        let finish = plan(&conn, &bevel(json!({}))).unwrap();
        assert_eq!(finish.cases[0].id, "SEED000-BEVEL-CBR");
        assert_eq!(
            finish.values["feed_mm_per_rev"],
            Sourced {
                value: DEFAULT_FEED_MM_PER_REV,
                source: Source::Default
            }
        );
        // A rough job takes the published roughing feed (the mean of the two
        // seed cases, 8.11 and 7.73 mm/rev by similarity).
        let rough = plan(&conn, &bevel(json!({"operation": "rough"}))).unwrap();
        let fa = rough.values["feed_mm_per_rev"];
        assert_eq!(fa.source, Source::Case);
        assert!(fa.value > 7.7 && fa.value < 8.2, "{fa:?}");
    }

    #[test]
    fn a_rough_job_retrieves_the_rough_cases_first_and_a_finish_job_the_finish_ones() {
        let conn = db::open_in_memory().unwrap();
        // A finish case of the same bevel gear beside seed 000's two rough ones.
        let rec = record(json!({
            "id": "SHOP-BEVEL-FINISH",
            "class": "conical",
            "material": "40Cr",
            "material_group": "quenched_tempered_steel",
            "module_mm": 2.0,
            "teeth": 19,
            "quality_grade": 7,
            "hob_coating": "unknown",
            "operation": "finish",
            "cutting_speed_m_min": 60.0,
            "feed_mm_per_rev": 1.0,
            "confidence": 0.6,
            "provenance": "test: a finishing cut",
        }));
        library::add(&conn, &library::CASES, &rec).unwrap();

        let rough = plan(&conn, &bevel(json!({"operation": "rough"}))).unwrap();
        let ids: Vec<&str> = rough.cases.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(
            ids,
            [
                "SEED000-BEVEL-CBR",
                "SEED000-BEVEL-HAND",
                "SHOP-BEVEL-FINISH"
            ]
        );
        assert_eq!(
            rough.values["operation_rough"],
            Sourced {
                value: 1.0,
                source: Source::Job
            }
        );
        assert_eq!(rough.proposal.overridden, ["operation_rough"]);
        // Seed 000's rough cut leaves 2.5 mm of stock.
        assert_eq!(rough.values["allowance_mm"].value, 2.5);

        // The same job, finish by default: the finish case first.
        let finish = plan(&conn, &bevel(json!({}))).unwrap();
        assert_eq!(finish.cases[0].id, "SHOP-BEVEL-FINISH");
        assert_eq!(
            finish.values["operation_rough"],
            Sourced {
                value: 0.0,
                source: Source::Default
            }
        );
        assert!(finish.proposal.overridden.is_empty());
        let seed_sim = |p: &ProcessPlan| {
            p.cases
                .iter()
                .find(|c| c.id == "SEED000-BEVEL-CBR")
                .unwrap()
                .similarity
        };
        assert!(seed_sim(&rough) > seed_sim(&finish));
        // Said explicitly, finish is the job's.
        let said = plan(&conn, &bevel(json!({"operation": "finish"}))).unwrap();
        assert_eq!(said.cases, finish.cases);
        assert_eq!(said.values["operation_rough"].source, Source::Job);
    }

    #[test]
    fn overrides_win_and_the_plan_records_what_was_proposed() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan(
            &conn,
            &request(
                json!({}),
                json!({"cutting_speed_m_min": 70.0, "feed_mm_per_rev": 1.2, "cut_mode": "climb"}),
            ),
        )
        .unwrap();
        assert_eq!(
            plan.values["cutting_speed_m_min"],
            Sourced {
                value: 70.0,
                source: Source::Job
            }
        );
        assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Job);
        assert_eq!(plan.process.cutting_speed_m_min, 70.0);
        assert_eq!(plan.process.feed_mm_per_rev, 1.2);
        assert_eq!(plan.process.cut_mode, CutMode::Climb);
        assert_eq!(
            plan.proposal.values["cutting_speed_m_min"].source,
            Source::Case
        );
        assert_abs_diff_eq!(
            plan.proposal.values["cutting_speed_m_min"].value,
            90.0,
            epsilon = 1e-9
        );
        assert_eq!(
            plan.proposal.overridden,
            ["cutting_speed_m_min", "feed_mm_per_rev", "cut_mode_climb"]
        );
        // The number of cuts still comes from the cases, so they are listed.
        assert_eq!(plan.values["cuts"].source, Source::Case);
        assert!(!plan.cases.is_empty());
    }

    #[test]
    fn a_job_that_overrides_every_case_value_lists_no_cases() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan(
            &conn,
            &request(
                json!({"id": "HOB-M3-80L"}),
                json!({"cutting_speed_m_min": 70.0, "feed_mm_per_rev": 1.2,
                       "cut_mode": "climb", "cuts": 1}),
            ),
        )
        .unwrap();
        assert!(plan.cases.is_empty());
        assert_eq!(plan.confidence, 1.0);
        assert!(plan.proposal.hob.is_none(), "a named hob is not matched");
        assert_eq!(plan.proposal.overridden.len(), 4);
    }

    #[test]
    fn a_proposal_above_the_machines_hob_speed_is_clamped_to_the_machine() {
        let conn = db::open_in_memory().unwrap();
        let mut set = library::Record::new();
        set.insert("limits.max_hob_rpm".into(), json!(300.0));
        library::edit(&conn, &library::MACHINES, "H01", &set).unwrap();
        let plan = plan(&conn, &request(json!({}), json!({}))).unwrap();
        // 300 rpm on an 80 mm hob: vc ≤ 300·π·80/1000 = 75.398 m/min; the
        // 90 m/min cases fail that hard constraint, the default is clamped.
        let vc = plan.values["cutting_speed_m_min"];
        assert_eq!(vc.source, Source::Machine);
        assert_abs_diff_eq!(
            vc.value,
            300.0 * std::f64::consts::PI * 80.0 / 1000.0,
            epsilon = 1e-9
        );
        assert!(plan.cases.is_empty());
        assert_eq!(plan.values["feed_mm_per_rev"].source, Source::Default);
        assert_eq!(plan.confidence, DEFAULT_CONFIDENCE);
    }

    #[test]
    fn an_unknown_material_gets_defaults_and_low_confidence() {
        let conn = db::open_in_memory().unwrap();
        let mut req = request(json!({}), json!({}));
        req.spec.gear.material = "unobtainium".into();
        let plan = plan(&conn, &req).unwrap();
        assert_eq!(plan.values["cutting_speed_m_min"].source, Source::Default);
        assert_eq!(
            plan.values["cutting_speed_m_min"].value,
            DEFAULT_CUTTING_SPEED_M_MIN
        );
        assert_eq!(plan.confidence, DEFAULT_CONFIDENCE);
    }

    #[test]
    fn no_fitting_hob_names_every_rejection() {
        let conn = db::open_in_memory().unwrap();
        let mut req = request(json!({}), json!({}));
        req.spec.gear.module_mm = 5.0;
        let errors = plan(&conn, &req).unwrap_err();
        assert_eq!(errors[0].code, "NO_MATCHING_HOB");
        assert!(
            errors[0].got.contains("HOB-M4-90: normal base pitch"),
            "{}",
            errors[0].got
        );
    }

    #[test]
    fn unknown_machine_and_hob_errors_name_the_field_and_the_choices() {
        let conn = db::open_in_memory().unwrap();
        let mut req = request(json!({"id": "NOPE"}), json!({}));
        let errors = plan(&conn, &req).unwrap_err();
        assert_eq!(
            (errors[0].code.as_str(), errors[0].field.as_str()),
            ("UNKNOWN_HOB", "hob.id")
        );
        assert!(
            errors[0].expected.contains("HOB-M3-80"),
            "{}",
            errors[0].expected
        );
        req.spec.job.machine = MachineId::new("H99").unwrap();
        let errors = plan(&conn, &req).unwrap_err();
        assert_eq!(
            (errors[0].code.as_str(), errors[0].expected.as_str()),
            ("UNKNOWN_MACHINE", "one of H01, H02")
        );
    }

    #[test]
    fn incomplete_inline_hob_lists_every_missing_field() {
        let conn = db::open_in_memory().unwrap();
        let req = request(json!({"starts": 1, "od_mm": 80.0}), json!({}));
        let errors = plan(&conn, &req).unwrap_err();
        let fields: Vec<&str> = errors.iter().map(|e| e.field.as_str()).collect();
        assert_eq!(
            fields,
            [
                "hob.module_mm",
                "hob.lead_angle_deg",
                "hob.hand",
                "hob.length_mm"
            ]
        );
        assert!(errors.iter().all(|e| e.code == "HOB_FIELD_MISSING"));
    }

    #[test]
    fn a_hob_id_with_inline_data_is_ambiguous() {
        let conn = db::open_in_memory().unwrap();
        let req = request(json!({"id": "HOB-M3-80", "od_mm": 80.0}), json!({}));
        let errors = plan(&conn, &req).unwrap_err();
        assert_eq!(errors[0].code, "HOB_AMBIGUOUS");
        let _ = ProcessOverrides::default();
    }

    #[test]
    fn the_database_file_is_created_once_and_reopened_without_reseeding() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("kb/knowledge.db");
        let conn = db::open(&path).unwrap();
        assert_eq!(db::hobs(&conn).unwrap().len(), 5);
        assert_eq!(db::schema_version(&conn).unwrap(), 4);
        let n = library::list(&conn, &library::CASES).unwrap().len();
        assert_eq!(n, 14);
        drop(conn);
        let conn = db::open(&path).unwrap();
        assert_eq!(db::hobs(&conn).unwrap().len(), 5);
        assert_eq!(library::list(&conn, &library::CASES).unwrap().len(), n);
        assert_eq!(
            db::machines(&conn).unwrap()[0],
            crate::seed::seed_machine_h01()
        );
    }
}
