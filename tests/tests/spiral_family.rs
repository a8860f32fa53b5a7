//! The spiral face milling family through the whole system: a
//! face job and a planar-thread job, submitted with `gearcam submit --wait`
//! to a cluster of real service processes behind a router on loopback,
//! reach the milling machines' agents (M01 FANUC, M02 LinuxCNC) and are
//! stored under the controllers' naming; the stored programs, read back from
//! the agents' directories, are replayed by the Macro B / LinuxCNC subset
//! interpreter and follow the spiral of the face they were made for,
//! computed here from the job file's numbers alone.

use gearcam_spiral::macrob::{replay, replay_linuxcnc, Move};
use gearcam_testkit::Cluster;
use sha2::{Digest, Sha256};

/// The feed moves below the face, as (x, y).
fn cutting(moves: &[Move]) -> Vec<(f64, f64)> {
    moves
        .iter()
        .filter(|m| m.feed && m.z < 0.0)
        .map(|m| (m.x, m.y))
        .collect()
}

#[test]
fn a_face_job_and_a_groove_job_reach_the_mills_agents_under_their_naming() {
    let mut cluster = Cluster::start();
    cluster.start_agent_for("M01");
    cluster.start_agent_for("M02");
    let examples = gearcam_testkit::examples::dir();

    // The annulus Ro 100, Ri 20 on the FANUC mill: the macro as O3001.
    let face = cluster.job_file(
        "face.toml",
        &std::fs::read_to_string(examples.join("face_annulus_fanuc.toml")).unwrap(),
    );
    let (out, v) = cluster.submit_wait(&face);
    assert!(out.status.success(), "{v}\n{}", cluster.logs());
    assert_eq!(v["state"], "delivered", "{v}");
    let path = cluster.dir().join("M01/programs/O3001");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}\n{}", path.display(), cluster.logs()));
    assert_eq!(
        hex::encode(Sha256::digest(text.as_bytes())),
        v["program"]["sha256"].as_str().unwrap()
    );
    assert!(
        text.starts_with("%\nO3001 (SPIRAL FACE MILLING)\n"),
        "{text}"
    );
    // Every cutting point of the replayed macro lies in the band the tool
    // centre must sweep: from Ro + rt outside the face (the tool enters
    // from outside) to no further in than Ri + rt (no ring at the inner
    // edge); a 63 mm face mill from the library (the header names it).
    assert!(text.contains("TOOL FM-063 FACE-MILL D63"), "{text}");
    let moves = replay(&text, 1_000_000).unwrap();
    let pts = cutting(&moves);
    assert!(pts.len() > 100);
    let radius = |p: &(f64, f64)| (p.0 * p.0 + p.1 * p.1).sqrt();
    let r_max = pts.iter().map(radius).fold(0.0, f64::max);
    let r_min = pts.iter().map(radius).fold(f64::INFINITY, f64::min);
    assert!(r_max > 100.0 + 31.5, "starts at {r_max}: inside the face");
    assert!(
        r_min <= 20.0 + 31.5,
        "ends at {r_min}: leaves a ring at the inner edge"
    );
    // Climb milling with M03 outside-in: clockwise (the angle decreases).
    let a0 = pts[1].1.atan2(pts[1].0);
    let a1 = pts[2].1.atan2(pts[2].0);
    assert!(a1 < a0, "not clockwise: {a0} then {a1}");

    // The planar spiral groove on the LinuxCNC mill: PT-4002.ngc.
    let groove = cluster.job_file(
        "groove.toml",
        &std::fs::read_to_string(examples.join("groove_linuxcnc.toml")).unwrap(),
    );
    let (out, v) = cluster.submit_wait(&groove);
    assert!(out.status.success(), "{v}\n{}", cluster.logs());
    let path = cluster.dir().join("M02/programs/PT-4002.ngc");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}\n{}", path.display(), cluster.logs()));
    let moves = replay_linuxcnc(&text, 1_000_000).unwrap();
    // The groove's centre line: radius 60 − 16 mm per turn, 3 turns, in
    // depth passes down to 4 mm; compare each cutting point's radius with
    // the line at its unwrapped angle.
    let depths: std::collections::BTreeSet<i64> = moves
        .iter()
        .filter(|m| m.feed && m.z < 0.0)
        .map(|m| (m.z * 1000.0).round() as i64)
        .collect();
    assert_eq!(depths.iter().next(), Some(&-4000), "{depths:?}");
    assert!(depths.len() >= 2, "one pass only: {depths:?}");
    let last: Vec<(f64, f64)> = moves
        .iter()
        .filter(|m| m.feed && (m.z + 4.0).abs() < 1e-9)
        .map(|m| (m.x, m.y))
        .collect();
    let mut turned = 0.0;
    let mut prev = last[0].1.atan2(last[0].0);
    let mut worst: f64 = 0.0;
    for p in &last[1..] {
        let a = p.1.atan2(p.0);
        let mut d = a - prev;
        if d > std::f64::consts::PI {
            d -= std::f64::consts::TAU;
        } else if d < -std::f64::consts::PI {
            d += std::f64::consts::TAU;
        }
        turned += d.abs();
        prev = a;
        let expected = 60.0 - 16.0 * turned / std::f64::consts::TAU;
        worst = worst.max((radius(p) - expected).abs());
    }
    assert!(
        (turned / std::f64::consts::TAU - 3.0).abs() < 1e-6,
        "{turned}"
    );
    assert!(
        worst < 0.01,
        "the groove strays {worst} mm from its centre line"
    );
    cluster.assert_all_running();
}
