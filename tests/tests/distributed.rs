//! Distributed tests: a Zenoh router and every gearcam service as its own
//! process on loopback, jobs submitted with the real `gearcam submit --wait`.
// Test code: clocks for timeouts, the environment for switches.
#![allow(clippy::disallowed_methods)]

use std::time::Duration;

use approx::assert_abs_diff_eq;
use gearcam_proto::{decode, keys, DeliveryReply, EventKind, JobEvent, StationReply};
use gearcam_testkit::Cluster;
use sha2::{Digest, Sha256};

/// A spur job as a planner would write it, with every process value given so
/// the expected numbers below depend only on this file and docs/hobbing.md#4-the-cycle-positions-speeds-feeds.
const SPUR_JOB: &str = r#"
[job]
machine = "H01"
part_number = "TS-0001"
quantity = 5

[gear]
module_mm = 3.0
teeth = 25
pressure_angle_deg = 20.0
helix_angle_deg = 0.0
face_width_mm = 30.0
profile_shift = 0.0
addendum_coef = 1.0
clearance_coef = 0.25
blank_od_mm = 81.0
material = "20CrMnTi"
quality_grade = 7
fixture_height_mm = 100.0

[hob]
starts = 1
od_mm = 80.0
module_mm = 3.0
pressure_angle_deg = 20.0
lead_angle_deg = 2.3716
hand = "right"
length_mm = 100.0

[process]
cut_mode = "conventional"
cuts = 1
cutting_speed_m_min = 90.0
feed_mm_per_rev = 2.0
safety_mm = 2.0

[options]
coolant = true
outer_support = false
fixture_clamp = true
sync_cancel = true
chip_conveyor = false
mist_separator = false
"#;

/// docs/hobbing.md#4-the-cycle-positions-speeds-feeds for the job above, computed here independently of the model crate.
struct Expected {
    x_c: f64,
    z_c: f64,
    z_d: f64,
    feed_mm_min: f64,
}

fn expected_spur() -> Expected {
    let (mn, z, b, h_fix, da1, da0, z0, vc, fa, safety) = (
        3.0_f64, 25.0_f64, 30.0, 100.0, 81.0_f64, 80.0_f64, 1.0, 90.0, 2.0, 2.0,
    );
    let gamma0 = 2.3716_f64.to_radians();
    // Check 5's theoretical centre distance; the default depth makes L equal to it.
    let d = z * mn;
    let d0 = z0 * mn / gamma0.sin();
    let l = d0 / 2.0 + d / 2.0;
    let h = (da0 + da1) / 2.0 - l;
    // ΔH′: the lowest point of the hob's tip cylinder (radius r, 100 mm
    // long, tilted by |η| = γ0 for a spur gear) over the blank disc, by a
    // sweep around the hob: for each angle θ the point lies over the disc
    // for an interval of the hob-axial y, the lowest at its largest y.
    let (r_blank, r_hob, half) = (da1 / 2.0, da0 / 2.0, 50.0);
    let g = gamma0;
    let n = 2_000_000;
    let mut best = f64::MIN;
    for i in 0..n {
        let th = std::f64::consts::TAU * i as f64 / n as f64;
        let x = l + r_hob * th.cos();
        if x.abs() > r_blank {
            continue;
        }
        let w = (r_blank * r_blank - x * x).sqrt();
        let a = r_hob * th.sin() * g.sin();
        let y_hi = ((w - a) / g.cos()).min(half);
        if y_hi < ((-w - a) / g.cos()).max(-half) {
            continue;
        }
        best = best.max(y_hi * g.sin() - r_hob * th.sin() * g.cos());
    }
    assert!(h > 0.0 && best > 0.0);
    let nt = 1000.0 * vc / (std::f64::consts::PI * da0);
    Expected {
        x_c: l,
        z_c: h_fix + b + best + safety,
        z_d: h_fix - best - safety,
        feed_mm_min: fa * z0 * nt / z,
    }
}

/// The number after `word=` in an NC line.
fn word(line: &str, word: &str) -> Option<f64> {
    line.split_whitespace()
        .find_map(|t| t.strip_prefix(&format!("{word}=")))
        .and_then(|v| v.parse().ok())
}

