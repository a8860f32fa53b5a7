//! Case-based reasoning for cutting data (docs/knowledge.md#case-based-reasoning; seed 000 §1): retrieve the
//! cases most similar to a job, and adapt their solutions to it.
//!
//! Pure functions on plain data: no database, no clock.
//!
//! # Retrieval
//!
//! 1. Hard constraints. A case is a candidate only when its class and material
//!    group equal the job's, and its cutting speed is one the machine can run
//!    with the job's hob (`vc ≤ max_hob_rpm·π·da0/1000`). Cases are kept in
//!    blocks by (class, material group), so the first two constraints cost one
//!    hash look-up; the speed limit is a mask in the scoring loop.
//! 2. Weighted similarity. `sim = Σ wᵢ·sᵢ / Σ wᵢ` over the features the job
//!    knows, with a local similarity `sᵢ ∈ [0, 1]` per feature:
//!
//!    | feature | local similarity |
//!    |---|---|
//!    | module | `1 − |ln(m_job/m_case)| / ln 2` (a factor 2 apart → 0) |
//!    | teeth | `1 − |ln(z_job/z_case)| / ln 3` |
//!    | helix | `1 − |β_job − β_case| / 20°` |
//!    | face_width | `1 − |ln(b_job/b_case)| / ln 3`; 0.5 when the case does not know it |
//!    | material | 1 same material, 0.7 another of the same group |
//!    | hardness | `1 − |HB_job − HB_case| / 100`; 0.5 when the case does not know it |
//!    | grade | `1 − |Q_job − Q_case| / 3` |
//!    | hob_material | 1 same, 0 different (HSS and carbide cut at very different speeds) |
//!    | hob_coating | 1 same, 0.5 different |
//!    | starts | `1 − |z0_job − z0_case| / 2` |
//!    | operation | 1 same (rough/finish), 0 different |
//!    | machine | 1 same machine, 0.6 another |
//!
//!    every value clamped to [0, 1]. An exact copy of the job scores exactly 1.
//! 3. Top k by similarity, ties broken by case id, with a k-sized heap.
//!
//! The cases are held column by column (structure of arrays, `f32`) so the
//! scoring loop is a straight pass the compiler vectorises; see
//! `benches/retrieval.rs` for its speed over 1,000,000 cases.
//!
//! # Adaptation
//!
//! The similarity-weighted mean of the retrieved cases' solutions, adapted to
//! the job: the cutting speed is kept as it is (a different hob diameter
//! changes the hob rpm, computed later from vc and da0, not vc), and the feed
//! per revolution scales with the module as `fa·sqrt(m_job/m_case)` (an
//! engineering estimate: linear scaling overshoots common feed tables, which
//! grow more slowly than the module). The number of cuts and the allowance
//! come from the most similar case. Confidence = best similarity × the
//! similarity-weighted mean confidence of the cases used.

use std::cmp::{Ordering, Reverse};
use std::collections::{BTreeMap, BinaryHeap, HashMap};

use gearcam_proto::CutMode;

/// The features of retrieval, in the order of [`Weights`].
pub const FEATURES: &[&str] = &[
    "module",
    "teeth",
    "helix",
    "face_width",
    "material",
    "hardness",
    "grade",
    "hob_material",
    "hob_coating",
    "starts",
    "operation",
    "machine",
];

const NF: usize = 12;

/// Default weights: an engineering estimate (module, hob material, starts and
/// rough/finish decide cutting data most).
pub const DEFAULT_WEIGHTS: [(&str, f64); NF] = [
    ("module", 3.0),
    ("teeth", 1.0),
    ("helix", 1.0),
    ("face_width", 0.5),
    ("material", 1.5),
    ("hardness", 1.5),
    ("grade", 1.0),
    ("hob_material", 2.0),
    ("hob_coating", 1.0),
    ("starts", 1.5),
    ("operation", 2.0),
    ("machine", 1.0),
];

/// How many cases a proposal is built from.
pub const TOP_K: usize = 3;

/// Similarity weights by feature (index as in [`FEATURES`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Weights(pub [f64; NF]);

impl Default for Weights {
    fn default() -> Self {
        Weights(DEFAULT_WEIGHTS.map(|(_, w)| w))
    }
}

