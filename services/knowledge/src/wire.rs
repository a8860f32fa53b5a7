//! The knowledge service's part of the wire EDM family (docs/wire.md): the
//! seed of the wire libraries, and the plan of a die job — the machine, the
//! wire and its spark gap, the starting technology for the plate's material
//! group, and the program form — each value with its source.

use gearcam_proto::{
    CaseRef, Code, Dialect, DieSpec, Family, JobError, JobRequest, JobSpec, MachineId, Source,
    Sourced, Stage, WireMachine, WireOverrides, WirePlan, WireProcess, WireProgram, WireSpec,
};
use rusqlite::{Connection, Transaction};
use serde_json::json;

use crate::library::{self, Record};
use crate::spiral::{add, num, text};
use crate::{records, KnowledgeError};

/// Provenance of the seeded machines.
pub const MACHINES_SEED: &str = "gearcam seed: example wire EDM machines (engineering estimate of \
    a typical fast-wire machine with a 3B/4B control and a slow-wire machine with an ISO control; \
    replace with your shop's)";
/// Provenance of the seeded wires.
pub const WIRES_SEED: &str = "gearcam seed: common wires (molybdenum 0.18 mm for fast-wire, brass \
    0.25 mm for slow-wire) with an engineering estimate of the spark gap; measure your own";
/// Provenance of the seeded technology.
pub const DATA_SEED: &str = "gearcam seed: engineering estimate of a first cut's technology \
    (not shop history); tune on a test cut";

fn form(name: &str) -> Option<WireProgram> {
    [
        WireProgram::ThreeB,
        WireProgram::FourB,
        WireProgram::IsoWire,
    ]
    .into_iter()
    .find(|f| f.as_str() == name)
}

/// Seeds the tables of migration 8.
pub fn seed_v8(tx: &Transaction<'_>) -> Result<(), KnowledgeError> {
    crate::audit::acting_as(tx, "seed")?;
    add(
        tx,
        &library::WIRE_MACHINES,
        json!({"id": "W01", "name": "Fast-wire EDM, 3B/4B control",
               "controller": "HF 3B/4B", "dialect": "wire3b", "programs": "3b 4b",
               "default_program": "3b", "wire": "MO-018", "max_thickness_mm": 300.0,
               "max_radius_mm": 200.0, "source": MACHINES_SEED}),
    )?;
    add(
        tx,
        &library::WIRE_MACHINES,
        json!({"id": "W02", "name": "Slow-wire EDM, ISO control",
               "controller": "ISO wire (FANUC-type)", "dialect": "wireiso",
               "programs": "iso-wire", "default_program": "iso-wire", "wire": "BR-025",
               "max_thickness_mm": 150.0, "max_radius_mm": 180.0, "source": MACHINES_SEED}),
    )?;
    for (id, material, d, gap) in [
        ("MO-018", "molybdenum", 0.18, 0.01),
        ("MO-012", "molybdenum", 0.12, 0.01),
        ("BR-025", "brass", 0.25, 0.02),
        ("BR-020", "brass", 0.20, 0.015),
    ] {
        add(
            tx,
            &library::WIRES,
            json!({"id": id, "material": material, "diameter_mm": d, "spark_gap_mm": gap,
                   "source": WIRES_SEED}),
        )?;
    }
    for (name, group) in [
        ("Cr12MoV", "tool_steel"),
        ("SKD11", "tool_steel"),
        ("D2", "tool_steel"),
    ] {
        tx.execute(
            "INSERT OR IGNORE INTO materials (name, material_group, source) VALUES (?1, ?2, ?3)",
            rusqlite::params![name, group, "gearcam seed: wire EDM example material"],
        )?;
    }
    for (id, wire, group, on, off, amps, rate, conf) in [
        (
            "WD-MO-TOOL",
            "molybdenum",
            "tool_steel",
            24.0,
            120.0,
            3.0,
            60.0,
            0.5,
        ),
        (
            "WD-MO-ANY",
            "molybdenum",
            "any",
            20.0,
            100.0,
            3.0,
            70.0,
            0.3,
        ),
        (
            "WD-BR-TOOL",
            "brass",
            "tool_steel",
            1.2,
            12.0,
            12.0,
            110.0,
            0.5,
        ),
        ("WD-BR-ANY", "brass", "any", 1.0, 10.0, 10.0, 120.0, 0.3),
    ] {
        add(
            tx,
            &library::WIRE_DATA,
            json!({"id": id, "wire_material": wire, "material_group": group,
                   "pulse_on_us": on, "pulse_off_us": off, "current_a": amps,
                   "cutting_rate_mm2_min": rate, "confidence": conf, "source": DATA_SEED}),
        )?;
    }
    Ok(())
}

