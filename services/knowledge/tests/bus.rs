//! The knowledge service on a real Zenoh session over TCP loopback: library
//! queries on `gearcam/v1/kb/**`, the change log and a confirmation, and a
//! job without a process section planned from the cases.

use std::time::Duration;

use gearcam_bus::{Bus, BusConfig, CancellationToken};
use gearcam_knowledge::service::{self, Config};
use gearcam_proto::plan::{
    ConfirmReply, ConfirmRequest, KbLogReply, KbLogRequest, KbOp, KbRecord, KbReply, KbRequest,
    KbValue,
};
use gearcam_proto::{decode, encode, keys, JobRequest, JobSpec, Message, ProcessPlan, Source};
use tokio::time::timeout;

const T: Duration = Duration::from_secs(20);

async fn query(bus: &Bus, key: &str, req: Option<&KbRequest>) -> KbReply {
    let mut get = bus.session().get(key).timeout(Duration::from_secs(5));
    if let Some(r) = req {
        get = get.payload(encode(r).unwrap());
    }
    let replies = timeout(T, get).await.unwrap().unwrap();
    let reply = timeout(T, replies.recv_async()).await.unwrap().unwrap();
    let sample = reply.result().expect("an ok reply");
    decode(&sample.payload().to_bytes()).unwrap()
}

/// A query of any message on `key`, its reply decoded.
async fn ask<Q: Message, R: Message>(bus: &Bus, key: &str, req: Option<&Q>) -> R {
    let mut get = bus.session().get(key).timeout(Duration::from_secs(5));
    if let Some(r) = req {
        get = get.payload(encode(r).unwrap());
    }
    let replies = timeout(T, get).await.unwrap().unwrap();
    let reply = timeout(T, replies.recv_async()).await.unwrap().unwrap();
    let sample = reply.result().expect("an ok reply");
    decode(&sample.payload().to_bytes()).unwrap()
}

