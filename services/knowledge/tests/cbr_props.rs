//! Properties of case-based reasoning: an exact copy of a job as a
//! case ranks first with similarity 1; ranking does not depend on the order
//! of the cases; the job's overrides always win.

use gearcam_knowledge::cbr::{Case, CaseBase, Limits, Operation, Problem, Solution, Weights};
use gearcam_knowledge::{db, plan};
use gearcam_proto::{JobRequest, JobSpec, Source};
use proptest::prelude::*;
use proptest::sample::select;

fn problem() -> impl Strategy<Value = Problem> {
    (
        (
            select(vec!["cylindrical", "conical"]),
            select(vec!["20CrMnTi", "16MnCr5", "42CrMo4"]),
            select(vec!["case_hardening_steel", "quenched_tempered_steel"]),
            proptest::option::of(120.0..320.0f64),
            0.5..10.0f64,
            5u32..150,
            0.0..40.0f64,
        ),
        (
            proptest::option::of(5.0..120.0f64),
            4u8..12,
            proptest::option::of(select(vec!["HSS", "carbide"])),
            proptest::option::of(select(vec!["none", "TiN", "AlCrN"])),
            1u32..4,
            any::<bool>(),
            proptest::option::of(select(vec!["H01", "H02"])),
        ),
    )
        .prop_map(
            |((class, material, group, hb, m, z, beta), (b, q, hm, hc, z0, rough, mc))| Problem {
                class: class.into(),
                material: material.into(),
                material_group: group.into(),
                hardness_hb: hb,
                module_mm: m,
                teeth: z,
                helix_angle_deg: beta,
                face_width_mm: b,
                quality_grade: q,
                hob_material: hm.map(Into::into),
                hob_coating: hc.map(Into::into),
                hob_starts: z0,
                operation: if rough {
                    Operation::Rough
                } else {
                    Operation::Finish
                },
                machine: mc.map(Into::into),
            },
        )
}

fn case(id: String, problem: Problem, vc: f64) -> Case {
    Case {
        id,
        problem,
        solution: Solution {
            cutting_speed_m_min: vc,
            feed_mm_per_rev: 2.0,
            hob_od_mm: None,
            radial_feed_mm_min: None,
            cuts: 1,
            allowance_mm: None,
            cut_mode: None,
        },
        confidence: 0.5,
        provenance: "property test".into(),
    }
}

fn cases() -> impl Strategy<Value = Vec<Case>> {
    proptest::collection::vec((problem(), 40.0..200.0f64), 0..40).prop_map(|v| {
        v.into_iter()
            .enumerate()
            .map(|(i, (p, vc))| case(format!("C{i:03}"), p, vc))
            .collect()
    })
}

