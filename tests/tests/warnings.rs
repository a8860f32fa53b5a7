//! The model's warnings reach the user. A blank at the
//! edge of its window (`BLANK_OD_EDGE`) is delivered with the warning's
//! code and text in `gearcam submit`'s progress and result, in
//! `submit --json`, and in `gearcam status`; through the real binary and
//! services.

use std::process::{Command, Stdio};

use gearcam_testkit::{bin, Cluster};

#[test]
fn warnings_reach_the_user() {
    let cluster = Cluster::start();
    // H01 allows a blank 2.0 mm below the tip diameter (81 mm); 1.9 mm
    // below is within the window, at its edge.
    let spur = gearcam_testkit::examples::example("spur_840d.toml");
    let edge = spur.replacen("blank_od_mm = 81.0", "blank_od_mm = 79.1", 1);
    assert_ne!(edge, spur, "the example gives its blank diameter");
    let job = cluster.job_file("edge.toml", &edge);

    let (out, v) = cluster.submit_wait(&job);
    assert!(out.status.success(), "{v}");
    assert_eq!(v["state"], "delivered", "{v}");
    let w = &v["warnings"][0];
    assert_eq!(w["code"], "BLANK_OD_EDGE", "{v}");
    assert!(w["message"].as_str().is_some_and(|m| !m.is_empty()), "{v}");

    let human = Command::new(bin("gearcam"))
        .args([
            "submit",
            &job.display().to_string(),
            "--connect",
            &cluster.endpoint,
            "--wait",
        ])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&human.stdout).into_owned()
        + &String::from_utf8_lossy(&human.stderr);
    assert!(human.status.success(), "{text}");
    assert!(text.contains("! BLANK_OD_EDGE gear.blank_od_mm"), "{text}");

    let id = v["job"].as_str().unwrap();
    let status = Command::new(bin("gearcam"))
        .args(["status", id, "--connect", &cluster.endpoint, "--json"])
        .output()
        .unwrap();
    let s: serde_json::Value = serde_json::from_slice(&status.stdout).unwrap();
    assert_eq!(s["warnings"][0]["code"], "BLANK_OD_EDGE", "{s}");
}
