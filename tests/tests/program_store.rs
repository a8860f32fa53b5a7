//! The program store's ownership and edit rules, through the real binary
//! and services on loopback: a program name belongs to one part, and an
//! operator's edit at the machine has a way forward that keeps the edit in
//! the history.
// Test code: a clock for the waits.
#![allow(clippy::disallowed_methods)]

use std::time::{Duration, Instant};

use gearcam_proto::{decode, encode, keys, JobId, JobRequest, JobSpec, StationReply};
use gearcam_testkit::{gearcam, Cluster};

/// The example job `file` with its part number (and program name, if given).
fn job_text(file: &str, part: &str, program_name: Option<&str>) -> String {
    let text = gearcam_testkit::examples::example(file);
    let mut doc: toml::Table = toml::from_str(&text).unwrap();
    let job = doc["job"].as_table_mut().unwrap();
    job.insert("part_number".into(), part.into());
    if let Some(name) = program_name {
        job.insert("program_name".into(), name.into());
    }
    toml::to_string(&doc).unwrap()
}

fn history(c: &Cluster, machine: &str) -> Vec<serde_json::Value> {
    let (code, out, err) = gearcam(&[
        "program",
        "history",
        "--machine",
        machine,
        "--connect",
        &c.endpoint,
        "--json",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let h: serde_json::Value = serde_json::from_str(&out).unwrap();
    h["versions"].as_array().unwrap().clone()
}

/// Long 840D part numbers must not be cut to one name, and the FANUC rule
/// must not give `XX-9-2107` the current `O2107` of part `HG-2107`.
#[test]
fn a_program_name_belongs_to_one_part() {
    let mut c = Cluster::start();
    c.start_agent_for("H02");

    // 840D: two parts whose numbers differ after the 24th character.
    let mut names = Vec::new();
    for (i, part) in [
        "GEARBOX-OUTPUT-SHAFT-PINION-STAGE2-A",
        "GEARBOX-OUTPUT-SHAFT-PINION-STAGE2-B",
    ]
    .iter()
    .enumerate()
    {
        let f = c.job_file(
            &format!("long{i}.toml"),
            &job_text("spur_840d.toml", part, None),
        );
        let (_, v) = c.submit_wait(&f);
        assert_eq!(v["state"], "delivered", "{v}");
        names.push(v["program"]["name"].as_str().unwrap().to_string());
    }
    assert_ne!(names[0], names[1]);
    let h = history(&c, "H01");
    for (name, part) in names.iter().zip(["-A", "-B"]) {
        let v = h.iter().find(|v| v["name"] == name.as_str()).unwrap();
        assert!(v["part_number"].as_str().unwrap().ends_with(part), "{v}");
    }

    // FANUC: the digit rule gives both parts O2107; the second is refused,
    // naming both parts, and the first part's program is untouched.
    let f = c.job_file(
        "hg.toml",
        &job_text("helical_shift_fanuc.toml", "HG-2107", None),
    );
    let (_, v) = c.submit_wait(&f);
    assert_eq!(v["program"]["name"], "O2107", "{v}");
    let o2107 = c.dir.path().join("H02/programs/O2107");
    let before = std::fs::read(&o2107).unwrap();
    let f = c.job_file(
        "xx.toml",
        &job_text("helical_shift_fanuc.toml", "XX-9-2107", None),
    );
    let (out, v) = c.submit_wait(&f);
    assert_eq!(v["state"], "failed", "{v}");
    assert_eq!(out.status.code(), Some(1));
    let e = &v["errors"][0];
    assert_eq!(e["code"], "PROGRAM_NAME_TAKEN", "{v}");
    let message = e["message"].as_str().unwrap();
    assert!(
        message.contains("HG-2107") && message.contains("XX-9-2107"),
        "{message}"
    );
    assert!(
        message.contains("O2108"),
        "a free name is offered: {message}"
    );
    assert_eq!(std::fs::read(&o2107).unwrap(), before);

    // The job names its own program, as the refusal says.
    let f = c.job_file(
        "xx2.toml",
        &job_text("helical_shift_fanuc.toml", "XX-9-2107", Some("O2108")),
    );
    let (_, v) = c.submit_wait(&f);
    assert_eq!(
        (v["state"].as_str(), v["program"]["name"].as_str()),
        (Some("delivered"), Some("O2108")),
        "{v}"
    );
    let h = history(&c, "H02");
    let parts: Vec<(&str, &str)> = h
        .iter()
        .map(|v| {
            (
                v["name"].as_str().unwrap(),
                v["part_number"].as_str().unwrap(),
            )
        })
        .collect();
    assert_eq!(parts, [("O2108", "XX-9-2107"), ("O2107", "HG-2107")]);
    // The table shows the part beside the name.
    let (_, table, _) = gearcam(&[
        "program",
        "history",
        "--machine",
        "H02",
        "--connect",
        &c.endpoint,
    ]);
    assert!(table.lines().next().unwrap().contains("PART"), "{table}");
    assert!(
        table
            .lines()
            .any(|l| l.contains("O2107") && l.contains("HG-2107")),
        "{table}"
    );

    // An empty part number at the wire (a client other than the CLI) is
    // refused on its field; it was every job's `GC_PART`.
    let mut spec: JobSpec =
        toml::from_str(&gearcam_testkit::examples::example("spur_840d.toml")).unwrap();
    spec.job.part_number = " ".into();
    let reply = submit_raw(&c.endpoint, spec);
    let StationReply::Refused { errors } = reply else {
        panic!("accepted: {reply:?}")
    };
    assert_eq!(
        (errors[0].code.as_str(), errors[0].field.as_str()),
        ("INVALID_PART_NUMBER", "spec.job.part_number")
    );
    // An infinite module at the wire is refused on its field by the
    // station, before the knowledge service would look for a hob of
    // module inf.
    let mut spec: JobSpec =
        toml::from_str(&gearcam_testkit::examples::example("spur_840d.toml")).unwrap();
    spec.hobbing_mut()
        .unwrap()
        .gear
        .as_mut()
        .expect("the example's gear")
        .module_mm = f64::INFINITY;
    let reply = submit_raw(&c.endpoint, spec);
    let StationReply::Refused { errors } = reply else {
        panic!("accepted: {reply:?}")
    };
    assert_eq!(
        (errors[0].code.as_str(), errors[0].field.as_str()),
        ("NOT_FINITE", "spec.gear.module_mm"),
        "{errors:?}"
    );
}

/// Submits a job over a Zenoh session of its own, as a foreign client would.
fn submit_raw(endpoint: &str, spec: JobSpec) -> StationReply {
    let request = JobRequest {
        job_id: JobId::new("RAW-EMPTY-PART").unwrap(),
        submitted_at_ms: 1,
        submitted_by: "test".into(),
        spec,
    };
    tokio::runtime::Runtime::new().unwrap().block_on(async {
        let session = zenoh::open(gearcam_testkit::client_config(endpoint))
            .await
            .unwrap();
        let deadline = Instant::now() + Duration::from_secs(20);
        loop {
            let replies = session
                .get(keys::station_submit("test"))
                .payload(encode(&request).unwrap())
                .timeout(Duration::from_secs(5))
                .await
                .unwrap();
            if let Ok(reply) = replies.recv_async().await {
                let bytes = reply.result().expect("a reply").payload().to_bytes();
                return decode::<StationReply>(&bytes).unwrap();
            }
            // No station queryable yet: retry.
            assert!(Instant::now() < deadline, "the station never answered");
            tokio::time::sleep(Duration::from_millis(200)).await;
        }
    })
}

/// An edit at the machine, once detected, must not fail the job for good,
/// refuse later jobs of the program, or stay out of the history: the job
/// waits until the edit is resolved, and the edit is kept.
#[test]
fn an_edit_at_the_machine_is_resolved_and_kept() {
    let c = Cluster::start();
    let text = gearcam_testkit::examples::example("spur_840d.toml");
    let (_, v) = c.submit_wait(&c.job_file("first.toml", &text));
    assert_eq!(v["state"], "delivered", "{v}");
    let path = c.program_dir().join("_N_SP_1001_MPF");
    let edited = std::fs::read_to_string(&path)
        .unwrap()
        .replace("; PART", "; EDITED BY THE OPERATOR\n; PART");
    std::fs::write(&path, &edited).unwrap();

    // A new program for the part waits on the conflict, and says so.
    let second = text.replace("quantity = 20", "quantity = 21");
    let v = c.submit(&c.job_file("second.toml", &second));
    let id = v["job"].as_str().unwrap().to_string();
    let v = c.wait_status(&id, |v| {
        v["waiting_for"]
            .as_str()
            .is_some_and(|w| w.contains("PROGRAM_CHANGED_AT_MACHINE"))
    });
    assert_eq!(v["state"], "waiting");
    assert!(
        v["waiting_for"]
            .as_str()
            .unwrap()
            .contains("gearcam program resolve SP_1001 --machine H01"),
        "{v}"
    );
    let (_, jobs, _) = gearcam(&["jobs", "--connect", &c.endpoint]);
    assert!(jobs.contains("PROGRAM_CHANGED_AT_MACHINE"), "{jobs}");
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        edited,
        "the edit was overwritten"
    );

    // Adopt the edit: it becomes a version, with who. The decision is
    // final: the job that waited to replace it ends superseded, and no
    // re-drive ever writes over the adopted edit (the station re-drives
    // every second here: several pass).
    let (code, out, err) = gearcam(&[
        "program",
        "resolve",
        "SP_1001",
        "--machine",
        "H01",
        "--adopt",
        "--by",
        "operator Li",
        "--connect",
        &c.endpoint,
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("end superseded") && out.contains(&id), "{out}");
    let v = c.wait_status(&id, |v| v["state"] == "superseded");
    assert_eq!(v["errors"][0]["code"], "JOB_SUPERSEDED", "{v}");
    assert!(
        v["errors"][0]["got"]
            .as_str()
            .unwrap()
            .contains("adopted by operator Li"),
        "{v}"
    );
    std::thread::sleep(std::time::Duration::from_secs(4));
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        edited,
        "a re-drive overwrote the adopted edit"
    );
    let v = c.wait_status(&id, |_| true);
    assert_eq!(v["state"], "superseded", "{v}");
    let h = history(&c, "H01");
    let states: Vec<(&str, &str)> = h
        .iter()
        .map(|v| (v["state"].as_str().unwrap(), v["by"].as_str().unwrap_or("")))
        .collect();
    assert_eq!(states, [("adopted", "operator Li"), ("stored", "")]);
    let (_, jobs, _) = gearcam(&["jobs", "--connect", &c.endpoint]);
    assert!(
        jobs.contains("superseded") && jobs.contains("JOB_SUPERSEDED"),
        "{jobs}"
    );
    let adopted = h[0]["seq"].as_u64().unwrap().to_string();
    let (_, text, _) = gearcam(&[
        "program",
        "show",
        "SP_1001",
        &adopted,
        "--machine",
        "H01",
        "--connect",
        &c.endpoint,
    ]);
    assert_eq!(text, edited);

    // Replace: gearcam's version goes back, the edit stays in the history,
    // and a job that waited on it is delivered.
    std::fs::write(&path, "; a second edit\n").unwrap();
    let third = gearcam_testkit::examples::example("spur_840d.toml")
        .replace("quantity = 20", "quantity = 22");
    let v = c.submit(&c.job_file("third.toml", &third));
    let third_id = v["job"].as_str().unwrap().to_string();
    c.wait_status(&third_id, |v| {
        v["waiting_for"]
            .as_str()
            .is_some_and(|w| w.contains("PROGRAM_CHANGED_AT_MACHINE"))
    });
    let (code, out, err) = gearcam(&[
        "program",
        "resolve",
        "SP_1001",
        "--machine",
        "H01",
        "--replace",
        "--by",
        "planner Wang",
        "--connect",
        &c.endpoint,
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("delivered at their next re-drive"), "{out}");
    let v = c.wait_status(&third_id, |v| v["state"] == "delivered");
    assert_eq!(v["program"]["name"], "SP_1001");
    let h = history(&c, "H01");
    let states: Vec<&str> = h.iter().map(|v| v["state"].as_str().unwrap()).collect();
    assert_eq!(states[..3], ["stored", "restored", "machine-edit"]);
    assert_eq!(h[0]["job"], third_id.as_str());
    assert_eq!(
        std::fs::read(&path).unwrap().len() as u64,
        h[0]["size_bytes"].as_u64().unwrap()
    );
    // Nothing left to resolve: a typed refusal, exit 1.
    let (code, _, err) = gearcam(&[
        "program",
        "resolve",
        "SP_1001",
        "--machine",
        "H01",
        "--adopt",
        "--connect",
        &c.endpoint,
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("NO_CONFLICT"), "{err}");
}

/// `gearcam cancel`: a journaled job not yet delivered ends `cancelled`,
/// with who, and is never stored after — not by a re-drive once its
/// conflict is resolved, not by a program of it that reaches the agent
/// late. A delivered job cannot be cancelled (`JOB_FINAL`), an unknown one
/// is not found, a second cancel answers the same.
#[test]
fn a_cancelled_job_is_never_stored() {
    let c = Cluster::start();
    let text = gearcam_testkit::examples::example("spur_840d.toml");
    let (_, v) = c.submit_wait(&c.job_file("first.toml", &text));
    assert_eq!(v["state"], "delivered", "{v}");
    let first = v["job"].as_str().unwrap().to_string();
    let path = c.program_dir().join("_N_SP_1001_MPF");
    let edited = std::fs::read_to_string(&path).unwrap() + "; EDITED\n";
    std::fs::write(&path, &edited).unwrap();
    let second = text.replace("quantity = 20", "quantity = 21");
    let v = c.submit(&c.job_file("second.toml", &second));
    let id = v["job"].as_str().unwrap().to_string();
    c.wait_status(&id, |v| {
        v["waiting_for"]
            .as_str()
            .is_some_and(|w| w.contains("PROGRAM_CHANGED_AT_MACHINE"))
    });

    let cancel = |job: &str| {
        gearcam(&[
            "cancel",
            job,
            "--by",
            "planner Wang",
            "--connect",
            &c.endpoint,
        ])
    };
    let (code, out, err) = cancel(&id);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("cancelled"), "{out}");
    let v = c.wait_status(&id, |_| true);
    assert_eq!(v["state"], "cancelled", "{v}");
    assert_eq!(v["errors"][0]["code"], "JOB_CANCELLED");
    assert!(v["errors"][0]["got"]
        .as_str()
        .unwrap()
        .contains("planner Wang"));
    // Again: the same answer. A delivered job: JOB_FINAL. An unknown one: 3.
    assert_eq!(cancel(&id).0, Some(0));
    let (code, _, err) = cancel(&first);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("JOB_FINAL"), "{err}");
    assert_eq!(cancel("NO-SUCH-JOB").0, Some(3));

    // The conflict resolved: the cancelled job is not re-driven onto the
    // machine.
    let (code, out, err) = gearcam(&[
        "program",
        "resolve",
        "SP_1001",
        "--machine",
        "H01",
        "--replace",
        "--by",
        "operator Li",
        "--connect",
        &c.endpoint,
    ]);
    assert_eq!(code, Some(0), "{out}{err}");
    std::thread::sleep(Duration::from_secs(4));
    let stored: Vec<serde_json::Value> = history(&c, "H01")
        .into_iter()
        .filter(|v| v["job"] == id.as_str() && v["state"] == "stored")
        .collect();
    assert!(stored.is_empty(), "{stored:?}");

    // Its program, made again from the journaled request exactly as the
    // services make it, delivered straight to the agent as a late sender
    // would: refused, JOB_CANCELLED, nothing written.
    let request: Vec<u8> = rusqlite::Connection::open(c.dir().join("station.db"))
        .unwrap()
        .query_row("SELECT request FROM jobs WHERE job = ?1", [&id], |r| {
            r.get(0)
        })
        .unwrap();
    let request: JobRequest = decode(&request).unwrap();
    let conn = gearcam_knowledge::db::open_in_memory().unwrap();
    let plan = gearcam_knowledge::plan::plan(&conn, &request).unwrap();
    let model = gearcam_model::compute(&plan).unwrap();
    let program = gearcam_testkit::pipeline::program_of(&model).unwrap();
    let before = std::fs::read(&path).unwrap();
    let rt = tokio::runtime::Runtime::new().unwrap();
    let reply = rt.block_on(async {
        let session = zenoh::open(gearcam_testkit::client_config(&c.endpoint))
            .await
            .unwrap();
        let replies = session
            .get(keys::machine_program(&program.machine, &program.job_id))
            .payload(encode(&program).unwrap())
            .timeout(Duration::from_secs(10))
            .await
            .unwrap();
        let reply = replies.recv_async().await.expect("the agent answers");
        decode::<gearcam_proto::DeliveryReply>(
            &reply.result().expect("a reply").payload().to_bytes(),
        )
        .unwrap()
    });
    match reply {
        gearcam_proto::DeliveryReply::Refused { error } => {
            assert_eq!(error.code, "JOB_CANCELLED", "{error:?}")
        }
        other => panic!("a cancelled job's program was answered {other:?}"),
    }
    assert_eq!(std::fs::read(&path).unwrap(), before);
}

/// `gearcam` with the environment of a user, or with no login name at all.
fn gearcam_as(user: Option<&str>, args: &[&str]) -> (Option<i32>, String, String) {
    let mut cmd = std::process::Command::new(gearcam_testkit::bin("gearcam"));
    cmd.args(args)
        .env_remove("USER")
        .env_remove("LOGNAME")
        .stdin(std::process::Stdio::null());
    if let Some(u) = user {
        cmd.env("USER", u);
    }
    let out = cmd.output().expect("gearcam runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Who did it, one rule everywhere: the login name, else `unknown` (not
/// `gearcam`, `planner` or no one), written with every change — an
/// adoption, a rollback, a cancellation, a knowledge-base edit.
#[test]
fn who_did_it_is_the_login_name_else_unknown() {
    let c = Cluster::start();
    let text = gearcam_testkit::examples::example("spur_840d.toml");
    let (_, v) = c.submit_wait(&c.job_file("first.toml", &text));
    assert_eq!(v["state"], "delivered", "{v}");
    let path = c.program_dir().join("_N_SP_1001_MPF");
    std::fs::write(&path, std::fs::read_to_string(&path).unwrap() + "; EDIT\n").unwrap();
    let e = &c.endpoint;
    let (code, out, err) = gearcam_as(
        None,
        &[
            "program",
            "resolve",
            "SP_1001",
            "--machine",
            "H01",
            "--adopt",
            "--connect",
            e,
        ],
    );
    assert_eq!(code, Some(0), "{out}{err}");
    let first = history(&c, "H01").last().unwrap()["seq"].as_u64().unwrap();
    let (code, out, err) = gearcam_as(
        Some("alice"),
        &[
            "program",
            "rollback",
            "SP_1001",
            &first.to_string(),
            "--machine",
            "H01",
            "--connect",
            e,
        ],
    );
    assert_eq!(code, Some(0), "{out}{err}");
    let h = history(&c, "H01");
    let by: Vec<(&str, &str)> = h
        .iter()
        .map(|v| (v["state"].as_str().unwrap(), v["by"].as_str().unwrap_or("")))
        .collect();
    assert_eq!(by[..2], [("rollback", "alice"), ("adopted", "unknown")]);

    // A cancellation.
    std::fs::write(&path, "; another edit\n").unwrap();
    let v = c.submit(&c.job_file(
        "second.toml",
        &text.replace("quantity = 20", "quantity = 21"),
    ));
    let id = v["job"].as_str().unwrap().to_string();
    let (code, out, err) = gearcam_as(None, &["cancel", &id, "--connect", e]);
    assert_eq!(code, Some(0), "{out}{err}");
    let v = c.wait_status(&id, |_| true);
    assert_eq!(v["errors"][0]["got"], "cancelled by unknown", "{v}");

    // A knowledge-base edit, in a data directory of its own.
    let data = c.dir().join("local");
    let d = data.display().to_string();
    let (code, out, err) = gearcam_as(
        None,
        &[
            "kb",
            "edit",
            "wire-machines",
            "W01",
            "--set",
            "rotates=false",
            "--data",
            &d,
        ],
    );
    assert_eq!(code, Some(0), "{out}{err}");
    let (_, out, _) = gearcam_as(
        None,
        &["kb", "changes", "--limit", "1", "--json", "--data", &d],
    );
    assert!(out.contains("\"unknown\""), "{out}");
}
