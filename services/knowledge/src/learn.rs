//! The learning loop: the knowledge service records every job it plans and
//! every delivery it hears of; after delivery the planner confirms the job
//! with the values actually used and the outcome, and the job becomes a case.
//! The hob's shift position and remaining life move on by the quantity cut.

use gearcam_proto::Code;
use gearcam_proto::{DeliveryReceipt, ProcessPlan, Source, SpiralPart, SpiralPlan, Stage};
use rusqlite::Connection;
use serde_json::{json, Value};

use crate::hobmatch;
use crate::library::{self, Outcome, Record};
use crate::records::{self, JobClass, JobState};
use crate::KnowledgeError;

/// Records a planned job (state `planned`; a re-plan replaces the row and
/// starts the job over).
pub fn record_planned(
    conn: &Connection,
    plan: &ProcessPlan,
    at_ms: u64,
) -> Result<(), KnowledgeError> {
    record_job(
        conn,
        &Planned {
            job_id: plan.job_id.as_str(),
            part_number: &plan.request.spec.job.part_number,
            machine: plan.machine.id.as_str(),
            class: plan.class.as_str(),
            quantity: plan.request.spec.job.quantity,
            tool: &plan.hob.id,
            confidence: plan.confidence,
            plan_json: serde_json::to_string(plan)?,
        },
        at_ms,
    )
}

/// What the jobs library records of a planned job, of either family.
pub(crate) struct Planned<'a> {
    /// The job.
    pub job_id: &'a str,
    /// Its part.
    pub part_number: &'a str,
    /// Its machine.
    pub machine: &'a str,
    /// Its class (`spiral-face`, `spiral-groove` for the spiral family).
    pub class: &'a str,
    /// Parts ordered.
    pub quantity: u32,
    /// The tool (hob or mill).
    pub tool: &'a str,
    /// The proposal's confidence.
    pub confidence: f64,
    /// The plan as JSON.
    pub plan_json: String,
}

/// Records a planned job (state `planned`; a re-plan replaces the row and
/// starts the job over).
pub(crate) fn record_job(
    conn: &Connection,
    p: &Planned<'_>,
    at_ms: u64,
) -> Result<(), KnowledgeError> {
    conn.prepare_cached(
        "INSERT OR REPLACE INTO jobs (job_id, part_number, machine, class, quantity, tool_id, state,
                                      confidence, plan_json, planned_at_ms)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, 'planned', ?7, ?8, ?9)",
    )?
    .execute(rusqlite::params![
            p.job_id,
            p.part_number,
            p.machine,
            p.class,
            p.quantity,
            p.tool,
            p.confidence,
            p.plan_json,
        at_ms as i64,
    ])?;
    Ok(())
}

/// Marks a planned job delivered (from the agent's `delivered` event).
/// Returns false when the job is unknown or already past delivery.
pub fn record_delivered(conn: &Connection, r: &DeliveryReceipt) -> Result<bool, KnowledgeError> {
    let n = conn
        .prepare_cached(
            "UPDATE jobs SET state = 'delivered', delivered_at_ms = ?2, program_name = ?3
             WHERE job_id = ?1 AND state = 'planned'",
        )?
        .execute(rusqlite::params![
            r.job_id.as_str(),
            r.stored_at_ms as i64,
            r.name
        ])?;
    Ok(n == 1)
}

/// Marks a planned job refused (from a later stage's `failed` event): it was
/// never cut from gearcam's program and never becomes a case. Returns false
/// when the job is unknown or no longer planned.
pub fn record_refused(conn: &Connection, job_id: &str) -> Result<bool, KnowledgeError> {
    let n = conn
        .prepare_cached(
            "UPDATE jobs SET state = 'refused' WHERE job_id = ?1 AND state = 'planned'",
        )?
        .execute([job_id])?;
    Ok(n == 1)
}

