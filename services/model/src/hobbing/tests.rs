use super::*;
use crate::fixtures;
use crate::geometry::geometry;
use approx::assert_relative_eq;
use gearcam_proto::Hand;

fn kin(plan: &ProcessPlan) -> Kinematics {
    kinematics(plan, &geometry(&plan.gear))
}

#[test]
fn spec_worked_self_check_helical() {
    // docs/reference.md#worked-self-check: da0 80, vc 100, z0 1, z 25, fa 2, mn 3, β 15°
    // → Nt 397.887 rpm, Ni 15.9155 rpm, differential 0.395446 °/mm.
    let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
    assert_relative_eq!(k.hob_rpm, 397.887, epsilon = 5e-4);
    assert_relative_eq!(k.index_rpm, 15.9155, epsilon = 5e-5);
    assert_relative_eq!(k.differential_deg_per_mm, 0.395446, epsilon = 5e-7);
    // Same hands, conventional: s = +1, Pz = π·3·25/sin 15° = 910.3657 mm,
    // Nw = Ni/(1 − 2/Pz) (independent Python computation).
    assert_relative_eq!(k.table_rpm, 15.950_536_430_075, epsilon = 1e-9);
    assert_relative_eq!(k.axial_feed_mm_min, 31.901_072_860_149, epsilon = 1e-9);
}

#[test]
fn spur_feed_is_fa_times_index_speed() {
    // docs/hobbing.md#4-the-cycle-positions-speeds-feeds: spur Vf = fa·z0·Nt/z = 2·15.9155 = 31.831 mm/min, no differential.
    let k = kin(&fixtures::plan());
    assert_relative_eq!(k.axial_feed_mm_min, 31.831, epsilon = 5e-4);
    assert_eq!(k.table_rpm, k.index_rpm);
    assert_eq!(k.differential_deg_per_mm, 0.0);
}

#[test]
fn differential_flips_with_cut_mode_and_hob_hand() {
    // The C-per-Z coupling belongs to the gear's helix alone. A climb cut or
    // a left-hand hob once gave −0.395446.
    let right = kin(&fixtures::helical_plan(15.0, Hand::Right));
    for (hob_hand, mode) in [
        (Hand::Right, CutMode::Climb),
        (Hand::Left, CutMode::Conventional),
        (Hand::Left, CutMode::Climb),
    ] {
        let mut plan = fixtures::helical_plan(15.0, Hand::Right);
        plan.hob.hand = hob_hand;
        plan.process.cut_mode = mode;
        let k = kin(&plan);
        assert_relative_eq!(k.differential_deg_per_mm, 0.395446, epsilon = 5e-7);
        assert_eq!(k.differential_deg_per_mm, right.differential_deg_per_mm);
        assert_eq!(
            k.factors.c_per_z_deg_per_mm,
            right.factors.c_per_z_deg_per_mm
        );
    }
    // The gear's hand alone turns it.
    let left = kin(&fixtures::helical_plan(15.0, Hand::Left));
    assert_relative_eq!(left.differential_deg_per_mm, -0.395446, epsilon = 5e-7);
    // The table speed during the cut is the patent's magnitude rule
    // Nw = Ni/(1 ∓ fa/Pz): opposite hands (or climb) turn slower
    // (independent Python values).
    assert_relative_eq!(left.table_rpm, 15.880_605_820_559, epsilon = 1e-9);
    let mut climb = fixtures::helical_plan(15.0, Hand::Right);
    climb.process.cut_mode = CutMode::Climb;
    assert_relative_eq!(
        kin(&climb).axial_feed_mm_min,
        31.761_211_641_118,
        epsilon = 1e-9
    );
}

