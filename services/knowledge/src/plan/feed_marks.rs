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
//! The virtual run of the program (the template service's simulation)
//! measures the gear the feed leaves and is the independent check of this
//! bound.

use gearcam_gearmeasure::iso1328::{self, Class, GearData, Item};
use gearcam_proto::{GearClass, GearSpec, HobData};

/// The share of the ffβ tolerance the feed marks may take.
pub const FEED_MARK_SHARE: f64 = 0.5;

/// The largest axial feed per workpiece revolution, mm/rev, whose feed marks
/// stay within [`FEED_MARK_SHARE`] of the ffβ and Fr tolerances of the
/// drawing's class; `None` where the bound does not apply: a gear whose helix is not
/// measured across the face (a worm wheel, a part of several gears, a
/// conical gear), a class or gear outside ISO 1328-1's scope, or a hob too
/// small for the tooth.
pub fn max_feed_mm_per_rev(gear: &GearSpec, class: GearClass, hob: &HobData) -> Option<f64> {
    if !matches!(class, GearClass::Cylindrical | GearClass::Crowned) {
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
    let beta = gear.helix_angle_deg.to_radians();
    let alpha_t = (alpha_n.tan() / beta.cos()).atan();
    let beta_b = (beta.tan() * alpha_t.cos()).atan();
    let s = FEED_MARK_SHARE;
    let helix = 8.0 * rho_min * beta_b.cos() * s * tolerance_mm(Item::HelixForm) / alpha_n.sin();
    let runout = 8.0 * rho_min * s * tolerance_mm(Item::Runout);
    (rho_min > 0.0 && alpha_n > 0.0).then(|| helix.min(runout).sqrt())
}

/// What the feed marks of a feed `f_mm` cut at the hob radius `rho_mm` add
/// to ffβ and to Fr, µm (the module docs): the inverse of the bound.
pub fn feed_mark_um(f_mm: f64, rho_mm: f64, alpha_n_deg: f64, beta_b_rad: f64) -> (f64, f64) {
    let runout = 1000.0 * f_mm * f_mm / (8.0 * rho_mm);
    let helix = runout * alpha_n_deg.to_radians().sin() / beta_b_rad.cos();
    (helix, runout)
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

    /// At the bound the marks take the share of one tolerance and no more
    /// of the other, and finer classes and smaller hobs allow less feed.
    #[test]
    fn the_bound_leaves_marks_of_the_share_of_the_tolerance() {
        let (gear, hob) = spur(4);
        assert_eq!(hob.od_mm, 80.0);
        let f = max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &hob).unwrap();
        let rho = 40.0 - 2.25 * 3.0;
        let data = GearData::new(25, 3.0, 0.0, 30.0).unwrap();
        let tol = |item| iso1328::tolerance_um(&data, item, Class::new(4).unwrap());
        let (helix, runout) = feed_mark_um(f, rho, 20.0, 0.0);
        let (h, r) = (
            helix / (FEED_MARK_SHARE * tol(Item::HelixForm)),
            runout / (FEED_MARK_SHARE * tol(Item::Runout)),
        );
        assert!((h.max(r) - 1.0).abs() < 1e-9 && h.min(r) <= 1.0, "{h} {r}");
        let f7 = max_feed_mm_per_rev(&spur(7).0, GearClass::Cylindrical, &hob).unwrap();
        let small_hob = HobData {
            od_mm: 60.0,
            ..hob.clone()
        };
        let small = max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &small_hob).unwrap();
        assert!(f7 > f && small < f, "{f7} {f} {small}");
    }

    /// No bound where the helix is not measured across the face or the gear
    /// is outside the standard.
    #[test]
    fn no_bound_outside_its_scope() {
        let (gear, h) = spur(4);
        assert!(max_feed_mm_per_rev(&gear, GearClass::Cylindrical, &h).is_some());
        assert_eq!(max_feed_mm_per_rev(&gear, GearClass::WormWheel, &h), None);
        assert_eq!(max_feed_mm_per_rev(&gear, GearClass::MultiGear, &h), None);
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
    }
}
