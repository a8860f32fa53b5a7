//! An authenticated flood on the secure deployment (`deploy/secure/`: every
//! service a process with its own user, the ACL, the router's size limits):
//! a planner's bursts of concurrent queries on the station's, the knowledge
//! base's and an agent's keys, small and oversized, crash nothing; every
//! query within the size limits is answered (a reply or a typed refusal)
//! within its timeout; no oversized one reaches a service; and a job
//! submitted afterwards is delivered.
//!
//! Over Zenoh's TLS link (`GEARCAM_SECURE_LINK=tls`), which reads and
//! writes one TLS stream from two tasks at once, the same flood leaves
//! queries unanswered and can abort the router or a service; without the
//! size limits the oversized queries reach the services and are answered.

use std::path::Path;
use std::time::Duration;

use gearcam_proto::keys::MAX_REQUEST_BYTES;
use gearcam_testkit::flood::{burst, Asked};
use gearcam_testkit::secure::Secure;

/// Bursts of the flood.
const BURSTS: usize = 6;

async fn flood(config: &Path) -> Vec<Asked> {
    let session = zenoh::open(zenoh::Config::from_file(config).expect("planner config"))
        .await
        .expect("the planner connects");
    let mut asked = Vec::new();
    for n in 0..BURSTS {
        asked.extend(burst(&session, n).await);
    }
    session.close().await.expect("the session closes");
    asked
}

#[test]
fn an_authenticated_flood_crashes_nothing_and_every_query_is_answered() {
    let mut secure = Secure::start();
    let planner = secure.cfg("planner");
    // The deployment serves before the flood: a job is delivered.
    let job = gearcam_testkit::examples::dir().join("spur_840d.toml");
    let job = job.display().to_string();
    let deliver = || {
        let submit = ["submit", job.as_str(), "--wait", "--timeout", "60"];
        gearcam_testkit::secure::gearcam_json(&planner, &submit, &[]).1
    };
    let v = deliver();
    assert_eq!(
        v["state"],
        "delivered",
        "before the flood: {v}\n{}",
        secure.logs()
    );

    let rt = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .expect("a runtime");
    let asked = rt.block_on(flood(&planner));
    // Let a process the flood broke end before it is looked at.
    std::thread::sleep(Duration::from_secs(2));
    let dead = secure.dead();
    assert!(dead.is_empty(), "died in the flood: {dead:#?}");

    let unanswered: Vec<String> = asked
        .iter()
        .filter(|a| a.bytes <= MAX_REQUEST_BYTES && a.replies == 0)
        .map(Asked::name)
        .collect();
    assert!(
        unanswered.is_empty(),
        "{} of {} queries within the limit got no reply: {unanswered:?}",
        unanswered.len(),
        asked
            .iter()
            .filter(|a| a.bytes <= MAX_REQUEST_BYTES)
            .count()
    );
    let through: Vec<String> = asked
        .iter()
        .filter(|a| a.bytes > MAX_REQUEST_BYTES && a.replies > 0)
        .map(Asked::name)
        .collect();
    assert!(
        through.is_empty(),
        "{} oversized queries reached a service: {through:?}",
        through.len()
    );

    let v = deliver();
    assert_eq!(
        v["state"],
        "delivered",
        "after the flood: {v}\n{}",
        secure.logs()
    );
    let dead = secure.dead();
    assert!(dead.is_empty(), "died after the flood: {dead:#?}");
}

/// The router's size limits are the ones `gearcam_proto::keys::SIZE_LIMITS` gives the
/// station and the CLI: a change of either without the other fails here.
#[test]
fn the_routers_size_limits_are_the_protocols() {
    let config = zenoh::Config::from_file(gearcam_testkit::secure::deploy().join("router.json5"))
        .expect("router.json5 is a Zenoh configuration");
    let filters: serde_json::Value =
        serde_json::from_str(&config.get_json("low_pass_filter").expect("low_pass_filter"))
            .expect("JSON");
    let filters = filters.as_array().expect("a list of filters");
    assert_eq!(
        filters.len(),
        gearcam_proto::keys::SIZE_LIMITS.len(),
        "{filters:?}"
    );
    for limit in gearcam_proto::keys::SIZE_LIMITS {
        let f = filters
            .iter()
            .find(|f| f["id"] == limit.id)
            .unwrap_or_else(|| panic!("no filter {} in router.json5", limit.id));
        assert_eq!(f["size_limit"], limit.bytes, "{}", limit.id);
        assert_eq!(
            f["messages"],
            serde_json::json!(limit.messages),
            "{}",
            limit.id
        );
        assert_eq!(
            f["key_exprs"],
            serde_json::json!(limit.key_exprs),
            "{}",
            limit.id
        );
        assert_eq!(f["flows"], serde_json::json!(["ingress"]), "{}", limit.id);
    }
}
