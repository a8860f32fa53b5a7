//! The program store under faults, through real processes on loopback
//! (router, station, services, agent).
// Test code: clocks for the waits.
#![allow(clippy::disallowed_methods)]

use std::time::{Duration, Instant};

use gearcam_proto::{
    decode, encode, keys, DeliveryReply, Dialect, JobId, MachineId, NcProgram, TemplateRef,
};
use gearcam_testkit::{gearcam, Cluster};
use sha2::{Digest, Sha256};

fn sha(bytes: &[u8]) -> String {
    hex::encode(Sha256::digest(bytes))
}

/// The spur example with `quantity` (a new program text for the same part).
fn spur(c: &Cluster, quantity: u32) -> std::path::PathBuf {
    let text = gearcam_testkit::examples::example("spur_840d.toml")
        .replace("quantity = 20", &format!("quantity = {quantity}"));
    c.job_file(&format!("spur-{quantity}.toml"), &text)
}

/// The current version of SP_1001 at H01, once the agent answers (30 s at most).
fn current_version(c: &Cluster) -> serde_json::Value {
    let deadline = Instant::now() + Duration::from_secs(30);
    while gearcam(&[
        "program",
        "history",
        "--machine",
        "H01",
        "--connect",
        &c.endpoint,
    ])
    .0 != Some(0)
    {
        assert!(
            Instant::now() < deadline,
            "the agent does not answer\n{}",
            c.logs()
        );
        std::thread::sleep(Duration::from_millis(200));
    }
    let (code, out, err) = gearcam(&[
        "program",
        "history",
        "SP_1001",
        "--machine",
        "H01",
        "--connect",
        &c.endpoint,
        "--json",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let h: serde_json::Value = serde_json::from_str(&out).unwrap();
    h["versions"]
        .as_array()
        .unwrap()
        .iter()
        .find(|v| v["current"] == true)
        .unwrap()
        .clone()
}

/// The agent killed between the rename and the index commit must not leave
/// the machine holding a program the history does not show as current, nor
/// the next program for the name taken for an operator's edit.
#[test]
fn a_crash_between_rename_and_commit_is_finished_at_restart() {
    let mut c = Cluster::start();
    let (_, v) = c.submit_wait(&spur(&c, 20));
    assert_eq!(v["state"], "delivered", "{v}");

    // The agent that dies right after renaming the next program into place.
    c.proc("agent").kill();
    c.start_agent_with("agent-crashing", "H01", &["--fault-crash-after-rename"]);
    let second = c.submit(&spur(&c, 21));
    let second = second["job"].as_str().unwrap().to_string();
    let deadline = Instant::now() + Duration::from_secs(30);
    while c.proc("agent-crashing").running() {
        assert!(
            Instant::now() < deadline,
            "the fault was not hit\n{}",
            c.logs()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    // No re-drive may tidy up behind the store's back: the station is down
    // while the agent starts again.
    c.proc("station").kill();
    c.start_agent_with("agent-again", "H01", &[]);
    let file = std::fs::read(c.program_dir().join("_N_SP_1001_MPF")).unwrap();
    let current = current_version(&c);
    assert_eq!(
        current["sha256"],
        sha(&file),
        "the machine holds a program the history does not show as current: {current}"
    );
    assert_eq!(current["job"], second.as_str());

    // The station comes back: the job is delivered, and the next program
    // for the name is stored, not refused as an edit.
    c.proc("station").restart();
    c.wait_status(&second, |v| v["state"] == "delivered");
    let (_, v) = c.submit_wait(&spur(&c, 22));
    assert_eq!(v["state"], "delivered", "{v}");
}

/// A store that cannot write (disk full) does not fail the accepted job for
/// good: the job waits, says why, and is delivered once the store can write
/// again.
#[test]
fn a_store_that_cannot_write_makes_the_job_wait_not_fail() {
    let mut c = Cluster::start();
    // A directory where the agent's temporary file goes: every write fails
    // (EISDIR, even for root), as on a full disk.
    let pid = c.proc("agent").pid();
    let blocker = c.program_dir().join(format!("._N_SP_1001_MPF.tmp-{pid}"));
    std::fs::create_dir_all(&blocker).unwrap();
    let job = c.submit(&spur(&c, 20));
    let id = job["job"].as_str().unwrap().to_string();
    let v = c.wait_status(&id, |v| {
        v["waiting_for"]
            .as_str()
            .is_some_and(|w| w.contains("STORE_IO_ERROR"))
    });
    assert_eq!(v["state"], "waiting", "{v}");
    // Space freed: the station's re-drive delivers it.
    std::fs::remove_dir(&blocker).unwrap();
    let v = c.wait_status(&id, |v| v["state"] == "delivered" || v["state"] == "failed");
    assert_eq!(v["state"], "delivered", "{v}");
    let names: Vec<String> = std::fs::read_dir(c.program_dir())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["_N_SP_1001_MPF"], "no temporary file is left");
}

/// A repeated delivery must not answer the original receipt without looking
/// at the file: the file may have been deleted at the machine.
#[test]
fn a_repeated_delivery_checks_the_file() {
    let c = Cluster::start();
    let (_, v) = c.submit_wait(&spur(&c, 20));
    assert_eq!(v["state"], "delivered", "{v}");
    let job = JobId::new(v["job"].as_str().unwrap()).unwrap();
    // The program as the template service sent it: its stored text.
    let (code, out, err) = gearcam(&[
        "program",
        "show",
        "SP_1001",
        "1",
        "--machine",
        "H01",
        "--connect",
        &c.endpoint,
        "--json",
    ]);
    assert_eq!(code, Some(0), "{err}");
    let shown: serde_json::Value = serde_json::from_str(&out).unwrap();
    let text = shown["text"].as_str().unwrap().to_string();
    let program = NcProgram {
        job_id: job.clone(),
        machine: MachineId::new("H01").unwrap(),
        name: "SP_1001".into(),
        revision: 1,
        dialect: Dialect::Sinumerik840d,
        sha256: sha(text.as_bytes()),
        text,
        template: TemplateRef {
            id: "cylindrical_840d".into(),
            version: 7,
        },
        part_number: "SP-1001".into(),
        cases: vec![],
        model_version: "-".into(),
        generator: "-".into(),
        path_check: Default::default(),
        form: None,
        simulation: None,
    };
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let session = zenoh::open(gearcam_testkit::client_config(&c.endpoint))
            .await
            .unwrap();
        let ask = |key: String, payload: Option<Vec<u8>>| {
            let session = session.clone();
            async move {
                let replies = session
                    .get(&key)
                    .payload(payload.unwrap_or_default())
                    .timeout(Duration::from_secs(10))
                    .await
                    .unwrap();
                let reply = replies.recv_async().await.expect("the agent answers");
                decode::<DeliveryReply>(&reply.result().expect("a reply").payload().to_bytes())
                    .unwrap()
            }
        };
        let machine = program.machine.clone();
        let deliver = || {
            ask(
                keys::machine_program(&machine, &job),
                Some(encode(&program).unwrap()),
            )
        };
        match deliver().await {
            DeliveryReply::Stored { receipt } => {
                assert!(receipt.duplicate, "a repeat of a held program")
            }
            other => panic!("a repeat of a held program: {other:?}"),
        }
        std::fs::remove_file(c.program_dir().join("_N_SP_1001_MPF")).unwrap();
        match deliver().await {
            DeliveryReply::Refused { error } => {
                assert_eq!(error.code, "PROGRAM_CHANGED_AT_MACHINE")
            }
            other => panic!("answered {other:?} for a program the machine no longer holds"),
        }
        let lost = ask(keys::store_job(&machine, &job), None).await;
        assert_eq!(
            lost,
            DeliveryReply::NotStored,
            "the lost-receipt query says what the machine holds"
        );
    });
}

/// Truncates an SQLite file to 0 bytes and removes its WAL, as a fault or a
/// careless hand would leave it.
fn empty(db: &std::path::Path) {
    std::fs::write(db, b"").unwrap();
    for suffix in ["-wal", "-shm"] {
        let mut side = db.as_os_str().to_owned();
        side.push(suffix);
        let _ = std::fs::remove_file(side);
    }
}

/// Waits for `label` to exit; its log.
fn exits(c: &mut Cluster, label: &str) -> String {
    let deadline = Instant::now() + Duration::from_secs(30);
    while c.proc(label).running() {
        assert!(
            Instant::now() < deadline,
            "{label} kept running\n{}",
            c.logs()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    std::fs::read_to_string(&c.proc(label).log).unwrap()
}

/// An emptied index or journal must not be taken as a fresh one, which
/// would make the agent forget its whole history, the station its
/// unfinished jobs, silently.
#[test]
fn an_emptied_index_or_journal_is_refused_with_a_recovery() {
    let mut c = Cluster::start();
    let (_, v) = c.submit_wait(&spur(&c, 20));
    assert_eq!(v["state"], "delivered", "{v}");
    let job = v["job"].as_str().unwrap().to_string();

    // The agent's index.
    c.proc("agent").kill();
    empty(&c.index_db());
    c.start_agent_with("agent-on-empty", "H01", &[]);
    let log = exits(&mut c, "agent-on-empty");
    assert!(
        log.contains("is empty") && log.contains("--rebuild-index"),
        "{log}"
    );
    // The recovery the message names: rebuild from the files' headers.
    let out = std::process::Command::new(gearcam_testkit::bin("gearcam-agent"))
        .args(["--machine", "H01", "--program-dir"])
        .arg(c.program_dir())
        .arg("--index")
        .arg(c.index_db())
        .arg("--rebuild-index")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        String::from_utf8_lossy(&out.stdout).contains("1 program(s)"),
        "{out:?}"
    );
    c.start_agent_with("agent-rebuilt", "H01", &[]);
    let current = current_version(&c);
    assert_eq!(
        (current["job"].as_str(), current["state"].as_str()),
        (Some(job.as_str()), Some("rebuilt"))
    );
    assert_eq!(current["part_number"], "SP-1001");

    // The station's journal.
    c.proc("station").kill();
    empty(&c.dir.path().join("station.db"));
    c.proc("station").restart();
    let log = exits(&mut c, "station");
    assert!(
        log.contains("job journal") && log.contains("is empty"),
        "{log}"
    );
}

/// A second agent for one machine (a misconfiguration) must not serve too:
/// deliveries would reach both, receipts split, jobs fail though stored once.
#[test]
fn a_second_agent_for_a_machine_refuses_to_serve() {
    let mut c = Cluster::start();
    let (_, v) = c.submit_wait(&spur(&c, 20));
    assert_eq!(v["state"], "delivered", "{v}");
    c.start_agent_with("agent-second", "H01", &[]);
    let log = exits(&mut c, "agent-second");
    assert!(
        log.contains("another agent already serves machine H01"),
        "{log}"
    );
    let first = std::fs::read_to_string(&c.proc("agent").log).unwrap();
    assert!(
        first.contains("a second agent for machine H01 started"),
        "the serving agent reports it: {first}"
    );
    // The first one still serves, alone.
    for q in 21..24 {
        let (_, v) = c.submit_wait(&spur(&c, q));
        assert_eq!(v["state"], "delivered", "{v}");
    }
    let rows: i64 = rusqlite::Connection::open(c.index_db())
        .unwrap()
        .query_row(
            "SELECT COUNT(*) FROM programs WHERE state = 'stored'",
            [],
            |r| r.get(0),
        )
        .unwrap();
    assert_eq!(rows, 4);
}

/// An operator's edit saved while a delivery is being written (between the
/// checks and the rename) is not overwritten. The agent's write is held
/// open for 3 s by fault injection; the edit falls into it.
#[test]
fn an_edit_during_a_delivery_is_kept() {
    let mut c = Cluster::start();
    let (_, v) = c.submit_wait(&spur(&c, 20));
    assert_eq!(v["state"], "delivered", "{v}");
    c.proc("agent").kill();
    c.start_agent_with(
        "agent-slow",
        "H01",
        &["--fault-pause-before-rename-ms", "3000"],
    );
    let job = c.submit(&spur(&c, 21));
    let id = job["job"].as_str().unwrap().to_string();
    // The write is under way once its temporary file is there.
    let deadline = Instant::now() + Duration::from_secs(30);
    let writing = || {
        std::fs::read_dir(c.program_dir())
            .unwrap()
            .any(|e| e.unwrap().file_name().to_string_lossy().contains(".tmp-"))
    };
    while !writing() {
        assert!(Instant::now() < deadline, "no write started\n{}", c.logs());
        std::thread::sleep(Duration::from_millis(20));
    }
    let path = c.program_dir().join("_N_SP_1001_MPF");
    std::fs::write(&path, "; FEED LOWERED BY THE OPERATOR\n").unwrap();
    let v = c.wait_status(&id, |v| {
        v["waiting_for"]
            .as_str()
            .is_some_and(|w| w.contains("PROGRAM_CHANGED_AT_MACHINE"))
    });
    assert_eq!(v["state"], "waiting", "{v}");
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "; FEED LOWERED BY THE OPERATOR\n"
    );
}