#[test]
fn swivel_ignores_the_hands() {
    // η = s_g·β − s_h·γ0 (γ0 = 2.3716°). A wrong rule once gave a spur gear
    // +2.3716 for both hob hands and the left-hand mirror image of a
    // right-hand set-up the same swivel.
    let mut g = fixtures::gear();
    let right = fixtures::hob();
    let left = HobData {
        hand: Hand::Left,
        ..fixtures::hob()
    };
    assert_relative_eq!(swivel_deg(&g, &right), -2.3716, epsilon = 1e-12);
    assert_relative_eq!(swivel_deg(&g, &left), 2.3716, epsilon = 1e-12);
    g.helix_angle_deg = 15.0;
    g.helix_hand = Some(Hand::Right);
    assert_relative_eq!(swivel_deg(&g, &right), 12.6284, epsilon = 1e-12);
    assert_relative_eq!(swivel_deg(&g, &left), 17.3716, epsilon = 1e-12);
    g.helix_hand = Some(Hand::Left);
    assert_relative_eq!(swivel_deg(&g, &right), -17.3716, epsilon = 1e-12);
    assert_relative_eq!(swivel_deg(&g, &left), -12.6284, epsilon = 1e-12);
    // H01 maps A = −η: the right-hand set-up keeps the patent's A = −12.6284.
    let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
    assert_relative_eq!(k.swivel_axis_deg, -12.6284, epsilon = 1e-12);
    let mut mirrored = fixtures::helical_plan(15.0, Hand::Left);
    mirrored.hob.hand = Hand::Left;
    let m = kin(&mirrored);
    assert_relative_eq!(m.swivel_axis_deg, 12.6284, epsilon = 1e-12);
    // A profile's offset and sign map η to its axis.
    mirrored.machine.settings.swivel_sign = 1.0;
    mirrored.machine.settings.swivel_offset_deg = 90.0;
    assert_relative_eq!(
        kin(&mirrored).swivel_axis_deg,
        90.0 - 12.6284,
        epsilon = 1e-12
    );
}

#[test]
fn indexing_840d_ignores_the_hob_hand() {
    // The C-per-B ratio's sign is the hob's hand.
    let mut plan = fixtures::plan();
    let k = kin(&plan);
    assert_eq!(k.coupling, Ratio { num: 1, den: 25 });
    assert_eq!(k.factors.c_per_b, Ratio { num: 1, den: 25 });
    plan.hob.hand = Hand::Left;
    let k = kin(&plan);
    assert_eq!(k.coupling, Ratio { num: -1, den: 25 });
    assert_eq!(k.factors.c_per_b, Ratio { num: -1, den: 25 });
    // A machine whose table turns the other way flips the programmed sign.
    plan.machine.settings.table_sign = -1.0;
    assert_eq!(kin(&plan).factors.c_per_b, Ratio { num: 1, den: 25 });
}

#[test]
fn clearance_without_swivel_is_the_approach_length() {
    // docs/hobbing.md#4-the-cycle-positions-speeds-feeds: for γ = 0, ΔH′ = √(h·(da0 − h)).
    let c = Clearance {
        blank_od_mm: 81.0,
        hob_od_mm: 80.0,
        depth_mm: 6.75,
        swivel_deg: 0.0,
        hob_length_mm: 100.0,
    };
    let s = c.solve();
    assert_relative_eq!(
        s.clearance_mm,
        (6.75f64 * (80.0 - 6.75)).sqrt(),
        epsilon = 1e-9
    );
    assert_relative_eq!(s.clearance_mm, 22.235_950_620_560, epsilon = 1e-9);
    assert!(!s.length_bound_ignored);
}

#[test]
fn delta_h_prime_too_small() {
    // The patent's factor cos γ − tan γ·sin γ made ΔH′
    // 2.1 mm short at γ 12.6°, 3.8 mm at 17° and 6.1 mm at 22° for this
    // blank. References: an independent Python sweep of the hob's tip
    // cylinder (2·10⁶ angles around the hob, the lowest point over the
    // blank disc for each), not the ΔH formula.
    for (gamma, want) in [
        (0.0, 22.235_950_620),
        (17.0, 24.466_873_472),
        (22.0, 25.988_919_048),
    ] {
        let c = Clearance {
            blank_od_mm: 85.0,
            hob_od_mm: 80.0,
            depth_mm: 6.75,
            swivel_deg: gamma,
            hob_length_mm: 100.0,
        };
        assert_relative_eq!(c.solve().clearance_mm, want, epsilon = 1e-6);
    }
    // The fixture gears (hob 80 × 100, h 6.750963).
    let k = kin(&fixtures::plan());
    assert_relative_eq!(k.clearance_mm, 22.279_643_304, epsilon = 1e-6);
    let k = kin(&fixtures::helical_plan(15.0, Hand::Right));
    assert_relative_eq!(k.clearance_mm, 23.456_419_441, epsilon = 1e-6);
    let k = kin(&fixtures::helical_plan(15.0, Hand::Left));
    assert_relative_eq!(k.clearance_mm, 24.548_048_363, epsilon = 1e-6);
    // A tilt either way gives the same clearance.
    let mut c = Clearance {
        blank_od_mm: 85.0,
        hob_od_mm: 80.0,
        depth_mm: 6.75,
        swivel_deg: 17.0,
        hob_length_mm: 100.0,
    };
    let plus = c.solve().clearance_mm;
    c.swivel_deg = -17.0;
    assert_eq!(c.solve().clearance_mm, plus);
}

