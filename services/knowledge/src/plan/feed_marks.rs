//! The feed a drawing's accuracy class allows: the knowledge base's bound on
//! the axial feed by the depth of the feed marks it leaves on the flanks.
//!
//! The hob's flanks are surfaces of revolution about its axis. Along the feed
//! (the hob's turning direction) such a flank, at distance ρ from the axis
//! and inclined by the normal pressure angle αn, curves by sin αn/ρ; two of
//! its cuts one feed f apart leave a cusp of depth
//!
//! ```text
//! δn ≈ f²·sin αn / (8·ρ)
//! ```
//!
//! normal to the flank, deepest where ρ is least: where the hob cuts the
//! gear's tip, a whole tooth height h = (2·ha* + c*)·mn inside the hob's tip
//! radius. The marks show in two of the graded items:
//!
//! - **Helix form ffβ.** Along the face width the cusps are the helix trace's
//!   form deviation, read along the transverse base tangent as δn / cos βb.
//! - **Runout Fr.** Each gap is cut one feed per table turn lower, but the
//!   gaps one after another are a fraction of a feed apart, so a transverse
//!   section meets each gap at another phase of its cusps. A ball between
//!   two flanks that both stand δn proud rises by δn / sin αn, so over the
//!   teeth the ball's height varies by up to f² / (8·ρ).
//!
//! The bound keeps each within a share ([`FEED_MARK_SHARE`]) of its
//! tolerance in the drawing's class; the rest is left to the machine, the
//! hob and the clamping. Solved for f, the smaller of
//!
//! ```text
//! f ≤ √(8·ρ_min·cos βb·s·ffβT / sin αn)      f ≤ √(8·ρ_min·s·FrT)
//! ```
//!
//! The bound holds the feed of the finishing cut: a single cut's feed, or
//! the finishing feed of several cuts (the rough cuts keep theirs). The
//! virtual run of the program (the template service's simulation) measures
//! the gear the feed leaves and is the independent check of this bound.

use std::collections::BTreeMap;

use gearcam_gearmeasure::iso1328::{self, Class, GearData, Item};
use gearcam_proto::plan::Proposal;
use gearcam_proto::{GearClass, GearSpec, HobData, Operation, ProcessOverrides, Source, Sourced};

/// The share of the ffβ and Fr tolerances the feed marks may take.
pub const FEED_MARK_SHARE: f64 = 0.5;
/// The plan value of the feed (of every cut, or of the rough cuts).
pub const FEED: &str = "feed_mm_per_rev";
/// The plan value of the finishing cut's feed when there are several cuts.
pub const FINISH_FEED: &str = "finish_feed_mm_per_rev";

/// The largest axial feed per workpiece revolution, mm/rev, whose feed marks
/// stay within [`FEED_MARK_SHARE`] of the ffβ and Fr tolerances of the
/// drawing's class; `None` where the bound does not apply: a worm wheel
/// (measured in its throat plane alone, fed radially or tangentially), a
/// part of several gears (each with its own drawing; one feed bound would
/// need them all), a class or gear outside ISO 1328-1's scope, or a hob
/// too small for the tooth. Along a cone of angle δ the hob moves fa/cos δ
/// along the cone line per revolution, so the cusps are those of that feed:
/// the bound is cos δ times a cylinder's.
pub fn max_feed_mm_per_rev(gear: &GearSpec, class: GearClass, hob: &HobData) -> Option<f64> {
    if !matches!(
        class,
        GearClass::Cylindrical | GearClass::Crowned | GearClass::Conical
    ) {
        return None;
    }
    let data = GearData::new(
        gear.teeth,
        gear.module_mm,
        gear.helix_angle_deg,
        gear.face_width_mm,
    )
    .ok()?;
    let class = Class::new(gear.quality_grade).ok()?;
    let tolerance_mm = |item| iso1328::tolerance_um(&data, item, class) / 1000.0;
    let whole_depth = (2.0 * gear.addendum_coef + gear.clearance_coef) * gear.module_mm;
    let rho_min = hob.od_mm / 2.0 - whole_depth;
    let alpha_n = gear.pressure_angle_deg.to_radians();
    // sin βb = sin β·cos αn.
    let beta_b = (gear.helix_angle_deg.to_radians().sin() * alpha_n.cos()).asin();
    let s = FEED_MARK_SHARE;
    let helix = 8.0 * rho_min * beta_b.cos() * s * tolerance_mm(Item::HelixForm) / alpha_n.sin();
    let runout = 8.0 * rho_min * s * tolerance_mm(Item::Runout);
    let along_cone = gear
        .cone
        .as_ref()
        .map_or(1.0, |c| c.angle_deg.to_radians().cos());
    (rho_min > 0.0 && alpha_n > 0.0).then(|| helix.min(runout).sqrt() * along_cone)
}

