//! The wire EDM family through the whole system: a die job for
//! the 3B/4B machine W01 and one for the ISO machine W02, submitted with
//! `gearcam submit --wait` to a cluster of real service processes behind a
//! router on loopback, reach the machines' agents and are stored under the
//! controls' naming (`PD-2001.3b`, `O4001`). The stored programs, read back
//! from the agents' directories and replayed as the controls run them, lie
//! where the gear's own radii (computed here from the job files' numbers)
//! put them, and cross the pitch circle twice per tooth.

use gearcam_testkit::Cluster;
use gearcam_wire::Segment;
use sha2::{Digest, Sha256};

/// Points along the segments, 20 per segment.
fn points(path: &[Segment]) -> Vec<(f64, f64)> {
    path.iter()
        .flat_map(|s| {
            let a = s.arc();
            (0..20).map(move |i| a.point_at(a.length * f64::from(i) / 20.0))
        })
        .collect()
}

/// The smallest and largest radius, and how often the radius crosses `r`.
fn radii(pts: &[(f64, f64)], r: f64) -> (f64, f64, usize) {
    let rad: Vec<f64> = pts.iter().map(|p| p.0.hypot(p.1)).collect();
    let crossings = rad
        .windows(2)
        .filter(|w| (w[0] - r) * (w[1] - r) < 0.0)
        .count();
    (
        rad.iter().copied().fold(f64::INFINITY, f64::min),
        rad.iter().copied().fold(0.0, f64::max),
        crossings,
    )
}

#[test]
fn die_jobs_reach_the_wire_machines_agents_under_their_naming() {
    let mut cluster = Cluster::start();
    cluster.start_agent_for("W01");
    cluster.start_agent_for("W02");
    let examples = gearcam_testkit::examples::dir();

    // m 2, z 20 die on W01 in 3B, a quarter with the control's rotation.
    let job = cluster.job_file(
        "die.toml",
        &std::fs::read_to_string(examples.join("die_m2z20_3b.toml")).unwrap(),
    );
    let (out, v) = cluster.submit_wait(&job);
    assert!(out.status.success(), "{v}\n{}", cluster.logs());
    assert_eq!(v["state"], "delivered", "{v}");
    let path = cluster.dir().join("W01/programs/PD-2001.3b");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}\n{}", path.display(), cluster.logs()));
    assert_eq!(
        hex::encode(Sha256::digest(text.as_bytes())),
        v["program"]["sha256"].as_str().unwrap()
    );
    assert!(text.contains("; CERTIFICATE REPLAYED"), "{text}");
    let body: String = text
        .lines()
        .filter(|l| !l.starts_with(';'))
        .map(|l| format!("{l}\n"))
        .collect();
    let blocks = gearcam_wire::threeb::read(&body).unwrap();
    // Lead-in from the opening's centre, the quarter four times turned by
    // 90° clockwise (three quarter turns counter-clockwise each), lead-out.
    let inner = &blocks[1..blocks.len() - 1];
    let mut at = gearcam_wire::threeb::replay(&blocks[..1], (0.0, 0.0))[0].to();
    let mut wire = Vec::new();
    for k in 0..4u8 {
        let turned = gearcam_wire::threeb::rotate_quarter(inner, (4 - k) % 4);
        let part = gearcam_wire::threeb::replay(&turned, at);
        at = part.last().unwrap().to();
        wire.extend(part);
    }
    // The wire (radius 0.09 + gap 0.01) runs inside the opening: from the
    // root circle m(z/2 − 1.25) − 0.1 to the tip circle m(z/2 + 1) − 0.1.
    let (lo, hi, crossings) = radii(&points(&wire), 20.0);
    assert!((lo - (17.5 - 0.1)).abs() < 0.002, "{lo}");
    assert!((hi - (22.0 - 0.1)).abs() < 0.002, "{hi}");
    assert_eq!(crossings, 2 * 20, "pitch circle crossings");
    assert!(at.0.hypot(at.1 - 21.9) < 0.002, "ends at {at:?}");

    // m 1, z 40 die on W02 in ISO: O4001, the outline with G42.
    let job = cluster.job_file(
        "iso.toml",
        &std::fs::read_to_string(examples.join("die_m1z40_iso.toml")).unwrap(),
    );
    let (out, v) = cluster.submit_wait(&job);
    assert!(out.status.success(), "{v}\n{}", cluster.logs());
    let path = cluster.dir().join("W02/programs/O4001");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}\n{}", path.display(), cluster.logs()));
    assert!(text.starts_with("%\nO4001\n"), "{text}");
    let replay = gearcam_wire::iso::replay(&text).unwrap();
    let outline: Vec<Segment> = replay
        .moves
        .iter()
        .filter(|m| m.side.is_some() && !m.rapid)
        .skip(1)
        .map(|m| m.segment)
        .collect();
    assert!(replay
        .moves
        .iter()
        .filter(|m| m.side.is_some())
        .all(|m| m.side == Some(gearcam_wire::iso::Side::Right) && m.offset_mm == Some(0.145)));
    let (lo, hi, crossings) = radii(&points(&outline), 20.0);
    assert!((lo - 18.75).abs() < 0.002, "{lo}");
    assert!((hi - 21.0).abs() < 0.002, "{hi}");
    assert_eq!(crossings, 2 * 40, "pitch circle crossings");
    cluster.assert_all_running();
}