#[test]
fn short_hob_bounds_the_contact_point() {
    // β 20° same hands, η = 17.6284°: a 4 mm hob reaches less far than a
    // 100 mm one (Python sweep of the hob's tip cylinder).
    let mut plan = fixtures::helical_plan(20.0, Hand::Right);
    let free = kin(&plan).clearance_mm;
    assert_relative_eq!(free, 24.649_370_772, epsilon = 1e-6);
    plan.hob.length_mm = 4.0;
    let k = kin(&plan);
    assert_relative_eq!(k.clearance_mm, 21.424_671_864, epsilon = 1e-6);
    let geo = geometry(&plan.gear);
    let set = setup(&plan, &geo);
    let s = Clearance {
        blank_od_mm: set.blank_od_mm,
        hob_od_mm: 80.0,
        depth_mm: set.depth_mm,
        swivel_deg: k.swivel_deg,
        hob_length_mm: 4.0,
    }
    .solve();
    assert!(s.hob_axial_mm.abs() <= 2.0 + 1e-12, "{s:?}");
    assert!(!s.length_bound_ignored);
}

#[test]
fn hob_too_short_for_any_contact_falls_back_to_the_free_maximum() {
    let c = Clearance {
        blank_od_mm: 85.0,
        hob_od_mm: 80.0,
        depth_mm: 6.75,
        swivel_deg: 80.0,
        hob_length_mm: 1e-9,
    };
    let bounded = c.solve();
    let free = Clearance {
        hob_length_mm: 1e9,
        ..c
    }
    .solve();
    if bounded.length_bound_ignored {
        assert_eq!(bounded.clearance_mm, free.clearance_mm);
    } else {
        assert!(bounded.clearance_mm <= free.clearance_mm + 1e-9);
    }
}

#[test]
fn contact_point_lies_on_the_blank_cylinder_below_the_hob_centre() {
    let c = Clearance {
        blank_od_mm: 85.0,
        hob_od_mm: 80.0,
        depth_mm: 6.75,
        swivel_deg: -12.0,
        hob_length_mm: 100.0,
    };
    let (lo, hi) = c.domain();
    let l = c.centre_distance_mm();
    for i in 1..10 {
        let x = lo + (hi - lo) * f64::from(i) / 10.0;
        let p = c.contact_in_gear_frame(x);
        assert_relative_eq!(p.x, l - x, epsilon = 1e-12);
        assert_relative_eq!(p.x * p.x + p.y * p.y, 42.5 * 42.5, epsilon = 1e-9);
        // The point lies ΔH(x) below the hob centre.
        assert_relative_eq!(-p.z, c.delta_h(x), epsilon = 1e-9);
        // And on the hob's tip cylinder: distance r from the hob axis.
        let g = 12f64.to_radians();
        let axis = [0.0, g.cos(), -g.sin()];
        let v = [p.x - l, p.y, p.z];
        let along = v[1] * axis[1] + v[2] * axis[2];
        let d2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - along * along;
        assert_relative_eq!(d2.sqrt(), 40.0, epsilon = 1e-9);
    }
}

#[test]
fn positions_conventional_and_climb() {
    // L 73.749037, ΔH′ 22.279643 (Python sweep), top = 100 + 30 + ΔH′ + 2.
    let plan = fixtures::plan();
    let p = kin(&plan).positions;
    let (xc, top, bottom) = (73.749_036_780_371, 154.279_643_304, 75.720_356_696);
    assert_eq!((p.A.x_mm, p.A.z_mm), (300.0, 350.0));
    assert_relative_eq!(p.B.x_mm, xc + 100.0, epsilon = 1e-9);
    assert_relative_eq!(p.B.z_mm, top, epsilon = 1e-6);
    assert_relative_eq!(p.C.x_mm, xc, epsilon = 1e-9);
    assert_relative_eq!(p.C.z_mm, top, epsilon = 1e-6);
    assert_relative_eq!(p.D.x_mm, xc, epsilon = 1e-9);
    assert_relative_eq!(p.D.z_mm, bottom, epsilon = 1e-6);
    assert_relative_eq!(p.E.x_mm, xc + 5.0, epsilon = 1e-9);
    assert_relative_eq!(p.E.z_mm, bottom, epsilon = 1e-6);

    let mut climb = fixtures::plan();
    climb.process.cut_mode = CutMode::Climb;
    climb.gear.od_correction_mm = 0.1;
    let q = kin(&climb).positions;
    assert_relative_eq!(q.B.x_mm, xc + 100.1, epsilon = 1e-9);
    assert_relative_eq!(q.B.z_mm, bottom, epsilon = 1e-6);
    assert_relative_eq!(q.C.z_mm, bottom, epsilon = 1e-6);
    assert_relative_eq!(q.D.z_mm, top, epsilon = 1e-6);
    assert_relative_eq!(q.E.x_mm, xc + 5.1, epsilon = 1e-9);
    assert_relative_eq!(q.E.z_mm, top, epsilon = 1e-6);
}

