//! While an agent is frozen, the station's re-drives (each asking the
//! agent's store for a lost receipt, up to 2 s) must not run one at a time
//! in its only loop, leaving submit and status unanswered for tens of
//! seconds and SIGTERM ignored. Through real processes: the agent is
//! stopped with SIGSTOP while 20 jobs wait on it.
// Test code: clocks for the bounded waits.
#![allow(clippy::disallowed_methods)]

use std::process::Command;
use std::time::{Duration, Instant};

use gearcam_testkit::{gearcam, Cluster};

fn signal(pid: u32, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &pid.to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill {sig} {pid}");
}

#[test]
fn the_station_answers_and_stops_while_an_agent_is_frozen() {
    let mut c = Cluster::start();
    let spur = gearcam_testkit::examples::example("spur_840d.toml");
    let (_, v) = c.submit_wait(&c.job_file("first.toml", &spur));
    assert_eq!(v["state"], "delivered", "{v}");

    let agent = c.proc("agent").pid();
    signal(agent, "-STOP");
    let mut ids = Vec::new();
    for q in 0..20 {
        let job = c.job_file(
            &format!("j{q}.toml"),
            &spur.replace("quantity = 20", &format!("quantity = {}", 30 + q)),
        );
        ids.push(c.submit(&job)["job"].as_str().unwrap().to_string());
    }
    // A station started again wakes every unfinished job at once: 20
    // re-drives, each asking the frozen agent's store for a lost receipt and
    // waiting for its timeout. The station must still answer (the CLI gives
    // up after 3 tries of 5 s) and take new jobs.
    std::thread::sleep(Duration::from_millis(1500));
    c.proc("station").kill();
    c.proc("station").restart();
    std::thread::sleep(Duration::from_millis(1500));
    for (round, id) in ids.iter().take(3).enumerate() {
        let (code, _, err) = gearcam(&["status", id, "--connect", &c.endpoint, "--json"]);
        assert_eq!(
            code,
            Some(0),
            "status unanswered while re-drives wait: {err}"
        );
        let (code, _, err) = gearcam(&["jobs", "--connect", &c.endpoint, "--json"]);
        assert_eq!(code, Some(0), "jobs unanswered while re-drives wait: {err}");
        let job = c.job_file(
            &format!("late{round}.toml"),
            &spur.replace("quantity = 20", &format!("quantity = {}", 60 + round)),
        );
        c.submit(&job);
        std::thread::sleep(Duration::from_secs(2));
    }

    // SIGTERM: the station stops promptly (bounded wait: a stalled station
    // took over 120 s), though drives are still waiting on the agent.
    let station = c.proc("station").pid();
    signal(station, "-TERM");
    let deadline = Instant::now() + Duration::from_secs(10);
    while c.proc("station").running() {
        assert!(
            Instant::now() < deadline,
            "the station ignored SIGTERM\n{}",
            c.logs()
        );
        std::thread::sleep(Duration::from_millis(100));
    }

    // The agent thaws, the station comes back: every job is delivered.
    signal(agent, "-CONT");
    c.proc("station").restart();
    c.wait_all_delivered(24, Duration::from_secs(120));
}