/// A wire EDM machine from its record.
fn profile(r: &Record) -> Result<WireMachine, KnowledgeError> {
    let id = text(r, "id");
    let bad = |field: &str| {
        KnowledgeError::Seed(format!(
            "wire-machines record {id}: field {field} is not usable"
        ))
    };
    Ok(WireMachine {
        id: MachineId::new(id).map_err(|_| bad("id"))?,
        name: text(r, "name").to_string(),
        controller: text(r, "controller").to_string(),
        dialect: match text(r, "dialect") {
            "wire3b" => Dialect::Wire3b,
            "wireiso" => Dialect::WireIso,
            _ => return Err(bad("dialect")),
        },
        programs: text(r, "programs")
            .split_whitespace()
            .map(|p| form(p).ok_or_else(|| bad("programs")))
            .collect::<Result<_, _>>()?,
        default_program: form(text(r, "default_program")).ok_or_else(|| bad("default_program"))?,
        max_thickness_mm: num(r, "max_thickness_mm"),
        max_radius_mm: num(r, "max_radius_mm"),
        rotates: r
            .get("rotates")
            .and_then(serde_json::Value::as_bool)
            .ok_or_else(|| bad("rotates"))?,
    })
}

/// Every wire EDM machine's profile, ordered by id.
pub fn wire_machines(conn: &Connection) -> Result<Vec<WireMachine>, KnowledgeError> {
    library::list(conn, &library::WIRE_MACHINES)?
        .iter()
        .map(profile)
        .collect()
}

/// Why a plan failed: the job's errors, or the knowledge base's.
enum Failed {
    Job(Vec<JobError>),
    Base(KnowledgeError),
}

impl From<KnowledgeError> for Failed {
    fn from(e: KnowledgeError) -> Self {
        Failed::Base(e)
    }
}

/// The plan of a wire EDM job.
pub fn plan_wire(conn: &Connection, req: &JobRequest) -> Result<WirePlan, Vec<JobError>> {
    plan_inner(conn, req).map_err(|f| match f {
        Failed::Job(errors) => errors,
        Failed::Base(e) => vec![Stage::Knowledge.error(
            Code::KNOWLEDGE_BASE_ERROR,
            "-",
            "a readable knowledge base",
            e.to_string(),
            "the knowledge base could not be read; check the knowledge service's log and database file",
        )],
    })
}

/// Plans a checked job: its machine and die, the wire, the technology for
/// the wire and the plate's material group, the program form, and the
/// process with each value's source.
fn plan_inner(conn: &Connection, req: &JobRequest) -> Result<WirePlan, Failed> {
    let spec = crate::sections::sections(req, Family::WireEdm, JobSpec::wire)
        .map_err(|e| Failed::Job(vec![e]))?;
    let (machine, record, die) = machine_and_die(conn, req, spec)?;
    let o = &spec.wire;
    let (wire_id, wire) = wire_of(conn, o, &record)?;
    let (data, group) = technology(conn, &die, &wire)?;
    let program = o.program.unwrap_or(machine.default_program);
    let whole = whole_part(o, &machine)?;
    let process = wire_process(o, wire_id, &wire, &data, program, whole);
    let confidence = num(&data, "confidence");
    Ok(WirePlan {
        job_id: req.job_id.clone(),
        request: req.clone(),
        die,
        machine,
        process,
        cases: vec![CaseRef {
            id: text(&data, "id").to_string(),
            similarity: if text(&data, "material_group") == group {
                1.0
            } else {
                0.5
            },
            provenance: text(&data, "source").to_string(),
        }],
        confidence,
    })
}