/// What the planner confirms about a delivered job.
#[derive(Debug, Clone, PartialEq)]
pub struct Confirmation {
    /// The job.
    pub job_id: String,
    /// Parts actually cut (default: the job's quantity).
    pub quantity: Option<u32>,
    /// Cutting speed actually used, m/min (default: the plan's).
    pub cutting_speed_m_min: Option<f64>,
    /// Feed actually used, mm/rev (default: the plan's); for a spiral face
    /// milling job the feed per tooth, mm.
    pub feed_mm_per_rev: Option<f64>,
    /// Cuts actually made (default: the plan's); for a spiral face milling
    /// job the depth passes.
    pub cuts: Option<u32>,
    /// `ok`, `rework`, `scrap` or `unknown`.
    pub outcome: String,
    /// Grade measured.
    pub quality_achieved: Option<u8>,
    /// Remarks.
    pub notes: String,
    /// How far to trust the new case, 0–1.
    pub confidence: f64,
    /// Who confirms.
    pub by: String,
    /// When, ms since the epoch.
    pub at_ms: u64,
    /// Accept a job still in state `planned` (its delivery was not heard, e.g.
    /// it was cut from a program delivered another way).
    pub allow_undelivered: bool,
}

/// The result of a confirmation.
#[derive(Debug, Clone, PartialEq)]
pub struct Confirmed {
    /// The library of the new case: `cases` (hobbing) or `milling-cases`
    /// (spiral face milling).
    pub case_library: &'static str,
    /// The new case.
    pub case: Record,
    /// The hob after the update, when it is a library hob.
    pub hob: Option<Record>,
    /// The job after the update.
    pub job: Record,
}

/// Confirms a delivered job: it becomes a case, the hob's shift position and
/// remaining life move on, the job is marked confirmed; all in one transaction.
pub fn confirm(conn: &Connection, c: &Confirmation) -> Outcome<Confirmed> {
    act_as_confirmer(conn, c)?;
    let job = confirmable_job(conn, c)?;
    if matches!(job.class, JobClass::SpiralFace | JobClass::SpiralGroove) {
        return confirm_spiral(conn, c, &job.plan_json);
    }
    if job.class == JobClass::Wire {
        return Err(vec![Stage::Knowledge.error(
            Code::CONFIRM_FAMILY,
            "job",
            "a hobbing or spiral face milling job",
            "a wire EDM job",
            "the wire EDM family keeps no cases yet: its technology comes from the wire-data library; tune it with gearcam kb edit wire-data",
        )]);
    }
    confirm_hobbing(conn, c, &job.plan_json)
}

/// Names this confirmation as the one acting, so that the audit trail
/// records the case and the hob's wear as the confirmer's, for this job.
fn act_as_confirmer(conn: &Connection, c: &Confirmation) -> Outcome<()> {
    crate::audit::acting_as(conn, &format!("{} (confirm {})", c.by, c.job_id)).map_err(|e| {
        vec![Stage::Knowledge.error(
            Code::KNOWLEDGE_BASE_ERROR,
            "-",
            "a writable knowledge base",
            e.to_string(),
            "the confirmation could not be recorded",
        )]
    })
}

/// The job to confirm: one this knowledge base planned, not refused, and
/// either delivered or, when the planner allows an undelivered job, still
/// planned with the values that ran given.
fn confirmable_job(conn: &Connection, c: &Confirmation) -> Outcome<records::JobRecord> {
    let Some(job) = records::job(conn, &c.job_id)? else {
        return Err(vec![Stage::Knowledge.error(
            Code::UNKNOWN_JOB,
            "job",
            "a job the knowledge service planned (gearcam kb list jobs)",
            c.job_id.as_str(),
            "only jobs planned by this knowledge base can be confirmed",
        )]);
    };
    not_refused(c, job.state)?;
    values_that_ran_given(c, job.state)?;
    confirmable_state(c, job.state)?;
    Ok(job)
}

/// A job a later stage refused was never cut from gearcam's program, so it
/// never becomes a case.
fn not_refused(c: &Confirmation, state: JobState) -> Outcome<()> {
    if state == JobState::Refused {
        return Err(vec![Stage::Knowledge.error(
            Code::JOB_STATE,
            "state",
            "a delivered job",
            state.as_str(),
            format!(
                "job {} was refused by a later stage: gearcam delivered no program for it, so it cannot become a case; fix the job and submit it again",
                c.job_id
            ),
        )]);
    }
    Ok(())
}

/// A job whose delivery was not heard becomes a case only with the values
/// that really ran, given by the planner: the plan's may not be what ran.
fn values_that_ran_given(c: &Confirmation, state: JobState) -> Outcome<()> {
    if c.allow_undelivered && state == JobState::Planned {
        let missing: Vec<&str> = [
            ("--cutting-speed", c.cutting_speed_m_min.is_none()),
            ("--feed", c.feed_mm_per_rev.is_none()),
        ]
        .into_iter()
        .filter_map(|(name, missing)| missing.then_some(name))
        .collect();
        if !missing.is_empty() {
            return Err(vec![Stage::Knowledge.error(
                Code::CONFIRM_VALUES_MISSING,
                "undelivered",
                "the cutting speed and feed that really ran (--cutting-speed, --feed)",
                format!("no {}", missing.join(", no ")),
                "gearcam did not hear this job's delivery, so the plan's values may not be what ran; give the values that ran",
            )]);
        }
    }
    Ok(())
}