impl Weights {
    /// Weights from a map by feature name; missing features keep their default.
    pub fn from_map(map: &BTreeMap<String, f64>) -> Weights {
        let mut w = Weights::default();
        for (i, name) in FEATURES.iter().enumerate() {
            if let Some(v) = map.get(*name) {
                w.0[i] = v.max(0.0);
            }
        }
        w
    }

    /// The weights by feature name.
    pub fn to_map(&self) -> BTreeMap<String, f64> {
        FEATURES
            .iter()
            .zip(self.0)
            .map(|(n, w)| (n.to_string(), w))
            .collect()
    }
}

/// Rough or finish hobbing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Operation {
    /// Roughing: stock left for a later operation.
    Rough,
    /// Finishing: the cut gives the final flanks.
    Finish,
}

impl From<gearcam_proto::Operation> for Operation {
    fn from(op: gearcam_proto::Operation) -> Operation {
        match op {
            gearcam_proto::Operation::Rough => Operation::Rough,
            gearcam_proto::Operation::Finish => Operation::Finish,
        }
    }
}

impl Operation {
    /// As written in the database.
    pub fn as_str(self) -> &'static str {
        match self {
            Operation::Rough => "rough",
            Operation::Finish => "finish",
        }
    }

    /// From the database text (anything but `rough` is finish).
    pub fn parse(s: &str) -> Operation {
        if s == "rough" {
            Operation::Rough
        } else {
            Operation::Finish
        }
    }
}

/// The problem features of a job or a case.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Group-technology class (hard constraint).
    pub class: String,
    /// Material name.
    pub material: String,
    /// Material group (hard constraint).
    pub material_group: String,
    /// Hardness, HB, if known.
    pub hardness_hb: Option<f64>,
    /// Normal module, mm.
    pub module_mm: f64,
    /// Teeth.
    pub teeth: u32,
    /// Helix angle magnitude, degrees.
    pub helix_angle_deg: f64,
    /// Face width, mm, if known.
    pub face_width_mm: Option<f64>,
    /// Accuracy grade.
    pub quality_grade: u8,
    /// Hob material, if known.
    pub hob_material: Option<String>,
    /// Hob coating, if known.
    pub hob_coating: Option<String>,
    /// Hob starts.
    pub hob_starts: u32,
    /// Rough or finish.
    pub operation: Operation,
    /// Machine, if known.
    pub machine: Option<String>,
}

/// What was done: a case's cutting data.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Cutting speed vc, m/min.
    pub cutting_speed_m_min: f64,
    /// Axial feed per workpiece revolution, mm/rev.
    pub feed_mm_per_rev: f64,
    /// Hob outside diameter used, mm.
    pub hob_od_mm: Option<f64>,
    /// Radial feed rate, mm/min.
    pub radial_feed_mm_min: Option<f64>,
    /// Number of cuts.
    pub cuts: u32,
    /// Stock / finish allowance, mm.
    pub allowance_mm: Option<f64>,
    /// Cutting mode, if recorded.
    pub cut_mode: Option<CutMode>,
}

/// A case: problem → solution → outcome, with trust.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Case id.
    pub id: String,
    /// Problem features.
    pub problem: Problem,
    /// Solution.
    pub solution: Solution,
    /// Confidence, 0–1.
    pub confidence: f64,
    /// Where its values come from.
    pub provenance: String,
}

/// The job's limits that filter cases.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Largest cutting speed the machine can run with the job's hob, m/min
    /// (`max_hob_rpm·π·da0/1000`); `f64::INFINITY` when unknown.
    pub max_cutting_speed_m_min: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_cutting_speed_m_min: f64::INFINITY,
        }
    }
}

/// A retrieved case: its index in [`CaseBase::cases`] and its similarity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Index into [`CaseBase::cases`].
    pub index: usize,
    /// Similarity to the job, 0–1.
    pub similarity: f64,
}

const NONE: u32 = u32::MAX;
const UNKNOWN_QUERY: u32 = u32::MAX - 1;
const CHUNK: usize = 256;