/// The job's machine (its profile and its record) and die, once the job
/// is checked: its `[die]` section, its machine, and its program's name by
/// the control's rule, before anything is planned. Every error found, in
/// that order, or all three.
fn machine_and_die(
    conn: &Connection,
    req: &JobRequest,
    spec: &WireSpec,
) -> Result<(WireMachine, Record, DieSpec), Failed> {
    let mut errors = Vec::new();
    if spec.die.is_none() {
        errors.push(Stage::Knowledge.error(
            Code::MISSING_SECTION,
            "die",
            "a [die] section (part, module_mm, teeth, thickness_mm, material)",
            "none",
            "a wire-edm job describes the gear whose punch or die it cuts",
        ));
    }
    let machine_id = req.spec.job.machine.as_str();
    let record = library::get(conn, &library::WIRE_MACHINES, machine_id)?;
    let machine = match record {
        Some(ref r) => Some(profile(r)?),
        None => {
            errors.push(library::machine_error(conn, machine_id, "wire EDM")?);
            None
        }
    };
    if let Some(m) = &machine {
        // The program's name by the control's rule, before anything is planned.
        let four_b = spec.wire.program.unwrap_or(m.default_program) == WireProgram::FourB;
        errors.extend(gearcam_proto::naming::name_error(
            m.dialect,
            &req.spec.job,
            four_b,
            Stage::Knowledge,
        ));
    }
    let (Some(machine), Some(record), Some(die), true) =
        (machine, record, spec.die.clone(), errors.is_empty())
    else {
        return Err(Failed::Job(errors));
    };
    Ok((machine, record, die))
}

/// The wire: the job's wire id, else the machine's (its `record`), with
/// its library record; a wire the knowledge base does not have is refused.
fn wire_of(
    conn: &Connection,
    o: &WireOverrides,
    record: &Record,
) -> Result<(String, Record), Failed> {
    let wire_id = o
        .wire
        .clone()
        .unwrap_or_else(|| text(record, "wire").to_string());
    let Some(wire) = library::get(conn, &library::WIRES, &wire_id)? else {
        let wires = library::keys(conn, &library::WIRES)?;
        return Err(Failed::Job(vec![Stage::Knowledge.error(
            Code::UNKNOWN_WIRE,
            "wire.wire",
            format!("a wire of the knowledge base: one of {}", wires.join(", ")),
            wire_id,
            "the wire is not in the knowledge base (gearcam kb list wires)",
        )]));
    };
    Ok((wire_id, wire))
}

/// The technology to start from, and the plate's material group: the
/// wire-data row of the wire's material for that group, else its row for
/// any material; with neither, the job is refused.
fn technology(conn: &Connection, die: &DieSpec, wire: &Record) -> Result<(Record, String), Failed> {
    let material = records::material(conn, &die.material)?;
    let group = material
        .as_ref()
        .map_or("unknown".to_string(), |m| m.material_group.clone());
    let wire_material = text(wire, "material");
    let rows = library::list(conn, &library::WIRE_DATA)?;
    let data = rows
        .iter()
        .find(|r| text(r, "wire_material") == wire_material && text(r, "material_group") == group)
        .or_else(|| {
            rows.iter().find(|r| {
                text(r, "wire_material") == wire_material && text(r, "material_group") == "any"
            })
        });
    let Some(data) = data else {
        return Err(Failed::Job(vec![Stage::Knowledge.error(
            Code::NO_CUTTING_DATA,
            "die.material",
            format!("a wire-data row for {wire_material} wire and the plate's material group (gearcam kb list wire-data)"),
            format!("{} (group {group})", die.material),
            "the knowledge base has no technology to propose for this wire and material",
        )]));
    };
    Ok((data.clone(), group))
}

/// Whether the program cuts the whole part. A control that cannot turn a
/// section runs every block once: it is given the whole part unless the
/// job asks otherwise, and a job that asks for a turned program there is
/// refused rather than sent.
fn whole_part(o: &WireOverrides, machine: &WireMachine) -> Result<bool, Failed> {
    if o.whole == Some(false) && !machine.rotates {
        return Err(Failed::Job(vec![Stage::Knowledge.error(
            Code::PROGRAM_FORM,
            "wire.whole",
            format!(
                "true, or no whole key: the control of {} ({}) does not turn a section of blocks",
                machine.id, machine.controller
            ),
            "false",
            "a quarter or half program needs the control's rotation",
        )]));
    }
    Ok(o.whole.unwrap_or(!machine.rotates))
}

