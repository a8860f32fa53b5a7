//! Transport security and access control through a router configured from
//! `deploy/secure/` (TLS, a user and password per service, ACL default deny):
//! the pipeline works for the services, and a planner cannot deliver a program
//! or forge a stage's message, nor change a machine's current program (a
//! supervisor can); a wrong password cannot even connect.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use gearcam_proto::plan::{
    ConfirmReply, ConfirmRequest, KbLogReply, KbOp, KbRecord, KbReply, KbRequest, KbValue,
};
use gearcam_proto::{
    decode, encode, keys, DeliveryReply, Dialect, JobId, JobIds, MachineId, NcProgram,
    StationReply, StoreReply, StoreRequest, TemplateRef,
};
use gearcam_testkit::bin;
use gearcam_testkit::secure::Secure;
use sha2::{Digest, Sha256};

const JOB: &str = r#"
[job]
machine = "H01"
part_number = "SEC-0001"
[gear]
module_mm = 3.0
teeth = 25
face_width_mm = 30.0
fixture_height_mm = 100.0
[hob]
id = "HOB-M3-80"
"#;

fn submit(dir: &Path, planner: &Path, part: &str) -> serde_json::Value {
    submit_text(dir, planner, part, &JOB.replace("SEC-0001", part))
}

/// Submits the job file `text` as `{part}.toml`, waiting for the outcome.
fn submit_text(dir: &Path, planner: &Path, part: &str, text: &str) -> serde_json::Value {
    let job = dir.join(format!("{part}.toml"));
    std::fs::write(&job, text).unwrap();
    let out = Command::new(bin("gearcam"))
        .args([
            "submit",
            &job.display().to_string(),
            "--config",
            &planner.display().to_string(),
            "--wait",
            "--json",
            "--timeout",
            "60",
        ])
        .output()
        .unwrap();
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "no JSON ({e}): {} {}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

async fn planner_session(config: &Path) -> zenoh::Result<zenoh::Session> {
    zenoh::open(zenoh::Config::from_file(config)?).await
}

#[test]
fn services_work_through_the_secure_router_and_planners_cannot_deliver_or_forge() {
    let mut secure = Secure::start();
    let dir = secure.dir().to_path_buf();
    let dir = dir.as_path();
    let cfg = |name: &str| secure.cfg(name).display().to_string();
    let programs = dir.join("H01/programs");
    let logs = || secure.logs();
    let planner = PathBuf::from(cfg("planner"));
    let planner_cfg = planner.clone();

    // The whole pipeline works through TLS, passwords and the ACL.
    let v = submit(dir, &planner, "SEC-0001");
    assert_eq!(v["state"], "delivered", "{v}\n{}", logs());
    let sec_job = JobId::new(v["job"].as_str().unwrap()).unwrap();
    // So does a wire EDM die to W01 under its own agent user.
    let die = std::fs::read_to_string(gearcam_testkit::examples::dir().join("die_m2z20_3b.toml"))
        .unwrap()
        .replace("PD-2001", "SEC-W001");
    let v = submit_text(dir, &planner, "SEC-W001", &die);
    assert_eq!(v["state"], "delivered", "{v}\n{}", logs());
    assert!(dir.join("W01/programs/SEC-W001.3b").is_file(), "{}", logs());

    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        // A wrong password cannot connect.
        let bad = dir.join("bad.json5");
        std::fs::write(
            &bad,
            std::fs::read_to_string(&planner)
                .unwrap()
                .replace("change-me-planner", "guess"),
        )
        .unwrap();
        assert!(
            planner_session(&bad).await.is_err(),
            "a wrong password must not open a session"
        );

        let session = planner_session(&planner)
            .await
            .expect("the planner connects");
        // The station received the job's model from the model service and
        // journaled it; a planner reads it from the station.
        let replies = session
            .get(keys::station_job_model(&sec_job))
            .timeout(Duration::from_secs(5))
            .await
            .unwrap();
        let reply = replies.recv_async().await.expect("the station answers");
        let bytes = reply.result().expect("a model").payload().to_bytes();
        match <gearcam_proto::AnyModel as gearcam_proto::Incoming>::decode_incoming(&bytes) {
            Ok(gearcam_proto::AnyModel::Hobbing(m)) => assert_eq!(m.job_id, sec_job),
            other => panic!("the station's model of {sec_job}: {other:?}\n{}", logs()),
        }
        // A planner may not deliver a program to a machine: the router drops the query.
        let text = "%_N_EVIL_MPF\n;$PATH=/_N_MPF_DIR\nM2\n".to_string();
        let program = NcProgram {
            job_id: JobId::new("EVIL-1").unwrap(),
            machine: MachineId::new("H01").unwrap(),
            name: "EVIL".into(),
            revision: 1,
            dialect: Dialect::Sinumerik840d,
            sha256: hex::encode(Sha256::digest(text.as_bytes())),
            text,
            template: TemplateRef {
                id: "forged".into(),
                version: 1,
            },
            part_number: "EVIL".into(),
            cases: vec![],
            model_version: "-".into(),
            generator: "-".into(),
            path_check: Default::default(),
            form: None,
            simulation: None,
        };
        let replies = session
            .get("gearcam/v1/machines/H01/programs/EVIL-1")
            .payload(encode(&program).unwrap())
            .timeout(Duration::from_secs(3))
            .await
            .unwrap();
        assert!(
            replies.recv_async().await.is_err(),
            "the agent must not see a planner's delivery"
        );
        // Nor forge a stage's message (a plan): no stage reacts to it.
        let events = session
            .declare_subscriber("gearcam/v1/jobs/EVIL-2/events/*")
            .await
            .unwrap();
        session
            .put("gearcam/v1/jobs/EVIL-2/plan", vec![0x80])
            .await
            .unwrap();
        let heard = tokio::time::timeout(Duration::from_secs(3), events.recv_async()).await;
        assert!(heard.is_err(), "a forged plan reached the model service");
        // A planner may not change a machine's current program, neither
        // under its own name nor under the supervisor's; a supervisor may.
        let h01 = MachineId::new("H01").unwrap();
        let change = keys::store_change(&h01, "supervisor", "SEC_0001");
        let rollback = encode(&StoreRequest::Rollback {
            seq: 1,
            by: "supervisor".into(),
        })
        .unwrap();
        for key in [
            keys::store_change(&h01, "planner", "SEC_0001"),
            change.clone(),
        ] {
            let replies = session
                .get(&key)
                .payload(rollback.clone())
                .timeout(Duration::from_secs(3))
                .await
                .unwrap();
            assert!(
                replies.recv_async().await.is_err(),
                "the agent must not see a planner's rollback on {key}"
            );
        }
        session.close().await.unwrap();
        let supervisor = planner_session(Path::new(&cfg("supervisor")))
            .await
            .expect("the supervisor connects");
        let replies = supervisor
            .get(&change)
            .payload(rollback)
            .timeout(Duration::from_secs(5))
            .await
            .unwrap();
        let reply = replies
            .recv_async()
            .await
            .expect("the agent answers a supervisor");
        let sample = reply.result().expect("a typed reply");
        match decode::<StoreReply>(&sample.payload().to_bytes()).unwrap() {
            StoreReply::Changed { receipt, .. } => assert_eq!(receipt.name, "SEC_0001"),
            other => panic!("a supervisor's rollback: {other:?}"),
        }
        // A planner cannot write the knowledge base.
        // A change on the change key does not even reach the service; one
        // hidden in a read query is refused; H01's spindle M-code stays 3.
        let planner = planner_session(&planner_cfg)
            .await
            .expect("the planner connects");
        let mut set = KbRecord::new();
        set.insert("mcodes.spindle_on".into(), KbValue::Int(4));
        let edit = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: "planner".into(),
        };
        let replies = planner
            .get(keys::kb_change("planner", "machines", Some("H01")))
            .payload(encode(&edit).unwrap())
            .timeout(Duration::from_secs(3))
            .await
            .unwrap();
        assert!(
            replies.recv_async().await.is_err(),
            "a planner's change reached the knowledge base"
        );
        let replies = planner
            .get(keys::kb_record("machines", "H01"))
            .payload(encode(&edit).unwrap())
            .timeout(Duration::from_secs(5))
            .await
            .unwrap();
        let reply = replies.recv_async().await.expect("a read is answered");
        let reply: KbReply = decode(&reply.result().unwrap().payload().to_bytes()).unwrap();
        assert_eq!(reply.errors[0].code, "KB_WRONG_KEY", "{reply:?}");
        planner.close().await.unwrap();
        // An administrator (the supervisor) can; the change is recorded as
        // the supervisor's login, whatever name the payload gives.
        let mut set = KbRecord::new();
        set.insert("coating".into(), KbValue::Text("TiAlN".into()));
        let edit = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: "supervisor Wu".into(),
        };
        let replies = supervisor
            .get(keys::kb_change("supervisor", "hobs", Some("HOB-M3-80")))
            .payload(encode(&edit).unwrap())
            .timeout(Duration::from_secs(5))
            .await
            .unwrap();
        let reply = replies
            .recv_async()
            .await
            .expect("the supervisor's change is answered");
        let reply: KbReply = decode(&reply.result().unwrap().payload().to_bytes()).unwrap();
        assert!(reply.errors.is_empty(), "{reply:?}");
        supervisor.close().await.unwrap();
    });
    let kb = rusqlite::Connection::open(dir.join("kb.db")).unwrap();
    let spindle: String = kb
        .query_row(
            "SELECT profile_json FROM machines WHERE id = 'H01'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    let spindle: serde_json::Value = serde_json::from_str(&spindle).unwrap();
    assert_eq!(
        spindle["mcodes"]["spindle_on"], 3,
        "a planner changed H01's spindle M-code"
    );
    let (by, op): (String, String) = kb
        .query_row(
            "SELECT by_user, op FROM kb_changes WHERE library = 'hobs' AND record_id = 'HOB-M3-80' ORDER BY seq DESC LIMIT 1",
            [],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .unwrap();
    assert_eq!((by.as_str(), op.as_str()), ("supervisor", "edit"));
    // Nothing was stored that should not be, and everything still serves.
    assert!(!programs.join("_N_EVIL_MPF").exists());
    let v = submit(dir, &planner, "SEC-0002");
    assert_eq!(v["state"], "delivered", "{v}\n{}", logs());
    let mut files: Vec<String> = std::fs::read_dir(&programs)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    assert_eq!(files, ["_N_SEC_0001_MPF", "_N_SEC_0002_MPF"]);
    let log = secure.logs();
    for p in &mut secure.procs {
        assert!(p.running(), "{} died\n{log}", p.name);
    }
}

/// Runs `gearcam ARGS --config CONFIG`; exit code, stdout, stderr.
fn cli(config: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(bin("gearcam"))
        .args(args)
        .arg("--config")
        .arg(config)
        .output()
        .unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Every machine and every role on the secure deployment, every bus command
/// of the CLI; nobody declares another's liveliness token (a planner's
/// `alive/agent/H09` would make the station drive jobs to an absent agent).
#[test]
fn every_role_machine_and_command_on_the_secure_deployment() {
    let secure = Secure::start();
    let dir = secure.dir();
    let (planner, operator, admin) = (
        secure.cfg("planner"),
        secure.cfg("operator"),
        secure.cfg("admin"),
    );

    // Both machines: an 840D job to H01, a FANUC job to H02.
    let v = submit(dir, &planner, "SEC-0101");
    assert_eq!(v["state"], "delivered", "{v}\n{}", secure.logs());
    let h01_job = JobId::new(v["job"].as_str().unwrap()).unwrap();
    let fanuc = gearcam_testkit::examples::example("helical_shift_fanuc.toml");
    let job = dir.join("fanuc.toml");
    std::fs::write(&job, fanuc).unwrap();
    let (code, out, err) = cli(
        &planner,
        &[
            "submit",
            job.to_str().unwrap(),
            "--wait",
            "--json",
            "--timeout",
            "60",
        ],
    );
    assert_eq!(code, Some(0), "{out}{err}\n{}", secure.logs());
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["program"]["name"], "O2107", "{v}");
    let id = v["job"].as_str().unwrap().to_string();
    let h02_job = JobId::new(id.as_str()).unwrap();

    // A planner's reads.
    for args in [
        vec!["jobs", "--json"],
        vec!["status", id.as_str(), "--json"],
        vec!["program", "history", "--machine", "H02", "--json"],
        vec!["program", "show", "O2107", "1", "--machine", "H02"],
    ] {
        let (code, _, err) = cli(&planner, &args);
        assert_eq!(code, Some(0), "planner {args:?}: {err}");
    }
    // Changing a machine's program: the operator may, a planner and an
    // admin may not (the router drops the query: nothing answers).
    let rollback = [
        "program",
        "rollback",
        "O2107",
        "1",
        "--machine",
        "H02",
        "--json",
    ];
    for who in [&planner, &admin] {
        let (code, _, err) = cli(who, &rollback);
        assert_eq!(code, Some(2), "{} may not roll back: {err}", who.display());
    }
    let (code, out, err) = cli(&operator, &rollback);
    assert_eq!(code, Some(0), "the operator rolls back: {out}{err}");
    let (code, _, err) = cli(
        &operator,
        &["program", "resolve", "O2107", "--machine", "H02", "--adopt"],
    );
    assert_eq!(
        code,
        Some(1),
        "the operator's resolve is answered (nothing to resolve): {err}"
    );
    assert!(err.contains("NO_CONFLICT"), "{err}");

    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        // Changing the knowledge base: the admin may, under its own name;
        // the operator may not, and neither may the admin under the
        // supervisor's name.
        let mut set = KbRecord::new();
        set.insert("coating".into(), KbValue::Text("AlCrN".into()));
        let edit = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: "admin Li".into(),
        };
        for (who, user, answered) in [
            (&operator, "operator", false),
            (&admin, "supervisor", false),
            (&admin, "admin", true),
        ] {
            let s = planner_session(who).await.unwrap();
            let replies = s
                .get(keys::kb_change(user, "hobs", Some("HOB-M3-80")))
                .payload(encode(&edit).unwrap())
                .timeout(Duration::from_secs(3))
                .await
                .unwrap();
            assert_eq!(
                replies.recv_async().await.is_ok(),
                answered,
                "{}",
                who.display()
            );
            s.close().await.unwrap();
        }
        // Every role reads the change log: the admin's change is the newest.
        let s = planner_session(&planner).await.unwrap();
        let replies = s
            .get(keys::kb_log(Some("hobs"), Some("HOB-M3-80")))
            .timeout(Duration::from_secs(5))
            .await
            .unwrap();
        let reply = replies.recv_async().await.expect("a planner reads the log");
        let log: KbLogReply = decode(&reply.result().unwrap().payload().to_bytes()).unwrap();
        assert_eq!(log.changes[0].by, "admin", "{log:?}");
        // Confirming a delivered job: a planner may, under their own name
        // only; the job becomes a case recorded as the planner's.
        let confirm = ConfirmRequest {
            quantity: Some(1),
            cutting_speed_m_min: None,
            feed_mm_per_rev: None,
            cuts: None,
            outcome: "ok".into(),
            quality_achieved: None,
            notes: String::new(),
            confidence: 0.8,
            undelivered: false,
        };
        for (user, answered) in [("admin", false), ("planner", true)] {
            let replies = s
                .get(keys::kb_confirm(user, &h01_job))
                .payload(encode(&confirm).unwrap())
                .timeout(Duration::from_secs(5))
                .await
                .unwrap();
            let reply = replies.recv_async().await;
            assert_eq!(reply.is_ok(), answered, "a planner confirms as {user}");
            if let Ok(reply) = reply {
                let r: ConfirmReply =
                    decode(&reply.result().unwrap().payload().to_bytes()).unwrap();
                assert!(r.errors.is_empty(), "{r:?}");
                let provenance = &r.case.expect("the case")["provenance"];
                assert!(
                    matches!(provenance, KbValue::Text(p) if p.contains("by planner")),
                    "{provenance:?}"
                );
            }
        }
        s.close().await.unwrap();
        // A planner cannot report a job's events, not even
        // on the agent's key: nobody hears them.
        let listener = planner_session(&operator).await.unwrap();
        let heard = listener
            .declare_subscriber("gearcam/v1/jobs/FORGED-1/events/*")
            .await
            .unwrap();
        let forger = planner_session(&planner).await.unwrap();
        let forged = gearcam_proto::JobEvent {
            job_id: JobId::new("FORGED-1").unwrap(),
            stage: gearcam_proto::Stage::Agent,
            at_ms: 1,
            event: gearcam_proto::EventKind::Failed { errors: vec![] },
        };
        let job = JobId::new("FORGED-1").unwrap();
        for reporter in ["agent-H01", "station", "template"] {
            forger
                .put(keys::job_event(&job, reporter), encode(&forged).unwrap())
                .await
                .unwrap();
        }
        let got = tokio::time::timeout(Duration::from_secs(2), heard.recv_async()).await;
        assert!(got.is_err(), "a planner's forged event was delivered");
        listener.close().await.unwrap();
        // Even with the template service's credentials,
        // the agent stores no program of a job the station did not journal,
        // and none that fails its own path check (the hob run backwards).
        let file = dir.join("H01/programs/_N_SEC_0101_MPF");
        let stored = std::fs::read_to_string(&file).unwrap();
        let template = planner_session(&secure.cfg("template")).await.unwrap();
        let program = |job: &JobId, text: String| NcProgram {
            job_id: job.clone(),
            machine: MachineId::new("H01").unwrap(),
            name: "SEC_0101".into(),
            revision: 2,
            dialect: Dialect::Sinumerik840d,
            sha256: hex::encode(Sha256::digest(text.as_bytes())),
            text,
            template: TemplateRef {
                id: "forged".into(),
                version: 1,
            },
            part_number: "SEC-0101".into(),
            cases: vec![],
            model_version: "-".into(),
            generator: "-".into(),
            path_check: Default::default(),
            form: None,
            simulation: None,
        };
        let reversed = stored.replacen(" M3 ", " M4 ", 1);
        assert_ne!(reversed, stored);
        for (job, text, code) in [
            (
                JobId::new("NOT-JOURNALED-1").unwrap(),
                stored.clone(),
                "JOB_NOT_JOURNALED",
            ),
            (h01_job.clone(), reversed, "PATH_CHECK_FAILED"),
        ] {
            let replies = template
                .get(keys::machine_program(&MachineId::new("H01").unwrap(), &job))
                .payload(encode(&program(&job, text)).unwrap())
                .timeout(Duration::from_secs(10))
                .await
                .unwrap();
            let reply = replies.recv_async().await.expect("the agent answers");
            match decode::<DeliveryReply>(&reply.result().unwrap().payload().to_bytes()).unwrap() {
                DeliveryReply::Refused { error } => assert_eq!(error.code, code, "{error:?}"),
                other => panic!("{job}: stored what it must not: {other:?}"),
            }
        }
        assert_eq!(std::fs::read_to_string(&file).unwrap(), stored);
        template.close().await.unwrap();
        // The agent's one question before it stores a group: the station
        // answers the jobs journaled for the agent's machine only, and
        // refuses a question larger than a group by name.
        let agent = planner_session(&secure.cfg("agent-H01")).await.unwrap();
        let not_journaled = JobId::new("NOT-JOURNALED-1").unwrap();
        let many: Vec<JobId> = (0..=JobIds::MAX)
            .map(|i| JobId::new(format!("J{i}")).unwrap())
            .collect();
        for (jobs, want) in [
            (
                vec![h01_job.clone(), not_journaled, h02_job.clone()],
                Ok(vec![h01_job.clone()]),
            ),
            (many, Err("TOO_MANY_JOBS")),
        ] {
            let replies = agent
                .get(keys::station_journaled(&MachineId::new("H01").unwrap()))
                .payload(encode(&JobIds { jobs }).unwrap())
                .timeout(Duration::from_secs(10))
                .await
                .unwrap();
            let reply = replies.recv_async().await.expect("the station answers");
            match decode::<StationReply>(&reply.result().unwrap().payload().to_bytes()).unwrap() {
                StationReply::Jobs { jobs } => assert_eq!(
                    Ok(jobs.into_iter().map(|s| s.job).collect::<Vec<_>>()),
                    want
                ),
                StationReply::Refused { errors } => {
                    assert_eq!(Err(errors[0].code.as_str()), want, "{errors:?}")
                }
                other => panic!("an unexpected answer: {other:?}"),
            }
        }
        agent.close().await.unwrap();
        // A planner declares an agent's liveliness token: nobody sees it.
        let _fake = forger
            .liveliness()
            .declare_token("gearcam/v1/alive/agent/H09")
            .await
            .unwrap();
        tokio::time::sleep(Duration::from_millis(500)).await;
        let watcher = planner_session(&operator).await.unwrap();
        let replies = watcher
            .liveliness()
            .get("gearcam/v1/alive/agent/H09")
            .timeout(Duration::from_secs(2))
            .await
            .unwrap();
        assert!(
            replies.recv_async().await.is_err(),
            "a planner's token for agent H09 is visible"
        );
        // The real ones are.
        let replies = watcher
            .liveliness()
            .get("gearcam/v1/alive/agent/H02")
            .timeout(Duration::from_secs(2))
            .await
            .unwrap();
        assert!(
            replies.recv_async().await.is_ok(),
            "agent H02's token is not visible"
        );
    });
}

