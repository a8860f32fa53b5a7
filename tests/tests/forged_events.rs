//! The journal must not trust a `delivered` or `failed` event whoever
//! published it. Through real processes: a job waits for its
//! (absent) agent; events forged by someone else (on another service's key,
//! for another machine, or a state the reporter does not own) leave it
//! waiting; only the machine's agent delivers it.
// Test code: clocks for the waits.
#![allow(clippy::disallowed_methods)]

use std::time::{Duration, Instant};

use gearcam_proto::{
    encode, keys, DeliveryReceipt, EventKind, JobError, JobEvent, JobId, MachineId, Stage,
};
use gearcam_testkit::{gearcam, Cluster};

fn state(c: &Cluster, id: &str) -> serde_json::Value {
    let (_, out, _) = gearcam(&["status", id, "--connect", &c.endpoint, "--json"]);
    serde_json::from_str(&out).unwrap_or_default()
}

#[test]
fn only_the_owner_of_a_state_may_report_it() {
    let mut c = Cluster::start_without_agent();
    let job = c.job_file(
        "spur.toml",
        &gearcam_testkit::examples::example("spur_840d.toml"),
    );
    let id = c.submit(&job)["job"].as_str().unwrap().to_string();
    let deadline = Instant::now() + Duration::from_secs(30);
    while state(&c, &id)["state"] != "waiting" {
        assert!(
            Instant::now() < deadline,
            "the job did not wait for its agent\n{}",
            c.logs()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let job_id = JobId::new(id.clone()).unwrap();
    let receipt = |machine: &str| DeliveryReceipt {
        job_id: job_id.clone(),
        machine: MachineId::new(machine).unwrap(),
        name: "SP_1001".into(),
        file_name: "_N_SP_1001_MPF".into(),
        path: "/nowhere".into(),
        revision: 1,
        sha256: "00".repeat(32),
        size_bytes: 1,
        stored_at_ms: 1,
        duplicate: false,
    };
    let event = |stage: Stage, event: EventKind| JobEvent {
        job_id: job_id.clone(),
        stage,
        at_ms: 1,
        event,
    };
    let forged = [
        // A delivery reported on the template service's key.
        (
            "template",
            event(
                Stage::Agent,
                EventKind::Delivered {
                    receipt: receipt("H01"),
                },
            ),
        ),
        // A delivery from another machine's agent.
        (
            "agent-H09",
            event(
                Stage::Agent,
                EventKind::Delivered {
                    receipt: receipt("H09"),
                },
            ),
        ),
        // H01's agent key, but a receipt for another machine.
        (
            "agent-H01",
            event(
                Stage::Agent,
                EventKind::Delivered {
                    receipt: receipt("H02"),
                },
            ),
        ),
        // A refusal in the model's name on the station's key.
        (
            "station",
            event(
                Stage::Model,
                EventKind::Failed {
                    errors: vec![JobError::new(
                        Stage::Model,
                        gearcam_proto::Code::INTERNAL_ERROR,
                        "-",
                        "-",
                        "-",
                        "forged",
                    )],
                },
            ),
        ),
    ];
    let rt = tokio::runtime::Runtime::new().unwrap();
    rt.block_on(async {
        let session = zenoh::open(gearcam_testkit::client_config(&c.endpoint))
            .await
            .unwrap();
        for (reporter, ev) in &forged {
            session
                .put(keys::job_event(&job_id, reporter), encode(ev).unwrap())
                .await
                .unwrap();
        }
        tokio::time::sleep(Duration::from_secs(2)).await;
        session.close().await.unwrap();
    });
    let s = state(&c, &id);
    assert_eq!(s["state"], "waiting", "a forged event decided the job: {s}");

    // The machine's agent comes: the job is delivered for real.
    c.start_agent();
    c.wait_all_delivered(1, Duration::from_secs(60));
}
