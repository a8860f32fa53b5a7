//! An authenticated planner's flood: bursts of concurrent queries on the
//! station's, the knowledge base's and H01's program store's keys, most of
//! them small garbage a service refuses with a typed error, every fifth a
//! third of a megabyte.

use std::time::Duration;

/// Concurrent queries in one burst.
pub const QUERIES: usize = 40;

/// The largest payload of the flood: a third of a megabyte.
pub const OVERSIZED: usize = 300 * 1024;

/// How long each query may take.
pub const TIMEOUT: Duration = Duration::from_secs(15);

/// The planner-readable keys of the flood: the planner's submit key, the
/// station's job list and a status, two knowledge-base libraries, H01's
/// program store.
pub fn keys() -> Vec<String> {
    use gearcam_proto::{keys, JobId, MachineId};
    vec![
        keys::station_submit("planner"),
        keys::STATION_JOBS.to_string(),
        keys::station_job(&JobId::new("NO-SUCH-JOB").expect("a job id")),
        keys::kb_library("machines"),
        keys::kb_library("hobs"),
        keys::store_programs(&MachineId::new("H01").expect("a machine id")),
    ]
}

/// One query of the flood and how many replies it got.
#[derive(Debug, Clone)]
pub struct Asked {
    /// The key queried.
    pub key: String,
    /// The payload's size, bytes.
    pub bytes: usize,
    /// Replies received (answers and typed refusals) within [`TIMEOUT`].
    pub replies: usize,
}

impl Asked {
    /// The key and the size, for a failure message.
    pub fn name(&self) -> String {
        format!("{} ({} bytes)", self.key, self.bytes)
    }
}

/// The payload of query `i`.
fn payload(i: usize) -> Vec<u8> {
    let bytes = if i % 5 == 4 {
        OVERSIZED
    } else {
        16 + 97 * (i % 200)
    };
    (0..bytes).map(|b| (b * 31 + i) as u8).collect()
}

/// Burst number `n`: [`QUERIES`] queries at once on `session`, each waited
/// for until its timeout.
pub async fn burst(session: &zenoh::Session, n: usize) -> Vec<Asked> {
    let keys = keys();
    let mut tasks = Vec::new();
    for q in 0..QUERIES {
        let i = n * QUERIES + q;
        let key = keys[i % keys.len()].clone();
        let body = payload(i);
        let bytes = body.len();
        let session = session.clone();
        tasks.push(tokio::spawn(async move {
            let mut replies = 0;
            if let Ok(rx) = session.get(&key).payload(body).timeout(TIMEOUT).await {
                while rx.recv_async().await.is_ok() {
                    replies += 1;
                }
            }
            Asked {
                key,
                bytes,
                replies,
            }
        }));
    }
    let mut asked = Vec::with_capacity(QUERIES);
    for t in tasks {
        asked.push(t.await.expect("a query task"));
    }
    asked
}