/// One (class, material group) block, column by column.
#[derive(Debug, Default, Clone)]
struct Block {
    index: Vec<u32>,
    ln_module: Vec<f32>,
    ln_teeth: Vec<f32>,
    helix: Vec<f32>,
    ln_face: Vec<f32>,
    face_known: Vec<f32>,
    material: Vec<u32>,
    hardness: Vec<f32>,
    hardness_known: Vec<f32>,
    grade: Vec<f32>,
    hob_material: Vec<u32>,
    coating: Vec<u32>,
    starts: Vec<f32>,
    operation: Vec<u32>,
    machine: Vec<u32>,
    vc: Vec<f32>,
}

fn ln32(x: f64) -> f32 {
    x.ln() as f32
}

/// The case base held in memory for retrieval.
#[derive(Debug, Default, Clone)]
pub struct CaseBase {
    cases: Vec<Case>,
    names: HashMap<String, u32>,
    blocks: HashMap<(u32, u32), Block>,
}

impl CaseBase {
    /// Builds the case base. Cases are put in id order first, so retrieval
    /// does not depend on the order they are given in.
    pub fn new(mut cases: Vec<Case>) -> CaseBase {
        cases.sort_by(|a, b| a.id.cmp(&b.id));
        let mut cb = CaseBase {
            cases: Vec::new(),
            names: HashMap::new(),
            blocks: HashMap::new(),
        };
        for c in cases {
            cb.push(c);
        }
        cb
    }

    fn code(&mut self, s: &str) -> u32 {
        let n = self.names.len() as u32;
        *self.names.entry(s.to_string()).or_insert(n)
    }

    fn query_code(&self, s: Option<&str>) -> u32 {
        s.map(|s| self.names.get(s).copied().unwrap_or(UNKNOWN_QUERY))
            .unwrap_or(UNKNOWN_QUERY)
    }

    fn push_columns(&mut self, c: &Case, index: usize) {
        let p = &c.problem;
        let key = (self.code(&p.class), self.code(&p.material_group));
        let material = self.code(&p.material);
        let hob_material = p
            .hob_material
            .as_deref()
            .map(|s| self.code(s))
            .unwrap_or(NONE);
        let coating = p
            .hob_coating
            .as_deref()
            .map(|s| self.code(s))
            .unwrap_or(NONE);
        let machine = p.machine.as_deref().map(|s| self.code(s)).unwrap_or(NONE);
        let b = self.blocks.entry(key).or_default();
        b.index.push(index as u32);
        b.ln_module.push(ln32(p.module_mm));
        b.ln_teeth.push(ln32(f64::from(p.teeth.max(1))));
        b.helix.push(p.helix_angle_deg as f32);
        b.ln_face.push(p.face_width_mm.map(ln32).unwrap_or(0.0));
        b.face_known
            .push(if p.face_width_mm.is_some() { 1.0 } else { 0.0 });
        b.material.push(material);
        b.hardness.push(p.hardness_hb.unwrap_or(0.0) as f32);
        b.hardness_known
            .push(if p.hardness_hb.is_some() { 1.0 } else { 0.0 });
        b.grade.push(f32::from(p.quality_grade));
        b.hob_material.push(hob_material);
        b.coating.push(coating);
        b.starts.push(p.hob_starts as f32);
        b.operation.push(match p.operation {
            Operation::Rough => 0,
            Operation::Finish => 1,
        });
        b.machine.push(machine);
        b.vc.push(c.solution.cutting_speed_m_min as f32);
    }

    /// Adds one case after the others (ties rank it after every earlier case;
    /// [`CaseBase::new`] restores id order).
    pub fn push(&mut self, case: Case) {
        let i = self.cases.len();
        self.push_columns(&case, i);
        self.cases.push(case);
    }

    /// The cases, in id order (indices of [`Hit`]).
    pub fn cases(&self) -> &[Case] {
        &self.cases
    }

    /// Number of cases.
    pub fn len(&self) -> usize {
        self.cases.len()
    }

    /// True when there are no cases.
    pub fn is_empty(&self) -> bool {
        self.cases.is_empty()
    }