#[test]
fn given_depth_sets_the_centre_distance() {
    let mut plan = fixtures::plan();
    plan.process.depth_mm = Some(6.0);
    let k = kin(&plan);
    // L = (80 + 81)/2 − 6 = 74.5.
    assert_relative_eq!(k.centre_distance_mm, 74.5, epsilon = 1e-12);
    assert_eq!(k.depth_mm, 6.0);
}

#[test]
fn coupling_is_reduced_and_exact() {
    let hob = |starts, hand| HobData {
        starts,
        hand,
        ..fixtures::hob()
    };
    assert_eq!(
        coupling(&hob(1, Hand::Right), 25),
        Ratio { num: 1, den: 25 }
    );
    assert_eq!(
        coupling(&hob(2, Hand::Right), 40),
        Ratio { num: 1, den: 20 }
    );
    assert_eq!(
        coupling(&hob(3, Hand::Left), 40),
        Ratio { num: -3, den: 40 }
    );
}

#[test]
fn rough_cuts_leave_the_allowance_from_job_case_or_default() {
    use gearcam_proto::{Source, Sourced};
    let mut plan = fixtures::plan();
    plan.process.cuts = 3;
    // Default 0.1·mn = 0.3 mm; rough cuts share h − 0.3 evenly.
    let k = kin(&plan);
    let h = k.depth_mm;
    let depths: Vec<f64> = k.cuts.iter().map(|c| c.depth_mm).collect();
    assert_relative_eq!(depths[0], (h - 0.3) / 2.0, epsilon = 1e-12);
    assert_relative_eq!(depths[1], h - 0.3, epsilon = 1e-12);
    assert_relative_eq!(depths[2], h, epsilon = 1e-12);
    assert!(k.cuts[1].resync && k.cuts[2].resync && !k.cuts[0].resync);
    // A case's proposal replaces the default; the job's value wins over both.
    plan.values.insert(
        "allowance_mm".into(),
        Sourced {
            value: 0.4,
            source: Source::Case,
        },
    );
    assert_relative_eq!(kin(&plan).cuts[1].allowance_mm, 0.4, epsilon = 1e-12);
    plan.sections_mut().process.finish_allowance_mm = Some(0.25);
    assert_relative_eq!(kin(&plan).cuts[1].allowance_mm, 0.25, epsilon = 1e-12);
    // Each cut is timed from its own feed stroke; the part time is their sum.
    let k = kin(&plan);
    let sum: f64 = k.cuts.iter().map(|c| c.time_min).sum();
    assert_relative_eq!(k.part_time_min, sum, epsilon = 1e-12);
    assert_relative_eq!(k.job_time_min, sum * 10.0, epsilon = 1e-9);
}

#[test]
fn shift_compensation_is_one_gear_pitch_per_hob_axial_pitch() {
    // |C per Y| = 360·cos γ0/(π·mn0·z): a shift by px0 = π·mn0/cos γ0
    // turns the table by 360°/z, the same way for both hands (the frame
    // module's tests derive the sign from the tooth phase).
    let hob = fixtures::hob();
    let c = shift_compensation_deg_per_mm(&hob, 25);
    let px0 = PI * 3.0 / 2.3716f64.to_radians().cos();
    assert_relative_eq!(c * px0, -360.0 / 25.0, epsilon = 1e-12);
    let left = HobData {
        hand: Hand::Left,
        ..hob
    };
    assert_eq!(shift_compensation_deg_per_mm(&left, 25), c);
}

#[test]
fn cut_time_is_axial_travel_over_feed_rate() {
    // (b + 2ΔH′)·z/(Nt·z0·fa) with the Python reference values.
    let k = kin(&fixtures::plan());
    // (30 + 2·22.279643)·25/(397.887·1·2) (Python).
    let want = (30.0 + 2.0 * 22.279_643_304) * 25.0 / (1000.0 * 100.0 / (PI * 80.0) * 2.0);
    assert_relative_eq!(k.cut_time_min, want, epsilon = 1e-6);
}
