//! The program store's speed: `cargo bench -p gearcam-agent --bench store`.
//!
//! Stores groups of programs the size of a hobbing program (2.4 KB) with
//! [`Store::store_batch`], as the agent does with the deliveries that arrive
//! together: every file written durably, renamed, and its index row
//! committed. The store lives in a temporary directory on the file system
//! of the system's temporary directory (`TMPDIR`), so the figures are that
//! disk's fsyncs. Prints per group size the time of one group and the jobs
//! per second it sustains, each the median of several groups into a store
//! that already holds thousands of programs (as a machine's store does).

// A bench measures time itself for the printed figure.
#![allow(clippy::disallowed_methods)]

use gearcam_agent::store::{sha256_hex, Faults, Store, StoreConfig};
use gearcam_proto::{Dialect, JobId, MachineId, NcProgram, TemplateRef};
use std::time::Instant;

fn program(n: usize) -> NcProgram {
    let name = format!("SP_{n:06}");
    let mut text = format!("%_N_{name}_MPF\n");
    while text.len() < 2400 {
        text.push_str("N10 G01 X12.345 Z-45.678 F1.2 ; a block of a hobbing program\n");
    }
    text.push_str("M30\n");
    NcProgram {
        job_id: JobId::new(format!("J{n:06}")).expect("job id"),
        machine: MachineId::new("H01").expect("machine id"),
        name,
        revision: 1,
        dialect: Dialect::Sinumerik840d,
        sha256: sha256_hex(text.as_bytes()),
        text,
        template: TemplateRef {
            id: "bench".into(),
            version: 1,
        },
        part_number: "P".into(),
        cases: vec![],
        model_version: "m".into(),
        generator: "bench".into(),
        path_check: Default::default(),
        form: None,
        simulation: None,
    }
}

fn main() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let mut store = Store::open(StoreConfig {
        machine: MachineId::new("H01").expect("machine id"),
        dialect: Dialect::Sinumerik840d,
        program_dir: dir.path().join("programs"),
        index_path: dir.path().join("index.db"),
        faults: Faults::default(),
    })
    .expect("store");
    let mut next = 0usize;
    let mut group = |store: &mut Store, size: usize| -> f64 {
        let programs: Vec<NcProgram> = (next..next + size).map(program).collect();
        next += size;
        let start = Instant::now();
        let results = store.store_batch(&programs);
        let ms = start.elapsed().as_secs_f64() * 1e3;
        for r in results {
            r.expect("stored");
        }
        ms
    };
    // A store that already holds thousands of programs.
    for _ in 0..40 {
        group(&mut store, 64);
    }
    println!("program store: groups of 2.4 KB programs, each durable before its receipt");
    for size in [1usize, 8, 64] {
        let rounds = if size == 1 { 200 } else { 40 };
        let mut ms: Vec<f64> = (0..rounds).map(|_| group(&mut store, size)).collect();
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        let p90 = ms[ms.len() * 9 / 10];
        println!(
            "  group of {size:>2}: median {median:6.2} ms, p90 {p90:6.2} ms; {:6.0} jobs/s",
            size as f64 * 1e3 / median
        );
    }
}