    /// The `k` cases most similar to the job that pass the hard constraints,
    /// best first (ties by case id).
    pub fn retrieve(&self, q: &Problem, limits: &Limits, weights: &Weights, k: usize) -> Vec<Hit> {
        if k == 0 {
            return Vec::new();
        }
        let (Some(&class), Some(&group)) =
            (self.names.get(&q.class), self.names.get(&q.material_group))
        else {
            return Vec::new();
        };
        let Some(b) = self.blocks.get(&(class, group)) else {
            return Vec::new();
        };
        let job = self.encode(q, limits, weights);
        // The same summation order as in the loop, so an exact copy scores 1.
        let mut wsum = 0.0f32;
        for x in job.w {
            wsum += x;
        }
        let n = b.index.len();
        let mut top = TopK::new(k);
        let mut scores = [0f32; CHUNK];
        let mut start = 0;
        while start < n {
            let end = (start + CHUNK).min(n);
            let out = &mut scores[..end - start];
            score_chunk(&job, b, start, end, out);
            top.offer(out, &b.index[start..end]);
            start = end;
        }
        top.hits(wsum)
    }

    /// The job encoded as a row of a block (logarithms, codes, `f32`), with
    /// the weights of the features it knows and its speed limit.
    fn encode(&self, q: &Problem, limits: &Limits, weights: &Weights) -> Encoded {
        // Features the job does not know weigh nothing.
        let mut w = weights.0.map(|x| x as f32);
        if q.face_width_mm.is_none() {
            w[3] = 0.0;
        }
        if q.hardness_hb.is_none() {
            w[5] = 0.0;
        }
        if q.hob_material.is_none() {
            w[7] = 0.0;
        }
        if q.hob_coating.is_none() {
            w[8] = 0.0;
        }
        if q.machine.is_none() {
            w[11] = 0.0;
        }
        Encoded {
            w,
            qm: ln32(q.module_mm),
            qz: ln32(f64::from(q.teeth.max(1))),
            qh: q.helix_angle_deg as f32,
            qb: q.face_width_mm.map(ln32).unwrap_or(0.0),
            qmat: self.query_code(Some(&q.material)),
            qhb: q.hardness_hb.unwrap_or(0.0) as f32,
            qg: f32::from(q.quality_grade),
            qhm: self.query_code(q.hob_material.as_deref()),
            qc: self.query_code(q.hob_coating.as_deref()),
            qs: q.hob_starts as f32,
            qop: match q.operation {
                Operation::Rough => 0,
                Operation::Finish => 1,
            },
            qmc: self.query_code(q.machine.as_deref()),
            vmax: if limits.max_cutting_speed_m_min.is_finite() {
                limits.max_cutting_speed_m_min as f32
            } else {
                f32::INFINITY
            },
        }
    }
}

/// The job as retrieval compares it with a block's columns: the weights
/// (zero for a feature the job does not know), then per feature the job's
/// value in the column's form (`q` + the column), and the largest cutting
/// speed the machine can run with the job's hob.
#[derive(Debug, Clone, Copy)]
struct Encoded {
    w: [f32; NF],
    qm: f32,
    qz: f32,
    qh: f32,
    qb: f32,
    qmat: u32,
    qhb: f32,
    qg: f32,
    qhm: u32,
    qc: u32,
    qs: f32,
    qop: u32,
    qmc: u32,
    vmax: f32,
}

