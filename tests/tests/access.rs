//! Transport security and access control through a router configured from
//! `deploy/secure/` (TLS, a user and password per service, ACL default deny):
//! the pipeline works for the services, and a planner cannot deliver a program
//! or forge a stage's message, nor change a machine's current program (a
//! supervisor can); a wrong password cannot even connect.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

use gearcam_proto::plan::{KbOp, KbRecord, KbReply, KbRequest, KbValue};
use gearcam_proto::{
    decode, encode, keys, Dialect, JobId, MachineId, NcProgram, StoreReply, StoreRequest,
    TemplateRef,
};
use gearcam_testkit::{bin, Proc};
use sha2::{Digest, Sha256};

fn deploy() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../deploy/secure")
}

/// Copies a deploy config into `dir` with its paths and port made local.
fn local_config(dir: &Path, name: &str, port: u16) -> PathBuf {
    let text = std::fs::read_to_string(deploy().join(name)).unwrap();
    let text = text
        .replace("/etc/gearcam/", &format!("{}/", dir.display()))
        .replace("tls/0.0.0.0:7447", &format!("tls/127.0.0.1:{port}"))
        .replace("tls/localhost:7447", &format!("tls/localhost:{port}"));
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

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
    let job = dir.join(format!("{part}.toml"));
    std::fs::write(&job, JOB.replace("SEC-0001", part)).unwrap();
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
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let made = Command::new("bash")
        .arg(deploy().join("make-certs.sh"))
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        made.status.success(),
        "make-certs.sh: {}",
        String::from_utf8_lossy(&made.stderr)
    );
    std::fs::copy(deploy().join("users.txt"), dir.join("users.txt")).unwrap();
    // The router listens on a port the operating system chooses; the
    // services' configurations get the port it printed.
    let router = local_config(dir, "router.json5", 0);
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let router = Proc::start(
        dir,
        "router",
        "gearcam",
        &s(&["router", "--config", &router.display().to_string()]),
    );
    let port = router.listening_port(Duration::from_secs(20));
    let cfg = |name: &str| {
        local_config(dir, &format!("{name}.json5"), port)
            .display()
            .to_string()
    };
    let mut procs = vec![router];
    let (journal, db) = (
        dir.join("station.db").display().to_string(),
        dir.join("kb.db").display().to_string(),
    );
    let (programs, index) = (
        dir.join("H01/programs"),
        dir.join("H01/index.db").display().to_string(),
    );
    procs.push(Proc::start(
        dir,
        "station",
        "gearcam",
        &s(&[
            "station",
            "--config",
            &cfg("station"),
            "--journal",
            &journal,
        ]),
    ));
    procs.push(Proc::start(
        dir,
        "knowledge",
        "gearcam-knowledge",
        &s(&["--config", &cfg("knowledge"), "--db", &db]),
    ));
    procs.push(Proc::start(
        dir,
        "model",
        "gearcam-model",
        &s(&["--config", &cfg("model")]),
    ));
    procs.push(Proc::start(
        dir,
        "template",
        "gearcam-template",
        &s(&[
            "--config",
            &cfg("template"),
            "--library",
            &dir.join("templates.db").display().to_string(),
        ]),
    ));
    procs.push(Proc::start(
        dir,
        "agent",
        "gearcam-agent",
        &s(&[
            "--config",
            &cfg("agent-H01"),
            "--machine",
            "H01",
            "--program-dir",
            &programs.display().to_string(),
            "--index",
            &index,
        ]),
    ));
    let log_files: Vec<(String, PathBuf)> = procs
        .iter()
        .map(|p| (p.name.clone(), p.log.clone()))
        .collect();
    let logs = || {
        log_files
            .iter()
            .map(|(name, log)| {
                format!(
                    "--- {name} ---\n{}",
                    std::fs::read_to_string(log).unwrap_or_default()
                )
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let planner = PathBuf::from(cfg("planner"));
    let planner_cfg = planner.clone();

    // The whole pipeline works through TLS, passwords and the ACL.
    let v = submit(dir, &planner, "SEC-0001");
    assert_eq!(v["state"], "delivered", "{v}\n{}", logs());

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
            .declare_subscriber("gearcam/v1/jobs/EVIL-2/events")
            .await
            .unwrap();
        session
            .put("gearcam/v1/jobs/EVIL-2/plan", vec![0x80])
            .await
            .unwrap();
        let heard = tokio::time::timeout(Duration::from_secs(3), events.recv_async()).await;
        assert!(heard.is_err(), "a forged plan reached the model service");
        // A planner may not change a machine's current program; a supervisor may.
        let h01 = MachineId::new("H01").unwrap();
        let change = keys::store_change(&h01, "SEC_0001");
        let rollback = encode(&StoreRequest::Rollback { seq: 1 }).unwrap();
        let replies = session
            .get(&change)
            .payload(rollback.clone())
            .timeout(Duration::from_secs(3))
            .await
            .unwrap();
        assert!(
            replies.recv_async().await.is_err(),
            "the agent must not see a planner's rollback"
        );
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
            StoreReply::Changed { receipt } => assert_eq!(receipt.name, "SEC_0001"),
            other => panic!("a supervisor's rollback: {other:?}"),
        }
        // Issue 13 point 10: a planner cannot write the knowledge base.
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
            .get(keys::kb_change("machines", Some("H01")))
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
        // An administrator (the supervisor) can; the change is recorded.
        let mut set = KbRecord::new();
        set.insert("coating".into(), KbValue::Text("TiAlN".into()));
        let edit = KbRequest {
            op: KbOp::Edit,
            record: None,
            set,
            by: "supervisor Wu".into(),
        };
        let replies = supervisor
            .get(keys::kb_change("hobs", Some("HOB-M3-80")))
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
    assert_eq!((by.as_str(), op.as_str()), ("supervisor Wu", "edit"));
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
    for p in &mut procs {
        assert!(p.running(), "{} died\n{}", p.name, logs());
    }
}