/// Holds the finishing feed to `bound` ([`max_feed_mm_per_rev`], `None`
/// where it does not apply): a single cut's feed, or the finishing feed of
/// several cuts (the knowledge base's proposal; the finish otherwise takes
/// the feed), where the feed proposed or decided is faster. The proposal
/// takes the bound (source `grade`); the decided value takes it unless the
/// job gave its own, which stays (the planner's decision), the bound shown
/// beside it as proposed. A rough job is not held.
pub fn hold_finishing_feed(
    bound: Option<f64>,
    proposal: &mut Proposal,
    values: &mut BTreeMap<String, Sourced>,
    process: &ProcessOverrides,
) {
    let Some(bound) = bound else { return };
    if process.operation == Some(Operation::Rough) {
        return;
    }
    let grade = Sourced {
        value: bound,
        source: Source::Grade,
    };
    let several = values.get("cuts").is_some_and(|c| c.value > 1.0);
    let key = if several { FINISH_FEED } else { FEED };
    // The finishing feed as proposed, and as decided: several cuts
    // finish at the job's finishing feed, else at the feed.
    let proposed = proposal.values.get(FEED).map(|f| f.value);
    let decided = match (several, process.finish_feed_mm_per_rev) {
        (true, Some(f)) => Some(Sourced {
            value: f,
            source: Source::Job,
        }),
        // The finish takes the feed by default: whoever gave the feed
        // did not decide the finishing feed.
        (true, None) => values.get(FEED).map(|f| Sourced {
            source: Source::Default,
            ..*f
        }),
        (false, _) => values.get(FEED).copied(),
    };
    if proposed.is_some_and(|f| f > bound) || decided.is_some_and(|d| d.value > bound) {
        proposal.values.insert(key.into(), grade);
    }
    if decided.is_some_and(|d| d.value > bound && d.source != Source::Job) {
        values.insert(key.into(), grade);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The gear and hob the knowledge base plans for a spur gear of module
    /// 3, 25 teeth, b 30 (the bundled `spur_840d` example) of `grade`.
    fn spur(grade: u8) -> (GearSpec, HobData) {
        let conn = crate::db::open_in_memory().unwrap();
        let spec: gearcam_proto::JobSpec = serde_json::from_value(serde_json::json!({
            "job": {"machine": "H01", "part_number": "P-1"},
            "gear": {"module_mm": 3.0, "teeth": 25, "face_width_mm": 30.0,
                     "material": "20CrMnTi", "quality_grade": grade,
                     "fixture_height_mm": 100.0},
            "hob": {"id": "HOB-M3-80"},
        }))
        .unwrap();
        let req = gearcam_proto::JobRequest {
            job_id: gearcam_proto::JobId::new("J1").unwrap(),
            submitted_at_ms: 0,
            submitted_by: "test".into(),
            spec,
        };
        let plan = super::super::plan(&conn, &req).unwrap();
        (plan.gear, plan.hob)
    }

    /// Against values worked by hand from ISO 1328-1's formulas. Spur,
    /// z 25, mn 3, b 30, class 4, hob Ø80: ρ = 40 − 2.25·3 = 33.25 mm;
    /// FpT = 0.002·75 + 0.55·√75 + 0.7·3 + 12 = 19.01, FrT = 0.9·19.01/√2 =
    /// 12.10 → 12 µm; ffβT = (0.07·√75 + 0.45·√30 + 4)/√2 = 5.00 → 5.0 µm.
    /// The runout sets it: √(8·33.25·0.5·0.012) = 1.263 mm/rev (the helix
    /// would allow √(8·33.25·0.5·0.005/sin 20°) = 1.394). Helical, z 200,
    /// β 20°, class 5: d = 638.5, FrT = 0.9·(1.277 + 0.55·√638.5 + 2.1 +
    /// 12) = 26.35 → 26 µm, ffβT = 0.07·√638.5 + 0.45·√30 + 4 = 8.23 → 8.0
    /// µm, βb = asin(sin 20°·cos 20°) = 18.75°: the helix sets it,
    /// √(8·33.25·cos 18.75°·0.5·0.008/sin 20°) = 1.716 mm/rev (the runout
    /// would allow 1.860).
    #[test]
    fn the_bound_is_the_closed_form_worked_by_hand() {
        let (gear, hob) = spur(4);
        assert_eq!(hob.od_mm, 80.0);
        let f = max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &hob).unwrap();
        assert!(
            (f - (8.0f64 * 33.25 * 0.5 * 0.012).sqrt()).abs() < 1e-9,
            "{f}"
        );
        assert!((f - 1.263).abs() < 1e-3, "{f}");
        let helical = GearSpec {
            teeth: 200,
            helix_angle_deg: 20.0,
            helix_hand: Some(gearcam_proto::Hand::Right),
            quality_grade: 5,
            ..gear.clone()
        };
        let f = max_feed_mm_per_rev(&helical, GearClass::Cylindrical, &hob).unwrap();
        let beta_b = (20f64.to_radians().sin() * 20f64.to_radians().cos()).asin();
        let want = (8.0 * 33.25 * beta_b.cos() * 0.5 * 0.008 / 20f64.to_radians().sin()).sqrt();
        assert!(
            (f - want).abs() < 1e-9 && (f - 1.716).abs() < 1e-3,
            "{f} {want}"
        );
        // Finer classes and smaller hobs allow less feed.
        let f7 = max_feed_mm_per_rev(&spur(7).0, GearClass::Cylindrical, &hob).unwrap();
        let small_hob = HobData {
            od_mm: 60.0,
            ..hob.clone()
        };
        let small = max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &small_hob).unwrap();
        assert!(f7 > 1.263 && small < 1.263, "{f7} {small}");
    }

    /// No bound where the helix is not measured across the face, the gear
    /// is outside the standard or the hob cannot cut the tooth.
    #[test]
    fn no_bound_outside_its_scope() {
        let (gear, h) = spur(4);
        assert!(max_feed_mm_per_rev(&gear, GearClass::Crowned, &h).is_some());
        // Along a cone of 30° the hob travels 1/cos 30° further per
        // revolution: the same cusps at cos 30° of the feed.
        let cone = GearSpec {
            cone: Some(gearcam_proto::ConeSpec {
                angle_deg: 30.0,
                large_end: Default::default(),
            }),
            ..gear.clone()
        };
        let (plain, conical) = (
            max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &h).unwrap(),
            max_feed_mm_per_rev(&cone, GearClass::Conical, &h).unwrap(),
        );
        assert!((conical - plain * 30f64.to_radians().cos()).abs() < 1e-12);
        for class in [
            GearClass::WormWheel,
            GearClass::MultiGear,
            GearClass::CurvedTooth,
        ] {
            assert_eq!(max_feed_mm_per_rev(&gear, class, &h), None, "{class:?}");
        }
        let coarse = GearSpec {
            quality_grade: 12,
            ..gear.clone()
        };
        assert_eq!(
            max_feed_mm_per_rev(&coarse, GearClass::Cylindrical, &h),
            None
        );
        let tiny = GearSpec {
            teeth: 3,
            ..gear.clone()
        };
        assert_eq!(max_feed_mm_per_rev(&tiny, GearClass::Cylindrical, &h), None);
        let small = HobData {
            od_mm: 12.0,
            ..h.clone()
        };
        assert_eq!(
            max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &small),
            None
        );
    }

    fn sourced(value: f64, source: Source) -> Sourced {
        Sourced { value, source }
    }

    /// What the bound holds, for a bound of 1 mm/rev: `cuts` cuts, the
    /// case's feed `case`, the job's feed and finishing feed and operation.
    fn held(
        cuts: f64,
        case: f64,
        job: Option<f64>,
        job_finish: Option<f64>,
        rough: bool,
    ) -> (BTreeMap<String, Sourced>, BTreeMap<String, Sourced>) {
        let mut proposal = Proposal::default();
        proposal
            .values
            .insert(FEED.into(), sourced(case, Source::Case));
        let mut values = BTreeMap::new();
        values.insert("cuts".into(), sourced(cuts, Source::Job));
        let feed = job.map_or(sourced(case, Source::Case), |f| sourced(f, Source::Job));
        values.insert(FEED.into(), feed);
        let process = ProcessOverrides {
            finish_feed_mm_per_rev: job_finish,
            operation: rough.then_some(Operation::Rough),
            ..ProcessOverrides::default()
        };
        hold_finishing_feed(Some(1.0), &mut proposal, &mut values, &process);
        (proposal.values, values)
    }

    /// A single cut's feed and a finishing feed are held; the rough cuts'
    /// feed, a rough job and the job's own values are not.
    #[test]
    fn the_finishing_feed_is_held_and_the_planners_values_stay() {
        let grade = sourced(1.0, Source::Grade);
        // One cut at the case's 2 mm/rev: proposed and decided at the bound.
        let (p, v) = held(1.0, 2.0, None, None, false);
        assert_eq!((p[FEED], v[FEED]), (grade, grade));
        // Below the bound: nothing changes.
        let (p, v) = held(1.0, 0.8, None, None, false);
        assert_eq!(
            (p[FEED].source, v[FEED].source),
            (Source::Case, Source::Case)
        );
        // The job's own 2 mm/rev stays; the bound is proposed beside it.
        let (p, v) = held(1.0, 2.0, Some(2.0), None, false);
        assert_eq!((p[FEED], v[FEED]), (grade, sourced(2.0, Source::Job)));
        // Two cuts: the rough feed stays, the finishing feed is held, even
        // when the job gave the rough feed (the finish only took it by default).
        for job in [None, Some(2.0)] {
            let (p, v) = held(2.0, 2.0, job, None, false);
            assert_eq!(p[FEED].source, Source::Case);
            assert_ne!(v[FEED].source, Source::Grade);
            assert_eq!((p[FINISH_FEED], v[FINISH_FEED]), (grade, grade));
        }
        // The job's own finishing feed stays (the model reads it), proposed beside it.
        let (p, v) = held(2.0, 0.8, None, Some(1.5), false);
        assert_eq!(p[FINISH_FEED], grade);
        assert!(!v.contains_key(FINISH_FEED));
        // A rough job is not held.
        let (p, v) = held(1.0, 2.0, None, None, true);
        assert_eq!(
            (p[FEED].source, v[FEED].source),
            (Source::Case, Source::Case)
        );
    }
}