/// The process: the wire's diameter and spark gap (the job's, else the
/// wire library's) and the technology row's values, each with its source.
fn wire_process(
    o: &WireOverrides,
    wire_id: String,
    wire: &Record,
    data: &Record,
    program: WireProgram,
    whole: bool,
) -> WireProcess {
    let sourced = |value: f64, source: Source| Sourced { value, source };
    let given = |job: Option<f64>, library: f64| match job {
        Some(v) => sourced(v, Source::Job),
        None => sourced(library, Source::Library),
    };
    let from_data = |field: &str| sourced(num(data, field), Source::Case);
    WireProcess {
        wire: if o.wire_diameter_mm.is_some() {
            "job".into()
        } else {
            wire_id
        },
        wire_diameter_mm: given(o.wire_diameter_mm, num(wire, "diameter_mm")),
        spark_gap_mm: given(o.spark_gap_mm, num(wire, "spark_gap_mm")),
        pulse_on_us: from_data("pulse_on_us"),
        pulse_off_us: from_data("pulse_off_us"),
        current_a: from_data("current_a"),
        cutting_rate_mm2_min: from_data("cutting_rate_mm2_min"),
        program,
        whole,
    }
}

/// Records a planned wire job in the jobs library (state `planned`; its
/// class `wire-punch` or `wire-die`, its wire in `tool_id`).
pub fn record_planned(
    conn: &Connection,
    plan: &WirePlan,
    at_ms: u64,
) -> Result<(), KnowledgeError> {
    crate::learn::record_job(
        conn,
        &crate::learn::Planned {
            job_id: plan.job_id.as_str(),
            part_number: &plan.request.spec.job.part_number,
            machine: plan.machine.id.as_str(),
            class: &format!("wire-{}", plan.die.part.as_str()),
            quantity: plan.request.spec.job.quantity,
            tool: &plan.process.wire,
            confidence: plan.confidence,
            plan_json: serde_json::to_string(plan)?,
        },
        at_ms,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db;
    use gearcam_proto::{DiePart, JobId, JobSpec};
    use serde_json::Value;

    fn request(v: Value) -> JobRequest {
        let spec: JobSpec = serde_json::from_value(v).unwrap();
        JobRequest {
            job_id: JobId::new("J-W1").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec,
        }
    }

    fn die(machine: &str, extra: Value) -> JobRequest {
        let mut v = json!({
            "job": {"family": "wire-edm", "machine": machine, "part_number": "PD-1"},
            "die": {"part": "die", "module_mm": 2.0, "teeth": 20, "thickness_mm": 20.0,
                    "material": "Cr12MoV"},
        });
        if let (Value::Object(m), Value::Object(e)) = (&mut v, extra) {
            m.extend(e);
        }
        request(v)
    }

    /// W01 threads its molybdenum wire; the spark gap comes with the wire
    /// (library), the technology from the tool-steel row (case), the form
    /// is the machine's; the job's own values win and say so.
    #[test]
    fn a_die_gets_the_machines_wire_and_the_technology_of_its_material() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan_wire(&conn, &die("W01", json!({}))).unwrap();
        assert_eq!(plan.die.part, DiePart::Die);
        let p = &plan.process;
        assert_eq!(p.wire, "MO-018");
        assert_eq!(
            (p.wire_diameter_mm.value, p.wire_diameter_mm.source),
            (0.18, Source::Library)
        );
        assert_eq!(
            (p.spark_gap_mm.value, p.spark_gap_mm.source),
            (0.01, Source::Library)
        );
        assert!((p.offset_mm() - 0.1).abs() < 1e-12);
        assert_eq!(p.program, WireProgram::ThreeB);
        assert_eq!(plan.cases[0].id, "WD-MO-TOOL");
        assert_eq!(p.cutting_rate_mm2_min.source, Source::Case);

        let plan = plan_wire(
            &conn,
            &die(
                "W01",
                json!({"wire": {"wire_diameter_mm": 0.2, "program": "4b"}}),
            ),
        )
        .unwrap();
        assert_eq!(plan.process.wire_diameter_mm.source, Source::Job);
        assert_eq!(plan.process.wire, "job");
        assert_eq!(plan.process.program, WireProgram::FourB);

        // W02 threads brass; a plate of an unknown group takes the `any` row.
        let mut req = die("W02", json!({}));
        req.spec.wire_mut().unwrap().die.as_mut().unwrap().material = "unobtainium".into();
        let plan = plan_wire(&conn, &req).unwrap();
        assert_eq!(plan.process.wire, "BR-025");
        assert_eq!(plan.cases[0].id, "WD-BR-ANY");
        assert_eq!(plan.process.program, WireProgram::IsoWire);
    }

    /// A machine whose control cannot turn a section of blocks gets whole
    /// programs by default, and a job asking it for a turned one is refused
    /// on `wire.whole`; a machine that turns them gets a quarter unless the
    /// job asks for the whole part.
    #[test]
    fn a_control_without_rotation_gets_whole_programs() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan_wire(&conn, &die("W01", json!({}))).unwrap();
        assert!(plan.machine.rotates);
        assert!(!plan.process.whole);
        let plan = plan_wire(&conn, &die("W01", json!({"wire": {"whole": true}}))).unwrap();
        assert!(plan.process.whole);
        conn.execute("UPDATE wire_machines SET rotates = 0 WHERE id = 'W01'", [])
            .unwrap();
        let plan = plan_wire(&conn, &die("W01", json!({}))).unwrap();
        assert!(!plan.machine.rotates);
        assert!(plan.process.whole);
        let e = plan_wire(&conn, &die("W01", json!({"wire": {"whole": false}}))).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str(), e[0].got.as_str()),
            ("PROGRAM_FORM", "wire.whole", "false")
        );
        assert!(e[0].expected.contains("W01"), "{:?}", e[0]);
    }

    /// A die job for a hobbing machine, a [gear] section in it, or no [die].
    #[test]
    fn a_die_job_refuses_other_families_machines_and_sections() {
        let conn = db::open_in_memory().unwrap();
        let e = plan_wire(&conn, &die("H01", json!({}))).unwrap_err();
        assert_eq!(e[0].code, "MACHINE_FAMILY");
        assert!(e[0].expected.contains("W01"), "{:?}", e[0]);
        let foreign = serde_json::from_value::<gearcam_proto::JobSpec>(json!({
            "job": {"family": "wire-edm", "machine": "W01", "part_number": "PD-1"},
            "gear": {"module_mm": 2.0, "teeth": 20, "face_width_mm": 10.0, "fixture_height_mm": 100.0},
        }))
        .unwrap_err();
        assert!(
            foreign
                .to_string()
                .contains("[gear] belongs to the hobbing family"),
            "{foreign}"
        );
        let mut req = die("W01", json!({}));
        req.spec.wire_mut().unwrap().die = None;
        let e = plan_wire(&conn, &req).unwrap_err();
        assert_eq!(
            (e[0].code.as_str(), e[0].field.as_str()),
            ("MISSING_SECTION", "die")
        );
        let e = plan_wire(&conn, &die("W01", json!({"wire": {"wire": "NOPE"}}))).unwrap_err();
        assert_eq!(e[0].code, "UNKNOWN_WIRE");
    }

    /// A planned die is a row of the jobs library with its family's class,
    /// and that row can be edited like any other (its class is one the
    /// library knows).
    #[test]
    fn a_planned_wire_job_is_a_jobs_row_of_its_class() {
        let conn = db::open_in_memory().unwrap();
        let plan = plan_wire(&conn, &die("W01", json!({}))).unwrap();
        record_planned(&conn, &plan, 1).unwrap();
        let row = library::get(&conn, &library::JOBS, "J-W1")
            .unwrap()
            .unwrap();
        assert_eq!(row["class"], "wire-die");
        let mut set = Record::new();
        set.insert("quantity".into(), json!(3));
        let edited = library::edit(&conn, &library::JOBS, "J-W1", &set);
        assert!(edited.is_ok(), "{edited:?}");
    }
}
