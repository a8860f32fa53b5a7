//! From a job request to a process plan: machine, hob (matched and
//! explained), cutting data proposed by case-based reasoning and adapted to
//! the machine, the job's overrides on top, every value with its source.
//!
//! Sources of the decided values: `job` (the job file overrides), `case`
//! (retrieved and adapted cases, [`crate::cbr`]), `machine` (the machine
//! profile, or a proposal clamped to the machine's limits), `default`
//! (gearcam's documented defaults when no case applies), `grade` (a
//! finishing feed held to what the drawing's class allows,
//! [`feed_marks`]) and `library` (the drawing data `gear.*` of a job that
//! names its part instead of giving a `[gear]` section; the plan's request
//! carries the filled gear).
//!
//! # Steps
//!
//! 1. `resolve_gear_and_machine`: the drawing data (the job's `[gear]`, or
//!    the workpiece library's part) and the machine profile;
//! 2. `choose_hob`: the named library hob, the job's inline hob, or the
//!    library hob matched to the gear ([`crate::hobmatch`]);
//! 3. `retrieval_problem` and `retrieve_cases`: the job as a retrieval
//!    problem and the cases most similar to it;
//! 4. `propose_values`: the adapted cases' values, else the defaults,
//!    within the machine's limits (`within_machine_limits`);
//! 5. `apply_overrides`: the job's own values on top; then the finishing
//!    feed held to the drawing's class ([`feed_marks::hold_finishing_feed`]);
//! 6. `cases_used` and `assemble`: the plan with its cases and confidence.

use gearcam_proto::Code;
use std::collections::BTreeMap;

use gearcam_proto::plan::Proposal;
use gearcam_proto::{
    CaseRef, CutMode, Family, GearClass, GearSpec, HobData, HobSpec, HobbingSpec, JobError,
    JobRequest, JobSpec, MachineProfile, ProcessData, ProcessOverrides, ProcessPlan, Source,
    Sourced, Stage, WorkpieceRef,
};
use rusqlite::Connection;

use crate::cbr::{self, Adapted, CaseBase, Hit, Limits, Problem, Weights};
use crate::history;
use crate::hobmatch;
use crate::library;
use crate::records::{self, HobRecord, MaterialRecord};
use crate::KnowledgeError;

pub mod feed_marks;
mod limits;

use limits::within_machine_limits;

/// Cutting speed when no case applies, m/min: an engineering estimate for
/// HSS hobs in steel, deliberately low.
pub const DEFAULT_CUTTING_SPEED_M_MIN: f64 = 80.0;
/// Feed per workpiece revolution when no case applies, mm/rev (engineering estimate).
pub const DEFAULT_FEED_MM_PER_REV: f64 = 1.8;
/// Confidence of a proposal made of defaults only.
pub const DEFAULT_CONFIDENCE: f64 = 0.2;