/// Submits `text` as the job file `name` and waits: it must be delivered.
/// Returns what `gearcam submit --wait --json` printed.
fn delivered(cluster: &Cluster, name: &str, text: &str) -> serde_json::Value {
    let job = cluster.job_file(name, text);
    let (out, v) = cluster.submit_wait(&job);
    assert!(
        out.status.success(),
        "submit failed: {v}\n{}",
        cluster.logs()
    );
    assert_eq!(v["state"], "delivered", "{v}");
    v
}

#[test]
fn a_spur_job_is_delivered_through_every_service_process() {
    let mut cluster = Cluster::start();
    let v = delivered(&cluster, "spur.toml", SPUR_JOB);
    let receipt_hash = v["program"]["sha256"].as_str().expect("sha256").to_string();
    let job_id = v["job"].as_str().expect("job id").to_string();

    // The program file in the agent's directory, under the 840D naming.
    let path = cluster.program_dir().join("_N_TS_0001_MPF");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}\n{}", path.display(), cluster.logs()));
    assert_eq!(hex::encode(Sha256::digest(text.as_bytes())), receipt_hash);
    assert!(
        text.starts_with("%_N_TS_0001_MPF\n;$PATH=/_N_MPF_DIR\n"),
        "{text}"
    );

    // The index row.
    let conn = rusqlite::Connection::open(cluster.index_db()).unwrap();
    let (name, sha, job_col): (String, String, String) = conn
        .query_row("SELECT name, sha256, job FROM programs", [], |r| {
            Ok((r.get(0)?, r.get(1)?, r.get(2)?))
        })
        .unwrap();
    assert_eq!(
        (name.as_str(), sha.as_str(), job_col.as_str()),
        ("TS_0001", receipt_hash.as_str(), job_id.as_str())
    );

    // The numbers in the program against docs/hobbing.md#4-the-cycle-positions-speeds-feeds.
    let e = expected_spur();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with(';')).collect();
    let g1 = lines
        .iter()
        .position(|l| l.contains(" G1 "))
        .expect("a G1 feed block");
    let c_line = lines[..g1]
        .iter()
        .rev()
        .find(|l| l.contains("X="))
        .expect("infeed to C");
    // The approach: retract, rise to A, swivel, down to B's height, in to B.
    let b_line = lines[..g1]
        .iter()
        .rev()
        .find(|l| l.contains(" G0 ") && l.contains("Z="))
        .expect("rapid to B");
    assert_abs_diff_eq!(word(c_line, "X").unwrap(), e.x_c, epsilon = 1e-3);
    assert_abs_diff_eq!(word(b_line, "Z").unwrap(), e.z_c, epsilon = 1e-3);
    assert_abs_diff_eq!(word(lines[g1], "Z").unwrap(), e.z_d, epsilon = 1e-3);
    assert_abs_diff_eq!(word(lines[g1], "F").unwrap(), e.feed_mm_min, epsilon = 1e-3);
    assert!(
        text.contains("EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25)"),
        "{text}"
    );
    cluster.assert_all_running();
}

/// Every hobbing program runs on the virtual machine before it is
/// delivered: the spur job's drawing asking for class 2 (the run predicts a
/// coarser class) is delivered with the `PREDICTED_GRADE` warning, which
/// names the deviation that sets the class.
#[test]
fn a_hobbing_program_is_simulated_before_delivery_and_warns_of_its_grade() {
    let mut cluster = Cluster::start();
    let strict = SPUR_JOB.replace("quality_grade = 7", "quality_grade = 2");
    let v = delivered(&cluster, "strict.toml", &strict);
    let warnings = v["warnings"].as_array().expect("warnings");
    let grade = warnings
        .iter()
        .find(|w| w["code"] == "PREDICTED_GRADE")
        .unwrap_or_else(|| panic!("no PREDICTED_GRADE warning: {v}"));
    assert_eq!(grade["field"], "simulation.grade", "{v}");
    let message = grade["message"].as_str().unwrap_or_default();
    assert!(message.contains("class"), "{message}");
    cluster.assert_all_running();
}

