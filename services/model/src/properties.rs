//! Property tests over wide random valid inputs, cylindrical,
//! conical and crowned gears: positions ordered,
//! ΔH′ at least the spur approach length when γ = 0, speeds and feeds
//! positive and within the machine's limits or reported, results finite,
//! crowning chords within their tolerance, span steps of one base pitch.

use std::f64::consts::PI;

use gearcam_proto::{
    Code, ConeSpec, CrowningShape, CrowningSpec, CutMode, Hand, Infeed, Kinematics, LargeEnd,
    MoveKind, ProcessPlan,
};
use proptest::prelude::*;

use crate::fixtures;
use crate::hobbing::Clearance;

/// A valid cylindrical job: module, teeth, helix, face width, hob starts and
/// diameter, cut mode, cuts, infeed, feed and cutting speed from wide ranges;
/// the hob matches the gear's base pitch and its lead angle follows from its
/// diameter (d0 = da0 − 2.5·mn0, docs/reference.md#check-4-hob-outside-diameter with equality).
fn plans() -> impl Strategy<Value = ProcessPlan> {
    (
        (
            0.5f64..8.0,
            6u32..160,
            0.0f64..40.0,
            any::<bool>(),
            4.0f64..120.0,
        ),
        (1u32..4, 18.0f64..45.0, 20.0f64..250.0),
        (
            any::<bool>(),
            1u32..5,
            any::<bool>(),
            0.3f64..4.0,
            20.0f64..250.0,
        ),
        (0.0f64..120.0, 0.0f64..5.0, 0u8..4, 0.0f64..1.0),
    )
        .prop_map(
            |(
                (mn, z, beta, right, b),
                (z0, od_per_mn, hob_len_per_mn),
                (climb, cuts, radial_axial, fa, vc),
                (h_fixture, safety, class, shape_param),
            )| {
                let mut g = fixtures::gear();
                g.module_mm = mn;
                g.teeth = z;
                g.helix_angle_deg = if beta < 1.0 { 0.0 } else { beta };
                g.helix_hand =
                    (beta >= 1.0).then_some(if right { Hand::Right } else { Hand::Left });
                g.face_width_mm = b;
                g.fixture_height_mm = h_fixture;
                let mut plan = fixtures::plan_with(g);
                let od = od_per_mn * mn;
                let d0 = od - 2.5 * mn;
                plan.hob.module_mm = mn;
                plan.hob.starts = z0;
                plan.hob.od_mm = od;
                plan.hob.lead_angle_deg = (f64::from(z0) * mn / d0).asin().to_degrees();
                plan.hob.length_mm = hob_len_per_mn * mn;
                plan.process.cut_mode = if climb {
                    CutMode::Climb
                } else {
                    CutMode::Conventional
                };
                plan.process.cuts = cuts;
                plan.process.feed_mm_per_rev = fa;
                plan.process.cutting_speed_m_min = vc;
                plan.process.safety_mm = safety;
                // 0: cylindrical, 1: conical, 2: circular crowning, 3: parabolic.
                match class {
                    1 => {
                        plan.gear.cone = Some(ConeSpec {
                            angle_deg: 1.0 + 19.0 * shape_param,
                            large_end: if right {
                                LargeEnd::Bottom
                            } else {
                                LargeEnd::Top
                            },
                        })
                    }
                    2 | 3 => {
                        plan.gear.crowning = Some(CrowningSpec {
                            amount_mm: 0.005 + 0.1 * shape_param,
                            shape: if class == 2 {
                                CrowningShape::Circular
                            } else {
                                CrowningShape::Parabolic
                            },
                            chord_tolerance_mm: Some(0.0005),
                        })
                    }
                    _ => {
                        if radial_axial {
                            plan.sections_mut().process.infeed = Some(Infeed::RadialAxial);
                        }
                    }
                }
                plan.class = gearcam_proto::classify(&plan.gear, &plan.sections().units);
                // A machine large enough for the positions most of the time.
                let lim = &mut plan.machine.limits;
                lim.module_mm = [0.1, 10.0];
                lim.max_workpiece_od_mm = 2000.0;
                lim.max_hob_od_mm = 500.0;
                lim.x_mm = [0.0, 2000.0];
                lim.z_mm = [-500.0, 2000.0];
                plan
            },
        )
}

fn finite(k: &Kinematics) -> bool {
    let mut v = vec![
        k.swivel_deg,
        k.clearance_mm,
        k.centre_distance_mm,
        k.depth_mm,
        k.hob_rpm,
        k.index_rpm,
        k.table_rpm,
        k.axial_feed_mm_min,
        k.differential_deg_per_mm,
        k.cut_time_min,
        k.part_time_min,
        k.job_time_min,
        k.factors.c_per_y_deg_per_mm,
    ];
    for c in &k.cuts {
        let p = c.positions;
        v.extend([
            p.B.x_mm, p.B.z_mm, p.C.x_mm, p.C.z_mm, p.D.x_mm, p.D.z_mm, p.E.x_mm, p.E.z_mm,
        ]);
        v.extend([
            c.table_rpm,
            c.axial_feed_mm_min,
            c.radial_feed_mm_min,
            c.time_min,
            c.clearance_mm,
        ]);
        for m in &c.moves {
            v.extend(m.x_mm);
            v.extend(m.z_mm);
            v.extend(m.y_mm);
            v.push(m.feed_mm_min);
        }
    }
    v.iter().all(|x| x.is_finite())
}

