//! The foreign client of `proto/examples/client.py` (Python, `eclipse-zenoh`
//! and `msgpack` from PyPI, written from `proto/README.md`) against the real
//! services, each its own process behind a router on loopback: it submits a
//! job, follows it to `delivered`, reads the program back from the machine's
//! store and checks its hash, and checks every typed refusal of the wire
//! contract (unknown machine, same id with another spec, bad id, unknown job,
//! unknown program or version, a store change without a request).

use std::process::Command;

use gearcam_testkit::Cluster;

#[test]
fn the_python_client_delivers_reads_back_and_sees_typed_refusals() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let probe = Command::new("python3")
        .args(["-c", "import zenoh, msgpack"])
        .output()
        .expect("python3 on PATH");
    assert!(
        probe.status.success(),
        "the example client needs its packages: pip install -r proto/examples/requirements.txt\n{}",
        String::from_utf8_lossy(&probe.stderr)
    );
    let cluster = Cluster::start();
    let out = Command::new("python3")
        .arg(root.join("proto/examples/client.py"))
        .args([
            "--connect",
            &cluster.endpoint,
            "--job-id",
            "PY-1",
            "--refusals",
        ])
        .arg(root.join("examples/spur_840d.toml"))
        .output()
        .expect("run the client");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "client failed\nstdout:\n{stdout}\nstderr:\n{stderr}\nlogs:\n{}",
        cluster.logs()
    );
    eprintln!("{stdout}");
    // The client's own checks printed; the hash it computed is the agent's file's.
    assert!(
        stdout.contains("ok: sha256 of the text read back = receipt"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok: refused with UNKNOWN_MACHINE"),
        "{stdout}"
    );
    let file = stdout
        .lines()
        .find_map(|l| l.strip_prefix("delivered PY-1: "))
        .and_then(|l| l.split_whitespace().next())
        .expect("the delivered line")
        .to_string();
    let on_disk = std::fs::read(cluster.program_dir().join(&file)).expect("the stored file");
    let hash = {
        use sha2::{Digest, Sha256};
        hex::encode(Sha256::digest(&on_disk))
    };
    assert!(
        stdout.contains(&hash),
        "the file's hash {hash} in\n{stdout}"
    );
}

/// Runs the client, unchanged, on `example` for `machine` as job `job`:
/// it must report the delivery of `name`, and the hash it read back from
/// the agent's store must be the hash of the file `name` on disk.
fn python_delivers(machine: &str, example: &str, job: &str, name: &str) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut cluster = Cluster::start();
    cluster.start_agent_for(machine);
    let out = Command::new("python3")
        .arg(root.join("proto/examples/client.py"))
        .args(["--connect", &cluster.endpoint, "--job-id", job])
        .arg(root.join("examples").join(example))
        .output()
        .expect("run the client");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "client failed\nstdout:\n{stdout}\nstderr:\n{}\nlogs:\n{}",
        String::from_utf8_lossy(&out.stderr),
        cluster.logs()
    );
    assert!(
        stdout.contains(&format!("delivered {job}: {name}")),
        "{stdout}"
    );
    let on_disk = std::fs::read(cluster.dir().join(machine).join("programs").join(name)).unwrap();
    let hash = {
        use sha2::{Digest, Sha256};
        hex::encode(Sha256::digest(&on_disk))
    };
    assert!(
        stdout.contains(&hash),
        "the file's hash {hash} in\n{stdout}"
    );
}

/// The same client, unchanged, submits a spiral face milling job (a planar
/// spiral groove for the LinuxCNC mill M02): the family is a field of the
/// job file, and the client sees the same events and receipt.
#[test]
fn the_python_client_delivers_a_spiral_job_to_the_linuxcnc_mill() {
    python_delivers("M02", "groove_linuxcnc.toml", "PY-S1", "PT-4002.ngc");
}

/// The same client, unchanged, submits a wire EDM die job (a 40-tooth die
/// in ISO for W02): it reads the stored program back from the agent's store
/// by its name and checks its hash like any other.
#[test]
fn the_python_client_delivers_a_wire_die_to_the_iso_machine() {
    python_delivers("W02", "die_m1z40_iso.toml", "PY-W1", "O4001");
}