#[test]
fn a_hob_with_the_wrong_base_pitch_is_refused_naming_the_check() {
    let mut cluster = Cluster::start();
    let bad = SPUR_JOB.replace(
        "module_mm = 3.0\npressure_angle_deg = 20.0\nlead_angle_deg",
        "module_mm = 2.5\npressure_angle_deg = 20.0\nlead_angle_deg",
    );
    assert_ne!(bad, SPUR_JOB);
    let job = cluster.job_file("bad.toml", &bad);
    let (out, v) = cluster.submit_wait(&job);
    assert_eq!(out.status.code(), Some(1), "{v}");
    assert_eq!(v["state"], "failed", "{v}");
    let errors = v["errors"].as_array().expect("errors");
    let e = errors
        .iter()
        .find(|e| e["code"] == "BASE_PITCH_MISMATCH")
        .unwrap_or_else(|| panic!("no BASE_PITCH_MISMATCH in {v}"));
    assert_eq!(e["stage"], "model");
    assert_eq!(e["field"], "hob.module_mm");
    assert_eq!(
        std::fs::read_dir(cluster.program_dir())
            .map(|d| d.count())
            .unwrap_or(0),
        0
    );
    cluster.assert_all_running();
}

#[test]
fn every_service_survives_malformed_messages_and_reports_them() {
    let mut cluster = Cluster::start();
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap();
    let reports = rt.block_on(async {
        let session = session_with_services(&cluster.endpoint).await;
        let events = session
            .declare_subscriber("gearcam/v1/jobs/*/events/*")
            .await
            .unwrap();
        let garbage: &[u8] = &[0xc1, 0xff, 0x00, 0x13, 0x37];
        // An envelope of a future schema version, to each stage as well.
        let future = future_version_envelope();
        let targets = [
            (
                "gearcam/v1/jobs/BAD-K/request",
                garbage.to_vec(),
                "knowledge",
                "MALFORMED_MESSAGE",
            ),
            (
                "gearcam/v1/jobs/BAD-M/plan",
                garbage.to_vec(),
                "model",
                "MALFORMED_MESSAGE",
            ),
            (
                "gearcam/v1/jobs/BAD-T/model",
                future.clone(),
                "template",
                "UNKNOWN_SCHEMA_VERSION",
            ),
            (
                "gearcam/v1/machines/H01/programs/BAD-A",
                future,
                "agent",
                "UNKNOWN_SCHEMA_VERSION",
            ),
        ];
        for (key, payload, stage, _) in &targets {
            if *stage == "agent" {
                // Delivery to an agent is a request: the refusal is also the reply.
                let replies = session
                    .get(*key)
                    .payload(payload.clone())
                    .timeout(Duration::from_secs(10))
                    .await
                    .unwrap();
                let reply = replies.recv_async().await.expect("the agent answers");
                let bytes = reply
                    .result()
                    .expect("an ok reply carrying the refusal")
                    .payload()
                    .to_bytes();
                match decode::<DeliveryReply>(&bytes).unwrap() {
                    DeliveryReply::Refused { error } => {
                        assert_eq!(error.code, "UNKNOWN_SCHEMA_VERSION")
                    }
                    other => panic!("expected a refusal, got {other:?}"),
                }
            } else {
                session.put(*key, payload.clone()).await.unwrap();
            }
        }
        let mut seen = Vec::new();
        while seen.len() < targets.len() {
            let sample = tokio::time::timeout(Duration::from_secs(30), events.recv_async())
                .await
                .expect("a typed error event for every malformed message")
                .unwrap();
            let ev: JobEvent =
                decode(&sample.payload().to_bytes()).expect("events are well formed");
            if let EventKind::Failed { errors } = ev.event {
                seen.push((
                    ev.job_id.to_string(),
                    ev.stage.as_str().to_string(),
                    errors[0].code.to_string(),
                ));
            }
        }
        session.close().await.unwrap();
        seen.sort();
        seen
    });
    assert_eq!(
        reports,
        vec![
            (
                "BAD-A".to_string(),
                "agent".to_string(),
                "UNKNOWN_SCHEMA_VERSION".to_string()
            ),
            (
                "BAD-K".into(),
                "knowledge".into(),
                "MALFORMED_MESSAGE".into()
            ),
            ("BAD-M".into(), "model".into(), "MALFORMED_MESSAGE".into()),
            (
                "BAD-T".into(),
                "template".into(),
                "UNKNOWN_SCHEMA_VERSION".into()
            ),
        ]
    );
    // Every service keeps serving: a good job still goes through.
    cluster.assert_all_running();
    let job = cluster.job_file("spur.toml", SPUR_JOB);
    let (out, v) = cluster.submit_wait(&job);
    assert!(out.status.success(), "{v}\n{}", cluster.logs());
    assert_eq!(v["state"], "delivered");
    assert_eq!(
        std::fs::read_dir(cluster.program_dir()).unwrap().count(),
        1,
        "nothing else stored"
    );
}