/// A job is confirmed once, after delivery: it must be delivered, or
/// planned when the planner allows an undelivered job.
fn confirmable_state(c: &Confirmation, state: JobState) -> Outcome<()> {
    let ok_state =
        state == JobState::Delivered || (c.allow_undelivered && state == JobState::Planned);
    if !ok_state {
        return Err(vec![Stage::Knowledge.error(
            Code::JOB_STATE,
            "state",
            if c.allow_undelivered {
                "delivered or planned"
            } else {
                "delivered (or pass --undelivered for a job cut from a program delivered another way)"
            },
            state.as_str(),
            format!(
                "job {} is {}; a job is confirmed once, after delivery",
                c.job_id,
                state.as_str()
            ),
        )]);
    }
    Ok(())
}

/// Confirms a delivered hobbing job (state checked by the caller): it
/// becomes a case with the values that ran, a library hob's shift position
/// and remaining life move on by the quantity cut, and the job is marked
/// confirmed; one transaction.
fn confirm_hobbing(conn: &Connection, c: &Confirmation, plan_json: &str) -> Outcome<Confirmed> {
    let plan = stored_plan(plan_json)?;
    let quantity = c.quantity.unwrap_or(plan.request.spec.job.quantity);
    let material = records::material(conn, &plan.gear.material)?;
    let lib_hob = if plan.hob.source == Source::Library {
        records::hob(conn, &plan.hob.id)?
    } else {
        None
    };
    let case_id = format!("JOB-{}", c.job_id);
    let case = hobbing_case(
        c,
        &plan,
        material.as_ref(),
        lib_hob.as_ref(),
        quantity,
        &case_id,
    );
    let tx = conn.unchecked_transaction().map_err(KnowledgeError::from)?;
    let case = library::add(&tx, &library::CASES, &case)?;
    let hob = match lib_hob {
        Some(h) => Some(wear_hob(&tx, &h, &plan.hob.id, quantity)?),
        None => None,
    };
    let job = mark_confirmed(&tx, c, quantity, &case_id)?;
    tx.commit().map_err(KnowledgeError::from)?;
    Ok(Confirmed {
        case_library: library::CASES.name,
        case,
        hob,
        job,
    })
}

/// The case a confirmed hobbing job becomes: the gear, the machine, the hob
/// and the values that ran (the plan's unless the planner gives others),
/// with a provenance naming the values that differ. A material or hob the
/// knowledge base does not know is recorded as unknown.
fn hobbing_case(
    c: &Confirmation,
    plan: &ProcessPlan,
    material: Option<&records::MaterialRecord>,
    lib_hob: Option<&records::HobRecord>,
    quantity: u32,
    case_id: &str,
) -> Record {
    let g = &plan.gear;
    let vc = c
        .cutting_speed_m_min
        .unwrap_or(plan.process.cutting_speed_m_min);
    let fa = c.feed_mm_per_rev.unwrap_or(plan.process.feed_mm_per_rev);
    let cuts = c.cuts.unwrap_or(plan.process.cuts);
    let mut changed = Vec::new();
    if c.cutting_speed_m_min.is_some() {
        changed.push(format!("vc {vc} m/min"));
    }
    if c.feed_mm_per_rev.is_some() {
        changed.push(format!("fa {fa} mm/rev"));
    }
    if c.cuts.is_some() {
        changed.push(format!("{cuts} cuts"));
    }
    let case = json!({
        "id": case_id,
        "class": plan.class,
        "machine": plan.machine.id.as_str(),
        "material": g.material.trim(),
        "material_group": material.map_or("unknown", |m| m.material_group.as_str()),
        "hardness_hb": material.and_then(|m| m.hardness_hb),
        "module_mm": g.module_mm,
        "teeth": g.teeth,
        "helix_angle_deg": g.helix_angle_deg.abs(),
        "face_width_mm": g.face_width_mm,
        "quality_grade": g.quality_grade,
        "hob_material": lib_hob.map_or("unknown", |h| h.material.as_str()),
        "hob_coating": lib_hob.map_or("unknown", |h| h.coating.as_str()),
        "hob_starts": plan.hob.starts,
        "hob_od_mm": plan.hob.od_mm,
        "operation": plan.sections().process.operation.unwrap_or_default().as_str(),
        "cutting_speed_m_min": vc,
        "feed_mm_per_rev": fa,
        "hob_rpm": vc * 1000.0 / (std::f64::consts::PI * plan.hob.od_mm),
        "cuts": cuts,
        "cut_mode": match plan.process.cut_mode {
            gearcam_proto::CutMode::Climb => "climb",
            gearcam_proto::CutMode::Conventional => "conventional",
        },
        "outcome": c.outcome,
        "quality_achieved": c.quality_achieved,
        "notes": c.notes,
        "confidence": c.confidence,
        "provenance": provenance(c, quantity, &plan.request.spec.job.part_number, &changed),
        "job_id": c.job_id,
        "created_at_ms": c.at_ms,
    });
    let Value::Object(case) = case else {
        unreachable!("a JSON object")
    };
    case
}

