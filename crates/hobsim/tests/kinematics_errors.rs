//! What-if machine errors: each changes the pose by its closed form, and a
//! table runout cuts a radial runout 2·e into the gear.

mod common;

use std::f64::consts::{PI, TAU};

use gearcam_hobsim::cut::{self, Blank, Resolution};
use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{
    self, Axes, Gearbox, MachineErrors, MachineRates, Pose, Segment, Timeline,
};

/// The hob's middle in the machine frame: (X, 0, Z) + Y·u, u = (0, cos η, −sin η).
fn centre(p: &Pose) -> [f64; 3] {
    let (s, c) = p.eta_rad.sin_cos();
    [p.axes.x_mm, p.axes.y_mm * c, p.axes.z_mm - p.axes.y_mm * s]
}

fn axis(p: &Pose) -> [f64; 3] {
    let (s, c) = p.eta_rad.sin_cos();
    [0.0, c, -s]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A coupled feed of 3 s at η 22°, shifted `shift` mm, the hob at 1.3 rev/s.
fn timeline(errors: MachineErrors, shift: f64) -> Timeline {
    let at = |z| Axes {
        x_mm: 74.0,
        y_mm: shift,
        z_mm: z,
    };
    Timeline::from_segments(vec![Segment {
        line: 1,
        t0_s: 0.0,
        t1_s: 3.0,
        from: at(140.0),
        to: at(90.0),
        eta_rad: 22f64.to_radians(),
        hob_rev_s: 1.3,
        gearbox: Some(Gearbox {
            c_per_b: 1.0 / 31.0,
            c_per_z_rad_mm: 0.004,
            c_per_y_rad_mm: 0.0,
        }),
        c_extra_rad: 0.0,
        feed: true,
    }])
    .expect("timeline")
    .with_errors(errors)
}

/// Every pose of the run (shifted 7 mm) with errors against the ideal one,
/// at 97 instants.
fn pairs(errors: MachineErrors) -> Vec<(Pose, Pose)> {
    pairs_shifted(errors, 7.0)
}

fn pairs_shifted(errors: MachineErrors, shift: f64) -> Vec<(Pose, Pose)> {
    let tl = timeline(errors, shift);
    (0..97)
        .map(|k| {
            let t = 3.0 * f64::from(k) / 96.0;
            (tl.nominal_pose_in(0, t), tl.pose_in(0, t))
        })
        .collect()
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(TAU) - PI
}

#[test]
fn a_centre_distance_offset_moves_the_hob_along_x() {
    for (n, e) in pairs(MachineErrors {
        centre_distance_mm: 0.03,
        ..Default::default()
    }) {
        let d = sub(centre(&e), centre(&n));
        assert!((d[0] - 0.03).abs() < 1e-12 && d[1].abs() < 1e-12 && d[2].abs() < 1e-12);
        assert_eq!((n.b_rad, n.c_rad, n.eta_rad), (e.b_rad, e.c_rad, e.eta_rad));
    }
}

#[test]
fn a_swivel_offset_turns_the_hob_axis_about_the_swivel_axis() {
    for (n, e) in pairs(MachineErrors {
        swivel_deg: 0.05,
        ..Default::default()
    }) {
        let angle = dot(axis(&n), axis(&e)).clamp(-1.0, 1.0).acos();
        assert!((angle - 0.05f64.to_radians()).abs() < 1e-9, "{angle}");
        // The swivel axis is x through the unshifted hob centre (X, 0, Z):
        // the shifted middle stays 7 mm from it, in the plane x = X.
        let o = [n.axes.x_mm, 0.0, n.axes.z_mm];
        let r = sub(centre(&e), o);
        assert!(r[0].abs() < 1e-12 && (dot(r, r).sqrt() - 7.0).abs() < 1e-12);
    }
}

/// Radial runout: the hob centre circles the spindle axis once per hob turn,
/// e_r from it, perpendicular to u, at angle B + φ_r from e1 = −x̂.
#[test]
fn a_radial_runout_circles_the_hob_centre_once_per_turn() {
    let (e_r, phi) = (0.02, 40f64);
    for (n, e) in pairs(MachineErrors {
        hob_radial_mm: e_r,
        hob_radial_phase_deg: phi,
        ..Default::default()
    }) {
        let d = sub(centre(&e), centre(&n));
        assert!((dot(d, d).sqrt() - e_r).abs() < 1e-12, "{d:?}");
        assert!(dot(d, axis(&n)).abs() < 1e-12);
        let (s, c) = n.eta_rad.sin_cos();
        let along_w = dot(d, [0.0, s, c]);
        let along_e1 = -d[0];
        let got = along_w.atan2(along_e1);
        assert!(wrap(got - n.b_rad - phi.to_radians()).abs() < 1e-9);
    }
}

#[test]
fn an_axial_runout_moves_the_hob_along_its_axis_once_per_turn() {
    let (e_a, phi) = (0.01, -75f64);
    for (n, e) in pairs(MachineErrors {
        hob_axial_mm: e_a,
        hob_axial_phase_deg: phi,
        ..Default::default()
    }) {
        let d = sub(centre(&e), centre(&n));
        let want = e_a * (n.b_rad + phi.to_radians()).cos();
        let u = axis(&n);
        for i in 0..3 {
            assert!((d[i] - want * u[i]).abs() < 1e-12, "{d:?}");
        }
    }
}

/// Table runout e at workpiece angle φ: the hob centre's distance to the
/// gear's axis is √((X − e·cos ψ)² + (e·sin ψ)²), ψ = φ − C, ≈ X − e·cos(C − φ);
/// in the workpiece frame (turned by +C) the hob is offset by the constant
/// −e·(cos φ, sin φ).
#[test]
fn a_table_runout_moves_the_gear_axis_with_the_table() {
    let (e_t, phi) = (0.05, 110f64);
    let errors = MachineErrors {
        table_mm: e_t,
        table_phase_deg: phi,
        ..Default::default()
    };
    // Unshifted: the hob centre is (X, 0, Z) on the ideal machine.
    for (n, e) in pairs_shifted(errors, 0.0) {
        let h = centre(&e);
        let psi = phi.to_radians() - n.c_rad;
        let x = n.axes.x_mm;
        let exact = ((x - e_t * psi.cos()).powi(2) + (e_t * psi.sin()).powi(2)).sqrt();
        let got = h[0].hypot(h[1]);
        assert!((got - exact).abs() < 1e-12, "{got} vs {exact}");
        assert!((got - (x - e_t * (n.c_rad - phi.to_radians()).cos())).abs() < e_t * e_t / x);
        assert!(
            (h[2] - n.axes.z_mm).abs() < 1e-12,
            "the runout is horizontal"
        );
    }
    // Shifted or not: in the workpiece frame the hob is offset by the
    // constant −e·(cos φ, sin φ), and not at all in height.
    for shift in [0.0, 7.0] {
        for (n, e) in pairs_shifted(errors, shift) {
            let (h, hn) = (centre(&e), centre(&n));
            let (s, c) = n.c_rad.sin_cos();
            let turn = |p: [f64; 3]| [p[0] * c - p[1] * s, p[0] * s + p[1] * c];
            let (a, b) = (turn(h), turn(hn));
            let (ps, pc) = phi.to_radians().sin_cos();
            assert!((a[0] - b[0] + e_t * pc).abs() < 1e-12, "{a:?} {b:?}");
            assert!((a[1] - b[1] + e_t * ps).abs() < 1e-12, "{a:?} {b:?}");
            assert!((h[2] - hn[2]).abs() < 1e-12);
        }
    }
}

/// The spur program on a table with runout e: each gap's root stands at
/// df/2 − e·cos(θ − φ) (θ the gap's angle): a radial runout of 2·e.
#[test]
fn a_table_runout_cuts_a_radial_runout_of_twice_its_size() {
    let (text, model) = common::program("spur_840d");
    let (_, trace) = gearcam_nc::check(&text, &model);
    let (e_t, phi) = (0.2, 35f64);
    let errors = MachineErrors {
        table_mm: e_t,
        table_phase_deg: phi,
        ..Default::default()
    };
    let tl = kinematics::from_trace_with(&trace, &model, MachineRates::default(), errors)
        .expect("timeline");
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let g = &model.plan.gear;
    let z = Blank::planes(g.fixture_height_mm + 15.0, g.fixture_height_mm + 15.0, 1);
    let mut blank = Blank::new(z, model.model.blank_od_mm / 2.0, 25 * 24).expect("blank");
    let res = Resolution::coarse();
    cut::cut(&tl, &hob, &mut blank, res).expect("cut");
    let o = &blank.r_mm[0];
    let gaps = common::gaps(o, model.geometry.d_mm / 2.0);
    assert_eq!(gaps.len(), 25);
    let df2 = model.geometry.df_mm / 2.0;
    let n = o.len();
    for (a, b) in gaps {
        let b = if b < a { b + n } else { b };
        let (i, root) = (a..=b)
            .map(|i| (i, o[i % n]))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap();
        let theta = TAU * i as f64 / n as f64;
        let want = df2 - e_t * (theta - phi.to_radians()).cos();
        // The feed marks and the sampling lift a root by up to 0.0225 mm.
        assert!(
            root - want > -2e-3 && root - want < 0.0225,
            "gap at {theta:.3} rad: root {root:.4}, want {want:.4}"
        );
    }
}