const LIMIT_CODES: [Code; 8] = [
    Code::HOB_RPM_LIMIT,
    Code::TABLE_RPM_LIMIT,
    Code::AXIAL_FEED_LIMIT,
    Code::SWIVEL_LIMIT,
    Code::POSITION_TRAVEL_LIMIT,
    Code::FEED_RATE_LIMIT,
    Code::WORKPIECE_OD_LIMIT,
    Code::ENVELOPE_COLLISION,
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn valid_jobs_compute_ordered_finite_models_or_report_limits(plan in plans()) {
        let report = crate::validate::validate(&plan);
        prop_assume!(report.is_ok());
        let geo = crate::geometry::geometry(&plan.gear);
        let k = crate::hobbing::kinematics(&plan, &geo);
        prop_assert!(finite(&k), "{k:?}");
        prop_assert!(k.hob_rpm > 0.0 && k.index_rpm > 0.0 && k.table_rpm > 0.0);
        prop_assert!(k.clearance_mm > 0.0);
        let b = plan.gear.face_width_mm;
        let h = plan.gear.fixture_height_mm;
        for c in &k.cuts {
            let p = c.positions;
            prop_assert!(c.axial_feed_mm_min > 0.0 && c.table_rpm > 0.0 && c.time_min > 0.0);
            prop_assert!(c.clearance_mm > 0.0);
            // Retract points lie outside the cutting X; the feed crosses the face.
            prop_assert!(p.B.x_mm > p.C.x_mm && p.E.x_mm > p.D.x_mm);
            // The path's X stays at or outside the finishing X of the cut at
            // the reference section, except along a cone, where it follows δ,
            // and towards the faces of a crowned gear, deeper by the crowning.
            let crown = k.crowning.as_ref().map_or(0.0, |c| c.amount_mm);
            if k.class != gearcam_proto::GearClass::Conical {
                for m in &c.moves {
                    if let Some(x) = m.x_mm {
                        prop_assert!(x >= c.centre_distance_mm + plan.gear.od_correction_mm - crown - 1e-9);
                    }
                }
            }
            match plan.process.cut_mode {
                CutMode::Conventional => {
                    prop_assert!(p.D.z_mm < p.C.z_mm);
                    prop_assert!(p.D.z_mm < h && p.C.z_mm > h + b);
                }
                CutMode::Climb => {
                    prop_assert!(p.D.z_mm > p.C.z_mm);
                    prop_assert!(p.C.z_mm < h && p.D.z_mm > h + b);
                }
            }
            for m in c.moves.iter().filter(|m| m.kind != MoveKind::Rapid && m.kind != MoveKind::Dwell) {
                prop_assert!(m.feed_mm_min > 0.0);
            }
        }
        // Rough cuts never cut deeper than the finishing cut.
        for w in k.cuts.windows(2) {
            prop_assert!(w[0].depth_mm <= w[1].depth_mm + 1e-12);
        }
        match crate::compute(&plan) {
            Ok(m) => {
                let lim = &plan.machine.limits;
                prop_assert!(m.model.hob_rpm <= lim.max_hob_rpm + 1e-6);
                prop_assert!(m.model.cuts.iter().all(|c| c.table_rpm <= lim.max_table_rpm + 1e-6));
                prop_assert!(m.model.cuts.iter().all(|c| c.axial_feed_mm_min <= lim.max_axial_feed_mm_min + 1e-6));
            }
            Err(errors) => {
                for e in &errors {
                    prop_assert!(LIMIT_CODES.contains(&e.code), "{e:?}");
                }
            }
        }
    }

    #[test]
    fn without_swivel_the_clearance_is_at_least_the_spur_approach_length(
        blank in 10.0f64..600.0,
        hob in 20.0f64..250.0,
        depth_frac in 0.001f64..0.3,
        length in 1.0f64..400.0,
    ) {
        let depth = depth_frac * hob.min(blank);
        let c = Clearance {
            blank_od_mm: blank,
            hob_od_mm: hob,
            depth_mm: depth,
            swivel_deg: 0.0,
            hob_length_mm: length,
        };
        let approach = (depth * (hob - depth)).sqrt();
        let s = c.solve();
        prop_assert!(s.clearance_mm.is_finite());
        prop_assert!(s.clearance_mm >= approach * (1.0 - 1e-9), "{} < {approach}", s.clearance_mm);
    }

    #[test]
    fn the_clearance_is_the_lowest_point_of_the_hob_over_the_blank(
        blank in 10.0f64..400.0,
        hob in 20.0f64..200.0,
        depth_frac in 0.01f64..0.3,
        swivel in -45.0f64..45.0,
        length_frac in 0.02f64..3.0,
    ) {
        let depth = depth_frac * hob.min(blank);
        let c = Clearance {
            blank_od_mm: blank,
            hob_od_mm: hob,
            depth_mm: depth,
            swivel_deg: swivel,
            hob_length_mm: length_frac * hob,
        };
        let s = c.solve();
        let brute = hob_sweep(&c);
        if s.length_bound_ignored {
            // No point of the hob lies over the disc; the answer errs high.
            prop_assert!(brute == f64::NEG_INFINITY || s.clearance_mm >= brute - 1e-6);
        } else {
            prop_assert!(s.clearance_mm >= brute - 1e-6, "{} < {brute}", s.clearance_mm);
            prop_assert!(s.clearance_mm <= brute + 1e-4, "{} > {brute}", s.clearance_mm);
            prop_assert!(s.hob_axial_mm.abs() <= c.hob_length_mm / 2.0 + 1e-9);
        }
    }

    #[test]
    fn parabolic_chords_stay_within_their_tolerance(amount in 0.001f64..0.2, tol in 1e-5f64..0.01) {
        let n = crate::path::parabolic_chords(amount, tol);
        prop_assert!(n >= 2);
        // The deviation of a chord of b/n from the parabola is Cb/n².
        prop_assert!(amount / (f64::from(n) * f64::from(n)) <= tol * (1.0 + 1e-12));
    }

    #[test]
    fn one_more_tooth_in_the_span_adds_one_base_pitch(mn in 0.5f64..10.0, z in 6u32..200, x in -0.5f64..1.0, beta in 0.0f64..40.0, k in 1u32..10) {
        let mut g = fixtures::gear();
        g.module_mm = mn;
        g.teeth = z;
        g.profile_shift = x;
        g.helix_angle_deg = beta;
        let step = crate::geometry::span_mm(&g, k + 1) - crate::geometry::span_mm(&g, k);
        prop_assert!((step - PI * mn * 20f64.to_radians().cos()).abs() < 1e-9);
        let geo = crate::geometry::geometry(&g);
        prop_assert!(geo.span_teeth >= 1 && geo.span_teeth <= z);
        prop_assert!(geo.sn_mm.is_finite() && geo.over_balls_mm.is_finite() && geo.span_mm.is_finite());
    }
}