/// Scores the cases `start..end` of block `b` against the job into `out`:
/// the weighted sum of the local similarities (module docs), or −1 for a
/// case whose cutting speed the machine cannot run. A straight pass over
/// equal-length slices, so the compiler vectorises it.
fn score_chunk(job: &Encoded, b: &Block, start: usize, end: usize, out: &mut [f32]) {
    let Encoded {
        w,
        qm,
        qz,
        qh,
        qb,
        qmat,
        qhb,
        qg,
        qhm,
        qc,
        qs,
        qop,
        qmc,
        vmax,
    } = *job;
    let inv_ln2 = 1.0 / std::f32::consts::LN_2;
    let inv_ln3 = 1.0 / 3f32.ln();
    let len = end - start;
    let lm = &b.ln_module[start..end];
    let lz = &b.ln_teeth[start..end];
    let hx = &b.helix[start..end];
    let lf = &b.ln_face[start..end];
    let fk = &b.face_known[start..end];
    let mt = &b.material[start..end];
    let hb = &b.hardness[start..end];
    let hk = &b.hardness_known[start..end];
    let gr = &b.grade[start..end];
    let hm = &b.hob_material[start..end];
    let co = &b.coating[start..end];
    let st = &b.starts[start..end];
    let op = &b.operation[start..end];
    let mc = &b.machine[start..end];
    let vc = &b.vc[start..end];
    let out = &mut out[..len];
    let (lm, lz, hx, lf, fk, mt, hb, hk) = (
        &lm[..len],
        &lz[..len],
        &hx[..len],
        &lf[..len],
        &fk[..len],
        &mt[..len],
        &hb[..len],
        &hk[..len],
    );
    let (gr, hm, co, st, op, mc, vc) = (
        &gr[..len],
        &hm[..len],
        &co[..len],
        &st[..len],
        &op[..len],
        &mc[..len],
        &vc[..len],
    );
    for i in 0..len {
        let s0 = (1.0 - (qm - lm[i]).abs() * inv_ln2).max(0.0);
        let s1 = (1.0 - (qz - lz[i]).abs() * inv_ln3).max(0.0);
        let s2 = (1.0 - (qh - hx[i]).abs() * (1.0 / 20.0)).max(0.0);
        let s3r = (1.0 - (qb - lf[i]).abs() * inv_ln3).max(0.0);
        let s3 = fk[i] * s3r + (1.0 - fk[i]) * 0.5;
        let s4 = if qmat == mt[i] { 1.0 } else { 0.7 };
        let s5r = (1.0 - (qhb - hb[i]).abs() * (1.0 / 100.0)).max(0.0);
        let s5 = hk[i] * s5r + (1.0 - hk[i]) * 0.5;
        let s6 = (1.0 - (qg - gr[i]).abs() * (1.0 / 3.0)).max(0.0);
        let s7 = if qhm == hm[i] { 1.0 } else { 0.0 };
        let s8 = if qc == co[i] { 1.0 } else { 0.5 };
        let s9 = (1.0 - (qs - st[i]).abs() * 0.5).max(0.0);
        let s10 = if qop == op[i] { 1.0 } else { 0.0 };
        let s11 = if qmc == mc[i] { 1.0 } else { 0.6 };
        let mut num = 0.0f32;
        num += w[0] * s0;
        num += w[1] * s1;
        num += w[2] * s2;
        num += w[3] * s3;
        num += w[4] * s4;
        num += w[5] * s5;
        num += w[6] * s6;
        num += w[7] * s7;
        num += w[8] * s8;
        num += w[9] * s9;
        num += w[10] * s10;
        num += w[11] * s11;
        out[i] = if vc[i] <= vmax { num } else { -1.0 };
    }
}

/// The `k` best candidates so far, in a k-sized heap, and the score a new
/// one must beat once the heap is full.
struct TopK {
    k: usize,
    heap: BinaryHeap<Reverse<Ranked>>,
    threshold: f32,
}

impl TopK {
    fn new(k: usize) -> TopK {
        TopK {
            k,
            heap: BinaryHeap::with_capacity(k + 1),
            threshold: -1.0,
        }
    }

    /// Offers the scores of one chunk, `index` holding their cases' indices.
    /// Within a block indices grow with the scan, so a later case that only
    /// ties the current k-th best never displaces it: comparing with the
    /// k-th best score is exact.
    fn offer(&mut self, scores: &[f32], index: &[u32]) {
        let (k, heap) = (self.k, &mut self.heap);
        let mut threshold = self.threshold;
        for (i, &num) in scores.iter().enumerate() {
            if num < 0.0 || num <= threshold {
                continue;
            }
            let r = Ranked {
                score: num,
                index: index[i],
            };
            if heap.len() < k {
                heap.push(Reverse(r));
            } else {
                heap.pop();
                heap.push(Reverse(r));
            }
            if heap.len() == k {
                threshold = heap.peek().map(|Reverse(w)| w.score).unwrap_or(-1.0);
            }
        }
        self.threshold = threshold;
    }