fn weights() -> impl Strategy<Value = Weights> {
    proptest::array::uniform12(0.0..5.0f64).prop_map(|mut w| {
        w[0] += 0.1; // at least one feature counts
        Weights(w)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn an_exact_copy_of_the_job_ranks_first_with_similarity_one(
        job in problem(), mut others in cases(), w in weights(), at in 0usize..40,
    ) {
        let at = at.min(others.len());
        others.insert(at, case("COPY".into(), job.clone(), 100.0));
        let cb = CaseBase::new(others);
        let hits = cb.retrieve(&job, &Limits::default(), &w, 3);
        prop_assert!(!hits.is_empty());
        prop_assert_eq!(hits[0].similarity, 1.0);
        // Only another exact match could tie it; the copy is among the hits at 1.
        let copy = hits.iter().find(|h| cb.cases()[h.index].id == "COPY");
        prop_assert!(copy.is_some_and(|h| h.similarity == 1.0), "{:?}", hits);
        for h in &hits {
            prop_assert!((0.0..=1.0).contains(&h.similarity));
        }
    }

    #[test]
    fn ranking_is_invariant_to_the_order_of_the_cases(
        job in problem(), cs in cases(), w in weights(), seed in any::<u64>(), k in 1usize..8,
    ) {
        let mut shuffled = cs.clone();
        // Fisher–Yates with a small xorshift, driven by the seed.
        let mut s = seed | 1;
        for i in (1..shuffled.len()).rev() {
            s ^= s << 13; s ^= s >> 7; s ^= s << 17;
            shuffled.swap(i, (s % (i as u64 + 1)) as usize);
        }
        let limits = Limits { max_cutting_speed_m_min: 150.0 };
        let a = CaseBase::new(cs);
        let b = CaseBase::new(shuffled);
        let ra: Vec<(String, f64)> = a.retrieve(&job, &limits, &w, k).iter()
            .map(|h| (a.cases()[h.index].id.clone(), h.similarity)).collect();
        let rb: Vec<(String, f64)> = b.retrieve(&job, &limits, &w, k).iter()
            .map(|h| (b.cases()[h.index].id.clone(), h.similarity)).collect();
        prop_assert_eq!(ra, rb);
    }
}

fn request(process: serde_json::Value) -> JobRequest {
    let spec: JobSpec = serde_json::from_value(serde_json::json!({
        "job": {"machine": "H01", "part_number": "PROP", "quantity": 10},
        "gear": {"module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0,
                 "material": "20CrMnTi", "quality_grade": 7, "fixture_height_mm": 100.0},
        "process": process,
    }))
    .unwrap();
    JobRequest {
        job_id: gearcam_proto::JobId::new("PROP").unwrap(),
        submitted_at_ms: 0,
        submitted_by: "proptest".into(),
        spec,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn overrides_always_win(
        vc in proptest::option::of(10.0..400.0f64),
        fa in proptest::option::of(0.1..8.0f64),
        cuts in proptest::option::of(1u32..4),
        climb in proptest::option::of(any::<bool>()),
        safety in proptest::option::of(0.0..10.0f64),
        depth in proptest::option::of(1.0..7.0f64),
    ) {
        let conn = db::open_in_memory().unwrap();
        let mut p = serde_json::Map::new();
        let mut given: Vec<(&str, f64)> = Vec::new();
        if let Some(v) = vc { p.insert("cutting_speed_m_min".into(), v.into()); given.push(("cutting_speed_m_min", v)); }
        if let Some(v) = fa { p.insert("feed_mm_per_rev".into(), v.into()); given.push(("feed_mm_per_rev", v)); }
        if let Some(v) = cuts { p.insert("cuts".into(), v.into()); given.push(("cuts", f64::from(v))); }
        if let Some(c) = climb {
            p.insert("cut_mode".into(), (if c { "climb" } else { "conventional" }).into());
            given.push(("cut_mode_climb", f64::from(u8::from(c))));
        }
        if let Some(v) = safety { p.insert("safety_mm".into(), v.into()); given.push(("safety_mm", v)); }
        if let Some(v) = depth { p.insert("depth_mm".into(), v.into()); given.push(("depth_mm", v)); }
        let plan = plan::plan(&conn, &request(serde_json::Value::Object(p))).unwrap();
        for (name, v) in &given {
            prop_assert_eq!(plan.values[*name].value, *v, "{}", name);
            prop_assert_eq!(plan.values[*name].source, Source::Job, "{}", name);
            if *name != "depth_mm" {
                prop_assert!(plan.proposal.overridden.iter().any(|n| n == name), "{}", name);
                prop_assert!(plan.proposal.values[*name].source != Source::Job);
            }
        }
        if let Some(v) = vc { prop_assert_eq!(plan.process.cutting_speed_m_min, v); }
        if let Some(v) = fa { prop_assert_eq!(plan.process.feed_mm_per_rev, v); }
        if let Some(v) = cuts { prop_assert_eq!(plan.process.cuts, v); }
        if let Some(v) = safety { prop_assert_eq!(plan.process.safety_mm, v); }
        prop_assert_eq!(plan.process.depth_mm, depth);
        // Values the job did not give are never marked as the job's.
        for (name, v) in &plan.values {
            if !given.iter().any(|(n, _)| n == name) {
                prop_assert!(v.source != Source::Job, "{}", name);
            }
        }
    }
}