#[test]
fn most_generated_jobs_are_valid_so_the_properties_are_exercised() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let strategy = plans();
    let (mut valid, mut computed) = (0, 0);
    for _ in 0..200 {
        let plan = strategy.new_tree(&mut runner).unwrap().current();
        if crate::validate::validate(&plan).is_ok() {
            valid += 1;
            if crate::compute(&plan).is_ok() {
                computed += 1;
            }
        }
    }
    // Both branches of the first property (a model, or limit errors) and the
    // valid-input assumption must be exercised by a fair share of the cases.
    assert!(valid >= 100, "only {valid} of 200 generated jobs are valid");
    assert!(
        computed >= 20 && computed < valid,
        "{computed} of {valid} computed"
    );
}

/// The lowest point below the hob centre of the hob's tip cylinder over the
/// blank disc, by a sweep around the hob (20 000 angles, then 4 000 around
/// the best): for each angle θ the point (L + r·cos θ, y·cos γ + r·sin θ·sin γ)
/// lies over the disc for an interval of the hob-axial y, and the lowest is
/// at the interval's largest y. It does not use the ΔH formula of the solver.
fn hob_sweep(c: &Clearance) -> f64 {
    let (big_r, r) = (c.blank_od_mm / 2.0, c.hob_od_mm / 2.0);
    let l = big_r + r - c.depth_mm;
    let g = c.swivel_deg.abs().to_radians();
    let half = c.hob_length_mm / 2.0;
    let at = |th: f64| {
        let x = l + r * th.cos();
        if x.abs() > big_r {
            return f64::NEG_INFINITY;
        }
        let w = (big_r * big_r - x * x).sqrt();
        let a = r * th.sin() * g.sin();
        let y_hi = ((w - a) / g.cos()).min(half);
        let y_lo = ((-w - a) / g.cos()).max(-half);
        if y_hi < y_lo {
            return f64::NEG_INFINITY;
        }
        y_hi * g.sin() - r * th.sin() * g.cos()
    };
    let n = 20_000;
    let step = std::f64::consts::TAU / f64::from(n);
    let (mut best_i, mut best) = (0, f64::NEG_INFINITY);
    for i in 0..n {
        let v = at(step * f64::from(i));
        if v > best {
            (best_i, best) = (i, v);
        }
    }
    let centre = step * f64::from(best_i);
    for j in -2000..=2000 {
        best = best.max(at(centre + step * f64::from(j) / 2000.0));
    }
    best
}