    /// The candidates best first, their similarity the score over the sum
    /// of the weights `wsum` (at most 1).
    fn hits(self, wsum: f32) -> Vec<Hit> {
        let mut hits: Vec<Ranked> = self.heap.into_iter().map(|Reverse(r)| r).collect();
        hits.sort_by(|a, b| b.cmp(a));
        hits.into_iter()
            .map(|r| Hit {
                index: r.index as usize,
                similarity: if wsum > 0.0 {
                    f64::from(r.score / wsum).min(1.0)
                } else {
                    0.0
                },
            })
            .collect()
    }
}

/// A candidate in the top-k heap: higher score ranks higher, then lower index
/// (earlier case id).
#[derive(Debug, Clone, Copy)]
struct Ranked {
    score: f32,
    index: u32,
}

impl PartialEq for Ranked {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Ranked {}
impl PartialOrd for Ranked {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Ranked {
    fn cmp(&self, o: &Self) -> Ordering {
        self.score
            .total_cmp(&o.score)
            .then_with(|| o.index.cmp(&self.index))
    }
}

/// The adapted proposal.
#[derive(Debug, Clone, PartialEq)]
pub struct Adapted {
    /// Cutting speed, m/min (kept from the cases).
    pub cutting_speed_m_min: f64,
    /// Feed per revolution, mm/rev (scaled with the module); `None` for a
    /// finishing job when every case is a rough cut: a roughing feed is
    /// never proposed for finishing (seed 000's rough bevel cut, 7.9 mm/rev,
    /// proposed for a grade 7 finish, was the bug).
    pub feed_mm_per_rev: Option<f64>,
    /// Radial feed rate, mm/min (scaled with the module), when the cases have it.
    pub radial_feed_mm_min: Option<f64>,
    /// Number of cuts (most similar case).
    pub cuts: u32,
    /// Allowance, mm (most similar case), when it has one.
    pub allowance_mm: Option<f64>,
    /// Cutting mode (most similar case), when it has one.
    pub cut_mode: Option<CutMode>,
    /// Confidence, 0–1.
    pub confidence: f64,
}

/// Adapts the retrieved cases' solutions to the job (see the module docs).
/// `None` when no case has a positive similarity.
pub fn adapt(cb: &CaseBase, hits: &[Hit], q: &Problem) -> Option<Adapted> {
    let used: Vec<(&Case, f64)> = hits
        .iter()
        .filter(|h| h.similarity > 0.0)
        .map(|h| (&cb.cases[h.index], h.similarity))
        .collect();
    let (best, best_sim) = *used.first()?;
    let ssum: f64 = used.iter().map(|(_, s)| s).sum();
    let mean = |f: &dyn Fn(&Case) -> f64| used.iter().map(|(c, s)| s * f(c)).sum::<f64>() / ssum;
    let scale = |c: &Case| (q.module_mm / c.problem.module_mm).sqrt();
    let with_radial: Vec<&(&Case, f64)> = used
        .iter()
        .filter(|(c, _)| c.solution.radial_feed_mm_min.is_some())
        .collect();
    let radial = if with_radial.is_empty() {
        None
    } else {
        let s: f64 = with_radial.iter().map(|(_, s)| s).sum();
        Some(
            with_radial
                .iter()
                .map(|(c, w)| w * c.solution.radial_feed_mm_min.unwrap_or(0.0) * scale(c))
                .sum::<f64>()
                / s,
        )
    };
    let finishing: Vec<&(&Case, f64)> = used
        .iter()
        .filter(|(c, _)| c.problem.operation == Operation::Finish)
        .collect();
    let feed = match q.operation {
        Operation::Finish if finishing.is_empty() => None,
        Operation::Finish => {
            let s: f64 = finishing.iter().map(|(_, s)| s).sum();
            Some(
                finishing
                    .iter()
                    .map(|(c, w)| w * c.solution.feed_mm_per_rev * scale(c))
                    .sum::<f64>()
                    / s,
            )
        }
        Operation::Rough => Some(mean(&|c| c.solution.feed_mm_per_rev * scale(c))),
    };
    Some(Adapted {
        cutting_speed_m_min: mean(&|c| c.solution.cutting_speed_m_min),
        feed_mm_per_rev: feed,
        radial_feed_mm_min: radial,
        cuts: best.solution.cuts.max(1),
        allowance_mm: best.solution.allowance_mm,
        cut_mode: best.solution.cut_mode,
        confidence: (best_sim * mean(&|c| c.confidence)).clamp(0.0, 1.0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn problem() -> Problem {
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

    fn case(id: &str, problem: Problem, vc: f64, fa: f64) -> Case {
        Case {
            id: id.into(),
            problem,
            solution: Solution {
                cutting_speed_m_min: vc,
                feed_mm_per_rev: fa,
                hob_od_mm: Some(80.0),
                radial_feed_mm_min: None,
                cuts: 1,
                allowance_mm: None,
                cut_mode: None,
            },
            confidence: 0.8,
            provenance: "test".into(),
        }
    }

    #[test]
    fn local_similarities_follow_the_documented_functions() {
        let q = problem();
        let mut c = q.clone();
        c.module_mm = 6.0; // a factor 2 → module similarity 0
        let cb = CaseBase::new(vec![case("A", c, 90.0, 2.0)]);
        let mut w = Weights([0.0; NF]);
        w.0[0] = 1.0;
        w.0[4] = 1.0; // same material → 1
        let hits = cb.retrieve(&q, &Limits::default(), &w, 3);
        approx::assert_abs_diff_eq!(hits[0].similarity, 0.5, epsilon = 1e-6);
        // Module 3 vs 6 only, helix 15 vs 5: (0 + (1 − 10/20)) / 2.
        let mut c = q.clone();
        c.helix_angle_deg = 5.0;
        let cb = CaseBase::new(vec![case("B", c, 90.0, 2.0)]);
        let mut w = Weights([0.0; NF]);
        w.0[2] = 1.0;
        let hits = cb.retrieve(&q, &Limits::default(), &w, 3);
        approx::assert_abs_diff_eq!(hits[0].similarity, 0.5, epsilon = 1e-6);
    }

    #[test]
    fn hard_constraints_filter_class_group_and_machine_speed() {
        let q = problem();
        let mut other_group = q.clone();
        other_group.material_group = "cast_iron".into();
        let mut other_class = q.clone();
        other_class.class = "conical".into();
        let cb = CaseBase::new(vec![
            case("FAST", q.clone(), 400.0, 2.0),
            case("GROUP", other_group, 90.0, 2.0),
            case("CLASS", other_class, 90.0, 2.0),
            case("OK", q.clone(), 90.0, 2.0),
        ]);
        let limits = Limits {
            max_cutting_speed_m_min: 300.0,
        };
        let hits = cb.retrieve(&q, &limits, &Weights::default(), 10);
        let ids: Vec<&str> = hits
            .iter()
            .map(|h| cb.cases()[h.index].id.as_str())
            .collect();
        assert_eq!(ids, ["OK"]);
    }

    #[test]
    fn adaptation_keeps_cutting_speed_and_scales_feed_with_module() {
        let q = problem();
        let mut c = q.clone();
        c.module_mm = 2.0;
        let cb = CaseBase::new(vec![case("M2", c, 90.0, 2.0)]);
        let hits = cb.retrieve(&q, &Limits::default(), &Weights::default(), 3);
        let a = adapt(&cb, &hits, &q).unwrap();
        assert_eq!(a.cutting_speed_m_min, 90.0);
        approx::assert_abs_diff_eq!(
            a.feed_mm_per_rev.unwrap(),
            2.0 * 1.5f64.sqrt(),
            epsilon = 1e-12
        );
        approx::assert_abs_diff_eq!(a.confidence, hits[0].similarity * 0.8, epsilon = 1e-12);
    }

    #[test]
    fn unknown_job_features_weigh_nothing() {
        let mut q = problem();
        q.machine = None;
        q.hardness_hb = None;
        let mut c = q.clone();
        c.machine = Some("H02".into());
        c.hardness_hb = Some(300.0);
        let cb = CaseBase::new(vec![case("A", c, 90.0, 2.0)]);
        let hits = cb.retrieve(&q, &Limits::default(), &Weights::default(), 1);
        assert_eq!(hits[0].similarity, 1.0);
    }
}