/// Runs `gearcam ARGS --config CONFIG --json` as the operating-system user
/// `mallory`, whose name must never be what gearcam records on an
/// authenticated connection.
fn as_mallory(config: &Path, args: &[&str]) -> (Option<i32>, serde_json::Value) {
    gearcam_testkit::secure::gearcam_json(
        config,
        args,
        &[("USER", "mallory"), ("LOGNAME", "mallory")],
    )
}

/// Authorship is the login the router checked, on every change: the
/// submitter of a job, who cancels one, who rolls a program back (and the
/// knowledge base's changes above); not the operating-system user, not a
/// name in the payload, and `--by` naming someone else is refused.
#[test]
fn every_change_is_recorded_as_the_login() {
    let secure = Secure::start();
    let dir = secure.dir();
    let (planner, operator) = (secure.cfg("planner"), secure.cfg("operator"));
    let spur = dir.join("spur.toml");
    std::fs::write(&spur, JOB).unwrap();
    let spur = spur.display().to_string();
    // Submitted by the planner, as journaled.
    let (code, v) = as_mallory(&planner, &["submit", &spur, "--wait", "--timeout", "60"]);
    assert_eq!(code, Some(0), "{v}\n{}", secure.logs());
    let journal = rusqlite::Connection::open(dir.join("station.db")).unwrap();
    let request: Vec<u8> = journal
        .query_row(
            "SELECT request FROM jobs WHERE job = ?1",
            [v["job"].as_str().unwrap()],
            |r| r.get(0),
        )
        .unwrap();
    let request: gearcam_proto::JobRequest = decode(&request).unwrap();
    assert_eq!(request.submitted_by, "planner");
    // A client of its own that writes another name into the request is
    // journaled as its login all the same.
    let mut forged = request.clone();
    forged.job_id = gearcam_proto::JobId::new("SEC-FORGED-1").unwrap();
    forged.submitted_by = "supervisor Wu".into();
    // A part of its own, so that its program does not join SEC_0001's.
    forged.spec.job.part_number = "SEC-FORGED".into();
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let session = planner_session(&planner).await.unwrap();
        let replies = session
            .get(keys::station_submit("planner"))
            .payload(encode(&forged).unwrap())
            .timeout(Duration::from_secs(10))
            .await
            .unwrap();
        let reply = replies.recv_async().await.expect("the station answers");
        let reply: gearcam_proto::StationReply =
            decode(&reply.result().expect("a reply").payload().to_bytes()).unwrap();
        assert!(
            matches!(reply, gearcam_proto::StationReply::Accepted { .. }),
            "{reply:?}"
        );
        // Under the supervisor's name, a planner's submit and cancel do not
        // even reach the station.
        let job = gearcam_proto::JobId::new("SEC-FORGED-1").unwrap();
        for key in [
            keys::station_submit("supervisor"),
            keys::station_cancel("supervisor", &job),
        ] {
            let replies = session
                .get(&key)
                .payload(encode(&forged).unwrap())
                .timeout(Duration::from_secs(3))
                .await
                .unwrap();
            assert!(
                replies.recv_async().await.is_err(),
                "{key} reached the station"
            );
        }
        session.close().await.unwrap();
    });
    let by: Vec<u8> = journal
        .query_row(
            "SELECT request FROM jobs WHERE job = 'SEC-FORGED-1'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    let by: gearcam_proto::JobRequest = decode(&by).unwrap();
    assert_eq!(
        by.submitted_by, "planner",
        "the payload's name was journaled"
    );
    // Rolled back by the operator, as the store's history says.
    let (code, v) = as_mallory(
        &operator,
        &["program", "rollback", "--machine", "H01", "SEC_0001", "1"],
    );
    assert_eq!(code, Some(0), "{v}");
    let (code, v) = as_mallory(
        &operator,
        &["program", "history", "--machine", "H01", "SEC_0001"],
    );
    assert_eq!(code, Some(0), "{v}");
    let versions = v["versions"].as_array().expect("the versions");
    let newest = versions
        .iter()
        .max_by_key(|r| r["seq"].as_u64())
        .expect("a version");
    assert_eq!(
        (newest["state"].as_str(), newest["by"].as_str()),
        (Some("rollback"), Some("operator")),
        "{v}"
    );
    // Cancelled by the planner: a job for M01, whose agent is not running,
    // waits until it is cancelled.
    let mill = dir.join("mill.toml");
    std::fs::write(
        &mill,
        gearcam_testkit::examples::example("face_annulus_fanuc.toml"),
    )
    .unwrap();
    let (code, v) = as_mallory(&planner, &["submit", &mill.display().to_string()]);
    assert_eq!(code, Some(0), "{v}");
    let job = v["job"].as_str().unwrap().to_string();
    let (code, v) = as_mallory(&planner, &["cancel", &job, "--by", "mallory"]);
    assert_eq!(code, Some(64), "--by someone else on a login: {v}");
    let (code, v) = as_mallory(&planner, &["cancel", &job]);
    assert_eq!(code, Some(0), "the cancelled job's status: {v}");
    assert_eq!(v["state"], "cancelled", "{v}");
    assert!(v["errors"][0]["got"] == "cancelled by planner", "{v}");
}