/// Moves a library hob on by the parts cut: its shift position by the
/// shift they need (up to its usable length), its remaining life by their
/// number.
fn wear_hob(
    tx: &rusqlite::Transaction<'_>,
    h: &records::HobRecord,
    hob_id: &str,
    quantity: u32,
) -> Outcome<Record> {
    let used = hobmatch::shift_needed_mm(h, quantity);
    let pos = (h.shift_position_mm + used).min(h.usable_length_mm);
    let life = h.remaining_life_parts.saturating_sub(u64::from(quantity));
    let mut set = Record::new();
    set.insert("shift_position_mm".into(), json!(pos));
    set.insert("remaining_life_parts".into(), json!(life));
    library::edit(tx, &library::HOBS, hob_id, &set)
}

/// Confirms a delivered spiral job (state checked by the caller): it
/// becomes a milling case with the values that ran (the plan's unless the
/// planner gives others: `feed_mm_per_rev` is the feed per tooth here and
/// `cuts` the depth passes), and the job is marked confirmed; one transaction.
fn confirm_spiral(conn: &Connection, c: &Confirmation, plan_json: &str) -> Outcome<Confirmed> {
    let plan: SpiralPlan = serde_json::from_str(plan_json).map_err(|e| {
        vec![Stage::Knowledge.error(
            Code::KNOWLEDGE_BASE_ERROR,
            "plan_json",
            "a stored spiral plan",
            e.to_string(),
            "the job's stored plan cannot be read",
        )]
    })?;
    let material = records::material(conn, plan.part.material())?;
    let p = &plan.process;
    let vc = c.cutting_speed_m_min.unwrap_or(p.cutting_speed_m_min.value);
    let fz = c.feed_mm_per_rev.unwrap_or(p.feed_per_tooth_mm.value);
    let passes = c.cuts.unwrap_or(p.passes);
    let quantity = c.quantity.unwrap_or(plan.request.spec.job.quantity);
    let (ro, ri) = match &plan.part {
        SpiralPart::Face(f) => (f.outer_radius_mm, f.inner_radius_mm),
        SpiralPart::Groove(g) => (g.outer_radius_mm, 0.0),
    };
    let mut changed = Vec::new();
    if c.cutting_speed_m_min.is_some() {
        changed.push(format!("vc {vc} m/min"));
    }
    if c.feed_mm_per_rev.is_some() {
        changed.push(format!("fz {fz} mm"));
    }
    if c.cuts.is_some() {
        changed.push(format!("{passes} passes"));
    }
    let case_id = format!("JOB-{}", c.job_id);
    let Value::Object(case) = json!({
        "id": case_id,
        "kind": plan.part.kind(),
        "machine": plan.machine.id.as_str(),
        "material": plan.part.material().trim(),
        "material_group": material.as_ref().map_or("unknown", |m| m.material_group.as_str()),
        "outer_radius_mm": ro,
        "inner_radius_mm": ri,
        "tool_id": (plan.tool.source == Source::Library).then_some(plan.tool.id.as_str()),
        "tool_diameter_mm": 2.0 * plan.tool.radius_mm,
        "flutes": plan.tool.flutes,
        "step_over_mm": p.step_over_mm.value,
        "passes": passes,
        "depth_mm": plan.part.depth_mm(),
        "cutting_speed_m_min": vc,
        "feed_per_tooth_mm": fz,
        "outcome": c.outcome,
        "notes": c.notes,
        "confidence": c.confidence,
        "provenance": provenance(c, quantity, &plan.request.spec.job.part_number, &changed),
        "job_id": c.job_id,
        "created_at_ms": c.at_ms,
    }) else {
        unreachable!("a JSON object")
    };
    let tx = conn.unchecked_transaction().map_err(KnowledgeError::from)?;
    let case = library::add(&tx, &library::MILLING_CASES, &case)?;
    let job = mark_confirmed(&tx, c, quantity, &case_id)?;
    tx.commit().map_err(KnowledgeError::from)?;
    Ok(Confirmed {
        case_library: library::MILLING_CASES.name,
        case,
        hob: None,
        job,
    })
}