/// The values cases propose; a job that sets every one of them uses no case.
const CASE_VALUES: [&str; 4] = [
    "cutting_speed_m_min",
    "feed_mm_per_rev",
    "cuts",
    "cut_mode_climb",
];

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
    vec![Stage::Knowledge.error(
        Code::KNOWLEDGE_BASE_ERROR,
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

/// The plan, step by step (see the module docs).
fn plan_inner(
    conn: &Connection,
    cases: &CaseBase,
    req: &JobRequest,
) -> Result<ProcessPlan, PlanError> {
    // The hobbing sections: a job of another family is not planned here.
    let h = crate::sections::sections(req, Family::Hobbing, JobSpec::hobbing)
        .map_err(|e| PlanError::Job(vec![e]))?;
    let mut proposal = Proposal::default();
    // The drawing data first: every later step reads the resolved gear; the
    // plan carries it beside the request as it was asked.
    let (WithGear { gear, hardness_hb }, machine) =
        resolve_gear_and_machine(conn, req, h, &mut proposal)?;
    let class = gearcam_proto::classify(&gear, &h.units);
    let hob = choose_hob(conn, req, h, &gear, &machine, &mut proposal)?;
    // What retrieval reads of the knowledge base is read before the job's
    // hob errors are reported: a knowledge base that cannot be read is
    // reported first.
    let material = records::material(conn, &gear.material)?;
    let weights = history::load_weights(conn)?;
    let hob = hob.map_err(PlanError::Job)?;

    let problem = retrieval_problem(
        h,
        &gear,
        class,
        &machine,
        &hob,
        material.as_ref(),
        hardness_hb,
    );
    proposal.weights = weights.to_map();
    let hits = retrieve_cases(
        cases,
        &problem,
        &weights,
        &machine,
        &hob.data,
        material.is_some(),
    );
    let adapted = cbr::adapt(cases, &hits, &problem);
    let proposed = propose_values(
        &mut proposal,
        adapted.as_ref(),
        &machine,
        &hob.data,
        gear.teeth,
    );
    let mut values = apply_overrides(&mut proposal, h);
    let bound = feed_marks::max_feed_mm_per_rev(&gear, class, &hob.data);
    feed_marks::hold_finishing_feed(bound, &mut proposal, &mut values, &h.process);
    let used = cases_used(cases, &hits, &values);
    Ok(assemble(
        req.clone(),
        &h.process,
        Resolved {
            gear,
            class,
            machine,
            hob: hob.data,
        },
        proposed,
        values,
        used,
        proposal,
    ))
}

/// The drawing data of a request, resolved.
struct WithGear {
    /// The job's `[gear]`, or the workpiece library's record of its part.
    gear: GearSpec,
    /// The part's hardness from the workpiece library, when the record gives
    /// one and the gear is of the record's material.
    hardness_hb: Option<f64>,
}

/// Step 1: the request with its drawing data resolved ([`resolve_gear`])
/// and the profile of the job's machine, whose control's rule the program's
/// name must pass; when any of them cannot be had, the reasons for all (no
/// gear, an unknown machine, a name the control refuses) at once.
fn resolve_gear_and_machine(
    conn: &Connection,
    req: &JobRequest,
    h: &HobbingSpec,
    proposal: &mut Proposal,
) -> Result<(WithGear, MachineProfile), PlanError> {
    let resolved = resolve_gear(conn, req, h, proposal)?;
    let machine = records::machine(conn, &req.spec.job.machine)?;
    // The program's name by the control's rule, before anything is planned.
    let name = machine.as_ref().and_then(|m| {
        gearcam_proto::naming::name_error(m.dialect, &req.spec.job, false, Stage::Knowledge)
    });
    match (resolved, machine, name) {
        (Ok(with_gear), Some(machine), None) => Ok((with_gear, machine)),
        (resolved, machine, name) => {
            let mut errors: Vec<JobError> = resolved.err().into_iter().chain(name).collect();
            if machine.is_none() {
                errors.push(library::machine_error(
                    conn,
                    req.spec.job.machine.as_str(),
                    "hobbing",
                )?);
            }
            Err(PlanError::Job(errors))
        }
    }
}

/// The request with its drawing data resolved: the job's `[gear]`, or the
/// workpiece library's record of its part number. Records the library's
/// part in the proposal (and its values with source `library`). The inner
/// error is the job's: no gear and no library part.
fn resolve_gear(
    conn: &Connection,
    req: &JobRequest,
    h: &HobbingSpec,
    proposal: &mut Proposal,
) -> Result<Result<WithGear, JobError>, KnowledgeError> {
    let spec = &req.spec;
    let part = spec.job.part_number.trim();
    let Some(record) = records::workpiece(conn, part)? else {
        if let Some(gear) = &h.gear {
            return Ok(Ok(WithGear {
                gear: gear.clone(),
                hardness_hb: None,
            }));
        }
        let known: Vec<String> = library::keys(conn, &library::WORKPIECES)?
            .into_iter()
            .take(20)
            .collect();
        return Ok(Err(Stage::Knowledge.error(
            Code::GEAR_MISSING,
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
            .hardness_hb
            .filter(|_| g.material.trim() == library_gear.material.trim())
    };
    if let Some(gear) = &h.gear {
        proposal.workpiece = Some(WorkpieceRef {
            part_number: part.to_string(),
            provenance: record.source.clone(),
            supplied_gear: false,
            differs: gear_differences(gear, &library_gear),
        });
        return Ok(Ok(WithGear {
            gear: gear.clone(),
            hardness_hb: hardness(gear),
        }));
    }
    if let Some(missing) = history::workpiece_lacks_class_data(&record, !h.units.is_empty()) {
        let class = record.class.as_str();
        return Ok(Err(Stage::Knowledge.error(
            Code::WORKPIECE_INCOMPLETE,
            "gear",
            format!("a [gear] section with {missing}"),
            format!("part number {part:?}: a {class} workpiece without {missing}"),
            format!("the workpiece library has no {missing} of {part}; give the job's [gear] section in full"),
        )));
    }
    proposal.workpiece = Some(WorkpieceRef {
        part_number: part.to_string(),
        provenance: record.source.clone(),
        supplied_gear: true,
        differs: Vec::new(),
    });
    let hardness_hb = hardness(&library_gear);
    Ok(Ok(WithGear {
        gear: library_gear,
        hardness_hb,
    }))
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
    let theirs: BTreeMap<&str, f64> = gear_values(record).into_iter().collect();
    let ours: BTreeMap<&str, f64> = gear_values(job).into_iter().collect();
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

/// The job's hob as resolved: its data for the plan, and its library record
/// when it is a library hob (retrieval compares its material and coating).
struct JobHob {
    data: HobData,
    record: Option<HobRecord>,
}

impl JobHob {
    fn library(record: HobRecord) -> JobHob {
        JobHob {
            data: record.data(),
            record: Some(record),
        }
    }

    fn inline(data: HobData) -> JobHob {
        JobHob { data, record: None }
    }
}

/// The outcome of a step that the job's own data can make fail: the job's
/// errors inside, a knowledge base that cannot be read outside.
type JobOutcome<T> = Result<Result<T, Vec<JobError>>, KnowledgeError>;

/// Step 2: the hob. The library hob the job names, the job's inline hob
/// data, or else the library hob matched to the gear and the machine
/// ([`match_hob`]). The job's errors: both an id and inline data, an
/// unknown id, incomplete inline data, or no library hob that fits.
fn choose_hob(
    conn: &Connection,
    req: &JobRequest,
    job: &HobbingSpec,
    gear: &GearSpec,
    machine: &MachineProfile,
    proposal: &mut Proposal,
) -> JobOutcome<JobHob> {
    let h = &job.hob;
    match (&h.id, h.has_inline_data()) {
        (Some(id), true) => Ok(Err(vec![Stage::Knowledge.error(
            Code::HOB_AMBIGUOUS,
            "hob",
            "either hob.id or inline hob data",
            format!("hob.id = {id} and inline data"),
            "give either a library hob id or the hob's data inline, not both",
        )])),
        (Some(id), false) => match records::hob(conn, id.as_str())? {
            Some(r) => Ok(Ok(JobHob::library(r))),
            None => {
                let known = library::keys(conn, &library::HOBS)?;
                Ok(Err(vec![Stage::Knowledge.error(
                    Code::UNKNOWN_HOB,
                    "hob.id",
                    format!("one of {}", known.join(", ")),
                    id.to_string(),
                    "the hob is not in the tool library; use a library id or give the hob's data inline",
                )]))
            }
        },
        (None, true) => Ok(inline_hob(h).map(JobHob::inline)),
        (None, false) => match_hob(conn, gear, req.spec.job.quantity, machine, proposal),
    }
}

/// The job's inline hob data, or every field it lacks (not only the first).
fn inline_hob(h: &HobSpec) -> Result<HobData, Vec<JobError>> {
    fn need<T>(v: Option<T>, field: &str, errors: &mut Vec<JobError>) -> Option<T> {
        if v.is_none() {
            errors.push(Stage::Knowledge.error(
                Code::HOB_FIELD_MISSING,
                &format!("hob.{field}"),
                "a value (inline hob data needs starts, od_mm, module_mm, lead_angle_deg, hand, length_mm)",
                "nothing",
                format!("inline hob data is incomplete: add hob.{field}, or give hob.id from the library instead"),
            ));
        }
        v
    }
    let mut errors = Vec::new();
    let starts = need(h.starts, "starts", &mut errors);
    let od = need(h.od_mm, "od_mm", &mut errors);
    let module = need(h.module_mm, "module_mm", &mut errors);
    let lead = need(h.lead_angle_deg, "lead_angle_deg", &mut errors);
    let hand = need(h.hand, "hand", &mut errors);
    let length = need(h.length_mm, "length_mm", &mut errors);
    match (starts, od, module, lead, hand, length) {
        (
            Some(starts),
            Some(od_mm),
            Some(module_mm),
            Some(lead_angle_deg),
            Some(hand),
            Some(length_mm),
        ) => Ok(HobData {
            id: "inline".into(),
            starts,
            od_mm,
            module_mm,
            pressure_angle_deg: h.pressure_angle_deg.unwrap_or(20.0),
            lead_angle_deg,
            hand,
            length_mm,
            usable_length_mm: None,
            source: Source::Job,
        }),
        _ => Err(errors),
    }
}

/// Matches a library hob to the gear and the machine ([`hobmatch::choose`])
/// and records the choice explained, or every rejection, in the proposal.
fn match_hob(
    conn: &Connection,
    g: &GearSpec,
    quantity: u32,
    machine: &MachineProfile,
    proposal: &mut Proposal,
) -> JobOutcome<JobHob> {
    let hobs = records::hobs(conn)?;
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
        quantity,
        max_hob_od_mm: machine.limits.max_hob_od_mm,
        max_swivel_deg: machine.limits.max_swivel_deg,
    };
    match hobmatch::choose(&hobs, &need) {
        Ok((chosen, why)) => {
            proposal.hob = Some(why);
            Ok(Ok(JobHob::library(chosen)))
        }
        Err(why) => {
            let pb = g.module_mm * g.pressure_angle_deg.to_radians().cos();
            let got = why
                .rejected
                .iter()
                .map(|r| format!("{}: {}", r.id, r.reasons.join("; ")))
                .collect::<Vec<_>>()
                .join(" | ");
            let e = Stage::Knowledge.error(
                Code::NO_MATCHING_HOB,
                "hob",
                format!(
                    "a library hob with normal base pitch mn0·cos α0 = {pb:.4} mm, class for grade {}, usable length for {} parts",
                    g.quality_grade, quantity
                ),
                if got.is_empty() { "an empty tool library".to_string() } else { got },
                "no library hob fits the gear; add one (gearcam kb add hobs ...) or give the hob inline",
            );
            proposal.hob = Some(why);
            Ok(Err(vec![e]))
        }
    }
}

/// Step 3: the job as a retrieval problem. The part's own hardness when the
/// workpiece library knows it, else the material's typical one; the hob's
/// material and coating when it is a library hob (unknown for an inline
/// one); finish hobbing unless the job says rough.
fn retrieval_problem(
    job: &HobbingSpec,
    g: &GearSpec,
    class: GearClass,
    machine: &MachineProfile,
    hob: &JobHob,
    material: Option<&MaterialRecord>,
    hardness_hb: Option<f64>,
) -> Problem {
    Problem {
        class: class.to_string(),
        material: g.material.trim().to_string(),
        // Only read when the material is known: retrieval needs its group.
        material_group: material
            .map(|m| m.material_group.clone())
            .unwrap_or_default(),
        hardness_hb: hardness_hb.or_else(|| material.and_then(|m| m.hardness_hb)),
        module_mm: g.module_mm,
        teeth: g.teeth,
        helix_angle_deg: g.helix_angle_deg.abs(),
        face_width_mm: Some(g.face_width_mm),
        quality_grade: g.quality_grade,
        hob_material: hob.record.as_ref().map(|h| h.material.clone()),
        hob_coating: hob.record.as_ref().map(|h| h.coating.clone()),
        hob_starts: hob.data.starts,
        // `[process] operation`; a job that does not say finishes the flanks.
        operation: job.process.operation.unwrap_or_default().into(),
        machine: Some(machine.id.to_string()),
    }
}

/// Step 3: the cases most similar to the job ([`CaseBase::retrieve`]),
/// among those the machine can cut with the job's hob; none for a material
/// the knowledge base does not know or a module that is not a positive
/// number.
fn retrieve_cases(
    cases: &CaseBase,
    problem: &Problem,
    weights: &Weights,
    machine: &MachineProfile,
    hob: &HobData,
    material_known: bool,
) -> Vec<Hit> {
    let limits = Limits {
        max_cutting_speed_m_min: machine.limits.max_hob_rpm * std::f64::consts::PI * hob.od_mm
            / 1000.0,
    };
    if material_known && problem.module_mm > 0.0 && problem.module_mm.is_finite() {
        cases.retrieve(problem, &limits, weights, cbr::TOP_K)
    } else {
        Vec::new()
    }
}

/// What the knowledge base proposes beyond the values themselves.
struct Proposed {
    /// The proposed cutting mode.
    cut_mode: CutMode,
    /// Confidence of the proposal.
    confidence: f64,
}

/// Step 4: the proposal, every value with its source: the adapted cases'
/// cutting speed, feed, cuts and cutting mode, each else gearcam's default;
/// cutting speed and feed within the machine's limits; the machine's
/// safety distance; finish unless the job says rough; the cases' radial
/// feed and allowance when they have them.
fn propose_values(
    proposal: &mut Proposal,
    adapted: Option<&Adapted>,
    machine: &MachineProfile,
    hob: &HobData,
    teeth: u32,
) -> Proposed {
    let sourced = |value: f64, source: Source| Sourced { value, source };
    let mut vc = match adapted {
        Some(a) => sourced(a.cutting_speed_m_min, Source::Case),
        None => sourced(DEFAULT_CUTTING_SPEED_M_MIN, Source::Default),
    };
    let mut fa = match adapted.and_then(|a| a.feed_mm_per_rev) {
        Some(fa) => sourced(fa, Source::Case),
        None => sourced(DEFAULT_FEED_MM_PER_REV, Source::Default),
    };
    let cuts = match adapted {
        Some(a) => sourced(f64::from(a.cuts), Source::Case),
        None => sourced(1.0, Source::Default),
    };
    let (mode, mode_source) = match adapted.and_then(|a| a.cut_mode) {
        Some(m) => (m, Source::Case),
        None => (CutMode::Conventional, Source::Default),
    };
    let confidence = adapted.map_or(DEFAULT_CONFIDENCE, |a| a.confidence);
    within_machine_limits(&mut vc, &mut fa, machine, hob, teeth);

    let values = &mut proposal.values;
    let mut prop = |name: &str, value: Sourced| {
        values.insert(name.to_string(), value);
    };
    prop("cutting_speed_m_min", vc);
    prop("feed_mm_per_rev", fa);
    prop("cuts", cuts);
    prop(
        "cut_mode_climb",
        sourced(f64::from(u8::from(mode == CutMode::Climb)), mode_source),
    );
    prop(
        "safety_mm",
        sourced(machine.settings.safety_mm, Source::Machine),
    );
    // Rough or finish is the job's to say; finish unless it does.
    prop("operation_rough", sourced(0.0, Source::Default));
    if let Some(a) = adapted {
        if let Some(r) = a.radial_feed_mm_min {
            prop("radial_feed_mm_min", sourced(r, Source::Case));
        }
        if let Some(x) = a.allowance_mm {
            prop("allowance_mm", sourced(x, Source::Case));
        }
    }
    Proposed {
        cut_mode: mode,
        confidence,
    }
}

/// Step 5: the decided values, the job's overrides on top of the proposal.
/// A job that names a library part and gives its own `[gear]` overrides the
/// record's drawing data as a whole; then every process value the job sets.
/// The names of the proposed values the job overrode go into the proposal.
fn apply_overrides(proposal: &mut Proposal, spec: &HobbingSpec) -> BTreeMap<String, Sourced> {
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
    let job_gear = if proposal
        .workpiece
        .as_ref()
        .is_some_and(|w| !w.supplied_gear)
    {
        spec.gear.as_ref().map(gear_values).unwrap_or_default()
    } else {
        Vec::new()
    };
    let mut values = proposal.values.clone();
    let set = job_gear
        .into_iter()
        .chain(overrides.into_iter().filter_map(|(n, v)| Some((n, v?))));
    for (name, value) in set {
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
    values
}

/// Step 6: the retrieved cases the plan's values come from, with their
/// similarity; `None` when the job set every value cases propose
/// ([`CASE_VALUES`]), so no case was used.
fn cases_used(
    cases: &CaseBase,
    hits: &[Hit],
    values: &BTreeMap<String, Sourced>,
) -> Option<Vec<CaseRef>> {
    let from_kb = CASE_VALUES.iter().any(|n| values[*n].source != Source::Job);
    from_kb.then(|| {
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
    })
}

/// What the plan is for, decided once: the gear, its class, the machine
/// and the hob.
struct Resolved {
    gear: GearSpec,
    class: GearClass,
    machine: MachineProfile,
    hob: HobData,
}

/// Step 6: the plan. Its process data are the decided values (the job's
/// cutting mode, else the proposed one); its confidence is the proposal's
/// when cases or defaults gave a value, 1 when the job set them all.
fn assemble(
    req: JobRequest,
    p: &ProcessOverrides,
    resolved: Resolved,
    proposed: Proposed,
    values: BTreeMap<String, Sourced>,
    cases: Option<Vec<CaseRef>>,
    proposal: Proposal,
) -> ProcessPlan {
    let value = |name: &str| values[name].value;
    let process = ProcessData {
        cut_mode: p.cut_mode.unwrap_or(proposed.cut_mode),
        cuts: value("cuts") as u32,
        cutting_speed_m_min: value("cutting_speed_m_min"),
        feed_mm_per_rev: value("feed_mm_per_rev"),
        depth_mm: p.depth_mm,
        safety_mm: value("safety_mm"),
    };
    let confidence = if cases.is_some() {
        proposed.confidence
    } else {
        1.0
    };
    ProcessPlan {
        job_id: req.job_id.clone(),
        class: resolved.class,
        gear: resolved.gear,
        request: req,
        machine: resolved.machine,
        hob: resolved.hob,
        process,
        values,
        cases: cases.unwrap_or_default(),
        confidence,
        proposal,
    }
}

#[cfg(test)]
pub(crate) mod tests;
