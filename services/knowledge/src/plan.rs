//! From a job request to a process plan: machine, hob, cutting data, each value
//! with its source.

use std::collections::BTreeMap;

use gearcam_proto::{
    CaseRef, CutMode, Hand, HobData, HobSpec, JobError, JobRequest, MachineProfile, ProcessData,
    ProcessPlan, Source, Sourced, Stage,
};
use rusqlite::Connection;

use crate::db;
use crate::KnowledgeError;

/// Normal base pitch tolerance for hob matching, mm (SPEC §4.2 check 3).
const BASE_PITCH_TOL_MM: f64 = 1e-4;

fn err(
    code: &str,
    field: &str,
    expected: impl Into<String>,
    got: impl Into<String>,
    message: impl Into<String>,
) -> JobError {
    JobError {
        stage: Stage::Knowledge,
        code: code.into(),
        field: field.into(),
        expected: expected.into(),
        got: got.into(),
        message: message.into(),
    }
}

/// The group-technology class of a job. This release knows cylindrical gears
/// (spur and helical); later classes are added with their models.
pub fn classify(_req: &JobRequest) -> &'static str {
    "cylindrical"
}

/// Builds the process plan for a request, or every reason it cannot be built.
pub fn plan(conn: &Connection, req: &JobRequest) -> Result<ProcessPlan, Vec<JobError>> {
    plan_inner(conn, req).map_err(|e| match e {
        PlanError::Job(errors) => errors,
        PlanError::Kb(e) => vec![err(
            "KNOWLEDGE_BASE_ERROR",
            "-",
            "a readable knowledge base",
            e.to_string(),
            "the knowledge base could not be read; check the knowledge service's log and database file",
        )],
    })
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

fn plan_inner(conn: &Connection, req: &JobRequest) -> Result<ProcessPlan, PlanError> {
    let spec = &req.spec;
    let mut errors = Vec::new();
    let machine = db::machine(conn, &spec.job.machine)?;
    let Some(machine) = machine else {
        let known: Vec<String> = db::machines(conn)?
            .into_iter()
            .map(|m| m.id.to_string())
            .collect();
        return Err(PlanError::Job(vec![err(
            "UNKNOWN_MACHINE",
            "job.machine",
            format!("one of {}", known.join(", ")),
            spec.job.machine.to_string(),
            "the machine is not in the knowledge base; pick a configured machine or add it",
        )]));
    };

    let hob = resolve_hob(conn, req, &machine, &mut errors)?;

    let mut values = BTreeMap::new();
    let mut cases = Vec::new();
    let group = db::material_group(conn, &spec.gear.material)?;
    let (group, group_known) = match group {
        Some(g) => (g, true),
        None => ("steel".to_string(), false),
    };
    let cd = db::cutting_data(conn, &group, "HSS")?;
    let (vc, vc_src) = match (spec.process.cutting_speed_m_min, &cd) {
        (Some(v), _) => (v, Source::Job),
        (None, Some(cd)) => (cd.cutting_speed_m_min, Source::Case),
        (None, None) => (80.0, Source::Default),
    };
    let (fa, fa_src) = match (spec.process.feed_mm_per_rev, &cd) {
        (Some(v), _) => (v, Source::Job),
        (None, Some(cd)) => (cd.feed_mm_per_rev, Source::Case),
        (None, None) => (1.8, Source::Default),
    };
    let mut confidence: f64 = 1.0;
    if let Some(cd) = &cd {
        if vc_src == Source::Case || fa_src == Source::Case {
            let provenance = if group_known {
                cd.source.clone()
            } else {
                format!(
                    "{} (material {:?} is not in the materials table; treated as {})",
                    cd.source, spec.gear.material, cd.material_group
                )
            };
            cases.push(CaseRef {
                id: cd.id.clone(),
                similarity: if group_known { 1.0 } else { 0.5 },
                provenance,
            });
            confidence = if group_known {
                cd.confidence
            } else {
                cd.confidence * 0.5
            };
        }
    } else if vc_src == Source::Default || fa_src == Source::Default {
        confidence = 0.2;
    }
    values.insert(
        "cutting_speed_m_min".into(),
        Sourced {
            value: vc,
            source: vc_src,
        },
    );
    values.insert(
        "feed_mm_per_rev".into(),
        Sourced {
            value: fa,
            source: fa_src,
        },
    );

    let (cut_mode, cm_src) = match spec.process.cut_mode {
        Some(m) => (m, Source::Job),
        None => (CutMode::Conventional, Source::Default),
    };
    let (cuts, cuts_src) = match spec.process.cuts {
        Some(c) => (c, Source::Job),
        None => (1, Source::Default),
    };
    let (safety, safety_src) = match spec.process.safety_mm {
        Some(s) => (s, Source::Job),
        None => (machine.settings.safety_mm, Source::Machine),
    };
    values.insert(
        "cut_mode_climb".into(),
        Sourced {
            value: f64::from(u8::from(cut_mode == CutMode::Climb)),
            source: cm_src,
        },
    );
    values.insert(
        "cuts".into(),
        Sourced {
            value: f64::from(cuts),
            source: cuts_src,
        },
    );
    values.insert(
        "safety_mm".into(),
        Sourced {
            value: safety,
            source: safety_src,
        },
    );
    if let Some(h) = spec.process.depth_mm {
        values.insert(
            "depth_mm".into(),
            Sourced {
                value: h,
                source: Source::Job,
            },
        );
    }
    if let Some(h) = &hob {
        values.insert(
            "hob_od_mm".into(),
            Sourced {
                value: h.od_mm,
                source: h.source,
            },
        );
    }

    if !errors.is_empty() {
        return Err(PlanError::Job(errors));
    }
    let hob = hob.expect("a hob when there are no errors");
    Ok(ProcessPlan {
        job_id: req.job_id.clone(),
        request: req.clone(),
        class: classify(req).into(),
        machine,
        hob,
        process: ProcessData {
            cut_mode,
            cuts,
            cutting_speed_m_min: vc,
            feed_mm_per_rev: fa,
            depth_mm: spec.process.depth_mm,
            safety_mm: safety,
        },
        values,
        cases,
        confidence,
    })
}

fn inline_hob(h: &HobSpec, errors: &mut Vec<JobError>) -> Option<HobData> {
    let mut missing = |field: &str| {
        errors.push(err(
            "HOB_FIELD_MISSING",
            &format!("hob.{field}"),
            "a value (inline hob data needs starts, od_mm, module_mm, lead_angle_deg, hand, length_mm)",
            "nothing",
            format!("inline hob data is incomplete: add hob.{field}, or give hob.id from the library instead"),
        ));
    };
    let starts = h.starts.or_else(|| {
        missing("starts");
        None
    });
    let od = h.od_mm.or_else(|| {
        missing("od_mm");
        None
    });
    let module = h.module_mm.or_else(|| {
        missing("module_mm");
        None
    });
    let lead = h.lead_angle_deg.or_else(|| {
        missing("lead_angle_deg");
        None
    });
    let hand = h.hand.or_else(|| {
        missing("hand");
        None
    });
    let length = h.length_mm.or_else(|| {
        missing("length_mm");
        None
    });
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
) -> Result<Option<HobData>, KnowledgeError> {
    let spec = &req.spec;
    let h = &spec.hob;
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
        (Some(id), false) => match db::hob(conn, id.as_str())? {
            Some(hob) => Ok(Some(hob)),
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
        (None, true) => Ok(inline_hob(h, errors)),
        (None, false) => {
            // Hob matching: equal normal base pitch, a hob the machine takes,
            // same hand as a helical gear when the library has one.
            let g = &spec.gear;
            let pb = g.module_mm * g.pressure_angle_deg.to_radians().cos();
            let mut candidates: Vec<HobData> = db::hobs(conn)?
                .into_iter()
                .filter(|h| {
                    (h.module_mm * h.pressure_angle_deg.to_radians().cos() - pb).abs()
                        <= BASE_PITCH_TOL_MM
                })
                .filter(|h| h.od_mm <= machine.limits.max_hob_od_mm)
                .collect();
            let want = g.helix_hand.unwrap_or(Hand::Right);
            candidates.sort_by_key(|h| (h.hand != want, h.starts, h.id.clone()));
            match candidates.into_iter().next() {
                Some(h) => Ok(Some(h)),
                None => {
                    errors.push(err(
                        "NO_MATCHING_HOB",
                        "hob",
                        format!("a library hob with normal base pitch mn0·cos α0 = {pb:.4} mm"),
                        "none in the library",
                        "no library hob matches the gear's module and pressure angle; add one or give the hob inline",
                    ));
                    Ok(None)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use gearcam_proto::{GearSpec, JobHeader, JobSpec, MachineId, Options, ProcessOverrides};

    fn request(hob: HobSpec, process: ProcessOverrides) -> JobRequest {
        JobRequest {
            job_id: gearcam_proto::JobId::new("J1").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec: JobSpec {
                job: JobHeader {
                    id: None,
                    machine: MachineId::new("H01").unwrap(),
                    quantity: 1,
                    part_number: "P-1".into(),
                },
                gear: GearSpec {
                    module_mm: 3.0,
                    teeth: 25,
                    pressure_angle_deg: 20.0,
                    helix_angle_deg: 15.0,
                    helix_hand: Some(Hand::Left),
                    face_width_mm: 30.0,
                    profile_shift: 0.0,
                    addendum_coef: 1.0,
                    clearance_coef: 0.25,
                    blank_od_mm: None,
                    od_correction_mm: 0.0,
                    material: "16MnCr5".into(),
                    quality_grade: 7,
                    fixture_height_mm: 50.0,
                },
                hob,
                process,
                options: Options::default(),
            },
        }
    }

    #[test]
    fn proposes_cutting_data_from_the_material_group_with_provenance() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan(
            &conn,
            &request(HobSpec::default(), ProcessOverrides::default()),
        )
        .unwrap();
        assert_eq!(plan.cases[0].id, "CD-CASE-HSS");
        assert_eq!(
            plan.values["cutting_speed_m_min"],
            Sourced {
                value: 90.0,
                source: Source::Case
            }
        );
        assert_eq!(plan.values["safety_mm"].source, Source::Machine);
        assert_eq!(plan.process.cut_mode, CutMode::Conventional);
        // Hob matching: module 3 at 20°, and the left-hand hob for a left-hand gear.
        assert_eq!(plan.hob.id, "HOB-M3-80L");
    }

    #[test]
    fn overrides_win_and_are_recorded_as_job_values() {
        let conn = db::open_in_memory().unwrap();
        let process = ProcessOverrides {
            cutting_speed_m_min: Some(70.0),
            feed_mm_per_rev: Some(1.2),
            cut_mode: Some(CutMode::Climb),
            ..ProcessOverrides::default()
        };
        let plan = plan(&conn, &request(HobSpec::default(), process)).unwrap();
        assert_eq!(
            plan.values["cutting_speed_m_min"],
            Sourced {
                value: 70.0,
                source: Source::Job
            }
        );
        assert_eq!(
            plan.values["feed_mm_per_rev"],
            Sourced {
                value: 1.2,
                source: Source::Job
            }
        );
        assert_eq!(plan.process.cut_mode, CutMode::Climb);
        assert!(plan.cases.is_empty());
    }

    #[test]
    fn unknown_machine_and_hob_errors_name_the_field_and_the_choices() {
        let conn = db::open_in_memory().unwrap();
        let mut req = request(
            HobSpec {
                id: Some(gearcam_proto::HobId::new("NOPE").unwrap()),
                ..HobSpec::default()
            },
            ProcessOverrides::default(),
        );
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
            ("UNKNOWN_MACHINE", "one of H01")
        );
    }

    #[test]
    fn incomplete_inline_hob_lists_every_missing_field() {
        let conn = db::open_in_memory().unwrap();
        let hob = HobSpec {
            starts: Some(1),
            od_mm: Some(80.0),
            ..HobSpec::default()
        };
        let errors = plan(&conn, &request(hob, ProcessOverrides::default())).unwrap_err();
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
        let hob = HobSpec {
            id: Some(gearcam_proto::HobId::new("HOB-M3-80").unwrap()),
            od_mm: Some(80.0),
            ..HobSpec::default()
        };
        let errors = plan(&conn, &request(hob, ProcessOverrides::default())).unwrap_err();
        assert_eq!(errors[0].code, "HOB_AMBIGUOUS");
    }

    #[test]
    fn the_database_file_is_created_once_and_reopened_without_reseeding() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("kb/knowledge.db");
        let conn = db::open(&path).unwrap();
        assert_eq!(db::hobs(&conn).unwrap().len(), 5);
        drop(conn);
        let conn = db::open(&path).unwrap();
        assert_eq!(db::hobs(&conn).unwrap().len(), 5);
        assert_eq!(db::machines(&conn).unwrap()[0], db::seed_machine_h01());
    }
}