/// A confirmed case's provenance: the job, the parts, who, and the values
/// that ran where they differ from the plan.
fn provenance(c: &Confirmation, quantity: u32, part: &str, changed: &[String]) -> String {
    format!(
        "confirmed job {} ({} parts of {}) by {}{}",
        c.job_id,
        quantity,
        part,
        c.by,
        if changed.is_empty() {
            ": values as planned".to_string()
        } else {
            format!(
                ": values actually used differ from the plan: {}",
                changed.join(", ")
            )
        }
    )
}

/// Marks the job confirmed, with the quantity cut and its new case.
fn mark_confirmed(
    tx: &rusqlite::Transaction<'_>,
    c: &Confirmation,
    quantity: u32,
    case_id: &str,
) -> Outcome<Record> {
    let mut set = Record::new();
    set.insert("state".into(), json!("confirmed"));
    set.insert("confirmed_at_ms".into(), json!(c.at_ms));
    set.insert("delivered_quantity".into(), json!(quantity));
    set.insert("case_id".into(), json!(case_id));
    library::edit(tx, &library::JOBS, &c.job_id, &set)
}

/// A plan as the jobs library stored it. Plans stored before the plan
/// carried the resolved gear beside the request (and the class as a name)
/// had the gear in `request.spec.gear`: it is taken from there.
fn stored_plan(json: &str) -> Result<ProcessPlan, KnowledgeError> {
    let mut v: serde_json::Value = serde_json::from_str(json)?;
    if v.get("gear").is_none() {
        let gear = v
            .pointer("/request/spec/gear")
            .cloned()
            .unwrap_or(serde_json::Value::Null);
        if let Some(map) = v.as_object_mut() {
            map.insert("gear".into(), gear);
        }
    }
    let plan: ProcessPlan = serde_json::from_value(v)?;
    // A row of the jobs library can be edited by hand: a hobbing plan that
    // carries another family's job is a record that does not fit.
    if plan.request.spec.hobbing().is_none() {
        return Err(KnowledgeError::Record {
            library: "jobs",
            id: plan.job_id.to_string(),
            field: "plan_json.request.spec.job.family".into(),
            detail: format!(
                "a hobbing plan carries a {} job",
                plan.request.spec.family().as_str()
            ),
        });
    }
    Ok(plan)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{cbr, db, plan};
    use serde_json::json;

    fn confirmation(job: &str) -> Confirmation {
        Confirmation {
            job_id: job.into(),
            quantity: Some(20),
            cutting_speed_m_min: Some(95.0),
            feed_mm_per_rev: None,
            cuts: None,
            outcome: "ok".into(),
            quality_achieved: Some(7),
            notes: "good flanks".into(),
            confidence: 0.9,
            by: "test".into(),
            at_ms: 1_700_000_000_000,
            allow_undelivered: false,
        }
    }

    #[test]
    fn a_confirmed_job_becomes_the_best_case_for_the_same_job_and_wears_the_hob() {
        let conn = db::open_in_memory().unwrap();
        let req = plan::tests::request(json!({}), json!({}));
        let p = plan::plan(&conn, &req).unwrap();
        record_planned(&conn, &p, 1).unwrap();
        // Not delivered yet: refused with the state named.
        let e = confirm(&conn, &confirmation("J1")).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].got.as_str()),
            ("JOB_STATE", "planned")
        );
        let receipt: DeliveryReceipt = serde_json::from_value(json!({
            "job_id": "J1", "machine": "H01", "name": "P_1", "file_name": "_N_P_1_MPF",
            "path": "/x", "revision": 1, "sha256": "00", "size_bytes": 1,
            "stored_at_ms": 2, "duplicate": false
        }))
        .unwrap();
        assert!(record_delivered(&conn, &receipt).unwrap());
        let hob_before = library::get(&conn, &library::HOBS, &p.hob.id)
            .unwrap()
            .unwrap();
        let done = confirm(&conn, &confirmation("J1")).unwrap();
        assert_eq!(done.case["id"], "JOB-J1");
        assert_eq!(done.case["cutting_speed_m_min"], 95.0);
        assert_eq!(
            done.case["operation"], "finish",
            "the job said nothing: finish"
        );
        assert!(done.case["provenance"]
            .as_str()
            .unwrap()
            .contains("vc 95 m/min"));
        assert_eq!(done.job["state"], "confirmed");
        // 20 parts at 2 parts per 0.5 mm step: 5 mm of shift, 20 parts of life.
        let hob = done.hob.unwrap();
        assert_eq!(
            hob["shift_position_mm"].as_f64().unwrap(),
            hob_before["shift_position_mm"].as_f64().unwrap() + 5.0
        );
        assert_eq!(
            hob["remaining_life_parts"].as_i64().unwrap(),
            hob_before["remaining_life_parts"].as_i64().unwrap() - 20
        );
        // The same job again now retrieves its own case first, with similarity 1.
        let again = plan::plan(&conn, &req).unwrap();
        assert_eq!(again.cases[0].id, "JOB-J1");
        assert_eq!(again.cases[0].similarity, 1.0);
        assert_eq!(again.cases.len(), cbr::TOP_K);
        // Once only.
        let e = confirm(&conn, &confirmation("J1")).unwrap_err();
        assert_eq!(e[0].got, "confirmed");
        let e = confirm(&conn, &confirmation("NOPE")).unwrap_err();
        assert_eq!(e[0].code, "UNKNOWN_JOB");
    }

    /// A plan the jobs library stored before the plan carried its gear
    /// beside the request (gear in `request.spec.gear`, class a name) still
    /// reads, with the same gear.
    #[test]
    fn a_plan_stored_in_the_old_shape_still_reads() {
        let conn = db::open_in_memory().unwrap();
        let req = plan::tests::request(json!({}), json!({}));
        let now = plan::plan(&conn, &req).unwrap();
        let mut old = serde_json::to_value(&now).unwrap();
        let gear = old.as_object_mut().unwrap().remove("gear").unwrap();
        old["request"]["spec"]["gear"] = gear;
        old["class"] = json!("cylindrical");
        let read = stored_plan(&old.to_string()).unwrap();
        assert_eq!(read.gear, now.gear);
        assert_eq!(read.class, now.class);
        // Without the compatibility step the old shape does not read.
        assert!(serde_json::from_value::<ProcessPlan>(old).is_err());
    }

    #[test]
    fn a_stored_hobbing_plan_with_another_familys_job_is_a_record_error() {
        let conn = db::open_in_memory().unwrap();
        let req = plan::tests::request(json!({}), json!({}));
        let mut edited = serde_json::to_value(plan::plan(&conn, &req).unwrap()).unwrap();
        edited["request"]["spec"] = json!({
            "job": {"family": "wire-edm", "machine": "W01", "part_number": "PD-1"},
            "die": {"part": "die", "module_mm": 2.0, "teeth": 20, "thickness_mm": 20.0,
                    "material": "Cr12MoV"},
        });
        let err = stored_plan(&edited.to_string()).unwrap_err();
        assert!(
            err.to_string()
                .contains("a hobbing plan carries a wire-edm job"),
            "{err}"
        );
    }

    /// A job whose delivery was not heard becomes a case only with the
    /// values that really ran: the confirmation must give them.
    #[test]
    fn an_undelivered_job_needs_the_values_that_ran() {
        let conn = db::open_in_memory().unwrap();
        let req = plan::tests::request(json!({}), json!({}));
        let p = plan::plan(&conn, &req).unwrap();
        record_planned(&conn, &p, 1).unwrap();
        let mut c = confirmation("J1");
        c.allow_undelivered = true;
        c.cutting_speed_m_min = None;
        let e = confirm(&conn, &c).unwrap_err();
        assert_eq!(e[0].code, "CONFIRM_VALUES_MISSING");
        assert_eq!(e[0].got, "no --cutting-speed, no --feed");
        c.cutting_speed_m_min = Some(95.0);
        c.feed_mm_per_rev = Some(2.1);
        assert!(confirm(&conn, &c).is_ok());
    }
}
