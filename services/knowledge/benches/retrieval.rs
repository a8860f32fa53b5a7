//! Retrieval over 1,000,000 cases (docs/knowledge.md#case-based-reasoning; target: p50 under 5 ms).
//!
//! `cargo bench -p gearcam-knowledge --bench retrieval`; criterion prints the
//! time per retrieval, and `target/criterion/<bench>/new/estimates.json`
//! holds its median (p50).
//!
//! Two case bases of 1,000,000 synthetic cases each (a fixed xorshift seed, so
//! every run measures the same data):
//! - `shop_mix`: cases spread over the 6 classes and 5 material groups as a
//!   shop's history would be (cylindrical gears dominate), so the hard
//!   constraints leave the job's (class, group) block to score;
//! - `one_block`: the worst case, every case of the job's class and material
//!   group, so all 1,000,000 are scored.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use gearcam_knowledge::cbr::{
    Case, CaseBase, Limits, Operation, Problem, Solution, Weights, TOP_K,
};

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[(self.next() % xs.len() as u64) as usize]
    }
}

const CLASSES: &[&str] = &[
    "cylindrical",
    "cylindrical",
    "cylindrical",
    "conical",
    "worm_wheel",
    "crowned",
    "curved_tooth",
    "multi_gear",
];
const GROUPS: &[&str] = &[
    "case_hardening_steel",
    "quenched_tempered_steel",
    "cast_iron",
    "nonferrous",
    "steel",
];
const MATERIALS: &[&str] = &[
    "20CrMnTi", "16MnCr5", "42CrMo4", "C45", "GG25", "CuSn12", "40Cr",
];
const HOB_MATERIALS: &[&str] = &["HSS", "PM-HSS", "carbide"];
const COATINGS: &[&str] = &["none", "TiN", "TiAlN", "AlCrN"];
const MACHINES: &[&str] = &["H01", "H02", "H03", "H04"];

fn cases(n: usize, one_block: bool) -> Vec<Case> {
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    (0..n)
        .map(|i| {
            let (class, group) = if one_block {
                ("cylindrical", "case_hardening_steel")
            } else {
                (r.pick(CLASSES), r.pick(GROUPS))
            };
            Case {
                id: format!("C{i:07}"),
                problem: Problem {
                    class: class.into(),
                    material: r.pick(MATERIALS).into(),
                    material_group: group.into(),
                    hardness_hb: (r.unit() < 0.8).then(|| 150.0 + 150.0 * r.unit()),
                    module_mm: 1.0 + 7.0 * r.unit(),
                    teeth: 10 + (r.next() % 120) as u32,
                    helix_angle_deg: 35.0 * r.unit(),
                    face_width_mm: (r.unit() < 0.9).then(|| 10.0 + 90.0 * r.unit()),
                    quality_grade: 5 + (r.next() % 6) as u8,
                    hob_material: Some(r.pick(HOB_MATERIALS).into()),
                    hob_coating: Some(r.pick(COATINGS).into()),
                    hob_starts: 1 + (r.next() % 3) as u32,
                    operation: if r.unit() < 0.3 {
                        Operation::Rough
                    } else {
                        Operation::Finish
                    },
                    machine: Some(r.pick(MACHINES).into()),
                },
                solution: Solution {
                    cutting_speed_m_min: 60.0 + 200.0 * r.unit(),
                    feed_mm_per_rev: 1.0 + 3.0 * r.unit(),
                    hob_od_mm: Some(60.0 + 60.0 * r.unit()),
                    radial_feed_mm_min: None,
                    cuts: 1 + (r.next() % 2) as u32,
                    allowance_mm: None,
                    cut_mode: None,
                },
                confidence: r.unit(),
                provenance: "synthetic benchmark case".into(),
            }
        })
        .collect()
}

fn job() -> Problem {
    Problem {
        class: "cylindrical".into(),
        material: "20CrMnTi".into(),
        material_group: "case_hardening_steel".into(),
        hardness_hb: Some(180.0),
        module_mm: 3.0,
        teeth: 25,
        helix_angle_deg: 15.0,
        face_width_mm: Some(30.0),
        quality_grade: 7,
        hob_material: Some("HSS".into()),
        hob_coating: Some("TiN".into()),
        hob_starts: 1,
        operation: Operation::Finish,
        machine: Some("H01".into()),
    }
}

fn bench(c: &mut Criterion) {
    let q = job();
    // 1500 rpm on an 80 mm hob.
    let limits = Limits {
        max_cutting_speed_m_min: 1500.0 * std::f64::consts::PI * 80.0 / 1000.0,
    };
    let w = Weights::default();
    let mut g = c.benchmark_group("retrieval_1m");
    g.sample_size(50);
    for (name, one_block) in [("shop_mix", false), ("one_block", true)] {
        let cb = CaseBase::new(cases(1_000_000, one_block));
        assert_eq!(cb.len(), 1_000_000);
        assert_eq!(cb.retrieve(&q, &limits, &w, TOP_K).len(), TOP_K);
        g.bench_function(name, |b| {
            b.iter(|| black_box(cb.retrieve(black_box(&q), &limits, &w, TOP_K)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