/// `{"schema": 99, "kind": ..., "body": {}}` as MessagePack, written by hand so
/// the test does not depend on our codec: fixmap(3), then the three pairs.
fn future_version_envelope() -> Vec<u8> {
    let mut v = vec![0x83];
    v.push(0xa6);
    v.extend_from_slice(b"schema");
    v.push(99); // positive fixint
    v.push(0xa4);
    v.extend_from_slice(b"kind");
    v.push(0xa3);
    v.extend_from_slice(b"any");
    v.push(0xa4);
    v.extend_from_slice(b"body");
    v.push(0x80); // empty map
    v
}

/// A station that re-drives a job while its first delivery is still under
/// way makes the whole pipeline run twice; the agent must store the program
/// once and answer the repeat with the original receipt (idempotency).
#[test]
fn a_repeated_request_is_stored_once_and_answered_with_the_original_receipt() {
    let mut cluster = Cluster::start();
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap();
    let receipts = rt.block_on(async {
        let session = session_with_services(&cluster.endpoint).await;
        let spec: gearcam_proto::JobSpec = serde_json::from_value(serde_json::json!({
            "job": {"machine": "H01", "part_number": "REP-1"},
            "gear": {"module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0, "fixture_height_mm": 100.0},
            "hob": {"id": "HOB-M3-80"}
        }))
        .unwrap();
        let req = gearcam_proto::JobRequest {
            job_id: gearcam_proto::JobId::new("REP-1").unwrap(),
            submitted_at_ms: 1,
            submitted_by: "test".into(),
            spec,
        };
        let events = session.declare_subscriber("gearcam/v1/jobs/REP-1/events/*").await.unwrap();
        let bytes = gearcam_proto::encode(&req).unwrap();
        // Journaled by the station first (the agent stores only journaled
        // jobs); the station sends it too.
        let replies = session
            .get(keys::station_submit("test"))
            .payload(bytes.clone())
            .timeout(Duration::from_secs(10))
            .await
            .unwrap();
        let reply = replies.recv_async().await.expect("the station answers");
        let reply: StationReply = decode(&reply.result().unwrap().payload().to_bytes()).unwrap();
        assert!(matches!(reply, StationReply::Accepted { .. }), "{reply:?}");
        // Twice more, back to back, as a re-drive racing the first delivery would.
        session.put("gearcam/v1/jobs/REP-1/request", bytes.clone()).await.unwrap();
        session.put("gearcam/v1/jobs/REP-1/request", bytes).await.unwrap();
        let mut receipts = Vec::new();
        while receipts.len() < 2 {
            let sample = tokio::time::timeout(Duration::from_secs(30), events.recv_async())
                .await
                .expect("both deliveries answered")
                .unwrap();
            let ev: JobEvent = decode(&sample.payload().to_bytes()).unwrap();
            match ev.event {
                EventKind::Delivered { receipt } => receipts.push(receipt),
                EventKind::Failed { errors } => panic!("a repeat was refused: {errors:?}"),
                _ => {}
            }
        }
        session.close().await.unwrap();
        receipts
    });
    assert_eq!(receipts[0].sha256, receipts[1].sha256);
    assert_eq!(
        receipts[0].stored_at_ms, receipts[1].stored_at_ms,
        "the repeat gets the original receipt"
    );
    assert_eq!(
        (receipts[0].duplicate, receipts[1].duplicate),
        (false, true)
    );
    let conn = rusqlite::Connection::open(cluster.index_db()).unwrap();
    let rows: i64 = conn
        .query_row("SELECT COUNT(*) FROM programs", [], |r| r.get(0))
        .unwrap();
    assert_eq!(rows, 1);
    cluster.assert_all_running();
}

/// A client session to the cluster's router, once every service is alive.
async fn session_with_services(endpoint: &str) -> zenoh::Session {
    let session = zenoh::open(gearcam_testkit::client_config(endpoint))
        .await
        .unwrap();
    for service in ["station", "knowledge", "model", "template", "agent/H01"] {
        let key = format!("gearcam/v1/alive/{service}");
        let deadline = std::time::Instant::now() + Duration::from_secs(30);
        loop {
            let replies = session
                .liveliness()
                .get(&key)
                .timeout(Duration::from_millis(500))
                .await
                .unwrap();
            if replies.recv_async().await.is_ok() {
                break;
            }
            assert!(
                std::time::Instant::now() < deadline,
                "{service} never became alive"
            );
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    }
    session
}

/// A well-formed program for H01 under `name` (its hash right).
fn program_named(job: &str, name: &str) -> gearcam_proto::NcProgram {
    let text = format!("%_N_X_MPF\n; {job}\nM2\n");
    gearcam_proto::NcProgram {
        job_id: gearcam_proto::JobId::new(job).unwrap(),
        machine: gearcam_proto::MachineId::new("H01").unwrap(),
        name: name.into(),
        revision: 1,
        dialect: gearcam_proto::Dialect::Sinumerik840d,
        sha256: hex::encode(Sha256::digest(text.as_bytes())),
        text,
        template: gearcam_proto::TemplateRef {
            id: "t".into(),
            version: 1,
        },
        part_number: "P".into(),
        cases: vec![],
        model_version: "-".into(),
        generator: "-".into(),
        path_check: Default::default(),
        form: None,
        simulation: None,
    }
}

#[test]
fn oversize_payloads_and_path_names_are_refused_and_nothing_is_stored() {
    let mut cluster = Cluster::start();
    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        let session = session_with_services(&cluster.endpoint).await;
        // An oversize request: the knowledge service refuses it with a typed error.
        let events = session
            .declare_subscriber("gearcam/v1/jobs/BIG-1/events/*")
            .await
            .unwrap();
        let big = vec![0x90u8; gearcam_proto::MAX_MESSAGE_BYTES + 1];
        session
            .put("gearcam/v1/jobs/BIG-1/request", big)
            .await
            .unwrap();
        let sample = tokio::time::timeout(Duration::from_secs(30), events.recv_async())
            .await
            .expect("a typed error for the oversize payload")
            .unwrap();
        let ev: JobEvent = decode(&sample.payload().to_bytes()).unwrap();
        match ev.event {
            EventKind::Failed { errors } => assert_eq!(errors[0].code, "MESSAGE_TOO_LARGE"),
            other => panic!("expected a refusal, got {other:?}"),
        }
        // Program names that would leave the program directory are refused.
        for (job, name) in [
            ("PATH-1", "../../EVIL"),
            ("PATH-2", "AB/EVIL"),
            ("PATH-3", ".."),
        ] {
            let replies = session
                .get(format!("gearcam/v1/machines/H01/programs/{job}"))
                .payload(gearcam_proto::encode(&program_named(job, name)).unwrap())
                .timeout(Duration::from_secs(10))
                .await
                .unwrap();
            let reply = replies.recv_async().await.expect("the agent answers");
            match decode::<DeliveryReply>(&reply.result().unwrap().payload().to_bytes()).unwrap() {
                DeliveryReply::Refused { error } => {
                    assert_eq!(error.code, "BAD_PROGRAM_NAME", "{name}")
                }
                other => panic!("{name}: expected a refusal, got {other:?}"),
            }
        }
        session.close().await.unwrap();
    });
    let programs = cluster.program_dir();
    assert_eq!(
        std::fs::read_dir(&programs).map(|d| d.count()).unwrap_or(0),
        0
    );
    let root = cluster.dir.path();
    assert!(!root.join("EVIL").exists() && !root.join("H01/EVIL").exists());
    // Still serving.
    cluster.assert_all_running();
    let job = cluster.job_file("spur.toml", SPUR_JOB);
    let (out, v) = cluster.submit_wait(&job);
    assert!(out.status.success(), "{v}\n{}", cluster.logs());
}