fn text(s: &str) -> KbValue {
    KbValue::Text(s.into())
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn libraries_are_browsed_and_edited_over_zenoh_and_a_job_gets_a_proposal() {
    let dir = tempfile::tempdir().unwrap();
    // The server listens on a port the operating system chooses, read back.
    let server = timeout(T, Bus::open(&BusConfig::loopback(&["tcp/127.0.0.1:0"])))
        .await
        .unwrap()
        .unwrap();
    let port = gearcam_testkit::process::listening_port(std::process::id())
        .expect("the server listens on a TCP port");
    let endpoint = format!("tcp/127.0.0.1:{port}");
    let shutdown = CancellationToken::new();
    let task = tokio::spawn(service::run(
        server.clone(),
        Config {
            db_path: dir.path().join("knowledge.db"),
        },
        shutdown.clone(),
    ));
    let client = timeout(T, Bus::open(&BusConfig::client(&[endpoint])))
        .await
        .unwrap()
        .unwrap();
    timeout(T, client.wait_alive(&[service::SERVICE.to_string()], T))
        .await
        .unwrap()
        .unwrap();

    // List: the seeded hobs.
    let r = query(&client, &keys::kb_library("hobs"), None).await;
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    assert_eq!(r.library, "hobs");
    let ids: Vec<&KbValue> = r.records.iter().map(|r| &r["id"]).collect();
    assert!(ids.contains(&&text("HOB-M3-80L")), "{ids:?}");

    // Add a hob, then read it back by id.
    let mut hob = KbRecord::new();
    for (k, v) in [
        ("module_mm", KbValue::Float(2.5)),
        ("starts", KbValue::Int(1)),
        ("hand", text("right")),
        ("lead_angle_deg", KbValue::Float(2.2)),
        ("od_mm", KbValue::Float(70.0)),
        ("length_mm", KbValue::Float(80.0)),
        ("usable_length_mm", KbValue::Float(70.0)),
        ("accuracy_class", text("AA")),
        ("coating", text("TiAlN")),
        ("remaining_life_parts", KbValue::Int(300)),
    ] {
        hob.insert(k.into(), v);
    }
    let add = KbRequest {
        op: KbOp::Add,
        record: Some(hob),
        set: KbRecord::new(),
        by: "admin Zhang".into(),
    };
    // A change on a read key is refused: the access control cannot tell it
    // from a read there.
    let r = query(&client, &keys::kb_record("hobs", "HOB-M25-70"), Some(&add)).await;
    assert_eq!(r.errors[0].code, "KB_WRONG_KEY", "{:?}", r.errors);
    let r = query(
        &client,
        &keys::kb_change("tester", "hobs", Some("HOB-M25-70")),
        Some(&add),
    )
    .await;
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    assert_eq!(r.records[0]["material"], text("HSS"), "default filled in");
    let r = query(&client, &keys::kb_record("hobs", "HOB-M25-70"), None).await;
    assert_eq!(r.records[0]["coating"], text("TiAlN"));

    // A bad edit names the field, what was expected and what was given.
    let mut set = KbRecord::new();
    set.insert("accuracy_class".into(), text("Z"));
    set.insert("od_mm".into(), KbValue::Float(-1.0));
    let edit = KbRequest {
        op: KbOp::Edit,
        record: None,
        set,
        by: "admin Zhang".into(),
    };
    let r = query(
        &client,
        &keys::kb_change("tester", "hobs", Some("HOB-M25-70")),
        Some(&edit),
    )
    .await;
    let fields: Vec<(&str, &str, &str)> = r
        .errors
        .iter()
        .map(|e| (e.field.as_str(), e.expected.as_str(), e.got.as_str()))
        .collect();
    assert_eq!(
        fields,
        [
            ("od_mm", "a number > 0", "-1.0"),
            ("accuracy_class", "one of AA, A, B, C", "\"Z\"")
        ]
    );
    // A machine limit edited by dotted path.
    let mut set = KbRecord::new();
    set.insert("limits.max_hob_rpm".into(), KbValue::Float(1200.0));
    let edit = KbRequest {
        op: KbOp::Edit,
        record: None,
        set,
        by: "admin Zhang".into(),
    };
    let r = query(
        &client,
        &keys::kb_change("tester", "machines", Some("H01")),
        Some(&edit),
    )
    .await;
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    let KbValue::Map(limits) = &r.records[0]["limits"] else {
        panic!("limits is a map")
    };
    assert_eq!(limits["max_hob_rpm"], KbValue::Float(1200.0));
    // Unknown library and record.
    let r = query(&client, &keys::kb_library("gears"), None).await;
    assert_eq!(r.errors[0].code, "UNKNOWN_LIBRARY");
    let r = query(&client, &keys::kb_record("cases", "NOPE"), None).await;
    assert_eq!(r.errors[0].code, "NOT_FOUND");

    // The change log, on the key without a library too: the machine's
    // edit above is the newest change, the key's user's.
    let log: KbLogReply = ask(&client, &keys::kb_log(None, None), None::<&KbLogRequest>).await;
    assert!(log.errors.is_empty(), "{:?}", log.errors);
    let c = &log.changes[0];
    assert_eq!(
        (c.by.as_str(), c.library.as_str(), c.record_id.as_str()),
        ("tester", "machines", "H01")
    );
    let one = KbLogRequest { limit: 1 };
    let log: KbLogReply = ask(&client, &keys::kb_log(Some("hobs"), None), Some(&one)).await;
    let ops: Vec<(&str, &str)> = log
        .changes
        .iter()
        .map(|c| (c.op.as_str(), c.record_id.as_str()))
        .collect();
    assert_eq!(ops, [("add", "HOB-M25-70")]);
    // A confirmation of a job this knowledge base never planned.
    let confirm = ConfirmRequest {
        quantity: None,
        cutting_speed_m_min: None,
        feed_mm_per_rev: None,
        cuts: None,
        outcome: "ok".into(),
        quality_achieved: None,
        notes: String::new(),
        confidence: 0.8,
        undelivered: false,
    };
    let job = gearcam_proto::JobId::new("NEVER-PLANNED").unwrap();
    let r: ConfirmReply = ask(&client, &keys::kb_confirm("tester", &job), Some(&confirm)).await;
    assert_eq!(r.errors[0].code, "UNKNOWN_JOB", "{:?}", r.errors);

    // A job with no process section: the plan carries cases, similarities and confidence.
    let spec: JobSpec = serde_json::from_value(serde_json::json!({
        "job": {"machine": "H01", "part_number": "SP-1001", "quantity": 20},
        "gear": {"module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0, "blank_od_mm": 81.0,
                 "material": "20CrMnTi", "quality_grade": 7, "fixture_height_mm": 100.0},
    }))
    .unwrap();
    let req = JobRequest {
        job_id: gearcam_proto::JobId::new("KB-BUS-1").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "test".into(),
        spec,
    };
    let plans = client
        .session()
        .declare_subscriber(keys::job_plan(&req.job_id))
        .await
        .unwrap();
    client
        .put(&keys::job_request(&req.job_id), &req)
        .await
        .unwrap();
    let sample = timeout(T, plans.recv_async()).await.unwrap().unwrap();
    let plan: ProcessPlan = decode(&sample.payload().to_bytes()).unwrap();
    assert_eq!(plan.cases[0].id, "SEED-CASE-M3");
    assert!(plan.cases[0].similarity > 0.5);
    assert!(plan.confidence > 0.0 && plan.confidence < 1.0);
    assert_eq!(plan.values["cutting_speed_m_min"].source, Source::Case);
    assert_eq!(plan.hob.id, "HOB-M3-80");
    // The job is recorded for the learning loop.
    let r = query(&client, &keys::kb_record("jobs", "KB-BUS-1"), None).await;
    assert_eq!(r.records[0]["state"], text("planned"));

    shutdown.cancel();
    timeout(T, task).await.unwrap().unwrap().unwrap();
    client.close().await;
    server.close().await;
}
